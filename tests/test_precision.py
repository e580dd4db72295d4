"""Precision tiers: labels, the --digits control, and accuracy against independent computations.

Timing is never asserted here (see ``benchmarks/bench_precision.py``).
"""

import json
import math
import subprocess
import sys

import mpmath as mp
import numpy as np
import pytest

from rotorlib.core.closed_forms import pendulum
from rotorlib.core.precision import Tier, heyoka_available, precision_tier, tier
from rotorlib.orbits.floquet import (
    _monodromy,
    monodromy,
    textbook_monodromy,
    variational_monodromy,
)
from rotorlib.orbits.hill import hill_problem, solve_hill

HEYOKA = heyoka_available()
needs_heyoka = pytest.mark.skipif(not HEYOKA, reason="heyoka not installed")


def textbook_reference(x, phase, bits=512):
    """tr M from the 4x4 variational equations over one period in ``bits``-bit arithmetic.

    Independent of the Hill reduction and of rotorlib's closed-form orbits:
    E = 4 -+ exp(x), p2 = sqrt(4E/3) at G and the period (4K(E/4)/sqrt3 or
    2 kappa K(kappa^2)/sqrt3, kappa^2 = 4/E) are computed in mpmath.
    """
    return textbook_monodromy(
        pendulum(log_abs_dE=float(x), phase=phase), Tier(f"mp{bits}")
    )


def agreeing_digits(a, b):
    with mp.workdps(200):
        a, b = mp.mpf(a), mp.mpf(b)
        d = abs(a - b)
        return math.inf if d == 0 else float(-mp.log10(d / abs(b)))


# --------------------------------------------------------------------------- the tier map


@pytest.mark.parametrize(
    "digits,expected",
    [
        (None, "float64"),
        (1, "float64"),
        (15, "float64"),
        (16, "real128"),
        (31, "real128"),
        (32, "mp"),
    ],
)
def test_precision_tier_map(digits, expected):
    be, prec = precision_tier(digits)
    assert (
        prec.startswith(expected) and prec == tier(digits).name
    )  # a name Tier accepts
    if HEYOKA:
        assert be == "heyoka"
    else:
        assert be == ("scipy" if expected == "float64" else "mpmath")
        assert prec == tier(digits).name or be == "mpmath"


def test_precision_tier_bits_cover_digits():
    for d in (32, 40, 60, 100):
        _, prec = precision_tier(d)
        assert int(prec[2:]) * math.log10(2) >= d + 5


@pytest.mark.parametrize("digits", [0, 1001, 2.5, "30"])
def test_precision_tier_refuses(digits):
    with pytest.raises(ValueError):
        precision_tier(digits)


def test_integrator_choice_is_private_and_labelled():
    """Forcing an integrator is a private test hook; mpmath's working precision is
    labelled as the tier mp<bits> of its arithmetic (20 digits: 70 bits)."""
    o = pendulum(E=1.0)
    M = _monodromy(o, None, "mpmath")
    assert M.precision == "mp70" and Tier(M.precision).bits == 70
    with pytest.raises(ValueError, match="scipy integrates in float64 only"):
        _monodromy(o, 20, "scipy")


# --------------------------------------------------------------------------- results say which precision


@needs_heyoka
@pytest.mark.parametrize(
    "digits,label", [(None, "float64"), (20, "real128"), (40, "mp")]
)
def test_monodromy_reports_precision(digits, label):
    M = monodromy(pendulum(log_abs_dE=-21.0012, phase="lib"), digits=digits)
    assert M.precision.startswith(label)
    assert M.backend == "heyoka"
    if digits:
        # trace_str carries the digits asked for (leading "4." then digits-1 more)
        assert len(M.trace_str.replace(".", "").lstrip("-0")) >= digits - 1


def test_scipy_backend_reports_float64():
    M = _monodromy(pendulum(E=3.9), None, "scipy")
    assert (M.backend, M.precision) == ("scipy", "float64")


