"""The nonlinear 4-D flow in pendulum variables, with section events, in float64 or real128.

The equations are Hamilton's equations of
``H = p1^2/4 + 3 p2^2/4 + 3 - cos 2a1 - cos(a2 - a1) - cos(a1 + a2)``
(:func:`rotorlib.system.rhs_alpha`), integrated with heyoka's Taylor method
(tolerance = machine epsilon of the chosen type: 2.2e-16 in float64,
1.9e-34 in real128). Integrators are compiled once per (precision, event)
and cached (~0.5 s float64, ~2 s real128 the first time).

Events (terminal, located to the working precision by heyoka's polynomial
root finder):

``turn``
    ``p2 = 0`` while ``p2`` decreases: the turning point of a librating ``a2``.
``a2_down``
    ``a2 = level`` while ``a2`` decreases.
``a2_up``
    ``a2 = level`` while ``a2`` increases.

Precision: one crossing costs ~0.1 ms (float64) and ~10 ms (real128) for a
quarter period near E = 4. The flow itself near the separatrix amplifies
round-off like ``1/|E - 4|`` (``../shared/NUMERICS.md``), so float64 results
keep ~``16 + log10|E - 4|`` digits; real128 keeps ~``34 + log10|E - 4|``.
"""
from __future__ import annotations

import functools

import mpmath as mp
import numpy as np

__all__ = ["PRECISIONS", "to_fp", "from_fp", "integrator", "flow_to_event", "flow_for",
           "variational_integrator", "monodromy_matrix", "sample", "extrema"]

PRECISIONS = ("float64", "real128")
EVENTS = ("turn", "a2_down", "a2_up", None)


def _hy():
    import heyoka as hy
    return hy


def _check_precision(precision):
    if precision not in PRECISIONS:
        raise ValueError(f"precision must be one of {PRECISIONS}, got {precision!r}")


def to_fp(v, precision):
    """A number (float, str, mpf) in the integrator's type, without losing digits."""
    if precision == "float64":
        return float(v)
    hy = _hy()
    if isinstance(v, (float, np.floating)):
        v = repr(float(v))
    elif isinstance(v, (int, np.integer)):
        v = str(int(v))
    elif not isinstance(v, str):
        with mp.workdps(40):
            v = mp.nstr(mp.mpf(v), 38)
    return hy.real128(v)


def from_fp(v, precision):
    """Back to a Python number: float (float64) or ``mpmath.mpf`` at 36 digits (real128)."""
    if precision == "float64":
        return float(v)
    with mp.workdps(36):
        return mp.mpf(str(v))


def _dtype(precision):
    return float if precision == "float64" else _hy().real128


def _sys():
    hy = _hy()
    a1, a2, p1, p2 = hy.make_vars("a1", "a2", "p1", "p2")
    s_m, s_p = hy.sin(a2 - a1), hy.sin(a1 + a2)
    two = hy.expression(2.0)
    half = hy.expression(0.5)
    threehalves = hy.expression(1.5)
    sys = [(a1, half * p1), (a2, threehalves * p2),
           (p1, -(two * hy.sin(two * a1) - s_m + s_p)), (p2, -(s_m + s_p))]
    return sys, (a1, a2, p1, p2)


@functools.lru_cache(maxsize=None)
def integrator(precision="float64", event=None):
    """A cached heyoka integrator of the nonlinear flow with one terminal event.

    The event level (for ``a2_up``/``a2_down``) is the runtime parameter ``par[0]``.
    """
    _check_precision(precision)
    if event not in EVENTS:
        raise ValueError(f"event must be one of {EVENTS}, got {event!r}")
    hy = _hy()
    sys, (a1, a2, p1, p2) = _sys()
    kw = {"fp_type": hy.real128} if precision == "real128" else {}
    dt = _dtype(precision)
    evs = []
    if event == "turn":
        evs = [hy.t_event(p2, direction=hy.event_direction.negative, **kw)]
    elif event == "a2_down":
        evs = [hy.t_event(a2 - hy.par[0], direction=hy.event_direction.negative, **kw)]
    elif event == "a2_up":
        evs = [hy.t_event(a2 - hy.par[0], direction=hy.event_direction.positive, **kw)]
    if event in ("a2_down", "a2_up"):
        kw["pars"] = np.zeros(1, dtype=dt)
    return hy.taylor_adaptive(sys, np.zeros(4, dtype=dt), t_events=evs, compact_mode=precision != "float64", **kw)


def flow_to_event(x0, event, level=0.0, precision="float64", t_max=1e4):
    """Integrate from ``x0`` (t = 0) to the first ``event`` and return ``(t, x)``.

    ``x0`` entries and ``level`` may be floats, decimal strings or mpf; the
    result is float64 (a numpy array) or a list of mpf (real128).
    """
    hy = _hy()
    ta = integrator(precision, event)
    dt = _dtype(precision)
    ta.time = to_fp(0.0, precision)
    ta.state[:] = np.array([to_fp(v, precision) for v in x0], dtype=dt)
    if event in ("a2_down", "a2_up"):
        ta.pars[0] = to_fp(level, precision)
    res = ta.propagate_until(to_fp(t_max, precision))
    # a terminal event ends the call with a small integer outcome (heyoka: -1 - index without callback);
    # the named outcomes (success, time_limit, ...) are large negative codes.
    if int(res[0]) < -1000:
        raise RuntimeError(f"event {event!r} not reached before t = {t_max} (outcome {res[0]})")
    t = from_fp(ta.time, precision)
    x = [from_fp(v, precision) for v in ta.state]
    return t, (np.array(x, dtype=float) if precision == "float64" else x)


