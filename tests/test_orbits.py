"""Closed-form pendula and breathers against the equations of motion, at the extremes too."""

import math

import mpmath as mp
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from rotorlib.core.closed_forms import breather, pendulum, separatrix_pendulum_state
from rotorlib.core.system import energy_alpha, rhs_alpha


def _eom_residual(orbit, n=801):
    T = orbit.period
    t = np.linspace(0, T, n)
    h = 1e-6 * T
    X = orbit.state(t)
    dX = (orbit.state(t + h) - orbit.state(t - h)) / (2 * h)
    F = np.array([rhs_alpha(0, x) for x in X])
    return np.max(np.abs(dX - F)) / max(1.0, np.max(np.abs(F)))


PENDULA = [
    dict(E=0.01),
    dict(E=1.0),
    dict(E=3.9),
    dict(E=5.0),
    dict(E=100.0),
    dict(E=1e6),
    dict(log_abs_dE=-30, phase="lib"),
    dict(log_abs_dE=-30, phase="rot"),
    dict(log_abs_dE=-300, phase="lib"),
    dict(log_abs_dE=-700, phase="rot"),
]
BREATHERS = [
    (0.01, "LG"),
    (3.0, "LG"),
    (4.0, "LG"),
    (4.3, "LG"),
    (4.4999, "LG"),
    (4.0001, "LD"),
    (4.3, "LD"),
    (4.4999, "LD"),
    (4.5001, "R"),
    (4.6, "R"),
    (9.0, "R"),
    (20.0, "R"),
    (1e4, "R"),
]


@pytest.mark.parametrize("kw", PENDULA)
def test_pendulum_energy_and_eom(kw):
    o = pendulum(**kw)
    t = np.linspace(0, o.period, 2001)
    E = energy_alpha(o.state(t))
    assert np.max(np.abs(E - o.E)) < 5e-15 * max(1, o.E)
    assert _eom_residual(o) < 1e-6  # finite-difference limited


@pytest.mark.parametrize("E,fam", BREATHERS)
def test_breather_energy_eom_and_closure(E, fam):
    o = breather(E, fam)
    t = np.linspace(-o.period, 2 * o.period, 3001)
    X = o.state(t)
    assert np.max(np.abs(energy_alpha(X) - E)) < 5e-15 * max(1, E)
    assert _eom_residual(o) < 1e-6
    f0, _ = o.phi(0.0)
    f1, _ = o.phi(o.period)
    assert abs(f1 - f0 - (2 * np.pi if fam == "R" else 0.0)) < 1e-12


@pytest.mark.parametrize("E", [0.5, 2.0, 3.99])
def test_pendulum_period_by_quadrature(E):
    # tau = 4 int_0^{a_max} da / a2', a2' = sqrt(3 (E - 2 + 2 cos a))
    with mp.workdps(30):
        amax = 2 * mp.asin(mp.sqrt(mp.mpf(E) / 4))

        def f(a):
            return mp.re(1 / mp.sqrt(3 * (E - 2 + 2 * mp.cos(a))))

        ref = 4 * mp.quad(f, [0, amax])
    assert abs(pendulum(E).period / float(ref) - 1) < 1e-13


@pytest.mark.parametrize(
    "E,fam", [(1.0, "LG"), (4.3, "LG"), (4.3, "LD"), (6.0, "R"), (30.0, "R")]
)
def test_breather_period_by_quadrature(E, fam):
    # E = phi'^2 + 3 - 2 cos phi - cos 2 phi; tau = closed-loop integral of dphi / phi'
    def v(f):
        return E - 3 + 2 * mp.cos(f) + mp.cos(2 * f)

    def inv(f):
        return mp.re(1 / mp.sqrt(v(f)))

    with mp.workdps(30):
        if fam == "R":
            ref = mp.quad(inv, [0, mp.pi, 2 * mp.pi])
        else:
            c = (
                -1 + mp.sqrt(9 - 2 * E)
            ) / 2  # cos of the turning point nearest the centre
            if fam == "LG":
                fmax = mp.acos(c)
                ref = 4 * mp.quad(inv, [0, fmax])
            else:
                fmin = mp.acos((-1 - mp.sqrt(9 - 2 * E)) / 2)
                ref = 4 * mp.quad(inv, [fmin, mp.pi])
    assert abs(breather(E, fam).period / float(ref) - 1) < 1e-12


def test_closed_form_beats_integration_near_separatrix():
    """At log(4-E) = -30 the closed form closes exactly; a DOP853 integration of the pendulum cannot."""
    o = pendulum(log_abs_dE=-30, phase="lib")
    assert np.max(np.abs(o.state(o.period) - o.state0)) < 1e-13
    sol = solve_ivp(
        rhs_alpha, (0, o.period), o.state0, method="DOP853", rtol=1e-12, atol=1e-12
    )
    assert np.max(np.abs(sol.y[:, -1] - o.state0)) > 1e-6


def test_period_logarithmic_divergence():
    for x in (-20.0, -60.0, -300.0):
        o = pendulum(log_abs_dE=x, phase="lib")
        asym = (
            -2 / math.sqrt(3) * (x - math.log(4) - math.log(16))
        )  # -(2/w0) log((1-E/4)/16)
        assert abs(o.period - asym) < 10 * math.exp(x) + 4e-16 * o.period
        r = pendulum(log_abs_dE=x, phase="rot")
        kappa = math.sqrt(r.energy.m)
        asym_r = -kappa / math.sqrt(3) * (math.log(r.energy.m1) - math.log(16))
        assert abs(r.period - asym_r) < 10 * math.exp(x) * abs(x) + 4e-16 * r.period


