"""The paper's search for newborn orbits (§6) against the symmetric shooting of the engine.

The paper fixes the perturbation ``u`` along the transverse eigenvector, integrates until
``a2`` completes one (IS) or two (PD) cycles and minimises the departure from periodicity
``d(p2(0))`` (:func:`paper_search`). The engine finds the root of a signed residual over a
quarter or half period instead (:func:`rotorlib.paper.newborn.birth_member`).
:func:`compare_searches`, :func:`work_precision` and :func:`defect_landscape` score the two
(chapter ``book/04_search.ipynb``): as a minimisation the paper's search is limited to
~sqrt(eps); :func:`residual_scan` shows where a family has no member at a given energy.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any

import mpmath as mp
import numpy as np
from numpy.typing import ArrayLike

from ..core import flow
from ..core.flow import Section, SectionNotReached, StateLike
from ..core.precision import REAL128, Tier, tier
from ..core.system import energy_alpha, potential_alpha
from ..orbits.shooting import residual
from .newborn import FamilySpec, birth_member, family_spec, seed

__all__ = [
    "periodicity_defect",
    "PaperSearchResult",
    "paper_search",
    "SearchComparison",
    "default_amplitude",
    "compare_searches",
    "WorkPrecision",
    "work_precision",
    "DefectLandscape",
    "defect_landscape",
    "residual_scan",
]

_TURN, _UP = Section((0, 0, 0, 1), 0.0, -1), Section((0, 1, 0, 0), 0.0, 1)


def _with_p2(spec: FamilySpec, u: float, p2: float) -> list[float]:
    """``[a1, a2, p1, p2]`` on the family's start line with ``p2(0)`` given."""
    return [u, 0.0, 0.0, p2] if spec.start == "a1" else [0.0, 0.0, u, p2]


def periodicity_defect(
    label: str, x0: StateLike, digits: int | Tier | None = None
) -> tuple[float, float]:
    """The paper's departure from periodicity of the orbit from ``x0`` (``a2(0) = 0``), §6 step 3.

    Integrates until ``a2`` completes one (IS) or two (PD) cycles (libration: back through
    ``a2 = 0`` going up after each turning point; rotation: to ``a2 = 2 pi`` or ``4 pi``) and
    returns ``(d, t*)``, ``d = [(a1(t*) - a1(0))^2 + (p1(t*) - p1(0))^2 + (p2(t*) - p2(0))^2]^(1/2)``.
    Precision: the tier of ``digits`` (:func:`~rotorlib.core.precision.tier`); the flow
    amplifies round-off like ``1/|E - 4|`` over the full period.
    """
    spec, t = family_spec(label), tier(digits)
    cycles = 1 if spec.kind == "IS" else 2
    with t.context():
        x0 = [t.num(v) for v in x0]
        if spec.phase == "lib":
            x, tt = x0, 0
            for _ in range(cycles):
                for sec in (_TURN, _UP):
                    dt, x = flow.to_section(x, sec, t)
                    tt = tt + dt
        else:
            tt, x = flow.to_section(x0, Section((0, 1, 0, 0), 2.0 * cycles, 1), t)
        d = t.m.sqrt(sum((x[k] - x0[k]) ** 2 for k in (0, 2, 3)))
    return float(d), float(tt)


@dataclass(frozen=True)
class PaperSearchResult:
    """Result of :func:`paper_search`: the fixed ``u``, the minimiser ``p2``, its energy ``E``,
    ``n_evaluations`` of ``d`` (each over one or two cycles of
    ``a2``), the integration time ``t_star`` of the minimiser and whether the minimiser sits on
    an end of the bracket (``at_bound``: the bracket missed the minimum)."""

    label: str
    u: float
    p2: float
    E: float
    n_evaluations: int
    t_star: float
    at_bound: bool


def paper_search(
    label: str,
    u: float,
    E_guess: float,
    width: float | None = None,
    xatol: float = 1e-16,
    maxiter: int = 500,
) -> PaperSearchResult:
    """Paper §6 as written: minimise ``d(p2(0))`` (:func:`periodicity_defect`) at fixed ``u``
    with Brent's bounded minimiser (:func:`scipy.optimize.minimize_scalar`), over the ``p2``
    of the energies ``E_guess -+ width`` (default ``width = |E_guess - E_n| / 2``).

    Precision: float64. Brent stops once its bracket is below ``sqrt(eps) |p2| + xatol/3``:
    at a smooth minimum ``f''(x) h^2 / 2`` is invisible below ``h ~ sqrt(eps)``, so ``E`` is
    found to ~1e-8 relative whatever ``xatol``. A root of the signed symmetric residual has
    no such limit. Raises ValueError for ``u`` or the bracket outside the energy shell.
    """
    from scipy.optimize import minimize_scalar

    spec = family_spec(label)
    u, E_guess = float(u), float(E_guess)
    w = 0.5 * abs(E_guess - spec.E_birth) if width is None else float(width)
    if not (w > 0 and math.isfinite(w)):
        raise ValueError(
            f"the bracket half-width must be > 0, got {w!r} (E_guess = E_n?)"
        )

    def d(p2: float) -> float:
        return periodicity_defect(spec.label, _with_p2(spec, u, p2))[0]

    lo, hi = (
        spec.problem.state(u, E_guess - w)[3],
        spec.problem.state(u, E_guess + w)[3],
    )
    res = minimize_scalar(
        d,
        bounds=(lo, hi),
        method="bounded",
        options={"xatol": xatol, "maxiter": maxiter},
    )
    p2 = float(res.x)
    x0 = _with_p2(spec, u, p2)
    edge = 1e-3 * (hi - lo) + 3 * (math.sqrt(np.finfo(float).eps) * abs(p2) + xatol)
    return PaperSearchResult(
        spec.label,
        u,
        p2,
        float(energy_alpha(np.array(x0))),
        int(res.nfev),  # evaluations of d
        periodicity_defect(spec.label, x0)[1],  # t*
        bool(min(p2 - lo, hi - p2) < edge),
    )


