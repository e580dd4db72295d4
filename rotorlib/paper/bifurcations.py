"""Stability transitions of pendula: the bifurcation cascade (paper §3 summary and §5).

The transverse stability of the pendulum at ``x = log|E - 4|`` is governed by
``Delta(x)``, the trace of the coefficient-period map of the transverse Hill
(Lamé) problem (:mod:`rotorlib.orbits.hill`): ``tr M = Delta^2`` in libration and
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
consecutive roots of one equation are >= 1.1 apart), sign changes are located
by :func:`locate_root` (the engine's Illinois method,
:func:`rotorlib.orbits.continuation.illinois`: the one locator of ``tr M = 4`` and ``0``,
for pendula and breathers) to ``1e-15`` (absolute), with heyoka's float64
Taylor integrator (~0.1 ms per ``Delta``). :func:`refine_root` locates them again
in an extended tier (the same method on mpmath numbers).

Precision: ``Delta`` is accurate to ~1e-13 absolute at any depth, and
``|dDelta/dx| > 0.5`` at every root, so ``log|E - 4|`` is accurate to ~2e-13
absolute (>= 13 significant digits for ``|x| > 1``; for ``PD^r_1``, at
``x = 0.468``, ~12 digits) and the period, from the closed form
``4K/sqrt3`` (lib) or ``2 kappa K/sqrt3`` (rot), to ~3e-13 absolute.
``tests/test_bifurcations.py`` re-locates every one of the first 80 roots with
heyoka real128 (~32 digits) and checks a few with the textbook 4x4
variational equations in 256-bit arithmetic. ``transition(label, digits=30)``
returns a root refined in real128. The breather's transition ``PD^b``
(:func:`rotorlib.paper.breathers.pd_transition`) is a :class:`Transition` too.
"""

from __future__ import annotations

import dataclasses
import math
import re
from collections.abc import Callable, Sequence
from concurrent.futures import Executor
from dataclasses import dataclass, field
from typing import Any

import mpmath as mp
import numpy as np

from ..core.closed_forms import PendulumOrbit, pendulum
from ..core.energy import BreatherEnergy, PendulumEnergy, pendulum_energy
from ..core.parallel import pmap
from ..core.precision import Tier, json_number, tier
from ..orbits.continuation import illinois
from ..orbits.family import SpecialPoint
from ..orbits.hill import hill_problem, solve_hill
from ..orbits.periodic_orbit import OrbitResult

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
    "refine_root",
    "locate_root",
    "level_crossings",
    "SQRT3_PI",
    "CLASSES",
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
#: ``(x of the first root, asymptotic spacing of the roots)`` of each (kind, phase): in
#: libration one PD per sqrt3 pi and two IS; in rotation two of each per 2 sqrt3 pi.
_FIRST = {
    ("IS", "lib"): (-4.67, SQRT3_PI / 2),
    ("PD", "lib"): (-2.43, SQRT3_PI),
    ("IS", "rot"): (-4.67, SQRT3_PI),
    ("PD", "rot"): (1.0, SQRT3_PI),
}
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


