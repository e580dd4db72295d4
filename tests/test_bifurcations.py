"""Stability transitions of pendula (issue 3): labels, roots, independent cross-checks, CLI.

Independent checks:

* every one of the 80 transitions (n <= 20 in IS^l, PD^l, IS^r, PD^r) is
  re-located from scratch in heyoka real128 arithmetic (~32 digits, energy
  built in mpmath from log|E-4|, no float64 rounding) and compared with the
  float64 root to 12 significant digits in log|E-4| and in the period;
* a few roots are checked with the textbook route, the full nonlinear flow plus
  the 4x4 variational equations in 256-bit arithmetic (no Hill reduction), at
  the located energy: tr M = 4 (IS) or M_perp = -I (PD^l) or tr M = 0 (PD^r);
* E and the period against mpmath's K(m) from the decimal energy.
"""

import functools
import json
import math
import subprocess
import sys

import mpmath as mp
import numpy as np
import pytest
from conftest import requires_heyoka

import rotorlib
from rotorlib.core.precision import Tier
from rotorlib.paper import bifurcations as bf

pytestmark = requires_heyoka


@functools.cache
def all80():
    return tuple(bf.transitions(phase="both", n_max=20))


def by_label():
    return {t.label: t for t in all80()}


# ----------------------------------------------------------------------------- labels


@pytest.mark.parametrize(
    "text,expected",
    [
        ("IS^l_3", ("IS", "lib", 3)),
        ("ISl3", ("IS", "lib", 3)),
        ("IS^l_{3}", ("IS", "lib", 3)),
        ("PDr2", ("PD", "rot", 2)),
        ("pd^r_12", ("PD", "rot", 12)),
        ("is^L_1", ("IS", "lib", 1)),
        (" PD^ℓ_4 ", ("PD", "lib", 4)),
    ],
)
def test_parse_label_accepts(text, expected):
    assert bf.parse_label(text) == expected


@pytest.mark.parametrize(
    "text",
    ["XYl1", "ISl0", "ISq2", "IS", "IS^l_", "IS^l_-1", "IS^l_1.5", "", "PD r", 3, None],
)
def test_parse_label_rejects(text):
    with pytest.raises(ValueError):
        bf.parse_label(text)


def test_transition_rejects_bad_input():
    with pytest.raises(ValueError):
        bf.transition("ISl0")
    with pytest.raises(ValueError):
        bf.transition("PD^l_140")  # beyond the float64 range of |E - 4|
    with pytest.raises(ValueError):
        bf.transitions(phase="up")
    with pytest.raises(ValueError):
        bf.transitions(n_max=0)
    with pytest.raises(ValueError):
        bf.transitions(kinds=("XX",))


# ----------------------------------------------------------------------------- the 80 roots

# The paper's leading values (Tables I, II; the brief of issue 3), 4 decimals, to pin the numbering.
PAPER_X = {
    "IS^l_1": -4.6658,
    "IS^l_2": -5.7819,
    "IS^l_3": -10.1183,
    "PD^l_1": -2.4268,
    "PD^l_2": -7.9522,
    "PD^r_1": 0.4682,
    "PD^r_2": -0.7395,
    "PD^r_3": -10.1185,
    "IS^r_2": -5.7927,
    "IS^r_3": -15.5598,
}


