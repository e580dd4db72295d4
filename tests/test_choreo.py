"""The choreographies born at G (rotorlib.beyond.choreo, rotorlib.beyond.choreo_family, ``orbit CG``,
``family``) against independent computations written here in the rotor angles.

The independent route: three rotors ``theta_i`` with ``H = sum p_i^2/2 + sum (1 -
cos(theta_i - theta_j))`` (zero total momentum, so ``H = E``), started on the mirror
``theta = (s, 0, -s)`` (``phi1 = phi2 = s``) with velocity ``-v (1, -2, 1)`` at right
angles, and the choreography condition itself imposed: the state after ``T/3`` is the
relabelled start, ``theta_i(T/3) = theta_{i+1}(0)``. Unknowns ``(s, T)``, solved by
``scipy.optimize.least_squares`` on scipy's DOP853 (rtol 1e-13); ``tr M`` from the 6x6
variational equations (``tr M = tr M6 - 2``: the centre of mass adds a Jordan block at 1).
The real128 checks integrate the same equations with heyoka's real128 Taylor method.
"""

from __future__ import annotations

import math

import mpmath as mp
import numpy as np
import pytest
from independent import PAIRS, decimal_theta, real128_closure, rotor_system
from scipy.integrate import solve_ivp
from scipy.optimize import least_squares

from rotorlib import cli
from rotorlib.beyond.choreo import T0, cg_problem, relabelling
from rotorlib.beyond.choreo_family import (
    cg_orbit,
    family,
    fold,
    fold_energy,
    follow,
    special_points,
)
from rotorlib.commands.orbit import record
from rotorlib.orbits.family import Branch
from rotorlib.orbits.shooting import residual, solve


def _rhs(t, y):
    th, p = y[:3], y[3:]
    f = np.zeros(3)
    for i, j in PAIRS:
        s = math.sin(th[i] - th[j])
        f[i] -= s
        f[j] += s
    return np.concatenate([p, f])


def _rhs_var(t, y):
    th = y[:3]
    out = np.empty_like(y)
    out[:6] = _rhs(t, y[:6])
    H = np.zeros((3, 3))  # d^2 V / d theta^2
    for i, j in PAIRS:
        c = math.cos(th[i] - th[j])
        H[i, i] += c
        H[j, j] += c
        H[i, j] -= c
        H[j, i] -= c
    J = np.zeros((6, 6))
    J[:3, 3:] = np.eye(3)
    J[3:, :3] = -H
    out[6:] = (J @ y[6:].reshape(6, 6)).ravel()
    return out


def _start(s, E):
    V = 3 - 2 * math.cos(s) - math.cos(2 * s)
    # kinetic energy v^2 (1 + 4 + 1)/2 = 3 v^2; the sense of rotation of rotorlib's CG
    v = -math.sqrt(max(E - V, 0.0) / 3)
    return np.array([s, 0.0, -s, v, -2 * v, v])


def _choreo_residual(x, E):
    s, T = x
    y0 = _start(s, E)
    y = solve_ivp(_rhs, (0, T / 3), y0, method="DOP853", rtol=1e-13, atol=1e-15).y[
        :, -1
    ]
    # theta_i(T/3) = theta_{i+1}(0) up to a common shift: compare differences, momenta
    d_now = np.array([y[0] - y[1], y[1] - y[2]])
    d_want = np.array([y0[1] - y0[2], y0[2] - y0[0]])
    dd = (d_now - d_want + math.pi) % (2 * math.pi) - math.pi
    return np.concatenate([dd, y[3:] - np.roll(y0[3:], -1)])


def independent_cg(E, s0, T0_):
    """``(s, T, tr M)`` of the choreography at ``E`` near ``(s0, T0_)``."""
    sol = least_squares(
        _choreo_residual, [s0, T0_], args=(E,), xtol=1e-15, ftol=1e-15, gtol=1e-15
    )
    s, T = sol.x
    y0 = np.concatenate([_start(s, E), np.eye(6).ravel()])
    y = solve_ivp(_rhs_var, (0, T), y0, method="DOP853", rtol=1e-13, atol=1e-15)
    M6 = y.y[6:, -1].reshape(6, 6)
    return s, T, np.trace(M6) - 2, float(np.max(np.abs(sol.fun)))


