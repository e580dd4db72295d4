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
Where that stops (a fold in ``E``, or a stretch where ``t1`` varies steeply
with ``u``) :func:`continue_in_amplitude` follows ``r(u, E) = 0`` by
pseudo-arclength continuation in the plane ``(u, E)``; it measured where each
family ends or folds (:data:`FAMILY_REACH`, the range :func:`newborn_orbit`
accepts).

The paper's own search (§6 step 3: minimise the full-period departure from
periodicity over ``p2(0)``) is :func:`paper_search`; :func:`compare_searches`
and :func:`work_precision` score it against the symmetric shooting (chapter
``book/04_search.ipynb``): as a minimisation it is limited to ~sqrt(eps).

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
           "family_range", "a1_structure", "trace_slope_at_birth", "PaperSearchResult", "periodicity_defect",
           "FAMILY_REACH", "range_message", "SearchComparison", "compare_searches", "default_amplitude",
           "WorkPrecision", "work_precision", "DefectLandscape", "defect_landscape", "residual_scan",
           "AmplitudeContinuation", "continue_in_amplitude"]

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


#: Where each family was followed to, measured (``tests/test_newborn.py`` re-measures some):
#: ``label -> (E_upper, how)``. Float64 families: :func:`continue_in_amplitude` from birth,
#: ``E_upper`` = the largest energy on the branch (rounded down at 1e-7), ``how`` says why it ends
#: there: ``'fold'`` (the branch turns back to lower energies: no member above ``E_upper``),
#: ``'E = 4.5'`` (:func:`newborn_orbit` was checked up to ``E_upper``; continued further in amplitude the
#: branch runs towards ``E = 4.5``, the maxima of ``V``, with a growing period) or ``'followed'``
#: (checked up to there; the family may go on). "Checked": :func:`newborn_orbit` converges with closure
#: < 1e-9 on a ladder of energies up to ``E_upper``. Extended-precision families: the energies at which
#: :func:`newborn_orbit` was run and checked (``E = 4`` for libration, ``E_n + 1000 |E_n - 4|`` rotation).
FAMILY_REACH = {
    "IS^l_1": (4.4999101, "E = 4.5"), "IS^l_2": (4.48, "E = 4.5"), "IS^l_3": (5.4889383, "fold"),
    "IS^l_4": (4.49, "E = 4.5"), "IS^l_5": (4.0016721, "followed"), "IS^l_6": (4.0012564, "followed"),
    "IS^l_7": (4.0, "followed"), "IS^l_8": (4.0, "followed"),
    "PD^l_1": (4.45, "E = 4.5"), "PD^l_2": (4.4870156, "E = 4.5"), "PD^l_3": (4.45, "E = 4.5"),
    "PD^l_4": (4.0, "followed"),
    "IS^r_1": (4.49, "E = 4.5"), "IS^r_2": (4.4980101, "E = 4.5"), "IS^r_3": (4.0034066, "followed"),
    "IS^r_4": (4.02, "followed"),
    "PD^r_1": (5.9831001, "fold"), "PD^r_2": (4.5516743, "fold"), "PD^r_3": (4.4681256, "E = 4.5"),
    "PD^r_4": (4.2, "followed"), "PD^r_5": ("1000", "followed"), "PD^r_6": ("1000", "followed"),
}


def family_range(spec: FamilySpec) -> tuple:
    """``(E_min, E_max)`` accepted for the family: ``E_n < E <= E_max`` with ``E_max`` from :data:`FAMILY_REACH`.

    Every family is born at ``E_n`` and exists only above it (forward fork). ``E_max`` is where it
    was measured to end or fold (continuation in amplitude, :func:`continue_in_amplitude`), or how
    far it was followed; PD^r_5 and PD^r_6 (extended precision) are accepted to
    ``E_n + 1000 |E_n - 4|``.
    """
    if spec.label not in FAMILY_REACH:
        raise ValueError(f"no newborn family {spec.label} is followed here (families: {', '.join(FAMILIES)})")
    top, _ = FAMILY_REACH[spec.label]
    if isinstance(top, str):
        top = spec.E_birth + float(top) * abs(spec.E_birth - 4.0)
    return spec.E_birth, top


