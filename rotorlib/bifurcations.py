"""Stability transitions of pendula: the bifurcation cascade (paper §3 summary and §5).

The transverse stability of the pendulum at ``x = log|E - 4|`` is governed by
``Delta(x)``, the trace of the coefficient-period map of the transverse Hill
(Lamé) problem (:mod:`rotorlib.hill`): ``tr M = Delta^2`` in libration and
``tr M = 2 + Delta`` in rotation. The transitions are the roots of

* libration: ``Delta = +2`` or ``Delta = -2`` (``tr M = 4``, isochronous ``IS^l_n``)
  and ``Delta = 0`` (``tr M`` has a double zero, period doubling ``PD^l_n``);
* rotation: ``Delta = +2`` (``IS^r_n``) and ``Delta = -2`` (``tr M = 0``, ``PD^r_n``).

Numbering follows the paper: ``n`` increases with ``E`` in libration and
decreases with ``E`` in rotation, i.e. in both phases ``n`` increases as the
orbit approaches the separatrix (``x`` decreases); IS and PD are numbered
separately.

Method: ``Delta`` is tabulated on a grid in ``x`` (step 0.05; ``Delta`` is
asymptotically periodic in ``x`` with period ``2 sqrt(3) pi = 10.88``, and
consecutive roots of one equation are >= 1.1 apart), sign changes are refined
with Brent's method to ``xtol = 1e-14`` (absolute), with heyoka's float64
Taylor integrator (~0.1 ms per ``Delta``).

Precision: ``Delta`` is accurate to ~1e-13 absolute at any depth, and
``|dDelta/dx| > 0.5`` at every root, so ``log|E - 4|`` is accurate to ~2e-13
absolute (>= 13 significant digits for ``|x| > 1``; for ``PD^r_1``, at
``x = 0.468``, ~12 digits) and the period, from the closed form
``4K/sqrt3`` (lib) or ``2 kappa K/sqrt3`` (rot), to ~3e-13 absolute.
``tests/test_bifurcations.py`` re-locates every one of the first 80 roots with
heyoka real128 (~32 digits) and checks a few with the textbook 4x4
variational equations in 256-bit arithmetic. ``transition(label, digits=30)``
returns a root refined in real128.
"""

from __future__ import annotations

import dataclasses
import math
import re
from dataclasses import dataclass

import mpmath as mp
import numpy as np

from .energy import PendulumEnergy, pendulum_energy
from .hill import (
    HillProblem,
    heyoka_available,
    hill_problem,
    precision_tier,
    solve_hill,
)
from .orbits import pendulum
from .parallel import pmap
from .precision import check_digits, json_number

__all__ = [
    "Transition",
    "parse_label",
    "transition",
    "transitions",
    "delta",
    "delta_mp",
    "trace_of_delta",
    "trace_curve",
    "refine_mp",
    "SQRT3_PI",
    "CLASSES",
    "transition_class",
    "X_MIN",
]

#: ``sqrt(3) pi``: predicted ``log delta^l``; ``log delta^r = 2 sqrt(3) pi``.
SQRT3_PI = math.sqrt(3.0) * math.pi

#: Deepest ``log|E - 4|`` searched: ``|E - 4| = exp(x)`` must stay a normal float64.
X_MIN = -700.0
#: Start of the scan: E = 0.1 (lib, ``log 3.9``; at E = 0 itself Delta = -2 exactly, the harmonic limit,
#: and -2 < Delta for 0 < E <= 0.1) and E = 4 + e^8 ~ 2985 (rot; Delta -> 2 from below as E -> inf).
X_START = {"lib": math.log(3.9), "rot": 8.0}
_GRID_STEP = 0.05
_KINDS = ("IS", "PD")
_PHASE_LETTER = {"lib": "l", "rot": "r"}

#: Targets of Delta for each (kind, phase).
_TARGETS = {
    ("IS", "lib"): (2.0, -2.0),
    ("PD", "lib"): (0.0,),
    ("IS", "rot"): (2.0,),
    ("PD", "rot"): (-2.0,),
}

#: The seven classes of §5 (name -> (kind, phase, parity or None)).
CLASSES = {
    "IS^l_odd": ("IS", "lib", 1),
    "IS^l_even": ("IS", "lib", 0),
    "PD^l": ("PD", "lib", None),
    "IS^r_odd": ("IS", "rot", 1),
    "IS^r_even": ("IS", "rot", 0),
    "PD^r_odd": ("PD", "rot", 1),
    "PD^r_even": ("PD", "rot", 0),
}


