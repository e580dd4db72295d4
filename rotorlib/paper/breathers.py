"""The rotational isosceles breather R, its period-doubling transition and its daughter family (paper §8).

The breather ``phi1 = phi2 = phi`` is ``b1 = 2 phi, b2 = 0`` in the breather variables
``[b1, b2, q1, q2]`` of :mod:`rotorlib.core.system` (the paper's beta_i, pi_i). Its
monodromy is block diagonal, ``(b1, q1 | b2, q2)`` = (longitudinal | transverse),
with ``tr M = 2 + Delta`` for R (``Delta^2`` for LG, LD); it comes from
:func:`rotorlib.orbits.floquet.monodromy`.

Transition
    :func:`breather_transitions` locates the single stability transition of R
    (``tr M = 0``, a period doubling; paper E ~ 8.97, period ~ 2.63) with the one
    locator of pendula and breathers (:func:`rotorlib.paper.bifurcations.locate_root`, the
    engine's Illinois method) in float64 (~2e-15) and, with ``digits > 15``, again
    with the trace evaluated at that many digits (heyoka real128 / multiprecision,
    :func:`rotorlib.paper.bifurcations.refine_root`). It is a
    :class:`rotorlib.paper.bifurcations.Transition`, as the pendulum's are.

Daughter family ``PD^b``
    Born at the transition with the doubled period. Two searches:

    * the paper's (:func:`daughter_by_er_minimisation`): start at
      ``(b1, b2, q1, q2) = (0, delta, q1, 0)``, integrate until ``b1 = 8 pi``
      (two breather periods) and minimise ``Er(q1)``;
    * the engine's symmetric shooting (:data:`DAUGHTER`). ``V(b1, b2)`` is even in
      ``b1`` and in ``b2`` separately, so ``(b1, b2, q1, q2, t) ->
      (-b1, b2, q1, -q2, -t)`` and ``(b1, b2, q1, q2, t) -> (4 pi - b1, -b2, q1, q2, -t)``
      are reversing symmetries with fixed sets ``{b1 = 0, q2 = 0}`` and
      ``{b1 = 2 pi, b2 = 0}``. An orbit starting on the first set that reaches the
      second when ``b1`` first equals ``2 pi`` is periodic, with period four times
      that time, and ``b2`` changes sign after half a period (multiplier -1): the
      period-doubled daughter. In pendulum variables ``b1 = a1 + a2``,
      ``b2 = 3 a1 - a2``; the parent R (``delta = 0``) is divided out.

    The family is continued in ``delta`` (:func:`daughter_family`); it exists for
    ``E < E_PD`` (a backward fork-like bifurcation).

Precision: the transition energy to ~1e-15 in float64 and to >= 20 digits with
``digits=30``; daughter orbits (float64) close to ~1e-12 over their period and ``tr M``
is accurate to ~1e-9; :func:`breather_daughter` with ``digits=D`` re-solves the member in
the tier that delivers ``D`` digits. ``tests/test_breathers.py`` checks both against
independent integrators.
"""

from __future__ import annotations

import functools
import math
import re
from dataclasses import dataclass, field, replace
from typing import Any

import mpmath as mp
import numpy as np
from scipy import optimize

from ..core.closed_forms import breather
from ..core.energy import as_float
from ..core.flow import Section, flow, sample, to_section
from ..core.precision import FLOAT64, Tier, tier
from ..core.system import alpha_to_beta, beta_to_alpha, potential_beta
from ..orbits.continuation import (
    Branch,
    ContinuationOptions,
    Natural,
    continuation,
    switch,
)
from ..orbits.floquet import monodromy, trace_monodromy
from ..orbits.periodic_orbit import PeriodicOrbit, orbit_from_state
from ..orbits.shooting import ShootingProblem, StartSet, solve
from .bifurcations import Transition, level_crossings, refine_root