def test_separatrix_state():
    t = np.linspace(-5, 5, 101)
    X = separatrix_pendulum_state(t)
    assert np.max(np.abs(energy_alpha(X) - 4.0)) < 1e-14


@pytest.mark.parametrize(
    "kw",
    [
        dict(E=-1.0),
        dict(E=4.0),
        dict(E=float("nan")),
        dict(E=float("inf")),
        dict(E="abc"),
        dict(log_abs_dE=2.0, phase="lib"),
        dict(log_abs_dE=-30.0),
        dict(log_abs_dE="-inf", phase="rot"),
        dict(log_abs_dE="-1e400", phase="lib"),
        dict(E="1e-1000000", phase="lib"),
        dict(E=True),
        dict(E=3.0, phase="rot"),
        dict(E=1.0, log_abs_dE=-3.0, phase="lib"),
        dict(log_abs_dE=-3.0, phase="up"),
    ],
)
def test_pendulum_bad_input(kw):
    with pytest.raises(ValueError):
        pendulum(**kw)


@pytest.mark.parametrize("phase", ["lib", "rot"])
def test_beyond_float64_range(phase):
    """log|E-4| = -800: the energy is carried by its log; K, period (float64 view of the mpmath closed
    form) follow the logarithmic asymptotics; the float64 state refuses (|E-4| is not a normal float)."""
    o = pendulum(log_abs_dE=-800, phase=phase)
    assert (
        o.energy.eps < 1e-307
        and o.energy.log_abs_dE == -800.0
        and not o.energy.in_float64_range
    )
    # K = log(4/sqrt(m1)) + O(m1 log m1), m1 = eps/4 (lib) or eps/E (rot), E = 4 to 1e-347
    K = math.log(4.0) - 0.5 * (-800.0 - math.log(4.0))
    assert abs(o.K - K) < 1e-13 * K
    per = 4 * K / math.sqrt(3) if phase == "lib" else 2 * K / math.sqrt(3)
    assert abs(o.period - per) < 1e-13 * per
    assert math.isinf(o.dperiod_dE)  # ~ 1/|E - 4|: beyond float64
    with pytest.raises(ValueError, match="float64 range"):
        o.state(0.0)
    with pytest.raises(ValueError, match="float64 range"):
        o.closed_form()


def test_decimal_energy_read_exactly():
    """A decimal with more digits than float64: E = 4 - 1e-20 keeps its distance (E itself rounds to 4.0)."""
    o = pendulum(E="3.99999999999999999999")
    assert o.energy.phase == "lib" and o.energy.E == 4.0 and o.energy.eps == 1e-20
    assert abs(o.energy.log_abs_dE - math.log(1e-20)) < 1e-15 * 46
    with mp.workdps(50):
        v = o.energy.mp_values(40)
        assert abs(v["eps"] / mp.mpf("1e-20") - 1) < mp.mpf(
            "1e-39"
        )  # correct to 40 digits
        assert abs(v["E"] - mp.mpf("3.99999999999999999999")) < mp.mpf("4e-39")
    b = breather(E="4.5000000000000000000000000001")
    assert b.energy.family == "R" and b.energy.eps == 1e-28 and b.E == 4.5
    with pytest.raises(ValueError, match="separatrix"):
        pendulum(E="4.000000000000000000000000")
    with pytest.raises(ValueError, match="separatrix"):
        breather(E="4.50")


@pytest.mark.parametrize(
    "E,fam",
    [
        (4.5, None),
        (4.3, "R"),
        (5.0, "LG"),
        (3.9, "LD"),
        (-0.1, None),
        (float("nan"), "R"),
        (5.0, "XX"),
    ],
)
def test_breather_bad_input(E, fam):
    with pytest.raises(ValueError):
        breather(E, fam)


@pytest.mark.parametrize(
    "make",
    [
        lambda: pendulum(E=1.0),
        lambda: pendulum(E=0.001),
        lambda: pendulum(log_abs_dE=-30, phase="lib"),
        lambda: pendulum(log_abs_dE=-30, phase="rot"),
        lambda: breather(E=3.0, family="LG"),
        lambda: breather(E=4.0, family="LG"),
        lambda: breather(log_abs_dE=-30, family="LD"),
        lambda: breather(E=9.0, family="R"),
        lambda: breather(log_abs_dE=-30, family="R"),
    ],
)
def test_closed_form_float64_against_mpmath(make):
    """The float64 and the 40-digit closed forms are the same formulas: K, period, d(period)/dE agree
    to float64 accuracy, and d(period)/dE agrees with a 40-digit numerical derivative of the period."""
    o = make()
    f = o.closed_form(derivative=True)
    with mp.workdps(50):
        g = o.closed_form(40, derivative=True)
        for key in ("K", "period", "dperiod_dE"):
            assert abs(f[key] / g[key] - 1) < 2e-14, key
        # the 40-digit derivative against differentiation of the 40-digit period along the decimal E
        E0, h = g["E"], min(g["E"] * mp.mpf("1e-12"), g["eps"] * mp.mpf("1e-6"))
        fam = o.energy.family if o.family != "pendulum" else None

        def period(E):
            text = mp.nstr(E, 45)
            orb = pendulum(E=text) if fam is None else breather(E=text, family=fam)
            return orb.closed_form(45)["period"]

        num = (period(E0 + h) - period(E0 - h)) / (2 * h)
        assert abs(num / g["dperiod_dE"] - 1) < 1e-9
