"""The front door: one call per task, ``digits`` the one precision knob.

==========================================  =================================================
call                                        returns
==========================================  =================================================
``orbit(label, E, *, digits=None)``         one :class:`~rotorlib.orbits.periodic_orbit.PeriodicOrbit`
``family(label, E_range, *, digits=None)``  one :class:`~rotorlib.orbits.continuation.Branch`
``transition(label, *, digits=None)``       one :class:`~rotorlib.paper.bifurcations.Transition`
``census(E, t_max, *, digits=None, ...)``   one :class:`~rotorlib.beyond.atlas.Atlas`
==========================================  =================================================

``digits=None`` is float64 (near a separatrix the tier that keeps 15 digits); an integer
asks for that many significant digits (real128 up to 31, multiprecision beyond). Every
result has ``label``, ``E``, ``period``, ``trace``, ``multipliers``, ``stability``,
``state0``, ``digits``, the decimal strings ``E_str``, ``period_str``, ``trace_str``,
``state0_str``, and ``to_dict()``, the JSON the command line prints.

Which module serves a label is decided here and nowhere else: :data:`REGISTRY` maps each
label (a kind of labels: ``IS^l_n`` stands for every ``n``) to the functions that give its
orbit, its family, its transition and, for the choreographies, the periods at an energy
by which :func:`census` names the orbits it finds (:func:`name_choreography`). The modules
below know only their own labels.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import mpmath as mp
import numpy as np

from .beyond import (
    atlas,
    choreo,
    choreo_family,
    choreo_resonance,
    choreo_rotation,
    choreo_s,
    choreo_z3,
)
from .beyond.atlas import Atlas
from .beyond.catalogue import catalogue
from .beyond.choreo import Choreography
from .core.parallel import executor_for
from .core.precision import Tier, check_digits, tier
from .orbits.family import Branch, energy_range
from .orbits.periodic_orbit import PeriodicOrbit
from .paper import bifurcations, breathers, newborn, newborn_families
from .paper.bifurcations import Transition

__all__ = [
    "orbit",
    "family",
    "transition",
    "census",
    "catalogue",
    "LABELS",
    "REGISTRY",
    "Served",
    "resolve",
    "name_choreography",
]


def _digits(digits: int | Tier | None) -> int | None:
    """``digits`` checked; a :class:`Tier`: the digits its working digits keep, less 8."""
    if_tier = digits.dps - 8 if isinstance(digits, Tier) and digits.extended else None
    return if_tier if isinstance(digits, Tier) else check_digits(digits)


def _closed_form(label: str, E: Any, digits: int | None) -> PeriodicOrbit:
    """A pendulum or breather as a PeriodicOrbit: state from the closed form, monodromy and
    trace from the symmetry-reduced (Hill) problem at ``digits``."""
    from .core.closed_forms import breather, pendulum
    from .orbits.floquet import monodromy

    orb = pendulum(E) if label == "pendulum" else breather(E, family=label)
    m = monodromy(orb, digits=digits)
    en = orb.energy
    d = digits if digits and digits > 15 else 15
    E_str, period_str = en.decimal_E(d), m.period_str
    state0_str: tuple[str, ...] = ()
    if d > 15:  # the base point in closed form: G (pendulum, LG, R) or D (LD)
        with mp.workdps(d + 10):
            Em = mp.mpf(E_str)
            x = {
                "pendulum": (0, 0, 0, mp.sqrt(4 * Em / 3)),
                "LD": (mp.pi / 2, 3 * mp.pi / 2, -mp.sqrt(Em - 4), -mp.sqrt(Em - 4)),
            }.get(label, (0, 0, mp.sqrt(Em), mp.sqrt(Em)))
            state0_str = tuple(mp.nstr(mp.mpf(v), d) if v else "0.0" for v in x)
        d = min(d, len(period_str.lstrip("-0.").replace(".", "").split("e")[0]))
    try:  # a rotating pendulum's a2 covers the circle: its excursion is pi
        xs = orb.state(np.linspace(0.0, float(m.period), 2001))
        a1m = float(np.max(np.abs(xs[:, 0])))
        a2m = (
            math.pi
            if label == "pendulum" and en.phase == "rot"
            else float(np.max(np.abs(xs[:, 1] - xs[0, 1])))
        )
    except ValueError:  # beyond the float64 range of the closed form
        a1m = a2m = math.nan
    return PeriodicOrbit(
        label,
        float(orb.E),
        float(m.period),
        np.asarray(orb.state0, dtype=float),
        m.in_alpha_state_order(),
        float(m.trace),
        float(m.residual),
        0.0,
        m.precision,
        a1m,
        a2m,
        float(en.log_abs_dE) if label == "pendulum" else math.nan,
        {"stability": m.stability, "family": m.family},
        digits=d,
        E_str=E_str,
        period_str=period_str,
        trace_str=m.trace_str,
        state0_str=state0_str,
    )


# --------------------------------------------------------------------------- the registry


def _breather_transition(label: str, digits: Any) -> Transition:
    """``PD^b`` with the digits rule of the pendulum's transitions: a :class:`Tier`
    delivers its working digits less 9, ``digits <= 15`` is float64."""
    t = tier(digits)
    d = None if not t.extended else (digits if isinstance(digits, int) else t.dps - 9)
    return breathers.pd_transition(digits=d)


@dataclass(frozen=True)
class Served:
    """One row of :data:`REGISTRY`: the functions that serve a kind of label, each
    called with the label as its module spells it (:func:`resolve`).

    Attributes
    ----------
    kind : str
        ``closed form``, ``newborn``, ``breather daughter`` or ``choreography``.
    orbit : callable
        ``(label, E, digits, branch) -> PeriodicOrbit``.
    family, transition : callable or None
        ``(label, E_range, digits) -> Branch``; ``(label, digits) -> Transition``.
    periods : callable or None
        For naming a census's choreographies: ``(label, E, choreography) ->`` the
        periods of the family's members at ``E`` (none if the family's orbits do not
        rotate as ``choreography`` does).
    branches : bool
        Whether the family may have several members at one energy (``branch``).
    """

    kind: str
    orbit: Callable[[str, Any, Any, int], PeriodicOrbit]
    family: Callable[[str, Any, Any], Branch] | None = None
    transition: Callable[[str, Any], Transition] | None = None
    periods: Callable[[str, float, Choreography], list[float]] | None = None
    branches: bool = False


def _non_rotating(
    periods: Callable[[str, float], list[float]],
) -> Callable[[str, float, Choreography], list[float]]:
    """The periods a census names a choreography by, for the non-rotating ones only."""
    return lambda lab, E, c: [] if c.rotating else periods(lab, E)


_CLOSED = Served("closed form", lambda lab, E, d, b: _closed_form(lab, E, d))
_NEWBORN = Served(
    "newborn",
    lambda lab, E, d, b: newborn.newborn_orbit(lab, E, digits=d),
    lambda lab, rng, d: newborn_families.family(lab, rng, digits=d),
    lambda lab, d: bifurcations.transition(lab, digits=d),
)
_CG = Served(
    "choreography",
    lambda lab, E, d, b: choreo_family.cg_orbit(E, digits=d, label=lab),
    lambda lab, rng, d: (
        choreo_rotation.cg_family(rng, digits=d)  # with CG's resonances
        if lab == "CG"
        else choreo_family.family(lab, rng, digits=d)
    ),
    periods=_non_rotating(choreo_family.periods_at),
)
_Z3 = Served(
    "choreography",
    lambda lab, E, d, b: choreo_z3.z3_orbit(lab, E, digits=d, branch=b),
    lambda lab, rng, d: choreo_z3.z3_family(lab, rng, digits=d),
    periods=choreo_z3.periods_at,
    branches=True,
)
# the third D6 choreography (rotorlib.beyond.choreo_s)
_CS = Served(
    "choreography",
    lambda lab, E, d, b: choreo_s.cs_orbit(E, digits=d, branch=b),
    lambda lab, rng, d: choreo_s.cs_family(rng, digits=d),
    periods=_non_rotating(lambda lab, E: choreo_s.cs_periods(E)),
    branches=True,
)
_DAUGHTER = Served(
    "breather daughter",
    lambda lab, E, d, b: breathers.breather_daughter(E, digits=d),
    transition=_breather_transition,
)

#: Label -> :class:`Served`: the one table of which module serves which label
#: (``IS^l_n`` and the other newborn rows stand for every ``n >= 1``).
REGISTRY: dict[str, Served] = {
    "pendulum": _CLOSED,
    "R": _CLOSED,
    "LG": _CLOSED,
    "LD": _CLOSED,
    "IS^l_n": _NEWBORN,
    "PD^l_n": _NEWBORN,
    "IS^r_n": _NEWBORN,
    "PD^r_n": _NEWBORN,
    "PD^b": _DAUGHTER,
    "CG": _CG,
    "CT": _CG,
    "CZ1": _Z3,
    "CZ2": _Z3,
    "CR1": _Z3,
    "CS": _CS,
    # the choreographies born from CG at its resonances p/q (CG1/4a, CG1/4b: CZ2, CZ1)
    **{
        name: Served(
            "choreography",
            lambda lab, E, d, b: choreo_resonance.resonance_orbit(lab, E, d, b),
            lambda lab, rng, d: choreo_resonance.resonance_family(lab, rng, d),
            periods=_non_rotating(choreo_resonance.periods_at),
            branches=True,
        )
        for name in choreo_resonance.family_names()
    },
}

#: The orbit labels :func:`orbit` accepts, by kind (IS/PD labels take any ``n >= 1``).
LABELS = {
    k: tuple(lab for lab, s in REGISTRY.items() if s.kind == k)
    for k in ("closed form", "newborn", "breather daughter", "choreography")
}


def resolve(label: str, what: str = "label") -> tuple[str, str]:
    """``(row, label)``: the row of :data:`REGISTRY` that serves ``label`` and the label
    as that row's module spells it (a newborn label as given: the module reads it with
    :func:`~rotorlib.paper.bifurcations.parse_label`).

    Examples
    --------
    >>> resolve("ISl2"), resolve("cg"), resolve("PDb"), resolve("p")
    (('IS^l_n', 'ISl2'), ('CG', 'CG'), ('PD^b', 'PD^b'), ('pendulum', 'pendulum'))
    >>> resolve("bogus")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: unknown label 'bogus': use one of closed form: pendulum, R, LG, LD; ...
    """
    lab = str(label).strip()
    if lab.lower() in ("pendulum", "p"):
        return "pendulum", "pendulum"
    key = {k.upper(): k for k in REGISTRY}.get(lab.upper())  # CG1/5a keeps its "a"
    if key:
        return key, key
    if breathers.is_breather_label(lab):
        return "PD^b", "PD^b"
    try:
        kind, phase, _ = bifurcations.parse_label(lab)
    except ValueError:
        raise ValueError(
            f"unknown {what} {label!r}: use one of "
            + "; ".join(f"{k}: {', '.join(v)}" for k, v in LABELS.items())
        ) from None
    return f"{kind}^{phase[0]}_n", lab


def name_choreography(E: float, chor: Choreography, period: float) -> str:
    """The label of the choreography family with a member of this ``period`` (to 1e-7)
    at ``E`` among the families whose orbits rotate as ``chor`` does (the rows of
    :data:`REGISTRY` with ``periods``, in order: ``CG``, ``CT`` first), else
    ``choreography``: how :func:`census` names a census's choreographies (each Z3 family
    is followed once per process, ~20 s).

    Examples
    --------
    >>> from rotorlib.beyond.choreo import choreography_of
    >>> o = orbit("CG", 5.3)
    >>> name_choreography(5.3, choreography_of(o.state0, o.period), o.period)
    'CG'
    """
    rows = [(lab, s.periods) for lab, s in REGISTRY.items() if s.periods is not None]
    return choreo.label_by_period(E, chor, period, rows)


def _serving(label: str, what: str) -> tuple[Callable[..., Any], str, str]:
    """``(function, row, label)``: the ``what`` (``family`` or ``transition``) of the
    row of :data:`REGISTRY` that serves ``label``; ValueError naming the labels that
    have one otherwise."""
    row, lab = resolve(label, f"{what} label")
    serve = getattr(REGISTRY[row], what)
    if serve is None:
        raise ValueError(
            f"{label!r} has no {what}: the labels with one are "
            f"{', '.join(k for k, s in REGISTRY.items() if getattr(s, what))} (IS/PD: "
            "any n >= 1; ASCII 'ISl3', 'PDr2', 'PDb' too)"
        )
    return serve, row, lab


def orbit(
    label: str, E: float | str, *, digits: int | Tier | None = None, branch: int = 0
) -> PeriodicOrbit:
    """The periodic orbit ``label`` at energy ``E``.

    Parameters
    ----------
    label : str
        ``pendulum`` (libration for ``E < 4``, rotation above), the isosceles breathers
        ``R``, ``LG``, ``LD``; a family born at a pendulum bifurcation, ``IS^l_n``,
        ``PD^l_n``, ``IS^r_n``, ``PD^r_n`` (also ``ISl2``, ``PDr3``); the breather's
        period-doubled daughter ``PD^b``; a choreography ``CG``, ``CT``, ``CZ1``, ``CZ2``,
        ``CR1``, or one born from CG at its resonance ``p/q``, ``CG2/7a`` ... ``CG1/8b``
        (:mod:`rotorlib.beyond.choreo_resonance`; :data:`LABELS`).
    E : float or str
        Energy (m = g = r = 1). A decimal string keeps every digit (e.g. ``"4.0000001"``).
    digits : int or Tier, optional
        Significant digits of the state, period and trace. ``None``: float64 (the tier that
        keeps 15 digits near E = 4); 16-31: real128; more: multiprecision.
    branch : int
        Which member, where a family has several at ``E`` (see Notes).

    Returns
    -------
    PeriodicOrbit

    Raises
    ------
    ValueError
        An unknown label, an energy outside the family's range (with the range and why),
        or ``digits`` outside 1-1000.

    Notes
    -----
    A family that folds has more than one member at some energies (``CR1`` has two at
    ``E = 5.6``): ``branch`` numbers them by period (0 the shortest); every other family
    has one member, ``branch=0``.

    Examples
    --------
    >>> import rotorlib
    >>> o = rotorlib.orbit("pendulum", 3.9)
    >>> round(o.trace, 10), o.stability
    (0.0195119424, 'stable')
    >>> o40 = rotorlib.orbit("pendulum", "3.9", digits=40)
    >>> o40.trace_str[:32]
    '0.019511942411167610530751636443'
    >>> rotorlib.orbit("ISl2", 4.0).stability
    'unstable'
    """
    row, lab = resolve(label, "orbit label")
    served = REGISTRY[row]
    if branch and not served.branches:
        raise ValueError(
            f"branch={branch!r}: only "
            f"{', '.join(k for k, s in REGISTRY.items() if s.branches)} have more than "
            f"one member at an energy ({lab} has one)"
        )
    return served.orbit(lab, E, _digits(digits), branch)


def family(
    label: str, E_range: tuple[float, float], *, digits: int | Tier | None = None
) -> Branch:
    """The family ``label`` followed over ``E_range = (lo, hi)``.

    Members lie inside ``E_range``, never outside it; the special points (folds, the
    energies where ``tr M`` crosses 4 (``IS``) or 0 (``PD``)) are located by the
    continuation engine, and ``reason`` says why the branch stopped.

    Examples
    --------
    >>> import rotorlib
    >>> b = rotorlib.family("IS^l_1", (3.9, 4.1))
    >>> bool(all(3.9 <= E <= 4.1 for E in b.E)), [p.kind for p in b.special_points]
    (True, ['IS'])
    """
    lo, hi = energy_range(E_range)
    serve, row, lab = _serving(label, "family")
    # a newborn family reads a Tier itself (the tier of its continuation)
    return serve(lab, (lo, hi), digits if row in LABELS["newborn"] else _digits(digits))


def transition(label: str, *, digits: int | Tier | None = None) -> Transition:
    """The stability transition ``label`` of the pendulum (``IS^l_n``, ``PD^r_n``, ...) or
    of the breather (``PD^b``): exact decimal energy, period and kind.

    Examples
    --------
    >>> import rotorlib
    >>> tr = rotorlib.transition("IS^l_2", digits=20)
    >>> tr.kind, tr.label
    ('IS', 'IS^l_2')
    """
    serve, _, lab = _serving(label, "transition")
    return serve(lab, digits)


def census(
    E: float,
    t_max: float,
    *,
    digits: int | Tier | None = None,
    workers: int | None = None,
    scheduler: str | None = None,
) -> Atlas:
    """Every symmetric periodic orbit with period ``<= t_max`` at energy ``E``.

    ``workers`` processes (or a Dask ``scheduler`` address) share the work; the result
    does not depend on them.

    Examples
    --------
    >>> import rotorlib
    >>> a = rotorlib.census(4.3, 6.0)
    >>> [o.label for o in a.orbits][:2]
    ['pendulum', 'CG']
    """
    with executor_for(workers, scheduler) as ex:  # None: serial
        return atlas.census(
            E,
            t_max,
            digits=_digits(digits),
            executor=ex,
            name_choreography=name_choreography,
        )
