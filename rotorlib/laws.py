"""The laws of the cascade (paper §7.3-7.6): slope theorems, fans, self-similar scaling and duality.

Built on :mod:`rotorlib.bifurcations` (pendulum transitions, ``Delta``) and
:mod:`rotorlib.newborn` (the families born there).

Slope theorems (§7.3)
---------------------
Near an isochronous (fork-like) bifurcation the new family obeys
``E - E_n = c u^2 + O(u^4)`` and ``tr M - 4 = d u^2 + O(u^4)`` with ``u`` its
``a1`` amplitude, so ``d tr M_new / dE = d / c`` at birth. :func:`fork_fit`
fits both against ``s = u^2`` (least squares, quadratic in ``s``, no constant
term: the family starts at the pendulum) on members just above birth; this is
a continuation derivative, not a two-point difference near a root. The
pendulum's slope is computed independently here by a central difference of
``Delta(x)`` (``x = log|E - 4|``, :func:`rotorlib.bifurcations.delta`) and
compared with ``Transition.dtrace_dE``. The theorems: ``tr M_pend' = -(1/2)
tr M_new'`` (IS) and ``tr M_pend' = (1/8) tr M_new'`` (PD^r, the new orbit's
``M`` being over its doubled period).

Fans (§7.4)
-----------
Librational families are evaluated at ``E = 4`` itself. Rotational families
exist only above ``E_n > 4``; their ``tr M(E)`` is extrapolated linearly back to
``E = 4`` with the newborn slope: ``tr M(4) ~ 4 + s_new (4 - E_n)``. With the
slope theorem ``s_new = r s_pend`` (``r = -2`` IS, ``8`` PD) this is
``4 - r dtrM_pend/dx`` (:func:`fan_prediction`), a function of the pendulum alone
that is asymptotically periodic in ``x`` with the period of the cascade, so
every class of rotational bifurcation (IS^r odd/even, PD^r odd/even) has a fan
in this extrapolated sense.

Scaling (§7.5) and duality (§7.6)
---------------------------------
Amplitude ratios at ``E = 4`` (:func:`amplitudes`, :func:`ratios`),
the asymptotic formulas ``a1max ~ sqrt(E - E_n)``, ``pi - a2max ~ sqrt(4 - E_n)``,
the energies of dual bifurcations (:func:`duality_pairs`) and the periodic
transverse (Lamé) solutions at dual transitions (:func:`dual_lame`).

Rotational families in amplitude (§7.5, §9)
-------------------------------------------
The rotational scaling constants ``alpha^r``, ``beta^r`` need a family far from its
birth (IS^r_3 at E(IS^r_1)). :func:`follow_rotational` continues a rotational family
in its amplitude ``u`` with the energy ``q`` of the ``a2`` motion above the barrier
as second unknown (:func:`rotational_state`), passing folds in ``E``;
:func:`rotational_member` matches a prescribed ``E - 4`` (float64 or heyoka
real128), :func:`rotational_ratios` forms the paper's ratios, and
:func:`branch_profile` / :func:`rotational_exit` give ``tr M`` along a branch and
where it leaves ``[0, 4]``. Every rotational family followed (IS^r_1..4, PD^r_2..4)
ends at ``E -> 4.5``, the maximum of the potential, with a diverging period.
"""
from __future__ import annotations

import json
import math
import subprocess
import sys
from dataclasses import dataclass, field

import numpy as np

__all__ = ["SQRT3_PI", "DELTA_L", "SQRT_DELTA_L", "SlopeLaw", "fork_fit", "pendulum_slope", "pendulum_dtrace_dx", "newborn_slope",
           "slope_law", "cli_orbit", "expected_ratio", "fan_prediction", "fan_traces", "amplitudes", "ratios",
           "asymptotic_a1", "asymptotic_a2_deficit", "DualPair", "dual_label", "duality_pairs", "fit_rate",
           "dual_lame", "reach", "compare", "table", "rotational_state", "rotational_dE", "rotational_residual",
           "RotationalBranch", "follow_rotational", "RotationalMember", "rotational_member", "RotationalRatio",
           "rotational_ratios", "BranchProfile", "branch_profile", "rotational_exit",
           "BranchStability", "branch_stability"]

#: ``sqrt(3) pi``; ``delta^l = e^{sqrt3 pi}`` (230.76), ``sqrt(delta^l) = e^{sqrt3 pi / 2}`` (15.19).
SQRT3_PI = math.sqrt(3.0) * math.pi
DELTA_L = math.exp(SQRT3_PI)
SQRT_DELTA_L = math.exp(SQRT3_PI / 2)


# --------------------------------------------------------------------------- slope theorems (§7.3)

@dataclass(frozen=True)
class SlopeLaw:
    """Slopes of ``tr M(E)`` at a bifurcation: pendulum and newborn family.

    Attributes
    ----------
    label : str
    E_birth : float
    pendulum_slope : float
        ``d tr M / dE`` of the pendulum at ``E_n`` (central difference of ``Delta``).
    pendulum_slope_lib : float
        The same from ``Transition.dtrace_dE`` (an independent implementation).
    newborn_slope : float
        ``d/c`` of :func:`fork_fit`.
    ratio : float
        ``newborn_slope / pendulum_slope``.
    expected : float
        ``-2`` (IS) or ``8`` (PD^r).
    c, d : float
        ``E - E_n ~ c u^2``, ``tr M - 4 ~ d u^2``.
    fit_residual : float
        Largest residual of the two fits relative to the data range.
    E, trace, u : tuple
        The members used.
    """

    label: str
    E_birth: float
    pendulum_slope: float
    pendulum_slope_lib: float
    newborn_slope: float
    ratio: float
    expected: float
    c: float
    d: float
    fit_residual: float
    E: tuple = field(default=())
    trace: tuple = field(default=())
    u: tuple = field(default=())

    @property
    def rel_error(self) -> float:
        """``|ratio / expected - 1|``."""
        return abs(self.ratio / self.expected - 1.0)


def fork_fit(E, trace, u, E_birth, trace_birth=4.0, degree=2):
    """Fit ``E - E_n = c1 s + c2 s^2`` and ``tr M - 4 = d1 s + d2 s^2`` with ``s = u^2``.

    Returns ``(slope = d1/c1, c1, d1, residual)``; ``residual`` is the largest
    fit residual relative to the range of the data (both fits). Needs at least
    ``degree + 1`` members.
    """
    E = np.asarray(E, float) - float(E_birth)
    y = np.asarray(trace, float) - float(trace_birth)
    s = np.asarray(u, float) ** 2
    if len(s) < degree + 1:
        raise ValueError(f"fork_fit needs at least {degree + 1} members, got {len(s)}")
    if np.any(s <= 0):
        raise ValueError("amplitudes must be nonzero (the members must lie on the new family)")
    A = np.column_stack([s ** k for k in range(1, degree + 1)])
    sc = s.max()
    cE, *_ = np.linalg.lstsq(A / sc ** np.arange(1, degree + 1), E, rcond=None)
    cT, *_ = np.linalg.lstsq(A / sc ** np.arange(1, degree + 1), y, rcond=None)
    cE = cE / sc ** np.arange(1, degree + 1)
    cT = cT / sc ** np.arange(1, degree + 1)
    res = max(np.max(np.abs(A @ cE - E)) / np.ptp(E), np.max(np.abs(A @ cT - y)) / max(np.ptp(y), 1e-300))
    return float(cT[0] / cE[0]), float(cE[0]), float(cT[0]), float(res)


def expected_ratio(label) -> float:
    """The slope theorem's ``tr M_new' / tr M_pend'``: -2 (IS^l, IS^r), 8 (PD^r)."""
    from .bifurcations import parse_label

    kind, phase, _ = parse_label(label)
    if kind == "PD" and phase == "lib":
        raise ValueError("PD^l: tr M of pendulum and new family both have a double zero (no slope law)")
    return -2.0 if kind == "IS" else 8.0


