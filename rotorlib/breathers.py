"""The rotational isosceles breather R, its period-doubling transition and its daughter family (paper §8).

The breather ``phi1 = phi2 = phi`` is ``b1 = 2 phi, b2 = 0`` in the breather variables
``[b1, b2, q1, q2]`` of :mod:`rotorlib.system` (the paper's beta_i, pi_i). Its
monodromy is block diagonal, ``(b1, q1 | b2, q2)`` = (longitudinal | transverse),
with ``tr M = 2 + Delta`` for R (``Delta^2`` for LG, LD); it comes from
:func:`rotorlib.monodromy.monodromy`.

Transition
    :func:`breather_transitions` locates the single stability transition of R
    (``tr M = 0``, a period doubling; paper E ~ 8.97, period ~ 2.63) by ``brentq``
    in float64 (~1e-15) and, with ``digits > 15``, refines it by one Newton step
    with the trace evaluated at that many digits (heyoka real128 / multiprecision).

Daughter family ``PD^b``
    Born at the transition with the doubled period. Two searches:

    * the paper's (:func:`daughter_by_er_minimisation`): start at
      ``(b1, b2, q1, q2) = (0, delta, q1, 0)``, integrate until ``b1 = 8 pi``
      (two breather periods) and minimise ``Er(q1)``;
    * symmetric shooting (:func:`daughter_by_shooting`). ``V(b1, b2)`` is even in
      ``b1`` and in ``b2`` separately, so ``(b1, b2, q1, q2, t) ->
      (-b1, b2, q1, -q2, -t)`` and ``(b1, b2, q1, q2, t) -> (4 pi - b1, -b2, q1, q2, -t)``
      are reversing symmetries with fixed sets ``{b1 = 0, q2 = 0}`` and
      ``{b1 = 2 pi, b2 = 0}``. An orbit starting on the first set that reaches the
      second when ``b1`` first equals ``2 pi`` is periodic, with period four times
      that time, and ``b2`` changes sign after half a period (multiplier -1): the
      period-doubled daughter. One unknown (``delta`` at fixed ``E``, or ``E`` at
      fixed ``delta``), a quarter period of integration.

    The family is continued in ``delta`` (:func:`daughter_family`); it exists for
    ``E < E_PD`` (a backward fork-like bifurcation). Its monodromy comes from the
    4x4 variational equations over the full period (heyoka float64, tolerance
    ~2e-16).

Precision: the transition energy to ~1e-15 in float64 and to >= 20 digits with
``digits=30``; daughter orbits close to ~1e-12 over their period and ``tr M`` is
accurate to ~1e-9 (variational equations over one period of a mildly unstable
orbit). ``tests/test_breathers.py`` checks both against independent integrators.
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field

import numpy as np
from scipy import optimize

from .monodromy import monodromy
from .orbits import breather
from .periodic import PeriodicOrbit
from .system import beta_to_alpha, energy_beta, potential_beta

__all__ = [
    "BreatherTransition", "breather_transitions", "pd_transition", "pd_eigenstructure", "PDEigenstructure",
    "breather_trace", "daughter_by_shooting", "daughter_by_er_minimisation", "daughter_family",
    "DaughterFamily", "breather_daughter", "DAUGHTER_E_MIN", "daughter_quarter_residual",
    "er_function", "beta_monodromy", "daughter_trajectory", "half_map_trace", "DEFAULT_DELTAS",
]

TWO_PI = 2.0 * math.pi
#: Lower end of the energy range over which :func:`breather_daughter` is supported (validated continuation).
DAUGHTER_E_MIN = 5.3
#: The grid of energies scanned for the transition of R.
#: Default continuation amplitudes b2(0) of the daughter family.
DEFAULT_DELTAS = np.concatenate([np.linspace(0.02, 0.12, 6), np.linspace(0.15, 5.65, 111), [5.67, 5.69]])
_SCAN = np.concatenate([np.linspace(4.55, 20.0, 160), np.geomspace(20.0, 1e4, 40)[1:]])


def breather_trace(E, family="R", digits=None):
    """``tr M`` of the breather ``family`` at energy ``E`` (float64 unless ``digits > 15``)."""
    M = monodromy(breather(E, family), digits=digits)
    return M.trace if digits is None or digits <= 15 else M


# ----------------------------------------------------------------------------------------------
# the transition
# ----------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class BreatherTransition:
    """A stability transition of the isosceles breather family.

    Attributes
    ----------
    label : str
        ``PD^b``.
    kind : str
        ``PD`` (``tr M = 0``) or ``IS`` (``tr M = 4``).
    family : str
        Breather family (``R``).
    E : float
        Transition energy (float64).
    E_str : str
        Energy as a decimal string with every digit the precision supports.
    period, period_str : float, str
        Period of the breather at ``E``.
    transition : str
        ``unstable->stable`` or ``stable->unstable`` as ``E`` increases.
    slope : float
        ``d tr M / dE`` at ``E``.
    precision : str
        ``float64`` or the extended tier used for ``E_str``.
    """

    label: str
    kind: str
    family: str
    E: float
    E_str: str
    period: float
    period_str: str
    transition: str
    slope: float
    precision: str

    def to_record(self) -> dict:
        """JSON-serialisable record (the ``bifurcations --family breather`` output)."""
        return {"label": self.label, "kind": self.kind, "family": self.family, "phase": "rot", "n": 1,
                "E": self.E_str, "log_abs_dE_4.5": repr(math.log(abs(self.E - 4.5))),
                "period": self.period_str, "transition": self.transition, "slope": self.slope,
                "precision": self.precision}


def _trace_slope(E, family="R", h=1e-5):
    return (breather_trace(E + h, family) - breather_trace(E - h, family)) / (2 * h)


def breather_transitions(family="R", digits=None, E_max=1e4):
    """Every stability transition (``tr M`` crossing 0 or 4) of a breather family.

    Parameters
    ----------
    family : {'R', 'LG', 'LD'}
        Only ``R`` has transitions (LG and LD have ``tr M > 4`` throughout: an empty list).
    digits : int, optional
        ``> 15``: refine each energy with the trace at that many digits.
    E_max : float
        Upper end of the scan for R.

    Returns
    -------
    list of BreatherTransition
    """
    if family not in ("R", "LG", "LD"):
        raise ValueError(f"breather family must be R, LG or LD; got {family!r}")
    if family != "R":
        grid = np.linspace(0.05, 4.45, 45) if family == "LG" else np.linspace(4.01, 4.49, 25)
    else:
        grid = _SCAN[_SCAN <= E_max]
    tr = np.array([breather_trace(E, family) for E in grid])
    out = []
    for level, kind in ((0.0, "PD"), (4.0, "IS")):
        s = np.sign(tr - level)
        for i in np.nonzero(s[:-1] * s[1:] < 0)[0]:
            f = lambda E: breather_trace(E, family) - level     # noqa: E731
            E = optimize.brentq(f, grid[i], grid[i + 1], xtol=1e-15, rtol=8.9e-16, maxiter=200)
            out.append(_make_transition(E, kind, level, family, digits))
    return sorted(out, key=lambda t: t.E)


def _make_transition(E, kind, level, family, digits):
    slope = _trace_slope(E, family)
    period = breather(E, family).period
    direction = ("unstable->stable" if slope > 0 else "stable->unstable") if kind == "PD" else \
        ("stable->unstable" if slope > 0 else "unstable->stable")
    if digits is None or digits <= 15:
        return BreatherTransition("PD^b" if kind == "PD" else "IS^b", kind, family, E, repr(E), period,
                                  repr(period), direction, slope, "float64")
    import mpmath as mp

    M = monodromy(breather(E, family), digits=digits)
    dT = breather(E, family).dperiod_dE
    with mp.workdps(digits + 10):
        corr = -(mp.mpf(M.trace_str) - level) / mp.mpf(slope)
        E_ext = mp.mpf(repr(E)) + corr          # the extended trace is evaluated at the decimal repr(E)
        per = mp.mpf(M.period_str) + mp.mpf(dT) * corr
        E_str, per_str = mp.nstr(E_ext, digits - 5), mp.nstr(per, digits - 5)
    return BreatherTransition("PD^b" if kind == "PD" else "IS^b", kind, family, float(E_ext), E_str,
                              float(per), per_str, direction, slope, M.precision)


def pd_transition(digits=None) -> BreatherTransition:
    """The period-doubling transition of the rotational breather R (paper: E ~ 8.97, period ~ 2.63)."""
    pds = [t for t in breather_transitions("R", digits=digits) if t.kind == "PD"]
    if len(pds) != 1:
        raise RuntimeError(f"expected one PD transition of R, found {len(pds)}")
    return pds[0]


@dataclass(frozen=True)
class PDEigenstructure:
    """Spectrum and eigenvectors of M at the breather's PD transition.

    Attributes
    ----------
    eigenvalues : ndarray (4,)
        Eigenvalues of M (basis ``(b1, q1, b2, q2)``).
    eigenvectors : dict
        ``{+1: ndarray (4, k), -1: ndarray (4, k)}``: a basis of each eigenspace
        (null space of ``M -+ I`` by SVD, singular values below ``tol`` counted as zero).
    geometric_multiplicity : dict
        ``{+1: k, -1: k}``.
    singular_values : dict
        Singular values of ``M - I`` and ``M + I``.
    matrix : ndarray (4, 4)
    basis : tuple of str
    """

    eigenvalues: np.ndarray
    eigenvectors: dict
    geometric_multiplicity: dict
    singular_values: dict
    matrix: np.ndarray
    basis: tuple


def pd_eigenstructure(E=None, tol=1e-8) -> PDEigenstructure:
    """Eigenvalues and eigenvectors of M of the breather R at its PD transition (or at ``E``)."""
    if E is None:
        E = pd_transition().E
    M = monodromy(breather(E, "R"))
    A = M.matrix
    vecs, mult, svals = {}, {}, {}
    for lam in (1, -1):
        _, s, vh = np.linalg.svd(A - lam * np.eye(4))
        null = vh[s < tol * max(1.0, s[0])].T
        null = null * np.sign(null[np.argmax(np.abs(null), axis=0), range(null.shape[1])])
        vecs[lam], mult[lam], svals[lam] = null, null.shape[1], s
    ev = np.linalg.eigvals(A)
    return PDEigenstructure(np.sort_complex(ev), vecs, mult, svals, A, M.basis)


# ----------------------------------------------------------------------------------------------
# integrators (heyoka, breather variables)
# ----------------------------------------------------------------------------------------------

def _beta_sys(hy):
    b1, b2, q1, q2 = hy.make_vars("b1", "b2", "q1", "q2")
    sp, sm = hy.sin(0.5 * (b1 + b2)), hy.sin(0.5 * (b1 - b2))
    return [(b1, 2.0 * q1), (b2, 6.0 * q2), (q1, -0.5 * (sp + sm + 2.0 * hy.sin(b1))), (q2, -0.5 * (sp - sm))], b1


@functools.lru_cache(maxsize=None)
def _event_integrator():
    """Nonlinear flow with a terminal event at ``b1 = par[0]`` (upward crossing)."""
    import heyoka as hy

    sys, b1 = _beta_sys(hy)
    ev = hy.t_event(b1 - hy.par[0], direction=hy.event_direction.positive)
    return hy.taylor_adaptive(sys, [0.0] * 4, pars=[0.0], t_events=[ev], compact_mode=True)


@functools.lru_cache(maxsize=None)
def _var_integrator():
    import heyoka as hy

    sys, _ = _beta_sys(hy)
    vsys = hy.var_ode_sys(sys, hy.var_args.vars, order=1)
    return hy.taylor_adaptive(vsys, [0.0] * 20, compact_mode=True)


def _flow_to_b1(x0, target, t_max=100.0):
    """Integrate from ``x0 = [b1, b2, q1, q2]`` until ``b1 = target``; returns ``(t, state)``."""
    import heyoka as hy

    ta = _event_integrator()
    ta.time = 0.0
    ta.state[:] = x0
    ta.pars[0] = target
    res = ta.propagate_until(t_max)
    if int(res[0]) < -1000:             # a terminal event gives a small outcome code, limits huge ones
        raise ValueError(f"the orbit from {list(x0)} does not reach b1 = {target:.6g} (not rotational)")
    return float(ta.time), ta.state.copy()


def beta_monodromy(x0, period):
    """Monodromy in breather variables ``[b1, b2, q1, q2]`` and the final state, by heyoka's
    variational equations over ``period``."""
    ta = _var_integrator()
    ta.time = 0.0
    ta.state[:] = np.concatenate([np.asarray(x0, float), np.eye(4).ravel()])
    ta.propagate_until(float(period))
    st = ta.state.copy()
    return st[4:].reshape(4, 4), st[:4]


def _beta_to_alpha_matrix():
    return np.array([beta_to_alpha(e) for e in np.eye(4)]).T


# ----------------------------------------------------------------------------------------------
# the daughter family
# ----------------------------------------------------------------------------------------------

def _q1(E, delta):
    k = E - potential_beta(0.0, delta)
    if k <= 0:
        raise ValueError(f"E = {E!r} is below V(0, delta = {delta!r})")
    return math.sqrt(k)


def daughter_quarter_residual(E, delta):
    """``(b2, t)`` when ``b1`` first reaches ``2 pi`` from ``(0, delta, q1(E, delta), 0)``."""
    t, x = _flow_to_b1([0.0, delta, _q1(E, delta), 0.0], TWO_PI)
    return x[1], t


def er_function(q1_0, delta):
    """The paper's ``Er(pi_1(0))``: integrate ``(0, delta, q1_0, 0)`` until ``b1 = 8 pi``."""
    _, x = _flow_to_b1([0.0, delta, q1_0, 0.0], 4 * TWO_PI)
    return math.sqrt((x[1] - delta) ** 2 + (x[2] - q1_0) ** 2 + x[3] ** 2)