def test_numbering_and_structure():
    trs = all80()
    assert len(trs) == 80
    d = by_label()
    for lab, x in PAPER_X.items():
        assert abs(d[lab].log_abs_dE - x) < 6e-5, lab
    for kind in ("IS", "PD"):
        for phase in ("lib", "rot"):
            seq = [t for t in trs if t.kind == kind and t.phase == phase]
            assert [t.n for t in seq] == list(range(1, 21))
            xs = [t.log_abs_dE for t in seq]
            assert all(a > b for a, b in zip(xs, xs[1:])), (
                kind,
                phase,
            )  # n increases towards E = 4
            for t in seq:
                assert t.label == f"{kind}^{'l' if phase == 'lib' else 'r'}_{t.n}"
                assert (
                    float(t.log_abs_dE_str) == t.log_abs_dE
                    and len(t.log_abs_dE_str.lstrip("-0.")) >= 15
                )
                assert t.energy.phase == phase and t.energy.log_abs_dE == t.log_abs_dE
    # stability directions (paper Tables I, II headers) and the value of Delta
    for t in trs:
        if t.phase == "lib" and t.kind == "PD":
            assert t.transition == "stable->stable" and t.delta_target == 0.0
        elif t.phase == "lib":
            assert t.transition == (
                "stable->unstable" if t.n % 2 else "unstable->stable"
            )
            assert abs(t.delta_target) == 2.0
        elif t.kind == "IS":
            assert (
                t.transition == ("unstable->stable" if t.n % 2 else "stable->unstable")
                and t.delta_target == 2
            )
        else:
            assert (
                t.transition == ("unstable->stable" if t.n % 2 else "stable->unstable")
                and t.delta_target == -2
            )


def test_roots_satisfy_the_condition_and_slopes():
    """tr M from rotorlib.monodromy at each root is 4 or 0, and the slope sign matches the direction."""
    for t in all80():
        M = rotorlib.monodromy(rotorlib.pendulum(t.energy))
        target = 4.0 if t.kind == "IS" else 0.0
        assert abs(M.trace - target) < 1e-11, t.label
        if not (t.kind == "PD" and t.phase == "lib"):
            h = 1e-6  # tr M one step on either side in x
            up = rotorlib.monodromy(log_abs_dE=t.log_abs_dE + h, phase=t.phase).trace
            dn = rotorlib.monodromy(log_abs_dE=t.log_abs_dE - h, phase=t.phase).trace
            assert abs((up - dn) / (2 * h) - t.dtrace_dx) < 1e-5 * max(
                1, abs(t.dtrace_dx)
            ), t.label
            assert math.copysign(1, t.dtrace_dE) == math.copysign(1, t.dtrace_dx) * (
                1 if t.phase == "rot" else -1
            )


def test_no_missed_roots_between_grid_points():
    """The scan step (0.05) is far below the smallest spacing of consecutive roots of one equation."""
    trs = all80()
    for phase in ("lib", "rot"):
        for target in (2.0, -2.0, 0.0):
            xs = sorted(
                t.log_abs_dE
                for t in trs
                if t.phase == phase and t.delta_target == target
            )
            if len(xs) > 1:
                assert min(np.diff(xs)) > 1.0
    # libration near E = 0: Delta + 2 ~ 7e-4 E^3 > 0 (stable) on (0, 0.1], below where the scan starts
    for E in (1e-3, 0.01, 0.05, 0.1):
        assert 3e-4 * E**3 < bf.delta(math.log(4 - E), "lib") + 2.0 < 1e-3 * E**3
    # rotation at high energy: Delta < 2 and increasing towards 2 (no transition above the scan start)
    ds = [bf.delta(x, "rot") for x in (8.0, 10.0, 14.0, 20.0)]
    assert all(d < 2.0 for d in ds) and all(a < b for a, b in zip(ds, ds[1:]))


def test_energy_and_period_consistency():
    """E = 4 -/+ exp(x) and period = 4K/sqrt3 (lib) or 2 kappa K/sqrt3 (rot), from mpmath at 60 digits."""
    for t in all80():
        with mp.workdps(60 + int(-t.log_abs_dE / 2.3)):
            x = mp.mpf(t.log_abs_dE_str)
            eps = mp.exp(x)
            E = 4 - eps if t.phase == "lib" else 4 + eps
            assert abs(mp.mpf(t.energy.decimal_E(20)) - E) < eps * 1e-15
            if t.phase == "lib":
                period = 4 * mp.ellipk(E / 4) / mp.sqrt(3)
            else:
                period = 2 * mp.sqrt(4 / E) * mp.ellipk(4 / E) / mp.sqrt(3)
            assert abs(t.period - float(period)) < 1e-13 * float(period), t.label
            assert abs(t.E - float(E)) < 1e-15


