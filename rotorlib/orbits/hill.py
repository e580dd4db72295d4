"""The symmetry-reduced transverse (Lamé/Hill) problem of pendula and breathers.

Transverse perturbations obey a Hill equation ``y'' = -Q y`` whose
coefficient is even about the base point and periodic (paper eqs. for
``delta alpha_1`` and ``delta beta_2``). We write it in the elliptic argument
``u`` of the closed-form orbit and let the orbit enter through its amplitude
``theta = am(u | m)``, carried as ``psi = pi/2 - theta``::

    psi' = -sqrt(m1 + m sin(psi)^2),    y'' = -Q(psi) y,     0 <= u <= K(m).

The 1-D flow for ``psi`` *contracts* towards the saddle (psi -> 0), so
``psi`` keeps its relative accuracy at any distance to the separatrix,
unlike an integration of the pendulum itself, whose error grows like
``1/sqrt(eps)``. The endpoint value ``psi(K)`` (exactly 0) is returned as a
residual.

With ``y1, y2`` the fundamental solutions at the half-period ``h`` of the
coefficient, the coefficient-period map is ``S Phi(h)^-1 S Phi(h)``
(``S = diag(1, -1)``), whose trace is ``Delta = 2 (y1 y2' + y1' y2)``. The
orbit period is two coefficient periods for libration (pendulum, LG, LD) and
one for rotation (pendulum, R). The rotational breather's coefficient is not
symmetric about the quarter period, so its half period is integrated as two
contracting pieces, ``[0, K]`` forward and ``[2K, K]`` backward. Inverses are
adjugates (the Wronskian is 1 exactly): near the breather separatrix the maps
are nearly rank one and a computed determinant would cancel (``_half_map``).

Precision (``tests/test_monodromy.py``, ``tests/test_extremes.py``,
``tests/test_breather_depth.py``):

* float64 (heyoka Taylor, tol 2e-16; scipy DOP853, rtol 1e-13): pendula
  ``Delta`` to ~1e-13 absolute, breathers ~1e-14 relative (``tr M`` grows like
  ``|E - 4.5|^-2``), for every ``m1`` down to ~2e-307 (``|E - sep| >= 1.8e-307``;
  deeper energies are refused). Where ``Delta`` overflows float64 (R below
  ``|E - 4.5| ~ e^-355``) the float64 maps are composed again in mpmath
  (``delta_str``, ``delta_exact``).
* real128 (~32 digits) for ``m1 >= 1e-4800`` (``log|E - sep| >~ -11050``);
  heyoka multiprecision beyond (MPFR exponents), at a cost linear in
  ``K ~ |log|E - sep||/2`` (``log|E - 4| = -10000``: ~1 s in real128).
* mpmath's Taylor integrator as the slow independent reference.
"""

from __future__ import annotations

import contextlib
import functools
import math
import threading
from dataclasses import dataclass
from typing import TYPE_CHECKING

import mpmath as mp
import numpy as np

from ..core.precision import Tier, integrator_tier, load_heyoka, requested_digits

if TYPE_CHECKING:
    from ..core.closed_forms import BreatherOrbit, PendulumOrbit

__all__ = [
    "HillProblem",
    "hill_problem",
    "solve_hill",
    "HillSolution",
]


@dataclass(frozen=True)
class HillProblem:
    """Coefficients of the reduced transverse problem of one orbit.

    Attributes
    ----------
    kind : str
        One of ``pendulum-lib``, ``pendulum-rot``, ``breather-LG``,
        ``breather-LD``, ``breather-R``.
    m, m1, K : float or mpmath.mpf
        Elliptic parameter, its complement and K(m).
    c3 : float or mpf
        ``2m/3`` for pendula, ``3/nu^2`` for breathers (computed at the
        working precision).
    shape : float or mpf
        ``A^2`` (LG), ``D^2`` (LD) or ``lam^2`` (R); unused for pendula.
    repeats : int
        Coefficient periods per orbit period (2 libration, 1 rotation).
    momentum_scale : float
        ``delta p = momentum_scale * dy/du``: ``du/dt`` (which converts ``dy/du`` into
        a velocity ``delta q'``) times 2 for ``p1`` (pendula), 1/6 for ``q2`` (breathers).
    """

    kind: str
    m: object
    m1: object
    K: object
    c3: object
    shape: object
    repeats: int
    momentum_scale: float


