"""Numerical stability at the extremes: E -> 0, log|E - 4| down to -10000, E up to 1e6, E = 4, E -> 4.5.

Every float64 value is compared with an independent computation: heyoka
real128 (another precision), the textbook 4x4 variational equations (another
method), asymptotic series, or the asymptotic periodicity of tr M in
log|E - 4| (period 2 sqrt(3) pi).
"""

import json
import math
import subprocess
import sys

import mpmath as mp
import numpy as np
import pytest

from rotorlib.core.closed_forms import breather, pendulum
from rotorlib.core.precision import heyoka_available
from rotorlib.orbits.floquet import _monodromy, monodromy, variational_monodromy

HEYOKA = heyoka_available()
needs_heyoka = pytest.mark.skipif(not HEYOKA, reason="heyoka not installed")
PERIOD_X = 2.0 * math.sqrt(3.0) * math.pi  # asymptotic period of tr M in log|E - 4|


def ext(orbit, digits=30):
    """tr M of ``orbit`` as an mpf from the real128 tier."""
    with mp.workdps(digits + 10):
        return mp.mpf(monodromy(orbit, digits=digits).trace_str)


# --------------------------------------------------------------------------- E -> 0 (k -> 0)


def test_E0_is_the_linearised_limit():
    """At E = 0 both the transverse (a1'' = -3 a1) and longitudinal (a2'' = -3 a2) frequencies are sqrt(3):
    the transverse block over one period 2 pi/sqrt(3) is the identity and tr M = 4. That is the 1:1
    resonance of the equilibrium G, neutrally stable: reported as 'marginal' with the reason, not 'unstable'."""
    for orbit in (
        pendulum(E=0.0),
        pendulum(E="0"),
        breather(E=0, family="LG"),
    ):
        M = monodromy(orbit)
        assert abs(M.trace - 4.0) < 1e-14
        np.testing.assert_allclose(M.transverse, np.eye(2), atol=1e-13)
        assert abs(M.period - 2 * math.pi / math.sqrt(3)) < 1e-14
        assert M.stability == "marginal" and "1:1 resonance" in M.stability_note


@pytest.mark.parametrize("E,gap", [("1e-300", "2.86e-903"), ("1e-5", "2.86e-18")])
def test_tiny_E_is_marginal_with_the_series(E, gap):
    """E = 1e-300: tr M = 4 - pi^2 E^3/3456 (1 + O(E)) is 4.0 in float64 (and at 30 digits): the computed
    value cannot decide, so 'marginal', and the note gives the series value (stable). At E = 1e-5 the
    30-digit tier resolves 4 - tr M = 2.9e-18 and says 'stable'."""
    M = monodromy(pendulum(E=E))
    assert M.stability == "marginal" and M.trace == 4.0
    assert f"= {gap} > 0 (stable)" in M.stability_note
    if HEYOKA:
        M = monodromy(pendulum(E=E), digits=30)
        if E == "1e-5":
            assert M.stability == "stable" and M.stable and M.stability_note == ""
            with mp.workdps(40):
                assert abs((4 - mp.mpf(M.trace_str)) / mp.mpf(gap) - 1) < 0.01
        else:
            assert (
                M.stability == "marginal"
                and f"= {gap} > 0 (stable)" in M.stability_note
            )
    assert (
        monodromy(pendulum(E=1e-3)).stability == "stable"
    )  # 4 - tr M = 2.9e-12 is resolved


@needs_heyoka
@pytest.mark.parametrize("E", [1e-2, 1e-3, 1e-4])
def test_small_E_series(E):
    """4 - tr M = c E^3 (1 + b E + ...), c = pi^2/3456 and b ~ 0.40 (identified numerically, real128)."""
    c0 = math.pi**2 / 3456
    with mp.workdps(40):
        d = 4 - ext(pendulum(E=E))
        assert abs(float(d) / E**3 / c0 - 1 - 0.40 * E) < 0.02 * E + 1e-6
    # float64 keeps ~1e-15 absolute accuracy as tr M -> 4
    assert abs(monodromy(pendulum(E=E)).trace - float(4 - d)) < 2e-15