@dataclass(frozen=True)
class Transition:
    """A stability transition (bifurcation) of the pendulum family.

    Attributes
    ----------
    label : str
        Paper notation, ``IS^l_3``, ``PD^r_2``.
    kind : {'IS', 'PD'}
        Isochronous (``tr M = 4``) or period doubling (``tr M = 0``).
    phase : {'lib', 'rot'}
    n : int
        Index in the paper's numbering (1, 2, ...).
    log_abs_dE : float
        ``log|E - 4|`` (natural log); accurate to ~2e-13 absolute in float64.
    log_abs_dE_str : str
        The same as a decimal string (17 significant digits in float64; all the
        digits of the refined root when ``digits > 15``).
    E : float
        Energy in float64 (use ``energy.eps`` / ``energy.decimal_E()`` for ``E - 4``).
    energy : PendulumEnergy
        The energy, carrying ``log_abs_dE_str`` as its decimal input.
    period : float
        Pendulum period ``4K/sqrt3`` (lib) or ``2 kappa K/sqrt3`` (rot), ~3e-13 absolute.
    delta_target : float
        Value of ``Delta`` at the transition (+2, -2 or 0).
    transition : str
        ``stable->unstable``, ``unstable->stable`` or ``stable->stable`` (``PD^l``:
        double zero of ``tr M``), with increasing ``E``.
    dtrace_dE : float
        Slope ``d tr M / dE`` of the pendulum family at the transition (0 for ``PD^l``).
    """

    label: str
    kind: str
    phase: str
    n: int
    log_abs_dE: float
    log_abs_dE_str: str
    E: float
    energy: PendulumEnergy
    period: float
    delta_target: float
    transition: str
    dtrace_dE: float
    dtrace_dx: float = float("nan")
    period_str: str = ""
    precision: str = "float64"

    @property
    def cls(self) -> str:
        """The §5 class: ``IS^l_odd``, ``IS^l_even``, ``PD^l``, ``IS^r_odd``, ... ."""
        return transition_class(self.kind, self.phase, self.n)

    def to_dict(self) -> dict:
        """JSON-serialisable dict (the ``bifurcations --json`` output)."""
        return {
            "label": self.label,
            "kind": self.kind,
            "phase": self.phase,
            "n": self.n,
            "class": self.cls,
            **json_number("log_abs_dE", self.log_abs_dE, self.log_abs_dE_str),
            **json_number("E", self.E, self.energy.decimal_E(15)),
            **json_number("period", self.period, self.period_str or None),
            "transition": self.transition,
            "delta_target": self.delta_target,
            "dtrace_dE": self.dtrace_dE,
            "precision": self.precision,
        }


def transition_class(kind: str, phase: str, n: int) -> str:
    """Name of the §5 class of a transition (``PD^l`` is a single class)."""
    if kind == "PD" and phase == "lib":
        return "PD^l"
    return f"{kind}^{_PHASE_LETTER[phase]}_{'odd' if n % 2 else 'even'}"


_LABEL_RE = re.compile(
    r"^\s*(IS|PD)\s*\^?\s*(l|r|ℓ)\s*_?\s*(\{\s*(\d+)\s*\}|(\d+))\s*$", re.IGNORECASE
)


def parse_label(text) -> tuple:
    """Parse a transition label.

    Accepts ``IS^l_3``, ``ISl3``, ``IS^l_{3}``, ``PDr2`` (kind and phase letter
    case-insensitive; ``ℓ`` for ``l``).

    Returns
    -------
    (kind, phase, n) : (str, str, int)
        ``('IS', 'lib', 3)``.

    Raises
    ------
    ValueError
        Anything else (``XYl1``, ``ISl0``, ``ISq2``, non-strings).
    """
    if not isinstance(text, str):
        raise ValueError(
            f"a transition label must be a string like 'IS^l_3', got {text!r}"
        )
    mt = _LABEL_RE.match(text)
    if not mt:
        raise ValueError(
            f"not a transition label: {text!r} (expected e.g. 'IS^l_3', 'PD^r_2', 'ISl3')"
        )
    kind = mt.group(1).upper()
    phase = "rot" if mt.group(2).lower() == "r" else "lib"
    n = int(mt.group(4) or mt.group(5))
    if n < 1:
        raise ValueError(f"transition index must be >= 1, got {n} in {text!r}")
    return kind, phase, n