@dataclass(frozen=True, kw_only=True)
class Transition(OrbitResult, SpecialPoint):
    """A stability transition (bifurcation) of the pendulum or of a breather family.

    A :class:`~rotorlib.orbits.family.SpecialPoint` (a subclass: the one special-point
    type, with ``kind``, ``E``, ``E_str``, ``member``, ``located``, ``description``,
    ``rotation``, ``families``) that is also an orbit: it follows the result protocol
    (:class:`~rotorlib.orbits.periodic_orbit.OrbitResult`) for the pendulum or breather
    at the transition, where ``tr M`` is exactly 4 (``IS``) or 0 (``PD``), so
    ``stability`` is ``'marginal'`` and the multipliers are ``(1, 1, 1, 1)`` or ``(1, 1,
    -1, -1)``. Its ``member`` is ``None`` (the orbit is the closed form, on no branch),
    ``families`` the family born there (the newborn ``IS^l_n``, ... or ``PD^b``), and
    its own fields are keyword-only (a subclass of a dataclass with defaults).

    Attributes
    ----------
    label : str
        Paper notation: ``IS^l_3``, ``PD^r_2`` (pendulum), ``PD^b`` (breather R).
    kind : {'IS', 'PD'}
        Isochronous (``tr M = 4``) or period doubling (``tr M = 0``).
    family : {'pendulum', 'R', 'LG', 'LD'}
        The family whose stability changes.
    E, E_str : float, str
        Energy, and as a decimal with every verified digit (pendulum: the digits after
        the leading ``4.000``, ``PendulumEnergy.decimal_E``).
    period, period_str : float, str
        Period of the orbit at ``E`` (pendulum ``4K/sqrt3`` or ``2 kappa K/sqrt3``).
    trace, trace_str : float, str
        ``tr M`` at the transition: 4 or 0 exactly.
    state0, state0_str : ndarray (4,), tuple of str
        State ``[a1, a2, p1, p2]`` of the orbit at the base point G, from the closed
        form (``p2 = sqrt(4E/3)``; breather R: ``p1 = p2 = sqrt(E)``).
    transition : str
        ``stable->unstable``, ``unstable->stable`` or ``stable->stable`` (``PD^l``:
        double zero of ``tr M``), with increasing ``E``.
    slope : float
        ``d tr M / dE`` of the family at the transition (0 for ``PD^l``).
    digits : int
        Significant digits of the strings (15: float64).
    precision : str
        The tier that located the root (``float64``, ``real128``, ``mp<bits>``).
    phase, n : str, int
        ``lib`` or ``rot`` and the index in the paper's numbering (breather: ``rot``, 1).
    log_abs_dE, log_abs_dE_str : float, str
        ``log|E - 4|`` (breathers: ``log|E - 4.5|``); the pendulum's float64 root is
        accurate to ~2e-13 absolute.
    energy : PendulumEnergy or BreatherEnergy
        The energy, carrying ``log_abs_dE_str`` (or ``E_str``) as its decimal input:
        ``monodromy(transition)`` evaluates ``M`` there.
    delta_target : float
        ``Delta`` at the transition (+2, -2 or 0; ``tr M = Delta^2`` in libration,
        ``2 + Delta`` in rotation).
    dtrace_dx : float
        ``d tr M / d log|E - 4|`` (pendulum).

    Examples
    --------
    >>> from rotorlib.paper.bifurcations import transition
    >>> t = transition("IS^l_1")
    >>> t.kind, t.family, t.stability, t.transition, round(t.E, 6)
    ('IS', 'pendulum', 'marginal', 'stable->unstable', 3.990588)
    >>> t.to_dict()["class"], t.trace
    ('IS^l_odd', 4.0)
    """

    label: str
    kind: str
    family: str
    E: float
    E_str: str
    period: float
    period_str: str
    trace: float
    trace_str: str
    state0: np.ndarray
    state0_str: tuple[str, ...]
    transition: str
    slope: float
    digits: int = 15
    precision: str = "float64"
    phase: str = "rot"
    n: int = 1
    log_abs_dE: float = float("nan")
    log_abs_dE_str: str = ""
    energy: PendulumEnergy | BreatherEnergy | None = field(default=None, repr=False)
    delta_target: float = float("nan")
    dtrace_dx: float = float("nan")

    @classmethod
    def at_base_point(
        cls,
        label: str,
        kind: str,
        family: str,
        energy: PendulumEnergy | BreatherEnergy,
        period: tuple[float, str],
        momenta: tuple[str, str],
        transition: str | None,
        slope: float,
        digits: int | None,
        E_str: str,
        **pendulum_only: Any,
    ) -> Transition:
        """The transition of the orbit through G with momenta ``(p1, p2)`` (decimal
        strings) and ``period = (value, string)``; ``digits`` None: float64.
        ``transition`` None: from the sign of ``slope`` (``tr M`` rising through 4
        destabilises, rising through 0 stabilises)."""
        if transition is None:
            up = (slope > 0) == (kind == "IS")
            transition = "stable->unstable" if up else "unstable->stable"
        state0_str = ("0.0", "0.0", *momenta)
        level = 4.0 if kind == "IS" else 0.0
        return cls(
            label=label, kind=kind, family=family, E=energy.E, E_str=E_str,
            period=period[0], period_str=period[1], trace=level, trace_str=repr(level),
            state0=np.array([float(v) for v in state0_str]), state0_str=state0_str,
            transition=transition, slope=slope, digits=digits or 15,
            precision=tier(digits).name, energy=energy,
            located=f"root of tr M = {level:g} ({tier(digits).name})",
            description=f"{kind} of the {'' if family == 'pendulum' else 'breather '}"
            f"{family}: {transition}",
            families=(label,) if label != "IS^b" else (), **pendulum_only,
        )  # fmt: skip

    @property
    def cls(self) -> str:
        """The §5 class: ``IS^l_odd``, ``IS^l_even``, ``PD^l``, ``IS^r_odd``, ...
        (a breather transition: its label)."""
        if self.family != "pendulum":
            return self.label
        if self.kind == "PD" and self.phase == "lib":
            return "PD^l"  # a single class
        return (
            f"{self.kind}^{_PHASE_LETTER[self.phase]}_{'odd' if self.n % 2 else 'even'}"
        )

    @property
    def dtrace_dE(self) -> float:
        """``slope`` (the name of the pendulum's tables)."""
        return self.slope

    def to_dict(self) -> dict[str, Any]:
        """The JSON ``bifurcations --json`` prints (:func:`~rotorlib.core.precision.json_number`:
        float64 values as numbers, more digits in ``*_str`` strings)."""
        rec: dict[str, Any] = {
            "label": self.label,
            "kind": self.kind,
            "family": self.family,
            "phase": self.phase,
            "n": self.n,
            "class": self.cls,
            **json_number("log_abs_dE", self.log_abs_dE, self.log_abs_dE_str),
            **json_number("E", self.E, self.E_str),
            **json_number("period", self.period, self.period_str),
            "trace": self.trace,
            "state0": [float(v) for v in self.state0],
            "multipliers": [[z.real, z.imag] for z in self.multipliers],
            "stability": self.stability,
            "transition": self.transition,
            "delta_target": self.delta_target,
            "slope": self.slope,
            "digits": self.digits,
            "precision": self.precision,
        }
        if self.digits > 15:
            rec["state0_str"] = list(self.state0_str)
        return {
            **rec,
            "located": self.located,
            "description": self.description,
            "families": list(self.families),
        }