def range_message(spec: FamilySpec) -> str:
    """One sentence: where the family exists and why its range ends there."""
    lo, hi = family_range(spec)
    how = FAMILY_REACH[spec.label][1]
    why = {"fold": f"at E = {hi!r} the family folds back to lower energies (no member above it)",
           "E = 4.5": f"it was followed from birth to E = {hi!r}; continued further in amplitude it runs towards "
                      f"E = 4.5 (the maxima of V) with a growing period",
           "followed": f"it was followed from birth to E = {hi!r}"}[how]
    return f"{spec.label} exists for {lo!r} < E <= {hi!r} (born at E_n = {lo!r}; {why})"


# --------------------------------------------------------------------------- shooting

def _mpf(v):
    if isinstance(v, (np.floating, np.integer)):
        v = float(v)
    if isinstance(v, float):
        return mp.mpf(repr(v))
    return mp.mpf(v)


def _state_with_p2(spec: FamilySpec, u, p2, zero=0.0):
    """``[a1, a2, p1, p2]`` on the family's start line: ``a1 = u`` or ``p1 = u`` (``spec.start``), given ``p2``."""
    return [u, zero, zero, p2] if spec.start == "a1" else [zero, zero, u, p2]


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
        f0 = f(x0)
        for _ in range(30):           # a second point beyond the section's reach is moved closer
            try:
                f1 = f(x1)
                break
            except RuntimeError:
                x1 = x0 + (x1 - x0) / 8
        else:
            raise RuntimeError("no second point of the secant reaches the section")
        best = (abs(f1), x1) if abs(f1) < abs(f0) else (abs(f0), x0)
        last_dx = None
        for it in range(maxiter):
            if f1 == f0:
                break
            x2 = x1 - f1 * (x1 - x0) / (f1 - f0)
            for _ in range(30):        # a step that leaves the section's reach is halved back
                try:
                    f2 = f(x2)
                    break
                except RuntimeError:
                    x2 = x1 + (x2 - x1) / 2
            else:
                raise RuntimeError("the secant left the region where the section is reached")
            dx = abs(x2 - x1)
            x0, f0 = x1, f1
            x1, f1 = x2, f2
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
    u1 = u_guess * (1 + 1e-4) if precision == "float64" else _mpf(u_guess) * (1 + mp.mpf("1e-9"))
    u, it, fr = _secant(f, u_guess, u1, _tol(precision), prec=precision)
    if not fr < (1e-8 if precision == "float64" else 1e-24) or not (abs(float(u)) > 0):
        raise ValueError(f"{spec.label}: the shooting did not converge at E = {float(E)!r}")
    return u, it


def _res_u(spec, E, precision, u):
    return shoot_residual(spec, u, E, precision)


def _res_E(spec, u, precision, E):
    return shoot_residual(spec, u, E, precision)


def birth_member(spec: FamilySpec, u, precision="float64", tol=None):
    """Paper §6 step 3 in one unknown: fix the amplitude ``u``, adjust the energy (i.e. ``p2(0)``).

    A secant iteration on the signed symmetric residual :func:`shoot_residual` in ``E`` (a simple
    root: ``E`` to ~eps / |E - 4| in float64, ~1e-30 in real128). ``tol`` is the relative step at
    which the secant stops (default 1e-15 float64, 1e-32 real128). Returns ``(E, iterations)``; the
    residual is evaluated ``iterations + 2`` times; ``E - E_n ~ c u^2`` (fork-like).
    """
    f = functools.partial(_res_E, spec, u, precision)
    if precision == "float64":
        E0 = spec.E_birth
        E1 = E0 + 1e-3 * max(abs(E0 - 4.0), 1e-12) * (1 if spec.phase == "lib" else 1)
    else:
        E0 = _birth_mp(spec)
        E1 = E0 + mp.mpf(1e-3) * abs(E0 - 4)
    if tol is None:
        tol = 1e-15 if precision == "float64" else mp.mpf("1e-32")
    E, it, fr = _secant(f, E0, E1, tol, prec=precision)
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
        raise ValueError(f"{range_message(spec)}; got E = {float(E)!r}")


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
            try:
                path = _solve_path(spec, float(E), "float64", steps)
            except ValueError:
                # the continuation in E stopped at an intermediate fold or a hard stretch: take the
                # first member with this energy along the branch followed in amplitude
                path = [_member_on_branch(spec, float(E))]
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