__all__ = [
    "is_breather_label",
    "breather_transitions",
    "pd_transition",
    "pd_eigenstructure",
    "PDEigenstructure",
    "breather_trace",
    "DAUGHTER",
    "daughter_orbit",
    "daughter_by_er_minimisation",
    "daughter_family",
    "DaughterFamily",
    "breather_daughter",
    "DAUGHTER_E_MIN",
    "er_function",
    "daughter_trajectory",
    "half_map_trace",
    "DEFAULT_DELTAS",
]

#: Lower end of the energy range over which :func:`breather_daughter` is supported (validated continuation).
DAUGHTER_E_MIN = 5.3
#: Default continuation amplitudes b2(0) of the daughter family.
DEFAULT_DELTAS = np.concatenate(
    [np.linspace(0.02, 0.12, 6), np.linspace(0.15, 5.65, 111), [5.67, 5.69]]
)
_SCAN = np.concatenate([np.linspace(4.55, 20.0, 160), np.geomspace(20.0, 1e4, 40)[1:]])


def breather_trace(E: Any, family: str = "R", digits: int | None = None) -> Any:
    """``tr M`` of the breather ``family`` at energy ``E``: a float in float64, an mpf
    with every digit of ``trace_str`` when ``digits > 15``
    (:func:`rotorlib.orbits.floquet.trace_monodromy`)."""
    return trace_monodromy(breather(E, family), digits=digits)


# ----------------------------------------------------------------------------------------------
# the transition
# ----------------------------------------------------------------------------------------------


def _trace_slope(E: float, family: str = "R", h: float = 1e-5) -> float:
    return (breather_trace(E + h, family) - breather_trace(E - h, family)) / (2 * h)


def breather_transitions(
    family: str = "R", digits: int | None = None, E_max: float = 1e4
) -> list[Transition]:
    """Every stability transition (``tr M`` crossing 0 or 4) of a breather family.

    Parameters
    ----------
    family : {'R', 'LG', 'LD'}
        Only ``R`` has transitions (LG and LD have ``tr M > 4`` throughout: an empty list).
    digits : int, optional
        ``> 15``: each energy re-located with the trace at that many digits
        (:func:`rotorlib.paper.bifurcations.refine_root`); ``E_str`` and ``period_str`` then
        carry ``digits - 5`` significant digits.
    E_max : float
        Upper end of the scan for R.

    Returns
    -------
    list of Transition
        Float64: ``E`` to ~1e-15 (the engine's Illinois method on a scan of ``tr M``).
    """
    if family not in ("R", "LG", "LD"):
        raise ValueError(f"breather family must be R, LG or LD; got {family!r}")
    grid = {
        "LG": np.linspace(0.05, 4.45, 45),
        "LD": np.linspace(4.01, 4.49, 25),
        "R": _SCAN[_SCAN <= E_max],
    }[family]
    tr = np.array([breather_trace(E, family) for E in grid])
    return sorted(
        (
            _make_transition(float(E), kind, level, family, digits)
            for level, kind in ((0.0, "PD"), (4.0, "IS"))
            for _, E in level_crossings(
                lambda v: breather_trace(v, family), grid, tr, level
            )
        ),
        key=lambda t: t.E,
    )


def _make_transition(
    E: float, kind: str, level: float, family: str, digits: int | None
) -> Transition:
    slope = _trace_slope(E, family)
    d = None if digits is None or digits <= 15 else int(digits)
    if d is None:
        orbit = breather(E, family)
        E_str, per_str, p_str = (
            repr(E),
            repr(orbit.period),
            repr(float(orbit.state0[3])),
        )
    else:
        dps = d + 10

        def trace_at(v: Any) -> Any:
            M = monodromy(breather(mp.nstr(v, dps), family), digits=d)
            return mp.mpf(M.trace_str) - level

        with mp.workdps(dps):
            E_ext = refine_root(trace_at, E, d)
            per = breather(mp.nstr(E_ext, dps), family).closed_form(dps)["period"]
            E_str, per_str, p_str = (
                mp.nstr(v, d - 5) for v in (E_ext, per, mp.sqrt(E_ext))
            )
        orbit = breather(E_str, family)
    return Transition.at_base_point(
        "PD^b" if kind == "PD" else "IS^b",
        kind,
        family,
        orbit.energy,
        (orbit.period, per_str),
        (p_str, p_str),
        None,
        slope,
        None if d is None else d - 5,
        E_str,
        phase=orbit.energy.phase,
        log_abs_dE=orbit.energy.log_abs_dE,
        delta_target=level - 2.0 if family == "R" else float("nan"),
    )