def test_variational_reports_precision():
    o = pendulum(E=1.0)
    V = variational_monodromy(o.state0, o.period, rtol=1e-10)
    assert V.precision == "float64" and V.backend == "scipy-DOP853 rtol=1e-10"
    assert V.steps > 0 and type(V) is type(monodromy(o))


def test_hill_solution_reports_precision():
    sol = solve_hill(hill_problem(pendulum(E=3.0)), integrator="scipy")
    assert (sol.backend, sol.precision) == ("scipy", "float64") and sol.steps > 0
    sol = solve_hill(hill_problem(pendulum(E=3.0)))
    assert (sol.backend, sol.precision) == ("heyoka" if HEYOKA else "scipy", "float64")
    with pytest.raises(TypeError):  # one precision argument: digits
        solve_hill(hill_problem(pendulum(E=3.0)), backend="scipy")


def _cli(*args):
    return subprocess.run(
        [sys.executable, "-m", "rotorlib", "trace", *args],
        capture_output=True,
        text=True,
    )


def test_cli_reports_precision_in_table_and_json():
    r = _cli("pendulum", "--E", "3.9")
    assert r.returncode == 0 and "precision" in r.stdout and "float64" in r.stdout
    r = _cli("pendulum", "--E", "3.9", "5", "--json")
    recs = json.loads(r.stdout)
    be = "heyoka" if HEYOKA else "scipy"
    assert [(x["precision"], x["backend"]) for x in recs] == [("float64", be)] * 2


def test_cli_has_one_precision_option():
    r = _cli("pendulum", "--E", "3.9", "--backend", "scipy")
    assert r.returncode == 2 and "--backend" in r.stderr


# --------------------------------------------------------------------------- accuracy of the tiers


@needs_heyoka
def test_trace_digits30_at_minus60_against_textbook_512bit():
    """Target of issue 7: ``trace pendulum --phase rot --log-dE -60 --digits 30`` correct to 20 digits."""
    r = _cli(
        "pendulum", "--phase", "rot", "--log-dE", "-60", "--digits", "30", "--json"
    )
    rec = json.loads(r.stdout)
    assert rec["precision"] == "real128" and rec["backend"] == "heyoka"
    ref = textbook_reference(-60.0, "rot", bits=512)
    assert agreeing_digits(rec["trace_str"], ref.trace_str) >= 20
    # the closure of the 512-bit textbook orbit itself is tiny (its period and state are right)
    assert ref.closure < 1e-60


@needs_heyoka
def test_real128_and_mp_tiers_agree_deep_lib():
    o = pendulum(log_abs_dE=-21.0012, phase="lib")
    a = monodromy(o, digits=30).trace_str
    b = monodromy(o, digits=50).trace_str
    assert agreeing_digits(a, b) >= 29


@needs_heyoka
def test_mpmath_tier_agrees_with_heyoka_mp():
    """mpmath's Taylor integrator (independent of heyoka) against heyoka multiprecision."""
    o = pendulum(log_abs_dE=-10.0, phase="rot")
    a = _monodromy(o, 16, "mpmath")
    assert a.precision == "mp73" and a.backend == "mpmath"  # 21 digits
    b = monodromy(o, digits=40)
    assert agreeing_digits(a.trace_str, b.trace_str) >= 15


@pytest.mark.parametrize(
    "x,phase", [(-21.0012, "lib"), (-21.5, "rot"), (-22.0, "lib"), (-27.5529, "rot")]
)
def test_float64_within_1e11_deep_in_cascade(x, phase):
    """Target of issue 7 (accuracy part): float64 tr M within 1e-11 for log|E-4| in [-22, -21] and beyond."""
    o = pendulum(log_abs_dE=x, phase=phase)
    ref = (
        monodromy(o, digits=30).trace_str
        if HEYOKA
        else monodromy(o, digits=20).trace_str
    )
    for backend in ("heyoka", "scipy") if HEYOKA else ("scipy",):
        with mp.workdps(40):
            assert abs(_monodromy(o, None, backend).trace - mp.mpf(ref)) < 1e-11