_LABEL_RE = re.compile(
    r"^\s*(IS|PD)\s*\^?\s*(l|r|ℓ)\s*_?\s*(\{\s*(\d+)\s*\}|(\d+))\s*$", re.IGNORECASE
)


def parse_label(text: Any) -> tuple[str, str, int]:
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
    n = int(mt.group(4) or mt.group(5))
    if n < 1:
        raise ValueError(f"transition index must be >= 1, got {n} in {text!r}")
    return mt.group(1).upper(), ("rot" if mt.group(2).lower() == "r" else "lib"), n


# --------------------------------------------------------------------------- Delta(x)


def delta(x: float, phase: str) -> float:
    """``Delta`` at ``x = log|E - 4|`` in float64 (~1e-13 absolute; heyoka, else scipy)."""
    prob = hill_problem(pendulum(log_abs_dE=float(x), phase=phase))
    return solve_hill(prob).delta


def trace_of_delta(d: Any, phase: str) -> Any:
    """``tr M`` from ``Delta``: ``Delta^2`` (lib) or ``2 + Delta`` (rot)."""
    return d * d if phase == "lib" else 2 + d


def _mp_pendulum(x: Any, phase: str, dps: int) -> PendulumOrbit:
    """The pendulum at an mpmath/decimal ``x = log|E - 4|``, read at ``dps`` digits."""
    with mp.workdps(dps):
        return pendulum(log_abs_dE=mp.nstr(mp.mpf(x), dps), phase=phase)


def delta_mp(x: Any, phase: str, digits: int = 30) -> Any:
    """``Delta`` at an mpmath/decimal ``x`` in the tier of ``digits`` (heyoka real128 for
    ``digits <= 31``, multiprecision beyond).

    Returns an ``mpmath.mpf`` (caller's working precision should be >= ``digits``).
    The energy is built from ``x`` in mpmath at ``digits + 15`` digits, so no
    float64 rounding enters.
    """
    dps = digits + 15
    prob = hill_problem(_mp_pendulum(x, phase, dps), digits=digits)
    sol = solve_hill(prob, digits)
    with mp.workdps(dps):
        return mp.mpf(sol.delta_exact)


# --------------------------------------------------------------------------- scanning


def _scan_chunk(args):
    """Delta on a grid: module-level so process pools can pickle it."""
    phase, xs = args
    return np.array([delta(x, phase) for x in xs])


