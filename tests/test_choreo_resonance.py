"""CG's resonances and the choreographies born there (rotorlib.beyond.choreo_rotation,
rotorlib.beyond.choreo_resonance) against independent computations written here in the
rotor angles.

The independent route: three rotors ``theta_i`` with ``H = sum p_i^2/2 + sum (1 -
cos(theta_i - theta_j))``. CG is solved with the rotor equations of ``tests/test_choreo.py`` (start on the
mirror ``theta = (s, 0, -s)`` with velocity ``-v (1, -2, 1)``; the condition
``theta_i(T/3) = theta_{i+1}(0)`` imposed; ``least_squares`` on scipy's DOP853 at rtol
1e-12). Its reduced map over ``T/6`` is ``S^-1 Phi(T/6)`` on the six rotor variables,
``S`` the rotation of the hexagon (``theta_i -> -theta_{i+2}``, picked here as the one of
``S^{+-1}`` that maps the start to the state at ``T/6``), whose trace is ``tr DP - 2``
(the centre of mass adds ``-[[1, t], [0, 1]]``). The resonance ``p/q`` is the root of
``tr DP - 2 - 2 cos 2 pi p/q`` in ``E`` by ``brentq``. The 30-digit members of the
families close under heyoka's real128 Taylor method on the rotor equations, and their
third of a period is a relabelling of the rotors.
"""

from __future__ import annotations

import math

import mpmath as mp
import numpy as np
import pytest
from independent import decimal_theta, real128_states
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, least_squares
from test_choreo import _rhs, _rhs_var, _start  # rotors

from rotorlib.beyond import choreo_resonance as cr
from rotorlib.beyond import choreo_rotation as ro

RTOL = 1e-12


def _ivp(f, y0, T):
    return solve_ivp(f, (0, T), y0, method="DOP853", rtol=RTOL, atol=1e-14).y[:, -1]


def _cg_residual(x, E):
    s, T = x
    y0 = _start(s, E)
    y = _ivp(_rhs, y0, T / 3)
    d_now = np.array([y[0] - y[1], y[1] - y[2]])
    d_want = np.array([y0[1] - y0[2], y0[2] - y0[0]])
    dd = (d_now - d_want + math.pi) % (2 * math.pi) - math.pi
    return np.concatenate([dd, y[3:] - np.roll(y0[3:], -1)])


def _hexagon(k):
    """``theta_i -> -theta_{i+2}`` (k = 1) or its inverse (k = -1) on (theta, p)."""
    P = np.roll(np.eye(3), -2 if k == 1 else 2, axis=1)
    S = np.zeros((6, 6))
    S[:3, :3] = S[3:, 3:] = -P
    return S


def _centred(y):
    z = y.copy()
    z[:3] -= z[:3].mean()
    z[:3] = (z[:3] + math.pi) % (2 * math.pi) - math.pi
    return z


def independent_trace_reduced(E, guess):
    """``(tr DP, s, T)`` of CG at ``E`` (guess ``(s, T)``)."""
    sol = least_squares(_cg_residual, guess, args=(E,), xtol=1e-15, ftol=1e-15)
    s, T = sol.x
    y0 = _start(s, E)
    y = _ivp(_rhs_var, np.concatenate([y0, np.eye(6).ravel()]), T / 6)
    Phi = y[6:].reshape(6, 6)
    err = {
        k: np.max(np.abs(_centred(y[:6]) - _centred(_hexagon(k) @ y0))) for k in (1, -1)
    }
    k = min(err, key=err.get)
    assert err[k] < 1e-9, err
    return float(np.trace(np.linalg.inv(_hexagon(k)) @ Phi)) + 2, s, T


@pytest.mark.parametrize("pq", ro.RESONANCES)
def test_resonance_energy_against_independent_brentq(pq):
    p, q = pq
    r = ro.resonance(p, q)
    assert r.rotation == f"{p}/{q}" and len(r.families) == 2
    lev = 2 + 2 * math.cos(2 * math.pi * p / q)
    u = float(r.member.u)  # phi1 = phi2 = u: theta = (u, 0, -u) up to a shift
    guess = [u, float(r.member.period)]

    def f(E):
        trp, s, T = independent_trace_reduced(E, guess)
        guess[:] = [s, T]
        return trp - lev

    dE = 2e-3
    E = brentq(f, r.E - dE, r.E + dE, xtol=1e-13, rtol=1e-14)
    assert abs(E - r.E) < 1e-8
    assert abs(float(r.member.trace_reduced) - lev) < 1e-10


def test_rotation_number_falls_from_one_third_to_zero():
    E, rho, T = ro.rotation_curve()
    assert np.all(np.diff(T) > 0)
    assert abs(rho[0] - 1 / 3) < 1e-3 and rho[-1] < 0.05
    assert np.all(np.diff(rho) < 0)
    # each resonance sits where the curve passes its level
    for r in ro.resonances():
        assert abs(ro.rotation_number(r.member.trace_reduced) - r.p / r.q) < 1e-12
        i = np.searchsorted(E, r.E)
        assert rho[i - 1] > r.p / r.q > rho[i]
    assert math.isnan(ro.rotation_number(4.5)) and math.isnan(ro.rotation_number(-0.1))
    with pytest.raises(ValueError, match="rotation number"):
        ro.resonance(1, 3)
    with pytest.raises(ValueError, match="rotation number"):
        ro.resonance(1, 2)


