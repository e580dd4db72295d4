"""The special points of a catalogued family located as roots at 30 digits: the tasks
``locate`` (an IS or PD point: a root of ``tr M - level`` in ``E``), ``touch`` (``tr M``
reaching 4 without crossing it: an extremum of ``tr M``) and ``fold`` (a saddle-node:
an extremum of ``E`` along the branch, parametrised by the shooting unknown ``u``) of
:mod:`rotorlib.beyond.catalogue_tasks`. :mod:`rotorlib.beyond.catalogue_points` makes
their jobs from a family's float64 special points and stores what they return.

Precision: each returns the member at the point as
:func:`rotorlib.beyond.catalogue_members.polish_task` does (30-digit strings) with
``E_error``, the point's precision in ``E``: ~1e-25 for ``locate`` (a secant),
the final bracket (~1e-15) for ``touch``, ~1e-25 for ``fold``
(:func:`fold_task`: ``E`` is quadratic in ``u`` at a fold, so a bracket ``h`` in ``u``
leaves ``E`` to ``~h^2``).
"""

from __future__ import annotations

import math
from collections.abc import Callable

from .catalogue_members import member_strings, problem_of, resolve_member, solved

__all__ = ["locate_task", "touch_task", "fold_task", "golden_minimum"]


def golden_minimum(
    g: Callable[[float], float],
    lo: float,
    hi: float,
    steps: int,
    tol: float = 0.0,
    errors: tuple[type[Exception], ...] = (),
) -> tuple[float, float, float | None, str | None]:
    """A golden-section search for the minimum of ``g`` on ``[lo, hi]``: at most
    ``steps`` steps, stopping when the bracket is below ``tol`` or the float interior
    points no longer move apart. Returns the final bracket, the better of its two
    interior points (the second on a tie) and None; when ``g`` raised one of
    ``errors``, the bracket reached, None and why it stopped there. Why not scipy's bounded ``minimize_scalar``: its
    tolerance has a floor of ``sqrt(float eps) |x|``, while the 30-digit values of
    ``touch_task`` and ``fold_task`` resolve their extremum to the float's last bit.

    Examples
    --------
    >>> lo, hi, best, why = golden_minimum(lambda x: (x - 0.3) ** 2, 0.0, 1.0, 200)
    >>> abs(best - 0.3) < 1e-7, lo <= best <= hi, why
    (True, True, None)
    """
    r = (math.sqrt(5) - 1) / 2
    x1, x2 = hi - r * (hi - lo), lo + r * (hi - lo)
    try:
        f1, f2 = g(x1), g(x2)
        for _ in range(steps):
            if f1 < f2:
                hi, x2, f2 = x2, x1, f1
                x1 = hi - r * (hi - lo)
                f1 = g(x1)
            else:
                lo, x1, f1 = x1, x2, f2
                x2 = lo + r * (hi - lo)
                f2 = g(x2)
            if x1 >= x2 or hi - lo < tol:
                break
    except errors as exc:
        return lo, hi, None, f"{type(exc).__name__}: {exc}"[:200]
    return lo, hi, x1 if f1 < f2 else x2, None


def locate_task(args: dict) -> dict:
    """The special point ``args['kind']`` (``IS``: ``tr M = 4``; ``PD``: ``tr M = 0``)
    located again at ``args['digits']`` digits from its float64 location ``args['E']``
    (``args['u']``: its shooting unknown there): a secant in ``E`` on ``tr M - level``
    (:func:`rotorlib.orbits.shooting.secant`), the member at each ``E`` solved from the
    last one's ``u``. Returns the member at the root as :func:`polish_task` does
    (``E_str`` to ``digits``), with ``E_error``: the root's precision, ``(|tr M -
    level| + 1e-25 max(1, |tr M|)) / |d tr M / dE|`` (``tr M`` at 30 digits is good to
    ~25), ``tr_residual``: ``|tr M - level|`` at the root, and ``moved``: the root minus
    the float64 location; or ``{'failed': reason}``, also when ``E_error`` exceeds
    1e-12 relative.

    Why: the float64 location, by the continuation engine, is good to ~1e-10 relative
    where ``tr M`` crosses its level steeply, and worse where it does not; measured on
    the ``T <= 16`` build, the 30-digit ``tr M`` at the float64 location of an IS point
    of the pendulum's record (E = 4.0000133) is 1.6e-5 from its level, that is 5e-10
    off in ``E``.
    """
    return solved(_locate, args)


