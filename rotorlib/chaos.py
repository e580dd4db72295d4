"""An independent look at the band of global chaos 5.33 <= E <= 5.6 (paper §9).

The paper argues from the stability indices of known periodic orbits and cites
Poincaré sections of Ref. [gskhs-3rotor]. Here the band is examined directly:

* :func:`poincare_section` -- the section ``phi1 = 0 (mod 2 pi)``, ``phi1' > 0``,
  in the ``(phi2, P2)`` plane (relative variables of :mod:`rotorlib.system`).
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
``progress`` and go through :func:`rotorlib.parallel.pmap`.

Precision: FTLEs are statistical estimates; the integrator's own error (~1e-10
relative per unit time) is far below the finite-time spread (order 1/sqrt(T)
for chaotic orbits, ~log(T)/T for regular ones).
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from .energy import as_float
from .parallel import pmap
from .system import potential_alpha, potential_phi

__all__ = ["PoincareSection", "poincare_section", "sample_energy_shell", "ftle", "ChaoticFraction",
           "chaotic_fraction", "section_initial_conditions", "AmplitudeBranch", "newborn_amplitude_branch",
           "RotationalBandResult", "rotational_band",
           "DeepRotationalResult", "rotational_band_real128"]


def _check_E(E):
    E = as_float(E, "E")
    if E <= 0:
        raise ValueError(f"E must be > 0, got {E!r}")
    return E


# ----------------------------------------------------------------------------------------------
# Poincaré sections
# ----------------------------------------------------------------------------------------------

@functools.lru_cache(maxsize=None)
def _section_integrator():
    import heyoka as hy

    f1, f2, P1, P2 = hy.make_vars("f1", "f2", "P1", "P2")
    s12 = hy.sin(f1 + f2)
    sys = [(f1, 2.0 * P1 - P2), (f2, 2.0 * P2 - P1), (P1, -(hy.sin(f1) + s12)), (P2, -(hy.sin(f2) + s12))]
    hits = []

    def cb(ta, t, d_sgn):
        ta.update_d_output(t)
        x = ta.d_output.copy()
        if 2.0 * x[2] - x[3] > 0:
            hits.append(x)

    ev = hy.nt_event(hy.sin(0.5 * f1), cb)
    ta = hy.taylor_adaptive(sys, [0.0] * 4, nt_events=[ev], tol=1e-12)
    return ta, hits


def section_initial_conditions(E, n_phi=6, n_p=4, seed=None):
    """Initial conditions ``[phi1, phi2, P1, P2]`` on the section ``phi1 = 0`` at energy ``E``.

    A grid of ``n_phi`` values of ``phi2`` in ``(0, 2 pi)`` and ``n_p`` values of ``P2``
    strictly inside the allowed interval ``3 P2^2 <= 4 (E - V(0, phi2))``; points with
    ``V(0, phi2) >= E`` are dropped. ``seed``: jitter the grid randomly.
    """
    E = _check_E(E)
    rng = np.random.default_rng(seed)
    out = []
    for i in range(n_phi):
        f2 = 2 * np.pi * (i + 0.5 + (rng.uniform(-0.3, 0.3) if seed is not None else 0.0)) / n_phi
        K = E - potential_phi(0.0, f2)
        if K <= 0:
            continue
        pmax = math.sqrt(4 * K / 3)
        for j in range(n_p):
            P2 = pmax * (-1 + 2 * (j + 0.5) / n_p) * 0.95
            v = math.sqrt(max(4 * K - 3 * P2 * P2, 0.0))       # phi1' = 2 P1 - P2 > 0
            P1 = 0.5 * (v + P2)
            out.append([0.0, f2, P1, P2])
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
    h = np.array(hits[:n_hits]).reshape(-1, 4)
    hits.clear()
    return h


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
    phi2: list
    P2: list
    energy_error: float


def poincare_section(E, n_phi=6, n_p=4, n_hits=300, t_max=5e3, seed=None, executor=None, progress=False):
    """The section at energy ``E`` from a grid of initial conditions on it (see module docstring).

    Parameters
    ----------
    E : float
    n_phi, n_p : int
        Grid of initial conditions (:func:`section_initial_conditions`).
    n_hits : int
        Crossings recorded per initial condition (fewer if ``t_max`` is reached first).
    executor, progress
        Passed to :func:`rotorlib.parallel.pmap` (one task per initial condition).
    """
    E = _check_E(E)
    ics = section_initial_conditions(E, n_phi, n_p, seed)
    res = pmap(_section_one, [(x, int(n_hits), float(t_max)) for x in ics], executor=executor,
               progress=progress, desc=f"section E={E:g}")
    from .system import energy_phi

    err = max((float(np.max(np.abs(energy_phi(h) - E))) for h in res if len(h)), default=0.0)
    return PoincareSection(E, [np.mod(h[:, 1], 2 * np.pi) for h in res], [h[:, 3] for h in res], err)


# ----------------------------------------------------------------------------------------------
# the energy shell and finite-time Lyapunov exponents
# ----------------------------------------------------------------------------------------------

def sample_energy_shell(E, n, seed=0):
    """``n`` states ``[a1, a2, p1, p2]`` distributed microcanonically on ``H = E``.

    Configuration uniform on ``{V < E}`` in the fundamental domain ``[0, pi) x [0, 2 pi)``
    (rejection sampling), momentum direction uniform in the kinetic-ellipse angle.
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
    return np.stack([a1, a2, 2.0 * np.sqrt(K) * np.cos(th), 2.0 / math.sqrt(3.0) * np.sqrt(K) * np.sin(th)], -1)