def locate_root(
    f: Callable[[Any], Any],
    a: Any,
    b: Any,
    fa: Any,
    fb: Any,
    xtol: Any,
    maxiter: int = 100,
) -> Any:
    """The root of ``f`` between ``a`` and ``b`` (``fa``, ``fb`` of opposite signs) to
    ``|dx| <= xtol``: the engine's Illinois method (:func:`rotorlib.orbits.continuation.illinois`),
    in float64 or in mpmath numbers alike. The one locator of ``tr M = 4`` and ``0`` of
    pendula and breathers.

    Examples
    --------
    >>> round(locate_root(lambda x: x * x - 2, 1.0, 2.0, -1.0, 2.0, 1e-14), 12)
    1.414213562373
    """
    if fa == 0:
        return a
    if fb == 0:
        return b
    return illinois(f, lambda v: a + v, b - a, fa, fb, xtol / abs(b - a), maxiter)


def level_crossings(
    f: Callable[[Any], Any], xs: Any, fs: Any, level: float, xtol: float = 1e-15
) -> list[tuple[int, Any]]:
    """``[(i, x)]``: the roots ``x`` of ``f = level`` between ``xs[i]`` and ``xs[i + 1]``,
    wherever the tabulated ``fs = f(xs)`` crosses ``level`` (a grid value on the level is
    one crossing, a tangency none), each located by :func:`locate_root` to ``xtol``. The
    one scan of ``tr M`` (or ``Delta``) of pendula and breathers.

    Examples
    --------
    >>> xs = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0]
    >>> fs = [math.cos(x) for x in xs]
    >>> [(i, round(float(x), 12)) for i, x in level_crossings(math.cos, xs, fs, 0.0)]
    [(1, 1.570796326795), (4, 4.712388980385)]
    """
    g = np.asarray(fs) - level
    out = []
    for i in np.nonzero(np.sign(g[:-1]) * np.sign(g[1:]) <= 0)[0]:
        if g[i] == 0.0 and i > 0 and (g[i - 1] * g[i + 1] > 0):
            continue  # grid point at a tangency; not a crossing
        if g[i + 1] == 0.0 and i + 1 < len(g) - 1:
            continue  # counted in the next interval
        out.append(
            (
                int(i),
                locate_root(
                    lambda v: f(v) - level, xs[i], xs[i + 1], g[i], g[i + 1], xtol
                ),
            )
        )
    return out


def refine_root(
    f: Callable[[Any], Any],
    x0: Any,
    digits: int,
    h: float = 1e-11,
    reach: float = 1e-6,
    maxiter: int = 100,
) -> Any:
    """Re-locate the root of ``f`` near the float64 root ``x0`` to ``digits`` significant
    digits: ``f`` (evaluated in an extended tier, on mpmath numbers at ``digits + 10``
    working digits) is bracketed on ``x0 -+ h max(1, |x0|)`` (widened 100-fold until
    its signs differ, at most to ``reach``) and the root located there by
    :func:`locate_root` to ``10^-(digits + 1) max(1, |x0|)``. Returns an mpf.

    Raises
    ------
    RuntimeError
        No sign change within ``x0 -+ reach max(1, |x0|)``.
    """
    with mp.workdps(digits + 10):
        x0 = mp.mpf(x0)
        scale = max(mp.mpf(1), abs(x0))
        w = mp.mpf(h)
        while True:
            a, b = x0 - w * scale, x0 + w * scale
            fa, fb = f(a), f(b)
            if fa * fb <= 0:
                break
            w *= 100
            if w > reach:
                raise RuntimeError(f"root refinement found no root near {x0}")
        return locate_root(
            f, a, b, fa, fb, mp.mpf(10) ** (-(digits + 1)) * scale, maxiter
        )


def _slope(x, phase, h=1e-4):
    """dDelta/dx by a 4-point centred difference (relative error ~1e-9)."""
    d = [delta(x + k * h, phase) for k in (-2, -1, 1, 2)]
    return (d[0] - 8 * d[1] + 8 * d[2] - d[3]) / (12 * h)