_LABEL_RE = re.compile(r"^\s*(PD)\s*\^?\s*(\{\s*b\s*\}|b)\s*$", re.IGNORECASE)


def is_breather_label(text: Any) -> bool:
    """Whether ``text`` names the breather's transition ``PD^b`` (also ``PDb``,
    ``PD^{b}``), the label of its daughter family too.

    Examples
    --------
    >>> is_breather_label("PDb"), is_breather_label("PD^b_1")
    (True, False)
    """
    return isinstance(text, str) and bool(_LABEL_RE.match(text))


def pd_transition(digits: int | None = None) -> Transition:
    """The period-doubling transition ``PD^b`` of the rotational breather R (paper:
    E ~ 8.97, period ~ 2.63).

    Examples
    --------
    >>> from rotorlib.paper.breathers import pd_transition
    >>> t = pd_transition()
    >>> t.label, t.family, t.transition, round(t.E, 9), round(t.period, 9)
    ('PD^b', 'R', 'unstable->stable', 8.968972047, 2.633423826)
    """
    pds = [t for t in breather_transitions("R", digits=digits) if t.kind == "PD"]
    if len(pds) != 1:
        raise RuntimeError(f"expected one PD transition of R, found {len(pds)}")
    return pds[0]


@dataclass(frozen=True)
class PDEigenstructure:
    """Spectrum and eigenvectors of M at the breather's PD transition.

    Attributes
    ----------
    eigenvalues : ndarray (4,)
        Eigenvalues of M (basis ``(b1, q1, b2, q2)``).
    eigenvectors : dict
        ``{+1: ndarray (4, k), -1: ndarray (4, k)}``: a basis of each eigenspace
        (null space of ``M -+ I`` by SVD, singular values below ``tol`` counted as zero).
    geometric_multiplicity : dict
        ``{+1: k, -1: k}``.
    singular_values : dict
        Singular values of ``M - I`` and ``M + I``.
    matrix : ndarray (4, 4)
    basis : tuple of str
    """

    eigenvalues: np.ndarray
    eigenvectors: dict
    geometric_multiplicity: dict
    singular_values: dict
    matrix: np.ndarray
    basis: tuple


def pd_eigenstructure(E: float | None = None, tol: float = 1e-8) -> PDEigenstructure:
    """Eigenvalues and eigenvectors of M of the breather R at its PD transition (or at ``E``)."""
    if E is None:
        E = pd_transition().E
    M = monodromy(breather(E, "R"))
    A = M.matrix
    vecs, mult, svals = {}, {}, {}
    for lam in (1, -1):
        _, s, vh = np.linalg.svd(A - lam * np.eye(4))
        null = vh[s < tol * max(1.0, s[0])].T
        null = null * np.sign(
            null[np.argmax(np.abs(null), axis=0), range(null.shape[1])]
        )
        vecs[lam], mult[lam], svals[lam] = null, null.shape[1], s
    ev = np.sort_complex(np.linalg.eigvals(A))
    return PDEigenstructure(ev, vecs, mult, svals, A, M.basis)


# ----------------------------------------------------------------------------------------------
# the daughter family
# ----------------------------------------------------------------------------------------------