def _finish(E, delta, method, extra=None, q1_0=None, period=None) -> PeriodicOrbit:
    """Build the PeriodicOrbit from ``(0, delta, q1, 0)``.

    By default the orbit is taken to be the symmetric daughter: period = 4 x the time to
    ``b1 = 2 pi``. With ``period`` given (the Er search), that period is used as is.
    The monodromy is integrated over the full period; ``residual`` is the actual closure.
    """
    q1 = _q1(E, delta) if q1_0 is None else float(q1_0)
    x0 = np.array([0.0, delta, q1, 0.0])
    tq, xq = _flow_to_b1(x0, TWO_PI)
    T = 4.0 * tq if period is None else float(period)
    Mb, xT = beta_monodromy(x0, T)
    dx = xT - x0 - np.array([4 * TWO_PI, 0.0, 0.0, 0.0])
    Ta = _beta_to_alpha_matrix()
    Ma = Ta @ Mb @ np.linalg.inv(Ta)
    ts = np.linspace(0.0, T, 401)
    traj = _sample(x0, ts)
    b2max = float(np.max(np.abs(traj[:, 1])))
    ex = {"method": method, "delta_b2": float(delta), "q1_0": float(x0[2]), "quarter_period": tq,
          "beta2_max": b2max, "symmetric_residual": abs(float(xq[1]))}
    ex.update(extra or {})
    E_true = float(energy_beta(x0))
    return PeriodicOrbit("PD^b", float(E), T, beta_to_alpha(x0), Ma, float(np.trace(Mb)),
                         float(np.max(np.abs(dx))), abs(E_true - E), "float64",
                         b2max / 4.0, b2max / 4.0, math.log(abs(E - 4.0)), ex)


