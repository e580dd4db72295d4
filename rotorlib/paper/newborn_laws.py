"""The laws of the cascade (paper §7.3-7.6): slope theorems, fans, self-similar scaling and duality.

Built on :mod:`rotorlib.paper.bifurcations` (pendulum transitions, ``Delta``) and
:mod:`rotorlib.paper.newborn` (the families born there).

Slope theorems (§7.3)
---------------------
Near an isochronous (fork-like) bifurcation the new family obeys
``E - E_n = c u^2 + O(u^4)`` and ``tr M - 4 = d u^2 + O(u^4)`` with ``u`` its
``a1`` amplitude, so ``d tr M_new / dE = d / c`` at birth. :func:`fork_fit`
fits both against ``s = u^2`` (least squares, quadratic in ``s``, no constant
term: the family starts at the pendulum) on members just above birth; this is
a continuation derivative, not a two-point difference near a root. The
pendulum's slope is computed independently here by a central difference of
``Delta(x)`` (``x = log|E - 4|``, :func:`rotorlib.paper.bifurcations.delta`) and
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

Rotational scaling constants (§7.5)
-----------------------------------
``alpha^r``, ``beta^r`` need a family far from its birth (IS^r_3 at E(IS^r_1)).
:func:`rotational_member` follows the family with the engine
(:func:`rotorlib.paper.newborn_families.follow`, chart ``K``: the energy ``q`` of the ``a2`` motion
above the barrier is the second unknown, so ``E - 4 = q + T(u)`` keeps its digits),
locates the member at a prescribed ``E - 4`` (float64 or real128) and reads its
amplitudes on the symmetric quarter period; :func:`rotational_ratios` forms the
paper's ratios. Every rotational family followed (IS^r_1..4, PD^r_2..6) ends at
``E -> 4.5``, the maximum of the potential, with a diverging period.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from concurrent.futures import Executor
from dataclasses import dataclass, field
from typing import Any, cast

import mpmath as mp
import numpy as np
from numpy.typing import ArrayLike

from ..core import flow
from ..core.parallel import pmap
from ..core.precision import REAL128, Tier
from ..orbits.continuation import member
from ..orbits.family import Member
from ..orbits.periodic_orbit import PeriodicOrbit
from ..orbits.shooting import solve
from .bifurcations import delta, parse_label, trace_of_delta, transition
from .newborn import family_spec, follow, linear_orbit, newborn_orbit

__all__ = [
    "SQRT3_PI",
    "DELTA_L",
    "SQRT_DELTA_L",
    "SlopeLaw",
    "fork_fit",
    "pendulum_slope",
    "pendulum_dtrace_dx",
    "newborn_slope",
    "slope_law",
    "expected_ratio",
    "fan_prediction",
    "fan_traces",
    "amplitudes",
    "ratios",
    "asymptotic_a1",
    "asymptotic_a2_deficit",
    "DualPair",
    "dual_label",
    "duality_pairs",
    "fit_rate",
    "dual_lame",
    "NotReached",
    "a1_max",
    "rotational_member",
    "RotationalRatio",
    "rotational_ratios",
    "dE_str",
    "rotational_members",
    "a2dot_min",
    "closure",
    "rotational_record",
]

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


def fork_fit(
    E: ArrayLike, trace: ArrayLike, u: ArrayLike, E_birth: float
) -> tuple[float, float, float, float]:
    """Fit ``E - E_n = c1 s + c2 s^2`` and ``tr M - 4 = d1 s + d2 s^2`` with ``s = u^2``.

    Returns ``(slope = d1/c1, c1, d1, residual)``; ``residual`` is the largest
    fit residual relative to the range of the data (both fits). Needs at least
    3 members.
    """
    E = np.asarray(E, float) - float(E_birth)
    y = np.asarray(trace, float) - 4.0
    s = np.asarray(u, float) ** 2
    if len(s) < 3:
        raise ValueError(f"fork_fit needs at least 3 members, got {len(s)}")
    if np.any(s <= 0):
        raise ValueError(
            "amplitudes must be nonzero (the members must lie on the new family)"
        )
    A = np.column_stack([s, s**2])
    scale = s.max() ** np.arange(1, 3)  # columns of order 1
    cE = np.linalg.lstsq(A / scale, E, rcond=None)[0] / scale
    cT = np.linalg.lstsq(A / scale, y, rcond=None)[0] / scale
    res = max(
        np.max(np.abs(A @ cE - E)) / np.ptp(E),
        np.max(np.abs(A @ cT - y)) / max(np.ptp(y), 1e-300),
    )
    return float(cT[0] / cE[0]), float(cE[0]), float(cT[0]), float(res)


def expected_ratio(label: str) -> float:
    """The slope theorem's ``tr M_new' / tr M_pend'``: -2 (IS^l, IS^r), 8 (PD^r)."""
    kind, phase, _ = parse_label(label)
    if kind == "PD" and phase == "lib":
        raise ValueError(
            "PD^l: tr M of pendulum and new family both have a double zero (no slope law)"
        )
    return -2.0 if kind == "IS" else 8.0