def test_small_E_against_textbook():
    """Far from the separatrix the textbook 4x4 route is accurate: an independent check at E = 0.1."""
    o = pendulum(E=0.1)
    V = variational_monodromy(o.state0, o.period, rtol=1e-13)
    assert abs(V.trace - monodromy(o).trace) < 1e-10
    assert abs(V.trace - 4.0) < 1e-5  # tr M - 4 = -3e-6 there


# --------------------------------------------------------------------------- log|E - 4| from -1 to -700


@pytest.mark.parametrize("phase", ["lib", "rot"])
def test_trace_finite_and_smooth_down_to_minus700(phase):
    xs = np.linspace(
        -1.0, -700.0, 2797
    )  # step 0.25 (tr M has period 10.9 in log|E - 4|)
    tr = np.array([monodromy(pendulum(log_abs_dE=x, phase=phase)).trace for x in xs])
    assert np.all(np.isfinite(tr))
    # smooth: a cubic spline through every other point predicts the points in between
    from scipy.interpolate import CubicSpline

    spl = CubicSpline(xs[::-2], tr[::-2])
    mid = xs[-2:0:-2]  # interior points not on the spline
    assert np.max(np.abs(spl(mid) - tr[-2:0:-2])) < 0.002 * np.max(np.abs(tr))
    # asymptotically periodic in log|E - 4| with period 2 sqrt(3) pi (corrections O(|E - 4| log|E - 4|))
    deep = xs[xs < -60]
    for x in deep[::50]:
        a = monodromy(pendulum(log_abs_dE=x, phase=phase)).trace
        b = monodromy(pendulum(log_abs_dE=x + PERIOD_X, phase=phase)).trace
        assert abs(a - b) < 1e-12


@needs_heyoka
@pytest.mark.parametrize("phase", ["lib", "rot"])
@pytest.mark.parametrize("x", [-1.0, -21.0012, -100.0, -100.7, -300.0, -700.0])
def test_float64_against_real128_at_depth(x, phase):
    o = pendulum(log_abs_dE=x, phase=phase)
    with mp.workdps(40):
        assert abs(monodromy(o).trace - ext(o)) < 1e-12
        assert abs(_monodromy(o, None, "scipy").trace - ext(o)) < 1e-11


@needs_heyoka
def test_deepest_transitions_near_minus100():
    """Near log|E - 4| = -100 tr M crosses 4 (IS) and 0 (PD): compare a fine grid with real128."""
    for phase in ("lib", "rot"):
        xs = np.linspace(-100.0, -100.0 - PERIOD_X, 12)
        with mp.workdps(40):
            t64 = [monodromy(pendulum(log_abs_dE=x, phase=phase)).trace for x in xs]
            t128 = [ext(pendulum(log_abs_dE=x, phase=phase)) for x in xs]
            assert max(abs(a - b) for a, b in zip(t64, t128)) < 1e-12
        # one period of tr M spans both kinds of transition (tr M = Delta^2 >= 0 in libration)
        assert max(t64) > 4.0 and (
            min(t64) < 0.05 if phase == "lib" else min(t64) < 0.0
        )


# --------------------------------------------------------------------------- beyond float64: -800, -10000


@pytest.mark.parametrize("x", [-706.0, -707.0, -800.0])
@pytest.mark.parametrize("phase", ["lib", "rot"])
def test_float64_tier_range(x, phase):
    """float64 covers |E - 4| >= 1.8e-307 (log >= -706.3); deeper is refused with the reason."""
    o = pendulum(log_abs_dE=x, phase=phase)
    if x > -706.3:
        assert math.isfinite(monodromy(o).trace)
    else:
        with pytest.raises(ValueError, match="float64 range.*digits > 15"):
            monodromy(o)


