"""Periodic orbits born at the isochronous (IS) and period-doubling (PD) bifurcations of pendula (paper §6-7).

Symmetry-reduced shooting
-------------------------
The potential is even in ``a1`` and in ``a2``, so the flow has the reversing
symmetries (time reversal combined with a reflection)

* ``R2 : (a1, a2, p1, p2) -> ( a1, -a2, -p1,  p2)``, fixed set ``{a2 = 0, p1 = 0}``;
* ``R12: (a1, a2, p1, p2) -> (-a1, -a2,  p1,  p2)``, fixed set ``{a1 = a2 = 0}``;
* ``T  : (a1, a2, p1, p2) -> ( a1,  a2, -p1, -p2)``, fixed set ``{p1 = p2 = 0}``;
* ``R1 : (a1, a2, p1, p2) -> (-a1,  a2,  p1, -p2)``, fixed set ``{a1 = 0, p2 = 0}``;

and, modulo the lattice, their images with ``a2 -> 2 pi - a2`` (fixed sets on
``a2 = pi``). An orbit leaving the fixed set of one reversing symmetry at
``t = 0`` and meeting the fixed set of another at ``t1`` is periodic, with
period ``2 t1`` when the product of the two is the identity on the torus and
``4 t1`` when it is a reflection. The pendulum's base point G
(``a1 = a2 = 0``, ``p1 = 0``) lies on both ``Fix R2`` and ``Fix R12``; the
transverse eigenvector of the bifurcation picks which one the newborn orbit
keeps: ``(1,0,0,0)`` (``a1(0) = u``, start ``a1``) or ``(0,1,0,0)``
(``p1(0) = u``, start ``p1``). ``p2(0) > 0`` follows from the energy. The
Lamé analysis of the transverse equation at the bifurcation (the
coefficient-map at the half period of the coefficient is
``[[Delta/2, 2 y2 y2'], [2 y1 y1', Delta/2]]``) then fixes where and how the
orbit meets the second fixed set:

========  ==========================  ========================  =========================
family    section (event)             condition                 period
========  ==========================  ========================  =========================
IS^l      ``p2 = 0`` (a2 turns)       ``p1 = 0`` or ``a1 = 0``  ``4 t1`` (= tau)
PD^l      ``a2 = 0`` going down       ``a1 = 0``                ``4 t1`` (= 2 tau)
IS^r      ``a2 = pi``                 same type as start        ``2 t1`` (= tau)
PD^r      ``a2 = pi``                 other type                ``4 t1`` (= 2 tau)
========  ==========================  ========================  =========================

For IS^l the condition is of the start's type when ``Delta = +2`` at the
bifurcation (``IS^l_{1,2,5,6}``) and of the other type when ``Delta = -2``
(``IS^l_{3,4,7,8}``). ``start_type`` is decided from the transition's
direction (§5.3) and checked in ``tests/test_newborn.py`` against the
linearised problem. The residual ``r(u) = x_end[condition] / u`` has the
trivial pendulum branch ``u = 0`` divided out, so a secant in the one
unknown ``u`` converges on the new family. One shot covers a quarter
(IS^l) or half (PD^l, rotation) of a pendulum period: the unstable stretch
near the saddle that amplifies round-off is halved or quartered.

Continuation in energy (no damping or unfolding term: the energy is fixed
exactly by ``p2(0)``): the first member is found at a small amplitude by a
secant in ``E`` (the paper's "adjust one quantity"), which measures the
fork-like law ``E - E_n ~ c u^2``; later members are predicted by
extrapolation in ``s = sqrt(|E - E_n|)`` and corrected by the secant in ``u``.

Precision
---------
float64 (heyoka Taylor, tol 2.2e-16) while ``|E_n - 4| > 3e-8``
(``IS^l_{1..6}``, ``PD^l_{1..3}``, ``IS^r_{1..4}``, ``PD^r_{1..4}``);
heyoka real128 (tol 1.9e-34, unknowns carried in mpmath) beyond
(``IS^l_{7,8}``, ``PD^l_4``, ``PD^r_{5,6}``). The exported float64 orbits close
to ~1e-9 or better under an independent integrator (tests).
"""
from __future__ import annotations

import functools
import math
import time
from dataclasses import dataclass

import mpmath as mp
import numpy as np