def _member_on_branch(spec, E):
    """``(E, u)``: the first member with energy ``E`` along :func:`continue_in_amplitude` (float64)."""
    b = continue_in_amplitude(spec.label, E_cap=E, n_max=4000)
    k = np.nonzero(b.E >= E)[0]
    if k.size == 0:
        raise ValueError(f"{spec.label}: the family continued from its birth at E_n = {spec.E_birth!r} was not "
                         f"found beyond E = {float(np.max(b.E))!r} (in amplitude: {b.end}); asked for E = {E!r}")
    i = int(k[0])
    from scipy.optimize import brentq

    a, c = float(b.u[i - 1]), float(b.u[i])
    f = (E - b.E[i - 1]) / (b.E[i] - b.E[i - 1])
    # a sign change of r(., E) near the two members bracketing E: robust even where t1 varies steeply with u
    w = abs(c - a)
    grid = np.linspace(min(a, c) - w, max(a, c) + w, 61)
    vals = []
    for x in grid:
        try:
            vals.append(shoot_residual(spec, x, E))
        except (ValueError, RuntimeError):
            vals.append(np.nan)
    vals = np.array(vals)
    ok = np.isfinite(vals[:-1]) & np.isfinite(vals[1:]) & (vals[:-1] * vals[1:] < 0)
    for j in sorted(np.nonzero(ok)[0], key=lambda j: abs(grid[j] - (a + f * (c - a)))):
        try:
            x = brentq(lambda x: shoot_residual(spec, x, E), grid[j], grid[j + 1], xtol=1e-15, rtol=1e-15)
        except (ValueError, RuntimeError):
            continue
        T_branch = b.period[i - 1] + f * (b.period[i] - b.period[i - 1])
        T_x = spec.factor * float(shoot(spec, x, E)[0])
        if abs(shoot_residual(spec, x, E)) < 1e-8 and abs(T_x - T_branch) < 0.2 * T_branch:
            return E, x         # a root (not a jump of the section) on this branch (not another orbit)
    try:
        u, _ = solve_at_energy(spec, E, float(a + f * (c - a)))
    except RuntimeError as exc:
        raise ValueError(f"{spec.label}: no member found at E = {E!r} ({exc})") from None
    return E, u


def newborn_family(label, E_end=None, n=12, precision=None):
    """Members from near birth to ``E_end`` (default 4 for libration, ``E_n + 0.05`` rotation, or the top of
    :func:`family_range` if lower), spaced in
    ``sqrt(E - E_n)``. Returns a list of :class:`PeriodicOrbit` (births first)."""
    spec = family_spec(label)
    prec = precision or auto_precision(spec)
    if E_end is None:
        E_end = 4.0 if spec.phase == "lib" else min(spec.E_birth + 0.05, family_range(spec)[1])
    _check_E(spec, E_end)
    path = _solve_path(spec, E_end, prec, steps=n)
    return [_make_orbit(spec, E, u, prec, {}) for E, u in path]


# --------------------------------------------------------------------------- the paper's variant

@dataclass(frozen=True)
class PaperSearchResult:
    """Result of :func:`paper_search` (paper §6, step 3).

    Attributes
    ----------
    label : str
    u : float
        The fixed transverse perturbation (``a1(0)`` or ``p1(0)``).
    p2 : float
        The minimiser ``p2(0)``.
    E : float
        Its energy.
    d_min : float
        The departure from periodicity there.
    n_evaluations : int
        Number of evaluations of ``d`` (each one integration over one (IS) or two (PD) cycles of ``a2``).
    t_star : float
        The integration time ``t*`` of the minimiser (the orbit's period).
    at_bound : bool
        True if the minimiser sits on an end of the bracket (the bracket missed the minimum).
    """

    label: str
    u: float
    p2: float
    E: float
    d_min: float
    n_evaluations: int
    t_star: float
    at_bound: bool