def pendulum_dtrace_dx(label, h=1e-5) -> float:
    """``d tr M / dx`` of the pendulum at the transition, ``x = log|E - 4|``: central difference of
    ``tr M(Delta(x))`` (``Delta`` float64-accurate to ~1e-13; ``h = 1e-5``: ~1e-8 relative + ``O(h^2)``)."""
    from .bifurcations import delta, trace_of_delta, transition

    t = transition(label)
    x = t.log_abs_dE
    tp = trace_of_delta(delta(x + h, t.phase), t.phase)
    tm = trace_of_delta(delta(x - h, t.phase), t.phase)
    return float((tp - tm) / (2 * h))


def pendulum_slope(label, h=1e-5) -> float:
    """``d tr M / dE`` of the pendulum at the transition: ``(dtrM/dx) / (E - 4)`` with
    :func:`pendulum_dtrace_dx` and ``E - 4 = -+e^x`` (libration / rotation)."""
    from .bifurcations import transition

    t = transition(label)
    sign = -1.0 if t.phase == "lib" else 1.0
    return pendulum_dtrace_dx(label, h) / (sign * math.exp(t.log_abs_dE))


def slope_law(label, E, trace, u) -> SlopeLaw:
    """:class:`SlopeLaw` from given members ``(E, trace, u)`` of the family born at ``label``."""
    from .bifurcations import transition

    t = transition(label)
    s_new, c, d, res = fork_fit(E, trace, u, t.E)
    s_p = pendulum_slope(label)
    return SlopeLaw(t.label, t.E, s_p, float(t.dtrace_dE), s_new, s_new / s_p, expected_ratio(label), c, d, res,
                    tuple(float(v) for v in E), tuple(float(v) for v in trace), tuple(float(v) for v in u))


def newborn_slope(label, rel=(2e-4, 5e-4, 1e-3, 2e-3, 4e-3), precision=None) -> SlopeLaw:
    """Members at ``E_n + r |E_n - 4|`` (``rotorlib.newborn.newborn_orbit``) and their fork fit.

    The energies are formed in mpmath from the transition's ``log|E_n - 4|`` and passed as decimal
    strings (so ``E - E_n`` keeps its digits even 1e-10 from E = 4, where a float64 ``E`` would lose
    them); the amplitude is the shooting unknown ``u`` (``a1(0)`` or ``p1(0)``).
    """
    import mpmath as mp

    from .bifurcations import transition
    from .newborn import newborn_orbit

    t = transition(label)
    sign = 1 if t.phase == "rot" else -1
    with mp.workdps(40):
        eps = mp.e ** mp.mpf(t.log_abs_dE_str)
        Es = [mp.nstr(4 + sign * eps + mp.mpf(r) * eps, 36) for r in rel]
        dE = [float(mp.mpf(r) * eps) for r in rel]
    orbs = [newborn_orbit(label, E if (precision or "") != "float64" else float(E), precision=precision) for E in Es]
    amp = [abs(float(o.extra.get("u", o.alpha1_max))) for o in orbs]
    tr = [o.trace for o in orbs]
    s_new, c, d, res = fork_fit(dE, tr, amp, 0.0)
    s_p = pendulum_slope(label)
    return SlopeLaw(t.label, t.E, s_p, float(t.dtrace_dE), s_new, s_new / s_p, expected_ratio(label), c, d, res,
                    tuple(float(o.E) for o in orbs), tuple(tr), tuple(amp))


def cli_orbit(label, E, timeout=120) -> dict:
    """The JSON record of ``python -m rotorlib orbit LABEL --E E --json`` (a subprocess)."""
    out = subprocess.run([sys.executable, "-m", "rotorlib", "orbit", str(label), "--E", repr(float(E)), "--json"],
                         capture_output=True, text=True, timeout=timeout)
    if out.returncode != 0:
        raise ValueError(f"rotorlib orbit {label} --E {E!r} failed: {out.stderr.strip()}")
    rec = json.loads(out.stdout)
    return rec[0] if isinstance(rec, list) else rec


# --------------------------------------------------------------------------- fans (§7.4)

def fan_prediction(label) -> float:
    """Backward linear extrapolation of a rotational family to E = 4 using the slope theorem.

    ``tr M(4) ~ 4 + r s_pend (4 - E_n) = 4 - r dtrM_pend/dx`` with ``r`` from :func:`expected_ratio`
    (pendulum data only; float64, ~1e-8 relative).
    """
    return float(4.0 - expected_ratio(label) * pendulum_dtrace_dx(label))


def fan_traces(labels, E=4.0) -> dict:
    """``{label: PeriodicOrbit}`` at energy ``E`` (``newborn_orbit`` default precision: real128 near E = 4)."""
    from .newborn import newborn_orbit

    return {lab: newborn_orbit(lab, E) for lab in labels}


def reach(label, E_target):
    """How far the family born at ``label`` continues towards ``E_target``.

    Returns ``(E_reached, message)``: ``E_target`` and ``''`` when reached, else the last energy the
    continuation of :mod:`rotorlib.newborn` found (parsed from its error) and the message.
    """
    import re

    from .newborn import newborn_orbit

    try:
        newborn_orbit(label, E_target)
        return float(E_target), ""
    except ValueError as exc:
        m = re.search(r"beyond E = ([0-9.eE+-]+)", str(exc))
        return (float(m.group(1)) if m else float("nan")), str(exc)


# --------------------------------------------------------------------------- scaling of shapes (§7.5)

def amplitudes(orbit) -> tuple:
    """``(a1max, pi - a2max)`` of a librational newborn orbit, located in real128 from its 32-digit state.

    Falls back to the orbit's float64 extrema when no ``state0_str`` was stored.
    """
    st = orbit.extra.get("state0_str")
    if st is None:
        return float(orbit.alpha1_max), float(math.pi - orbit.alpha2_max)
    per = orbit.extra.get("period_str", orbit.period)
    return _extrema_real128(st, per)


def _extrema_real128(state, period):
    import mpmath as mp

    from . import flow

    ta = flow._extrema_integrator("real128")
    ta.time = flow.to_fp(0.0, "real128")
    ta.state[:] = np.array([flow.to_fp(v, "real128") for v in state], dtype=flow._dtype("real128"))
    flow._FOUND.clear()
    ta.propagate_until(flow.to_fp(period, "real128"))
    pts = list(flow._FOUND)
    flow._FOUND.clear()
    with mp.workdps(36):
        a1 = max(abs(mp.mpf(str(x[0]))) for k, x in pts if k == "a1")
        a2 = max(abs(mp.mpf(str(x[1]))) for k, x in pts if k == "a2")
        return float(a1), float(mp.pi - a2)


def ratios(values, k) -> list:
    """``values[i] / values[i + k]`` (the alpha(n), beta(n) sequences of paper eqs. al-seq, beta-al-2)."""
    v = list(values)
    return [v[i] / v[i + k] for i in range(len(v) - k)]


def asymptotic_a1(label, E=4.0) -> float:
    """Paper eq. (al1-asymptotic): ``a1max(n; E) ~ sqrt(E - E_n)``."""
    from .bifurcations import transition

    t = transition(label)
    if t.phase == "lib":
        import mpmath as mp

        with mp.workdps(30):
            return float(mp.sqrt(mp.mpf(E) - 4 + mp.e ** mp.mpf(t.log_abs_dE_str)))
    return math.sqrt(float(E) - t.E)


def asymptotic_a2_deficit(label) -> float:
    """Paper eq. (al-2-max): ``pi - a2max(n; 4) ~ sqrt(4 - E_n)`` (librational)."""
    from .bifurcations import transition

    t = transition(label)
    return math.exp(0.5 * t.log_abs_dE)


# --------------------------------------------------------------------------- duality (§7.6)

