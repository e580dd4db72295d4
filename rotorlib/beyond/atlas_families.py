"""The families of the atlas's orbits, their bifurcations, and the orbits born there.

:func:`families` follows orbits of a census (:mod:`rotorlib.beyond.atlas`) through a window of energy
with the engine (:func:`rotorlib.orbits.continuation.continuation`, pseudo-arclength, through folds),
with ``tr M`` of every member and its folds and crossings of ``tr M = 4`` (IS) and ``0`` (PD)
located: the paper's "new families born at bifurcations of the daughter trajectories".

:func:`daughters` switches branch at a located IS or PD point: the orbits born there (period
about the parent's at IS, twice it at PD) are found beside the parent at ``E = E_b -+ dE``.
A daughter orbit converges to the parent as ``dE -> 0``, so each of its points on a fixed set
tends to a point of the parent on a fixed set: the daughter meets the start set of the parent
near the parent's start, or the parent's target fixed set near the parent's symmetric point.
Both neighbourhoods are scanned (the census scan, ``atlas.symmetric_roots``, on a window of
the start set, the target point mapped onto its class's start set by the symmetry group)
for symmetric orbits of the daughter's period, refined and verified as in the census. The
daughters are atlas orbits: :func:`families` follows them in turn. A family is a
:class:`rotorlib.orbits.family.Branch`; :attr:`~rotorlib.orbits.family.Branch.stable_windows` reads its stable energies.

Precision: float64 (members to residual < 1e-8, folds to ~1e-15 in ``E``, IS/PD to ~1e-14
in the local parameter; daughters verified like census orbits, closure < 1e-9 |tr M|).
Scope: symmetric daughters (a daughter with no reversing symmetry is not seen by a scan of
fixed sets); a stable window narrower than the continuation step whose two ends lie between
the same two members is not seen either.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from concurrent.futures import Executor
from dataclasses import dataclass, replace
from fractions import Fraction

import numpy as np

from ..core.flow import SectionNotReached
from ..core.parallel import pmap
from ..core.system import lattice_reduce
from ..orbits.continuation import PALC, ContinuationOptions, continuation, member
from ..orbits.family import Branch
from ..orbits.periodic_orbit import PeriodicOrbit
from ..orbits.reversors import images, start_sets
from ..orbits.shooting import NoConvergence, residual, solve
from .atlas import (
    SAME_ORBIT,
    Atlas,
    atlas_orbit,
    distance_to_orbit,
    distinct_orbits,
    orbit_samples,
    symmetric_roots,
)

__all__ = ["families", "daughters", "Cascade", "cascade"]


def _family(args: tuple) -> Branch:
    o, lo, hi, step, du = args
    s = residual(o.extra["problem"], o.extra["u"], o.E)
    prob = replace(
        o.extra["problem"],
        label=o.family,
        factor=float(Fraction(o.period / float(s.t1)).limit_denominator(48)),
    )
    m0 = member(prob, o.extra["u"], o.E, traces=True)
    opts = ContinuationOptions(
        max_steps=600,
        E_range=(lo, hi),
        t_max=1.5 * o.period,
        jump=0.05,
        traces=True,
        folds=True,
    )
    if du is None:  # steps relative to E (E_ref = 0) and to u (floor 1)
        ds = step / max(hi, 1.0)
        alg = PALC(ds=ds, ds_max=ds, ds_min=1e-10, u_floor=1.0)
    else:
        alg = PALC(ds=1.0, ds_max=1.0, ds_min=1e-10, scales=(du, step))
    back, fwd = (
        continuation(prob, replace(alg, direction=d), opts, [m0]) for d in (-1, 1)
    )
    n = len(back.members)
    # the backward branch reversed: a fold stays at its member, an IS/PD point lies
    # after the member before it
    pts = sorted(
        [
            replace(p, index=n - 1 - p.index - (p.kind != "fold"))
            for p in back.special_points
        ]
        + [replace(p, index=n - 1 + p.index) for p in fwd.special_points],
        key=lambda p: p.position,
    )
    return Branch(
        prob,
        fwd.tier,
        back.members[::-1] + fwd.members[1:],
        tuple(p for p in pts if p.located and p.kind != "E"),
        f"{back.stop} / {fwd.stop}",
        f"backward: {back.reason}; forward: {fwd.reason}",
        (lo, hi),
    )


def families(
    orbits: Atlas | Sequence[PeriodicOrbit],
    E_range: tuple[float, float],
    step: float = 0.01,
    du: float | None = None,
    executor: Executor | None = None,
) -> list[Branch]:
    """Orbits of the atlas followed through ``E_range`` with the engine: pseudo-arclength
    continuation (:class:`rotorlib.orbits.continuation.PALC`, steps of at most ``step`` in ``E``)
    in both directions from each orbit until its family leaves the window, passing its folds,
    with ``tr M`` of every member and its folds and crossings of 4 and 0 located: the
    families of the atlas and their own bifurcations. One task per orbit through
    :func:`rotorlib.core.parallel.pmap`.

    Parameters
    ----------
    orbits : Atlas or sequence of PeriodicOrbit
        A census (:func:`rotorlib.beyond.atlas.census`), or orbits (e.g. :func:`daughters`).
    E_range : (float, float)
        The window; it must contain the energy of every orbit.
    step : float
        Largest step in ``E``.
    du : float, optional
        Largest step in the start parameter ``u`` (default: ``step / E`` relative to
        ``|u|``, at least ``step / E``); give it for a family that crosses a narrow window
        of energy with large changes of ``u`` (the generations of a cascade).

    Returns
    -------
    list of Branch
        One per orbit, in their order: the members in order along the family (through its
        folds: ``E`` need not be monotonic), the located folds (``E`` turns: a
        saddle-centre pair, or a pitchfork partner) and crossings of ``tr M = 4`` (``IS``)
        and ``0`` (``PD``); ``label`` is the orbit's family, ``problem.factor`` the
        period over the symmetric time, ``stop`` why each end stopped (``'backward /
        forward'``: ``E range``, ``period`` beyond 1.5 times the orbit's, ``steps``,
        ``stuck`` or ``section lost``).

    Precision: float64 members (residual < 1e-8); folds located to ~1e-15 in ``E``,
    ``IS``/``PD`` to ~1e-14 in the local parameter.
    """
    orbits = list(orbits.orbits if isinstance(orbits, Atlas) else orbits)
    lo, hi = (float(v) for v in E_range)
    if not (math.isfinite(lo) and math.isfinite(hi) and 0 < lo <= hi):
        raise ValueError(f"E_range must be finite with 0 < lo <= hi, got {E_range!r}")
    for o in orbits:
        if not lo <= o.E <= hi:
            raise ValueError(f"E_range must contain E = {o.E} (got {E_range!r})")
    for name, v in (("step", step), ("du", 1.0 if du is None else du)):
        if not (math.isfinite(v) and v > 0):
            raise ValueError(f"{name} must be finite and > 0, got {v!r}")
    return pmap(
        _family, [(o, lo, hi, float(step), du) for o in orbits], executor=executor
    )


# --------------------------------------------------------------------------- branch switching


def _locate(y, E, tol=1e-7):
    """``[(si, u)]``: the start sets on which an image of the state ``y`` (a point of a fixed
    set) lies, and its parameter there (nearest of 1440 samples, then bounded Brent on the
    distance, configuration modulo the lattice)."""
    from scipy.optimize import minimize_scalar

    ims = images(y)
    out = []
    for si, s in enumerate(start_sets(E)):
        us = np.linspace(*s.span(E), 1441)

        def dist(u, s=s):
            try:
                x = np.array(s.at(u, E), float)
            except ValueError:
                return math.inf
            return float(np.min(np.max(np.abs(lattice_reduce(x - ims)), axis=1)))

        ds = np.array([dist(u) for u in us])
        i = int(np.argmin(ds))
        if not ds[i] < 0.1:
            continue
        a, b = us[max(i - 1, 0)], us[min(i + 1, len(us) - 1)]
        res = minimize_scalar(
            dist, bounds=(a, b), method="bounded", options={"xatol": 1e-13}
        )
        if res.fun < tol:
            out.append((si, float(res.x)))
    return out


def _parent_at(fam: Branch, x, E):
    """The parent's start parameter at energy ``E`` near position ``x`` among the members
    (secant in ``u`` from the members' values, linear in ``E`` between them)."""
    i = min(max(int(math.floor(x)), 0), len(fam.members) - 2)
    (Ea, Eb), (ua, ub) = fam.E[i : i + 2], fam.u[i : i + 2]
    u0 = ua + (ub - ua) * (E - Ea) / (Eb - Ea) if Eb != Ea else ua
    return float(solve(fam.problem, u0, u0 + 1e-7 * max(1.0, abs(u0)), E=E).x)


def daughters(
    fam: Branch,
    point: int,
    dE: float = 1e-4,
    width: float = 0.05,
    grid: int = 40,
    executor: Executor | None = None,
) -> tuple:
    """Branch switching at the located ``IS`` or ``PD`` point ``fam.special_points[point]``:
    the symmetric orbits born there.

    At ``E = E_b - dE`` and ``E_b + dE`` (on whichever side the daughters exist), the
    parent is solved, its start and its symmetric point are mapped onto the start sets,
    and a window ``+- width`` around each is scanned (``grid`` points, bisected where the
    crossings change) for symmetric orbits whose period is the daughter's (the parent's at
    IS, twice it at PD, to ``10 |dT/dE| dE`` from the parent's slope, at least ``1e-5``
    relative) and that lie within ``width`` of the parent in phase space but are not the
    parent; of those the nearest to the parent are kept (a daughter tends to the parent as
    ``dE -> 0``; an orbit not born there does not). Each is refined and verified as in
    :func:`rotorlib.beyond.atlas.census` (images under the group count once).

    Parameters
    ----------
    fam : Branch
        A family of :func:`families`.
    point : int
        Index into ``fam.special_points`` (an ``IS`` or ``PD`` point).
    dE : float
        Distance in energy from the bifurcation (a pitchfork's daughters lie at
        ``~sqrt(dE)`` from the parent: keep ``dE`` small, but the daughter must be farther
        than ``SAME_ORBIT`` from it).
    width : float
        Half-width of the scanned windows in the start parameter.
    grid : int
        Start points per window.

    Returns
    -------
    tuple of PeriodicOrbit
        Sorted by ``E``, then period; label ``new``, family ``"<parent family>/<kind>"``.
    """
    marks = [(p.kind, p.E, p.position) for p in fam.special_points]
    if not (0 <= point < len(marks)) or marks[point][0] not in ("IS", "PD"):
        raise ValueError(
            f"point must index an IS or PD point of the family, got {point!r}"
        )
    if not (math.isfinite(dE) and 0 < dE < 0.1):
        raise ValueError(f"dE must be in (0, 0.1), got {dE!r}")
    if not (math.isfinite(width) and 0 < width <= 0.5):
        raise ValueError(f"width must be in (0, 0.5], got {width!r}")
    kind, Eb, x = marks[point]
    if kind == "IS" and any(
        k == "fold" and abs(E - Eb) < 1e-9 * max(1.0, Eb) for k, E, _ in marks
    ):
        raise ValueError(
            f"the IS point at E = {Eb:.9f} is a fold of the family (a saddle-centre pair: "
            f"its partner is the family's other branch, not a daughter)"
        )
    i = min(int(math.floor(x)), len(fam.members) - 2)
    (E0, E1), (T0, T1) = fam.E[i : i + 2], fam.period[i : i + 2]
    n = 2 if kind == "PD" else 1
    t_half = 1.03 * n * float(T0) / 2
    # the daughter's period leaves n T_parent at the rate of the parent's (10 times, margin)
    slope = abs((T1 - T0) / (E1 - E0)) if E1 != E0 else 0.0
    out = []
    for E in (Eb - dE, Eb + dE):
        try:
            u_p = _parent_at(fam, x, E)
        except (NoConvergence, SectionNotReached, ValueError):
            continue
        s = residual(fam.problem, u_p, E)
        T_p = float(fam.problem.factor * s.t1)
        parent, T_d = orbit_samples(s.x0, T_p), n * T_p
        # the parent's start on its own start set, and its symmetric point on others
        windows = [
            (k, u_p) for k, st in enumerate(start_sets(E)) if st == fam.problem.start
        ] + _locate(np.array(s.x1, float), E)
        found = [
            f
            for si, uc in windows
            for f in symmetric_roots(
                si, E, t_half, grid, (uc - width, uc + width), executor
            )
        ]
        near = []
        for f in found:
            if abs(f[5] - T_d) <= max(10 * n * slope * dE, 1e-5 * T_d):
                gap = distance_to_orbit(parent, f[4])
                if 10 * SAME_ORBIT < gap < width:  # not the parent
                    near.append((gap, f))
        # a daughter tends to the parent as dE -> 0, an orbit not born here does not: keep
        # the nearest (and any within twice its distance: the pair of a pitchfork), once
        gmin = min((g for g, _ in near), default=0.0)
        nearest = [f for g, f in sorted(near, key=lambda v: v[0]) if g < 2 * gmin]
        for f, fi in distinct_orbits((nearest, E, t_half, None)):
            if fi[5] <= max(1e6, 1e2 * abs(fi[3])) * 1e-15:  # closure: an orbit
                out.append(atlas_orbit("new", f"{fam.label}/{kind}", E, t_half, f, fi))
    return tuple(sorted(out, key=lambda o: (o.E, o.period)))


@dataclass(frozen=True)
class Cascade:
    """Generations of orbits born one from another (:func:`cascade`).

    Attributes
    ----------
    families : tuple of Branch
        The parent family, then each daughter's family (on the daughter's side of its birth).
    births : tuple of float
        The energy of each bifurcation: the starting point, then each daughter's PD point.
    periods : tuple of float
        Each generation's period at its birth.

    Examples
    --------
    >>> c = Cascade((), (5.51582, 5.51493, 5.514829), (9.45, 18.9))
    >>> [round(r, 2) for r in c.ratios]  # (E_1 - E_0) / (E_2 - E_1)
    [8.81]
    """

    families: tuple[Branch, ...]
    births: tuple[float, ...]
    periods: tuple[float, ...]

    @property
    def ratios(self) -> tuple[float, ...]:
        """``(E_n - E_{n-1}) / (E_{n+1} - E_n)`` of the bifurcation energies: Feigenbaum's
        ``delta`` in the limit (8.7210972... for area-preserving maps)."""
        E = self.births
        return tuple(
            (E[k] - E[k - 1]) / (E[k + 1] - E[k]) for k in range(1, len(E) - 1)
        )


def cascade(
    fam: Branch,
    point: int,
    generations: int = 3,
    executor: Executor | None = None,
) -> Cascade:
    """Follow a bifurcation cascade from ``fam.special_points[point]`` (IS or PD) of a
    family of :func:`families`: switch branch
    onto the stable daughter born there (:func:`daughters`), follow its family away from its
    birth (:func:`families`), locate its first PD point, and repeat ``generations`` times.

    Each generation's scale is the distance in ``E`` between its birth and the previous one
    (the first: the family's stable window beside the point); the daughter is sought at
    ``5 %`` of it beyond the birth, within ``10 sqrt(dE)`` of the parent's points on fixed
    sets, and its family is followed over 1.5 times it in steps of ``1 %`` (float64: the
    bifurcation energies to ~1e-13).

    Raises ValueError when no stable daughter is found or its family has no PD point.
    """
    if not (isinstance(generations, int) and 1 <= generations <= 6):
        raise ValueError(f"generations must be an integer in 1..6, got {generations!r}")
    Eb = fam.special_points[point].E
    near = [w for w in fam.stable_windows if w[0] - 1e-12 <= Eb <= w[1] + 1e-12]
    scale = max(w[1] - w[0] for w in near) if near else 1e-3
    fams, births, periods = [fam], [Eb], []
    for _ in range(generations):
        # the daughter lies ~sqrt(dE) from the parent (the last family): scan near it only
        dE = scale / 20
        born = daughters(
            fams[-1],
            point,
            dE=dE,
            width=min(0.05, 10 * math.sqrt(dE)),
            executor=executor,
        )
        d = next((o for o in born if o.stable), None)  # the first stable daughter
        if d is None:
            raise ValueError(f"no stable daughter born at E = {Eb:.12f}")
        periods.append(d.period)
        side = 1.0 if d.E > Eb else -1.0
        lo, hi = sorted((Eb, Eb + side * 1.5 * scale))
        (h,) = families([d], (lo, hi), step=scale / 100, du=0.01, executor=None)
        marks = [(p.kind, p.E) for p in h.special_points]
        pds = [
            (abs(E - Eb), i, E)
            for i, (k, E) in enumerate(marks)
            if k == "PD" and abs(E - Eb) > scale / 200
        ]
        if not pds:
            raise ValueError(f"the daughter born at E = {Eb:.12f} has no PD point")
        scale, point, Eb = min(pds)
        fams.append(h)
        births.append(Eb)
    return Cascade(tuple(fams), tuple(births), tuple(periods))
