"""Gutzwiller's trace formula with its phases: action, Maslov index, amplitude, symmetry.

For a periodic orbit ``p`` of period ``T_p`` at energy ``E`` the oscillating level density
of the whole spectrum (every sector, with multiplicities) is

    rho_osc(E) = (1/pi hbar) sum_p sum_(r >= 1) g_p T_p / sqrt|det(M_p^r - 1)|
                 * cos(r S_p / hbar - sigma_(p,r) pi/2)

with ``S_p = oint p . dq`` (:func:`orbit_action`), ``sigma_{p,r}`` the Maslov index of the
``r``-th repetition (:func:`maslov_index`), ``M_p`` the 2x2 reduced monodromy
(``|det(M - 1)| = |4 - tr M|`` with the full 4x4 trace) and ``g_p`` the number of distinct
images of the orbit under the 12 symmetries and time reversal.

**The Maslov index.** The linearised flow transverse to the orbit, on the energy shell, is a
path ``m(t)`` in ``Sp(2)`` from ``m(0) = 1`` to the reduced monodromy. It is written in a
frame that exists for every orbit (the flow vector ``f = (q', p')`` never vanishes): with
``z = q + i p`` and ``f`` read as a vector of ``C^2``, the complex line orthogonal to ``f``
is a symplectic plane transverse to the orbit on the shell, spanned by ``e1 = u`` and
``e2 = i u`` with ``u = (-conj f2, conj f1)/|f|``. The index is the Conley-Zehnder index of
``m(t)`` (Creagh, Robbins and Littlejohn, Phys. Rev. A 42, 1907 (1990); Sugita, Ann. Phys.
288, 277 (2001)): with ``theta(t)`` the continuous angle of the rotation part of ``m(t)``
(``-arg((a + d) + i (c - b))``, positive in the sense in which a positive kinetic energy
turns ``(q, p)``),

* hyperbolic end (``|tr m| > 2``): ``sigma = round(theta(T)/pi)``, ``sigma_r = r sigma``;
* elliptic end: the total rotation angle ``chi`` (in the same interval of length
  ``2 pi`` as ``theta(T)``), ``sigma_r = 2 floor(r chi / 2 pi) + 1``.

A libration (a brake orbit) turns ``f`` once, and with it the frame: it adds 2 to the
index, the two turning points of the one-dimensional rule; a rotation adds 0. For the
two-dimensional harmonic oscillator this gives the exact ``sigma_r = 2r + 2 floor(r omega_2
T/2 pi) + 1`` (``tests/test_quantum_trace.py``); for the pendulum the index is
``2 + (Hill's index of the transverse equation)`` (libration) or the latter alone (rotation).

**Precision.** The path is sampled at ``n`` equal steps (refined where ``theta`` turns by
more than 0.5 rad in a step); the index is an integer and is exact as long as the reduced
monodromy is not within ~1e-10 of marginal (``tr M = 4``, or ``tr M = 0`` for odd
repetitions of elliptic orbits), where it is undefined and a uniform approximation is
needed. The action is a trapezoid sum of the periodic integrand ``2 (E - V)``: spectrally
accurate, ~1e-13 relative with the default samples.

The signals (quantum and predicted) are in :mod:`rotorlib.beyond.quantum_signals`, the
tests of significance in :mod:`rotorlib.beyond.quantum_significance`.

**Symmetry.** :func:`orbit_symmetry` finds the group elements that map an orbit to itself
(with a time shift, or reversed in time); the orbit's images number ``24 / |stabiliser|``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

__all__ = [
    "check_positive",
    "transverse_frame",
    "transverse_path",
    "conley_zehnder",
    "maslov_index",
    "orbit_action",
    "pendulum_action",
    "OrbitTerm",
    "orbit_term",
    "orbit_symmetry",
    "CHARACTERS",
    "element_class",
    "reflection_term",
    "mirror_classes",
]


def check_positive(x: Any, name: str) -> float:
    """``float(x)``, or ValueError naming ``name`` unless it is positive and finite.

    Examples
    --------
    >>> check_positive(2, "hbar")
    2.0
    """
    x = float(x)
    if not (math.isfinite(x) and x > 0):
        raise ValueError(f"{name} must be positive and finite, not {x}")
    return x


def _state(x0):
    x = np.asarray(x0, float)
    if x.shape != (4,) or not np.all(np.isfinite(x)):
        raise ValueError(
            f"state0 must be 4 finite numbers [a1, a2, p1, p2], not {x0!r}"
        )
    return x


def transverse_frame(f: ArrayLike) -> np.ndarray:
    """Rows ``e1, e2``: the symplectic frame transverse to the flow vector
    ``f = (q1', q2', p1', p2')`` (module docstring): orthonormal, orthogonal to ``f`` and
    to ``J f``, ``omega(e1, e2) = 1``.

    Examples
    --------
    >>> e = transverse_frame([1.0, 0.0, 0.0, 0.0])
    >>> (e + 0.0).tolist()
    [[0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]]
    """
    f = np.asarray(f, float)
    if f.shape != (4,) or not np.all(np.isfinite(f)) or not np.any(f):
        raise ValueError(f"f must be a finite nonzero 4-vector, not {f!r}")
    z = f[:2] + 1j * f[2:]
    u = np.array([-np.conj(z[1]), np.conj(z[0])]) / np.linalg.norm(f)
    e1 = np.concatenate([u.real, u.imag])
    e2 = np.concatenate([(1j * u).real, (1j * u).imag])
    return np.array([e1, e2])


def _frame(x: np.ndarray) -> np.ndarray:
    from ..core.system import rhs_alpha

    return transverse_frame(np.asarray(rhs_alpha(0.0, x), float))


def _angle(m: np.ndarray) -> float:
    """Angle of the rotation part of ``m`` in ``(-pi, pi]``, clockwise in ``(q, p)``."""
    return -math.atan2(m[1, 0] - m[0, 1], m[0, 0] + m[1, 1])


def transverse_path(
    state0: ArrayLike, period: float, n: int = 200, max_turn: float = 0.5
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The reduced linearised flow ``m(t)`` along an orbit and its continuous angle.

    Returns ``(t, m, theta)``: the sample times (``0 .. period``), the 2x2 matrices
    ``m(t)`` in the transverse frame (module docstring; ``det m = 1``,
    ``tr m(T) = tr M - 2``) and ``theta(t)``, continuous, ``theta(0) = 0``. A step over
    which ``theta`` turns by more than ``max_turn`` is halved (at most 12 times).

    Examples
    --------
    >>> t, m, th = transverse_path([0.0, 0.0, 0.0, 2.0], 3.0, n=50)  # a pendulum arc
    >>> m.shape, round(float(np.linalg.det(m[-1])), 9)
    ((51, 2, 2), 1.0)
    """
    from ..core.flow import flow

    x = _state(state0)
    T = check_positive(period, "period")
    if not (isinstance(n, (int, np.integer)) and n >= 4):
        raise ValueError(f"n must be an integer >= 4, not {n!r}")
    F0 = _frame(x).T  # columns e1(0), e2(0)
    Phi = np.eye(4)
    times, mats, thetas = [0.0], [np.eye(2)], [0.0]
    t, dt0 = 0.0, T / n
    while t < T * (1 - 1e-14):
        dt = min(dt0, T - t)
        for _ in range(13):
            y, P = flow(x, dt, variational=True)
            y = np.array([float(v) for v in y])
            Phi_new = np.array([[float(v) for v in row] for row in P]) @ Phi
            m = _frame(y) @ Phi_new @ F0
            turn = _angle(m) - thetas[-1]
            turn = (turn + math.pi) % (2 * math.pi) - math.pi
            if abs(turn) <= max_turn or dt < dt0 / 4096:
                break
            dt *= 0.5
        x, Phi, t = y, Phi_new, t + dt
        times.append(t)
        mats.append(m)
        thetas.append(thetas[-1] + turn)
    return np.array(times), np.array(mats), np.array(thetas)