def test_textbook_float64_is_wrong_deep_in_cascade():
    """The trap the reduction avoids: the textbook scipy route is off by > 1e3 at log(4 - E) = -21."""
    o = pendulum(log_abs_dE=-21.0012, phase="lib")
    V = variational_monodromy(o.state0, o.period, rtol=1e-12)
    assert abs(V.trace - monodromy(o).trace) > 1e3


# --------------------------------------------------------------------------- the tolerance knob


def test_default_tol_is_unchanged():
    o = pendulum(log_abs_dE=-21.5, phase="rot")
    for be in ("heyoka", "scipy") if HEYOKA else ("scipy",):
        assert _monodromy(o, None, be).trace == _monodromy(o, None, be, tol=None).trace


@pytest.mark.parametrize(
    "backend", ["scipy", pytest.param("heyoka", marks=needs_heyoka)]
)
def test_looser_tol_is_less_accurate_and_cheaper(backend):
    o = pendulum(log_abs_dE=-21.5, phase="rot")
    prob = hill_problem(o)
    ref = monodromy(o, digits=30).trace if HEYOKA else monodromy(o).trace
    loose = solve_hill(prob, tol=1e-6, integrator=backend)
    tight = solve_hill(prob, integrator=backend)
    err = lambda s: abs(2.0 + s.delta - ref)  # noqa: E731  (rotation: tr M = 2 + Delta)
    assert err(tight) < 1e-12 < err(loose) < 1e-4
    if backend == "scipy":
        assert loose.steps < tight.steps


@needs_heyoka
def test_real128_tol_knob():
    o = pendulum(log_abs_dE=-21.5, phase="rot")
    ref = monodromy(o, digits=50).trace_str
    loose = monodromy(o, digits=30, tol=1e-20).trace_str
    assert 15 < agreeing_digits(loose, ref) < 27
    assert np.isfinite(float(loose))


def test_heyoka_disk_cache_is_bounded(monkeypatch):
    hy = pytest.importorskip("heyoka")
    from rotorlib.core import precision

    precision.load_heyoka.cache_clear()
    monkeypatch.setenv("ROTORLIB_HEYOKA_CACHE_MB", "300")
    precision.load_heyoka()
    assert hy.llvm_state.get_diskcache_limit() == 300 * 2**20
    precision.load_heyoka.cache_clear()
    monkeypatch.setenv("ROTORLIB_HEYOKA_CACHE_MB", "lots")
    with pytest.raises(ValueError, match="ROTORLIB_HEYOKA_CACHE_MB"):
        precision.load_heyoka()
    precision.load_heyoka.cache_clear()
    monkeypatch.delenv("ROTORLIB_HEYOKA_CACHE_MB")
    precision.load_heyoka()
    assert hy.llvm_state.get_diskcache_limit() == precision.HEYOKA_CACHE_MB * 2**20


def test_solve_hill_integrator_chooses_the_method_not_the_precision():
    """``integrator=`` forces one integrator of the public ``solve_hill`` (to check one
    against another); the precision is still ``digits``."""
    prob = hill_problem(pendulum(E=1.0))
    a = solve_hill(prob, integrator="scipy")
    b = solve_hill(prob, integrator="mpmath")  # 20 working digits for float64
    assert (a.backend, a.precision) == ("scipy", "float64")
    assert (b.backend, b.precision) == ("mpmath", "mp70")
    assert abs(a.delta - b.delta) < 1e-12
    with pytest.raises(ValueError, match="scipy integrates in float64 only"):
        solve_hill(hill_problem(pendulum(E=1.0), 20), 20, integrator="scipy")
    with pytest.raises(ValueError, match="integrator must be heyoka, scipy or mpmath"):
        solve_hill(prob, integrator="fortran")