def periodicity_defect(label, x0, precision="float64"):
    """The paper's departure from periodicity of the orbit started at ``x0 = [a1, a2, p1, p2]`` (§6 step 3).

    Integrates until ``a2`` completes one (IS) or two (PD) cycles (libration: back through ``a2 = 0``
    going up after each turning point; rotation: ``a2`` reaches ``a2(0) + 2 pi`` or ``+ 4 pi``) and
    returns ``(d, t*)`` with
    ``d = [(a1(t*) - a1(0))^2 + (p1(t*) - p1(0))^2 + (p2(t*) - p2(0))^2]^(1/2)``.

    Precision: heyoka Taylor in ``precision`` (float64 or real128; the result is a float). The flow
    amplifies round-off like ``1/|E - 4|`` over the full period.
    """
    spec = family_spec(label)
    flow._check_precision(precision)
    cycles = 1 if spec.kind == "IS" else 2
    x = list(x0)
    t = 0.0
    with mp.workdps(40):
        if spec.phase == "lib":
            for _ in range(cycles):
                dt, x = flow.flow_to_event(x, "turn", 0.0, precision)
                t = t + dt
                dt, x = flow.flow_to_event(x, "a2_up", 0.0, precision)
                t = t + dt
        else:
            lev = (2 * cycles) * (math.pi if precision == "float64" else mp.pi)
            t, x = flow.flow_to_event(x0, "a2_up", _mpf(x0[1]) + lev if precision != "float64" else x0[1] + lev,
                                      precision)
        if precision == "float64":
            d = math.sqrt((x[0] - x0[0]) ** 2 + (x[2] - x0[2]) ** 2 + (x[3] - x0[3]) ** 2)
        else:
            d = mp.sqrt(sum((_mpf(x[k]) - _mpf(x0[k])) ** 2 for k in (0, 2, 3)))
    return float(d), float(t)


def paper_search(label, u, E_guess, width=None, xatol=1e-16, maxiter=500) -> PaperSearchResult:
    """Paper §6 as written: fix the perturbation ``u`` along the transverse eigenvector, integrate
    until ``a2`` completes one (IS) or two (PD) cycles, and minimise the departure from periodicity
    ``d(p2(0))`` (:func:`periodicity_defect`) over ``p2(0)`` by Brent's bounded minimiser
    (:func:`scipy.optimize.minimize_scalar`, ``method='bounded'``).

    Parameters
    ----------
    label : str
    u : float
        Transverse perturbation: ``a1(0)`` or ``p1(0)`` (the family's start line, :func:`family_spec`).
    E_guess : float
        Centre of the bracket (in energy).
    width : float, optional
        Half-width of the bracket in energy; default ``0.5 |E_guess - E_n|`` (the fork
        ``E - E_n ~ c u^2`` puts the minimum within it when ``E_guess`` is within a factor 2).
    xatol : float
        Absolute tolerance in ``p2`` passed to the minimiser.
    maxiter : int

    Returns
    -------
    PaperSearchResult

    Precision: float64. Brent's bounded minimiser stops once its bracket is below
    ``sqrt(eps) |p2| + xatol / 3`` (its built-in tolerance: at a smooth minimum the change
    ``f''(x) h^2 / 2`` of ``f`` is invisible below ``h ~ sqrt(eps)``), so ``p2(0)`` and ``E`` are found to
    ~1e-8 relative whatever ``xatol``; the full-period integration adds the flow's own
    amplification ``~eps / |E - 4|``. A root of the signed symmetric residual
    (:func:`birth_member`, :func:`solve_at_energy`) has neither limit.

    Raises
    ------
    ValueError
        ``u`` or the bracket outside the energy shell, or non-positive ``width``.
    """
    from scipy.optimize import minimize_scalar

    spec = family_spec(label)
    u, E_guess = float(u), float(E_guess)
    w = 0.5 * abs(E_guess - spec.E_birth) if width is None else float(width)
    if not (w > 0 and math.isfinite(w)):
        raise ValueError(f"the bracket half-width must be > 0, got {w!r} (E_guess = E_n?)")
    neval = [0]

    def d(p2):
        neval[0] += 1
        return periodicity_defect(spec.label, _state_with_p2(spec, u, p2))[0]

    lo, hi = start_state(spec, u, E_guess - w)[3], start_state(spec, u, E_guess + w)[3]
    res = minimize_scalar(d, bounds=(lo, hi), method="bounded", options={"xatol": xatol, "maxiter": maxiter})
    p2 = float(res.x)
    from .system import energy_alpha

    x0 = _state_with_p2(spec, u, p2)
    dmin, tstar = periodicity_defect(spec.label, x0)
    at_bound = min(p2 - lo, hi - p2) < 1e-3 * (hi - lo) + 3 * (math.sqrt(np.finfo(float).eps) * abs(p2) + xatol)
    return PaperSearchResult(spec.label, u, p2, float(energy_alpha(np.array(x0))), dmin, neval[0], tstar,
                             bool(at_bound))