def pendulum_dtrace_dx(label: str, h: float = 1e-5) -> float:
    """``d tr M / dx`` of the pendulum at the transition, ``x = log|E - 4|``: central difference of
    ``tr M(Delta(x))`` (``Delta`` float64-accurate to ~1e-13; ``h = 1e-5``: ~1e-8 relative + ``O(h^2)``)."""
    t = transition(label)
    tp, tm = (
        trace_of_delta(delta(t.log_abs_dE + s, t.phase), t.phase) for s in (h, -h)
    )
    return float((tp - tm) / (2 * h))


def pendulum_slope(label: str, h: float = 1e-5) -> float:
    """``d tr M / dE`` of the pendulum at the transition: ``(dtrM/dx) / (E - 4)`` with
    :func:`pendulum_dtrace_dx` and ``E - 4 = -+e^x`` (libration / rotation)."""
    t = transition(label)
    E_minus_4 = (-1.0 if t.phase == "lib" else 1.0) * math.exp(t.log_abs_dE)
    return pendulum_dtrace_dx(label, h) / E_minus_4


def slope_law(
    label: str,
    E: Sequence[Any] | np.ndarray,
    trace: Sequence[Any] | np.ndarray,
    u: Sequence[Any] | np.ndarray,
    dE: Sequence[float] | None = None,
) -> SlopeLaw:
    """:class:`SlopeLaw` from given members ``(E, trace, u)`` of the family born at ``label``.

    ``dE``: their ``E - E_n`` where ``E`` alone would lose its digits (the fit then
    uses ``dE`` about 0 instead of ``E`` about the float64 ``E_n``).
    """
    t = transition(label)
    x, x0 = (E, t.E) if dE is None else (dE, 0.0)
    s_new, c, d, res = fork_fit(x, trace, u, x0)
    s_p = pendulum_slope(label)
    return SlopeLaw(
        t.label,
        t.E,
        s_p,
        float(t.dtrace_dE),
        s_new,
        s_new / s_p,
        expected_ratio(label),
        c,
        d,
        res,
        tuple(map(float, E)),
        tuple(map(float, trace)),
        tuple(map(float, u)),
    )


def newborn_slope(
    label: str,
    rel: Sequence[float] = (2e-4, 5e-4, 1e-3, 2e-3, 4e-3),
    digits: int | None = None,
) -> SlopeLaw:
    """Members at ``E_n + r |E_n - 4|`` (``rotorlib.paper.newborn.newborn_orbit``) and their fork fit.

    The energies are formed in mpmath from the transition's ``log|E_n - 4|`` and passed as decimal
    strings (so ``E - E_n`` keeps its digits even 1e-10 from E = 4, where a float64 ``E`` would lose
    them); the amplitude is the shooting unknown ``u`` (``a1(0)`` or ``p1(0)``).
    """
    t = transition(label)
    with mp.workdps(40):
        eps = mp.e ** mp.mpf(t.log_abs_dE_str)
        E_n = 4 + eps if t.phase == "rot" else 4 - eps
        Es = [mp.nstr(E_n + mp.mpf(r) * eps, 36) for r in rel]
        dE = [float(mp.mpf(r) * eps) for r in rel]
    orbs = [
        newborn_orbit(
            label, E if digits is None or digits > 15 else float(E), digits=digits
        )
        for E in Es
    ]
    amp = [abs(o.extra["u"]) for o in orbs]
    return slope_law(label, [o.E for o in orbs], [o.trace for o in orbs], amp, dE)


# --------------------------------------------------------------------------- fans (§7.4)