def hill_problem(
    orbit: PendulumOrbit | BreatherOrbit, digits: int | Tier | None = None
) -> HillProblem:
    """The reduced transverse problem of a pendulum or breather orbit.

    Parameters
    ----------
    orbit : PendulumOrbit or BreatherOrbit
    digits : int or Tier, optional
        ``None`` (or the float64 tier): float64 parameters (refused with ``ValueError``
        when ``|E - sep| < 1.8e-307``, below the float64 range). An integer: mpmath
        parameters correct to ``digits + 15`` digits, built from the decimal input of
        the energy at any depth (``PendulumOrbit.closed_form``);
        no float64 rounding of ``E`` enters. An extended tier: as the digits it
        delivers (:func:`~rotorlib.core.precision.requested_digits`).

    Examples
    --------
    >>> from rotorlib.core.closed_forms import pendulum
    >>> p = hill_problem(pendulum(E=3.9))
    >>> p.kind, p.repeats, round(p.m, 6)
    ('pendulum-lib', 2, 0.975)
    """
    if isinstance(digits, Tier):
        digits = requested_digits(digits)
    dps = None if digits is None else int(digits) + 15
    cf = orbit.closed_form(dps)
    m = cf["m"]
    ctx = contextlib.nullcontext() if dps is None else mp.workdps(dps)
    if orbit.family == "pendulum":
        lib = orbit.energy.phase == "lib"
        with ctx:
            c3 = 2 * m / 3
        du_dt = math.sqrt(3.0) if lib else math.sqrt(3.0 / float(m))
        kind = "pendulum-" + orbit.energy.phase
        return HillProblem(
            kind, m, cf["m1"], cf["K"], c3, 0.0, 2 if lib else 1, 2.0 * du_dt
        )
    with ctx:
        c3 = 3 / cf["nu"] ** 2
    repeats = 1 if orbit.family == "breather-R" else 2
    return HillProblem(
        orbit.family,
        m,
        cf["m1"],
        cf["K"],
        c3,
        cf["shape"],
        repeats,
        1 / 6 * float(cf["nu"]),  # du/dt = nu
    )


def _coefficient(kind, sp, cp, m, c3, shape, sign):
    """Q as an expression in sin(psi), cos(psi); works for floats, mpf and heyoka expressions."""
    # For pendula c3 = 2m/3 is passed in, computed at the working precision:
    # a literal 2/3 (or heyoka's rewriting of x/3 as x*(1/3) in double) would
    # leak a float64 rounding (~4e-17) into the real128 and multiprecision tiers.
    if kind == "pendulum-lib":
        return 1.0 - c3 * cp * cp
    if kind == "pendulum-rot":
        return m - c3 * cp * cp
    w2 = shape * cp * cp  # w^2 = A^2 sn^2 (LG) or v^2 = D^2 sn^2 (LD); sn = cos(psi)
    if kind == "breather-LG":
        return c3 * (1.0 - w2) / (1.0 + w2)
    if kind == "breather-LD":
        return c3 * (w2 - 1.0) / (w2 + 1.0)
    ct = sign * sp  # cos(theta)
    return c3 * ((1.0 + ct) - shape * (1.0 - ct)) / ((1.0 + ct) + shape * (1.0 - ct))


@dataclass(frozen=True)
class HillSolution:
    """Result of :func:`solve_hill`.

    Attributes
    ----------
    coefficient_map : ndarray (2, 2)
        Map over one coefficient period in the ``(y, dy/du)`` basis, float64.
    delta : float
        Its trace ``Delta`` (float64 view).
    delta_str : str
        ``Delta`` as a decimal string with all computed digits.
    psi_end : float
        Residual ``|psi(K)|`` (0 exactly; measures the orbit's phase error).
    backend, precision : str
        What produced the result.
    steps : int
        Integrator steps taken.
    """

    coefficient_map: np.ndarray
    delta: float
    delta_str: str
    psi_end: float
    backend: str
    precision: str
    steps: int
    delta_exact: object = None


def _equations(kind, x, pars, lib):
    """d/du of ``x = (psi, y1, z1, y2, z2)`` with the functions of ``lib`` (math, mpmath
    or heyoka): the one statement of the reduced problem for every integrator."""
    m, m1, c3, shape, sign = pars
    sp, cp = lib.sin(x[0]), lib.cos(x[0])
    q = _coefficient(kind, sp, cp, m, c3, shape, sign)
    return [-lib.sqrt(m1 + m * sp * sp), x[2], -q * x[1], x[4], -q * x[3]]


def _segment_scipy(prob, sign, rtol=None):
    from scipy.integrate import solve_ivp

    pars = [float(v) for v in (prob.m, prob.m1, prob.c3, prob.shape)] + [sign]
    # rtol=None is the verified default 1e-13; a looser rtol (work-precision
    # studies) scales the absolute tolerances by the same factor.
    scale = 1.0 if rtol is None else rtol / 1e-13
    atol = [scale * max(1e-300, 1e-17 * math.sqrt(pars[1]))] + [scale * 1e-16] * 4
    sol = solve_ivp(
        lambda u, x: _equations(prob.kind, x, pars, math),
        (0.0, float(prob.K)),
        [math.pi / 2, 1.0, 0.0, 0.0, 1.0],
        method="DOP853",
        rtol=1e-13 if rtol is None else rtol,
        atol=atol,
    )
    if not sol.success:
        raise RuntimeError(f"transverse integration failed: {sol.message}")
    x = sol.y[:, -1]
    return [[x[1], x[3]], [x[2], x[4]]], abs(x[0]), len(sol.t) - 1