def _sample(x0, ts):
    """States ``[b1, b2, q1, q2]`` at times ``ts`` (heyoka, float64)."""
    ta = _event_integrator()
    ta.time = 0.0
    ta.state[:] = x0
    ta.pars[0] = 1e9                       # no event
    out = ta.propagate_grid(np.asarray(ts, float))
    return np.asarray(out[-1])


@dataclass(frozen=True)
class DaughterFamily:
    """The daughter family ``PD^b`` continued in ``delta = b2(0)``.

    Attributes
    ----------
    delta, E, period, trace : ndarray
        Along the branch (``trace`` = ``tr M`` of the full 4x4 monodromy).
    E_PD : float
        The parent's transition energy.
    slope_ratio : float
        ``tr M_new'(E) / tr M_pend'(E)`` at the bifurcation, from the continuation:
        ``d tr M / d(delta^2)`` divided by ``dE / d(delta^2)`` (polynomial fit in
        ``delta^2`` of the points with ``delta <= delta_fit``), over the parent's slope.
    parent_slope : float
    E_unstable : float
        Energy below which the family is unstable (``tr M`` leaves ``(0, 4)``).
    unstable_crossing : str
        ``tr M = 0`` or ``tr M = 4``: which boundary is crossed there.
    """

    delta: np.ndarray
    E: np.ndarray
    period: np.ndarray
    trace: np.ndarray
    E_PD: float
    slope_ratio: float
    parent_slope: float
    E_unstable: float
    unstable_crossing: str
    fit: dict = field(default_factory=dict)