def _locate(args: dict) -> dict:
    from ..core.flow import monodromy_matrix
    from ..core.precision import tier
    from ..orbits.shooting import residual, secant, solve

    D = int(args["digits"])
    prob = problem_of(
        {**args["problem"], "label": "catalogue", "factor": args["factor"]}
    )
    level = 4 if args["kind"] == "IS" else 0
    t = tier(D)
    with t.context():
        last = {"u": t.num(repr(args["u"]))}

        def g(E):
            u0 = last["u"]
            u1 = u0 * (1 + t.num("1e-12"))
            u = solve(prob, u0, u1, E=E, digits=t, r_max=t.eps**0.6).x
            sh = residual(prob, u, E, t)
            _, _, tr = monodromy_matrix(sh.x0, t.scale(args["factor"], sh.t1), t)
            last["u"] = u
            return tr - level

        E0 = t.num(repr(args["E"]))
        root = secant(g, E0, E0 * (1 + t.num("1e-10")), t.num("1e-24"))
        # the root's precision: |tr M - level| there plus the 25-digit noise of tr M,
        # over the slope d tr M / dE (a difference 1e-16 relative beside the root)
        r0 = g(root.x)  # (and the member at the root: the last call was elsewhere)
        u = last["u"]
        dE = root.x * t.num("1e-16")
        slope = (g(root.x + dE) - r0) / dE
        err = (abs(r0) + t.num("1e-25") * max(1, abs(r0 + level))) / abs(slope)
        if not err < t.num("1e-12") * abs(root.x):
            raise ValueError(
                f"the root in E is not resolved to 1e-12 (|tr M - {level}| = "
                f"{float(abs(r0)):.1e}, slope {float(slope):.2e}, at E = "
                f"{float(root.x):.15g})"
            )
        out = member_strings(prob, u, t.text(root.x, D), D)
        return {
            **out,
            "E_error": float(err),
            "tr_residual": float(abs(r0)),
            "moved": float(root.x - E0),
        }


def touch_task(args: dict) -> dict:
    """Where ``tr M`` comes closest to ``args['level']`` (4) between two stored members
    at ``args['E']`` ``= [E_a, E_b]`` (shooting unknowns ``args['u']``: the member at
    each energy is solved from ``u`` interpolated linearly), at ``args['digits']``
    digits: a golden-section search for the extremum of ``tr M`` (the largest when
    ``tr M`` lies below the level, the smallest above), 60 steps. Returns the member
    there as :func:`polish_task` does, with ``E_error``: the final bracket (the search
    stops where the float energy no longer moves), and ``gap``: ``tr M - level`` at
    the extremum; or ``{'failed': reason}``. Why not scipy's bounded
    ``minimize_scalar``: its tolerance has a floor of ``sqrt(float eps) |E|`` (~7e-8
    here), while ``tr M - level ~ (E - E_*)^2`` at 30 digits resolves the extremum to
    the float energy's last bit (``E_error`` 1.8e-15 on CZ2).

    A touch is what the Maslov index of the stored members shows and the float64 path
    does not: ``tr M`` reaching 4 without crossing it (a pitchfork of a symmetric
    family). Measured on CZ2 at ``T <= 16``: the index goes from 3 to 5 between
    members at ``E = 4.5737`` and ``4.5759`` with ``tr M = 3.93`` and 3.97, and this
    search finds ``tr M - 4`` below 1e-15 at ``E = 4.57494119220``.
    """
    return solved(_touch, args)


def _touch(args: dict) -> dict:

    from mpmath import mpf

    (Ea, Eb), (ua, ub), level = args["E"], args["u"], args["level"]
    got: dict = {}

    def value(E: float) -> float:  # maximised: tr M - level, the sign turned below it
        d = mpf(got[E]["trace_str"]) - level
        return float(d if args["below"] else -d)

    def g(E: float) -> float:
        u = ua + (ub - ua) * (E - Ea) / (Eb - Ea)
        got[E] = resolve_member({**args, "u": u, "E_str": repr(E)})
        return value(E)

    lo, hi, best, _ = golden_minimum(lambda E: -g(E), min(Ea, Eb), max(Ea, Eb), 60)
    out = got[best]
    gap = float(mpf(out["trace_str"]) - level)
    return {**out, "E_error": hi - lo, "gap": gap}


