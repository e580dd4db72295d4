"""rotorlib's float64 path works without heyoka (scipy fallback): heyoka is hidden in a subprocess."""

import json
import subprocess
import sys
import textwrap

from rotorlib.core.closed_forms import breather, pendulum
from rotorlib.orbits.floquet import trace_monodromy

HIDE = textwrap.dedent("""
    import sys, importlib.abc
    class _Block(importlib.abc.MetaPathFinder):
        def find_spec(self, name, path=None, target=None):
            if name == "heyoka" or name.startswith("heyoka."):
                raise ImportError("heyoka hidden for this test")
    sys.meta_path.insert(0, _Block())
""")


def run_hidden(code):
    p = subprocess.run(
        [sys.executable, "-c", HIDE + textwrap.dedent(code)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert p.returncode == 0, p.stderr
    return json.loads(p.stdout)


def test_scipy_fallback_matches():
    out = run_hidden("""
        import json
        from rotorlib.core.closed_forms import breather, pendulum
        from rotorlib.orbits.floquet import monodromy
        from rotorlib.orbits.hill import heyoka_available
        assert not heyoka_available()
        res = []
        for kw in (dict(E=1.0), dict(E=5.0), dict(log_abs_dE=-30.0, phase="lib"), dict(log_abs_dE=-100.0, phase="rot")):
            M = monodromy(pendulum(**kw))
            res.append([M.trace, M.backend, M.precision])
        M = monodromy(breather(9.0, "R"))
        res.append([M.trace, M.backend, M.precision])
        print(json.dumps(res))
    """)
    refs = [
        trace_monodromy(pendulum(**kw))
        for kw in (
            dict(E=1.0),
            dict(E=5.0),
            dict(log_abs_dE=-30.0, phase="lib"),
            dict(log_abs_dE=-100.0, phase="rot"),
        )
    ]
    refs.append(trace_monodromy(breather(9.0, "R")))
    for (t, backend, prec), ref in zip(out, refs):
        assert backend == "scipy" and prec == "float64"
        assert abs(t - ref) < 1e-11 * max(1.0, abs(ref))


def test_cli_without_heyoka():
    p = subprocess.run(
        [
            sys.executable,
            "-c",
            HIDE + "import sys, runpy; sys.argv=['rotorlib','trace','pendulum',"
            "'--E','2','--json']; runpy.run_module('rotorlib', run_name='__main__')",
        ],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert p.returncode == 0, p.stderr
    assert json.loads(p.stdout)["backend"] == "scipy"


def test_extended_precision_without_heyoka_uses_mpmath():
    out = run_hidden("""
        import json
        from rotorlib.orbits.hill import precision_tier
        print(json.dumps(list(precision_tier(25))))
    """)
    assert out == ["mpmath", "mp103"]  # mpmath at 30 digits: a name Tier accepts