@functools.lru_cache(maxsize=None)
def _tangent_integrator():
    import heyoka as hy

    a1, a2, p1, p2, d1, d2, e1, e2 = hy.make_vars("a1", "a2", "p1", "p2", "d1", "d2", "e1", "e2")
    cm, cp = hy.cos(a2 - a1), hy.cos(a1 + a2)
    sm, sp = hy.sin(a2 - a1), hy.sin(a1 + a2)
    v11 = 4.0 * hy.cos(2.0 * a1) + cm + cp
    v12 = cp - cm
    v22 = cm + cp
    sys = [(a1, 0.5 * p1), (a2, 1.5 * p2), (p1, -(2.0 * hy.sin(2.0 * a1) - sm + sp)), (p2, -(sm + sp)),
           (d1, 0.5 * e1), (d2, 1.5 * e2), (e1, -(v11 * d1 + v12 * d2)), (e2, -(v12 * d1 + v22 * d2))]
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


def ftle(states, T=200.0, renorm=5.0, executor=None, progress=False, chunk=50, seed=0):
    """Finite-time Lyapunov exponents of states ``[a1, a2, p1, p2]`` over time ``T``.

    One random unit tangent vector per state (Euclidean norm in ``[a1, a2, p1, p2]``),
    renormalised every ``renorm``; work is split in chunks of ``chunk`` states for ``pmap``.
    """
    states = np.atleast_2d(np.asarray(states, float))
    if T <= 0 or renorm <= 0:
        raise ValueError("T and renorm must be > 0")
    chunks = [(states[i:i + chunk], float(T), float(renorm), seed + i) for i in range(0, len(states), chunk)]
    res = pmap(_ftle_chunk, chunks, executor=executor, progress=progress, desc="FTLE")
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
    ftles: list


def chaotic_fraction(energies, N=200, T=200.0, threshold=0.05, renorm=5.0, seed=0, executor=None,
                     progress=False, chunk=50):
    """``f(E)``: fraction of ``N`` microcanonical points per energy with FTLE ``> threshold``."""
    energies = [_check_E(E) for E in np.atleast_1d(energies)]
    if not 0 < threshold:
        raise ValueError("threshold must be > 0")
    samples = [sample_energy_shell(E, N, seed=seed + 7919 * k) for k, E in enumerate(energies)]
    allx = np.concatenate(samples)
    lam = ftle(allx, T=T, renorm=renorm, executor=executor, progress=progress, chunk=chunk, seed=seed)
    per = np.split(lam, np.cumsum([len(s) for s in samples])[:-1])
    f = np.array([np.mean(x > threshold) for x in per])
    return ChaoticFraction(np.array(energies), f, np.sqrt(f * (1 - f) / N), np.array([np.median(x) for x in per]),
                           int(N), float(T), float(renorm), float(threshold), per)


# ----------------------------------------------------------------------------------------------
# newborn pendulum families followed in their amplitude (past folds in E)
# ----------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class AmplitudeBranch:
    """A newborn pendulum family followed in its shooting amplitude ``u``.

    Attributes
    ----------
    label : str
    u, E, trace, closure : ndarray
        Amplitude, energy, ``tr M`` (4x4 variational equations, heyoka float64) and
        closure of each member (``nan`` where no member was found).
    exit_E, exit_u : float
        Where ``tr M`` first leaves ``[0, 4]`` along the branch (``nan`` if it does not).
    exit_level : float
        0 or 4: which edge is crossed there.
    """

    label: str
    u: np.ndarray
    E: np.ndarray
    trace: np.ndarray
    closure: np.ndarray
    exit_E: float
    exit_u: float
    exit_level: float