#: The daughter ``PD^b`` as a shooting problem: start ``(b1, b2, q1, q2) = (0, delta, q1, 0)``
#: (``a1 = delta/4``, ``a2 = -delta/4``, ``p1 = p2 = q1``), section ``b1 = a1 + a2 = 2 pi``,
#: condition ``b2 = 3 a1 - a2 = 0``, period ``4 t1``, closing on ``(a1, a2) + (2 pi, 6 pi)``.
DAUGHTER = ShootingProblem(
    "PD^b",
    StartSet("b1 = 0, q2 = 0", a=(0.25, -0.25), b=(1.0, 1.0)),
    Section((1, 1, 0, 0), 2.0, 1),
    Section((3, -1, 0, 0)),
    1,
    4,
    (2.0, 6.0),
    trivial=0.0,
    t_max=100.0,
    abort=Section((0, 0, 0.5, 1.5), 0.0, -1),
)  # b1 turning back


def _beta(x):
    return alpha_to_beta(np.array([float(v) for v in x]))


def daughter_orbit(
    E: Any,
    delta: Any,
    digits: int | Tier | None = None,
    method: str = "symmetric shooting (quarter period)",
    *,
    shown: int | None = None,
) -> PeriodicOrbit:
    """The daughter orbit of the member ``(delta, E)`` (:data:`DAUGHTER`), integrated in the
    tier of ``digits`` (extended: strings of ``shown`` digits): monodromy over the full period; ``alpha1_max = alpha2_max = max|b2| / 4`` (the
    largest excursion of ``a1`` and ``a2`` from the parent's line ``a2 = 3 a1`` at fixed
    ``b1``); ``extra`` has ``delta_b2``, ``q1_0``, ``quarter_period``, ``beta2_max`` and
    ``symmetric_residual`` (``|b2|`` at ``b1 = 2 pi``)."""
    t = tier(digits)
    with t.context():
        x0 = DAUGHTER.state(delta, E, t)
        tq, x1 = to_section(x0, DAUGHTER.section, t, t_max=DAUGHTER.t_max)
        return _finish(x0, 4 * tq, E, tq, x1, t, method, digits=shown)


def _finish(x0, T, E, tq, xq, t, method, extra=None, digits=None):
    o = orbit_from_state("PD^b", x0, T, t, DAUGHTER.lattice, E, shown=digits)
    b2max = float(np.max(np.abs(daughter_trajectory(o, 401)[:, 1])))
    ex = dict(
        o.extra,
        method=method,
        delta_b2=float(_beta(x0)[1]),
        q1_0=float(x0[2]),
        quarter_period=float(tq),
        beta2_max=b2max,
        symmetric_residual=abs(float(_beta(xq)[1])),
        **(extra or {}),
    )
    return replace(o, alpha1_max=b2max / 4, alpha2_max=b2max / 4, extra=ex)


@dataclass(frozen=True)
class DaughterFamily(Branch):
    """The daughter family ``PD^b``: the engine's :class:`~rotorlib.orbits.continuation.Branch`
    (continued in ``delta = b2(0)``; ``E``, ``period``, ``trace`` = ``tr M`` of the full
    4x4 monodromy, ``members``, ``special_points``, ``stop``) with the analysis of its
    birth.

    Attributes
    ----------
    delta : ndarray
        ``b2(0)`` of the members (the branch's ``u``).
    E_PD : float
        The parent's transition energy.
    slope_ratio : float
        ``tr M_new'(E) / tr M_R'(E)`` at the bifurcation: ``d tr M / d(delta^2)`` over
        ``dE / d(delta^2)`` (quadratic fits in ``delta^2`` of the points with
        ``delta <= delta_fit``), over the parent's slope.
    parent_slope : float
    E_unstable : float
        Energy below which the family is unstable (``tr M`` leaves ``(0, 4)``).
    unstable_crossing : str
        ``tr M = 0`` or ``tr M = 4``: which boundary is crossed there.
    fit : dict
        The quadratic fits (``E_fit``, ``trace_fit``) and their values at birth.
    """

    E_PD: float = math.nan
    slope_ratio: float = math.nan
    parent_slope: float = math.nan
    E_unstable: float = math.nan
    unstable_crossing: str = "none"
    fit: dict[str, Any] = field(default_factory=dict)

    @property
    def delta(self) -> np.ndarray:
        return self.u