@dataclass(frozen=True)
class SearchComparison:
    """The paper's search and the symmetric shooting at the same amplitude ``u`` (:func:`compare_searches`).

    Attributes
    ----------
    label : str
    u : float
        The fixed transverse perturbation.
    E_ref : float
        Reference energy of the member with this ``u``: the symmetric root in real128 (~1e-30).
    paper : PaperSearchResult
    paper_error : float
        ``|E_paper - E_ref|``.
    paper_defect : float
        The departure from periodicity of the paper's float64 initial state, integrated in real128.
    paper_span : float
        Integration time per evaluation (``t*``: one or two cycles of ``a2``).
    shooting_E : float
        :func:`birth_member` in float64.
    shooting_error : float
        ``|E_shooting - E_ref|``.
    shooting_defect : float
        The departure from periodicity of the shooting's float64 initial state, integrated in real128.
    shooting_evaluations : int
        Evaluations of the residual.
    shooting_span : float
        Integration time per evaluation (``t1``: a quarter or half of the period).
    paper_seconds, shooting_seconds : float
        Wall time of each search (warm integrators; informative only).
    """

    label: str
    u: float
    E_ref: float
    paper: PaperSearchResult
    paper_error: float
    paper_defect: float
    paper_span: float
    shooting_E: float
    shooting_error: float
    shooting_defect: float
    shooting_evaluations: int
    shooting_span: float
    paper_seconds: float
    shooting_seconds: float


def default_amplitude(label, rel=0.1):
    """A small amplitude on the family near birth: ``rel * sqrt(|E_n - 4|)`` (``a1``) or twice that (``p1``)."""
    spec = family_spec(label)
    if not rel > 0:
        raise ValueError(f"rel must be > 0, got {rel!r}")
    return rel * _u_scale(spec) * math.sqrt(abs(spec.E_birth - 4.0))


def _guess_E(spec, u):
    """The fork law ``E_n + c u^2`` with ``c`` from the seed member (the information both searches start from)."""
    _, _, c = _seed(spec.label, "float64")
    return spec.E_birth + float(c) * u * u


def compare_searches(label, u=None, xatol=1e-16, tol=None) -> SearchComparison:
    """Run :func:`paper_search` and :func:`birth_member` at the same ``u`` and score both against real128.

    Both start from the fork law ``E_n + c u^2`` (``c`` from :func:`birth_member` at a tiny
    amplitude): the paper's bracket is centred there with half-width ``0.5 c u^2``; the secant
    starts at ``E_n``. Accuracy: ``|E - E_ref|`` with ``E_ref`` the real128 symmetric root, and the
    real128 departure from periodicity of each float64 initial state. Cost: evaluations, integration
    time per evaluation, and wall time (the latter varies between runs and machines).

    Float64 families only (``|E_n - 4| > 3e-8``).
    """
    spec = family_spec(label)
    if abs(spec.E_birth - 4.0) < FLOAT64_LIMIT:
        raise ValueError(f"{spec.label}: compare_searches is float64 only (|E_n - 4| > {FLOAT64_LIMIT})")
    u = default_amplitude(label) if u is None else float(u)
    E_ref = birth_member(spec, u, "real128")[0]
    Eg = _guess_E(spec, u)
    t0 = time.perf_counter()
    ps = paper_search(label, u, Eg, width=0.5 * abs(Eg - spec.E_birth), xatol=xatol)
    t1 = time.perf_counter()
    E_s, it = birth_member(spec, u, tol=tol)
    t2 = time.perf_counter()
    x_p = _state_with_p2(spec, u, ps.p2)
    x_s = start_state(spec, u, float(E_s))
    d_p = periodicity_defect(label, x_p, "real128")[0]
    d_s = periodicity_defect(label, x_s, "real128")[0]
    span = float(shoot(spec, u, float(E_s))[0])
    with mp.workdps(40):
        err_p = float(abs(_mpf(ps.E) - E_ref))
        err_s = float(abs(_mpf(float(E_s)) - E_ref))
    return SearchComparison(spec.label, u, float(E_ref), ps, err_p, d_p, ps.t_star, float(E_s), err_s, d_s,
                            it + 2, span, t1 - t0, t2 - t1)


