"""The periodic-orbit engine (rotorlib.orbits.shooting, rotorlib.orbits.continuation): one residual, one
corrector, one continuation, at every precision, checked against what it does not use."""

import contextlib
import io
import json
import math

import mpmath as mp
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from rotorlib.core.flow import Section, SectionNotReached, crossings, to_section
from rotorlib.core.precision import REAL128, Tier, heyoka_available, tier
from rotorlib.core.system import rhs_alpha
from rotorlib.orbits.floquet import variational_monodromy
from rotorlib.orbits.shooting import NoConvergence, residual, secant, solve
from rotorlib.paper import newborn as nb

pytestmark = pytest.mark.skipif(not heyoka_available(), reason="heyoka not installed")


def test_tiers_match_the_hill_tiers():
    from rotorlib.core.precision import precision_tier

    for d in (None, 5, 15, 16, 31, 32, 60, 200):
        assert tier(d).name == precision_tier(d)[1]
    assert tier(20, extra=12).name.startswith("mp")  # 20 digits after losing 12
    for bad in (0, 1001, 2.5, True, "10"):
        with pytest.raises(ValueError):
            tier(bad)
    with pytest.raises(ValueError):
        Tier("float32")
    with mp.workdps(40):
        assert REAL128.num(0.1) == mp.mpf("0.1")  # a float is read as its decimal


def test_modular_section_crossings_against_scipy():
    """Every crossing of a2 = pi (mod 2 pi) going up, located by heyoka, agrees with scipy."""
    x0 = [0.1, 0.0, 0.0, 2.4]
    sec = Section((0, 1, 0, 0), 1.0, 1, period=2.0)
    hits = crossings(x0, (sec,), 20.0)
    ev = lambda t, y: math.sin((y[1] - math.pi) / 2)  # noqa: E731
    sol = solve_ivp(
        rhs_alpha, (0, 20), x0, method="DOP853", rtol=1e-12, atol=1e-12, events=ev
    )
    ups = [t for t, y in zip(sol.t_events[0], sol.y_events[0]) if 1.5 * y[3] > 0]
    assert len(hits) == len(ups) >= 5
    assert np.allclose([h[1] for h in hits], ups, atol=1e-9)
    t3, x3 = to_section(x0, sec, crossing=3)
    assert (
        abs(t3 - ups[2]) < 1e-9
        and abs(math.remainder(x3[1] - math.pi, 2 * math.pi)) < 1e-12
    )
    with pytest.raises(SectionNotReached):
        to_section(x0, sec, crossing=3, t_max=1.0)


def test_a_start_at_an_equilibrium_never_reaches_a_section():
    """At the saddle (a1, a2) = (pi/2, -pi/2) at rest (E = 4), which the census's start
    set meets at E = 4: SectionNotReached at once, in float64 and real128 (heyoka's
    event would fire again at rest at every step: 14,000 event stops per shot, and
    round-off then passes for crossings), and a start 1e-3 away from it still crosses."""
    sec = Section((1.0, 1.0, 0.0, 0.0), 0.0, 0, 2.0)
    x0 = [math.pi / 2, -math.pi / 2, 0.0, 0.0]
    assert max(abs(v) for v in rhs_alpha(0.0, x0)) < 1e-15
    for digits in (None, 30):
        with pytest.raises(SectionNotReached) as exc:
            to_section(x0, sec, digits, crossing=2, t_max=17.3)
        assert exc.value.crossings == 0
    t1, _ = to_section([x0[0] + 1e-3, x0[1], 0.0, 0.0], sec, crossing=2, t_max=17.3)
    assert 0 < float(t1) < 17.3