def fan_prediction(label: str) -> float:
    """Backward linear extrapolation of a rotational family to E = 4 using the slope theorem.

    ``tr M(4) ~ 4 + r s_pend (4 - E_n) = 4 - r dtrM_pend/dx`` with ``r`` from :func:`expected_ratio`
    (pendulum data only; float64, ~1e-8 relative).
    """
    return float(4.0 - expected_ratio(label) * pendulum_dtrace_dx(label))


def fan_traces(labels: Sequence[str], E: float | str = 4.0) -> dict[str, PeriodicOrbit]:
    """``{label: PeriodicOrbit}`` at energy ``E`` (``newborn_orbit`` default precision: real128 near E = 4)."""
    return {lab: newborn_orbit(lab, E) for lab in labels}


# --------------------------------------------------------------------------- scaling of shapes (§7.5)


def amplitudes(orbit: PeriodicOrbit) -> tuple[float, float]:
    """``(a1max, pi - a2max)`` of a librational newborn orbit, its turning points located in
    real128 from its 32-digit state (``pi - a2max`` formed in mpmath: no cancellation).
    Falls back to the orbit's float64 extrema for a float64 orbit."""
    if orbit.digits <= 15:
        return float(orbit.alpha1_max), float(math.pi - orbit.alpha2_max)
    hits = flow.crossings(
        orbit.state0_str,
        (flow.Section((0, 0, 1, 0)), flow.Section((0, 0, 0, 1))),
        orbit.period_str,  # type: ignore[arg-type]  # a string keeps its digits
        REAL128,
    )
    with REAL128.context():
        a1 = max(abs(x[0]) for k, _, x in hits if k == 0)
        a2 = max(abs(x[1]) for k, _, x in hits if k == 1)
        return float(a1), float(REAL128.pi - a2)


def ratios(values: Sequence[float], k: int) -> list[float]:
    """``values[i] / values[i + k]`` (the alpha(n), beta(n) sequences of paper eqs. al-seq, beta-al-2)."""
    return [values[i] / values[i + k] for i in range(len(values) - k)]


def asymptotic_a1(label: str, E: float | str = 4.0) -> float:
    """Paper eq. (al1-asymptotic): ``a1max(n; E) ~ sqrt(E - E_n)``."""
    t = transition(label)
    if t.phase == "lib":
        with mp.workdps(30):
            return float(mp.sqrt(mp.mpf(E) - 4 + mp.e ** mp.mpf(t.log_abs_dE_str)))
    return math.sqrt(float(E) - t.E)


def asymptotic_a2_deficit(label: str) -> float:
    """Paper eq. (al-2-max): ``pi - a2max(n; 4) ~ sqrt(4 - E_n)`` (librational)."""
    return math.exp(0.5 * transition(label).log_abs_dE)


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
    return f"{'IS' if r < 2 else 'PD'}^r_{2 * j + r + 1}"


def duality_pairs(n_max: int = 20, digits: int | None = None) -> list[DualPair]:
    """:class:`DualPair` for ``IS^l_1 .. IS^l_{n_max}``.

    ``digits=None``: float64 transitions (``x`` to ~2e-13 absolute, so ``diff`` is resolved only while it
    exceeds ~1e-12, i.e. ``n <= 10``). ``digits=30``: every root re-located in real128
    (:func:`rotorlib.paper.bifurcations.transition`, ~30 digits, ~0.3 s per root); ``diff`` and ``k2_sum - 2`` are
    then formed in mpmath and resolved to ~1e-28.
    """
    out = []
    with mp.workdps(40):
        for n in range(1, n_max + 1):
            tl, tr = (
                transition(x, digits=digits) for x in (f"IS^l_{n}", dual_label(n))
            )
            xl, xr = mp.mpf(tl.log_abs_dE_str), mp.mpf(tr.log_abs_dE_str)
            k2m2 = (
                mp.e**xr - mp.e**xl
            ) / 4  # E_r/4 + E_l/4 - 2 with E_l = 4 - e^xl, E_r = 4 + e^xr
            out.append(
                DualPair(
                    tl.label,
                    tr.label,
                    float(xl),
                    float(xr),
                    float(xl - xr),
                    float(2 + k2m2),
                    float(k2m2),
                )
            )
    return out


def fit_rate(ns: ArrayLike, values: ArrayLike) -> tuple[float, float]:
    """Least-squares ``log|v_n| = a - b n``; returns ``(b, a)`` (``|v_n| ~ e^{a - b n}``)."""
    ns = np.asarray(ns, float)
    y = np.log(np.abs(np.asarray(values, float)))
    b, a = np.polyfit(ns, y, 1)
    return float(-b), float(a)