def _member_at_u(nbm, spec, u, E_near, window):
    from scipy.optimize import brentq

    def f(x):
        return nbm.shoot_residual(spec, u, x)

    Es = np.linspace(E_near - window, E_near + window, 13)
    vals = []
    for x in Es:
        try:
            vals.append(f(x))
        except (ValueError, RuntimeError):
            vals.append(np.nan)
    roots = []
    for i in range(12):
        if np.isfinite(vals[i]) and np.isfinite(vals[i + 1]) and vals[i] * vals[i + 1] < 0:
            try:
                roots.append(brentq(f, Es[i], Es[i + 1], xtol=1e-13))
            except (ValueError, RuntimeError):      # the section is not reached inside the bracket
                pass
    if not roots:
        return None
    return min(roots, key=lambda r: abs(r - E_near))


def _member_trace(nbm, spec, u, E):
    from .monodromy import variational_monodromy

    t1, _ = nbm.shoot(spec, u, E)
    x0 = np.array(nbm.start_state(spec, u, E), float)
    v = variational_monodromy(x0, spec.factor * float(t1), method="heyoka")
    return v.trace, v.closure


def newborn_amplitude_branch(label, E_start, du_rel=0.03, n_max=30, window=0.03) -> AmplitudeBranch:
    """Follow a newborn pendulum family (``rotorlib.newborn``) in its amplitude ``u`` from the member
    at ``E_start`` until ``tr M`` leaves ``[0, 4]``; the exit is located by ``brentq`` in ``u``.

    At each ``u`` the energy is the root of ``rotorlib.newborn.shoot_residual`` nearest the previous
    one (bracketed on a 13-point grid of half-width ``window``), so the branch is followed through
    folds in ``E`` that a continuation in ``E`` cannot pass. Float64 only (for ``|E - 4| > 1e-3``).
    """
    from scipy.optimize import brentq

    from . import newborn as nbm

    spec = nbm.family_spec(label)
    o = nbm.newborn_orbit(label, E_start)
    us, Es, trs, cls = [o.extra["u"]], [o.E], [o.trace], [o.residual]
    exit_E = exit_u = exit_level = float("nan")
    for k in range(1, n_max + 1):
        u = us[0] * (1 + du_rel * k)
        E = _member_at_u(nbm, spec, u, Es[-1], window)
        if E is None:
            break
        tr, cl = _member_trace(nbm, spec, u, E)
        us.append(u), Es.append(E), trs.append(tr), cls.append(cl)
        if not 0.0 <= tr <= 4.0:
            lev = 4.0 if tr > 4.0 else 0.0
            E_prev = Es[-2]

            def g(x):
                Ex = _member_at_u(nbm, spec, x, E_prev, window)
                return _member_trace(nbm, spec, x, Ex)[0] - lev
            exit_u = brentq(g, us[-2], us[-1], xtol=1e-10)
            exit_E = _member_at_u(nbm, spec, exit_u, E_prev, window)
            exit_level = lev
            break
    return AmplitudeBranch(label, np.array(us), np.array(Es), np.array(trs), np.array(cls), float(exit_E),
                           float(exit_u), float(exit_level))


# ----------------------------------------------------------------------------------------------
# rotational newborn families followed in amplitude towards the band
# ----------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class RotationalBandResult:
    """A rotational newborn family followed in its amplitude towards the band (:func:`rotational_band`).

    Attributes
    ----------
    label : str
    profile : rotorlib.laws.BranchProfile
        ``E``, ``tr M``, ``t1`` ... along the branch.
    E_max : float
        Highest energy reached.
    reaches_band : bool
        Whether some member has ``E >= 5.33``.
    band_trace : ndarray
        ``tr M`` of the members inside ``5.33 <= E <= 5.6``.
    exit_E : float
        Where ``tr M`` first leaves ``[0, 4]`` (``nan`` if born outside it, or born closer than
        ``NOISY_BIRTH`` (1e-6) to E = 4, where float64 ``tr M`` is unreliable near birth).
    exit_level : float
    stays_unstable : bool
        Every member beyond the exit (or from birth) has ``tr M`` outside ``[0, 4]`` (for families born
        closer than ``NOISY_BIRTH`` (1e-6): every member with ``E - 4 > 1e-4``).
    """

    label: str
    profile: object
    E_max: float
    reaches_band: bool
    band_trace: np.ndarray
    exit_E: float
    exit_level: float
    stays_unstable: bool