def test_residual_gradient_against_finite_differences():
    """The variational gradient (event time differentiated) against a central difference."""
    spec = nb.family_spec("PD^r_1")
    for prob in (spec.problem, spec.problem.chart(4.0)):
        m, _ = nb.seed("PD^r_1")
        u, w = m.u * 5, prob.w_at(m.u * 5, m.E + 1e-4)
        s = residual(prob, u, w, derivative=True)
        for k, (du, dw) in enumerate(((1e-6, 0), (0, 1e-7))):
            fd = (
                residual(prob, u + du, w + dw).r - residual(prob, u - du, w - dw).r
            ) / (2 * (du or dw))
            assert abs(s.grad[k] / fd - 1) < 1e-5, (k, s.grad[k], fd)


def test_secant_and_solve_errors():
    r = secant(lambda x: x * x - 2, 1.0, 1.5, 1e-15)
    assert r.converged and abs(r.x - math.sqrt(2)) < 1e-15
    prob = nb.family_spec("IS^l_1").problem
    with pytest.raises(ValueError):
        solve(prob, 0.1, u=0.1, E=4.0)  # exactly one unknown fixed
    with pytest.raises(ValueError):
        residual(prob, 0.0, 3.995)  # the parent itself (u = trivial)
    with pytest.raises(NoConvergence) as e:
        solve(prob, 3.999, u=0.5)  # no member with u = 0.5 there
    assert e.value.fixed == {"u": 0.5}


def test_palc_passes_folds_and_locates_them():
    """PD^r_2 and PD^r_1 fold back in E at the energies the old continuation measured."""
    for label, E_fold in (("PD^r_2", 4.5516743), ("PD^r_1", 5.9831001)):
        b = nb.follow(label, max_steps=300)
        f = b.fold
        assert f is not None and abs(float(f.E) - E_fold) < 2e-7, (label, f)
        k = b.points("fold")[0].index
        assert max(b.E[: k + 1]) <= float(f.E) + 1e-12 and b.E[-1] < float(f.E) - 1e-3


def test_energy_events_are_members_at_that_energy():
    b = nb.follow("PD^r_2", E_range=(None, 4.55), energies=(4.52, 4.54))
    pts = b.points("E")
    assert [round(float(p.member.E), 12) for p in pts] == [4.52, 4.54]
    for p in pts:  # the same orbit, found at fixed E
        o = nb.newborn_orbit("PD^r_2", float(p.member.E), digits=15)
        assert abs(o.extra["u"] - float(p.member.u)) < 1e-9


def test_trace_events_against_the_textbook_monodromy():
    """Where the engine locates tr M = 4 (an IS point), the independent 4x4 route agrees."""
    b = nb.follow("IS^r_2", chart="K", E_range=(None, 4.03), traces=True)
    p = [p for p in b.special_points if p.kind in ("IS", "PD")][0]
    x0 = np.array(b.state(p.member), float)
    v = variational_monodromy(x0, b.problem.factor * float(p.member.t1), rtol=1e-13)
    level = 4.0 if p.kind == "IS" else 0.0
    assert abs(v.trace - level) < 1e-6 and v.closure < 1e-8
    assert abs(float(p.member.E) - 4.0181836) < 1e-7  # chapter 08's exit


def test_same_member_in_every_tier():
    o64 = nb.newborn_orbit("PD^r_1", 5.7, digits=15)
    o128 = nb.newborn_orbit("PD^r_1", 5.7, digits=25)
    o40 = nb.newborn_orbit("PD^r_1", 5.7, digits=40)
    assert (o64.precision, o128.precision) == (
        "float64",
        "real128",
    ) and o40.precision.startswith("mp")
    assert (
        abs(o64.trace - o40.trace) < 1e-10
        and abs(float(o128.trace_str) - o40.trace) < 1e-15
    )
    with mp.workdps(60):
        assert abs(mp.mpf(o128.period_str) - mp.mpf(o40.period_str)) < mp.mpf("1e-24")


def _record(*argv):
    from rotorlib.cli import main

    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        assert main(list(argv)) == 0
    return json.loads(buf.getvalue())