def daughter_family(
    deltas: Any = None, E_PD: float | None = None, delta_fit: float = 0.12
) -> DaughterFamily:
    """Continue the daughter family in ``delta = b2(0)`` from the bifurcation (the engine's
    natural continuation, predictor linear in ``delta^2`` from the parent at ``(0, E_PD)``,
    with ``tr M`` of every member and the exit from the stable window located).

    Parameters
    ----------
    deltas : array_like, optional
        Increasing positive amplitudes (default: 0.02 ... 5.69, reaching E ~ 5.29).
    E_PD : float, optional
        Parent transition energy (computed when omitted).
    delta_fit : float
        Points with ``delta <= delta_fit`` enter the slope fit.
    """
    E_PD = pd_transition().E if E_PD is None else float(E_PD)
    deltas = np.asarray(DEFAULT_DELTAS if deltas is None else deltas, float)
    first, _ = switch(DAUGHTER, float(deltas[0]), E_PD, -1e-4)
    alg = Natural(
        "u", tuple(float(d) for d in deltas[1:]), order=1, origin=0.0, origin_other=E_PD
    )
    b = continuation(
        DAUGHTER, alg, ContinuationOptions(traces=True, folds=False), [first]
    )
    sel = deltas <= delta_fit  # the quadratic fits in delta^2 near the birth
    pE = np.polyfit(deltas[sel] ** 2, b.E[sel], 2)
    pT = np.polyfit(deltas[sel] ** 2, b.trace[sel], 2)
    parent = _trace_slope(E_PD)
    leave = next(  # the first exit from the stable window, E falling
        (
            p
            for p in b.special_points
            if p.located and float(b.members[p.index].u) > 0.05
        ),
        None,
    )
    return DaughterFamily(
        b.problem,
        b.tier,
        b.members,
        b.special_points,
        b.stop,
        b.reason,
        b.E_range,
        E_PD,
        float((pT[-2] / pE[-2]) / parent),
        float(parent),
        math.nan if leave is None else leave.E,
        "none" if leave is None else f"tr M = {4 if leave.kind == 'IS' else 0}",
        {"E_fit": pE, "trace_fit": pT, "E_at_birth": pE[-1], "trace_at_birth": pT[-1]},
    )


def daughter_by_er_minimisation(
    delta: float, q1_guess: float, width: float = 0.05
) -> PeriodicOrbit:
    """The paper's search: fix ``b2(0) = delta``, minimise ``Er(pi1(0))`` over two breather
    periods (Brent from the bracket ``q1_guess -+ width``; ``pi1(0)`` to ~1e-8). The orbit
    returned has the energy of ``(0, delta, pi1(0), 0)``, the period ``t*`` (time to
    ``b1 = 8 pi``) and ``extra['Er']``; nothing assumes the symmetry, and
    ``extra['symmetric_residual'] = |b2|`` at ``b1 = 2 pi`` tells whether the minimiser
    found the symmetric daughter (~0) or another orbit through the same line."""
    res = optimize.minimize_scalar(
        er_function,
        bracket=(q1_guess - width, q1_guess, q1_guess + width),
        args=(delta,),
        tol=1e-12,
    )
    q1 = float(res.x)
    x0 = list(beta_to_alpha(np.array([0.0, delta, q1, 0.0])))
    t_star, _ = to_section(x0, Section((1, 1, 0, 0), 8.0, 1), t_max=100.0)
    tq, xq = to_section(x0, DAUGHTER.section, t_max=100.0)
    return _finish(
        x0,
        t_star,
        q1 * q1 + float(potential_beta(0.0, delta)),
        tq,
        xq,
        FLOAT64,
        "Er minimisation (paper)",
        {"Er": float(res.fun)},
    )