@dataclass(frozen=True)
class WorkPrecision:
    """Error against cost as the stopping tolerance is tightened (:func:`work_precision`).

    Attributes
    ----------
    label : str
    u : float
    tolerances_paper, tolerances_shooting : ndarray
        ``xatol`` of the minimiser (absolute, in ``p2``) and relative step of the secant (in ``E``).
    evaluations_paper, evaluations_shooting : ndarray
    integration_paper, integration_shooting : ndarray
        Total integration time (evaluations times the span of one evaluation), in units of the
        pendulum period at birth: a cost measure independent of the machine.
    error_paper, error_shooting : ndarray
        ``|E - E_ref|`` (``E_ref`` real128).
    """

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


def work_precision(label, u=None, tolerances_paper=None, tolerances_shooting=None) -> WorkPrecision:
    """Both searches at a sequence of stopping tolerances (float64), scored against real128.

    Defaults: ``xatol = 1e-2 ... 1e-16`` for the minimiser and ``tol = 1e-2 ... 1e-15`` for the secant.
    """
    spec = family_spec(label)
    u = default_amplitude(label) if u is None else float(u)
    tp = np.array(tolerances_paper if tolerances_paper is not None else [10.0 ** -k for k in range(2, 17)])
    ts = np.array(tolerances_shooting if tolerances_shooting is not None else [10.0 ** -k for k in range(2, 16)])
    if np.any(tp <= 0) or np.any(ts <= 0):
        raise ValueError("tolerances must be > 0")
    E_ref = birth_member(spec, u, "real128")[0]
    Eg = _guess_E(spec, u)
    tau = spec.period_birth
    ep, ip, rp = [], [], []
    for xa in tp:
        ps = paper_search(label, u, Eg, width=0.5 * abs(Eg - spec.E_birth), xatol=float(xa))
        ep.append(ps.n_evaluations)
        ip.append(ps.n_evaluations * ps.t_star / tau)
        with mp.workdps(40):
            rp.append(float(abs(_mpf(ps.E) - E_ref)))
    es, is_, rs = [], [], []
    for tl in ts:
        E_s, it = birth_member(spec, u, tol=float(tl))
        span = float(shoot(spec, u, float(E_s))[0])
        es.append(it + 2)
        is_.append((it + 2) * span / tau)
        with mp.workdps(40):
            rs.append(float(abs(_mpf(float(E_s)) - E_ref)))
    return WorkPrecision(spec.label, u, tp, ts, np.array(ep), np.array(es), np.array(ip), np.array(is_),
                         np.array(rp), np.array(rs))


@dataclass(frozen=True)
class DefectLandscape:
    """The two objective functions near a family member, as functions of ``p2(0) = p2* (1 + delta)``.

    Attributes
    ----------
    label : str
    u : float
    p2_star : float
        ``p2(0)`` of the member (from the real128 root, rounded to float64).
    delta : ndarray
        Relative offsets (positive).
    defect : ndarray
        The paper's ``d`` (full period, float64), at ``p2* (1 + delta)``.
    residual : ndarray
        ``|r|`` of the symmetric shooting (quarter or half period, float64), same states.
    """

    label: str
    u: float
    p2_star: float
    delta: np.ndarray
    defect: np.ndarray
    residual: np.ndarray


def defect_landscape(label, u=None, delta=None) -> DefectLandscape:
    """``d`` and ``|r|`` along ``p2(0)`` near the member with amplitude ``u`` (float64, :class:`DefectLandscape`).

    Default offsets ``delta = 10^-17 ... 10^-3``. Both are linear in ``delta`` (``d`` is a norm of
    three components that vanish together: a V-shaped minimum at 0; ``r`` a simple root) down to
    their round-off floors.
    """
    spec = family_spec(label)
    u = default_amplitude(label) if u is None else float(u)
    delta = np.logspace(-17, -3, 57) if delta is None else np.asarray(delta, float)
    E_ref = birth_member(spec, u, "real128")[0]
    p2s = float(start_state(spec, u, E_ref, "real128")[3])
    from .system import energy_alpha

    dd, rr = [], []
    for dl in delta:
        p2 = p2s * (1 + dl)
        x0 = _state_with_p2(spec, u, p2)
        dd.append(periodicity_defect(label, x0)[0])
        rr.append(abs(shoot_residual(spec, u, float(energy_alpha(np.array(x0))))))
    return DefectLandscape(spec.label, u, p2s, delta, np.array(dd), np.array(rr))