@dataclass(frozen=True)
class SearchComparison:
    """The paper's search and the symmetric shooting at the same amplitude ``u``.

    ``E_ref`` is the real128 root of the symmetric residual (~1e-30). For each search: the
    energy error against it, the real128 departure from periodicity of its float64 initial
    state, evaluations, integration time per evaluation (``t*`` for the paper, ``t1`` for the
    shooting) and wall time (warm integrators; informative only).
    """

    label: str
    u: float
    E_ref: float
    paper: PaperSearchResult
    paper_error: float
    paper_defect: float
    paper_span: float
    shooting_error: float
    shooting_defect: float
    shooting_evaluations: int
    shooting_span: float
    paper_seconds: float
    shooting_seconds: float


def default_amplitude(label: str, rel: float = 0.1) -> float:
    """A small amplitude near birth: ``rel sqrt|E_n - 4|`` (``a1`` start) or twice that (``p1``).

    Examples
    --------
    >>> from rotorlib.paper.search import default_amplitude
    >>> round(default_amplitude("IS^l_1"), 6)
    0.009701
    """
    spec = family_spec(label)
    if not rel > 0:
        raise ValueError(f"rel must be > 0, got {rel!r}")
    return rel * spec.u_scale * math.sqrt(spec.depth)


def _guess_E(spec: FamilySpec, u: float) -> float:
    """The fork law ``E_n + c u^2`` (``c`` from the seed): what both searches start from."""
    return spec.E_birth + float(seed(spec.label)[1]) * u * u


def _reference(label: str, u: float | None) -> tuple[FamilySpec, float, Any]:
    """``(spec, u, E_ref)``: the family, the amplitude (default :func:`default_amplitude`)
    and the real128 root of the symmetric residual there, the searches' reference."""
    spec = family_spec(label)
    u = default_amplitude(label) if u is None else float(u)
    return spec, u, birth_member(spec, u, REAL128)[0]


def _error(E: float, E_ref: Any) -> float:
    """``|E - E_ref|`` against the real128 root ``E_ref`` (a tier number, hence ``Any``),
    in 40 digits (the float64 ``E`` exactly)."""
    with mp.workdps(40):
        return float(abs(mp.mpf(repr(float(E))) - E_ref))


def compare_searches(
    label: str, u: float | None = None, xatol: float = 1e-16, tol: float | None = None
) -> SearchComparison:
    """:func:`paper_search` (bracket centred on the fork law, half-width ``c u^2 / 2``) and
    :func:`~rotorlib.paper.newborn.birth_member` (secant from ``E_n``) at the same ``u``, scored
    against real128. Float64 families only (``|E_n - 4| > 3e-8``)."""
    if family_spec(label).depth < Tier.separatrix_depth:
        raise ValueError(
            f"{family_spec(label).label}: compare_searches is float64 only "
            f"(|E_n - 4| > {Tier.separatrix_depth})"
        )
    spec, u, E_ref = _reference(label, u)
    t0 = time.perf_counter()
    ps = paper_search(label, u, _guess_E(spec, u), xatol=xatol)
    t1 = time.perf_counter()
    E_s, it = birth_member(spec, u, tol=tol)
    t2 = time.perf_counter()
    return SearchComparison(
        label=spec.label,
        u=u,
        E_ref=float(E_ref),
        paper=ps,
        paper_error=_error(ps.E, E_ref),
        paper_defect=periodicity_defect(label, _with_p2(spec, u, ps.p2), REAL128)[0],
        paper_span=ps.t_star,
        shooting_error=_error(E_s, E_ref),
        shooting_defect=periodicity_defect(
            label, spec.problem.state(u, float(E_s)), REAL128
        )[0],
        shooting_evaluations=it + 2,
        shooting_span=float(residual(spec.problem, u, float(E_s)).t1),
        paper_seconds=t1 - t0,
        shooting_seconds=t2 - t1,
    )