#: Per-thread cache of compiled integrators: an integrator holds mutable state (time, state,
#: pars), so threads (ThreadPoolExecutor sweeps) must not share one. heyoka caches the
#: compiled code itself, so a new thread rebuilds its integrators in milliseconds.
_THREAD_LOCAL = threading.local()

#: heyoka parameters used by each kind: (m, m1, c3[, shape[, sign]]).
_NPARS = {
    "pendulum-lib": 3,
    "pendulum-rot": 3,
    "breather-LG": 4,
    "breather-LD": 4,
    "breather-R": 5,
}


def _heyoka_integrator(kind, t, tol=None):
    """The heyoka integrator of ``kind`` in the tier ``t`` (``tol=None``: heyoka's
    default, the machine epsilon of the tier), built once per thread."""
    cache = _THREAD_LOCAL.__dict__.setdefault("integrators", {})
    key = (kind, t.name, tol)
    if key not in cache:
        hy = load_heyoka()
        x = hy.make_vars("psi", "y1", "z1", "y2", "z2")
        rhs = _equations(kind, x, [hy.par[i] for i in range(5)], hy)
        kw = {} if tol is None else {"tol": t.to_hy(float(tol))}
        cache[key] = hy.taylor_adaptive(
            list(zip(x, rhs)),
            t.hy_array([0] * 5),
            pars=t.hy_array([0] * _NPARS[kind]),
            compact_mode=t.extended,
            **t.hy_kwargs,
            **kw,
        )
    return cache[key]


def _segment_heyoka(prob, sign, t, tol=None):
    hy = load_heyoka()
    ta = _heyoka_integrator(prob.kind, t, tol)
    with mp.workdps(120):  # every digit of the mpmath parameters
        pars = [prob.m, prob.m1, prob.c3, prob.shape, sign][: _NPARS[prob.kind]]
        ta.pars[:] = t.hy_array(pars)
        ta.state[:] = t.hy_array([mp.pi / 2, 1, 0, 0, 1])
        K = t.to_hy(prob.K)
    ta.time = t.to_hy(0)
    res = ta.propagate_until(K)
    if res[0] != hy.taylor_outcome.time_limit:
        raise RuntimeError(f"transverse integration stopped early: {res[0]}")
    x = ta.state.copy()
    return [[x[1], x[3]], [x[2], x[4]]], abs(float(x[0])), int(res[3])


def _segment_mpmath(prob, sign, dps):
    with mp.workdps(dps):
        pars = [mp.mpf(v) for v in (prob.m, prob.m1, prob.c3, prob.shape)] + [sign]
        f = mp.odefun(
            lambda u, x: _equations(prob.kind, x, pars, mp), 0, [mp.pi / 2, 1, 0, 0, 1]
        )
        x = f(mp.mpf(prob.K))
        return [[x[1], x[3]], [x[2], x[4]]], abs(float(x[0])), 0


def _half_map(P1, P2):
    """Map over the coefficient's half period from the segment maps (2x2 nested lists, any number type).

    ``P1``: ``[0, K]`` forward; ``P2``: ``[2K, K]`` backward in ``s = 2K - u``,
    basis ``(y, dy/ds)`` (``None`` when the half period is one segment). The
    inverse of ``S P2 S`` is its adjugate ``[[d, b], [c, a]]``: ``det P2 = 1`` is
    the Wronskian, exact by construction. Forming the determinant of the
    computed matrix instead cancels catastrophically near the breather
    separatrix (entries ~ |E - 4.5|^-1/2, ``det`` = difference of two products
    ~ |E - 4.5|^-1): that was the float64 failure of R (``tests/test_extremes.py``).
    """
    if P2 is None:
        return P1
    (a, b), (c, d) = P2
    (e, f), (g, h) = P1
    return [[d * e + b * g, d * f + b * h], [c * e + a * g, c * f + a * h]]


def _coefficient_map(Ph):
    """``S Ph^-1 S Ph`` with ``Ph^-1`` the adjugate (``det Ph = 1``): ``[[t, 2qs], [2pr, t]]``, ``t = ps + qr``.

    ``Delta = 2t``. Near a separatrix the two products ``ps`` and ``qr`` have the
    same sign (measured for pendula and breathers at every depth tested), so
    ``Delta`` keeps the relative accuracy of the entries.
    """
    (p, q), (r, s) = Ph
    t = p * s + q * r
    return [[t, 2 * q * s], [2 * p * r, t]]