BAND = (5.33, 5.6)

#: Families born closer than this to E = 4 (IS^r_3, IS^r_4) have float64 ``tr M`` dominated by round-off
#: near their birth (O(1) scatter measured within ~1e-6 of it), so their exit is not located.
NOISY_BIRTH = 1e-6


def _rotational_band_one(args):
    from . import laws

    label, dE_stop, max_steps = args
    b = laws.follow_rotational(label, dE_stop, h_max=0.3, max_steps=max_steps)
    prof = laws.branch_profile(b)
    if math.exp(laws._rot_spec(label).log_abs_dE_birth) > NOISY_BIRTH:
        dE, lev, stays = laws.rotational_exit(b, prof)
    else:       # float64 tr M is noise near birth: judge only members with E - 4 > 1e-4
        far = prof.dE > 1e-4
        dE, lev, stays = float("nan"), float("nan"), bool(np.all((prof.trace[far] < 0) | (prof.trace[far] > 4)))
    E = prof.E
    inb = (E >= BAND[0]) & (E <= BAND[1])
    return RotationalBandResult(label, prof, float(E.max()), bool(np.any(E >= BAND[0])), prof.trace[inb],
                                4.0 + dE, lev, stays)


def rotational_band(labels, dE_stop=1.7, max_steps=2000, executor=None, progress=False) -> list:
    """Follow rotational newborn families (``IS^r_n``, ``PD^r_n`` with float64 shooting, ``n <= 4``) in
    their amplitude (:func:`rotorlib.laws.follow_rotational`) until ``E - 4 >= dE_stop`` or the family
    ends, with ``tr M`` of every member (:func:`rotorlib.laws.branch_profile`) and the first exit from
    the stable window (:func:`rotorlib.laws.rotational_exit`). One task per family through
    :func:`rotorlib.parallel.pmap`.

    Precision: float64 members (shooting residual < 1e-6, typically 1e-9); ``tr M`` from the float64
    variational equations, meaningful in size and sign up to ``|tr M| ~ 1e12``; the exit energy to
    ~1e-10.
    """
    from . import laws

    labels = list(labels)
    for lab in labels:
        spec = laws._rot_spec(lab)
        if laws._rot_precision(spec, None) != "float64":
            raise ValueError(f"{spec.label} needs real128 shooting; rotational_band follows float64 families only")
    return pmap(_rotational_band_one, [(lab, float(dE_stop), int(max_steps)) for lab in labels], executor=executor,
                progress=progress, desc="rotational families")


# ----------------------------------------------------------------------------------------------
# rotational families born within 3e-8 of E = 4 (PD^r_5, PD^r_6): real128 throughout
# ----------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class DeepRotationalResult:
    """A rotational family born within 3e-8 of E = 4 followed in real128 towards the band
    (:func:`rotational_band_real128`).

    Attributes
    ----------
    label : str
    stability : rotorlib.laws.BranchStability
        ``E``, ``t1``, ``tr M`` (real128) and the float64 comparison at the members evaluated.
    E_max : float
        Highest energy reached.
    reaches_band : bool
        Whether some member has ``E >= 5.33``.
    band_trace : ndarray
        ``tr M`` of the members inside ``5.33 <= E <= 5.6``.
    exit_E, exit_level : float
        Where ``tr M`` first leaves ``[0, 4]`` and the level crossed (``nan`` if born outside).
    stays_unstable : bool
        Every member beyond the exit (or from birth) has ``tr M`` outside ``[0, 4]``.
    min_trace_after_exit : float
        Smallest ``tr M`` among the members beyond the exit (from birth if born outside).
    n_members : int
        Members of the branch (all solved in real128).
    seconds_follow, seconds_trace : float
        Wall time of the continuation and of the real128 ``tr M`` (with the exit bisection).
    stop : str
        Why the continuation ended.
    """

    label: str
    stability: object
    E_max: float
    reaches_band: bool
    band_trace: np.ndarray
    exit_E: float
    exit_level: float
    stays_unstable: bool
    min_trace_after_exit: float
    n_members: int
    seconds_follow: float
    seconds_trace: float
    stop: str