def dual_lame(
    lib_label: str = "IS^l_1", rot_label: str = "IS^r_1", n: int = 2001
) -> dict[str, Any]:
    """Periodic transverse solutions ``a1'' = -(2 + cos a2) a1``, ``a1(0) = 1``, ``a1'(0) = 0`` at two dual
    transitions, on the paper's rescaled times ``z = sqrt3 t`` (lib) and ``z = sqrt3 k_r t`` (rot).

    The librational solution is sampled over one pendulum period (``z`` in ``[0, 4K(k_l)]``) and the
    rotational one over two (``z`` in ``[0, 4K(1/k_r)]``), both on ``n`` points of the normalised time
    ``z / z_max``. Integrated with :func:`rotorlib.paper.newborn.linear_orbit` (closed-form pendulum in the
    coefficient, scipy DOP853, rtol 1e-11).

    Returns
    -------
    dict with ``w`` (normalised time), ``lib``, ``rot`` (the two solutions), ``closure_lib``/``closure_rot``
    (``|a1(end) - 1|``: periodicity check), ``k2_lib``, ``k2_rot``, ``max_diff``.
    """
    tl, tr = transition(lib_label), transition(rot_label)
    t1, y1, _ = linear_orbit(lib_label, [1.0, 0.0, 0.0, 0.0], tl.period, n)
    t2, y2, _ = linear_orbit(rot_label, [1.0, 0.0, 0.0, 0.0], 2 * tr.period, n)
    return {
        "w": np.linspace(0.0, 1.0, n),
        "lib": y1,
        "rot": y2,
        "closure_lib": abs(y1[-1] - 1.0),
        "closure_rot": abs(y2[-1] - 1.0),
        "k2_lib": tl.E / 4.0,
        "k2_rot": tr.E / 4.0,
        "max_diff": float(np.max(np.abs(y1 - y2))),
        "zmax_lib": math.sqrt(3.0) * tl.period,
        "zmax_rot": math.sqrt(3.0 * tr.E / 4.0) * 2 * tr.period,
    }


# --------------------------------------------------------------------------- rotational scaling (§7.5)


class NotReached(ValueError):
    """A rotational family does not reach the energy asked for.

    Attributes
    ----------
    label : str
    dE : float
        ``E - 4`` asked for.
    dE_max : float
        The highest ``E - 4`` on the branch.
    stop : str
        Why the continuation ended.
    """

    def __init__(self, label: str, dE: float, dE_max: float, stop: str) -> None:
        self.label, self.stop = label, stop
        self.dE, self.dE_max = float(dE), float(dE_max)
        super().__init__(
            f"{label} does not reach E - 4 = {self.dE:.6g} along its amplitude "
            f"branch: highest E - 4 = {self.dE_max:.6g} ({stop})"
        )


def a1_max(m: Member) -> float:
    """``max |a1|`` of a rotational member: at the turning points ``p1 = 0`` of its
    symmetric quarter period ``(0, t1)`` (located in its tier) or at the ends.

    Examples
    --------
    >>> from rotorlib.paper.newborn_laws import a1_max, a2dot_min, rotational_member
    >>> m = rotational_member("IS^r_1", 0.02)
    >>> round(a1_max(m), 6), round(a2dot_min(m), 6)
    (0.105303, 0.16416)
    """
    t = Tier(m.precision)
    with t.context():
        hits = flow.crossings(list(m.x0), (flow.Section((0, 0, 1, 0)),), m.t1, t)
        return float(
            max([abs(m.x0[0]), abs(m.x1[0])] + [abs(x[0]) for _, _, x in hits])
        )


def a2dot_min(m: Member) -> float:
    """``min a2' = (3/2) p2`` of a rotational member, at ``a2 = pi`` (its symmetric point
    ``t1``)."""
    with Tier(m.precision).context():
        return float(1.5 * m.x1[3])


def closure(m: Member) -> float:
    """``max |x(T) - x(0) - L|`` of a member over its full period ``T`` (``L`` its family's
    lattice vector), integrated with the variational equations in the member's tier."""
    t, lattice = Tier(m.precision), family_spec(m.label).problem.lattice
    with t.context():
        xT = flow.monodromy_matrix(list(m.x0), m.period, t)[1]
        lat = [lattice[0] * t.pi, lattice[1] * t.pi, 0, 0]
        return max(abs(float(a - b - c)) for a, b, c in zip(xT, m.x0, lat))