def test_all_80_against_real128_relocation():
    """Issue 3 must-show: every one of the 80 roots to 12 significant digits (log|E-4| and period),
    re-located independently in real128 (heyoka, ~32 digits). Measured agreement: ~2e-15 relative."""
    worst_x = worst_p = 0.0
    for t in all80():
        with mp.workdps(45):
            x, per = bf.refine_mp(t.log_abs_dE, t.phase, t.delta_target, digits=30)
            # the real128 root satisfies the condition to ~1e-25
            assert abs(bf.delta_mp(x, t.phase, 30) - t.delta_target) < mp.mpf(
                "1e-24"
            ), t.label
            ex = abs(float(x) - t.log_abs_dE) / abs(float(x))
            ep = abs(float(per) - t.period) / float(per)
        assert ex < 1e-12 and ep < 1e-12, (t.label, ex, ep)
        worst_x, worst_p = max(worst_x, ex), max(worst_p, ep)
    assert (
        worst_x < 1e-14 and worst_p < 1e-14
    )  # what we actually reach (documented in the module)


def test_transition_digits30_is_refined():
    t = bf.transition("IS^l_3", digits=30)
    assert t.precision == "real128" and len(t.log_abs_dE_str.lstrip("-0.")) >= 29
    with mp.workdps(40):
        x = mp.mpf(t.log_abs_dE_str)
        assert abs(float(x) - by_label()["IS^l_3"].log_abs_dE) < 1e-13
        assert abs(bf.delta_mp(x, "lib", 30) + 2) < mp.mpf("1e-26")
        assert abs(
            mp.mpf(t.period_str) - 4 * mp.ellipk(1 - mp.exp(x) / 4) / mp.sqrt(3)
        ) < mp.mpf("1e-27")
    assert t.energy.given == ("log_abs_dE", t.log_abs_dE_str)


@pytest.mark.parametrize(
    "label", ["PD^l_1", "IS^l_1", "IS^l_2", "PD^r_1", "IS^r_2", "IS^l_3"]
)
def test_textbook_variational_at_located_roots(label):
    """The 4x4 variational equations of the full flow in 256-bit arithmetic (independent of the Hill
    reduction) at the root refined in real128: tr M = 4 (IS), 0 (PD^r), M_perp = -I (PD^l, double zero)."""
    t = by_label()[label]
    with mp.workdps(50):
        x, per = bf.refine_mp(t.log_abs_dE, t.phase, t.delta_target, digits=30)
        E = 4 - mp.exp(x) if t.phase == "lib" else 4 + mp.exp(x)
        state0 = ["0", "0", "0", mp.nstr(mp.sqrt(4 * E / 3), 45)]
        v = rotorlib.variational_monodromy(
            state0, mp.nstr(per, 45), digits=Tier("mp256")
        )
        tr = mp.mpf(v.trace_str)
    assert v.closure < 1e-25
    M = v.matrix  # state order a1, a2, p1, p2
    Mperp = M[np.ix_([0, 2], [0, 2])]
    if t.kind == "IS":
        assert abs(tr - 4) < mp.mpf("1e-24")
    elif t.phase == "rot":
        assert abs(tr) < mp.mpf("1e-24")
    else:
        assert np.max(np.abs(Mperp + np.eye(2))) < 1e-24
    # transverse eigenvector of the parabolic block (paper §5.3)
    mu = 1.0 if t.kind == "IS" else -1.0
    if not (t.kind == "PD" and t.phase == "lib"):
        N = Mperp - mu * np.eye(2)
        expect = (
            (1, 0)
            if ((t.phase == "lib") == (t.transition == "stable->unstable"))
            else (0, 1)
        )
        v_null = np.array(expect, dtype=float)
        assert np.max(np.abs(N @ v_null)) < 1e-20  # (1,0) or (0,1) is in the null space
        assert (
            np.max(np.abs(N @ v_null[::-1])) > 0.1
        )  # and the block is not -/+ I: rank 1