def test_resonance_digits30_agrees_with_float64():
    r = ro.resonance(1, 7, digits=30)
    assert r.refined is not None and r.agreement < 1e-11
    assert len(r.E_str.replace(".", "")) >= 12
    assert abs(float(r.E_str) - r.E) < 1e-11


def _theta(state_str):
    th, w = decimal_theta(state_str)  # the rotor state, 38 digits
    return th + w


def _shift_error(a, b, k):
    """``max |state a - relabelled state b|`` (relative angles mod 2 pi, momenta);
    relabelled: ``theta_i -> theta_{i+k}``."""
    b = b[k:3] + b[:k] + b[3 + k :] + b[3 : 3 + k]
    d = [(a[0] - a[1]) - (b[0] - b[1]), (a[1] - a[2]) - (b[1] - b[2])]
    d = [v - 2 * mp.pi * mp.nint(v / (2 * mp.pi)) for v in d]
    return float(max(abs(v) for v in d + [a[i] - b[i] for i in range(3, 6)]))


def _near_birth(name):
    lo, hi, why_lo, _ = cr.resonance_range(name)
    born_above = "born" in why_lo
    r = ro.resonance(*(int(v) for v in name[2:-1].split("/")))
    return f"{r.E + (0.01 if born_above else -0.01):.4f}"


@pytest.mark.parametrize("name", cr.family_names())
def test_digits30_member_closes_under_independent_real128(name):
    """Every family named at a resonance (CG1/4a, CG1/4b are CZ2, CZ1: ~25 s each, the
    Z3 continuation of chapter 10)."""
    E = _near_birth(name)
    o = cr.resonance_orbit(name, E, digits=30)
    assert (
        abs(float(E) - float(ro.resonance(*map(int, name[2:-1].split("/"))).E)) < 0.02
    )
    with mp.workdps(40):
        y0 = [mp.mpf(v) for v in _theta(o.state0_str)]
        T = mp.mpf(o.period_str)
        y3, yT = real128_states(
            _theta(o.state0_str), [mp.nstr(T / 3, 36), o.period_str]
        )
        closure = _shift_error(yT, y0, 0)
        third = min(_shift_error(y3, y0, k) for k in (1, 2))
    assert closure < 1e-20, closure
    assert third < 1e-20, third
    assert o.extra["choreography"] is not None
    assert not o.extra["choreography"]["rotating"]
    assert o.label == name


def test_family_cg_json_lists_resonances_and_touches(capsys):
    """``family CG --E-range 0.1 5.3153 --json``: the five resonances with ``rotation``,
    ``E`` (that of ``resonance``, checked independently above) and ``families``; every
    touch of tr M = 0 or 4 without a change of stability has kind ``touch``."""
    import json

    from rotorlib import cli

    assert cli.main(["family", "CG", "--E-range", "0.1", "5.3153", "--json"]) == 0
    rec = json.loads(capsys.readouterr().out)
    pts = rec["special_points"]
    res = [p for p in pts if p["kind"] == "resonance"]
    assert [p["rotation"] for p in res] == ["2/7", "1/4", "1/5", "1/7", "1/8"]
    for p in res:
        r = ro.resonance(*map(int, p["rotation"].split("/")))
        assert abs(p["E"] - r.E) < 1e-12
        assert p["families"] == list(r.families)
    for p in pts:
        if "(no change" in p["description"] and p["kind"] != "resonance":
            assert p["kind"] == "touch"  # 1/4 is also CG's touch tr M = 0
        assert p["kind"] not in ("IS", "PD") or "stable" in p["description"]
    assert {p["kind"] for p in pts} <= {"fold", "IS", "PD", "touch", "resonance"}
    assert sum(p["kind"] == "touch" for p in pts) >= 2  # 1:6 and 1:12


@pytest.mark.parametrize("name", ["CG1/5a", "CG1/8b"])
def test_orbit_and_family_cli_serve_the_new_families(name, capsys):
    import json

    from rotorlib import cli

    E = _near_birth(name)
    assert cli.main(["orbit", name, "--E", E, "--json"]) == 0
    rec = json.loads(capsys.readouterr().out)
    assert rec["choreography"] is not None and rec["label"] == name
    assert cli.main(["family", name.lower(), "--E-range", "4.6", "5.3", "--json"]) == 0
    b = json.loads(capsys.readouterr().out)
    kinds = [p["kind"] for p in b["special_points"]]
    assert "fold" in kinds  # the birth at CG
    assert cli.main(["orbit", name, "--E", "5.4"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "exists only for" in err[0]