def rotational_member(label: str, dE: float | str, digits: int | None = None) -> Member:
    """The member of a rotational newborn family with ``E - 4 = dE`` (a decimal string keeps
    its digits in real128), reached by :func:`rotorlib.paper.newborn_families.follow` in the
    ``K`` chart and located on the branch by a secant on its pseudo-arclength, with its
    ``tr M`` (:func:`a1_max`, :func:`a2dot_min` and :func:`closure` give the rest).

    Raises :class:`NotReached` when the family ends below (attributes: the highest ``E - 4``
    and why the continuation stopped). Precision: ``E - 4`` matched to ~1e-15 (float64) or
    ~1e-30 (real128) relative; residuals below 1e-8 (float64) and at the tier's round-off
    floor (real128: ~1e-18 at ``E - 4 ~ 1e-12``); a float64 member whose period does not
    close to 1e-8 is re-solved in real128. ``tr M`` moves by about ``|r| |M|^2``: at the
    deepest real128 members (IS^r_8, PD^r_8 at ``E - 4 ~ 1e-12``) it is good to ~5e-4
    relative (measured against 45-digit members of IS^r_8 and PD^r_8); pass ``digits``
    for more.

    Examples
    --------
    >>> from rotorlib.paper.newborn_laws import closure, rotational_member
    >>> m = rotational_member("IS^r_1", 0.02)
    >>> m.precision, round(float(m.E), 12), round(m.trace, 3), closure(m) < 1e-10
    ('float64', 4.02, 4.932, True)
    """
    spec = family_spec(label)
    if spec.phase != "rot":
        raise ValueError(f"{spec.label} is not a rotational family (IS^r_n, PD^r_n)")
    target = float(dE)
    if not target > 0:
        raise ValueError(f"dE must be > 0, got {dE!r}")
    deep = spec.depth < Tier.separatrix_depth
    with REAL128.context():  # 4 + dE keeping the digits of a decimal string (real128)
        E = 4 + REAL128.num(dE) if deep else 4 + float(dE)
    b = follow(
        label,
        chart="K",
        E_range=(None, 4 + target * 1.01),
        energies=(E,),
        digits=digits,
        jump=0.05 if deep else None,
        ds_max=0.5,
    )
    pts = b.points("E")
    if not pts:
        raise NotReached(spec.label, target, b.E_max - 4, b.stop)
    m, t = cast(Member, pts[0].member), b.tier
    if t.extended or (pts[0].located and closure(m) < 1e-8):
        return member(b.problem, m.u, m.w, t, traces=True)
    # too unstable for a float64 period (or not located): re-solved at E in real128
    with REAL128.context():
        E, u0 = 4 + REAL128.num(dE), REAL128.num(m.u)
        u = solve(
            b.problem,
            u0,
            u0 * (1 + REAL128.num("1e-12")),
            E=E,
            digits=REAL128,
            r_max=1e-18,
        ).x
        return member(b.problem, u, b.problem.w_at(u, E, REAL128), REAL128, traces=True)


def dE_str(label: str) -> str:
    """``E_n - 4`` of a rotational transition as a 35-digit decimal string."""
    t = transition(label)
    if t.phase != "rot":
        raise ValueError(f"{t.label} is not a rotational transition")
    with mp.workdps(40):
        return mp.nstr(mp.e ** mp.mpf(t.log_abs_dE_str), 35)


def rotational_record(m: Member) -> dict[str, Any]:
    """A rotational member as JSON: :meth:`Member.to_dict <rotorlib.orbits.family.Member.to_dict>`
    with ``dE`` (``E - 4`` formed in the tier), :func:`a1_max`, :func:`a2dot_min` and
    :func:`closure`."""
    with Tier(m.precision).context():
        dE = float(m.E - 4)
    return {
        **m.to_dict(),
        "dE": dE,
        "a1_max": a1_max(m),
        "a2dot_min": a2dot_min(m),
        "closure": closure(m),
    }


#: A rotational member as stored (:func:`rotational_record`), or why it does not exist.
MemberRecord = dict[str, Any] | str
#: ``(label, dE)``: a family and the decimal string of ``E - 4`` (:func:`dE_str`).
Key = tuple[str, str]