def _rotational_real128_one(args):
    import time

    from . import laws

    label, dE_stop, every, order, t1_jump, t1_grow, compare, max_steps = args
    t1_stop = None if t1_grow is None else laws._rot_spec(label).period_birth / 2 + t1_grow
    t0 = time.perf_counter()
    b = laws.follow_rotational(label, dE_stop, precision="real128", h_max=1.0, max_steps=max_steps, t1_jump=t1_jump,
                               order=order, t1_stop=t1_stop)
    t1 = time.perf_counter()
    s = laws.branch_stability(b, every=every, compare_float64=compare)
    t2 = time.perf_counter()
    E = s.E
    inb = (E >= BAND[0]) & (E <= BAND[1])
    out = (s.trace < 0) | (s.trace > 4)
    after = s.trace[int(np.argmax(out)):] if np.any(out) else np.array([])     # from the first member outside
    return DeepRotationalResult(label, s, float(4.0 + b.dE.max()), bool(np.any(4.0 + b.dE >= BAND[0])),
                                s.trace[inb], 4.0 + s.exit_dE, s.exit_level, s.stays_out,
                                float(after.min()) if len(after) else float("nan"), len(b.u), t1 - t0, t2 - t1,
                                b.stop)


def rotational_band_real128(labels, dE_stop=1.7, every=1, order=4, t1_jump=0.05, t1_grow=3.0,
                            compare_float64=False, max_steps=4000, executor=None, progress=False) -> list:
    """Follow rotational families born within 3e-8 of E = 4 (``PD^r_5``, ``PD^r_6``, ``IS^r_5`` ...) in
    their amplitude, in real128 throughout, until ``E - 4 >= dE_stop`` or the family ends, with real128
    ``tr M`` along the branch (:func:`rotorlib.laws.branch_stability`). One task per family through
    :func:`rotorlib.parallel.pmap`.

    Why real128 throughout: the shooting residual in float64 stays at its acceptance limit (~1e-6, the
    q-channel being ~``E_n - 4`` wide) and float64 ``tr M`` is round-off (wrong sign and size) at every
    member measured for PD^r_5 and PD^r_6 from birth to E - 4 = 0.01, while these families are already
    ``|tr M| > 1e9`` there; a float64 continuation resumed from real128 members jumps between families.
    The continuation uses a quartic predictor (``order``) and refuses steps that change ``t1`` by more
    than ``t1_jump`` (:func:`rotorlib.laws.follow_rotational`).

    Parameters
    ----------
    labels : list of str
    dE_stop : float
        Stop at ``E - 4 >= dE_stop`` (1.7 reaches past the band).
    every : int
        Evaluate ``tr M`` at every ``every``-th member (and the last).
    order, t1_jump : see :func:`rotorlib.laws.follow_rotational`.
    t1_grow : float or None
        Stop once ``t1`` exceeds its value at birth (half the pendulum period) by this much: the family is
        then ending on an orbit asymptotic to ``V = 4.5`` (``t1`` diverges logarithmically there and the
        steps shrink without end). ``None``: follow until the continuation sticks (minutes).
    compare_float64 : bool
        Also record float64 ``tr M``, closure and residual at the same members.
    max_steps : int
        Largest number of members (PD^r_6 needs ~2000 to ``t1_grow = 3``: the steps in ``log u`` shrink
        as ``u`` converges at the end).

    Notes
    -----
    Precision: Members: real128 shooting residual below ``max(1e-18, 1e-30 / (E_n - 4))`` (typically 1e-25).
    ``tr M``: real128 variational equations, ~``30 - log10|tr M|`` correct digits (full-period closure
    ~1e-30 near birth). The exit energy to ~1e-10 relative.
    """
    from . import laws

    labels = list(labels)
    for lab in labels:
        spec = laws._rot_spec(lab)
        if laws._rot_precision(spec, None) != "real128":
            raise ValueError(f"{spec.label} is a float64 family; use rotational_band")
    if not int(every) >= 1 or not int(order) >= 2:
        raise ValueError(f"need every >= 1 and order >= 2, got {every!r}, {order!r}")
    tasks = [(lab, float(dE_stop), int(every), int(order), float(t1_jump), None if t1_grow is None else float(t1_grow),
              bool(compare_float64), int(max_steps)) for lab in labels]
    return pmap(_rotational_real128_one, tasks, executor=executor, progress=progress, desc="rotational families")