def er_function(q1_0: float, delta: float) -> float:
    """The paper's ``Er(pi_1(0))``: integrate ``(0, delta, q1_0, 0)`` until ``b1 = 8 pi``."""
    x0 = list(beta_to_alpha(np.array([0.0, delta, q1_0, 0.0])))
    _, x = to_section(x0, Section((1, 1, 0, 0), 8.0, 1), t_max=100.0)
    b = _beta(x)
    return math.sqrt((b[1] - delta) ** 2 + (b[2] - q1_0) ** 2 + b[3] ** 2)


@functools.lru_cache(maxsize=4)
def _branch_table():
    return daughter_family()


def breather_daughter(E: Any, digits: int | None = None) -> PeriodicOrbit:
    """The orbit of the daughter family ``PD^b`` at energy ``E`` (the ``orbit PD^b`` command).

    ``delta`` is bracketed by the members of :func:`daughter_family` and solved at ``E`` by
    the secant (float64), then re-solved in the tier that delivers ``digits`` (extended:
    ``state0_str``, ``period_str``, ``trace_str`` with that many digits).

    Raises
    ------
    ValueError
        Outside the family's range ``DAUGHTER_E_MIN <= E < E_PD``.
    """
    Ef = as_float(E, "E")
    fam = _branch_table()
    if not (DAUGHTER_E_MIN <= Ef < fam.E_PD):
        raise ValueError(
            f"the breather daughter family PD^b exists for E < E_PD = "
            f"{fam.E_PD:.12f} (computed for {DAUGHTER_E_MIN} <= E < "
            f"{fam.E_PD:.12f}); got E = {E!r}"
        )
    # fam.E[i - 1] > E >= fam.E[i] (the branch falls to E ~ 5.29 < DAUGHTER_E_MIN)
    i = int(np.searchsorted(-fam.E, -Ef))
    lo, hi = (1e-3 if i == 0 else fam.delta[i - 1]), fam.delta[i]
    Eh = fam.E[i - 1] if i else fam.E_PD
    guess = lo + (hi - lo) * (Eh - Ef) / (Eh - fam.E[i])
    d = solve(DAUGHTER, guess, guess * (1 + 1e-6), E=Ef, tol=1e-15).x
    t = tier(digits)
    if t.extended:
        with t.context():
            d = solve(
                DAUGHTER, t.num(d), t.num(d) * (1 + t.num("1e-12")), E=str(E), digits=t
            ).x
    return daughter_orbit(str(E) if t.extended else Ef, d, t, shown=digits)


def daughter_trajectory(orbit: PeriodicOrbit, n: int = 801) -> np.ndarray:
    """States ``[b1, b2, q1, q2]`` at ``n`` equally spaced times over one period of a daughter."""
    return alpha_to_beta(sample(orbit.state0, orbit.period, int(n))[0])


def half_map_trace(orbit: PeriodicOrbit) -> float:
    """``tr N`` with ``N = S Phi(T/2)``, ``S = diag(1, -1, 1, -1)`` in ``[b1, b2, q1, q2]``.

    The daughter satisfies ``x(t + T/2) = S x(t) + (4 pi, 0, 0, 0)``, so ``M = N^2``; N is
    symplectic with eigenvalues ``1, 1, mu, 1/mu``, hence ``tr M = 2 + mu^2 + mu^-2 =
    (tr N - 2)^2``: ``tr M`` of this family can touch 0 but never go below it.
    """
    _, Phi = flow(orbit.state0, 0.5 * orbit.period, variational=True)
    A = np.array([alpha_to_beta(e) for e in np.eye(4)]).T  # alpha state -> beta state
    Pb = A @ np.array(Phi, float) @ np.linalg.inv(A)
    return float(np.trace(np.diag([1.0, -1.0, 1.0, -1.0]) @ Pb))