def _member_task(key: Key) -> MemberRecord:
    """The record of the member ``key = (label, dE)``, or why it does not exist."""
    try:
        return rotational_record(rotational_member(*key))
    except NotReached as exc:
        return str(exc)


@dataclass(frozen=True)
class RotationalRatio:
    """The paper's rotational scaling ratios (eq. alpha-beta-r) for one ``n`` of one class:
    ``alpha = a1max(n; E_{n-2}) / a1max(n+2; E_n)``, ``beta = a2'min(n; E_{n-2}) /
    a2'min(n+2; E_n)`` (``E_k`` the bifurcation energies of the same kind), ``nan`` with a
    ``reason`` when a member does not exist (its record is then ``None``); ``alpha_pred``,
    ``beta_pred`` the paper's estimates ``sqrt((E_{n-2} - E_n)/(E_n - E_{n+2}))``,
    ``sqrt((E_n - 4)/(E_{n+2} - 4))``."""

    kind: str
    n: int
    numerator: dict[str, Any] | None
    denominator: dict[str, Any] | None
    alpha: float
    beta: float
    alpha_pred: float
    beta_pred: float
    reason: str = ""


def _pairs(specs: Sequence[tuple[str, int]]) -> list[tuple[str, int, Key, Key]]:
    """``(kind, n, numerator, denominator)`` for each ``(kind, n)``: the keys
    ``(label, dE)`` of the two members of the ratio."""
    out = []
    for k, n in specs:
        if k not in ("IS", "PD") or int(n) < 3:
            raise ValueError(
                f"need kind 'IS' or 'PD' and n >= 3 (E_(n-2) must exist), "
                f"got {(k, n)!r}"
            )
        num, den = (f"{k}^r_{n}", f"{k}^r_{n - 2}"), (f"{k}^r_{n + 2}", f"{k}^r_{n}")
        out.append((k, int(n), (num[0], dE_str(num[1])), (den[0], dE_str(den[1]))))
    return out


def rotational_members(
    specs: Sequence[tuple[str, int]],
    executor: Executor | None = None,
    progress: bool = False,
) -> dict[Key, MemberRecord]:
    """The members that :func:`rotational_ratios` needs for ``specs``, each once:
    ``{(label, dE): record}``, ``dE`` the decimal string of ``E - 4`` (:func:`dE_str`),
    the record that of :func:`rotational_record`, or the :class:`NotReached` message (a
    string) for a family that ends below ``dE``. Computed through
    :func:`rotorlib.core.parallel.pmap` (``executor``: any
    :class:`concurrent.futures.Executor`); precision as in :func:`rotational_member`."""
    tasks = list(dict.fromkeys(key for *_, a, b in _pairs(specs) for key in (a, b)))
    return dict(
        zip(
            tasks,
            pmap(
                _member_task,
                tasks,
                executor=executor,
                progress=progress,
                desc="rotational members",
            ),
        )
    )


def rotational_ratios(
    specs: Sequence[tuple[str, int]],
    executor: Executor | None = None,
    progress: bool = False,
    members: Mapping[Key, MemberRecord] | None = None,
) -> list[RotationalRatio]:
    """:class:`RotationalRatio` for each ``(kind, n)`` of ``specs`` (``n >= 3``); the members
    (each once) from :func:`rotational_members` (``executor``: any
    :class:`concurrent.futures.Executor`), or from ``members``, a dict of the same form
    (e.g. members stored by a script and checked). Precision: ratios to ~1e-8 (float64
    members) or ~1e-15 (real128) relative, far below their distance to the limit."""
    res = rotational_members(specs, executor, progress) if members is None else members
    out = []
    with mp.workdps(40):
        for k, n, num_key, den_key in _pairs(specs):
            a, b, c = (mp.mpf(dE_str(f"{k}^r_{m}")) for m in (n - 2, n, n + 2))
            ap, bp = float(mp.sqrt((a - b) / (b - c))), float(mp.sqrt(b / c))
            recs = [res[num_key], res[den_key]]
            bad = [m for m in recs if isinstance(m, str)]
            num, den = (None if isinstance(m, str) else m for m in recs)
            alpha = beta = math.nan
            if num is not None and den is not None:
                alpha = num["a1_max"] / den["a1_max"]
                beta = num["a2dot_min"] / den["a2dot_min"]
            out.append(
                RotationalRatio(k, n, num, den, alpha, beta, ap, bp, "; ".join(bad))
            )
    return out