@dataclass(frozen=True)
class DualPair:
    """A librational IS bifurcation and its rotational dual.

    ``x_lib = log(4 - E(IS^l_n))``, ``x_rot = log(E(dual) - 4)``, ``diff = x_lib - x_rot``,
    ``k2_sum = k_l^2 + k_r^2 = E_l/4 + E_r/4`` (moduli with ``k^2 = E/4``; ``k_r > 1``).
    """

    lib: str
    rot: str
    x_lib: float
    x_rot: float
    diff: float
    k2_sum: float
    k2_minus_2: float = float("nan")


def dual_label(n_lib: int) -> str:
    """The §7.6 dual of ``IS^l_n``: ``IS^l_{4j+1,2} <-> IS^r_{2j+1,2}``, ``IS^l_{4j+3,4} <-> PD^r_{2j+3,4}``."""
    if isinstance(n_lib, bool) or not isinstance(n_lib, (int, np.integer)) or n_lib < 1:
        raise ValueError(f"n must be an integer >= 1, got {n_lib!r}")
    j, r = divmod(n_lib - 1, 4)
    if r in (0, 1):
        return f"IS^r_{2 * j + r + 1}"
    return f"PD^r_{2 * j + r + 1}"


def duality_pairs(n_max=20, digits=None) -> list:
    """:class:`DualPair` for ``IS^l_1 .. IS^l_{n_max}``.

    ``digits=None``: float64 transitions (``x`` to ~2e-13 absolute, so ``diff`` is resolved only while it
    exceeds ~1e-12, i.e. ``n <= 10``). ``digits=30``: every root re-located in real128
    (:func:`rotorlib.bifurcations.transition`, ~30 digits, ~0.3 s per root); ``diff`` and ``k2_sum - 2`` are
    then formed in mpmath and resolved to ~1e-28.
    """
    import mpmath as mp

    from .bifurcations import transition, transitions

    if digits is None:
        lib = {t.label: t for t in transitions("lib", n_max, kinds=("IS",))}
        rot = {t.label: t for t in transitions("rot", n_max // 2 + 3)}
        get_l, get_r = lib.__getitem__, rot.__getitem__
    else:
        get_l = get_r = (lambda lab: transition(lab, digits=digits))
    out = []
    with mp.workdps(40):
        for n in range(1, n_max + 1):
            tl, tr = get_l(f"IS^l_{n}"), get_r(dual_label(n))
            xl, xr = mp.mpf(tl.log_abs_dE_str), mp.mpf(tr.log_abs_dE_str)
            k2m2 = (mp.e ** xr - mp.e ** xl) / 4      # E_r/4 + E_l/4 - 2 with E_l = 4 - e^xl, E_r = 4 + e^xr
            out.append(DualPair(tl.label, tr.label, float(xl), float(xr), float(xl - xr), float(2 + k2m2),
                                float(k2m2)))
    return out


def fit_rate(ns, values) -> tuple:
    """Least-squares ``log|v_n| = a - b n``; returns ``(b, a)`` (``|v_n| ~ e^{a - b n}``)."""
    ns = np.asarray(ns, float)
    y = np.log(np.abs(np.asarray(values, float)))
    b, a = np.polyfit(ns, y, 1)
    return float(-b), float(a)


def dual_lame(lib_label="IS^l_1", rot_label="IS^r_1", n=2001):
    """Periodic transverse solutions ``a1'' = -(2 + cos a2) a1``, ``a1(0) = 1``, ``a1'(0) = 0`` at two dual
    transitions, on the paper's rescaled times ``z = sqrt3 t`` (lib) and ``z = sqrt3 k_r t`` (rot).

    The librational solution is sampled over one pendulum period (``z`` in ``[0, 4K(k_l)]``) and the
    rotational one over two (``z`` in ``[0, 4K(1/k_r)]``), both on ``n`` points of the normalised time
    ``z / z_max``. Integrated with :func:`rotorlib.newborn.linear_orbit` (closed-form pendulum in the
    coefficient, scipy DOP853, rtol 1e-11).

    Returns
    -------
    dict with ``w`` (normalised time), ``lib``, ``rot`` (the two solutions), ``closure_lib``/``closure_rot``
    (``|a1(end) - 1|``: periodicity check), ``k2_lib``, ``k2_rot``, ``max_diff``.
    """
    from .bifurcations import transition
    from .newborn import linear_orbit

    tl, tr = transition(lib_label), transition(rot_label)
    t1, y1, _ = linear_orbit(lib_label, [1.0, 0.0, 0.0, 0.0], tl.period, n)
    t2, y2, _ = linear_orbit(rot_label, [1.0, 0.0, 0.0, 0.0], 2 * tr.period, n)
    w = np.linspace(0.0, 1.0, n)
    return {"w": w, "lib": y1, "rot": y2, "closure_lib": abs(y1[-1] - 1.0), "closure_rot": abs(y2[-1] - 1.0),
            "k2_lib": tl.E / 4.0, "k2_rot": tr.E / 4.0, "max_diff": float(np.max(np.abs(y1 - y2))),
            "zmax_lib": math.sqrt(3.0) * tl.period, "zmax_rot": math.sqrt(3.0 * tr.E / 4.0) * 2 * tr.period}


# --------------------------------------------------------------------------- comparison tables

def compare(quantity, paper: str, ours, tol=None, rel=None, note="") -> dict:
    """One row of a paper / ours / difference / tolerance / verdict table.

    ``tol`` defaults to half a unit in the paper's last printed digit; ``rel`` (for values the paper
    marks ``≈``) makes the tolerance ``rel * |paper|``. Verdict ``agrees`` when ``|paper - ours| <= tol``,
    else ``DIFFERS``.
    """
    p = float(paper)
    if rel is not None:
        t = abs(p) * float(rel)
    elif tol is not None:
        t = float(tol)
    else:
        s = paper.strip().lower().split("e")[0]
        d = len(s.split(".")[1]) if "." in s else 0
        t = 0.5 * 10.0 ** (-d) * (10.0 ** int(paper.lower().split("e")[1]) if "e" in paper.lower() else 1.0)
    diff = p - float(ours)
    return {"quantity": quantity, "paper": paper, "ours": float(ours), "difference": diff, "tolerance": t,
            "verdict": "agrees" if abs(diff) <= t else "DIFFERS", "note": note}


def table(rows) -> str:
    """Plain-text rendering of :func:`compare` rows (ours printed to 6 significant digits)."""
    from .scaling import text_table

    return text_table(["quantity", "paper", "ours", "difference", "tolerance", "verdict", "note"],
                      [[r["quantity"], r["paper"], f"{r['ours']:.6g}", f"{r['difference']:+.2g}",
                        f"{r['tolerance']:.2g}", r["verdict"], r["note"]] for r in rows])


# --------------------------------------------------------------------------- rotational families in amplitude (§7.5, §9)

def _rot_spec(label):
    from .newborn import family_spec

    spec = family_spec(label)
    if spec.phase != "rot":
        raise ValueError(f"{spec.label} is not a rotational family (this continuation is for IS^r_n, PD^r_n)")
    return spec


def _rot_precision(spec, precision):
    from .newborn import FLOAT64_LIMIT

    if precision is None:
        precision = "float64" if abs(spec.E_birth - 4.0) > FLOAT64_LIMIT else "real128"
    if precision not in ("float64", "real128"):
        raise ValueError(f"precision must be 'float64' or 'real128', got {precision!r}")
    return precision


def _num(v, precision):
    from .newborn import _mpf

    return float(v) if precision == "float64" else _mpf(v)


def rotational_state(label, u, q, precision="float64"):
    """Start of a rotational newborn orbit in the amplitude variables ``(u, q)``.

    ``a2 = 0`` and ``a1 = u, p1 = 0`` (family starting on ``a1``) or ``a1 = 0, p1 = u`` (starting on ``p1``;
    see :func:`rotorlib.newborn.family_spec`), and ``p2 = sqrt(4 (4 + q) / 3)``: ``q`` is the energy of the
    ``a2`` motion at the base point above the barrier ``V(0, pi) = 4``. The energy is
    ``E = 4 + q + T(u)`` with ``T = 2 sin^2 u + 4 sin^2(u/2)`` (= ``V(u, 0)``) or ``u^2 / 4``, so ``E - 4`` is
    formed without cancellation (:func:`rotational_dE`). Returns a list of floats (float64) or mpf
    (real128, 40 digits).
    """
    import mpmath as mp

    from .newborn import _state_with_p2

    spec = _rot_spec(label)
    u, q = _num(u, precision), _num(q, precision)
    if precision == "float64":
        if 4 + q <= 0:
            raise ValueError(f"q = {q!r} <= -4: no a2 motion")
        return _state_with_p2(spec, u, math.sqrt(4 * (4 + q) / 3))
    with mp.workdps(40):
        if 4 + q <= 0:
            raise ValueError(f"q = {q} <= -4: no a2 motion")
        return _state_with_p2(spec, u, mp.sqrt(4 * (4 + q) / 3), zero=mp.mpf(0))


def rotational_dE(label, u, q, precision="float64"):
    """``E - 4 = q + T(u)`` of :func:`rotational_state` (float, or mpf in real128)."""
    import mpmath as mp

    spec = _rot_spec(label)
    u, q = _num(u, precision), _num(q, precision)
    if precision == "float64":
        T = 2 * math.sin(u) ** 2 + 4 * math.sin(u / 2) ** 2 if spec.start == "a1" else u * u / 4
        return q + T
    with mp.workdps(40):
        T = 2 * mp.sin(u) ** 2 + 4 * mp.sin(u / 2) ** 2 if spec.start == "a1" else u * u / 4
        return q + T


def _rot_shoot(spec, u, q, precision, t_max):
    import mpmath as mp

    from . import flow

    x0 = rotational_state(spec.label, u, q, precision)
    with mp.workdps(40):
        return flow.flow_to_event(x0, "a2_up", math.pi if precision == "float64" else mp.pi, precision, t_max=t_max)


def rotational_residual(label, u, q, precision="float64"):
    """Shooting residual of a rotational family at ``(u, q)``: ``x_k(t1) / u`` at the first crossing of
    ``a2 = pi`` (``k`` = the component that vanishes there for the family, :mod:`rotorlib.newborn`).
    Zero on the family; the pendulum ``u = 0`` is divided out. Raises RuntimeError if ``a2`` does not
    reach ``pi`` within four pendulum periods.
    """
    spec = _rot_spec(label)
    _, x = _rot_shoot(spec, u, q, precision, 4 * spec.period_birth + 50.0)
    k = 0 if spec.end == "a1" else 2
    return x[k] / _num(u, precision)


def _secant1(f, x0, x1, tol, floor, precision, maxiter=40):
    """Secant on a scalar; returns ``(x, |f(x)|)`` of the best iterate, or ``(None, inf)`` on failure."""
    import mpmath as mp

    try:
        f0, f1 = f(x0), f(x1)
    except (RuntimeError, ValueError):
        return None, float("inf")
    best = (abs(f1), x1) if abs(f1) < abs(f0) else (abs(f0), x0)
    last = None
    for it in range(maxiter):
        if f1 == f0:
            break
        x2 = x1 - f1 * (x1 - x0) / (f1 - f0)
        dx = abs(x2 - x1)
        x0, f0, x1 = x1, f1, x2
        try:
            f1 = f(x1)
        except (RuntimeError, ValueError):
            return None, float("inf")
        if abs(f1) < best[0]:
            best = (abs(f1), x1)
        if dx <= tol * max(abs(x1), floor) or f1 == 0:
            return x1, abs(f1)
        if last is not None and it >= 3 and dx >= last:
            break
        last = dx
    return best[1], best[0]


def _rot_predict(X, Y, xn, par, prec, order=2):
    """Polynomial extrapolation (degree ``order``, quadratic by default; in ``u^2`` when ``par == 'u'``)
    of ``Y`` through the last ``order + 1`` points."""
    import mpmath as mp

    g = (lambda v: v * v) if par == "u" else (lambda v: v)
    xs, ys = [g(v) for v in X[-(order + 1):]], list(Y[-(order + 1):])
    x = g(xn)
    while len(xs) > 1 and len(set(xs)) < len(xs):
        xs, ys = xs[1:], ys[1:]
    if len(xs) == 1:
        return ys[0], abs(ys[0]) * 1e-3
    if len(xs) == 2:
        yg = ys[1] + (ys[1] - ys[0]) * (x - xs[1]) / (xs[1] - xs[0])
    else:
        prod = math.prod if prec == "float64" else mp.fprod
        n = len(xs)
        yg = sum(ys[i] * prod([(x - xs[j]) / (xs[i] - xs[j]) for j in range(n) if j != i]) for i in range(n))
    return yg, abs(yg - ys[-1])


def _rot_correct(spec, un_or_qn, yg, change, par, prec, floor):
    """Secant on the unknown not stepped; returns ``(y, |r|)`` or ``(None, inf)``."""
    tol, rmax = _rot_tols(prec, math.exp(spec.log_abs_dE_birth))
    pert = max(change * _num(1e-4, prec), abs(yg) * tol * 100)
    pn = un_or_qn
    if par == "u":
        f = (lambda y: rotational_residual(spec.label, pn, y, prec))
    else:
        f = (lambda y: rotational_residual(spec.label, y, pn, prec))
    y, r = _secant1(f, yg, yg + pert, tol, floor, prec)
    if y is None or not r < rmax:
        return None, float("inf")
    return y, r


@dataclass(frozen=True)
class RotationalBranch:
    """A rotational newborn family followed in its amplitude (:func:`follow_rotational`).

    Attributes
    ----------
    label, precision : str
    u, q : tuple
        The members' ``(u, q)`` (:func:`rotational_state`): floats, or mpf in real128.
    dE : ndarray
        ``E - 4`` of each member (float).
    parameter : tuple of str
        Which of ``u``, ``q`` was stepped to reach each member (``u`` until ``u`` itself turns).
    residual : ndarray
        ``|rotational_residual|`` at each member.
    stop : str
        Why the continuation ended (``target``, ``steps``, ``t1`` (see ``t1_stop``) or ``stuck at ...``).
    """

    label: str
    precision: str
    u: tuple
    q: tuple
    dE: np.ndarray
    parameter: tuple
    residual: np.ndarray
    stop: str

    @property
    def E_folds(self) -> int:
        """Number of turning points of ``E`` along the branch (folds in E)."""
        d = np.diff(self.dE)
        return int(np.sum(np.sign(d[1:]) != np.sign(d[:-1])))


def _rot_tols(precision, d=None):
    """Secant tolerance and accepted residual. Near the separatrix the flow amplifies round-off like
    ``1 / (E_n - 4)`` (the ``a2`` motion's distance to the barrier), so the accepted real128 residual is
    ``1e-30 / (E_n - 4)`` (at most 1e-18... 1e-13 for ``E_n - 4`` from 1e-12 to 1e-17)."""
    import mpmath as mp

    if precision == "float64":
        return 1e-13, 1e-6
    r = mp.mpf("1e-18") if d is None else max(mp.mpf("1e-18"), mp.mpf("1e-30") / abs(mp.mpf(d)))
    return mp.mpf("1e-30"), r


def _rot_seed(spec, precision):
    import mpmath as mp

    from .bifurcations import transition

    t = transition(spec.label)
    with mp.workdps(40):
        d = mp.e ** mp.mpf(t.log_abs_dE_str)
        u = mp.mpf("1e-2") * mp.sqrt(d) * (1 if spec.start == "a1" else 2)
        if precision == "float64":
            d, u = float(d), float(u)
        tol, rmax = _rot_tols(precision, d)
        q, r = _secant1(lambda x: rotational_residual(spec.label, u, x, precision), d, d * (1 + _num(1e-3, precision)),
                        tol, d, precision)
    if q is None or not r < rmax:
        raise ValueError(f"{spec.label}: no seed member found near the bifurcation")
    return u, q, r, d


def follow_rotational(label, dE_stop, precision=None, h=0.3, max_steps=400, h_min=1e-5, h_max=0.3,
                      start=None, t1_jump=None, order=2, t1_stop=None) -> RotationalBranch:
    """Follow a rotational newborn family in its amplitude from birth until ``E - 4 >= dE_stop``.

    Why not in ``E``: the newborn orbit's ``a2`` motion keeps the energy ``~E_n - 4`` above the barrier
    at ``a2 = pi`` (the paper's "frozen" ``a2`` mode) while ``E - E_n`` grows, so at fixed ``E`` the
    residual in the amplitude ``u`` has a root in a channel of relative width ``~(E_n - 4)/(E - E_n)``
    that a secant in ``u`` started 1e-4 away (:mod:`rotorlib.newborn`) misses: that continuation stops
    at ``E - 4 ~ 1e-3`` for IS^r_3 with no fold in ``E``. Here the unknowns are ``u`` and ``q``, the
    ``a2``-mode energy above the barrier (:func:`rotational_state`), which varies smoothly and carries
    the small scale explicitly. Local parametrisation: each step advances ``log u`` (or ``q``, where
    ``u`` turns) by up to ``h``, predicts the other unknown by quadratic extrapolation and corrects it
    by a secant on :func:`rotational_residual`; a step whose correction exceeds a fifth of the
    predicted change is refused and ``h`` halved. Folds in ``E`` are passed since ``E`` is not a
    parameter.

    Parameters
    ----------
    label : str
        ``IS^r_n`` or ``PD^r_n``.
    dE_stop : float or str
        Stop once ``E - 4`` reaches this (a decimal string keeps its digits in real128).
    precision : {'float64', 'real128'}, optional
        Default float64 while ``|E_n - 4| > 3e-8``, else real128.
    h, h_max, h_min : float
        First, largest and smallest step (in ``log u``, or in ``q / (E - 4)`` while passing a turning
        point of ``u``); the continuation stops ("stuck") when a step below ``h_min`` is refused.
    max_steps : int
        Largest number of members.
    start : sequence of ``(u, q)``, optional
        Resume from these members (at least three, in order along the branch, e.g. the last members of an
        earlier run, possibly in the other precision) instead of seeding at birth.
        They are converted to ``precision`` as they are (not re-solved) and are the first members of the
        result, with the residual of ``precision`` evaluated at them.
    t1_jump : float, optional
        Refuse (and halve ``h``) a step whose time ``t1`` to ``a2 = pi`` differs from the previous
        member's by more than this fraction. The residual has one root in ``q`` per family at fixed ``u``
        (the families differ in ``t1``), and a long step can land on another family's root: PD^r_5
        followed without this guard jumps at ``E - 4 ~ 0.03`` from ``t1 ~ 7.35`` onto the PD^r_3 branch
        (``t1 ~ 4.2``). Default ``None``: no check (one extra shooting per member when set).
    order : int
        Degree of the polynomial predictor (through the last ``order + 1`` members; default 2). Near a
        birth close to E = 4 the corrector converges only inside a channel of width ``~|E_n - 4|`` in
        ``q`` (outside it ``a2`` never reaches ``pi``), so the step is limited by the predictor's error
        there and a higher ``order`` allows larger steps.
    t1_stop : float, optional
        Also stop (``stop = 't1'``) once ``t1`` exceeds this: ``t1`` diverges as a family ends on an
        orbit asymptotic to the potential maximum ``V = 4.5``, where the steps shrink without end.

    Returns
    -------
    RotationalBranch

    Notes
    -----
    Precision: Residuals ``|x_k(t1)/u|`` at the accepted members are below 1e-6 (float64; typically 1e-9,
    i.e. ``q`` to ~1e-9 relative) and ``max(1e-18, 1e-30 / (E_n - 4))`` (real128; typically 1e-22).
    A family whose members grow too unstable for the working precision (``|tr M|`` beyond ~1e12 in
    float64) stops with ``stop = 'stuck ...'``.
    """
    import mpmath as mp

    spec = _rot_spec(label)
    prec = _rot_precision(spec, precision)
    try:
        stop_val = float(dE_stop)
    except (TypeError, ValueError):
        raise ValueError(f"dE_stop must be a number, got {dE_stop!r}") from None
    if not stop_val > 0 or not math.isfinite(stop_val):
        raise ValueError(f"dE_stop must be > 0, got {dE_stop!r}")
    if t1_jump is not None and not float(t1_jump) > 0:
        raise ValueError(f"t1_jump must be > 0, got {t1_jump!r}")
    if t1_stop is not None and not float(t1_stop) > 0:
        raise ValueError(f"t1_stop must be > 0, got {t1_stop!r}")
    if int(order) != order or not 1 <= order <= 8:
        raise ValueError(f"order must be an integer from 1 to 8, got {order!r}")
    order = int(order)
    tol, _ = _rot_tols(prec, math.exp(spec.log_abs_dE_birth))
    with mp.workdps(40):
        stop = _num(dE_stop if isinstance(dE_stop, str) else float(dE_stop), prec)
        if start is None:
            u0, q0, r0, d = _rot_seed(spec, prec)
            U, Q, P, R = [u0], [q0], ["u"], [float(r0)]
        else:
            start = [(_num(a, prec), _num(b, prec)) for a, b in start]
            if len(start) < 3:
                raise ValueError(f"start needs at least three members, got {len(start)}")
            U, Q = [a for a, _ in start], [b for _, b in start]
            P = ["u"] * len(U)
            R = [float(abs(rotational_residual(spec.label, a, b, prec))) for a, b in start]
            d = _num(math.exp(spec.log_abs_dE_birth), prec)
        dE = [rotational_dE(spec.label, a, b, prec) for a, b in zip(U, Q)]
        t_max = 4 * spec.period_birth + 50.0
        track = t1_jump is not None or t1_stop is not None
        if track:
            T1 = [float(_rot_shoot(spec, U[-1], Q[-1], prec, t_max)[0])]
        reason = "steps"
        mode_q = 0
        exp = (lambda v: math.exp(v)) if prec == "float64" else mp.exp
        for _ in range(max_steps):
            if dE[-1] >= stop:
                reason = "target"
                break
            if t1_stop is not None and T1[-1] >= float(t1_stop):
                reason = "t1"
                break
            # parameter: u (in the direction it last moved); q only to pass a turning point of u
            if mode_q > 0:
                par, sgn = "q", (1 if Q[-1] > Q[-2] else -1)
            else:
                par = "u"
                sgn = 1 if len(U) < 2 else (1 if abs(U[-1]) > abs(U[-2]) else -1)
            accepted = False
            while not accepted and h >= h_min:
                if par == "u":
                    pn = U[-1] * exp(sgn * h)
                    X, Y = U, Q
                else:
                    pn = Q[-1] + sgn * h * abs(dE[-1])
                    X, Y = Q, U
                yg, change = _rot_predict(X, Y, pn, par, prec, order)
                y, r = _rot_correct(spec, pn, yg, change, par, prec, abs(d))
                ok = y is not None and (len(X) < 2 or abs(y - yg) <= 0.2 * change + 1e3 * tol * abs(y))
                if ok and track:
                    un, qn = (pn, y) if par == "u" else (y, pn)
                    try:
                        t1n = float(_rot_shoot(spec, un, qn, prec, t_max)[0])
                    except (RuntimeError, ValueError):
                        t1n = float("nan")
                    ok = t1_jump is None or abs(t1n - T1[-1]) <= float(t1_jump) * T1[-1]
                if ok:
                    un, qn = (pn, y) if par == "u" else (y, pn)
                    if track:
                        T1.append(t1n)
                    U.append(un), Q.append(qn), P.append(par), R.append(float(r))
                    dE.append(rotational_dE(spec.label, un, qn, prec))
                    accepted = True
                    h = min(h * 1.5, h_max)
                else:
                    h /= 2
            if accepted and mode_q > 0:
                mode_q -= 1
            if not accepted:
                if par == "u" and len(U) >= 2:       # u may turn here: pass it stepping q
                    mode_q, h = 4, 0.05
                    continue
                reason = f"stuck at E - 4 = {float(dE[-1]):.6g} (step below {h_min:g})"
                break
    return RotationalBranch(spec.label, prec, tuple(U), tuple(Q), np.array([float(v) for v in dE]), tuple(P),
                            np.array(R), reason)


@dataclass(frozen=True)
class RotationalMember:
    """One member of a rotational newborn family at a prescribed energy (:func:`rotational_member`).

    Attributes
    ----------
    label, precision : str
    dE : float
        ``E - 4``.
    dE_str : str
        ``E - 4`` to 30 significant digits (real128) or 17 (float64).
    u, q : float
        The amplitude unknowns (:func:`rotational_state`).
    period : float
    state0 : ndarray (4,)
        ``[a1, a2, p1, p2]`` rounded to float64.
    a1_max : float
        ``max |a1|`` over one period (turning points ``p1 = 0`` located by events).
    a2dot_min : float
        ``min a2' = (3/2) min p2``, attained where ``a2`` is an odd multiple of ``pi`` (``p2' = -2 sin a2 cos a1``).
    trace : float
        ``tr M`` (4x4 variational equations in the working precision).
    closure : float
        ``max |x(T) - x(0)|`` modulo the lattice (float64 rounding of the end state) of the orbit whose
        trace is given.
    residual : float
        ``|rotational_residual|``.
    trace_precision : str
        Precision of ``trace``: a float64 member whose full period does not close to 1e-8 (too unstable
        for float64 over a whole period) is polished in real128 at the same ``u`` and its trace taken there.
    """

    label: str
    precision: str
    dE: float
    dE_str: str
    u: float
    q: float
    period: float
    state0: np.ndarray
    a1_max: float
    a2dot_min: float
    trace: float
    closure: float
    residual: float
    trace_precision: str = ""


def _rot_member_props(spec, u, q, prec, r):
    import mpmath as mp

    from . import flow
    from .monodromy import _unwind

    with mp.workdps(40):
        x0 = rotational_state(spec.label, u, q, prec)
        t1, x1 = _rot_shoot(spec, u, q, prec, 4 * spec.period_birth + 50.0)
        T = spec.factor * t1
        # By the two reversing symmetries (x(-t) = R x(t), x(2 t1 - t) = S x(t), both keeping |a1| and p2)
        # the quarter [0, t1] (IS^r: half) carries every value of |a1| and of p2 at a2 = pi (mod 2 pi):
        # the extrema are read there, before the instability of the full period amplifies round-off.
        ta = flow._extrema_integrator(prec)
        ta.time = flow.to_fp(0.0, prec)
        ta.state[:] = np.array([flow.to_fp(v, prec) for v in x0], dtype=flow._dtype(prec))
        flow._FOUND.clear()
        ta.propagate_until(flow.to_fp(t1, prec))
        pts = list(flow._FOUND)
        flow._FOUND.clear()
        a1m = max([abs(flow.from_fp(x[0], prec)) for k, x in pts if k == "a1"] + [abs(x0[0]), abs(x1[0])])
        p2s = [x1[3]]
        M, xT, tr = flow.monodromy_matrix(x0, T, prec)
        x0f = np.array([float(v) for v in x0])
        dE = rotational_dE(spec.label, u, q, prec)
        return RotationalMember(spec.label, prec, float(dE), mp.nstr(dE, 30 if prec != "float64" else 17),
                                float(u), float(q), float(T), x0f, float(a1m), float(1.5 * min(p2s)), float(tr),
                                float(np.max(np.abs(_unwind(xT - x0f)))), float(r), prec)


def rotational_member(label, dE, precision=None, branch=None) -> RotationalMember:
    """The member of a rotational newborn family with ``E - 4 = dE``, reached in amplitude.

    Follows the family with :func:`follow_rotational` (or uses ``branch``) until ``E - 4`` passes
    ``dE``, then solves ``E(u, q(u)) - 4 = dE`` by a secant in ``u`` between the last two members,
    each ``q(u)`` from the shooting residual. ``dE`` may be a decimal string (kept in real128).

    Raises ValueError when the family does not reach ``dE`` (the message gives the highest ``E - 4``
    reached and why the continuation stopped).

    Precision: ``E - 4`` is matched to 1e-13 (float64) / 1e-28 (real128) relative; the amplitudes are
    those of the converged orbit (residual below 1e-6 / 1e-18).
    """
    import mpmath as mp

    spec = _rot_spec(label)
    prec = _rot_precision(spec, precision if branch is None else branch.precision)
    b = branch or follow_rotational(spec.label, dE, prec, h_max=1.0)
    with mp.workdps(40):
        target = _num(dE if isinstance(dE, str) else float(dE), prec)
        dEs = [rotational_dE(spec.label, u, q, prec) for u, q in zip(b.u, b.q)]
        idx = next((i for i in range(1, len(dEs)) if (dEs[i - 1] - target) * (dEs[i] - target) <= 0), None)
        if idx is None:
            raise ValueError(f"{spec.label} does not reach E - 4 = {float(target):.6g} along its amplitude "
                             f"branch: highest E - 4 = {max(float(v) for v in dEs):.6g} ({b.stop})")
        tol, _ = _rot_tols(prec, math.exp(spec.log_abs_dE_birth))
        # refine the last interval in up to 4 steps of u (quadratic predictor from the branch) until the
        # target is bracketed by members a fraction of a step apart
        U, Q = list(b.u[:idx]), list(b.q[:idx])
        ua, ub = b.u[idx - 1], b.u[idx]
        for k in range(1, 5):
            un = ua + (ub - ua) * k / 4
            yg, ch = _rot_predict(U, Q, un, "u", prec)
            y, r = _rot_correct(spec, un, yg, ch, "u", prec, abs(Q[-1]))
            if y is None:
                raise ValueError(f"{spec.label}: refinement failed near E - 4 = {float(target):.6g}")
            U.append(un), Q.append(y)
            if (rotational_dE(spec.label, un, y, prec) - target) * (dEs[idx - 1] - target) <= 0:
                break
        state = {"r": None}

        def q_of(u):
            yg, ch = _rot_predict(U, Q, u, "u", prec)
            qq, r = _rot_correct(spec, u, yg, ch, "u", prec, abs(Q[-1]))
            if qq is None:
                raise ValueError(f"{spec.label}: no member at u = {float(u)!r}")
            state["r"] = r
            return qq

        u, _ = _secant1(lambda uu: rotational_dE(spec.label, uu, q_of(uu), prec) - target, U[-2], U[-1],
                        tol * 10, abs(U[-1]), prec)
        if u is None:
            raise ValueError(f"{spec.label}: could not match E - 4 = {float(target):.6g}")
        q = q_of(u)
        m = _rot_member_props(spec, u, q, prec, state["r"])
        if prec == "float64" and not m.closure < 1e-8:
            # too unstable for a float64 period: polish q in real128 at the same u for the trace
            um, qm = _num(repr(float(u)), "real128"), _num(repr(float(q)), "real128")
            tol128, rmax128 = _rot_tols("real128", math.exp(spec.log_abs_dE_birth))
            q2, r2 = _secant1(lambda y: rotational_residual(spec.label, um, y, "real128"), qm,
                              qm * (1 + _num("1e-12", "real128")), tol128, abs(qm), "real128")
            if q2 is not None and r2 < rmax128:
                m2 = _rot_member_props(spec, um, q2, "real128", r2)
                m = RotationalMember(m.label, m.precision, m.dE, m.dE_str, m.u, m.q, m.period, m.state0, m.a1_max,
                                     m.a2dot_min, m2.trace, m2.closure, m.residual, "real128")
        return m


def _rot_dE_str(label) -> str:
    """``E_n - 4`` of a rotational transition as a 35-digit decimal string (from ``log_abs_dE_str``)."""
    import mpmath as mp

    from .bifurcations import transition

    t = transition(label)
    if t.phase != "rot":
        raise ValueError(f"{t.label} is not a rotational transition")
    with mp.workdps(40):
        return mp.nstr(mp.e ** mp.mpf(t.log_abs_dE_str), 35)


def _rot_member_task(args):
    label, dE = args
    try:
        return rotational_member(label, dE)
    except ValueError as exc:
        return str(exc)


@dataclass(frozen=True)
class RotationalRatio:
    """The paper's rotational scaling ratios (eq. alpha-beta-r) for one ``n`` of one class.

    ``alpha = a1max(n; E_{n-2}) / a1max(n+2; E_n)``, ``beta = a2'min(n; E_{n-2}) / a2'min(n+2; E_n)``
    with ``E_k`` the bifurcation energies of the same kind (IS^r or PD^r) and ``n`` of either parity.

    Attributes
    ----------
    kind : {'IS', 'PD'}
    n : int
    numerator, denominator : RotationalMember or None
        ``None`` when the family does not reach the energy (``reason`` says why).
    alpha, beta : float
        ``nan`` when not evaluable.
    alpha_pred, beta_pred : float
        The paper's estimates at this ``n``: ``sqrt((E_{n-2} - E_n) / (E_n - E_{n+2}))`` and
        ``sqrt((E_n - 4) / (E_{n+2} - 4))`` (both tend to ``sqrt(delta^r)``).
    reason : str
    """

    kind: str
    n: int
    numerator: object
    denominator: object
    alpha: float
    beta: float
    alpha_pred: float
    beta_pred: float
    reason: str = ""


def rotational_ratios(specs, executor=None, progress=False) -> list:
    """:class:`RotationalRatio` for each ``(kind, n)`` in ``specs`` (``n >= 3``).

    The members (``kind^r_n`` at ``E_{n-2}``, ``kind^r_{n+2}`` at ``E_n``) are found by
    :func:`rotational_member` (continuation in amplitude; float64 while ``E_n - 4 > 3e-8``, real128
    beyond), each once, through :func:`rotorlib.parallel.pmap` (``executor``: any
    :class:`concurrent.futures.Executor`).

    Precision: the amplitudes are those of orbits closing to the residuals of
    :func:`rotational_member`; ``a1max`` and ``a2'min`` are read on the symmetric quarter (half) period,
    so the ratios are good to ~1e-8 (float64 members) and ~1e-15 (real128) relative, far below their
    distance to the limit.
    """
    import mpmath as mp

    from .parallel import pmap

    specs = [(str(k), int(n)) for k, n in specs]
    for k, n in specs:
        if k not in ("IS", "PD") or n < 3:
            raise ValueError(f"need kind 'IS' or 'PD' and n >= 3 (E_(n-2) must exist), got {(k, n)!r}")
    tasks = []
    for k, n in specs:
        for t in ((f"{k}^r_{n}", _rot_dE_str(f"{k}^r_{n - 2}")), (f"{k}^r_{n + 2}", _rot_dE_str(f"{k}^r_{n}"))):
            if t not in tasks:
                tasks.append(t)
    res = dict(zip(tasks, pmap(_rot_member_task, tasks, executor=executor, progress=progress,
                               desc="rotational members")))
    out = []
    with mp.workdps(40):
        for k, n in specs:
            a, b, c = (mp.mpf(_rot_dE_str(f"{k}^r_{m}")) for m in (n - 2, n, n + 2))
            ap, bp = float(mp.sqrt((a - b) / (b - c))), float(mp.sqrt(b / c))
            num = res[(f"{k}^r_{n}", _rot_dE_str(f"{k}^r_{n - 2}"))]
            den = res[(f"{k}^r_{n + 2}", _rot_dE_str(f"{k}^r_{n}"))]
            bad = [m for m in (num, den) if isinstance(m, str)]
            if bad:
                out.append(RotationalRatio(k, n, None if isinstance(num, str) else num,
                                           None if isinstance(den, str) else den, float("nan"), float("nan"),
                                           ap, bp, "; ".join(bad)))
            else:
                out.append(RotationalRatio(k, n, num, den, num.a1_max / den.a1_max, num.a2dot_min / den.a2dot_min,
                                           ap, bp))
    return out


@dataclass(frozen=True)
class BranchProfile:
    """Diagnostics along a :class:`RotationalBranch` (float64 evaluation of each member).

    Attributes
    ----------
    label : str
    dE, u : ndarray
        ``E - 4`` and amplitude of each member.
    t1 : ndarray
        Time from the start line to ``a2 = pi`` (period = ``t1`` x 2 for IS^r, x 4 for PD^r).
    a1_pi, p2_pi : ndarray
        ``a1`` and ``p2`` at ``a2 = pi``.
    trace : ndarray
        ``tr M`` over one period (float64 variational equations; where ``|tr M|`` exceeds ~1e12 only its
        sign and size are meaningful).
    stop : str
        as ``RotationalBranch.stop``.
    """

    label: str
    dE: np.ndarray
    u: np.ndarray
    t1: np.ndarray
    a1_pi: np.ndarray
    p2_pi: np.ndarray
    trace: np.ndarray
    stop: str

    @property
    def E(self) -> np.ndarray:
        """Energies ``4 + dE``."""
        return 4.0 + self.dE


def branch_profile(branch: RotationalBranch, every=1) -> BranchProfile:
    """:class:`BranchProfile` of every ``every``-th member of ``branch`` (and the last one)."""
    from . import flow

    spec = _rot_spec(branch.label)
    idx = list(range(0, len(branch.u), max(1, int(every))))
    if idx[-1] != len(branch.u) - 1:
        idx.append(len(branch.u) - 1)
    t1s, a1s, p2s, trs = [], [], [], []
    for i in idx:
        x0 = [float(v) for v in rotational_state(branch.label, branch.u[i], branch.q[i], branch.precision)]
        if branch.precision == "float64":
            t1, x1 = _rot_shoot(spec, branch.u[i], branch.q[i], "float64", 4 * spec.period_birth + 50.0)
        else:
            t1, x1 = _rot_shoot(spec, branch.u[i], branch.q[i], "real128", 4 * spec.period_birth + 50.0)
            t1, x1 = float(t1), [float(v) for v in x1]
        _, _, tr = flow.monodromy_matrix(x0, spec.factor * float(t1), "float64")
        t1s.append(float(t1)), a1s.append(float(x1[0])), p2s.append(float(x1[3])), trs.append(float(tr))
    return BranchProfile(branch.label, branch.dE[idx], np.array([float(branch.u[i]) for i in idx]), np.array(t1s),
                         np.array(a1s), np.array(p2s), np.array(trs), branch.stop)


def rotational_exit(branch: RotationalBranch, profile: BranchProfile = None, xtol=1e-12):
    """Where ``tr M`` first leaves the stable window ``[0, 4]`` along a rotational branch.

    Returns ``(dE, level, stays_out)``: ``E - 4`` at the crossing (bisection in ``u`` between the two
    members that bracket it, each point re-solved for ``q`` and its ``tr M`` recomputed; float64 branch
    only), the level crossed (0 or 4), and whether every later member of ``profile`` stays outside
    ``[0, 4]``. ``(nan, nan, True)`` when the first member is already outside (born unstable) and all
    stay outside; ``(nan, nan, False)`` if it never leaves.
    """
    if branch.precision != "float64":
        raise ValueError("rotational_exit works on float64 branches")
    spec = _rot_spec(branch.label)
    prof = profile or branch_profile(branch)
    if len(prof.u) != len(branch.u):
        raise ValueError("profile must cover every member of the branch (every=1)")
    out = (prof.trace < 0) | (prof.trace > 4)
    if out[0]:
        return float("nan"), float("nan"), bool(np.all(out))
    k = int(np.argmax(out)) if np.any(out) else None
    if k is None:
        return float("nan"), float("nan"), False
    level = 4.0 if prof.trace[k] > 4 else 0.0
    dE = _rot_bisect_exit(spec, branch, k - 1, k, prof.trace[k - 1] - level, level, float(xtol))
    return dE, level, bool(np.all(out[k:]))


@dataclass(frozen=True)
class BranchStability:
    """``tr M`` along a :class:`RotationalBranch` in the branch's own precision, with the float64 values at
    the same members for comparison (:func:`branch_stability`).

    Attributes
    ----------
    label, precision : str
    dE, u : ndarray
        ``E - 4`` and amplitude of each member evaluated.
    t1 : ndarray
        Time from the start line to ``a2 = pi`` (period = ``t1`` x 2 for IS^r, x 4 for PD^r).
    trace, closure : ndarray
        ``tr M`` over one period from the 4x4 variational equations in ``precision`` (rounded to float),
        and ``max |x(T) - x(0)|`` (mod the lattice) of that integration.
    trace64, closure64, residual64 : ndarray
        The same member (``u``, ``q`` rounded to float64) integrated in float64: ``tr M``, closure, and
        ``|rotational_residual|`` in float64. Where these agree with ``trace`` / ``closure`` float64 is
        adequate; ``nan`` when not computed.
    exit_dE, exit_level : float
        ``E - 4`` where ``trace`` first leaves ``[0, 4]`` (bisection in ``u``, each point re-solved for
        ``q`` in ``precision``) and the level crossed; ``nan`` if the first member is already outside or
        no member leaves.
    stays_out : bool
        Every member after the exit (or every member, if the first is outside) has ``trace`` outside
        ``[0, 4]`` (members not evaluated, with ``every > 1``, are not checked).
    stop : str
        as ``RotationalBranch.stop``.
    """

    label: str
    precision: str
    dE: np.ndarray
    u: np.ndarray
    t1: np.ndarray
    trace: np.ndarray
    closure: np.ndarray
    trace64: np.ndarray
    closure64: np.ndarray
    residual64: np.ndarray
    exit_dE: float
    exit_level: float
    stays_out: bool
    stop: str

    @property
    def E(self) -> np.ndarray:
        """Energies ``4 + dE``."""
        return 4.0 + self.dE


def _rot_trace(spec, u, q, prec):
    """``(t1, tr M, closure)`` of the member ``(u, q)`` in ``prec``."""
    import mpmath as mp

    from . import flow
    from .monodromy import _unwind

    with mp.workdps(40):
        x0 = rotational_state(spec.label, u, q, prec)
        t1, _ = _rot_shoot(spec, u, q, prec, 4 * spec.period_birth + 50.0)
        _, xT, tr = flow.monodromy_matrix(x0, spec.factor * t1, prec)
        x0f = np.array([float(v) for v in x0])
        return float(t1), float(tr), float(np.max(np.abs(_unwind(xT - x0f))))


def branch_stability(branch: RotationalBranch, every=1, compare_float64=True, xtol=1e-10) -> BranchStability:
    """:class:`BranchStability` of every ``every``-th member of ``branch`` (and the last one).

    ``tr M`` is integrated in the branch's precision (real128 for the families born within 3e-8 of
    E = 4), so it stays meaningful where float64 gives noise; with ``compare_float64`` the float64 trace,
    closure and shooting residual of the same members are recorded beside it. The first exit from
    ``[0, 4]`` is located by bisection in ``u`` to ``xtol`` relative (each point re-solved for ``q`` in
    the branch's precision from a quadratic predictor on the neighbouring members).

    Notes
    -----
    Precision: real128: closure of the full period ~1e-30 near birth, growing like ``|tr M| x 1e-31``; ``tr M``
    then has ~``30 - log10|tr M|`` correct digits. float64: see :func:`branch_profile`. The exit energy
    is good to ``xtol`` in ``u`` (~1e-10 relative in ``E - 4``).
    """
    if not int(every) >= 1:
        raise ValueError(f"every must be >= 1, got {every!r}")
    if not 0 < float(xtol) < 1e-2:
        raise ValueError(f"xtol must be in (0, 1e-2), got {xtol!r}")
    spec = _rot_spec(branch.label)
    prec = branch.precision
    idx = list(range(0, len(branch.u), int(every)))
    if idx[-1] != len(branch.u) - 1:
        idx.append(len(branch.u) - 1)
    t1s, trs, cls, tr64, cl64, r64 = [], [], [], [], [], []
    for i in idx:
        t1, tr, cl = _rot_trace(spec, branch.u[i], branch.q[i], prec)
        t1s.append(t1), trs.append(tr), cls.append(cl)
        if compare_float64 and prec != "float64":
            uf, qf = float(branch.u[i]), float(branch.q[i])
            try:
                _, a, b = _rot_trace(spec, uf, qf, "float64")
                c = abs(float(rotational_residual(spec.label, uf, qf, "float64")))
            except (RuntimeError, ValueError):
                a = b = c = float("nan")
            tr64.append(a), cl64.append(b), r64.append(c)
        else:
            tr64.append(tr if prec == "float64" else float("nan")), cl64.append(cl if prec == "float64" else
                                                                                 float("nan"))
            r64.append(float(branch.residual[i]) if prec == "float64" else float("nan"))
    trs = np.array(trs)
    out = (trs < 0) | (trs > 4)
    nan = float("nan")
    if out[0]:
        exit_dE, level, stays = nan, nan, bool(np.all(out))
    elif not np.any(out):
        exit_dE, level, stays = nan, nan, False
    else:
        k = int(np.argmax(out))
        level = 4.0 if trs[k] > 4 else 0.0
        stays = bool(np.all(out[k:]))
        ia, fa = idx[k - 1], trs[k - 1]
        for j in range(idx[k - 1] + 1, idx[k]):          # narrow to consecutive members (every > 1)
            tj = _rot_trace(spec, branch.u[j], branch.q[j], prec)[1]
            if tj < 0 or tj > 4:
                level = 4.0 if tj > 4 else 0.0
                break
            ia, fa = j, tj
        exit_dE = _rot_bisect_exit(spec, branch, ia, ia + 1, fa - level, level, float(xtol))
    return BranchStability(spec.label, prec, branch.dE[idx], np.array([float(branch.u[i]) for i in idx]),
                           np.array(t1s), trs, np.array(cls), np.array(tr64), np.array(cl64), np.array(r64),
                           float(exit_dE), float(level), stays, branch.stop)


def _rot_bisect_exit(spec, branch, ia, ib, fa, level, xtol):
    """Bisection in ``u`` between members ``ia < ib`` for ``tr M = level``; returns ``E - 4`` (float)."""
    import mpmath as mp

    prec = branch.precision
    U, Q = list(branch.u[:ia + 1]), list(branch.q[:ia + 1])
    a, b = branch.u[ia], branch.u[ib]
    q_b = branch.q[ib]
    with mp.workdps(40):
        for _ in range(200):
            m = (a + b) / 2
            yg, ch = _rot_predict(U, Q, m, "u", prec)
            qm, _ = _rot_correct(spec, m, yg, ch, "u", prec, abs(Q[-1]))
            if qm is None:
                raise ValueError(f"{spec.label}: no member at u = {float(m)!r} while locating the exit")
            fm = _rot_trace(spec, m, qm, prec)[1] - level
            if (fm < 0) == (fa < 0):
                a, fa = m, fm
                U.append(m), Q.append(qm)
            else:
                b, q_b = m, qm
            if abs(b - a) <= xtol * abs(b):
                break
        return float(rotational_dE(spec.label, b, q_b, prec))