def _theta_state(rec_state):
    """Rotor angles and momenta (zero total momentum) of a state ``[a1, a2, p1, p2]``."""
    a1, a2, p1, p2 = rec_state
    phi1, phi2 = 2 * a1, a2 - a1
    # theta = (t1, t1 - phi1, t1 - phi1 - phi2), centred; momenta from phi' (H = E)
    th = np.array([0.0, -phi1, -phi1 - phi2])
    th -= th.mean()
    # a1' = p1/2, a2' = 3 p2/2 -> phi1' = p1, phi2' = 3 p2/2 - p1/2
    d1, d2 = p1, 1.5 * p2 - 0.5 * p1
    w = np.array([0.0, -d1, -d1 - d2])
    return th, w - w.mean()


@pytest.mark.parametrize("E", [0.1, 3.0, 5.0, 5.3])
def test_orbit_cg_against_independent_shooting(E):
    rec = record("CG", str(E))
    a1, a2, p1, p2 = rec["state0"]
    s0 = 2 * a1  # phi1 = phi2 = s on the start mirror
    s0 = (s0 + math.pi) % (2 * math.pi) - math.pi
    s, T, tr, res = independent_cg(E, s0 * (1 + 1e-4), rec["period"] * (1 + 1e-4))
    assert res < 1e-11
    assert abs(s - s0) < 1e-8
    assert abs(T - rec["period"]) < 1e-9
    assert abs(tr - rec["trace"]) < 1e-8
    assert rec["choreography"]["sixth"] and not rec["choreography"]["rotating"]
    assert 0 < rec["trace_reduced"] < 4 and rec["stable"]


@pytest.mark.parametrize("E", ["3", "5.3"])
def test_closure_under_independent_real128(E):
    # the float64 orbit closes to its own precision (tr M amplifies ~1e-16)
    rec = record("CG", E)
    th, w = _theta_state(rec["state0"])
    assert real128_closure(th, w, repr(rec["period"])) < 1e-12
    # the 30-digit orbit closes to ~30 digits
    rec30 = record("CG", E, digits=30)
    th, w = decimal_theta(rec30["state0_str"])
    assert real128_closure(th, w, rec30["period_str"]) < 1e-25


def test_digits30_period_against_independent_real128_newton():
    """The 30-digit period at E = 3 against a Newton solve of the T/3 choreography
    condition written here, integrated by heyoka in real128 (finite-difference
    Jacobian in mpmath)."""
    hy = pytest.importorskip("heyoka")
    rec = record("CG", "3", digits=30)
    R = hy.real128
    ta = hy.taylor_adaptive(rotor_system(), [R(0)] * 6, fp_type=R)
    mp.mp.dps = 40
    E = mp.mpf(3)

    def F(s, T):
        V = 3 - 2 * mp.cos(s) - mp.cos(2 * s)
        v = -mp.sqrt((E - V) / 3)
        y0 = [s, 0, -s, v, -2 * v, v]
        ta.time = R(0)
        ta.state[:] = np.array([R(mp.nstr(x, 38)) for x in y0])
        ta.propagate_until(R(mp.nstr(T / 3, 38)))
        y = [mp.mpf(str(x)) for x in ta.state]
        return [(y[0] - y[1]) - (y0[1] - y0[2]), y[3] - y0[4]]

    a1 = mp.mpf(rec["state0_str"][0])
    s = 2 * a1
    s = s - 2 * mp.pi * mp.nint(s / (2 * mp.pi))
    T = mp.mpf(repr(rec["period"]))
    for _ in range(4):
        r = F(s, T)
        h = mp.mpf("1e-16")
        rs, rt = F(s + h, T), F(s, T + h)
        J = mp.matrix([[(rs[i] - r[i]) / h, (rt[i] - r[i]) / h] for i in range(2)])
        ds, dT = mp.lu_solve(J, mp.matrix(r))
        s, T = s - ds, T - dT
    assert abs(T - mp.mpf(rec["period_str"])) < mp.mpf("1e-20")
    mp.mp.dps = 15