def _E_at_delta(delta, E_guess, E_PD, step=None):
    """The daughter energy at fixed ``delta`` (root in E of the quarter-period residual).

    Brackets the root around ``E_guess`` by widening ``[E_guess - s, E_guess + s]``
    (never above ``E_PD``), then ``brentq`` (``xtol`` 1e-14).
    """
    f = lambda E: daughter_quarter_residual(E, delta)[0]        # noqa: E731
    s = step if step is not None else max(1e-4, 0.02 * (E_PD - E_guess))
    for _ in range(30):
        lo, hi = E_guess - s, min(E_guess + s, E_PD + 1e-9)
        try:
            flo, fhi = f(lo), f(hi)
        except ValueError:                 # too low an energy: the orbit no longer rotates
            s *= 0.5
            continue
        if flo * fhi <= 0:
            return optimize.brentq(f, lo, hi, xtol=1e-14, rtol=8.9e-16)
        s *= 2.0
    raise RuntimeError(f"no daughter orbit bracketed at delta = {delta}")


def daughter_family(deltas=None, E_PD=None, delta_fit=0.12):
    """Continue the daughter family in ``delta = b2(0)`` from the bifurcation.

    Parameters
    ----------
    deltas : array_like, optional
        Increasing positive amplitudes (default: 0.02 ... 5.66, reaching E ~ 5.32).
    E_PD : float, optional
        Parent transition energy (computed when omitted).
    delta_fit : float
        Points with ``delta <= delta_fit`` enter the slope fit.

    Returns
    -------
    DaughterFamily
    """
    if E_PD is None:
        E_PD = pd_transition().E
    if deltas is None:
        deltas = DEFAULT_DELTAS
    deltas = np.asarray(deltas, float)
    Es, Ts, trs = [], [], []
    E_guess, step = E_PD - 1e-4, None
    for k, d in enumerate(deltas):
        E = _E_at_delta(d, E_guess, E_PD, step)
        orb = _finish(E, d, "shooting")
        Es.append(E)
        Ts.append(orb.period)
        trs.append(orb.trace)
        if k + 1 < len(deltas):            # secant predictor in delta^2 for the next amplitude
            if k == 0:
                E_guess = E_PD + (E - E_PD) * (deltas[1] / d) ** 2
            else:
                s0, s1, s2 = deltas[k - 1] ** 2, d * d, deltas[k + 1] ** 2
                E_guess = E + (E - Es[-2]) * (s2 - s1) / (s1 - s0)
            step = max(1e-6, 0.1 * abs(E_guess - E))
    Es, Ts, trs = map(np.array, (Es, Ts, trs))
    sel = deltas <= delta_fit
    s = deltas[sel] ** 2
    pE = np.polyfit(s, Es[sel], 2)
    pT = np.polyfit(s, trs[sel], 2)
    parent = _trace_slope(E_PD)
    ratio = (pT[-2] / pE[-2]) / parent
    # leaving the stable window (0, 4)
    E_unst, which = float("nan"), "none"
    for lev, name in ((0.0, "tr M = 0"), (4.0, "tr M = 4")):
        g = trs - lev
        idx = np.nonzero((np.sign(g[:-1]) != np.sign(g[1:])) & (deltas[:-1] > 0.05))[0]
        if len(idx):
            i = idx[0]

            def h(d, lev=lev):
                E = _E_at_delta(d, Es[i], E_PD)
                return _finish(E, d, "shooting").trace - lev
            dc = optimize.brentq(h, deltas[i], deltas[i + 1], xtol=1e-10)
            Ec = _E_at_delta(dc, Es[i], E_PD)
            if math.isnan(E_unst) or Ec > E_unst:
                E_unst, which = Ec, name
    return DaughterFamily(deltas, Es, Ts, trs, E_PD, float(ratio), float(parent), E_unst, which,
                          {"E_fit": pE, "trace_fit": pT, "E_at_birth": pE[-1], "trace_at_birth": pT[-1]})


