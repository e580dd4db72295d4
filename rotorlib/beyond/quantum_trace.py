"""Gutzwiller's trace formula with its phases: action, Maslov index, amplitude, symmetry.

For a periodic orbit ``p`` of period ``T_p`` at energy ``E`` the oscillating level density
of the whole spectrum (every sector, with multiplicities) is

    rho_osc(E) = (1/pi hbar) sum_p sum_{r >= 1} g_p T_p / sqrt|det(M_p^r - 1)|
                 * cos(r S_p / hbar - sigma_{p,r} pi/2)

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

The tests of significance are in :mod:`rotorlib.beyond.quantum_significance`.

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
    "transverse_frame",
    "transverse_path",
    "conley_zehnder",
    "maslov_index",
    "orbit_action",
    "pendulum_action",
    "OrbitTerm",
    "orbit_term",
    "orbit_symmetry",
    "quantum_signal",
    "semiclassical_signal",
    "smoothed_density",
    "smoothed_oscillation",
]


def _positive(x, name):
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
    T = _positive(period, "period")
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
    T = _positive(period, "period")
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

    E = _positive(E, "E")
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
    :func:`orbit_symmetry`) and ``period_slope`` (``dT/dE``, nan if unknown).
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
    T = _positive(period, "period")
    sigma = maslov_index(x, T, repetitions, n)
    stab = orbit_symmetry(x, T)
    return OrbitTerm(
        label=str(label),
        E=float(E),
        period=T,
        action=orbit_action(x, T),
        trace=float(trace),
        maslov=sigma,
        copies=24 // len(stab),
        stabiliser=stab,
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
    pts, _ = sample(x0, _positive(period, "period"), n)
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
# the two signals


def quantum_signal(
    levels: ArrayLike, E0: float, sigma: float, hbar: float, t: ArrayLike
) -> np.ndarray:
    """``(sqrt(2 pi) hbar/sigma) sum_n w(E_n - E0) exp(-i (E_n - E0) t/hbar)``, complex.

    The modulus is :func:`rotorlib.beyond.quantum_semiclassics.density_fourier`; the
    phase is what the trace formula predicts as ``S_p/hbar - sigma_p pi/2``. ``levels``: the
    whole spectrum with multiplicities; ``w`` a Gaussian of width ``sigma``.

    Examples
    --------
    >>> z = quantum_signal([1.0], 1.0, 0.5, 0.1, [0.0, 1.0])
    >>> np.round(np.abs(z), 6).tolist()
    [0.501326, 0.501326]
    """
    h, s = _positive(hbar, "hbar"), _positive(sigma, "sigma")
    E = np.asarray(levels, float)
    w = np.exp(-0.5 * ((E - E0) / s) ** 2)
    keep = w > 1e-17
    E, w = E[keep] - E0, w[keep]
    t = np.atleast_1d(np.asarray(t, float))
    out = np.empty(len(t), complex)
    for i0 in range(0, len(t), 256):
        out[i0 : i0 + 256] = np.exp(-1j * np.outer(t[i0 : i0 + 256], E) / h) @ w
    return math.sqrt(2.0 * math.pi) * h / s * out


def semiclassical_signal(
    terms: Sequence[OrbitTerm],
    E0: float,
    sigma: float,
    hbar: float,
    t: ArrayLike,
    r_max: int = 3,
    phases: bool = True,
) -> np.ndarray:
    """The trace formula's prediction for :func:`quantum_signal`.

    Each orbit and repetition gives ``A exp(i (r S/hbar - sigma_r pi/2))`` times the
    transform of the window, ``exp(-(t - r T)^2 sigma^2 / 2 hbar^2)``; with a known
    ``period_slope`` ``T'`` the quadratic term ``r T' (E - E0)^2/2`` of the action is kept
    (the Gaussian integral with complex width). ``phases=False``: the moduli only.
    Repetitions with ``det(M^r - 1) = 0`` are skipped. The orbits must be at ``E0``.

    Examples
    --------
    >>> tm = OrbitTerm("x", 1.0, 2.0, 0.0, 20.0, (0,), 1)
    >>> round(float(abs(semiclassical_signal([tm], 1.0, 0.5, 0.1, [2.0], 1)[0])), 6)
    0.5
    """
    h, s = _positive(hbar, "hbar"), _positive(sigma, "sigma")
    t = np.atleast_1d(np.asarray(t, float))
    out = np.zeros(len(t), complex)
    for tm in terms:
        if abs(tm.E - E0) > 1e-9 * max(1.0, abs(E0)):
            raise ValueError(f"orbit {tm.label} is at E = {tm.E}, not at E0 = {E0}")
        for r in range(1, min(r_max, len(tm.maslov)) + 1):
            try:
                A = tm.amplitude(r)
            except ValueError:
                continue
            ph = r * tm.action / h - tm.maslov[r - 1] * math.pi / 2 if phases else 0.0
            b = r * tm.period_slope if math.isfinite(tm.period_slope) else 0.0
            # int w(x) exp(i x (rT - t)/h + i b x^2/2h) dx / (sqrt(2 pi) s)
            a = 0.5 / s**2 - 0.5j * b / h
            g = np.exp(-((r * tm.period - t) ** 2) / (4 * a * h * h))
            out += A * np.exp(1j * ph) * g / (s * np.sqrt(2 * a))
    return out


def smoothed_density(levels: ArrayLike, E: ArrayLike, gamma: float) -> np.ndarray:
    """``sum_n exp(-(E - E_n)^2 / 2 gamma^2) / (sqrt(2 pi) gamma)``: the level density
    smoothed by a Gaussian of width ``gamma`` (``levels`` with multiplicities).

    Examples
    --------
    >>> round(float(smoothed_density([0.0], [0.0], 1.0)[0]), 6)
    0.398942
    """
    g = _positive(gamma, "gamma")
    x = np.sort(np.asarray(levels, float))
    E = np.atleast_1d(np.asarray(E, float))
    out = np.empty(len(E))
    for i, e in enumerate(E):
        lo, hi = np.searchsorted(x, [e - 9 * g, e + 9 * g])
        out[i] = np.exp(-0.5 * ((e - x[lo:hi]) / g) ** 2).sum()
    return out / (math.sqrt(2 * math.pi) * g)


def smoothed_oscillation(
    terms: Sequence[OrbitTerm],
    E: ArrayLike,
    gamma: float,
    hbar: float,
    r_max: int = 3,
) -> np.ndarray:
    """The trace formula's oscillating density smoothed by a Gaussian of width ``gamma``:
    ``(1/pi hbar) sum A_r exp(-(gamma r T/hbar)^2/2) cos(r S(E)/hbar - sigma_r pi/2)``
    with ``S(E) = S + T (E - E0) + T' (E - E0)^2/2`` (``T'`` = 0 where unknown) around
    each orbit's energy ``E0``.

    Examples
    --------
    >>> tm = OrbitTerm("x", 1.0, 2.0, 0.0, 20.0, (0,), 1)
    >>> round(float(smoothed_oscillation([tm], [1.0], 0.01, 0.1, 1)[0]), 6)
    1.560035
    """
    h, g = _positive(hbar, "hbar"), _positive(gamma, "gamma")
    E = np.atleast_1d(np.asarray(E, float))
    out = np.zeros(len(E))
    for tm in terms:
        dE = E - tm.E
        b = tm.period_slope if math.isfinite(tm.period_slope) else 0.0
        S = tm.action + tm.period * dE + 0.5 * b * dE**2
        for r in range(1, min(r_max, len(tm.maslov)) + 1):
            try:
                A = tm.amplitude(r)
            except ValueError:
                continue
            damp = math.exp(-0.5 * (g * r * tm.period / h) ** 2)
            out += A * damp * np.cos(r * S / h - tm.maslov[r - 1] * math.pi / 2)
    return out / (math.pi * h)
