"""The family CS (rotorlib.beyond.choreo_s) against an independent computation written
here in the rotor angles.

The independent route: three rotors ``theta_i`` with ``H = sum p_i^2/2 + sum (1 -
cos(theta_i - theta_j))`` (zero total momentum, so ``H = E``), started on the mirror
``theta = (s, 0, -s)`` with velocity ``v (1, -2, 1)``, ``v < 0``, at right angles, and
integrated by scipy's DOP853 (rtol 1e-12) to the first time ``t1`` where rotors 2 and 3
coincide (``theta_2 - theta_3 = 0 mod 2 pi``); the orbit is a ``D6`` rotating wave
(``T = 12 t1``) where it meets that mirror at right angles, ``theta_1' = 0``. At a fixed
``s`` that residual is solved for ``E`` by brentq; ``tr DP`` of the map over ``T/6``
from the 6x6 variational equations and the symmetry ``x(t + T/6) = g x(t)`` found here
(the centre of mass adds the multipliers ``-1, -1`` to ``g^-1 Phi``, so ``tr DP = tr -
(-2)``); the fold and the pitchfork are the roots of ``tr DP - 4`` and ``tr DP`` in
``s``, by brentq.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

# the rotor equations (scipy; real128 by heyoka) written in test_choreo, independent of
# rotorlib, and its reading of a state [a1, a2, p1, p2] into rotor angles
from independent import decimal_theta, real128_closure
from scipy.integrate import solve_ivp
from scipy.optimize import brentq
from test_choreo import _rhs as _rhs6
from test_choreo import _rhs_var

from rotorlib import cli
from rotorlib.beyond.choreo_s import cs_family, cs_orbit, cs_orbits, cs_points
from rotorlib.commands.orbit import record

RTOL = 1e-12


def _rhs(t, y):  # the flow (6) or the flow and its 6x6 variational equations (42)
    return _rhs6(t, y) if len(y) == 6 else _rhs_var(t, y)


def _start(s, E):
    V = 3 - 2 * math.cos(s) - math.cos(2 * s)
    v = -math.sqrt((E - V) / 3)  # kinetic energy 3 v^2
    return np.array([s, 0.0, -s, v, -2 * v, v])


def _mirror23(t, y):
    return math.sin((y[1] - y[2]) / 2)


_mirror23.terminal = True


def _shot(s, E):
    """``(theta_1'(t1), t1)`` at the first meeting of the mirror theta_2 = theta_3."""
    sol = solve_ivp(
        _rhs, (0, 50), _start(s, E), "DOP853", rtol=RTOL, atol=1e-14, events=_mirror23
    )
    (t1,), (y1,) = sol.t_events[0][:1], sol.y_events[0][:1]
    return y1[3], t1


def _energy(s, E_lo, E_hi):
    return brentq(lambda E: _shot(s, E)[0], E_lo, E_hi, xtol=1e-15, rtol=1e-15)


def _g():
    """``g`` on the rotor state with ``x(T/6) = g x(0)`` (a signed permutation)."""
    th = np.array([0.3, 0.0, -0.3])
    out = []
    for k in (1, 2):
        for sign in (1, -1):
            P = np.roll(np.eye(3), k, axis=1) * sign
            out.append(np.kron(np.eye(2), P))
    return out, th


def _trace_dp(s, E):
    """``tr DP`` over ``T/6`` and ``T`` at the member ``(s, E)``, and the shift error of
    ``x(T/6) = g x(0)`` (modulo a common rotation and the lattice)."""
    _, t1 = _shot(s, E)
    y0 = np.concatenate([_start(s, E), np.eye(6).ravel()])
    y = solve_ivp(_rhs, (0, 2 * t1), y0, "DOP853", rtol=RTOL, atol=1e-14).y[:, -1]
    x0, x6, Phi = y0[:6], y[:6], y[6:].reshape(6, 6)
    best = None
    for g in _g()[0]:
        d = x6 - g @ x0
        rel = np.array([d[0] - d[1], d[1] - d[2]])
        rel = (rel + math.pi) % (2 * math.pi) - math.pi
        err = max(np.max(np.abs(rel)), np.max(np.abs(d[3:] - d[3:].mean())))
        if best is None or err < best[0]:
            best = (err, g)
    err, g = best
    return float(np.trace(np.linalg.inv(g) @ Phi)) + 2, 12 * t1, err


def _root(level, s_a, s_b, E_guess):
    def f(s):
        E = _energy(s, E_guess - 2e-3, E_guess + 2e-3)
        return _trace_dp(s, E)[0] - level

    s = brentq(f, s_a, s_b, xtol=1e-13)
    return _energy(s, E_guess - 2e-3, E_guess + 2e-3)


def _cli_json(capsys, *argv):
    assert cli.main(list(argv)) == 0
    return json.loads(capsys.readouterr().out)


def test_fold_and_pitchfork_against_independent_brentq(capsys):
    """``family CS --E-range 4.6 6.9 --json``: the pitchfork and the fold against the
    roots of ``tr DP`` and ``tr DP - 4`` found here, to 1e-8; with ``--digits 30``
    (real128) the same points to 1e-12."""
    d = _cli_json(capsys, "family", "CS", "--E-range", "4.6", "6.9", "--json")
    d30 = _cli_json(
        capsys, "family", "CS", "--E-range", "4.6", "6.9", "--digits", "30", "--json"
    )
    pts = {p["kind"]: p for p in d["special_points"]}
    pts30 = {p["kind"]: p for p in d30["special_points"]}
    assert sorted(pts) == sorted(pts30) == ["fold", "pitchfork"]
    for kind, level in (("pitchfork", 0.0), ("fold", 4.0)):
        p, p30 = pts[kind], pts30[kind]
        u, E = p["member"]["u"], p["E"]
        E_ind = _root(level, u - 2e-4, u + 2e-4, E)
        assert abs(E_ind - E) < 1e-8, (kind, E_ind, E)
        assert abs(float(p30["E_str"]) - E) < 1e-12 and len(p30["E_str"]) > 17
        assert "real128 agree to" in p30["located"]
        assert p["branch"] == "CS"
    assert "unstable -> stable" in pts["pitchfork"]["description"]
    assert "extremum of E(u)" in pts["fold"]["located"]
    # and the API's points are those of the command
    assert [q.E for q in cs_points()] == [pts["pitchfork"]["E"], pts["fold"]["E"]]


def test_orbit_cs_against_independent_shooting():
    """``orbit CS --E 5.4``: period, tr M and the D6 symmetry against the shooting here."""
    rec = record("CS", "5.4")
    o = cs_orbit("5.4")
    assert rec["period"] == o.period and rec["trace"] == o.trace
    s0 = 2 * o.state0[0]  # phi1 = phi2 = s on the start mirror
    s = brentq(lambda s: _shot(s, 5.4)[0], s0 - 1e-3, s0 + 1e-3, xtol=1e-15, rtol=1e-15)
    trp, T, err = _trace_dp(s, 5.4)
    assert abs(T - o.period) < 1e-9 * o.period
    assert abs(trp - o.extra["trace_reduced"]) < 1e-7 * max(1, abs(trp))
    assert trp < 0 and not o.extra["stable"]  # unstable in the band: tr DP < 0
    tr_m = 2 + 2 * math.cosh(6 * math.acosh(1 - trp / 2))  # DP's multipliers -e^(+-a)
    assert abs(tr_m - o.trace) < 1e-6 * abs(tr_m)
    assert err < 1e-9
    c = o.extra["choreography"]
    assert c["sixth"] and not c["rotating"]
    assert o.extra["members_at_E"] == 2


def test_orbit_cs_digits30_closes_under_independent_real128():
    """The 30-digit member at E = 5.4 closes under real128 to its |tr M|-amplified
    precision, and its period agrees with the float64 member's."""
    rec = record("CS", "5.4", digits=30)
    o = cs_orbit("5.4", digits=30)
    assert rec["state0_str"] == list(o.state0_str)
    assert abs(float(o.period_str) - cs_orbit(5.4).period) < 1e-11
    th, w = decimal_theta(o.state0_str)
    assert real128_closure(th, w, o.period_str) < 1e-20
    # and the float64 state does not close to that: the test can fail
    th64, w64 = decimal_theta([repr(float(v)) for v in o.state0_str])
    assert real128_closure(th64, w64, o.period_str) > 1e-14


def test_family_json_and_members():
    """``family CS``'s JSON: its points and members; two members below the fold."""
    b = cs_family((4.6, 6.9))
    d = json.loads(json.dumps(b.to_dict()))
    assert [p["kind"] for p in d["special_points"]] == ["pitchfork", "fold"]
    assert all(4.6 <= m["E"] <= 6.9 for m in d["members"])
    # two members below the fold, up to 1e-4 from it (bracketed by the fold itself)
    assert [len(cs_orbits(E)) for E in (5.45, 6.8, 6.8678, 6.87)] == [2, 2, 2, 0]
    short, long_ = cs_orbits(6.8)
    assert short.extra["stable"] and not long_.extra["stable"]


def test_cs_refusals():
    with pytest.raises(ValueError, match="fold"):
        cs_orbit(6.9)
    with pytest.raises(ValueError, match="branch"):
        cs_orbit(5.45, branch=2)
    with pytest.raises(ValueError, match="misses"):
        cs_family((7.0, 8.0))
    with pytest.raises(ValueError, match="number"):
        cs_orbit("abc")
    assert cs_points() == cs_points(None)