def residual_scan(label, E, n=2001):
    """``r(u)`` of the symmetric shooting at energy ``E`` across the whole energy shell (float64).

    ``u`` runs over ``n`` points of ``(0, u_max)`` (``u_max``: the shell's edge on the start line,
    ``2 sqrt(E)`` for ``p1``, ``V(a1, 0) = E`` for ``a1``); ``r`` is ``nan`` where the section is not
    reached. Every member of the family at ``E`` is a zero of ``r`` (its reversing symmetry is kept
    along the family), so a scan without a sign change shows there is none. Returns ``(u, r)``.
    """
    spec = family_spec(label)
    E = float(E)
    if not (E > 0 and math.isfinite(E)) or n < 3:
        raise ValueError(f"need E > 0 and n >= 3, got E = {E!r}, n = {n!r}")
    if spec.start == "p1":
        umax = 2.0 * math.sqrt(E)
    else:
        from scipy.optimize import brentq

        umax = brentq(lambda a: float(potential_alpha(a, 0.0)) - E, 0.0, math.pi / 2) if E < 4.0 else math.pi / 2
    u = np.linspace(0.0, umax, n + 1)[1:] * (1 - 1e-12)
    r = np.full(u.size, np.nan)
    for i, ui in enumerate(u):
        try:
            r[i] = shoot_residual(spec, ui, E)
        except (ValueError, RuntimeError):
            pass
    return u, r


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


# --------------------------------------------------------------------------- continuation in amplitude (folds)

@dataclass(frozen=True)
class AmplitudeContinuation:
    """A family followed by pseudo-arclength continuation in the plane of (amplitude ``u``, energy ``E``).

    Attributes
    ----------
    label : str
    u, E, period : ndarray
        The members, in order along the branch from its birth (``u -> 0``, ``E -> E_n``).
    E_max : float
        The largest energy reached (a fold in ``E`` when ``end`` is not ``'E cap'``).
    u_at_E_max : float
    fold : bool
        True when ``E`` turns back after ``E_max`` (a fold: the family has no member above ``E_max``).
    end : str
        Why the continuation stopped: ``'period diverges'`` (the branch runs into a homoclinic or
        heteroclinic orbit: the shooting time grew beyond ``period_cap``), ``'E cap'``,
        ``'section lost'`` (the corrector failed: the orbit no longer meets its section transversally)
        or ``'steps'``.
    E_end, u_end : float
        The last member.
    """

    label: str
    u: np.ndarray
    E: np.ndarray
    period: np.ndarray
    E_max: float
    u_at_E_max: float
    fold: bool
    end: str
    E_end: float
    u_end: float