from . import flow
from .periodic import PeriodicOrbit
from .system import potential_alpha

__all__ = ["FamilySpec", "family_spec", "start_state", "shoot_residual", "newborn_orbit", "newborn_family",
           "solve_at_energy", "birth_member", "paper_search", "linear_orbit", "FAMILIES", "auto_precision",
           "family_range", "a1_structure", "trace_slope_at_birth"]

#: The families this module follows (paper Fig. 4-6 and Tables III-IV).
FAMILIES = tuple([f"IS^l_{n}" for n in range(1, 9)] + [f"PD^l_{n}" for n in range(1, 5)]
                 + [f"IS^r_{n}" for n in range(1, 5)] + [f"PD^r_{n}" for n in range(1, 7)])

#: float64 is used while |E_n - 4| exceeds this (../shared/NUMERICS.md: float64 fine to ~1e-8).
FLOAT64_LIMIT = 3e-8


@dataclass(frozen=True)
class FamilySpec:
    """How a family is searched.

    Attributes
    ----------
    label : str
        ``IS^l_2`` etc.
    kind, phase, n : str, str, int
    start : {'a1', 'p1'}
        The unknown: ``a1(0) = u`` (eigenvector (1,0,0,0)) or ``p1(0) = u`` ((0,1,0,0)).
    event : str
        Section of the second symmetric point (see :mod:`rotorlib.flow`).
    level : float
        Level of the ``a2`` section (0 or pi).
    end : {'a1', 'p1'}
        The component that vanishes there.
    factor : int
        Period = ``factor * t1``.
    E_birth, log_abs_dE_birth : float
        The bifurcation (from :mod:`rotorlib.bifurcations`).
    period_birth : float
        Pendulum period at the bifurcation (the newborn period there is
        this for IS, twice this for PD).
    transition : str
        Stability change of the pendulum with increasing E.
    """

    label: str
    kind: str
    phase: str
    n: int
    start: str
    event: str
    level: float
    end: str
    factor: int
    E_birth: float
    log_abs_dE_birth: float
    period_birth: float
    transition: str

    @property
    def lame_zeros(self) -> float:
        """Table III/IV: the number ``m`` of the Lamé function Ex^m (half-integer for PD^l)."""
        if self.phase == "lib":
            return (self.n + 1) // 2 + 1 if self.kind == "IS" else self.n + 0.5
        return (self.n + 1) // 2 if self.kind == "PD" else (self.n + 1) // 2 + 1


_OTHER = {"a1": "p1", "p1": "a1"}