def daughter_by_shooting(E, delta_bracket=None) -> PeriodicOrbit:
    """The daughter orbit at energy ``E`` by symmetric quarter-period shooting (unknown: ``delta``)."""
    if delta_bracket is None:
        raise ValueError("give a bracket (delta_lo, delta_hi) for delta")
    f = lambda d: daughter_quarter_residual(E, d)[0]            # noqa: E731
    d = optimize.brentq(f, *delta_bracket, xtol=1e-15, rtol=8.9e-16)
    return _finish(E, d, "symmetric shooting (quarter period)")


def daughter_by_er_minimisation(delta, q1_guess, width=0.05) -> PeriodicOrbit:
    """The paper's search: fix ``b2(0) = delta``, minimise ``Er(pi1(0))`` over two breather periods.

    Brent's method from the bracket ``(q1_guess - width, q1_guess, q1_guess + width)``;
    ``pi1(0)`` to ~1e-8. The returned orbit has the energy of ``(0, delta, pi1(0), 0)``,
    the period ``t*`` (time to ``b1 = 8 pi``) and ``extra['Er']``; nothing assumes the
    symmetry, and ``extra['symmetric_residual'] = |b2|`` at ``b1 = 2 pi`` tells whether the
    minimiser found the symmetric daughter (~0) or another orbit through the same line.
    """
    res = optimize.minimize_scalar(er_function, bracket=(q1_guess - width, q1_guess, q1_guess + width),
                                   args=(delta,), tol=1e-12)
    q1 = float(res.x)
    E = q1 * q1 + float(potential_beta(0.0, delta))
    t_star, _ = _flow_to_b1([0.0, delta, q1, 0.0], 4 * TWO_PI)
    return _finish(E, delta, "Er minimisation (paper)", {"Er": float(res.fun)}, q1_0=q1, period=t_star)