def conley_zehnder(mats: ArrayLike, repetitions: int = 1) -> tuple[int, ...]:
    """The indices ``sigma_1 .. sigma_R`` of a sampled path ``m(t)`` in ``Sp(2)`` from
    the identity (shape ``(n, 2, 2)``; consecutive samples must turn by less than
    ``pi/2``), read with the rules of the module docstring.

    Examples
    --------
    >>> c = lambda a: [[math.cos(a), math.sin(a)], [-math.sin(a), math.cos(a)]]
    >>> conley_zehnder([c(a) for a in np.linspace(0, 7.0, 50)], 2)  # rotation by 7
    (3, 5)
    """
    m = np.asarray(mats, float)
    if m.ndim != 3 or m.shape[1:] != (2, 2) or len(m) < 2 or not np.all(np.isfinite(m)):
        raise ValueError("mats must be a finite array of shape (n >= 2, 2, 2)")
    if not (isinstance(repetitions, (int, np.integer)) and repetitions >= 1):
        raise ValueError(f"repetitions must be an integer >= 1, not {repetitions!r}")
    a = np.array([_angle(x) for x in m])
    d = (np.diff(a) + math.pi) % (2 * math.pi) - math.pi
    theta = a[0] + float(np.sum(d))
    if abs(float(np.trace(m[-1])) - 2.0) < 1e-10:
        raise ValueError("a marginal end (tr m = 2) has no index")
    return tuple(_index(theta, m[-1], r)[0] for r in range(1, repetitions + 1))