@functools.lru_cache(maxsize=None)
def family_spec(label) -> FamilySpec:
    """The search recipe of a family, from its label (``IS^l_2``, ``ISl2``, ``PD^r_3``...)."""
    from .bifurcations import parse_label, transition

    kind, phase, n = parse_label(label)
    tr = transition(label)
    up = tr.transition.startswith("unstable")     # unstable -> stable with increasing E
    if phase == "lib":
        if kind == "IS":
            start = "p1" if up else "a1"
            plus = ((n + 1) // 2) % 2 == 1         # Delta = +2 for IS^l_{1,2,5,6}
            return FamilySpec(tr.label, kind, phase, n, start, "turn", 0.0, start if not plus else _OTHER[start],
                              4, tr.E, tr.log_abs_dE, tr.period, tr.transition)._fix_lib_is(plus)
        return FamilySpec(tr.label, kind, phase, n, "a1", "a2_down", 0.0, "a1", 4, tr.E, tr.log_abs_dE,
                          tr.period, tr.transition)
    start = "a1" if up else "p1"
    if kind == "IS":
        end = "p1" if start == "a1" else "a1"
        return FamilySpec(tr.label, kind, phase, n, start, "a2_up", math.pi, end, 2, tr.E, tr.log_abs_dE,
                          tr.period, tr.transition)
    end = start
    return FamilySpec(tr.label, kind, phase, n, start, "a2_up", math.pi, end, 4, tr.E, tr.log_abs_dE,
                      tr.period, tr.transition)


def _fix_lib_is(self, plus):
    # Delta = +2: y1'(h) = 0 (Ec, start a1 -> p1 = 0) or y2(h) = 0 (Es, start p1 -> a1 = 0);
    # Delta = -2: y1(h) = 0 (Ec, start a1 -> a1 = 0) or y2'(h) = 0 (Es, start p1 -> p1 = 0).
    end = _OTHER[self.start] if plus else self.start
    return FamilySpec(self.label, self.kind, self.phase, self.n, self.start, self.event, self.level, end,
                      self.factor, self.E_birth, self.log_abs_dE_birth, self.period_birth, self.transition)


FamilySpec._fix_lib_is = _fix_lib_is


def auto_precision(spec: FamilySpec) -> str:
    """``float64`` when ``|E_n - 4| > 0.05``, else ``real128``.

    The continuation runs in float64 while ``|E_n - 4| > 3e-8`` and the last
    member is polished in real128: the monodromy trace of a newborn orbit near
    E = 4 is far more sensitive to its initial state than the closure is
    (measured: IS^l_6 at E = 4, tr M = 7.6545 from the real128 state but 12.0
    from the same state rounded to float64).
    """
    return "float64" if abs(spec.E_birth - 4.0) > 0.05 else "real128"


def family_range(spec: FamilySpec) -> tuple:
    """``(E_min, E_max)`` accepted for the family: librational ``E_n <= E <= 4.05``, rotational ``E_n <= E <= E_n + 6``.

    Librational members continue past E = 4 only while ``a2`` still librates;
    the upper limit is a conservative bound checked by the continuation
    (which raises when ``a2`` stops turning).
    """
    if spec.phase == "lib":
        return spec.E_birth, 4.05
    return spec.E_birth, spec.E_birth + 6.0


# --------------------------------------------------------------------------- shooting

def _mpf(v):
    if isinstance(v, float):
        return mp.mpf(repr(v))
    return mp.mpf(v)


def start_state(spec: FamilySpec, u, E, precision="float64"):
    """Initial state on the starting symmetry line with unknown ``u`` at energy ``E``.

    ``a1(0) = u, a2 = p1 = 0`` or ``p1(0) = u, a1 = a2 = 0``; ``p2(0) > 0`` from the energy.
    Raises ValueError if ``u`` is beyond the energy shell.
    """
    if precision == "float64":
        u, E = float(u), float(E)
        if spec.start == "a1":
            kin = E - float(potential_alpha(u, 0.0))
            x = [u, 0.0, 0.0, None]
        else:
            kin = E - 0.25 * u * u
            x = [0.0, 0.0, u, None]
        if kin <= 0:
            raise ValueError(f"amplitude {u} is outside the energy shell E = {E}")
        x[3] = math.sqrt(4.0 * kin / 3.0)
        return x
    with mp.workdps(40):
        u, E = _mpf(u), _mpf(E)
        if spec.start == "a1":
            kin = E - (3 - mp.cos(2 * u) - 2 * mp.cos(u))
            x = [u, mp.mpf(0), mp.mpf(0), None]
        else:
            kin = E - u * u / 4
            x = [mp.mpf(0), mp.mpf(0), u, None]
        if kin <= 0:
            raise ValueError(f"amplitude {u} is outside the energy shell E = {E}")
        x[3] = mp.sqrt(4 * kin / 3)
        return x


def _level(spec, precision):
    if spec.level == 0.0:
        return 0.0
    return math.pi if precision == "float64" else mp.pi


def shoot(spec: FamilySpec, u, E, precision="float64"):
    """Integrate from the start line to the section; returns ``(t1, x(t1))``."""
    x0 = start_state(spec, u, E, precision)
    with mp.workdps(40):
        lev = _level(spec, precision)
        tmax = 4 * spec.period_birth + 200.0
        return flow.flow_to_event(x0, spec.event, lev, precision, t_max=tmax)


def shoot_residual(spec: FamilySpec, u, E, precision="float64"):
    """``r(u) = x_end(t1) / u``: zero on the new family (the pendulum ``u = 0`` divided out)."""
    _, x = shoot(spec, u, E, precision)
    k = 0 if spec.end == "a1" else 2
    if precision == "float64":
        return float(x[k]) / float(u)
    with mp.workdps(40):
        return x[k] / _mpf(u)


def _secant(f, x0, x1, tol, maxiter=40, prec="float64"):
    """Secant iteration; returns ``(root, iterations, |f(root)|)``.

    Stops when the step falls below ``tol * |x|`` or stops shrinking (the
    round-off floor of ``f``: near a fork the root is only determined to
    ~``noise(f) / f'``), returning the iterate with the smallest ``|f|``.
    """
    ctx = mp.workdps(40) if prec != "float64" else _Null()
    with ctx:
        if prec != "float64":
            x0, x1 = _mpf(x0), _mpf(x1)
        f0, f1 = f(x0), f(x1)
        best = (abs(f1), x1) if abs(f1) < abs(f0) else (abs(f0), x0)
        last_dx = None
        for it in range(maxiter):
            if f1 == f0:
                break
            x2 = x1 - f1 * (x1 - x0) / (f1 - f0)
            dx = abs(x2 - x1)
            x0, f0 = x1, f1
            x1 = x2
            f1 = f(x1)
            if abs(f1) < best[0]:
                best = (abs(f1), x1)
            if dx <= tol * abs(x1) or f1 == 0:
                return x1, it + 1, abs(f1)
            if last_dx is not None and it >= 3 and dx >= last_dx:
                break
            last_dx = dx
        return best[1], it + 1, best[0]


class _Null:
    def __enter__(self):
        return self

    def __exit__(self, *a):
        return False


def _tol(precision):
    return 4e-15 if precision == "float64" else mp.mpf("1e-31")


def solve_at_energy(spec: FamilySpec, E, u_guess, precision="float64"):
    """The family member at energy ``E``: secant in ``u`` from ``u_guess``. Returns ``(u, iterations)``."""
    f = functools.partial(_res_u, spec, E, precision)
    u1 = u_guess * (1 + 1e-4) if precision == "float64" else _mpf(u_guess) * (1 + mp.mpf("1e-4"))
    u, it, fr = _secant(f, u_guess, u1, _tol(precision), prec=precision)
    if not fr < (1e-8 if precision == "float64" else 1e-24) or not (abs(float(u)) > 0):
        raise ValueError(f"{spec.label}: the shooting did not converge at E = {float(E)!r}")
    return u, it


def _res_u(spec, E, precision, u):
    return shoot_residual(spec, u, E, precision)


def _res_E(spec, u, precision, E):
    return shoot_residual(spec, u, E, precision)


def birth_member(spec: FamilySpec, u, precision="float64"):
    """Paper §6 step 3 in one unknown: fix the amplitude ``u``, adjust the energy (i.e. ``p2(0)``).

    Returns ``(E, iterations)``; ``E - E_n ~ c u^2`` (fork-like).
    """
    f = functools.partial(_res_E, spec, u, precision)
    if precision == "float64":
        E0 = spec.E_birth
        E1 = E0 + 1e-3 * max(abs(E0 - 4.0), 1e-12) * (1 if spec.phase == "lib" else 1)
    else:
        E0 = _birth_mp(spec)
        E1 = E0 + mp.mpf(1e-3) * abs(E0 - 4)
    E, it, fr = _secant(f, E0, E1, 1e-15 if precision == "float64" else mp.mpf("1e-32"), prec=precision)
    return E, it


@functools.lru_cache(maxsize=None)
def _birth_mp(spec):
    """The bifurcation energy at ~30 digits (for the real128 search)."""
    from .bifurcations import transition

    tr = transition(spec.label, digits=30)
    with mp.workdps(40):
        x = mp.mpf(tr.log_abs_dE_str)
        return 4 - mp.exp(x) if spec.phase == "lib" else 4 + mp.exp(x)


def _u_scale(spec):
    # rough amplitude scale: transverse energy ~ a1^2 (a1 start) or p1^2/4 (p1 start)
    return 1.0 if spec.start == "a1" else 2.0


@functools.lru_cache(maxsize=64)
def _seed(label, precision):
    """First member near birth and the fork coefficient ``c`` in ``E - E_n = c u^2``."""
    spec = family_spec(label)
    d = abs(spec.E_birth - 4.0)
    u_s = 1e-2 * _u_scale(spec) * math.sqrt(d)
    E_s, _ = birth_member(spec, u_s, precision)
    En = spec.E_birth if precision == "float64" else _birth_mp(spec)
    with mp.workdps(40):
        c = (E_s - En) / (u_s * u_s) if precision == "float64" else (E_s - En) / _mpf(u_s) ** 2
    return u_s, E_s, c


def _solve_path(spec, E_target, precision, steps=None):
    """Continuation from the seed to ``E_target``; returns list of (E, u)."""
    u_s, E_s, c = _seed(spec.label, precision)
    if (float(c) > 0) != (float(E_target) > spec.E_birth):
        raise ValueError(f"{spec.label} exists only for E {'>' if float(c) > 0 else '<'} E_n = {spec.E_birth!r}")
    with mp.workdps(40):
        En = spec.E_birth if precision == "float64" else _birth_mp(spec)
        sq = (lambda v: math.sqrt(abs(v))) if precision == "float64" else (lambda v: mp.sqrt(abs(v)))
        s_s, s_t = sq(E_s - En), sq(_mpf(E_target) - En if precision != "float64" else E_target - En)
        if steps is None:
            steps = int(min(40, max(4, math.ceil(2 * math.log(float(s_t / s_s) + 1.0) + 6))))
        path = [(E_s, u_s)]
        sign = 1 if float(c) > 0 else -1
        targets = [s_s + (s_t - s_s) * i / steps for i in range(1, steps + 1)]
        halvings = 0
        while targets:
            s = targets[0]
            last = len(targets) == 1
            E = (E_target if precision == "float64" else _mpf(E_target)) if last else En + sign * s * s
            # predictor: u linear in s through the last two members (u ~ s / sqrt(c) at the first)
            if len(path) == 1:
                u_guess = u_s * s / s_s
            else:
                (E1, u1), (E2, u2) = path[-2], path[-1]
                s1, s2 = sq(E1 - En), sq(E2 - En)
                u_guess = u2 + (u2 - u1) * (s - s2) / (s2 - s1)
            try:
                u, _ = solve_at_energy(spec, E, u_guess, precision)
            except (ValueError, RuntimeError):
                if halvings >= 12:
                    raise ValueError(f"{spec.label}: the family continued from its birth at E_n = {spec.E_birth!r} "
                                     f"was not found beyond E = {float(path[-1][0])!r} (a fold in E, or a2 stops "
                                     f"reaching its section); asked for E = {float(E_target)!r}") from None
                halvings += 1
                s_prev = sq(path[-1][0] - En)
                targets.insert(0, (s_prev + s) / 2)     # adaptive: halve the step
                continue
            path.append((E, u))
            targets.pop(0)
    return path


def _make_orbit(spec, E, u, precision, extra):
    t1, x1 = shoot(spec, u, E, precision)
    x0 = start_state(spec, u, E, precision)
    with mp.workdps(40):
        T = spec.factor * t1
    M, xT, tr = flow.monodromy_matrix(x0, T, precision)
    from .monodromy import _unwind

    x0f = np.array([float(v) for v in x0])
    resid = float(np.max(np.abs(_unwind(xT - x0f))))
    from .system import energy_alpha

    a1m, a2m = flow.extrema(x0f, float(T), "float64")
    if spec.phase == "lib":
        eps = abs(float(E) - 4.0) if precision == "float64" else abs(_mpf(E) - 4)
    else:
        eps = abs(_mpf(E) - 4) if precision != "float64" else abs(float(E) - 4.0)
    log_dE = float(mp.log(eps)) if eps != 0 else float("nan")
    ex = dict(extra)
    ex.update({"u": float(u), "start": spec.start, "t1": float(t1), "section": spec.event,
               "condition": f"{spec.end} = 0", "phase": spec.phase})
    if precision != "float64":
        with mp.workdps(36):
            ex["state0_str"] = [mp.nstr(v, 32) for v in x0]
            ex["period_str"] = mp.nstr(T, 32)
            ex["trace_str"] = mp.nstr(tr, 25)
    return PeriodicOrbit(label=spec.label, E=float(E), period=float(T), state0=x0f, monodromy=M,
                         trace=float(tr), residual=resid, energy_residual=abs(float(energy_alpha(x0f)) - float(E)),
                         precision=precision, alpha1_max=a1m, alpha2_max=a2m, log_abs_dE=log_dE, extra=ex)


def _check_E(spec, E):
    lo, hi = family_range(spec)
    if not (lo <= float(E) <= hi):
        raise ValueError(f"{spec.label} exists for {lo!r} <= E <= {hi!r} (born at E_n = {lo!r}); got E = {float(E)!r}")


def newborn_orbit(label, E, precision=None, steps=None) -> PeriodicOrbit:
    """The member of the family born at ``label`` with energy ``E``.

    Parameters
    ----------
    label : str
        ``IS^l_2``, ``ISl2``, ``PD^r_3``, ``PDr3``, ...
    E : float or str
        Energy (a decimal string keeps all digits in real128).
    precision : {'float64', 'real128'}, optional
        Default :func:`auto_precision`.
    steps : int, optional
        Continuation steps from the seed (default from the distance to birth).

    Returns
    -------
    PeriodicOrbit
        ``state0`` on the starting symmetry line, ``trace`` from the
        variational equations over one period in the search precision.

    Raises
    ------
    ValueError
        Unknown label, or ``E`` outside the family's range (message names it).
    """
    spec = family_spec(label)
    _check_E(spec, E)
    prec = precision or auto_precision(spec)
    flow._check_precision(prec)
    t0 = time.perf_counter()
    if float(E) == spec.E_birth:
        raise ValueError(f"{spec.label}: E = E_n is the bifurcation itself (the new orbit is the pendulum there)")
    try:
        if prec == "float64" or abs(spec.E_birth - 4.0) > FLOAT64_LIMIT:
            path = _solve_path(spec, float(E), "float64", steps)
            E_f, u = path[-1]
            if prec == "real128":       # polish the float64 member in real128 at the same energy
                u, _ = solve_at_energy(spec, str(E), u, "real128")
                E_f = str(E)
        else:
            path = _solve_path(spec, str(E), prec, steps)
            E_f, u = path[-1]
    except RuntimeError as exc:
        raise ValueError(f"{spec.label}: no member found at E = {float(E)!r} ({exc})") from None
    return _make_orbit(spec, E_f, u, prec, {"steps": len(path) - 1, "seconds": time.perf_counter() - t0})


def newborn_family(label, E_end=None, n=12, precision=None):
    """Members from near birth to ``E_end`` (default 4 for libration, ``E_n + 0.05`` rotation), spaced in
    ``sqrt(E - E_n)``. Returns a list of :class:`PeriodicOrbit` (births first)."""
    spec = family_spec(label)
    prec = precision or auto_precision(spec)
    if E_end is None:
        E_end = 4.0 if spec.phase == "lib" else spec.E_birth + 0.05
    _check_E(spec, E_end)
    path = _solve_path(spec, E_end, prec, steps=n)
    return [_make_orbit(spec, E, u, prec, {}) for E, u in path]


# --------------------------------------------------------------------------- the paper's variant

def paper_search(label, u, E_guess, width=None, precision="float64"):
    """Paper §6 as written: fix the perturbation ``u`` along the transverse eigenvector, integrate
    until ``a2`` completes one (IS) or two (PD) cycles, and minimise the departure from periodicity

    ``d(p2(0)) = [(a1(t*) - a1(0))^2 + (p1(t*) - p1(0))^2 + (p2(t*) - p2(0))^2]^(1/2)``

    over ``p2(0)`` (Brent's bounded minimiser). Returns ``(E, d_min, n_evaluations)`` with ``E``
    the energy of the minimiser. Its accuracy is limited to ~sqrt(machine epsilon) relative in
    ``p2(0)`` (a minimum, not a root) and by the full-period instability.
    """
    from scipy.optimize import minimize_scalar

    spec = family_spec(label)
    cycles = 1 if spec.kind == "IS" else 2
    neval = [0]

    def d(p2):
        neval[0] += 1
        x0 = [u, 0.0, 0.0, p2] if spec.start == "a1" else [0.0, 0.0, u, p2]
        x = list(x0)
        if spec.phase == "lib":
            for _ in range(cycles):
                _, x = flow.flow_to_event(x, "turn", 0.0, precision)
                _, x = flow.flow_to_event(x, "a2_up", 0.0, precision, t_max=1e3)
        else:
            _, x = flow.flow_to_event(x0, "a2_up", 2 * math.pi * cycles, precision)
        return math.sqrt((x[0] - x0[0]) ** 2 + (x[2] - x0[2]) ** 2 + (x[3] - x0[3]) ** 2)

    def p2_of(E):
        return start_state(spec, u, E)[3]

    w = width or 1e-3 * max(abs(E_guess - spec.E_birth), 1e-12)
    lo, hi = p2_of(E_guess - w), p2_of(E_guess + w)
    res = minimize_scalar(d, bounds=(min(lo, hi), max(lo, hi)), method="bounded",
                          options={"xatol": 1e-16, "maxiter": 200})
    p2 = float(res.x)
    x0 = [u, 0.0, 0.0, p2] if spec.start == "a1" else [0.0, 0.0, u, p2]
    from .system import energy_alpha

    return float(energy_alpha(np.array(x0))), float(res.fun), neval[0]


# --------------------------------------------------------------------------- linearised (Lamé) orbit

def linear_orbit(label, x0, period, n=801):
    """The linearised orbit of Fig. 5: ``a2 = `` the pendulum at the bifurcation, ``a1`` from the
    transverse Lamé equation ``a1'' = -(2 + cos a2) a1`` with the same initial ``(a1, p1)``.

    Returns ``(t, a1, a2)`` on ``n`` points over ``[0, period]`` (scipy DOP853, rtol 1e-11).
    """
    from scipy.integrate import solve_ivp

    from .orbits import pendulum

    spec = family_spec(label)
    pend = pendulum(log_abs_dE=spec.log_abs_dE_birth, phase=spec.phase)
    t = np.linspace(0.0, float(period), n)

    def rhs(tt, y):
        a2 = pend.state(tt)[1]
        return [0.5 * y[1], -2.0 * (2.0 + math.cos(a2)) * y[0]]

    sol = solve_ivp(rhs, (0.0, float(period)), [float(x0[0]), float(x0[2])], method="DOP853", rtol=1e-11,
                    atol=1e-14, t_eval=t)
    a2 = np.array([pend.state(tt)[1] for tt in t])
    return t, sol.y[0], a2


# --------------------------------------------------------------------------- shape diagnostics (Tables III, IV)

def a1_structure(orbit: PeriodicOrbit, spec: FamilySpec = None, n=4000) -> dict:
    """Period of ``a1`` in units of the pendulum period at birth, and its nodes per orbit period.

    ``a1`` is sampled at ``n`` mid-points of one period (float64 heyoka); its
    period is the smallest of ``tau/2, tau, 2 tau`` (tau = the orbit's pendulum
    period: the orbit period for IS, half of it for PD) over which it repeats
    to 1e-6 of its amplitude. ``m`` is the Lamé count of Tables III/IV: the
    nodes of ``a1`` per orbit period divided by 2 (IS) or 4 (PD).
    """
    spec = spec or family_spec(orbit.label)
    tau = orbit.period / (2 if spec.kind == "PD" else 1)
    st, t = flow.sample(orbit.state0, orbit.period, n + 1)
    a1 = st[:, 0]
    mid = 0.5 * (a1[1:] + a1[:-1])
    nodes = int(np.sum(np.sign(mid[1:]) != np.sign(mid[:-1])) + (np.sign(mid[0]) != np.sign(mid[-1])))
    amp = np.max(np.abs(a1))
    per = None
    for frac in (0.5, 1.0, 2.0):
        x_shift = flow.flow_for(orbit.state0, frac * tau)
        if abs(x_shift[0] - orbit.state0[0]) < 1e-6 * amp and abs(x_shift[2] - orbit.state0[2]) < 1e-6 * 4 * amp:
            per = frac
            break
    m = nodes / (2 if spec.kind == "IS" else 4)
    return {"period_of_a1": per, "nodes": nodes, "m": m,
            "lame": ("Ec" if spec.start == "a1" else "Es")}


def trace_slope_at_birth(label, rel=(1e-3, 2e-3), precision=None):
    """``d tr M / dE`` of the new family at its birth, from two members at ``E_n + r |E_n - 4|``.

    Returns ``(slope_new, tr_at_birth_extrapolated)``.
    """
    spec = family_spec(label)
    d = abs(spec.E_birth - 4.0)
    Es = [spec.E_birth + r * d for r in rel]
    trs = [newborn_orbit(label, E, precision=precision).trace for E in Es]
    slope = (trs[1] - trs[0]) / (Es[1] - Es[0])
    return slope, trs[0] - slope * (Es[0] - spec.E_birth)
