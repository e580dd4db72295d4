"""Monodromy matrices of periodic orbits (paper §4, §5.3, §8).

Two routes:

* :func:`monodromy` for pendula and breathers: block-diagonal in the paper's
  basis, with the *transverse* block from the symmetry-reduced Hill problem
  (:mod:`rotorlib.orbits.hill`) and the *longitudinal* block in closed form,
  ``[[1, -c E tau'(E)], [0, 1]]`` (``c = 3`` for pendula at G, ``4`` for
  breathers at G; ``4 (E - 4)/E`` times that for LD at D), so that
  ``tr M_parallel = 2`` exactly. Accurate at any distance to the separatrix.
* :func:`variational_monodromy` (and :func:`textbook_monodromy`, its pendulum and
  breather R reference): the textbook route for any orbit, integrating the
  nonlinear flow and the 4x4 variational equations over one period (scipy DOP853
  with the equations of :mod:`rotorlib.core.system`, or heyoka in the tier of ``digits``
  through :func:`rotorlib.core.flow.monodromy_matrix`, the one builder of the equations).

Every route returns a :class:`Monodromy`; :func:`trace_monodromy` returns its trace. Near
  E = 4 its error grows like 1/|E - 4| (the book's *Numerical notes*, ``book/numerical_notes.md``): it is the
  reference only when run at enough digits.

Bases: pendulum blocks are ``(a1, p1 | a2, p2)`` = (transverse | longitudinal);
breather blocks ``(b1, q1 | b2, q2)`` = (longitudinal | transverse), as in the
paper. :meth:`Monodromy.in_alpha_state_order` gives the matrix in the state
order ``[a1, a2, p1, p2]`` used everywhere else.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from decimal import Decimal
from typing import Any

import mpmath as mp
import numpy as np
from scipy.linalg import block_diag

from ..core.closed_forms import BreatherOrbit, PendulumOrbit, breather, pendulum
from ..core.energy import BreatherEnergy, PendulumEnergy
from ..core.flow import monodromy_matrix
from ..core.precision import Tier, precision_tier, requested_digits, tier
from ..core.system import (
    beta_to_alpha,
    energy_alpha,
    jacobian_alpha,
    lattice_reduce,
    rhs_alpha,
)
from .hill import hill_problem, solve_hill

#: Names of the state ``[a1, a2, p1, p2]``: the basis of the variational routes.
STATE_ORDER = ("a1", "a2", "p1", "p2")

__all__ = [
    "Monodromy",
    "monodromy",
    "trace_monodromy",
    "variational_monodromy",
    "textbook_monodromy",
    "multipliers_from_trace",
    "stability_of",
]


def multipliers_from_trace(t: float) -> np.ndarray:
    """Eigenvalues ``(mu, 1/mu)`` of a 2x2 symplectic matrix with trace ``t``, stably.

    Complex conjugate on the unit circle for ``|t| < 2`` (stable), real for ``|t| > 2``.
    """
    disc = t * t - 4.0
    if disc >= 0:
        r = math.sqrt(disc)
        big = 0.5 * (t + math.copysign(r, t))
        return np.array([big, 1.0 / big])  # |t| >= 2: big != 0
    r = math.sqrt(-disc)
    return np.array([complex(0.5 * t, 0.5 * r), complex(0.5 * t, -0.5 * r)])


def stability_of(trace: float, digits: int = 15) -> str:
    """``stable`` (``0 < tr M < 4``), ``unstable`` or ``marginal``: ``tr M`` within
    ``max(1, |tr M|) 10^(7 - digits)`` of 0 or 4, where the computed trace cannot decide.

    Examples
    --------
    >>> stability_of(2.0), stability_of(5.0), stability_of(4.0 - 1e-12)
    ('stable', 'unstable', 'marginal')
    """
    tr = float(trace)
    if not math.isfinite(tr):
        return "unstable"
    tol = max(1.0, abs(tr)) * 10.0 ** (7 - int(digits))
    if min(abs(tr), abs(tr - 4.0)) <= tol:
        return "marginal"
    return "stable" if 0.0 < tr < 4.0 else "unstable"


@dataclass(frozen=True)
class Monodromy:
    """Monodromy matrix of a periodic orbit: the one result of every monodromy route.

    :func:`monodromy` (pendula and breathers, at their base point, in the paper's block
    basis) fills every attribute; the variational routes (:func:`variational_monodromy`,
    :func:`textbook_monodromy`: any orbit) give ``family='orbit'``, the matrix in the
    state order, no blocks (``None``) and no ``energy``, and add
    ``closure`` (also in ``residual``) and ``steps``: the one remaining difference.

    Attributes
    ----------
    family : str
        ``pendulum``, ``breather-LG``, ``breather-LD`` or ``breather-R``.
    E : float
        Energy (float64; see ``energy`` for the distance to the separatrix).
    period : float
        Period of the orbit.
    matrix : ndarray (4, 4)
        M in the paper's block basis ``basis``.
    basis : tuple of str
        Names of the four coordinates of ``matrix``.
    transverse, longitudinal : ndarray (2, 2)
        The blocks M_perp and M_parallel.
    trace : float
        ``tr M = tr M_perp + 2``.
    trace_transverse : float
        ``tr M_perp``.
    trace_str : str
        ``tr M`` as a decimal string with every digit the precision supports.
    multipliers : ndarray (2,)
        Eigenvalues of M_perp (M_parallel has 1, 1).
    stable : bool
        ``0 < tr M < 4`` for the computed value (see ``stability`` near the edges).
    stability : {'stable', 'unstable', 'marginal'}
        ``marginal`` when ``tr M`` is within the accuracy of the tier
        (``1e-12`` in float64, ``10^(2 - digits)`` above) of an edge of the
        stable interval, 0 or 4, so that the computed value cannot decide. The
        equilibrium ``E = 0`` is marginal: both normal modes have frequency
        sqrt(3) (1:1 resonance) and ``M`` is the identity (neutrally stable,
        every perturbation stays bounded). For small ``E > 0`` the pendulum has
        ``4 - tr M = pi^2 E^3/3456 (1 + O(E))`` (stable), unresolved below
        ``E ~ 7e-4`` in float64 (``4 - tr M < 1e-12``).
    stability_note : str
        One sentence explaining ``marginal`` (empty otherwise).
    precision, backend : str
        How the transverse block was computed.
    residual : float
        ``|psi(K)|`` of the reduced problem (0 in exact arithmetic).
    energy : PendulumEnergy, BreatherEnergy or None
        The :class:`~rotorlib.core.energy.PendulumEnergy` or ``BreatherEnergy``.
    closure : float
        Variational routes: ``max |x(T) - x(0)|`` modulo the lattice of ``(a1, a2)``.
    steps : int
        Variational routes: integrator steps (scipy; 0 for heyoka).

    Examples
    --------
    >>> from rotorlib.orbits.floquet import monodromy
    >>> M = monodromy(E=3.9)
    >>> M.basis, M.stability, round(M.trace, 10)
    (('a1', 'p1', 'a2', 'p2'), 'stable', 0.0195119424)
    """

    family: str
    E: float
    period: float
    matrix: np.ndarray
    basis: tuple[str, ...]
    transverse: np.ndarray | None
    longitudinal: np.ndarray | None
    trace: float
    trace_transverse: float
    trace_str: str
    multipliers: np.ndarray
    stable: bool
    precision: str
    backend: str
    residual: float
    energy: PendulumEnergy | BreatherEnergy | None = field(repr=False, default=None)
    period_str: str = ""
    stability: str = ""
    stability_note: str = ""
    closure: float = float("nan")
    steps: int = 0

    def in_alpha_state_order(self) -> np.ndarray:
        """M in the state order ``[a1, a2, p1, p2]`` (pendulum variables)."""
        if self.basis == STATE_ORDER:
            return self.matrix
        # basis (a1, p1, a2, p2) -> state order (a1, a2, p1, p2); breathers likewise
        # (b1, q1, b2, q2) -> (b1, b2, q1, q2), then to alpha
        P = np.eye(4)[[0, 2, 1, 3]]
        Ms = P @ self.matrix @ P.T
        if self.family == "pendulum":
            return Ms
        T = beta_to_alpha(np.eye(4)).T  # the linear map (b, q) -> (a, p)
        return T @ Ms @ np.linalg.inv(T)


def _as_orbit(orbit=None, E=None, log_abs_dE=None, phase=None, family="pendulum"):
    if orbit is None:
        if family == "pendulum":
            return pendulum(E=E, log_abs_dE=log_abs_dE, phase=phase)
        fam = {"lib": "LG", "rot": "R"}.get(phase) if family == "breather" else family
        return breather(E=E, family=fam, log_abs_dE=log_abs_dE)
    if isinstance(orbit, (PendulumOrbit, BreatherOrbit)):
        return orbit
    # an energy (e.g. ``transition(...).energy``), or an object carrying its orbit's energy
    energy = getattr(orbit, "energy", orbit)
    if isinstance(energy, PendulumEnergy):
        return PendulumOrbit(energy)
    if isinstance(energy, BreatherEnergy):
        return BreatherOrbit(energy)
    raise TypeError(
        "monodromy takes a pendulum or breather orbit "
        "(rotorlib.core.closed_forms.pendulum(...) or breather(...)) or its energy "
        "(a PendulumEnergy / BreatherEnergy, e.g. transition(label).energy), "
        f"or E=... / log_abs_dE=... keywords; got {type(orbit).__name__}"
    )


def monodromy(
    orbit: Any = None,
    *,
    E: Any = None,
    log_abs_dE: Any = None,
    phase: str | None = None,
    family: str = "pendulum",
    digits: int | Tier | None = None,
    tol: float | None = None,
) -> Monodromy:
    """Monodromy matrix of a pendulum or breather.

    Parameters
    ----------
    orbit : PendulumOrbit, BreatherOrbit, PendulumEnergy, BreatherEnergy, optional
        The orbit, or its energy (e.g. ``transition(label).energy``, or the
        transition itself); or give ``E`` / ``log_abs_dE`` (+ ``phase``) and ``family``
        (``pendulum``, ``breather`` or a breather family ``LG``, ``LD``, ``R``).
    digits : int or Tier, optional
        Requested significant digits. ``None`` or <= 15: float64; up to 31:
        heyoka real128; more: heyoka multiprecision. Without heyoka: scipy in
        float64, mpmath's Taylor integrator beyond (``digits + 5`` working digits).
    tol : float, optional
        Integrator tolerance passed to :func:`rotorlib.orbits.hill.solve_hill` (scipy
        ``rtol``, heyoka ``tol``); the default is the verified tier. Only for
        work-precision studies: ``precision`` does not record it.

    Returns
    -------
    Monodromy
        Float64: pendula ~1e-13 absolute in ``tr M`` at any ``|E - 4| >= 1.8e-307``;
        breathers ~1e-14 relative at any ``|E - 4.5| >= 1.8e-307`` (``tr M ~ |E - 4.5|^-2``
        overflows float64 below ``|E - 4.5| ~ e^-350``: ``trace`` is then ``inf``
        and ``trace_str`` carries 16 digits). Deeper energies are refused in
        float64 (``ValueError``) and computed by the extended tiers, which read
        the decimal input at ``digits + 15`` digits: ``trace_str`` to ``digits``
        digits (``tests/test_extremes.py``, ``tests/test_breather_depth.py``).

    Raises
    ------
    ValueError
        Bad precision request, or a float64 request beyond the float64 range.
    TypeError
        ``orbit`` is none of the above (the message names what to pass).

    Examples
    --------
    >>> from rotorlib.core.closed_forms import pendulum
    >>> M = monodromy(pendulum(E=3.9))
    >>> M.stability, round(M.trace, 10), M.multipliers.shape
    ('stable', 0.0195119424, (2,))
    >>> monodromy(E=3.9, digits=30).trace_str
    '0.0195119424111676105307516364433'
    """
    orbit = _as_orbit(orbit, E, log_abs_dE, phase, family)
    return _monodromy(orbit, requested_digits(digits), precision_tier(digits)[0], tol)


def _monodromy(
    orbit: PendulumOrbit | BreatherOrbit,
    digits: int | None,
    backend: str,
    tol: float | None = None,
) -> Monodromy:
    """:func:`monodromy` of ``orbit`` with the integrator ``backend`` (``heyoka``,
    ``scipy`` or ``mpmath``), whatever is installed: ``digits`` None is float64 (the
    mpmath Taylor integrator at 20 digits), more is heyoka's tier of ``digits`` or
    mpmath at ``digits + 5`` working digits (the test hook of the integrators)."""
    extended = backend == "mpmath" or tier(digits).extended
    prob = hill_problem(orbit, (digits or 20) if extended else None)
    sol = solve_hill(prob, digits, tol, integrator=backend)
    C = sol.coefficient_map
    d = np.array([1.0, prob.momentum_scale])
    with np.errstate(over="ignore", invalid="ignore"):  # inf/nan when tr M overflows
        Phi = C @ C if prob.repeats == 2 else C
        Mperp = (Phi * d[:, None]) * (1.0 / d)[None, :]  # D Phi D^-1
    tr_perp = sol.delta * sol.delta - 2.0 if prob.repeats == 2 else sol.delta
    tr_exact = tr_perp + 2.0
    period_str = repr(orbit.period)
    if extended or not math.isfinite(tr_perp):
        shown = max(5, digits or 20)
        with mp.workdps(len(sol.delta_str) + 5):
            dx = mp.mpf(sol.delta_exact)
            tr_exact = dx * dx if prob.repeats == 2 else dx + 2
            tr_str = mp.nstr(tr_exact, shown if extended else 16)
        if extended:
            period = orbit.closed_form((digits or 20) + 15)["period"]
            period_str = mp.nstr(period, shown)
    else:
        tr_str = repr(tr_exact)
    if isinstance(orbit, PendulumOrbit):
        basis = ("a1", "p1", "a2", "p2")
        Mpar = np.array([[1.0, -3.0 * orbit.E * orbit.dperiod_dE], [0.0, 1.0]])
        M = block_diag(Mperp, Mpar)
    else:
        basis = ("b1", "q1", "b2", "q2")
        q1sq = orbit.E - 4.0 if orbit.energy.family == "LD" else orbit.E
        Mpar = np.array([[1.0, -4.0 * q1sq * orbit.dperiod_dE], [0.0, 1.0]])
        M = block_diag(Mpar, Mperp)
    # stability from the value with every computed digit (the float64 view of 4 - 1e-18 is 4.0)
    stability, note = _stability(
        tr_exact, 10.0 ** (2 - (digits or 20)) if extended else 1e-12, orbit
    )
    return Monodromy(
        orbit.family, orbit.E, orbit.period, M, basis, Mperp, Mpar, tr_perp + 2.0,
        tr_perp, tr_str, multipliers_from_trace(tr_perp), bool(0 < tr_exact < 4),
        sol.precision, backend, sol.psi_end, orbit.energy, period_str, stability, note,
    )  # fmt: skip


def _stability(tr, tol: float, orbit) -> tuple:
    """``(stability, note)``: stable/unstable, or marginal within ``tol`` of tr M = 0 or 4 (see :class:`Monodromy`).

    ``tr`` is a float or an mpmath number (extended tiers).
    """
    edge = 4 if abs(tr - 4) <= abs(tr) else 0
    if abs(tr - edge) > tol:
        return ("stable" if 0 < tr < 4 else "unstable"), ""
    en = orbit.energy
    if en.given[0] == "E" and Decimal(en.given[1]) == 0:
        return "marginal", (
            "E = 0 is the equilibrium G: both normal modes have frequency sqrt(3) (1:1 resonance), "
            "M is the identity and all multipliers are 1: neutrally stable, not a transition"
        )
    note = (
        f"|tr M - {edge}| <= {tol:.0e}, the accuracy of this precision tier: on the stability edge "
        f"tr M = {edge} within rounding, the computed value cannot tell stable from unstable"
    )
    if (
        isinstance(orbit, PendulumOrbit)
        and en.phase == "lib"
        and orbit.E < 1e-2
        and edge == 4
    ):
        with mp.workdps(20):
            gap = mp.nstr(
                mp.pi**2 * en.mp_E_eps(20)[0] ** 3 / 3456, 3
            )  # underflows float64 for E < 1e-100
        note += f"; the small-E series gives 4 - tr M = pi^2 E^3/3456 (1 + O(E)) = {gap} > 0 (stable)"
    return "marginal", note


def trace_monodromy(orbit: Any = None, **kwargs: Any) -> Any:
    """``tr M`` of a pendulum or breather; see :func:`monodromy` for the arguments.

    Returns
    -------
    float or mpmath.mpf
        A float in float64 (``digits`` None or <= 15); with ``digits > 15`` the
        extended-precision value, an ``mpf`` holding every digit of
        ``Monodromy.trace_str`` (``digits`` significant digits), never its
        float64 rounding.

    Examples
    --------
    >>> from rotorlib.orbits.floquet import trace_monodromy
    >>> round(trace_monodromy(E=3.9), 10)
    0.0195119424
    >>> import mpmath
    >>> mpmath.nstr(trace_monodromy(E=3.9, digits=40), 40)
    '0.0195119424111676105307516364433125540919'
    """
    M = monodromy(orbit, **kwargs)
    if M.precision == "float64":
        return M.trace
    with mp.workdps(len(M.trace_str) + 5):
        return +mp.mpf(M.trace_str)


def variational_monodromy(
    state0: Sequence[Any],
    period: Any,
    *,
    digits: int | Tier | None = None,
    rtol: float = 1e-12,
) -> Monodromy:
    """The textbook monodromy: nonlinear flow + 4x4 variational equations over one period.

    Parameters
    ----------
    state0 : array_like (4,) or sequence of decimal strings
        Initial state ``[a1, a2, p1, p2]``. For extended precision pass decimal
        strings or mpmath numbers so no digits are lost.
    period : float, str or mpf
        Integration time.
    digits : int or Tier, optional
        The tier (:func:`rotorlib.core.precision.tier`): ``None`` float64, integrated by scipy
        DOP853 (the paper's baseline and that of ``book/numerical_notes.md``); extended
        tiers integrate with heyoka (:func:`rotorlib.core.flow.monodromy_matrix`, the one
        builder of the equations of motion) at the tier's machine epsilon.
    rtol : float
        Tolerance of scipy's ``solve_ivp(DOP853)`` (``atol = rtol 1e-3``; float64 only).

    Returns
    -------
    Monodromy
        ``family='orbit'``, ``matrix`` in the state order ``[a1, a2, p1, p2]`` (the
        ``basis``), no ``transverse``/``longitudinal`` blocks;
        ``closure = max |x(T) - x(0)|`` modulo the lattice of ``(a1, a2)``; ``backend``
        names the integrator (``scipy-DOP853 rtol=...`` or ``heyoka-taylor``).

    Notes
    -----
    For pendula near E = 4 the error grows like 1/|E - 4|; use :func:`monodromy`
    there, or this with ``digits`` beyond ``log10(1/|E - 4|)`` plus the digits wanted.

    Examples
    --------
    >>> from rotorlib.core.closed_forms import pendulum
    >>> o = pendulum(E=3.9)
    >>> V = variational_monodromy(o.state0, o.period)
    >>> round(V.trace, 6), V.basis, V.closure < 1e-9
    (0.019512, ('a1', 'a2', 'p1', 'p2'), True)
    """
    t = tier(digits)
    with t.context():
        x0 = [t.num(v) for v in state0]
        T = t.num(period)
        if not t.extended:
            Mv, xT, tr, steps = _scipy_variational(x0, T, rtol)
            backend, tr_str = f"scipy-DOP853 rtol={rtol:g}", repr(tr)
        else:
            Mv, xT, tr = monodromy_matrix(x0, T, t)
            steps, backend = 0, "heyoka-taylor"
            tr_str = t.text(tr)
        # the closure in the working precision: x(T) - x(0) formed before any rounding
        gap = lattice_reduce([a - b for a, b in zip(xT, x0)], t)
        closure = max(abs(float(v)) for v in gap)
        trf = float(tr)
        E = float(energy_alpha(np.array([float(v) for v in x0])))
        return Monodromy(
            "orbit", E, float(T), Mv, STATE_ORDER, None, None,
            trf, trf - 2.0, tr_str, multipliers_from_trace(trf - 2.0), 0 < trf < 4,
            t.name, backend, closure, None, t.text(T),
            stability_of(trf, t.dps - 9 if t.extended else 15), "",
            closure=closure, steps=steps,
        )  # fmt: skip


def _scipy_variational(
    x0: list[float], T: float, rtol: float
) -> tuple[np.ndarray, list[float], float, int]:
    from scipy.integrate import solve_ivp

    def rhs(t: float, z: np.ndarray) -> np.ndarray:
        x = z[:4]
        Phi = z[4:].reshape(4, 4)
        return np.concatenate([rhs_alpha(t, x), (jacobian_alpha(x) @ Phi).ravel()])

    z0 = np.concatenate([np.asarray(x0, float), np.eye(4).ravel()])
    sol = solve_ivp(rhs, (0.0, T), z0, method="DOP853", rtol=rtol, atol=rtol * 1e-3)
    z = sol.y[:, -1]
    Mv = z[4:].reshape(4, 4)
    return Mv, list(z[:4]), float(np.trace(Mv)), len(sol.t) - 1


#: The default tier of :func:`textbook_monodromy`: 256-bit multiprecision.
MP256 = Tier("mp256")


def textbook_monodromy(
    orbit: PendulumOrbit | BreatherOrbit, digits: int | Tier = MP256
) -> Monodromy:
    """The textbook monodromy of a pendulum or breather R in the tier of ``digits``
    (default 256-bit multiprecision; heyoka).

    The initial state at the base point G and the period are computed with
    mpmath from the energy's decimal input (``energy.mp_values``; pendulum: ``p2 = sqrt(4E/3)``,
    period ``4K(E/4)/sqrt3`` or ``2 kappa K(kappa^2)/sqrt3``; breather R:
    ``p1 = p2 = sqrt(E)``, period ``4K(m)/sqrt(Q)``), then the nonlinear flow and
    the 4x4 variational equations are integrated over one period
    (:func:`variational_monodromy`). It shares no code with the Hill reduction, so it
    is an independent reference. Near E = 4 it loses about ``2 log10(1/|E-4|)``
    digits: choose ``digits >= 2 log10(1/|E-4|)`` plus the digits wanted.

    Examples
    --------
    >>> from rotorlib.core.closed_forms import pendulum
    >>> V = textbook_monodromy(pendulum(E=3.9))
    >>> V.precision, V.trace_str[:22]
    ('mp256', '0.01951194241116761053')
    """
    t = tier(digits)
    dps = int(t.bits / 3.33) + 10
    with mp.workdps(dps):
        if isinstance(orbit, PendulumOrbit):
            v = orbit.energy.mp_values(dps)
            E, m = v["E"], v["m"]
            period = (
                4 * mp.ellipk(m) / mp.sqrt(3)
                if orbit.energy.phase == "lib"
                else 2 * mp.sqrt(m) * mp.ellipk(m) / mp.sqrt(3)
            )
            state0 = [mp.mpf(0), mp.mpf(0), mp.mpf(0), mp.sqrt(4 * E / 3)]
        elif isinstance(orbit, BreatherOrbit) and orbit.energy.family == "R":
            E = orbit.energy.mp_values(dps)["E"]
            Q = mp.sqrt(E * (E - 4))
            period = 4 * mp.ellipk((Q - E + 6) / (2 * Q)) / mp.sqrt(Q)
            state0 = [mp.mpf(0), mp.mpf(0), mp.sqrt(E), mp.sqrt(E)]
        else:
            raise ValueError(
                "textbook_monodromy supports pendula and the rotational breather R"
            )
        return variational_monodromy(state0, period, digits=t)