def _index(theta_T: float, m_T: np.ndarray, r: int) -> tuple[int, float]:
    tr = float(m_T[0, 0] + m_T[1, 1])
    if abs(tr) > 2.0:
        s = int(round(theta_T / math.pi))
        return r * s, float("nan")
    a0 = math.acos(tr / 2.0)
    alpha = a0 if m_T[1, 0] < 0 else 2 * math.pi - a0  # clockwise rotation in (0, 2 pi)
    chi = 2 * math.pi * math.floor(theta_T / (2 * math.pi)) + alpha
    return 2 * math.floor(r * chi / (2 * math.pi)) + 1, chi


def maslov_index(
    state0: ArrayLike, period: float, repetitions: int = 1, n: int = 200
) -> tuple[int, ...]:
    """The Maslov indices ``sigma_1 .. sigma_R`` of the first ``R = repetitions``
    repetitions of a periodic orbit (module docstring).

    Raises ValueError for a marginal orbit (``|tr m(T) - 2| < 1e-10``).

    Examples
    --------
    >>> import rotorlib
    >>> o = rotorlib.orbit("pendulum", 6.0)  # rotation: no turning point
    >>> maslov_index(o.state0, o.period, 2)  # turns by less than pi
    (1, 1)
    """
    if not (isinstance(repetitions, (int, np.integer)) and repetitions >= 1):
        raise ValueError(f"repetitions must be an integer >= 1, not {repetitions!r}")
    _, m, theta = transverse_path(state0, period, n)
    tr = float(np.trace(m[-1]))
    if abs(tr - 2.0) < 1e-10:
        raise ValueError(
            f"a marginal orbit (tr of the reduced monodromy {tr!r} = 2) has no Maslov index"
        )
    return tuple(_index(theta[-1], m[-1], r)[0] for r in range(1, repetitions + 1))


def orbit_action(state0: ArrayLike, period: float, n: int | None = None) -> float:
    """``S = oint p . dq = int_0^T 2 (E - V) dt`` over one period.

    The integrand is smooth and periodic, so the trapezoid sum on ``n`` equal steps
    (default ``max(2000, 400 T)``) converges geometrically: ~1e-13 relative.

    Examples
    --------
    >>> import rotorlib
    >>> o = rotorlib.orbit("pendulum", 2.0)
    >>> bool(abs(orbit_action(o.state0, o.period) - pendulum_action(2.0)) < 1e-11)
    True
    """
    from ..core.flow import states_at
    from ..core.system import energy_alpha, potential_alpha

    x = _state(state0)
    T = check_positive(period, "period")
    n = int(max(2000, 400 * T)) if n is None else int(n)
    if n < 8:
        raise ValueError(f"n must be at least 8, not {n}")
    E = float(energy_alpha(x))
    st = states_at(x, np.linspace(0.0, T, n + 1))[:-1]
    return float(T * np.mean(2.0 * (E - potential_alpha(st[:, 0], st[:, 1]))))


def pendulum_action(E: float) -> float:
    """Closed form of the pendulum's action (``a1 = 0``, ``E = 3 p2^2/4 + 2 - 2 cos a2``).

    Libration (``0 < E < 4``, ``m = E/4``): ``S = (32/sqrt 3)(E(m) - (1 - m) K(m))``;
    rotation (``E > 4``, ``m = 4/E``): ``S = (8 sqrt(E)/sqrt 3) E(m)`` (one turn of
    ``a2``). ``dS/dE`` is the period. Evaluated in mpmath at 30 digits (the libration's
    difference cancels like ``m`` near the bottom) and rounded: float64 accurate for every
    ``E``; at ``|E - 4| < 1e-25`` the input's own rounding dominates.

    Examples
    --------
    >>> round(pendulum_action(1e-8) / (2 * math.pi * 1e-8 / math.sqrt(3)), 6)  # E/omega
    1.0
    """
    import mpmath as mp

    E = check_positive(E, "E")
    if E == 4.0:
        raise ValueError("the separatrix E = 4 is not a periodic orbit")
    with mp.workdps(30):
        e = mp.mpf(E)
        if E < 4.0:
            m = e / 4
            val = 32 / mp.sqrt(3) * (mp.ellipe(m) - (1 - m) * mp.ellipk(m))
        else:
            val = 8 * mp.sqrt(e / 3) * mp.ellipe(4 / e)
        return float(val)


