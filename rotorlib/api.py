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
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import mpmath as mp
import numpy as np

from .beyond.catalogue import catalogue
from .core.precision import Tier, check_digits
from .orbits.family import Branch, energy_range
from .orbits.periodic_orbit import PeriodicOrbit
from .paper.bifurcations import Transition, is_breather_label, parse_label

if TYPE_CHECKING:  # imported when called: import rotorlib stays light
    from .beyond.atlas import Atlas

__all__ = ["orbit", "family", "transition", "census", "catalogue", "LABELS"]

#: The orbit labels :func:`orbit` accepts, by kind (IS/PD labels take any ``n >= 1``).
LABELS = {
    "closed form": ("pendulum", "R", "LG", "LD"),
    "newborn": ("IS^l_n", "PD^l_n", "IS^r_n", "PD^r_n"),
    "breather daughter": ("PD^b",),
    "choreography": ("CG", "CT", "CZ1", "CZ2", "CR1"),
}


def _kind(label: str) -> tuple[str, str]:
    """``(kind, label)``: the kind in :data:`LABELS` that ``label`` names (``unknown``:
    none) and its spelling for that kind's module (a newborn label as given: the module
    reads it with :func:`~rotorlib.paper.bifurcations.parse_label`, as :func:`transition` does)."""
    lab = str(label).strip()
    if lab.lower() in ("pendulum", "p"):
        return "closed form", "pendulum"
    for kind in ("closed form", "choreography"):
        if lab.upper() in LABELS[kind]:
            return kind, lab.upper()
    if is_breather_label(lab):
        return "breather daughter", "PD^b"
    try:
        parse_label(lab)
    except ValueError:
        return "unknown", lab
    return "newborn", lab


def _digits(digits: int | Tier | None) -> int | None:
    if isinstance(digits, Tier):
        return None if not digits.extended else digits.dps - 8
    return check_digits(digits)


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
        a2m = float(np.max(np.abs(xs[:, 1] - xs[0, 1])))
        a2m = math.pi if label == "pendulum" and en.phase == "rot" else a2m
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
        ``CR1`` (:data:`LABELS`).
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
    d = _digits(digits)
    kind, lab = _kind(label)
    if kind == "choreography":
        from .beyond.choreo_family import choreography_orbit

        return choreography_orbit(lab, E, digits=d, branch=branch)
    if branch:
        raise ValueError(
            f"branch={branch!r}: only the choreographies CZ1, CZ2, CR1 have more than "
            "one member at an energy"
        )
    if kind == "closed form":
        return _closed_form(lab, E, d)
    if kind == "breather daughter":
        from .paper.breathers import breather_daughter

        return breather_daughter(E, digits=d)
    if kind == "newborn":
        from .paper.newborn import newborn_orbit

        return newborn_orbit(lab, E, digits=d)
    raise ValueError(
        f"unknown orbit label {label!r}: use one of "
        + "; ".join(f"{k}: {', '.join(v)}" for k, v in LABELS.items())
    )


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
    kind, lab = _kind(label)
    d = _digits(digits)
    if kind == "choreography":
        from .beyond import choreo_family

        if lab in ("CG", "CT"):
            return choreo_family.family(lab, (lo, hi), digits=d)
        from .beyond.choreo_z3 import z3_family

        return z3_family(lab, (lo, hi), digits=d)
    if kind == "newborn":
        from .paper.newborn import family as _family

        return _family(lab, (lo, hi), digits=digits)
    raise ValueError(
        f"unknown family label {label!r}: families are the newborn IS^l_n, PD^l_n, "
        "IS^r_n, PD^r_n and the choreographies CG, CT, CZ1, CZ2, CR1"
    )


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
    from .paper.bifurcations import transition as _transition

    return _transition(label, digits=digits)


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
    from .beyond.atlas import census as _census
    from .core.parallel import executor_for

    with executor_for(workers, scheduler) as ex:  # None: serial
        return _census(E, t_max, digits=_digits(digits), executor=ex)