def _label(kind, phase, n):
    return f"{kind}^{_PHASE_LETTER[phase]}_{n}"


# --------------------------------------------------------------------------- Delta(x)


def delta(x: float, phase: str) -> float:
    """``Delta`` at ``x = log|E - 4|`` in float64 (~1e-13 absolute; heyoka, else scipy)."""
    orb = pendulum(log_abs_dE=float(x), phase=phase)
    prob = hill_problem(orb)
    return _solve(prob)


def _solve(prob):
    be = "heyoka" if heyoka_available() else "scipy"
    return solve_hill(prob, be, "float64").delta


def trace_of_delta(d, phase):
    """``tr M`` from ``Delta``: ``Delta^2`` (lib) or ``2 + Delta`` (rot)."""
    return d * d if phase == "lib" else 2 + d


def _mp_problem(x, phase, dps):
    """The Hill problem at an mpmath ``x = log|E-4|`` (no float64 rounding of the energy)."""
    dps = (
        dps + int(max(0.0, -float(x) / math.log(10))) + 10
    )  # m = 1 - O(eps) needs the extra digits
    with mp.workdps(dps):
        x = mp.mpf(x)
        eps = mp.exp(x)
        if phase == "lib":
            E = 4 - eps
            m1, m = eps / 4, E / 4
        else:
            E = 4 + eps
            m1, m = eps / E, 4 / E
        K = mp.ellipk(m)
        du_dt = math.sqrt(3.0) if phase == "lib" else math.sqrt(3.0 / float(m))
        return HillProblem(
            "pendulum-" + phase,
            +m,
            +m1,
            +K,
            2 * m / 3,
            0.0,
            2 if phase == "lib" else 1,
            du_dt,
            2.0,
        )


def delta_mp(x, phase: str, digits: int = 30):
    """``Delta`` at an mpmath/decimal ``x`` with heyoka real128 (``digits <= 31``) or multiprecision.

    Returns an ``mpmath.mpf`` (caller's working precision should be >= ``digits``).
    The energy is built from ``x`` in mpmath at ``digits + 15`` digits, so no
    float64 rounding enters.
    """
    be, prec = precision_tier(digits, "heyoka")
    dps = digits + 15
    prob = _mp_problem(x, phase, dps)
    sol = solve_hill(prob, be, prec)
    with mp.workdps(dps):
        return mp.mpf(sol.delta_exact)


def _period_mp(x, phase, dps):
    with mp.workdps(dps):
        prob = _mp_problem(x, phase, dps)
        if phase == "lib":
            return 4 * prob.K / mp.sqrt(3)
        return 2 * mp.sqrt(prob.m) * prob.K / mp.sqrt(3)


# --------------------------------------------------------------------------- scanning


def _scan_chunk(args):
    """Delta on a grid: module-level so process pools can pickle it."""
    phase, xs = args
    return np.array([delta(x, phase) for x in xs])


def _refine(phase, c, a, b, fa, fb):
    from scipy.optimize import brentq  # (lazy: scipy.optimize is slow to import)

    f = lambda x: delta(x, phase) - c  # noqa: E731
    if fa == 0.0:
        return a
    if fb == 0.0:
        return b
    return brentq(f, a, b, xtol=1e-14, rtol=1e-15, maxiter=200)


def _slope(x, phase, h=1e-4):
    """dDelta/dx by a 4-point centred difference (relative error ~1e-9)."""
    d = [delta(x + k * h, phase) for k in (-2, -1, 1, 2)]
    return (d[0] - 8 * d[1] + 8 * d[2] - d[3]) / (12 * h)


def _depth(phase, kinds, n_max):
    """Deepest x needed for n_max roots of each kind (from the asymptotic spacing, plus margin)."""
    # lib: PD every sqrt3 pi; IS two per sqrt3 pi. rot: IS and PD two per 2 sqrt3 pi.
    deepest = 0.0
    for kind in kinds:
        if phase == "lib":
            per = SQRT3_PI if kind == "PD" else SQRT3_PI / 2
            first = -2.43 if kind == "PD" else -4.67
        else:
            per = SQRT3_PI
            first = 1.0 if kind == "PD" else -4.67
        deepest = min(deepest, first - (n_max + 1) * per - 2.0)
    return deepest