# ----------------------------------------------------------------------------- CLI


def run(*args):
    p = subprocess.run(
        [sys.executable, "-m", "rotorlib", *args],
        capture_output=True,
        text=True,
        timeout=300,
    )
    return p.returncode, p.stdout, p.stderr


def test_cli_json_matches_library():
    rc, out, err = run("bifurcations", "--phase", "both", "--n-max", "3", "--json")
    assert rc == 0, err
    recs = json.loads(out)
    assert isinstance(recs, list) and len(recs) == 12
    d = by_label()
    for r in recs:
        for key in (
            "label",
            "kind",
            "phase",
            "n",
            "log_abs_dE",
            "E",
            "period",
            "transition",
        ):
            assert key in r
        t = d[r["label"]]
        assert r["kind"] == t.kind and r["phase"] == t.phase and r["n"] == t.n
        assert isinstance(r["log_abs_dE"], float) and r["log_abs_dE"] == t.log_abs_dE
        with mp.workdps(40):
            assert (
                abs(
                    mp.mpf(r.get("E_str", repr(r["E"])))  # E_str: digits beyond E
                    - 4
                    - (1 if t.phase == "rot" else -1) * mp.exp(t.log_abs_dE)
                )
                < 1e-14 * t.energy.eps
            )
        assert r["period"] == t.period and r["transition"] == t.transition
    rc, out, err = run(
        "bifurcations", "--phase", "rot", "--kind", "PD", "--n-max", "1", "--json"
    )
    assert rc == 0, err
    recs = json.loads(out)
    assert [r["label"] for r in recs] == ["PD^r_1"]


@pytest.mark.parametrize(
    "args",
    [
        ("--n-max", "0"),
        ("--n-max", "201"),
        ("--phase", "up"),
        ("--kind", "XY"),
        ("--n-max", "150"),
    ],
)
def test_cli_bad_input_one_line(args):
    rc, out, err = run("bifurcations", *args)
    assert rc == 2 and err.count("\n") == 1 and "Traceback" not in err


def test_cli_breather_family():
    rc, out, err = run("bifurcations", "--family", "breather", "--json")
    try:
        import rotorlib.paper.breathers  # noqa: F401
    except ModuleNotFoundError:
        assert rc == 2 and "breather transitions are not available yet" in err
        return
    assert rc == 0, err
    recs = json.loads(out)
    assert isinstance(recs, list) and all(
        "E" in r and "period" in r and "kind" in r for r in recs
    )


# ----------------------------------------------------------------------------- tr M_perp asymptotics (paper §5.2)

from rotorlib.paper import cascade_scaling as sc  # noqa: E402


def test_fit_harmonic_recovers_coefficients():
    tau = np.linspace(0.0, 20.0, 400)
    y = 0.3 + 1.7 * np.cos(tau) - 0.4 * np.sin(tau)
    f = sc.fit_harmonic(tau, y, 5.0, 5.0 + 2 * np.pi)
    assert (
        abs(f.c0 - 0.3) < 1e-12 and abs(f.c1 - 1.7) < 1e-12 and abs(f.s1 + 0.4) < 1e-12
    )
    assert abs(f.amplitude - math.hypot(1.7, 0.4)) < 1e-12 and f.max_residual < 1e-12
    assert np.allclose(f.c0 + f.amplitude * np.cos(tau + f.phase), y, atol=1e-12)
    assert 5.0 <= f.tau_min < f.tau_max <= 5.0 + 2 * np.pi and f.n == int(
        ((tau >= 5) & (tau <= 5 + 2 * np.pi)).sum()
    )