def continue_in_amplitude(label, E_cap=None, ds=0.05, n_max=600, period_cap=None, E_floor=None):
    """Follow a family through folds: pseudo-arclength continuation of ``r(u, E) = 0`` (float64).

    The curve ``r(u, E) = 0`` of :func:`shoot_residual` is followed in the scaled plane
    ``(u / s, (E - E_n) / d)`` with ``d = |E_n - 4|``, ``s = sqrt(d)``: predictor along the
    tangent (the kernel of the finite-difference gradient), Newton corrector on
    ``[r = 0, t . (x - x_prev) = ds]``; the step adapts (halved on failure, x1.3 on success,
    at most ``ds`` times the distance from birth in the scaled plane). Unlike the continuation in
    ``E`` of :func:`newborn_orbit` it passes folds (where ``dE/du = 0``).

    Parameters
    ----------
    label : str
    E_cap : float, optional
        Stop when ``E`` exceeds it (default: 4.2 for libration, ``E_n + 6`` for rotation).
    ds : float
        Largest step in the scaled plane.
    n_max : int
        Largest number of members.
    period_cap : float, optional
        Stop when the orbit's period exceeds it (default 12 times the period at birth).
    E_floor : float, optional
        Stop when ``E`` falls below it (default ``E_n - 2 d``).

    Returns
    -------
    AmplitudeContinuation

    Precision: each member satisfies ``|r| < 1e-9`` (float64 heyoka); meaningful while
    ``|E - 4| > ~1e-8`` (float64 families only).
    """
    spec = family_spec(label)
    if abs(spec.E_birth - 4.0) < FLOAT64_LIMIT:
        raise ValueError(f"{spec.label}: continue_in_amplitude is float64 only (|E_n - 4| > {FLOAT64_LIMIT})")
    if not (ds > 0 and n_max >= 1):
        raise ValueError(f"need ds > 0 and n_max >= 1, got ds = {ds!r}, n_max = {n_max!r}")
    En, d = spec.E_birth, abs(spec.E_birth - 4.0)
    s = math.sqrt(d)
    E_cap = (4.2 if spec.phase == "lib" else En + 6.0) if E_cap is None else float(E_cap)
    T_birth = spec.period_birth * (2 if spec.kind == "PD" else 1)     # the newborn orbit's period at birth
    period_cap = 12.0 * T_birth if period_cap is None else float(period_cap)
    E_floor = En - 2 * d if E_floor is None else float(E_floor)

    def res(x):
        return shoot_residual(spec, x[0] * s, En + x[1] * d)

    def grad(x, h=1e-5):
        return np.array([(res(x + [h, 0]) - res(x - [h, 0])) / (2 * h), (res(x + [0, h]) - res(x - [0, h])) / (2 * h)])

    u_s, E_s, _ = _seed(spec.label, "float64")
    x = np.array([u_s / s, (E_s - En) / d])
    pts = [x.copy()]
    tang, step, end = None, ds / 4, "steps"
    for _ in range(n_max):
        try:
            g = grad(x)
        except (ValueError, RuntimeError):
            end = "section lost"
            break
        tv = np.array([-g[1], g[0]]) / math.hypot(*g)
        if (tang is None and tv[0] < 0) or (tang is not None and tv @ tang < 0):
            tv = -tv
        ok = False
        while step > 1e-9:
            y = x + step * tv
            try:
                for _it in range(12):
                    J = np.array([grad(y), tv])
                    F = np.array([res(y), tv @ (y - x) - step])
                    dy = np.linalg.solve(J, -F)
                    y = y + dy
                    if np.max(np.abs(dy)) < 1e-10:
                        break
                ok = abs(res(y)) < 1e-8 * max(1.0, math.hypot(*J[0])) and np.linalg.norm(y - x) < 2 * step
            except (ValueError, RuntimeError, np.linalg.LinAlgError):
                ok = False
            if ok:
                break
            step /= 2
        if not ok:
            end = "section lost"
            break
        tang, x = tv, y
        pts.append(x.copy())
        step = min(step * 1.3, ds * max(1.0, float(np.hypot(*x))))
        E = En + x[1] * d
        t1 = float(shoot(spec, x[0] * s, E)[0])
        if spec.factor * t1 > period_cap:
            end = "period diverges"
            break
        if E > E_cap:
            end = "E cap"
            break
        if E < E_floor or x[0] <= 0:
            end = "E floor"
            break
    P = np.array(pts)
    u, E = P[:, 0] * s, En + P[:, 1] * d
    per = np.array([spec.factor * float(shoot(spec, ui, Ei)[0]) for ui, Ei in zip(u, E)])
    k = int(np.argmax(E))
    fold = bool(0 < k < len(E) - 1 and E[-1] < E[k])
    E_max, u_max = float(E[k]), float(u[k])
    if fold:
        u_max, E_max = _refine_fold(spec, u[k - 1], u[k + 1], E[k])
    return AmplitudeContinuation(spec.label, u, E, per, E_max, u_max, fold, end, float(E[-1]), float(u[-1]))


def _E_at_u(spec, u, E_near):
    """The member with amplitude ``u`` nearest ``E_near`` (secant in ``E``, float64)."""
    f = functools.partial(_res_E, spec, u, "float64")
    E, _, fr = _secant(f, E_near, E_near + 1e-7 * max(abs(E_near - 4.0), 1e-3), 1e-15)
    if not fr < 1e-8:
        raise ValueError(f"{spec.label}: no member with u = {u!r} near E = {E_near!r}")
    return float(E)


def _refine_fold(spec, u_lo, u_hi, E_guess):
    """Maximum of ``E(u)`` between ``u_lo`` and ``u_hi`` (bounded Brent; ``E`` to ~1e-15 since the
    maximum is quadratic in ``u``, ``u`` itself only to ~sqrt(eps))."""
    from scipy.optimize import minimize_scalar

    r = minimize_scalar(lambda uu: -_E_at_u(spec, uu, E_guess), bounds=(min(u_lo, u_hi), max(u_lo, u_hi)),
                        method="bounded", options={"xatol": 1e-10})
    return float(r.x), -float(r.fun)