def _independent_256_bit(state, period):
    """The 4x4 variational equations integrated over ``period`` from ``state`` with a heyoka
    integrator built here (256-bit MPFR), not by rotorlib. Returns ``(x(T), tr M)`` as mpf."""
    import heyoka as hy

    a1, a2, p1, p2 = hy.make_vars("a1", "a2", "p1", "p2")
    sm, sp = hy.sin(a2 - a1), hy.sin(a1 + a2)
    sys = [
        (a1, p1 / 2.0),
        (a2, 1.5 * p2),
        (p1, -(2.0 * hy.sin(2.0 * a1) - sm + sp)),
        (p2, -(sm + sp)),
    ]
    x0 = [hy.real(v, 256) for v in state]
    ta = hy.taylor_adaptive(
        hy.var_ode_sys(sys, hy.var_args.vars),
        x0,
        fp_type=hy.real,
        prec=256,
        compact_mode=True,
    )
    ta.propagate_until(hy.real(period, 256))
    with mp.workdps(80):
        st = [mp.mpf(str(v)) for v in ta.state]
        return st[:4], st[4] + st[9] + st[14] + st[19]


@pytest.mark.slow
@pytest.mark.parametrize(
    "label,E,lattice",
    [("ISl2", "4", (0, 0)), ("PDr3", "4.0002", (0, 4)), ("PDb", "8.3", (2, 6))],
)
def test_sixty_digits_against_an_independent_256_bit_integration(label, E, lattice):
    """The issue's must-show: ``orbit LABEL --E V --digits 60 --json`` returns 60-digit strings;
    energy, closure and trace agree with an independent 256-bit integration (a heyoka
    integrator built in this test, not by rotorlib) to ~1e-50."""
    rec = _record("orbit", label, "--E", E, "--digits", "60", "--json")
    s, T, tr = rec["state0_str"], rec["period_str"], rec["trace_str"]

    def significant(text):
        return len(
            text.lower().split("e")[0].replace("-", "").replace(".", "").lstrip("0")
        )

    assert all(significant(v) >= 60 for v in [T, tr] + [v for v in s if mp.mpf(v) != 0])
    assert rec["residual"] < 1e-55
    xT, trace = _independent_256_bit(s, T)
    with mp.workdps(80):
        x0 = [mp.mpf(v) for v in s]
        a1, a2, p1, p2 = x0
        H = (
            p1**2 / 4
            + 3 * p2**2 / 4
            + 3
            - mp.cos(2 * a1)
            - mp.cos(a2 - a1)
            - mp.cos(a1 + a2)
        )
        assert abs(H - mp.mpf(E)) < mp.mpf("1e-55")
        shift = [lattice[0] * mp.pi, lattice[1] * mp.pi, 0, 0]
        assert max(abs(b - a - c) for a, b, c in zip(x0, xT, shift)) < mp.mpf("1e-50")
        assert abs(trace - mp.mpf(tr)) < mp.mpf("1e-49") * max(1, abs(trace))


def test_a_rational_period_factor_is_exact_in_an_extended_tier():
    """A member whose period is 2/3 of t1 (the pendulum's record crossing its target set
    three times): in real128 and at 40 digits the period is 2 t1 / 3 to the tier's
    precision (the float 2/3 limited it, and the catalogue's closure, to ~1e-16);
    float64 and integer factors are unchanged."""
    import mpmath as mp

    from rotorlib.core.precision import tier
    from rotorlib.orbits.family import Member

    for D in (30, 40):
        t = tier(D)
        with t.context():
            t1 = t.num("4.123456789012345678901234567890123")
            m = Member(0, 0, 4, t1, 0, factor=2 / 3, precision=t.name)
            assert abs(m.period - 2 * t1 / 3) < 10 * t.eps * t1
            assert (
                abs(Member(0, 0, 4, t1, 0, factor=2, precision=t.name).period - 2 * t1)
                == 0
            )
    f = Member(0, 0, 4, 3.0, 0, factor=2 / 3)
    assert f.period == (2 / 3) * 3.0 and not isinstance(f.period, mp.mpf)