@pytest.mark.parametrize(
    "tau,y,lo,hi",
    [
        (np.arange(5.0), np.arange(4.0), -np.inf, np.inf),  # shapes differ
        (np.arange(10.0), np.arange(10.0), 2.0, 3.5),  # 2 samples in the window
        (np.arange(10.0), np.r_[np.arange(9.0), np.nan], -np.inf, np.inf),  # not finite
        (np.ones((3, 3)), np.ones((3, 3)), -np.inf, np.inf),  # not 1-d
    ],
)
def test_fit_harmonic_rejects_bad_input(tau, y, lo, hi):
    with pytest.raises(ValueError):
        sc.fit_harmonic(tau, y, lo, hi)


def test_separatrix_transmission_against_direct_scattering():
    """|t|^2 from the closed form against integrating -y'' - (2/3) sech^2(z) y = (1/3) y across the well."""
    from scipy.integrate import solve_ivp

    q = 1 / math.sqrt(3.0)

    def rhs(z, Y):
        k = 1 / 3 + (2 / 3) / math.cosh(z) ** 2
        return [Y[1], -k * Y[0], Y[3], -k * Y[2]]

    sol = solve_ivp(
        rhs,
        (-40.0, 40.0),
        [1.0, 0.0, 0.0, 1.0],
        method="DOP853",
        rtol=1e-13,
        atol=1e-15,
    )
    y1, dy1, y2, dy2 = sol.y[:, -1]
    S = np.array(
        [[y1, q * y2], [dy1 / q, dy2]]
    )  # in (y, y'/q), where free motion is a rotation
    assert abs(np.linalg.det(S) - 1) < 1e-10
    T_direct = 4.0 / (
        (S[0, 0] + S[1, 1]) ** 2 + (S[0, 1] - S[1, 0]) ** 2
    )  # amplitude of tr(R(theta) S) = 2/|t|
    T = sc.separatrix_transmission()
    assert abs(T_direct - T) < 1e-9 and 0.9 < T < 0.901
    assert abs(float(sc.separatrix_transmission(30)) - T) < 1e-15
    for bad in (0, -3, 2.5, "30"):
        with pytest.raises(ValueError):
            sc.separatrix_transmission(bad)


def test_trace_asymptotics_against_the_80_roots_and_a_deep_fit():
    T = by_label()
    rot, lib = sc.trace_asymptotics("rot"), sc.trace_asymptotics("lib")
    t = math.sqrt(rot.transmission)
    assert (
        rot.amplitude == 2 / t and rot.c0 == 0 and abs(lib.amplitude - 2 / t**2) < 1e-15
    )
    assert (
        abs(lib.c0 - (lib.amplitude - 2)) < 1e-15
        and abs(lib.window_width - 2 * rot.window_width) < 1e-15
    )
    # the unstable windows keep the width 2 arccos|t| (rotation) and 4 arccos|t| (libration)
    for a, b, w in (
        ("IS^r_19", "IS^r_20", rot.window_width),
        ("PD^r_19", "PD^r_20", rot.window_width),
        ("IS^l_19", "IS^l_20", lib.window_width),
    ):
        assert abs(T[b].period - T[a].period - w) < 1e-11
    # the fitted amplitude of tr M_perp on one period deep in rotation (log|E - 4| from -26 to -37)
    tr, tau = bf.trace_curve(np.linspace(-26.0, -37.0, 800), "rot")
    f = sc.fit_harmonic(tau, tr - 2.0)
    assert (
        abs(f.amplitude - rot.amplitude) < 1e-9
        and abs(f.c0) < 1e-9
        and f.max_residual < 1e-8
    )
    with pytest.raises(ValueError):
        sc.trace_asymptotics("both")


# ----------------------------------------------------------------------------- one Transition