def _deltas(phase, xs, executor, progress, desc):
    """``Delta`` on the grid ``xs`` (float64), in chunks through :func:`pmap`."""
    chunks = np.array_split(xs, max(1, min(16, len(xs) // 200)))
    return np.concatenate(
        pmap(
            _scan_chunk,
            [(phase, c) for c in chunks],
            executor=executor,
            progress=progress,
            desc=desc,
        )
    )


def _roots(phase, kinds, n_max, executor=None, progress=False):
    """``[(kind, n, target, x)]``: the float64 roots ``x`` of ``Delta = target`` in one
    phase with ``n <= n_max`` for each kind, in the order of ``kinds``, then ``n``."""
    # the deepest x needed, from the first root and the asymptotic spacing, plus margin
    x_lo = min(
        0.0,
        *(
            x1 - (n_max + 1) * per - 2.0
            for x1, per in (_FIRST[k, phase] for k in kinds)
        ),
    )
    if x_lo < X_MIN:
        raise ValueError(
            f"n_max = {n_max} needs log|E-4| down to about {x_lo:.0f} in {phase}, beyond the "
            f"float64 range of |E-4| (log|E-4| >= {X_MIN:.0f}); use a smaller n_max"
        )
    xs = np.arange(X_START[phase], x_lo - _GRID_STEP, -_GRID_STEP)
    ds = _deltas(phase, xs, executor, progress, f"scan {phase}")
    roots = []
    for kind in kinds:
        found = sorted(
            (i, c, x)
            for c in _TARGETS[(kind, phase)]
            for i, x in level_crossings(lambda v: delta(v, phase), xs, ds, c)
        )
        if len(found) < n_max:
            raise RuntimeError(
                f"found only {len(found)} {kind} roots in {phase} down to x = {x_lo}"
            )
        roots += [(kind, n, c, x) for n, (_, c, x) in enumerate(found[:n_max], 1)]
    return roots


def _make(
    kind: str,
    phase: str,
    n: int,
    x: Any,
    c: float,
    digits: int | None = None,
) -> Transition:
    """The transition at the root ``x`` of ``Delta = c`` (float64, or an mpf of ``digits``
    digits)."""
    x_str = (
        f"{float(x):.17g}" if digits is None else mp.nstr(x, digits, strip_zeros=False)
    )
    en = dataclasses.replace(
        pendulum_energy(log_abs_dE=float(x), phase=phase), given=("log_abs_dE", x_str)
    )
    orb = pendulum(en)
    d = _slope(float(x), phase)
    dtr_dx = 2 * c * d if phase == "lib" else d
    # x = log|E-4|: dx/dE = 1/(E-4) (rot), -1/(4-E) (lib)
    dtr_dE = dtr_dx * ((1.0 / en.eps) if phase == "rot" else (-1.0 / en.eps))
    sense = None  # from the slope
    if kind == "PD" and phase == "lib":  # a double zero of tr M
        sense, dtr_dE, dtr_dx = "stable->stable", 0.0, 0.0
    if digits is None:
        per_s, p2_s = repr(orb.period), repr(float(orb.state0[3]))
    else:
        dps = digits + 10
        with mp.workdps(dps):
            per_s = mp.nstr(orb.closed_form(dps)["period"], digits, strip_zeros=False)
            E = en.mp_E_eps(dps)[0]
            p2_s = mp.nstr(mp.sqrt(4 * E / 3), digits, strip_zeros=False)
    return Transition.at_base_point(
        f"{kind}^{_PHASE_LETTER[phase]}_{n}", kind, "pendulum", en, (orb.period, per_s), ("0.0", p2_s),
        sense, float(dtr_dE), digits, en.decimal_E(digits or 15), phase=phase, n=n,
        log_abs_dE=float(x), log_abs_dE_str=x_str, delta_target=c,
        dtrace_dx=float(dtr_dx),
    )  # fmt: skip


def transitions(
    phase: str = "both",
    n_max: int = 20,
    kinds: str | Sequence[str] = ("IS", "PD"),
    executor: Executor | None = None,
    progress: bool = False,
) -> list[Transition]:
    """All transitions with ``n <= n_max`` of the requested kinds and phases.

    Parameters
    ----------
    phase : {'lib', 'rot', 'both'}
    n_max : int
        1 <= n_max; the deepest root must have ``log|E - 4| >= -700`` (float64
        range), which allows n_max up to ~125 for ``PD^l`` and ``PD^r``.
    kinds : sequence of {'IS', 'PD'}
    executor : concurrent.futures.Executor, optional
        For the grid scan (see :func:`rotorlib.core.parallel.pmap`); default serial.
    progress : bool

    Returns
    -------
    list of Transition
        Ordered by phase (lib, rot), kind (IS, PD), n. Float64 precision:
        ``log|E-4|`` ~2e-13 absolute, period ~3e-13 absolute. ~1 s for
        ``n_max = 20``, both phases.
    """
    phases = {"lib": ("lib",), "rot": ("rot",), "both": ("lib", "rot")}.get(phase)
    if phases is None:
        raise ValueError(f"phase must be 'lib', 'rot' or 'both', got {phase!r}")
    if isinstance(kinds, str):
        kinds = (kinds,)
    kinds = tuple(k.upper() if isinstance(k, str) else k for k in kinds)
    if not kinds or any(k not in _KINDS for k in kinds):
        raise ValueError(
            f"kinds must be a non-empty subset of ('IS', 'PD'), got {kinds!r}"
        )
    if isinstance(n_max, bool) or not isinstance(n_max, (int, np.integer)) or n_max < 1:
        raise ValueError(f"n_max must be an integer >= 1, got {n_max!r}")
    return [
        _make(kind, ph, n, x, c)
        for ph in phases
        for kind, n, c, x in _roots(
            ph, tuple(k for k in _KINDS if k in kinds), int(n_max), executor, progress
        )
    ]


def trace_curve(
    xs: Any, phase: str, executor: Executor | None = None, progress: bool = False
) -> tuple[np.ndarray, np.ndarray]:
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


def refine_mp(
    x0: Any, phase: str, target: float, digits: int = 30, maxiter: int = 100
) -> tuple[Any, Any]:
    """Re-locate a root of ``Delta = target`` near ``x0`` at ``digits`` precision.

    :func:`refine_root` with ``Delta`` from :func:`delta_mp` (heyoka real128 for
    ``digits <= 31``, multiprecision beyond). Returns ``(x, period)`` as mpmath numbers
    (``digits + 10`` working digits).

    Raises
    ------
    RuntimeError
        No root of ``Delta = target`` within ``1e-6 max(1, |x0|)`` of ``x0``.
    """
    x = refine_root(
        lambda v: delta_mp(v, phase, digits) - target, x0, digits, maxiter=maxiter
    )
    dps = digits + 10
    with mp.workdps(dps):
        return x, _mp_pendulum(x, phase, dps).closed_form(dps)["period"]


def transition(label: str, *, digits: int | Tier | None = None) -> Transition:
    """One transition of the pendulum by its label (``'IS^l_3'``, ``'PDr2'``); the
    breather's, ``PD^b``, is :func:`rotorlib.paper.breathers.pd_transition` (the front
    door's :func:`rotorlib.transition` serves both).

    Parameters
    ----------
    label : str
        ``IS^l_n``, ``PD^l_n``, ``IS^r_n``, ``PD^r_n`` (:func:`parse_label`).
    digits : int or Tier, optional
        ``None`` or <= 15: float64 (pendulum: ~13 significant digits in ``log|E-4|``).
        More: the float64 root re-located in the tier of ``digits`` (heyoka real128 up
        to 31, multiprecision beyond) by :func:`refine_root`; the strings carry
        ``digits`` significant digits.

    Raises
    ------
    ValueError
        Bad label (the message names the accepted forms), or a pendulum transition
        beyond the float64 range of ``|E - 4|``.

    Examples
    --------
    >>> from rotorlib.paper.bifurcations import transition
    >>> t = transition("PD^r_1", digits=20)
    >>> t.label, t.kind, t.precision, t.log_abs_dE_str
    ('PD^r_1', 'PD', 'real128', '0.46821542651777454106')
    >>> t.E_str
    '5.59714143224631939243'
    """
    t = tier(digits)  # a Tier delivers the digits its working digits keep, less 9
    d = None if not t.extended else (digits if isinstance(digits, int) else t.dps - 9)
    try:
        kind, phase, n = parse_label(label)
    except ValueError as exc:
        raise ValueError(
            f"{exc}; the pendulum's transitions are IS^l_n, PD^l_n, IS^r_n, PD^r_n "
            "(n >= 1; ASCII 'ISl3', 'PDr2' too)"
        ) from None
    _, _, c, x = _roots(phase, (kind,), n)[n - 1]
    if d is not None:  # the float64 root re-located in the tier of d digits
        x, _ = refine_mp(x, phase, c, digits=d)
    return _make(kind, phase, n, x, c, d)