def _compose_mp(P1, P2, dps):
    """Coefficient map and Delta in mpmath at ``dps`` digits from entries of any type (via ``str``)."""

    def conv(P):
        return None if P is None else [[mp.mpf(str(v)) for v in row] for row in P]

    with mp.workdps(dps):
        C = _coefficient_map(_half_map(conv(P1), conv(P2)))
        return C, 2 * C[0][0]


def solve_hill(
    prob: HillProblem,
    digits: int | Tier | None = None,
    tol: float | None = None,
    *,
    integrator: str | None = None,
) -> HillSolution:
    """Integrate the reduced transverse problem and return the coefficient-period map.

    Parameters
    ----------
    prob : HillProblem
        From :func:`hill_problem` (with the same ``digits``, or more).
    digits : int or Tier, optional
        The integrator and tier of :func:`~rotorlib.core.precision.precision_tier`:
        heyoka in the tier of ``digits``; without heyoka scipy (float64) or mpmath's
        Taylor integrator.
    tol : float, optional
        Loosens or tightens the integrator: scipy's ``rtol`` (default 1e-13, absolute
        tolerances scaled alike) or heyoka's ``tol`` (default: the machine epsilon of
        the tier). The defaults are the verified tiers; other values serve
        work-precision studies (``benchmarks/bench_precision.py``). Ignored by mpmath.
    integrator : {None, 'heyoka', 'scipy', 'mpmath'}, optional
        Which integrator solves the problem: ``None`` the one
        :func:`~rotorlib.core.precision.precision_tier` picks; a name forces it, to
        check one integrator against another (the precision
        is still ``digits``: scipy integrates in float64 only, mpmath at ``digits + 5``
        working digits, 20 for float64).

    Returns
    -------
    HillSolution
        The segment maps are composed with exact adjugates (``_half_map``,
        ``_coefficient_map``) in the working precision. When the float64 ``Delta``
        overflows (breathers at ``|E - 4.5| < ~e^-350``: ``Delta ~ |E - 4.5|^-2``) the
        float64 entries are composed again in mpmath, so ``delta_exact`` and
        ``delta_str`` still carry the value (``delta`` and ``coefficient_map`` are then
        ``inf``).

    Examples
    --------
    >>> from rotorlib.core.closed_forms import pendulum
    >>> sol = solve_hill(hill_problem(pendulum(E=3.9)))
    >>> round(sol.delta, 10), sol.precision, sol.psi_end < 1e-13
    (-0.1396851546, 'float64', True)
    """
    integrator, t = integrator_tier(digits, integrator)
    if t.name == "real128" and mp.mpf(prob.m1) < mp.mpf(REAL128_MIN_M1):
        raise ValueError(
            f"m1 = {mp.nstr(mp.mpf(prob.m1), 3)} is below the real128 range (m1 >= {REAL128_MIN_M1}, "
            "|E - sep| > ~1e-4800, log > -11050): use digits > 31 (multiprecision)"
        )
    if integrator == "scipy":
        if t.extended:
            raise ValueError(f"scipy integrates in float64 only; {t.name} needs heyoka")
        segment = functools.partial(_segment_scipy, prob, rtol=tol)
    elif integrator == "heyoka":
        dps = 36 if t.name == "real128" else int(t.bits / 3.33) + 2
        segment = functools.partial(_segment_heyoka, prob, t=t, tol=tol)
    elif integrator == "mpmath":
        dps = mp.libmp.prec_to_dps(t.bits)
        segment = functools.partial(_segment_mpmath, prob, dps=dps)
    else:
        raise ValueError(
            f"integrator must be heyoka, scipy or mpmath, got {integrator!r}"
        )
    P1, r1, n1 = segment(1.0)
    P2, r2, n2 = segment(-1.0) if prob.kind == "breather-R" else (None, 0.0, 0)
    if t.extended:
        C, dexact = _compose_mp(P1, P2, dps + 5)
        dstr = mp.nstr(dexact, dps - 2 if integrator == "heyoka" else dps - 5)
    else:
        C = _coefficient_map(_half_map(_to_float(P1), _to_float(P2)))
        dexact = 2.0 * C[0][0]
        dstr = repr(dexact)
        if not math.isfinite(dexact):
            C, dexact = _compose_mp(_to_float(P1), _to_float(P2), 20)
            dstr = mp.nstr(dexact, 16)
    Cf = np.array(_to_float(C))
    return HillSolution(
        Cf, float(dexact), dstr, max(r1, r2), integrator, t.name, n1 + n2, dexact
    )


def _to_float(P):
    """A 2x2 nested list (or ``None``) of any number type as floats."""
    return None if P is None else [[float(v) for v in row] for row in P]


#: Smallest m1 the real128 tier accepts (real128 normals reach 3.4e-4932; psi decays to ~sqrt(m1)).
REAL128_MIN_M1 = "1e-4800"