def _deltas(phase, xs, executor, progress, desc):
    """``Delta`` on the grid ``xs`` (float64), in chunks through :func:`pmap`."""
    if not len(xs):
        return np.zeros(0)
    chunks = np.array_split(xs, max(1, min(16, len(xs) // 200)))
    parts = pmap(
        _scan_chunk,
        [(phase, c) for c in chunks],
        executor=executor,
        progress=progress,
        desc=desc,
    )
    return np.concatenate(parts)


def _find(phase, kinds, n_max, executor=None, progress=False):
    """Roots (x, target, kind) in one phase with n <= n_max for each kind."""
    x_lo = _depth(phase, kinds, n_max)
    if x_lo < X_MIN:
        raise ValueError(
            f"n_max = {n_max} needs log|E-4| down to about {x_lo:.0f} in {phase}, beyond the "
            f"float64 range of |E-4| (log|E-4| >= {X_MIN:.0f}); use a smaller n_max"
        )
    xs = np.arange(X_START[phase], x_lo - _GRID_STEP, -_GRID_STEP)
    ds = _deltas(phase, xs, executor, progress, f"scan {phase}")
    roots = []
    for kind in kinds:
        found = []
        for c in _TARGETS[(kind, phase)]:
            g = ds - c
            idx = np.nonzero(np.sign(g[:-1]) * np.sign(g[1:]) <= 0)[0]
            for i in idx:
                if g[i] == 0.0 and i > 0 and (g[i - 1] * g[i + 1] > 0):
                    continue  # grid point at a tangency; not a crossing
                if g[i + 1] == 0.0 and i + 1 < len(g) - 1:
                    continue  # counted in the next interval
                found.append((kind, c, xs[i], xs[i + 1], ds[i], ds[i + 1]))
        found.sort(key=lambda r: -r[2])
        roots.extend(found[:n_max])
        if len(found) < n_max:
            raise RuntimeError(
                f"found only {len(found)} {kind} roots in {phase} down to x = {x_lo}"
            )
    return roots, xs, ds


def _make(kind, phase, n, x, c, x_str=None, precision="float64", period_str=""):
    en = pendulum_energy(log_abs_dE=float(x), phase=phase)
    x_str = x_str or f"{float(x):.17g}"
    en = dataclasses.replace(en, given=("log_abs_dE", x_str))
    orb = pendulum(en)
    d = _slope(float(x), phase)
    dtr_dx = 2 * c * d if phase == "lib" else d
    # x = log|E-4|: dx/dE = 1/(E-4) (rot), -1/(4-E) (lib)
    dx_dE = (1.0 / en.eps) if phase == "rot" else (-1.0 / en.eps)
    dtr_dE = dtr_dx * dx_dE
    if kind == "PD" and phase == "lib":
        sense = "stable->stable"
        dtr_dE = 0.0
        dtr_dx = 0.0
    else:  # tr M rising through 4 (IS) destabilises, rising through 0 (PD) stabilises
        up = (dtr_dE > 0) == (kind == "IS")
        sense = "stable->unstable" if up else "unstable->stable"
    return Transition(
        _label(kind, phase, n),
        kind,
        phase,
        n,
        float(x),
        x_str,
        en.E,
        en,
        orb.period,
        c,
        sense,
        float(dtr_dE),
        float(dtr_dx),
        period_str,
        precision,
    )


def transitions(
    phase="both", n_max=20, kinds=("IS", "PD"), executor=None, progress=False
) -> list:
    """All transitions with ``n <= n_max`` of the requested kinds and phases.

    Parameters
    ----------
    phase : {'lib', 'rot', 'both'}
    n_max : int
        1 <= n_max; the deepest root must have ``log|E - 4| >= -700`` (float64
        range), which allows n_max up to ~125 for ``PD^l`` and ``PD^r``.
    kinds : sequence of {'IS', 'PD'}
    executor : concurrent.futures.Executor, optional
        For the grid scan (see :func:`rotorlib.parallel.pmap`); default serial.
    progress : bool

    Returns
    -------
    list of Transition
        Ordered by phase (lib, rot), kind (IS, PD), n. Float64 precision:
        ``log|E-4|`` ~2e-13 absolute, period ~3e-13 absolute. ~1 s for
        ``n_max = 20``, both phases.
    """
    phases = _check_phase(phase)
    if isinstance(kinds, str):
        kinds = (kinds,)
    kinds = tuple(k.upper() if isinstance(k, str) else k for k in kinds)
    if not kinds or any(k not in _KINDS for k in kinds):
        raise ValueError(
            f"kinds must be a non-empty subset of ('IS', 'PD'), got {kinds!r}"
        )
    if isinstance(n_max, bool) or not isinstance(n_max, (int, np.integer)) or n_max < 1:
        raise ValueError(f"n_max must be an integer >= 1, got {n_max!r}")
    out = []
    for ph in phases:
        roots, _, _ = _find(
            ph, tuple(k for k in _KINDS if k in kinds), int(n_max), executor, progress
        )
        for kind in _KINDS:
            rk = [r for r in roots if r[0] == kind]
            for n, (_, c, a, b, fa, fb) in enumerate(rk, start=1):
                x = _refine(ph, c, a, b, fa - c, fb - c)
                out.append(_make(kind, ph, n, x, c))
    return out


def trace_curve(xs, phase, executor=None, progress=False):
    """``tr M`` and the period of the pendulum on a grid of ``x = log|E - 4|`` (float64, ~1e-13).

    Returns
    -------
    (trace, period) : (ndarray, ndarray)
    """
    if phase not in ("lib", "rot"):
        raise ValueError(f"phase must be 'lib' or 'rot', got {phase!r}")
    xs = np.asarray(xs, dtype=float)
    ds = _deltas(phase, xs, executor, progress, f"tr M {phase}")
    per = np.array([pendulum(log_abs_dE=float(x), phase=phase).period for x in xs])
    return trace_of_delta(ds, phase), per


def _check_phase(phase):
    if phase == "both":
        return ("lib", "rot")
    if phase in ("lib", "rot"):
        return (phase,)
    raise ValueError(f"phase must be 'lib', 'rot' or 'both', got {phase!r}")


def refine_mp(x0, phase, target, digits=30, maxiter=10):
    """Re-locate a root of ``Delta = target`` near ``x0`` at ``digits`` precision.

    Chord iteration in mpmath: the slope from one secant over ``h = 1e-7``
    (relative error ~1e-7), then ``x <- x - f(x)/slope`` (each step gains ~7
    digits; robust when ``f`` reaches the noise level of the arithmetic).
    Delta is evaluated with heyoka real128 (``digits <= 31``) or
    multiprecision. Returns ``(x, period)`` as mpmath numbers (``digits + 10``
    working digits).

    Raises
    ------
    RuntimeError
        If the iteration leaves the neighbourhood of ``x0`` (|x - x0| > 1e-6).
    """
    dps = digits + 10
    with mp.workdps(dps):
        x = mp.mpf(x0)
        h = mp.mpf("1e-7")
        f0 = delta_mp(x, phase, digits) - target
        slope = (delta_mp(x + h, phase, digits) - target - f0) / h
        f = f0
        tol = mp.mpf(10) ** (-(digits + 1)) * max(1, abs(x))
        for _ in range(maxiter):
            step = f / slope
            x = x - step
            if abs(x - mp.mpf(x0)) > mp.mpf("1e-6"):
                raise RuntimeError(
                    f"root refinement left the neighbourhood of {x0!r} ({phase})"
                )
            if abs(step) < tol:
                break
            f = delta_mp(x, phase, digits) - target
        return x, _period_mp(x, phase, dps)


def transition(label, digits=None) -> Transition:
    """One transition by its label (``'IS^l_3'``, ``'PDr2'``).

    Parameters
    ----------
    label : str
        See :func:`parse_label`.
    digits : int, optional
        ``None`` or <= 15: float64 (~13 significant digits in ``log|E-4|``).
        16..31: the float64 root re-located with heyoka real128 (secant in
        mpmath), giving ``log_abs_dE_str`` and ``period_str`` with ``digits``
        significant digits (~30 correct); more digits use heyoka multiprecision.

    Raises
    ------
    ValueError
        Bad label, or a transition beyond the float64 range of ``|E - 4|``.
    """
    kind, phase, n = parse_label(label)
    check_digits(digits)
    roots, _, _ = _find(phase, (kind,), n)
    _, c, a, b, fa, fb = roots[n - 1]
    x = _refine(phase, c, a, b, fa - c, fb - c)
    if digits is None or digits <= 15:
        return _make(kind, phase, n, x, c)
    xm, per = refine_mp(x, phase, c, digits=digits)
    with mp.workdps(digits + 10):
        xs = mp.nstr(xm, digits, strip_zeros=False)
        ps = mp.nstr(per, digits, strip_zeros=False)
    prec = "real128" if digits <= 31 else "mp"
    return _make(kind, phase, n, float(xm), c, x_str=xs, precision=prec, period_str=ps)