@functools.lru_cache(maxsize=4)
def _branch_table():
    fam = daughter_family()
    return fam


def breather_daughter(E, digits=None) -> PeriodicOrbit:
    """The orbit of the daughter family ``PD^b`` at energy ``E`` (the ``orbit PD^b`` command).

    Parameters
    ----------
    E : float
        ``DAUGHTER_E_MIN <= E < E_PD`` (~8.969).
    digits : int, optional
        Only float64 (``None`` or <= 15) is implemented.

    Returns
    -------
    PeriodicOrbit
        Label ``PD^b``, state ``[a1, a2, p1, p2]`` at ``b1 = 0`` (``b2 = delta``,
        ``q2 = 0``), the doubled period, the 4x4 monodromy in alpha order and its
        trace. ``alpha1_max = alpha2_max = max|b2|/4``: the largest excursion of
        ``a1`` and of ``a2`` away from the parent breather's line ``a2 = 3 a1`` at
        fixed ``b1`` (``a1 = (b1 + b2)/4``, ``a2 = (3 b1 - b2)/4``); ``extra`` has
        ``beta2_max``, ``delta_b2``, ``q1_0``.

    Raises
    ------
    ValueError
        Outside the family's existence range, or for ``digits > 15``.
    """
    from .energy import as_float

    E = as_float(E, "E")
    if digits is not None and digits > 15:
        raise ValueError("breather_daughter: only float64 (digits <= 15) is implemented")
    fam = _branch_table()
    if not (DAUGHTER_E_MIN <= E < fam.E_PD):
        raise ValueError(f"the breather daughter family PD^b exists for E < E_PD = {fam.E_PD:.12f} "
                         f"(computed for {DAUGHTER_E_MIN} <= E < {fam.E_PD:.12f}); got E = {E!r}")
    # E decreases monotonically along the branch: bracket delta from the table
    i = int(np.searchsorted(-fam.E, -E))          # fam.E[i - 1] > E >= fam.E[i]
    if i >= len(fam.E):
        raise ValueError(f"E = {E!r} is below the computed branch (E >= {fam.E[-1]:.6f})")
    lo = 1e-3 if i == 0 else fam.delta[i - 1]
    hi = fam.delta[i]
    return daughter_by_shooting(E, (0.999 * lo, 1.001 * hi))


def daughter_trajectory(orbit: PeriodicOrbit, n=801) -> np.ndarray:
    """States ``[b1, b2, q1, q2]`` at ``n`` equally spaced times over one period of a daughter orbit."""
    x0 = np.array([0.0, orbit.extra["delta_b2"], orbit.extra["q1_0"], 0.0])
    return _sample(x0, np.linspace(0.0, orbit.period, int(n)))


def half_map_trace(orbit: PeriodicOrbit) -> float:
    """``tr N`` with ``N = S Phi(T/2)``, ``S = diag(1, -1, 1, -1)`` in ``[b1, b2, q1, q2]``.

    The daughter satisfies ``x(t + T/2) = S x(t) + (4 pi, 0, 0, 0)``, so ``M = N^2``; N is
    symplectic with eigenvalues ``1, 1, mu, 1/mu``, hence ``tr M = 2 + mu^2 + mu^-2 =
    (tr N - 2)^2``: ``tr M`` of this family can touch 0 but never go below it.
    """
    x0 = np.array([0.0, orbit.extra["delta_b2"], orbit.extra["q1_0"], 0.0])
    Phi, _ = beta_monodromy(x0, 0.5 * orbit.period)
    return float(np.trace(np.diag([1.0, -1.0, 1.0, -1.0]) @ Phi))
