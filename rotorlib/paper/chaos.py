"""An independent look at the band of global chaos 5.33 <= E <= 5.6 (paper §9).

The paper argues from the stability indices of known periodic orbits and cites
Poincaré sections of Ref. [gskhs-3rotor]. Here the band is examined directly:

* :func:`poincare_section` -- the section ``phi1 = 0 (mod 2 pi)``, ``phi1' > 0``,
  in the ``(phi2, P2)`` plane (relative variables of :mod:`rotorlib.core.system`).
  Initial conditions are put on the section itself: ``phi1 = 0``, a grid of
  ``(phi2, P2)`` with ``3 P2^2 <= 4 (E - V(0, phi2))``, and
  ``phi1' = 2 P1 - P2 = +sqrt(4 (E - V) - 3 P2^2)``.
* :func:`sample_energy_shell` -- N points distributed with the microcanonical
  measure ``delta(E - H) dq dp``. With two degrees of freedom and a quadratic
  kinetic energy ``p^T A p`` the momentum integral ``int delta(K - p^T A p) d^2p
  = pi / sqrt(det A)`` does not depend on ``K = E - V``, so the configuration is
  uniform on ``{V < E}`` and the momentum direction is uniform in the angle of
  the kinetic-energy ellipse: ``p1 = 2 sqrt(K) cos th``, ``p2 = (2/sqrt 3) sqrt(K) sin th``
  in pendulum variables ``[a1, a2, p1, p2]`` (fundamental domain ``0 <= a1 < pi``,
  ``0 <= a2 < 2 pi``).
* :func:`ftle` -- the finite-time Lyapunov exponent of each point: the flow and
  one tangent vector (heyoka Taylor, float64, tolerance 1e-12), renormalised
  every ``renorm`` time units, ``lambda = sum(log growth) / T``.
* :func:`chaotic_fraction` -- the fraction of the shell with ``lambda > threshold``
  and its binomial standard error ``sqrt(f (1 - f) / N)``, as a function of E.

Sweeps take ``executor`` (any :class:`concurrent.futures.Executor`) and
``progress`` and go through :func:`rotorlib.core.parallel.pmap`.

Precision: FTLEs are statistical estimates; the integrator's own error (~1e-10
relative per unit time) is far below the finite-time spread (order 1/sqrt(T)
for chaotic orbits, ~log(T)/T for regular ones).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from concurrent.futures import Executor
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..core.energy import as_float
from ..core.flow import equations_of_motion
from ..core.parallel import pmap
from ..core.precision import Tier
from ..core.system import alpha_to_phi, energy_phi, potential_alpha, potential_phi
from ..orbits.continuation import (
    ContinuationOptions,
    FamilyEnd,
    Natural,
    continuation,
    member,
)
from ..orbits.family import Branch
from ..orbits.periodic_orbit import PeriodicOrbit
from ..orbits.reversors import images
from .newborn import family_spec, follow, newborn_orbit

__all__ = [
    "PoincareSection",
    "poincare_section",
    "sample_energy_shell",
    "ftle",
    "ChaoticFraction",
    "chaotic_fraction",
    "section_initial_conditions",
    "Island",
    "island",
    "BAND",
    "NOISY_BIRTH",
    "amplitude_branch",
    "FamilyInBand",
    "band_families",
]


def _check_E(E: float) -> float:
    E = as_float(E, "E")
    if E <= 0:
        raise ValueError(f"E must be > 0, got {E!r}")
    return E


# ----------------------------------------------------------------------------------------------
# Poincaré sections
# ----------------------------------------------------------------------------------------------


@functools.cache
def _section_integrator():
    from ..core.precision import load_heyoka

    hy = load_heyoka()

    f1, f2, P1, P2 = hy.make_vars("f1", "f2", "P1", "P2")
    s12 = hy.sin(f1 + f2)
    sys = [
        (f1, 2.0 * P1 - P2),
        (f2, 2.0 * P2 - P1),
        (P1, -(hy.sin(f1) + s12)),
        (P2, -(hy.sin(f2) + s12)),
    ]
    hits = []

    def cb(ta, t, d_sgn):
        ta.update_d_output(t)
        x = ta.d_output.copy()
        if 2.0 * x[2] - x[3] > 0:
            hits.append(x)

    ev = hy.nt_event(hy.sin(0.5 * f1), cb)
    ta = hy.taylor_adaptive(sys, [0.0] * 4, nt_events=[ev], tol=1e-12)
    return ta, hits


def section_initial_conditions(
    E: float, n_phi: int = 6, n_p: int = 4, seed: int | None = None
) -> np.ndarray:
    """Initial conditions ``[phi1, phi2, P1, P2]`` on the section ``phi1 = 0`` at energy ``E``.

    A grid of ``n_phi`` values of ``phi2`` in ``(0, 2 pi)`` and ``n_p`` values of ``P2``
    strictly inside the allowed interval ``3 P2^2 <= 4 (E - V(0, phi2))``; points with
    ``V(0, phi2) >= E`` are dropped. ``seed``: jitter the grid randomly.

    Examples
    --------
    >>> from rotorlib.paper.chaos import section_initial_conditions
    >>> section_initial_conditions(5.0, n_phi=2, n_p=2).round(5)[:2]
    array([[ 0.     ,  1.5708 ,  1.04918, -0.95   ],
           [ 0.     ,  1.5708 ,  1.99918,  0.95   ]])
    """
    E = _check_E(E)
    rng = np.random.default_rng(seed)
    out: list[list[float]] = []
    for i in range(n_phi):
        f2 = (
            2
            * np.pi
            * (i + 0.5 + (rng.uniform(-0.3, 0.3) if seed is not None else 0.0))
            / n_phi
        )
        K = E - potential_phi(0.0, f2)
        if K <= 0:
            continue
        P2 = math.sqrt(4 * K / 3) * (-1 + 2 * (np.arange(n_p) + 0.5) / n_p) * 0.95
        P1 = 0.5 * (np.sqrt(np.maximum(4 * K - 3 * P2 * P2, 0.0)) + P2)  # phi1' > 0
        out += [[0.0, f2, a, b] for a, b in zip(P1, P2)]
    return np.array(out)


def _section_one(args):
    x0, n_hits, t_max = args
    ta, hits = _section_integrator()
    hits.clear()
    ta.time = 0.0
    ta.state[:] = x0
    t = 0.0
    while len(hits) < n_hits and t < t_max:
        t += 50.0
        ta.propagate_until(t)
    return np.array(hits[:n_hits]).reshape(-1, 4)


def _crossings(
    state: ArrayLike, t_max: float, n_hits: int = 100_000
) -> tuple[np.ndarray, np.ndarray]:
    """The crossings of the section ``phi1 = 0 (mod 2 pi)``, ``phi1' > 0`` by the trajectory
    from ``state`` (``[phi1, phi2, P1, P2]``, relative variables) up to time ``t_max`` (rounded
    up to a multiple of 50): ``(phi2 mod 2 pi, P2)`` arrays. Float64 Taylor integration,
    tolerance 1e-12.
    """
    h = _section_one((np.asarray(state, float), int(n_hits), float(t_max)))
    return np.mod(h[:, 1], 2 * np.pi), h[:, 3]


@dataclass(frozen=True)
class PoincareSection:
    """Points of the section ``phi1 = 0 (mod 2 pi)``, ``phi1' > 0``.

    Attributes
    ----------
    E : float
    phi2 : list of ndarray
        ``phi2 mod 2 pi`` of the crossings, one array per initial condition.
    P2 : list of ndarray
        ``P2`` at the crossings.
    energy_error : float
        Largest ``|H - E|`` over all crossings (the integrator's drift).
    """

    E: float
    phi2: list[np.ndarray]
    P2: list[np.ndarray]
    energy_error: float


def poincare_section(
    E: float,
    n_phi: int = 6,
    n_p: int = 4,
    n_hits: int = 300,
    t_max: float = 5e3,
    seed: int | None = None,
    executor: Executor | None = None,
    progress: bool = False,
) -> PoincareSection:
    """The section at energy ``E`` from a grid of initial conditions on it (see module docstring).

    Parameters
    ----------
    E : float
    n_phi, n_p : int
        Grid of initial conditions (:func:`section_initial_conditions`).
    n_hits : int
        Crossings recorded per initial condition (fewer if ``t_max`` is reached first).
    executor, progress
        Passed to :func:`rotorlib.core.parallel.pmap` (one task per initial condition).
    """
    E = _check_E(E)
    res = pmap(
        _section_one,
        [
            (x, int(n_hits), float(t_max))
            for x in section_initial_conditions(E, n_phi, n_p, seed)
        ],
        executor=executor,
        progress=progress,
        desc=f"section E={E:g}",
    )
    err = max(
        (float(np.max(np.abs(energy_phi(h) - E))) for h in res if len(h)), default=0.0
    )
    return PoincareSection(
        E, [np.mod(h[:, 1], 2 * np.pi) for h in res], [h[:, 3] for h in res], err
    )


# ----------------------------------------------------------------------------------------------
# the energy shell and finite-time Lyapunov exponents
# ----------------------------------------------------------------------------------------------


def sample_energy_shell(E: float, n: int, seed: int | None = 0) -> np.ndarray:
    """``n`` states ``[a1, a2, p1, p2]`` distributed microcanonically on ``H = E``.

    Configuration uniform on ``{V < E}`` in the fundamental domain ``[0, pi) x [0, 2 pi)``
    (rejection sampling), momentum direction uniform in the kinetic-ellipse angle.

    Examples
    --------
    >>> import numpy as np
    >>> from rotorlib.paper.chaos import sample_energy_shell
    >>> from rotorlib.core.system import energy_alpha
    >>> x = sample_energy_shell(5.0, 100, seed=1)
    >>> x.shape, bool(np.allclose(energy_alpha(x), 5.0, atol=1e-12))
    ((100, 4), True)
    """
    E = _check_E(E)
    n = int(n)
    if n < 1:
        raise ValueError(f"n must be >= 1, got {n}")
    rng = np.random.default_rng(seed)
    pts = np.empty((0, 2))
    while len(pts) < n:
        q = rng.uniform([0.0, 0.0], [np.pi, 2 * np.pi], size=(2 * n + 16, 2))
        pts = np.vstack([pts, q[potential_alpha(q[:, 0], q[:, 1]) < E]])
    a1, a2 = pts[:n, 0], pts[:n, 1]
    K = E - potential_alpha(a1, a2)
    th = rng.uniform(0.0, 2 * np.pi, n)
    return np.stack(
        [
            a1,
            a2,
            2.0 * np.sqrt(K) * np.cos(th),
            2.0 / math.sqrt(3.0) * np.sqrt(K) * np.sin(th),
        ],
        -1,
    )


@functools.cache
def _tangent_integrator():
    from ..core.precision import load_heyoka

    hy = load_heyoka()

    a1, a2, p1, p2, d1, d2, e1, e2 = hy.make_vars(
        "a1", "a2", "p1", "p2", "d1", "d2", "e1", "e2"
    )
    cm, cp = hy.cos(a2 - a1), hy.cos(a1 + a2)
    v11 = 4.0 * hy.cos(2.0 * a1) + cm + cp
    v12 = cp - cm
    v22 = cm + cp
    sys = equations_of_motion(hy) + [
        (d1, 0.5 * e1),
        (d2, 1.5 * e2),
        (e1, -(v11 * d1 + v12 * d2)),
        (e2, -(v12 * d1 + v22 * d2)),
    ]
    return hy.taylor_adaptive(sys, [0.0] * 8, tol=1e-12)


def _ftle_chunk(args):
    states, T, renorm, seed = args
    ta = _tangent_integrator()
    rng = np.random.default_rng(seed)
    out = np.empty(len(states))
    n_seg = max(1, int(round(T / renorm)))
    dt = T / n_seg
    for i, x in enumerate(states):
        v = rng.normal(size=4)
        v /= np.linalg.norm(v)
        ta.time = 0.0
        ta.state[:] = np.concatenate([x, v])
        acc = 0.0
        for k in range(n_seg):
            ta.propagate_until((k + 1) * dt)
            nv = np.linalg.norm(ta.state[4:])
            acc += math.log(nv)
            ta.state[4:] /= nv
        out[i] = acc / T
    return out


def ftle(
    states: ArrayLike,
    T: float = 200.0,
    renorm: float = 5.0,
    executor: Executor | None = None,
    progress: bool = False,
    chunk: int = 50,
    seed: int = 0,
) -> np.ndarray:
    """Finite-time Lyapunov exponents of states ``[a1, a2, p1, p2]`` over time ``T``.

    One random unit tangent vector per state (Euclidean norm in ``[a1, a2, p1, p2]``),
    renormalised every ``renorm``; work is split in chunks of ``chunk`` states for ``pmap``.
    """
    states = np.atleast_2d(np.asarray(states, float))
    if T <= 0 or renorm <= 0:
        raise ValueError("T and renorm must be > 0")
    res = pmap(
        _ftle_chunk,
        [
            (states[i : i + chunk], float(T), float(renorm), seed + i)
            for i in range(0, len(states), chunk)
        ],
        executor=executor,
        progress=progress,
        desc="FTLE",
    )
    return np.concatenate(res) if res else np.empty(0)


@dataclass(frozen=True)
class ChaoticFraction:
    """Fraction of the energy shell with FTLE above a threshold.

    Attributes
    ----------
    E : ndarray
    fraction, stderr : ndarray
        ``f`` and its binomial standard error ``sqrt(f (1 - f) / N)``.
    median_ftle : ndarray
    N : int
    T, renorm, threshold : float
    ftles : list of ndarray
        All exponents, per energy.
    """

    E: np.ndarray
    fraction: np.ndarray
    stderr: np.ndarray
    median_ftle: np.ndarray
    N: int
    T: float
    renorm: float
    threshold: float
    ftles: list[np.ndarray]


def chaotic_fraction(
    energies: ArrayLike,
    N: int = 200,
    T: float = 200.0,
    threshold: float = 0.05,
    renorm: float = 5.0,
    seed: int = 0,
    executor: Executor | None = None,
    progress: bool = False,
    chunk: int = 50,
) -> ChaoticFraction:
    """``f(E)``: fraction of ``N`` microcanonical points per energy with FTLE ``> threshold``."""
    energies = [_check_E(E) for E in np.atleast_1d(energies)]
    if not 0 < threshold:
        raise ValueError("threshold must be > 0")
    samples = [
        sample_energy_shell(E, N, seed=seed + 7919 * k) for k, E in enumerate(energies)
    ]
    lam = ftle(
        np.concatenate(samples),
        T=T,
        renorm=renorm,
        executor=executor,
        progress=progress,
        chunk=chunk,
        seed=seed,
    )
    per = np.split(lam, np.cumsum([len(s) for s in samples])[:-1])
    f = np.array([np.mean(x > threshold) for x in per])
    return ChaoticFraction(
        np.array(energies),
        f,
        np.sqrt(f * (1 - f) / N),
        np.array([np.median(x) for x in per]),
        int(N),
        float(T),
        float(renorm),
        float(threshold),
        per,
    )


# ----------------------------------------------------------------------------------------------
# newborn families followed towards the band (the engine, rotorlib.orbits.continuation)
# ----------------------------------------------------------------------------------------------

#: The band of global chaos quoted by the paper (its edges, in units of g).
BAND = (5.33, 5.6)

#: Families born closer than this to E = 4 (IS^r_3, IS^r_4) have float64 ``tr M`` dominated by
#: round-off near their birth (O(1) scatter measured within ~1e-6 of it): their exit is not
#: located and their stability is judged only where ``E - 4 > 1e-4``.
NOISY_BIRTH = 1e-6


def amplitude_branch(
    label: str, E_start: float, du_rel: float = 0.03, n_max: int = 30
) -> Branch:
    """A newborn family stepped in its amplitude from the member at ``E_start``:
    ``u_k = u_0 (1 + du_rel k)`` (natural continuation, the energy solved at each ``u``, so
    folds in ``E`` are passed), with ``tr M`` of every member, until ``tr M`` leaves
    ``[0, 4]`` (the crossing is then an ``IS``/``PD`` point of the branch). Float64 (for
    ``|E - 4| > 1e-3``). Returns a :class:`rotorlib.orbits.continuation.Branch`."""
    spec = family_spec(label)
    o = newborn_orbit(label, E_start, digits=15)
    m0 = member(spec.problem, o.extra["u"], o.E, traces=True)
    us = tuple(m0.u * (1 + du_rel * k) for k in range(1, n_max + 1))
    opts = ContinuationOptions(traces=True, folds=False, stop_on=("IS", "PD"))
    try:
        return continuation(spec.problem, Natural("u", us, order=1), opts, [m0])
    except FamilyEnd as end:  # the family ends before any exit
        return continuation(spec.problem, Natural("u", ()), opts, end.members)


@dataclass(frozen=True)
class FamilyInBand:
    """A newborn family followed towards the band (:func:`band_families`).

    Attributes
    ----------
    label : str
    branch : rotorlib.orbits.continuation.Branch
        Members (``E``, ``u``, ``t1``, ``trace``) and special points (``IS``/``PD``: tr M = 4/0).
    E_max : float
        Highest energy reached (the located fold when there is one).
    reaches_band : bool
        Whether some member has ``E >= 5.33``.
    band_trace : ndarray
        ``tr M`` of the members inside ``5.33 <= E <= 5.6``.
    exit_E, exit_level : float
        Where ``tr M`` first leaves ``[0, 4]`` and the level crossed (``nan`` when born
        outside the window, or born closer than :data:`NOISY_BIRTH` in float64).
    stays_unstable : bool
        Every member beyond the exit (or from birth) has ``tr M`` outside ``[0, 4]``.
    min_trace_after_exit : float
    """

    label: str
    branch: Branch
    E_max: float
    reaches_band: bool
    band_trace: np.ndarray
    exit_E: float
    exit_level: float
    stays_unstable: bool
    min_trace_after_exit: float


def _band_one(args):
    label, dE_stop, digits, t_grow, energies = args
    spec = family_spec(label)
    # the period may grow by t_grow beyond the orbit's period at birth
    t_max = None if t_grow is None else spec.factor * spec.period_birth / 2 + t_grow
    b = follow(
        label,
        chart="K",
        E_range=(None, 4 + dE_stop),
        digits=digits,
        traces=True,
        jump=0.05 if spec.depth < Tier.separatrix_depth else None,
        t_max=t_max,
        energies=energies,
        clip=False,  # the first member beyond E_max is reported (chapter 08)
    )
    E, tr = b.E, b.trace
    out = (tr < 0) | (tr > 4)
    exit_E = lev = float("nan")
    # float64 tr M is noise near a birth closer than NOISY_BIRTH: judge E - 4 > 1e-4 only
    if not b.tier.extended and spec.depth < NOISY_BIRTH:
        far = E - 4 > 1e-4
        stays, after = bool(np.all(out[far])), tr[far]
    elif out[0]:
        stays, after = bool(np.all(out)), tr
    else:
        pts = [p for p in b.special_points if p.kind in ("IS", "PD")]
        k = int(np.argmax(out)) if np.any(out) else len(out)  # the first one outside
        stays, after = bool(k < len(out) and np.all(out[k:])), tr[k:]
        if pts:
            exit_E, lev = float(pts[0].member.E), 4.0 if pts[0].kind == "IS" else 0.0
    return FamilyInBand(
        spec.label,
        b,
        float(b.E_max),
        bool(np.any(E >= BAND[0])),
        tr[(E >= BAND[0]) & (E <= BAND[1])],
        exit_E,
        lev,
        stays,
        float(after.min()) if len(after) else float("nan"),
    )


def band_families(
    labels: Sequence[str],
    dE_stop: float = 1.7,
    digits: int | Tier | None = None,
    t_grow: float | None = None,
    energies: Sequence[float | str] = (),
    executor: Executor | None = None,
    progress: bool = False,
) -> list[FamilyInBand]:
    """Follow newborn families (``IS^r_n``, ``PD^r_n``) with the engine from birth until
    ``E - 4 >= dE_stop`` or the family ends, with ``tr M`` of every member and the first exit
    from the stable window. One task per family through :func:`rotorlib.core.parallel.pmap`.

    ``digits``: the continuation's tier (default float64 while ``|E_n - 4| > 3e-8``, real128
    beyond: at PD^r_5,6 float64 ``tr M`` has the wrong size or sign at every member measured).
    ``energies``: members located at these energies (special points of kind ``E``).
    ``t_grow``: also stop once the period exceeds its value at birth by this much (the
    families end on orbits asymptotic to ``V = 4.5``, where the period diverges).

    Precision: float64 members to ``|r| < 1e-6`` (typically 1e-9), ``tr M`` meaningful in
    size and sign up to ``|tr M| ~ 1e12``; real128 members to ``max(eps^(2/3), 1e4 eps / d)``
    with ``~30 - log10|tr M|`` correct digits of ``tr M``; exits to ~1e-12 relative.
    """
    labels = list(labels)
    for lab in labels:
        if family_spec(lab).phase != "rot":
            raise ValueError(
                f"{lab}: band_families follows rotational families (IS^r_n, PD^r_n)"
            )
    return pmap(
        _band_one,
        [(lab, float(dE_stop), digits, t_grow, tuple(energies)) for lab in labels],
        executor=executor,
        progress=progress,
        desc="families",
    )


@dataclass(frozen=True)
class Island:
    """Whether an orbit sits in an island of the Poincaré section (:func:`island`).

    Attributes
    ----------
    orbit : rotorlib.orbits.periodic_orbit.PeriodicOrbit
    phi2, P2 : ndarray
        The crossings of the section by one image of the orbit in one period.
    test_phi2, test_P2 : ndarray
        The crossings by the test trajectory started ``delta`` away.
    delta : float
    spread : float
        Largest distance of a test crossing from the nearest crossing of the orbit, in
        units of ``delta``: of order 1 on an invariant curve around an elliptic orbit, of
        order ``1/delta`` where the test trajectory leaves (a hyperbolic orbit).
    """

    orbit: PeriodicOrbit
    phi2: np.ndarray
    P2: np.ndarray
    test_phi2: np.ndarray
    test_P2: np.ndarray
    delta: float
    spread: float


def island(
    orbit: PeriodicOrbit, delta: float = 0.01, t_max: float = 2000.0, n_hits: int = 400
) -> Island:
    """The orbit seen in the Poincaré section of :func:`rotorlib.paper.chaos.poincare_section`
    (``phi1 = 0``, ``phi1' > 0``): of its 24 images, the crossing with the largest
    ``phi1'`` (the most transversal) is moved by ``delta`` in ``phi2`` (``P2`` kept, ``P1``
    from the energy) and followed for ``t_max`` (at most ``n_hits`` crossings). Raises
    ValueError when no image crosses the section. Float64 (tolerance 1e-12).
    """
    if not (math.isfinite(delta) and 0 < delta < 0.5):
        raise ValueError(f"delta must be in (0, 0.5), got {delta!r}")
    if not (math.isfinite(t_max) and t_max > 0):
        raise ValueError(f"t_max must be finite and > 0, got {t_max!r}")
    E = orbit.E

    def speed2(f2: float, P2: float) -> float:  # (phi1')^2 on the section
        return float(4 * (E - potential_phi(0.0, f2)) - 3 * P2 * P2)

    crossings = []  # (phi1'^2, phi2, P2, the image's crossings in one turn)
    for y in images(orbit.state0):
        ph, P = _crossings(alpha_to_phi(y), orbit.period)
        back = np.flatnonzero(
            np.hypot((ph - ph[:1] + np.pi) % (2 * np.pi) - np.pi, P - P[:1]) < 1e-6
        )
        if len(back) > 1:  # integrated past one period: keep one turn
            ph, P = ph[: back[1]], P[: back[1]]
        crossings += [(speed2(f2, P2), f2, P2, ph, P) for f2, P2 in zip(ph, P)]
    if not crossings:
        raise ValueError(
            f"no image of the orbit T = {orbit.period:.6f} crosses phi1 = 0"
        )
    _, f2, P2, ph, P = max(crossings, key=lambda c: c[0])  # the first of the largest
    g = f2 + delta
    w = speed2(g, P2)
    if w <= 0:
        raise ValueError(
            "the test point falls outside the section; use a smaller delta"
        )
    qh, qP = _crossings([0.0, g, 0.5 * (math.sqrt(w) + P2), P2], t_max, n_hits)
    # the distance of each test crossing from the nearest crossing of the orbit
    spread = max(
        np.min(np.hypot((a - ph + np.pi) % (2 * np.pi) - np.pi, b - P))
        for a, b in zip(qh, qP)
    )
    return Island(orbit, ph, P, qh, qP, float(delta), float(spread) / delta)