def test_fold_at_band_edge_and_refusal(capsys):
    E_f = fold_energy()
    # two locations: the engine's maximum of E along the branch, the root of tr DP = 4
    assert abs(float(follow().fold.E) - E_f) < 1e-12
    # independent: E(s) of the rotor shooting near its maximum (a cubic through 7 points)
    u_f = float(fold()[0])
    hs = np.linspace(-3e-3, 3e-3, 7)
    Es = []
    for h in hs:
        s = u_f + h  # phi1 = phi2 = u on the engine's start line

        def res(x, s=s):
            return _choreo_residual([s, x[1]], x[0])

        # a guess from the engine's member with this amplitude, moved off by 1e-6
        w = solve(cg_problem(), E_f, u=u_f + h)
        T_g = 12 * residual(cg_problem(), u_f + h, w.x).t1
        rec = least_squares(
            res,
            [w.x + 1e-6, T_g * (1 + 1e-6)],
            xtol=1e-15,
            ftol=1e-15,
            gtol=1e-15,
        )
        assert np.max(np.abs(rec.fun)) < 1e-11
        Es.append(rec.x[0])
    c = np.polyfit(hs, Es, 3)
    r = np.roots(np.polyder(c))
    h_max = r[np.argmin(np.abs(r))].real
    assert abs(np.polyval(c, h_max) - E_f) < 1e-9
    # family CG prints it, and the orbit beyond it is refused in one line (exit 2)
    rep = family("CG", (5.3, 5.4))
    assert rep.special_points[-1].kind == "fold" and abs(rep.fold.E - E_f) < 1e-12
    assert cli.main(["orbit", "CG", "--E", f"{E_f + 1e-8:.12f}"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "fold" in err[0]
    below = record("CG", f"{E_f - 1e-8:.12f}")
    assert abs(below["trace_reduced"] - 4) < 1e-3
    assert cli.main(["family", "CG", "--E-range", "5.4", "6"]) == 2
    # the fold re-solved in the 30-digit tier (family --digits 30)
    p30 = special_points("CG", (5.3, 5.4), digits=30)[-1]
    assert len(p30.E_str) >= 20 and abs(float(p30.E_str) - E_f) < 1e-13
    p64 = special_points("CG", (5.3, 5.4))[-1]  # the float64 location
    assert p30.member.precision == "real128" and abs(p30.E - p64.E) < 1e-13
    assert "agree to" in p30.located and p64.located.startswith("located once")


def test_family_stability_kinds():
    """CG is stable from G to the fold (tr DP rises from 1 to 4): its tr M = 0, 4 are no
    stability changes; CT is unstable throughout (tr DP > 4)."""
    pts = special_points("CG")
    assert [p.description.split(" (")[0] for p in pts] == [
        "tr M = 0",
        "tr M = 4",
        "tr M = 0",
        "fold",
    ]
    assert [p.kind for p in pts] == ["touch", "touch", "touch", "fold"]  # no change
    for p in pts[:-1]:
        assert 0 < p.member.trace_reduced < 4 and p.member.stability == "stable"
        assert min(abs(p.member.trace), abs(p.member.trace - 4)) < 1e-8
    assert special_points("CT") == pts[-1:]
    rep = family("CT", (4.6, 5.3))
    assert rep.members and all(
        not m.stable and m.stability == "unstable" and m.trace_reduced > 4
        for m in rep.members
    )


def test_lindstedt_first_correction():
    """(T/T0 - 1)/E -> 1/24 for CG: the slope at E = 1e-3 and 2e-3 extrapolated to 0."""
    r = [(cg_orbit(E).period / T0 - 1) / E for E in (1e-3, 2e-3)]
    slope0 = 2 * r[0] - r[1]
    assert abs(slope0 - 1 / 24) < 1e-6


def test_relabelling_and_refusals():
    C = relabelling()
    assert np.allclose(np.linalg.matrix_power(C, 3), np.eye(4))
    rng = np.random.default_rng(0)
    for x in rng.uniform(-3, 3, (5, 4)):
        a1, a2, p1, p2 = x
        y = C @ x

        def H(a1, a2, p1, p2):
            V = 3 - math.cos(2 * a1) - math.cos(a2 - a1) - math.cos(a1 + a2)
            return p1 * p1 / 4 + 3 * p2 * p2 / 4 + V

        assert abs(H(*x) - H(*y)) < 1e-12
    for bad in ("-1", "0", "nan"):
        assert cli.main(["orbit", "CG", "--E", bad]) == 2
    assert cli.main(["orbit", "CT", "--E", "4.4"]) == 2
    assert cli.main(["family", "CX", "--E-range", "1", "2"]) == 2


def test_atlas_names_choreographies():
    from rotorlib.api import name_choreography
    from rotorlib.beyond.atlas import census

    a = census(5.3, 8.0, known=[], name_choreography=name_choreography)
    named = {o.label: o for o in a.orbits if o.extra["choreography"]}
    assert set(named) == {"CG", "CT"}
    assert named["CG"].stable and not named["CT"].stable
    rec = named["CG"].to_dict()
    assert rec["choreography"]["sixth"] and not rec["choreography"]["rotating"]
    assert abs(named["CG"].period - cg_orbit(5.3).period) < 1e-9
    others = [o for o in a.orbits if not o.extra["choreography"]]
    assert others and all(o.to_dict()["choreography"] is None for o in others)


def _census_data():
    import json
    from pathlib import Path

    path = Path(__file__).parents[1] / "book/data/choreographies_T16.json"
    return json.loads(path.read_text())


def test_z3_family_cr1_against_the_census():
    """The rotating Z3 choreography CR1 followed live from its seed: its PD and its fold
    are those the census's engine located (book/data/choreographies_T16.json, tr M of
    the members: an independent route, to ~1e-9), and the 30-digit locations agree with
    the float64 ones to < 1e-12, the fold also with the extremum of E(u)."""
    from rotorlib.beyond.choreo_z3 import z3_family

    (cr1,) = [f for f in _census_data()["families"] if f["label"] == "CR1"]
    stored = {k: e for k, e in cr1["points"] if k in ("PD", "fold") and e > 5.7}
    r = z3_family("CR1", (5.65, 5.75), digits=30)
    assert isinstance(r, Branch) and r.label == "CR1" and r.stop == "period / period"
    got = {p.kind: p for p in r.special_points}
    assert set(got) == {"PD", "fold"}
    from rotorlib.beyond.choreo_z3 import z3_points

    got64 = {p.kind: p for p in z3_points("CR1") if 5.65 <= p.E <= 5.75}
    for k in ("PD", "fold"):
        assert abs(got[k].member.E - stored[k]) < 1e-8
        assert got[k].member.precision == "real128" and "agree to" in got[k].located
        assert len(got[k].E_str) >= 20 and abs(got[k].E - got64[k].E) < 1e-12
        assert abs(float(got[k].E_str) - got[k].member.E) < 1e-12
    assert abs(got["PD"].member.trace_reduced) < 1e-12
    assert abs(got["fold"].member.trace_reduced - 4) < 1e-12
    assert "extremum of E(u)" in got["fold"].located
    assert r.fold is got["fold"].member and r.E_max == got["fold"].E
    # the 20 digits printed at digits=30 (real128) are those of the 40-digit tier (mp)
    with mp.workdps(40):
        for p40 in z3_points("CR1", 40):
            d = mp.mpf(p40.E_str) - mp.mpf(got[p40.kind].E_str)
            assert 0 < abs(d) < mp.mpf("1e-19")
    # the one stable member lies between PD and fold, where tr DP is in (0, 4)
    (st,) = [m for m in r.members if m.stable]
    assert got["PD"].member.E < st.E < got["fold"].member.E
    assert 0 < st.trace_reduced < 4 and 0 < st.trace < 4
    assert cli.main(["family", "CZ9", "--E-range", "4", "5"]) == 2


def test_family_cli_z3_digits(capsys):
    """``family CR1 --digits 30`` prints the special points to 20 digits."""
    assert (
        cli.main(["family", "CR1", "--E-range", "5.7", "5.71", "--digits", "30"]) == 0
    )
    out = capsys.readouterr().out
    lines = [ln for ln in out.splitlines() if ln.split()[1:2] == ["E"]]
    assert [ln.split()[0] for ln in lines] == ["PD", "fold"]
    for ln in lines:
        E = ln.split()[3]
        assert len(E.split(".")[1]) >= 15
    assert "PD" in out and "fold" in out and "agree to" in out


@pytest.mark.parametrize(
    "label, E_range",
    [
        ("CG", (5.2, 5.4)),
        ("CT", (5.0, 5.4)),
        ("CZ1", (4.4, 4.69)),
        ("CZ2", (4.55, 4.7)),
        ("CR1", (5.7, 5.71)),
    ],
)
def test_every_choreography_family_is_a_branch(label, E_range):
    """rotorlib.family gives one container for every choreography: a Branch of Members
    inside E_range, SpecialPoints of kind fold, IS, PD, touch or resonance; its JSON
    round-trips; a Z3 family's points are the census's
    (book/data/choreographies_T16.json) to 1e-12."""
    import json

    import rotorlib
    from rotorlib.orbits.family import Member, SpecialPoint

    b = rotorlib.family(label, E_range)
    lo, hi = E_range
    assert isinstance(b, Branch) and b.label == label and b.E_range == E_range
    assert b.members and all(isinstance(m, Member) for m in b.members)
    for m in b.members:
        assert lo <= m.E <= hi and m.label == label and m.period == m.factor * m.t1
        assert m.stable == bool(0 < m.trace_reduced < 4)  # the verdict of tr DP
    assert b.special_points and b.stop and b.reason
    for p in b.special_points:
        assert isinstance(p, SpecialPoint)
        assert p.kind in ("fold", "IS", "PD", "touch", "resonance")
        assert p.located and lo <= p.member.E <= hi
        assert -1 <= p.index < len(b.members)
    d = b.to_dict()
    assert json.loads(json.dumps(d, allow_nan=False)) == d
    assert d["E_range"] == list(E_range) and len(d["members"]) == len(b.members)
    assert [q["kind"] for q in d["special_points"]] == [
        p.kind for p in b.special_points
    ]
    assert d["members"][0]["trace_reduced"] == float(b.members[0].trace_reduced)
    if label in ("CG", "CT"):
        return
    (fam,) = [f for f in _census_data()["families"] if f["label"] == label]
    stored = [(q["kind"], q["E"]) for q in fam["special_points"] if lo <= q["E"] <= hi]
    got = [(p.description, p.member.E) for p in b.special_points]
    assert [k for k, _ in got] == [k for k, _ in stored]
    assert all(abs(a - b) < 1e-12 for (_, a), (_, b) in zip(got, stored))


def test_choreography_orbit_z3_against_the_census():
    """``rotorlib.orbit`` for CR1 (and CG) against the census's orbits: period and
    tr M, the choreography's symmetry, and the 30-digit member's closure under an
    independent real128 integration of the rotor equations."""
    from rotorlib import orbit as choreography_orbit

    data = _census_data()
    cr1 = sorted(
        (c for c in data["choreographies"] if c["label"] == "CR1"),
        key=lambda c: c["period"],
    )
    assert len(cr1) == 2 and cr1[1]["period"] - cr1[0]["period"] > 1
    for k, c in enumerate(cr1):
        o = choreography_orbit("CR1", c["E"], branch=k)
        assert abs(o.period - c["period"]) < 1e-9 * c["period"]
        assert abs(o.trace - c["trace"]) < 1e-6 * abs(c["trace"])
        assert o.extra["choreography"]["rotating"] and not o.extra["stable"]
        assert o.extra["members_at_E"] == 2
    cg = [c for c in data["choreographies"] if c["label"] == "CG"][0]
    assert abs(choreography_orbit("CG", cg["E"]).period - cg["period"]) < 1e-9
    o30 = choreography_orbit("CR1", "5.6", digits=30)
    assert abs(float(o30.period_str) - cr1[0]["period"]) < 1e-10
    th, w = decimal_theta(o30.state0_str)
    assert real128_closure(th, w, o30.period_str) < 1e-18


def test_choreography_orbit_refusals(capsys):
    """Beyond a family's range, an unknown label or a missing branch: one line, exit 2."""
    from rotorlib import orbit as choreography_orbit
    from rotorlib.beyond.choreo_z3 import z3_range

    lo, hi, _, why_hi = z3_range("CR1")
    assert abs(lo - 4.5) < 1e-4 and "fold" in why_hi
    with pytest.raises(ValueError, match="fold"):
        choreography_orbit("CR1", hi + 1e-6)
    with pytest.raises(ValueError, match="branch"):
        choreography_orbit("CR1", 5.6, branch=2)
    with pytest.raises(ValueError, match="unknown"):
        choreography_orbit("CZ7", 4.6)
    assert cli.main(["orbit", "CR1", "--E", "5.8"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "CR1 exists only for" in err[0]
    assert cli.main(["orbit", "CG", "--E", "3", "--branch", "1"]) == 2


def test_atlas_names_z3_choreographies():
    """The front door's name for the census's Z3 choreographies (the registry's
    choreography rows): their families' labels."""
    from rotorlib.api import name_choreography
    from rotorlib.beyond.choreo import choreography_of

    for c in _census_data()["choreographies"]:
        chor = choreography_of(c["state0"], c["period"])
        assert chor is not None and chor.to_dict() == c["choreography"]
        assert name_choreography(c["E"], chor, c["period"]) == c["label"]