def _shifted(x, x_top=-60.0):
    """x + k * 2 sqrt(3) pi in (x_top - period, x_top], as a 45-digit decimal string."""
    with mp.workdps(60):
        P = 2 * mp.sqrt(3) * mp.pi
        k = mp.floor((x_top - mp.mpf(x)) / P)
        return mp.nstr(mp.mpf(x) + k * P, 45)


@needs_heyoka
@pytest.mark.parametrize("phase", ["lib", "rot"])
def test_cli_deep_pendulum_by_periodicity(phase):
    """``trace pendulum --log-dE -800 -10000 --digits 30`` correct to 1e-20.

    tr M is asymptotically periodic in x = log|E - 4| with period 2 sqrt(3) pi, corrections
    O(|E - 4| log|E - 4|): tr M(x) = tr M(x') for x' = x + k 2 sqrt(3) pi in (-70.9, -60] to ~1e-24.
    tr M(x') (30 digits) is checked against the textbook 4x4 route at 512 bits from a state and
    period built in mpmath directly from x' (tests/independent.py), loss ~2 x 30 digits of 154.
    """
    from independent import textbook_pendulum

    r = subprocess.run(
        [
            sys.executable,
            "-m",
            "rotorlib",
            "trace",
            "pendulum",
            "--log-dE",
            "-800",
            "-1e4",
            "--phase",
            phase,
            "--digits",
            "30",
            "--json",
        ],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert r.returncode == 0, r.stderr
    recs = json.loads(r.stdout)
    for rec, x in zip(recs, (-800.0, -10000.0)):
        assert rec["precision"] == "real128" and rec["log_abs_dE"] in (-800, -1e4)
        xs = _shifted(x)
        shallow = monodromy(pendulum(log_abs_dE=xs, phase=phase), digits=30).trace_str
        ref, _, closure = textbook_pendulum(xs, phase, 512)
        with mp.workdps(60):
            assert abs(mp.mpf(shallow) - ref) < mp.mpf("1e-26")
            assert abs(mp.mpf(rec["trace_str"]) - ref) < mp.mpf("1e-20")
        assert closure < 1e-14


@needs_heyoka
def test_real128_range_refused_multiprecision_beyond():
    """real128 reaches m1 ~ 1e-4800 (log|E - 4| ~ -11050); below, one-line refusal naming the cure."""
    o = pendulum(log_abs_dE="-1e6", phase="lib")
    with pytest.raises(ValueError, match="real128 range.*digits > 31"):
        monodromy(o, digits=30)


# --------------------------------------------------------------------------- decimal input beyond float64


@needs_heyoka
def test_decimal_E_beyond_float64_digits():
    """``--E 3.99999999999999999999`` is 4 - 1e-20 exactly: the 30-digit tier equals the same energy given
    through its log (another input path) to 1e-25, and the float64 tier (which carries eps = 1e-20, not
    E = 4.0) agrees to 1e-12."""
    r = subprocess.run(
        [
            sys.executable,
            "-m",
            "rotorlib",
            *"trace pendulum --E 3.99999999999999999999 --digits 30 --json".split(),
        ],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert r.returncode == 0, r.stderr
    rec = json.loads(r.stdout)
    assert rec["E_str"] == "3.99999999999999999999" and rec["phase"] == "lib"
    with mp.workdps(60):
        x = mp.nstr(mp.log(mp.mpf("1e-20")), 50)
        ref = mp.mpf(
            monodromy(pendulum(log_abs_dE=x, phase="lib"), digits=30).trace_str
        )
        assert abs(mp.mpf(rec["trace_str"]) - ref) < mp.mpf("1e-25")
        assert abs(monodromy(pendulum(E="3.99999999999999999999")).trace - ref) < 1e-12


# --------------------------------------------------------------------------- E up to 1e6 (fast rotation)


@pytest.mark.parametrize("E", [1e2, 1e4, 1e6])
def test_large_E_asymptotics(E):
    """a1 sees the averaged potential, a1'' = -2 a1, over a period 2 pi/sqrt(3E):
    tr M = 2 + 2 cos(2 pi sqrt(2/(3E))) + O(1/E^2) = 4 - 8 pi^2/(3E) + O(1/E^2)."""
    tr = monodromy(pendulum(E=E)).trace
    lead = 8 * math.pi**2 / (3 * E)
    assert abs((4.0 - tr) / lead - 1.0) < 3.0 / E
    o = pendulum(E=E)
    assert (
        abs(o.period - 2 * math.pi / math.sqrt(3 * E))
        < 2 * math.pi / math.sqrt(3 * E) * 2.0 / E
    )


def test_large_E_against_textbook():
    o = pendulum(E=1e6)
    V = variational_monodromy(o.state0, o.period, rtol=1e-13)
    assert abs(V.trace - monodromy(o).trace) < 1e-10


@needs_heyoka
def test_large_E_against_real128():
    o = pendulum(E=1e6)
    with mp.workdps(40):
        assert abs(monodromy(o).trace - ext(o)) < 1e-14


# --------------------------------------------------------------------------- E = 4 refused


@pytest.mark.parametrize(
    "kw",
    [
        dict(E=4.0),
        dict(E=4),
        dict(E="4.000000000000000000000000000000"),
        dict(log_abs_dE=float("-inf"), phase="rot"),
        dict(log_abs_dE=-10.0),
    ],
)
def test_separatrix_refused(kw):
    with pytest.raises(ValueError):
        pendulum(**kw)
    with pytest.raises(ValueError):
        monodromy(**kw)


def test_cli_refuses_E4():
    r = subprocess.run(
        [sys.executable, "-m", "rotorlib", "trace", "pendulum", "--E", "4"],
        capture_output=True,
        text=True,
    )
    assert (
        r.returncode == 2
        and "separatrix" in r.stderr
        and len(r.stderr.strip().splitlines()) == 1
    )


# --------------------------------------------------------------------------- breathers near E = 4.5


@needs_heyoka
@pytest.mark.parametrize("family", ["LG", "LD", "R"])
@pytest.mark.parametrize("x", [-1.0, -5.0, -10.0])
def test_breathers_near_4p5_float64(family, x):
    """Relative accuracy of float64 tr M near the breather separatrix (tr M ~ |E - 4.5|^-2 there);
    the reference is heyoka multiprecision (45 digits), real128 must agree with it too."""
    o = breather(log_abs_dE=x, family=family)
    with mp.workdps(60):
        ref = mp.mpf(monodromy(o, digits=45).trace_str)
        rel = lambda v: float(abs(mp.mpf(v) - ref) / abs(ref))  # noqa: E731
        assert rel(monodromy(o, digits=30).trace_str) < 1e-25
        assert rel(monodromy(o).trace) < 1e-10  # deeper: tests/test_breather_depth.py


@needs_heyoka
@pytest.mark.parametrize("family", ["LG", "LD", "R"])
def test_breathers_deep_extended(family):
    """At |E - 4.5| = e^-20 the real128 tier gives 28+ digits of tr M (~1e17); both tiers read the decimal
    input (the 30-digit tier against an independent reference: tests/test_breather_depth.py)."""
    o = breather(log_abs_dE=-20.0, family=family)
    with mp.workdps(60):
        ref = mp.mpf(monodromy(o, digits=45).trace_str)
        assert abs(mp.mpf(monodromy(o, digits=30).trace_str) / ref - 1) < 1e-27
        assert abs(ref) > 1e15


@pytest.mark.parametrize(
    "E,family", [(4.5, None), (4.5, "LG"), (4.5, "R"), (4.6, "LG"), (4.4, "R")]
)
def test_breather_separatrix_refused(E, family):
    with pytest.raises(ValueError):
        breather(E=E, family=family)