def test_one_transition_class_for_pendulum_and_breather():
    """Pendulum and breather transitions are one class that follows the result protocol
    (a SpecialPoint too), and rotorlib.transition() is the one front door for both (ASCII
    and paper labels); bifurcations.transition knows the pendulum's labels only."""
    from rotorlib.orbits.family import SpecialPoint
    from rotorlib.paper.breathers import pd_transition

    b = rotorlib.transition("PD^b")
    assert type(b) is bf.Transition and isinstance(b, SpecialPoint)
    assert (
        b.to_dict() == rotorlib.transition("PDb").to_dict() == pd_transition().to_dict()
    )
    assert b.member is None and b.families == ("PD^b",) and "tr M = 0" in b.located
    with pytest.raises(ValueError, match="pendulum's transitions"):
        bf.transition("PD^b")
    p = rotorlib.transition("ISl2")
    assert p.to_dict() == bf.transition("IS^l_2").to_dict() and p.families == (
        "IS^l_2",
    )
    for t, fam, level in ((p, "pendulum", 4.0), (b, "R", 0.0)):
        assert t.family == fam and t.trace == level and t.stability == "marginal"
        assert not t.stable and t.digits == 15 and t.precision == "float64"
        assert abs(t.multipliers[2] - (1 if level else -1)) < 1e-12
        rec = t.to_dict()
        assert rec["E"] == t.E and rec["trace"] == level and rec["family"] == fam
        assert rec["stability"] == "marginal" and rec["slope"] == t.slope
        # state0 at G from the closed form: H(state0) = E
        a1, a2, p1, p2 = t.state0
        assert abs(p1**2 / 4 + 3 * p2**2 / 4 - t.E) < 1e-13 * t.E
    assert p.slope == p.dtrace_dE and b.cls == "PD^b" and p.cls == "IS^l_even"
    # monodromy(transition) evaluates M at the transition's energy, breathers too
    assert abs(rotorlib.monodromy(b).trace) < 1e-9
    assert abs(rotorlib.monodromy(p).trace - 4) < 1e-10


def test_breather_transition_extended_and_bad_labels():
    b30 = rotorlib.transition("PD^b", digits=30)
    assert b30.digits == 25 and b30.precision == "real128"
    assert len(b30.E_str.replace(".", "")) == 25
    with mp.workdps(40):  # tr M at E_str, evaluated independently of the locator
        M = rotorlib.monodromy(rotorlib.breather(b30.E_str, "R"), digits=30)
        assert abs(mp.mpf(M.trace_str)) < mp.mpf("1e-22")
        assert mp.mpf(b30.state0_str[3]) ** 2 - mp.mpf(b30.E_str) < mp.mpf("1e-23")
    for bad in ("PD^c", "IS^b_1", "XYl1", 3):
        with pytest.raises(ValueError, match="PD\\^b"):
            rotorlib.transition(bad)


def test_locators_agree_with_brent():
    """The one locator (the engine's Illinois method) against scipy's brentq."""
    from scipy.optimize import brentq

    t = by_label()["PD^l_2"]
    a, b = t.log_abs_dE - 0.01, t.log_abs_dE + 0.01
    x = brentq(lambda x: bf.delta(x, "lib"), a, b, xtol=1e-14)
    assert abs(x - t.log_abs_dE) < 1e-13
    with mp.workdps(30):
        r = bf.refine_root(lambda v: v**3 - 2, 1.25992105, 20)
        assert abs(r - mp.cbrt(2)) < mp.mpf("1e-20")
    with pytest.raises(RuntimeError):
        bf.refine_root(lambda v: v * v + 1, 0.0, 20)


def test_cli_json_is_to_dict_for_both_families(capsys):
    """``bifurcations --json`` prints Transition.to_dict(), breathers included, and
    --digits applies to the breather too."""
    from rotorlib.cli import main

    assert (
        main(["bifurcations", "--family", "breather", "--digits", "30", "--json"]) == 0
    )
    (rec,) = json.loads(capsys.readouterr().out)
    assert rec == json.loads(
        json.dumps(rotorlib.transition("PD^b", digits=30).to_dict())
    )
    assert rec["precision"] == "real128" and len(rec["E_str"]) > 20
    assert main(["bifurcations", "--n-max", "1", "--kind", "PD", "--json"]) == 0
    recs = json.loads(capsys.readouterr().out)
    assert [r["label"] for r in recs] == ["PD^l_1", "PD^r_1"]
    assert recs[1] == json.loads(json.dumps(by_label()["PD^r_1"].to_dict()))