def flow_for(x0, t, precision="float64"):
    """Integrate from ``x0`` for time ``t`` (no event)."""
    ta = integrator(precision, None)
    dt = _dtype(precision)
    ta.time = to_fp(0.0, precision)
    ta.state[:] = np.array([to_fp(v, precision) for v in x0], dtype=dt)
    ta.propagate_until(to_fp(t, precision))
    x = [from_fp(v, precision) for v in ta.state]
    return np.array(x, dtype=float) if precision == "float64" else x


@functools.lru_cache(maxsize=None)
def variational_integrator(precision="float64"):
    """Flow + first-order variational equations (state then the 4x4 matrix, row-major)."""
    _check_precision(precision)
    hy = _hy()
    sys, _ = _sys()
    vsys = hy.var_ode_sys(sys, hy.var_args.vars, order=1)
    kw = {"fp_type": hy.real128} if precision == "real128" else {}
    return hy.taylor_adaptive(vsys, np.zeros(4, dtype=_dtype(precision)), compact_mode=True, **kw)


def monodromy_matrix(x0, period, precision="float64"):
    """Monodromy matrix (order ``[a1, a2, p1, p2]``) and the end state after ``period``.

    Returns ``(M, x_T)`` as float64 arrays (the trace is returned as an mpf
    in real128 as a third element, else a float).
    """
    ta = variational_integrator(precision)
    dt = _dtype(precision)
    ta.time = to_fp(0.0, precision)
    st = [to_fp(v, precision) for v in x0] + [to_fp(v, precision) for v in np.eye(4).ravel()]
    ta.state[:] = np.array(st, dtype=dt)
    ta.propagate_until(to_fp(period, precision))
    s = [from_fp(v, precision) for v in ta.state]
    M = np.array([[float(s[4 + 4 * i + j]) for j in range(4)] for i in range(4)])
    if precision == "float64":
        tr = float(sum(s[4 + 5 * i] for i in range(4)))
    else:
        with mp.workdps(36):
            tr = sum(s[4 + 5 * i] for i in range(4))
    return M, np.array([float(v) for v in s[:4]]), tr


def sample(x0, period, n=801, precision="float64"):
    """States on a uniform grid of ``n`` times over ``[0, period]``, shape ``(n, 4)`` (float64)."""
    ta = integrator(precision, None)
    dt = _dtype(precision)
    ta.time = to_fp(0.0, precision)
    ta.state[:] = np.array([to_fp(v, precision) for v in x0], dtype=dt)
    grid = np.linspace(0.0, float(period), n)
    if precision == "real128":
        grid = np.array([to_fp(g, precision) for g in grid], dtype=dt)
    out = ta.propagate_grid(grid)
    return np.array(out[-1], dtype=float).reshape(n, 4), np.array(grid, dtype=float)


_FOUND = []


def _record(key):
    def cb(ta, t, d):
        _FOUND.append((key, [v for v in ta.update_d_output(t)]))
    return cb


@functools.lru_cache(maxsize=None)
def _extrema_integrator(precision):
    hy = _hy()
    sys, (a1, a2, p1, p2) = _sys()
    kw = {"fp_type": hy.real128} if precision == "real128" else {}
    return hy.taylor_adaptive(sys, np.zeros(4, dtype=_dtype(precision)),
                              nt_events=[hy.nt_event(p1, _record("a1"), **kw), hy.nt_event(p2, _record("a2"), **kw)],
                              compact_mode=precision != "float64", **kw)


def extrema(x0, period, precision="float64"):
    """``max |a1|`` and the largest excursion of ``a2`` over one period, located exactly.

    The extrema of ``a1`` are at ``p1 = 0`` and those of ``a2`` at ``p2 = 0``;
    each is located by a non-terminal event (precision of the integrator) and
    evaluated with heyoka's dense output. For a rotating ``a2`` (no ``p2 = 0``)
    the excursion is ``max |a2 - 2 pi round(a2 / 2 pi)|`` on a grid of 4001 points.

    Returns ``(a1_max, a2_max)`` as floats.
    """
    ta = _extrema_integrator(precision)
    ta.time = to_fp(0.0, precision)
    ta.state[:] = np.array([to_fp(v, precision) for v in x0], dtype=_dtype(precision))
    _FOUND.clear()
    ta.propagate_until(to_fp(period, precision))
    pts = list(_FOUND)
    _FOUND.clear()
    a1s = [abs(float(x[0])) for k, x in pts if k == "a1"]
    a2s = [abs(float(x[1])) for k, x in pts if k == "a2"]
    a1m = max(a1s + [abs(float(x0[0]))])
    if a2s:
        a2m = max(a2s)
    else:
        st, _ = sample(x0, period, 4001, "float64")
        w = st[:, 1] - 2 * np.pi * np.round(st[:, 1] / (2 * np.pi))
        a2m = float(np.max(np.abs(w)))
    return a1m, a2m