@dataclass(frozen=True)
class OrbitTerm:
    """One periodic orbit as it enters the trace formula.

    ``label``, ``E``, ``period`` (``T_p``), ``action`` (``S_p``), ``trace`` (full 4x4
    ``tr M``), ``maslov`` (``sigma_r`` for ``r = 1 ..``), ``copies`` (``g_p``),
    ``stabiliser`` (the symmetries that map the orbit to itself, as strings, see
    :func:`orbit_symmetry`), ``period_slope`` (``dT/dE``, nan if unknown), and for an
    orbit that lies in mirrors: their classes (``mirrors``, :func:`mirror_classes`) and
    the relative orbit's ``1/sqrt|2 + tr M^r|`` and index (:func:`reflection_term`).
    """

    label: str
    E: float
    period: float
    action: float
    trace: float
    maslov: tuple[int, ...]
    copies: int = 1
    stabiliser: tuple[str, ...] = ()
    period_slope: float = float("nan")
    extra: dict[str, Any] = field(default_factory=dict)
    mirrors: tuple[str, ...] = ()
    mirror_amplitude: tuple[float, ...] = ()
    mirror_maslov: tuple[int, ...] = ()

    def amplitude(self, r: int = 1) -> float:
        """``g_p T_p / sqrt|det(M_p^r - 1)|``."""
        from .quantum_semiclassics import gutzwiller_amplitude

        return self.copies * gutzwiller_amplitude(self.period, self.trace, r)

    @property
    def stability(self) -> str:
        return "stable" if abs(self.trace - 2.0) < 2.0 else "unstable"

    def to_dict(self) -> dict[str, Any]:
        return {
            "label": self.label,
            "E": self.E,
            "period": self.period,
            "action": self.action,
            "trace": self.trace,
            "maslov": list(self.maslov),
            "copies": self.copies,
            "stabiliser": list(self.stabiliser),
            "period_slope": self.period_slope,
            "extra": self.extra,
            "mirrors": list(self.mirrors),
            "mirror_amplitude": list(self.mirror_amplitude),
            "mirror_maslov": list(self.mirror_maslov),
        }

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> OrbitTerm:
        return cls(
            label=d["label"],
            E=float(d["E"]),
            period=float(d["period"]),
            action=float(d["action"]),
            trace=float(d["trace"]),
            maslov=tuple(int(v) for v in d["maslov"]),
            copies=int(d["copies"]),
            stabiliser=tuple(d.get("stabiliser", ())),
            period_slope=float(d.get("period_slope") or float("nan")),
            extra=dict(d.get("extra", {})),
            mirrors=tuple(d.get("mirrors", ())),
            mirror_amplitude=tuple(float(v) for v in d.get("mirror_amplitude", ())),
            mirror_maslov=tuple(int(v) for v in d.get("mirror_maslov", ())),
        )


def orbit_term(
    label: str,
    E: float,
    period: float,
    state0: ArrayLike,
    trace: float,
    repetitions: int = 3,
    n: int = 200,
) -> OrbitTerm:
    """Action, Maslov indices, symmetry and copies of one orbit: an :class:`OrbitTerm`.

    Examples
    --------
    >>> import rotorlib
    >>> o = rotorlib.orbit("pendulum", 6.0)
    >>> t = orbit_term("pendulum", 6.0, o.period, o.state0, o.trace, 2)
    >>> t.maslov, t.copies
    ((1, 1), 6)
    """
    x = _state(state0)
    T = check_positive(period, "period")
    sigma = maslov_index(x, T, repetitions, n)
    stab = orbit_symmetry(x, T)
    mirrors = mirror_classes(x, T)
    m_amp: tuple[float, ...] = ()
    m_sig: tuple[int, ...] = ()
    e = _frame(x)
    if mirrors and max(np.abs(e[0, 2:]).max(), np.abs(e[1, :2]).max()) < 1e-12:
        _, m, _ = transverse_path(x, T, n)  # e1: a position, e2: its momentum
        m_amp, m_sig = reflection_term(m[-1], sigma)
    else:
        mirrors = ()  # the start point does not split position and momentum
    return OrbitTerm(
        label=str(label),
        E=float(E),
        period=T,
        action=orbit_action(x, T),
        trace=float(trace),
        maslov=sigma,
        copies=24 // len(stab),
        stabiliser=stab,
        mirrors=mirrors,
        mirror_amplitude=m_amp,
        mirror_maslov=m_sig,
    )