def fold_task(args: dict) -> dict:
    """The fold (saddle-node) of a family located at ``args['digits']`` digits: the
    extremum of ``E`` along the branch, parametrised by the shooting unknown ``u``
    between ``args['u'] = [u_a, u_b]`` (float64 path members on both sides of the
    fold; ``args['E']``: the float64 fold, where ``E(u)`` is first solved). ``E(u)``
    is solved at fixed ``u`` (a secant in ``E`` from the nearest ``u`` solved: the
    residual's derivative in ``E`` does not vanish at a fold, its derivative in ``u``
    does), first on 9 points of ``[u_a, u_b]`` from the middle outwards (a failed
    solve ends the run on its side: the branch may not reach an end); the largest (else
    the smallest) ``E`` inside the run brackets the fold with its two neighbours, and
    a golden-section search in ``u`` finds the extremum (it stops when the bracket is
    below ``1e-14 max(1, |u|)`` or the float ``u`` no longer moves).
    Returns the member at the fold as
    :func:`rotorlib.beyond.catalogue_members.polish_task` does, with ``E_error``: three
    times the largest ``|E(u_best) - E|`` at the final bracket's ends plus the 30-digit
    solve's ``1e-28 |E|`` (``E - E_f ~ -c (u - u_f)^2``: the fold lies within the
    bracket, no farther from ``u_best`` than its length), ``gap``: ``tr M - 4`` there
    (``~ (u - u_f)``: a check, not a condition), ``moved``: the fold minus
    ``args['E']``, ``kind``: ``'max'`` or ``'min'``, ``bracket``: the final bracket
    in ``u``, and ``stopped``: why the search stopped early, or None (a solve of
    ``E(u)`` that fails inside the bracket: where the fold is degenerate, ``dr/dE``
    vanishes there too and the solve at fixed ``u`` is ill-conditioned; the bracket and
    ``E_error`` are then those reached); or ``{'failed': reason}``, also when no sample
    inside the run is an extremum or when ``E_error`` exceeds 1e-12 relative (measured
    on the ``T <= 16`` build: 2 of 34 folds, at E = 4.0575 and 5.8809, where ``E(u)``
    solved at neighbouring ``u`` scatters by ~1e-8: a degenerate fold).

    Why: the engine's float64 fold is where its secant on ``dE/ds`` stops; two records
    that meet at one fold (a saddle-node's two branches, or two daughters born at one
    point, followed from two census orbits in two shooting problems) put it 2e-9 to
    6e-9 apart in ``E`` (measured on the ``T <= 16`` build; at 30 digits they agree to
    < 1e-21).
    """
    return solved(_fold, args)


def _fold(args: dict) -> dict:
    from ..core.flow import SectionNotReached
    from ..core.precision import tier
    from ..orbits.shooting import NoConvergence, solve

    D = int(args["digits"])
    prob = problem_of(
        {**args["problem"], "label": "catalogue", "factor": args["factor"]}
    )
    t = tier(D)
    with t.context():
        got: dict = {}  # u -> (w, E)

        def solve_E(u: float, w0, step: str):  # the second unknown at fixed u
            w1 = w0 * (1 + t.num(step))
            return solve(prob, w0, w1, u=repr(u), digits=t, r_max=t.eps**0.6).x

        def E_of(u: float):
            if u not in got:  # from the nearest u solved, else from the fold's E
                near = min(got, key=lambda v: abs(v - u), default=None)
                w = None
                if near is not None:
                    try:
                        w = solve_E(u, got[near][0], "1e-12")
                    except NoConvergence:
                        pass
                if w is None:
                    w = solve_E(u, prob.w_at(u, t.num(repr(args["E"])), t), "1e-9")
                got[u] = (w, prob.energy(t.num(repr(u)), w, t))
            return got[u][1]

        # E on 9 points of [u_a, u_b], solved from the middle outwards; a point where
        # the solve fails ends the run on that side
        ua, ub = float(min(args["u"])), float(max(args["u"]))
        us = [ua + (ub - ua) * k / 8 for k in range(9)]
        E_of(us[4])  # raises if the middle has no member: no fold there
        run = [4]
        for side in (range(5, 9), range(3, -1, -1)):
            for k in side:
                try:
                    E_of(us[k])
                except (NoConvergence, SectionNotReached, ValueError):
                    break
                run.append(k)
        run.sort()
        Es = [E_of(us[k]) for k in run]
        for sign in (1, -1):  # an interior maximum, else an interior minimum
            j = max(range(len(run)), key=lambda i: sign * Es[i])
            if 0 < j < len(run) - 1:
                break
        else:
            raise ValueError(
                f"E(u) has no extremum inside u in [{us[run[0]]!r}, "
                f"{us[run[-1]]!r}]: no fold there"
            )
        ua, ub, Em = us[run[j - 1]], us[run[j + 1]], Es[j]

        def g(u: float) -> float:  # minimised: -E at a maximum, E at a minimum
            return float(-sign * (E_of(u) - Em))

        # a failed solve stops the search where it is (and says so)
        errors = (NoConvergence, SectionNotReached, ValueError)
        tol = 1e-14 * max(1.0, abs(ua))
        lo, hi, best, stopped = golden_minimum(g, ua, ub, 200, tol, errors)
        if best is None:  # stopped: the best point solved inside the bracket
            best = min((v for v in got if lo <= v <= hi), key=g)
        Eb = E_of(best)
        err = 3 * max(abs(Eb - E_of(lo)), abs(Eb - E_of(hi))) + t.num("1e-28") * abs(Eb)
        if not err < t.num("1e-12") * abs(Eb):
            raise ValueError(
                f"the fold is not resolved to 1e-12 (E_error {float(err):.1e} over a "
                f"bracket of {hi - lo:.1e} in u{'; ' + stopped if stopped else ''}): "
                "E(u) is ill-conditioned there"
            )
        out = member_strings(prob, t.num(repr(best)), t.text(Eb, D), D)
        gap = float(t.num(out["trace_str"]) - 4)
        return {
            **out,
            "E_error": float(err),
            "gap": gap,
            "moved": float(Eb - t.num(repr(args["E"]))),
            "kind": "max" if sign > 0 else "min",
            "bracket": hi - lo,
            "stopped": stopped,
        }