@dataclass(frozen=True)
class WorkPrecision:
    """Error against cost as the stopping tolerance is tightened (:func:`work_precision`):
    tolerances (``xatol`` in ``p2`` for the minimiser, relative step in ``E`` for the secant),
    evaluations, total integration time in units of the pendulum period at birth, and
    ``|E - E_ref|`` against real128."""

    label: str
    u: float
    tolerances_paper: np.ndarray
    tolerances_shooting: np.ndarray
    evaluations_paper: np.ndarray
    evaluations_shooting: np.ndarray
    integration_paper: np.ndarray
    integration_shooting: np.ndarray
    error_paper: np.ndarray
    error_shooting: np.ndarray


def work_precision(
    label: str,
    u: float | None = None,
    tolerances_paper: ArrayLike | None = None,
    tolerances_shooting: ArrayLike | None = None,
) -> WorkPrecision:
    """Both searches at a sequence of tolerances (default ``xatol = 1e-2 ... 1e-16``,
    ``tol = 1e-2 ... 1e-15``), scored against real128 (:class:`WorkPrecision`)."""
    spec, u, E_ref = _reference(label, u)
    tp = np.array(
        tolerances_paper
        if tolerances_paper is not None
        else [10.0**-k for k in range(2, 17)]
    )
    ts = np.array(
        tolerances_shooting
        if tolerances_shooting is not None
        else [10.0**-k for k in range(2, 16)]
    )
    if np.any(tp <= 0) or np.any(ts <= 0):
        raise ValueError("tolerances must be > 0")
    Eg, tau = _guess_E(spec, u), spec.period_birth
    paper = [paper_search(label, u, Eg, xatol=float(xa)) for xa in tp]
    shots = [birth_member(spec, u, tol=float(tl)) for tl in ts]  # (E, iterations)
    spans = [float(residual(spec.problem, u, float(E)).t1) for E, _ in shots]
    return WorkPrecision(
        spec.label,
        u,
        tp,
        ts,
        np.array([p.n_evaluations for p in paper]),
        np.array([it + 2 for _, it in shots]),
        np.array([p.n_evaluations * p.t_star / tau for p in paper]),
        np.array([(it + 2) * span / tau for (_, it), span in zip(shots, spans)]),
        np.array([_error(p.E, E_ref) for p in paper]),
        np.array([_error(E, E_ref) for E, _ in shots]),
    )


@dataclass(frozen=True)
class DefectLandscape:
    """The paper's ``d`` and the symmetric ``|r|`` (both float64) at ``p2(0) = p2* (1 + delta)``
    near a member (``p2*`` from the real128 root)."""

    label: str
    u: float
    delta: np.ndarray
    defect: np.ndarray
    residual: np.ndarray


def defect_landscape(
    label: str, u: float | None = None, delta: ArrayLike | None = None
) -> DefectLandscape:
    """:class:`DefectLandscape` for offsets ``delta`` (default ``10^-17 ... 10^-3``): both are
    linear in ``delta`` (``d`` a norm of three components vanishing together, ``r`` a simple
    root) down to their round-off floors."""
    spec, u, E_ref = _reference(label, u)
    delta = np.logspace(-17, -3, 57) if delta is None else np.asarray(delta, float)
    p2s = float(spec.problem.state(u, E_ref, REAL128)[3])
    x0s = [_with_p2(spec, u, p2s * (1 + dl)) for dl in delta]
    return DefectLandscape(
        spec.label,
        u,
        delta,
        defect=np.array([periodicity_defect(label, x0)[0] for x0 in x0s]),
        residual=np.array(
            [abs(residual(spec.problem, u, float(energy_alpha(x0))).r) for x0 in x0s]
        ),
    )


def residual_scan(label: str, E: float, n: int = 2001) -> tuple[np.ndarray, np.ndarray]:
    """``(u, r)``: the symmetric residual at energy ``E`` across the whole energy shell
    (float64; ``n`` points of ``(0, u_max)``, ``r = nan`` where the section is not reached).
    Every member at ``E`` keeps the family's symmetry, so a scan without a sign change shows
    there is none."""
    from scipy.optimize import brentq

    spec = family_spec(label)
    E = float(E)
    if not (E > 0 and math.isfinite(E)) or n < 3:
        raise ValueError(f"need E > 0 and n >= 3, got E = {E!r}, n = {n!r}")
    if spec.start == "p1":
        umax = 2.0 * math.sqrt(E)
    else:
        umax = (
            math.pi / 2
            if E >= 4.0
            else brentq(lambda a: float(potential_alpha(a, 0.0)) - E, 0.0, math.pi / 2)
        )
    u = np.linspace(0.0, umax, n + 1)[1:] * (1 - 1e-12)
    r = np.full(u.size, np.nan)
    for i, ui in enumerate(u):
        try:
            r[i] = residual(spec.problem, ui, E).r
        except (ValueError, SectionNotReached):
            pass
    return u, r