def orbit_symmetry(
    state0: ArrayLike, period: float, n: int = 4001, tol: float = 0.02
) -> tuple[str, ...]:
    """The stabiliser of an orbit in (symmetry group) x (time reversal).

    Returns the names ``g<k>`` (element ``k`` of
    :func:`rotorlib.orbits.reversors.symmetry_group`) and ``Tg<k>``
    (``g`` composed with time reversal) of the images ``g x0`` that lie on the orbit
    (within ``tol`` on ``n`` samples; distinct images are O(1) apart). The orbit has
    ``24 / len`` distinct images, each entering the trace formula with the same terms;
    a sector ``Gamma`` of the group sees the orbit through the characters of its
    stabiliser (the stabiliser is also the set of ``g`` for which a fraction ``T/k`` of
    the orbit closes up to ``g``).

    Examples
    --------
    >>> import rotorlib
    >>> o = rotorlib.orbit("pendulum", 3.0)
    >>> len(orbit_symmetry(o.state0, o.period))  # a libration: 8 of the 24, 3 images
    8
    """
    from ..core.flow import sample
    from ..orbits.reversors import images, symmetry_group

    group = symmetry_group()
    k_id = next(k for k, g in enumerate(group) if np.allclose(g, np.eye(2)))
    pairs = [(k, s) for k in range(len(group)) for s in (0, 1)]  # images()' order
    names = [("Tg" if s else "g") + str(k) for k, s in pairs]
    names = [names[2 * k_id]] + [n for i, n in enumerate(names) if i != 2 * k_id]
    x0 = _state(state0)
    pts, _ = sample(x0, check_positive(period, "period"), n)
    out = []
    for k, y in enumerate(images(x0)):
        d = pts - y
        j = np.rint(d[:, 0] / math.pi)
        d0, d1 = d[:, 0] - j * math.pi, d[:, 1] - j * math.pi
        d1 = d1 - 2 * math.pi * np.rint(d1 / (2 * math.pi))
        dist = np.sqrt(d0**2 + d1**2 + (d[:, 2:] ** 2).sum(axis=1))
        if dist.min() < tol:
            out.append(names[k])
    return tuple(out) if out else (names[0],)


# --------------------------------------------------------------------------------------
# symmetry sectors

#: Characters of the six sectors of ``S3 x Z2`` on the classes of ``C6v`` (chapter 11):
#: ``E`` identity, ``C6``/``C3`` the rotations of order 6/3, ``C2`` = -1, ``sv`` the
#: transpositions of two rotors, ``sd`` a transposition times the reflection.
CHARACTERS = {
    "A1": {"E": 1, "C6": 1, "C3": 1, "C2": 1, "sv": 1, "sd": 1},
    "A2": {"E": 1, "C6": 1, "C3": 1, "C2": 1, "sv": -1, "sd": -1},
    "B1": {"E": 1, "C6": -1, "C3": 1, "C2": -1, "sv": 1, "sd": -1},
    "B2": {"E": 1, "C6": -1, "C3": 1, "C2": -1, "sv": -1, "sd": 1},
    "E1": {"E": 2, "C6": 1, "C3": -1, "C2": -2, "sv": 0, "sd": 0},
    "E2": {"E": 2, "C6": -1, "C3": -1, "C2": 2, "sv": 0, "sd": 0},
}


