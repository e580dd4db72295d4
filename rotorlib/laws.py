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
           "dual_lame", "reach", "compare", "table"]

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
