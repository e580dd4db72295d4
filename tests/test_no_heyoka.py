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
        from rotorlib.core.precision import heyoka_available
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
        from rotorlib.core.precision import precision_tier
        print(json.dumps(list(precision_tier(25))))
    """)
    assert out == ["mpmath", "mp103"]  # mpmath at 30 digits: a name Tier accepts


#: The commands of the packaging test (tests/test_packaging.py): the flow's refuse
#: without heyoka, the quantum spectrum needs none.
FLOW_COMMANDS = (
    "orbit CG --E 3 --digits 30",
    "orbit ISl2 --E 4",
    "family IS^l_1 --E-range 3.99 4.1",
    "atlas --E 4.3 --t-max 8",
)
WORKS_WITHOUT = ("spectrum --hbar 0.5 --sector A1 --E-max 4", "trace pendulum --E 3.9")


def check_refusal(status: int, stderr: str) -> None:
    """One line on stderr, exit status 2, naming the extra and heyoka."""
    assert status == 2, stderr
    assert stderr.count("\n") == 1 and "Traceback" not in stderr, stderr
    assert stderr.startswith("rotorlib: error: ") and "internal error" not in stderr
    assert "rotorlib[fast]" in stderr and "heyoka" in stderr, stderr


def test_commands_that_integrate_the_flow_refuse_in_one_line():
    out = run_hidden(f"""
        import contextlib, io, json
        from rotorlib.cli import main
        res = []
        for cmd in {FLOW_COMMANDS + WORKS_WITHOUT!r}:
            err = io.StringIO()
            with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
                status = main(cmd.split())
            res.append([cmd, status, err.getvalue()])
        print(json.dumps(res))
    """)
    for cmd, status, stderr in out:
        if cmd in WORKS_WITHOUT:
            assert status == 0 and stderr == "", (cmd, stderr)
        else:
            check_refusal(status, stderr)


def test_front_door_raises_heyoka_missing():
    out = run_hidden("""
        import json, rotorlib
        from rotorlib.core.precision import HeyokaMissing
        try:
            rotorlib.orbit("ISl2", 4.0)
        except HeyokaMissing as exc:
            print(json.dumps([isinstance(exc, ImportError), exc.name, str(exc)]))
        else:
            print(json.dumps(None))
    """)
    assert out is not None, "rotorlib.orbit('ISl2', 4.0) did not raise without heyoka"
    is_import_error, name, message = out
    assert is_import_error and name == "heyoka"
    assert "rotorlib[fast]" in message and "\n" not in message


def test_heyoka_is_required_exactly_where_its_wheels_exist():
    """pyproject.toml: heyoka a dependency on Linux x86_64/aarch64 (PyPI's wheels), the
    extra ``fast`` elsewhere."""
    import tomllib
    from pathlib import Path

    from packaging.requirements import Requirement

    meta = tomllib.loads(
        (Path(__file__).resolve().parents[1] / "pyproject.toml").read_text()
    )["project"]
    reqs = {Requirement(r).name: Requirement(r) for r in meta["dependencies"]}
    assert {"numpy", "scipy", "mpmath", "heyoka"} <= set(reqs)
    marker = reqs["heyoka"].marker
    assert marker is not None
    for system, machine, required in (
        ("linux", "x86_64", True),
        ("linux", "aarch64", True),
        ("linux", "ppc64le", False),
        ("darwin", "arm64", False),
        ("win32", "AMD64", False),
    ):
        env = {"sys_platform": system, "platform_machine": machine}
        assert marker.evaluate(env) is required, (system, machine)
    fast = [Requirement(r) for r in meta["optional-dependencies"]["fast"]]
    assert [r.name for r in fast] == ["heyoka"] and fast[0].marker is None