def element_class(g: Any) -> str:
    """The class (a key of :data:`CHARACTERS`) of a symmetry ``g`` acting on
    ``(phi1, phi2) = (theta1 - theta2, theta2 - theta3)``.

    Examples
    --------
    >>> element_class([[-1, 0], [1, 1]]), element_class([[1, 0], [-1, -1]])  # swap 1, 2
    ('sv', 'sd')
    """
    g = np.rint(np.asarray(g, dtype=float)).astype(int)
    if g.shape != (2, 2) or abs(round(float(np.linalg.det(g)))) != 1:
        raise ValueError(
            f"g must be an integer 2x2 matrix of determinant +-1, not {g!r}"
        )
    tr, det = int(np.trace(g)), int(round(float(np.linalg.det(g))))
    if det == 1:
        return {2: "E", 1: "C6", -1: "C3", -2: "C2"}[tr]
    # a transposition of two rotors maps the differences (phi1, phi2, phi3 = -phi1 - phi2)
    # to minus a permutation of them; with the reflection theta -> -theta, to a permutation
    phi = np.array([[1, 0], [0, 1], [-1, -1]])
    images = {tuple(r) for r in phi @ g}
    return "sv" if images == {tuple(-r) for r in phi} else "sd"


def reflection_term(
    monodromy: ArrayLike, maslov: Sequence[int]
) -> tuple[tuple[float, ...], tuple[int, ...]]:
    """The relative orbit of a reflection that fixes a periodic orbit pointwise.

    ``monodromy``: the orbit's 2x2 reduced monodromy in coordinates ``(q_perp, p_perp)``
    across the mirror at the start point; ``maslov``: its indices ``sigma_r``. The
    reflection maps ``(q_perp, p_perp)`` to minus themselves, so the relative monodromy
    of ``r`` turns is ``-M^r``: ``|det(-M^r - 1)| = |2 + tr M^r|``, and the index differs
    from ``sigma_r`` only through Gutzwiller's stationary-phase term (0 or 1 as
    ``(tr - 2)/m_12`` is positive or negative): ``sigma~_r = sigma_r + nu(-M^r) - nu(M^r)``.
    Returns ``(1/sqrt|2 + tr M^r|, sigma~_r)`` for ``r = 1 .. len(maslov)``.

    Examples
    --------
    >>> c, s = math.cos(1.0), math.sin(1.0)  # an elliptic orbit turning by 1 radian
    >>> amp, sig = reflection_term([[c, s], [-s, c]], [1])
    >>> round(amp[0], 6), sig
    (0.569747, (0,))
    """
    M = np.asarray(monodromy, float)
    if M.shape != (2, 2) or not np.all(np.isfinite(M)):
        raise ValueError("monodromy must be a finite 2x2 matrix")
    amps, sig = [], []
    for r, s in enumerate(maslov, start=1):
        Mr = np.linalg.matrix_power(M, r)
        tr, m12 = float(np.trace(Mr)), float(Mr[0, 1])
        if m12 == 0 or abs(tr + 2) < 1e-12:
            raise ValueError(f"repetition {r}: the relative orbit is marginal")
        nu, nu_t = (tr - 2) / m12 < 0, (tr + 2) / m12 < 0
        amps.append(1.0 / math.sqrt(abs(2.0 + tr)))
        sig.append(int(s) + int(nu_t) - int(nu))
    return tuple(amps), tuple(sig)


def mirror_classes(
    state0: ArrayLike, period: float, tol: float = 1e-9
) -> tuple[str, ...]:
    """Classes of the reflections that fix an orbit pointwise (``g x(t) = x(t)`` for all
    ``t``, up to the lattice), one entry per such reflection.

    Examples
    --------
    >>> import rotorlib
    >>> o = rotorlib.orbit("pendulum", 5.45)
    >>> mirror_classes(o.state0, o.period)
    ('sv',)
    """
    from ..core.flow import sample
    from ..orbits.reversors import A, symmetry_group

    x0 = _state(state0)
    pts, _ = sample(x0, check_positive(period, "period"), 64)
    out = []
    for g in symmetry_group():
        if round(np.linalg.det(g)) != -1:
            continue
        q = A @ g @ np.linalg.inv(A)
        y = np.hstack([pts[:, :2] @ q.T, pts[:, 2:] @ np.linalg.inv(q)])
        d = y - pts
        k = np.rint(d[:, 0] / math.pi)
        d0, d1 = d[:, 0] - k * math.pi, d[:, 1] - k * math.pi
        d1 = d1 - 2 * math.pi * np.rint(d1 / (2 * math.pi))
        if max(np.abs(d0).max(), np.abs(d1).max(), np.abs(d[:, 2:]).max()) < tol:
            out.append(element_class(g))
    return tuple(out)
