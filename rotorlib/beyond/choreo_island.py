"""The island of the stable choreography CG on the Poincaré section of chapter 8.

CG crosses the section ``phi1 = 0 (mod 2 pi)``, ``phi1' > 0`` of
:func:`rotorlib.paper.chaos.poincare_section` once per period, at ``P2 = 0``: a fixed point
of the return map, elliptic while CG is stable (from G to its fold at ``E_f ~ 5.3153``);
its mirror image (CG run backwards) is a second fixed point at ``2 pi - phi2``. The
return map preserves the area ``d phi2 d P2``, so the two islands have the same area.

:func:`island_area` measures the island of one fixed point: a grid of ``n x n`` points of
the section in a box about it, the finite-time Lyapunov exponent of each
(:func:`rotorlib.paper.chaos.ftle`, ``T = 300``, threshold ``0.05``: chapter 8's
criterion for a chaotic orbit), and the connected set of regular points (4-neighbours)
containing the fixed point. The box is first shrunk by thirds until that set has at
least 20 points, then fitted to it (two cells of margin) and sampled again: the area is
the number of regular cells times the cell's area, with an uncertainty of half the area
of its boundary cells (those next to a chaotic or unsampled one), and the fraction is
twice the area (both islands) over the section's area ``int 2 sqrt(4 (E - V(0,
phi2))/3) d phi2``.

Scope: the island's measure in the flux (section) measure, not the microcanonical volume
of chapter 8's chaotic fraction; regular points that an FTLE over ``T = 300`` cannot tell
from a thin chaotic layer are counted as regular. Float64 (heyoka, tolerance 1e-12).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import quad

from ..core.flow import Section, to_section
from ..core.system import alpha_to_phi, phi_to_alpha, potential_phi
from ..paper.chaos import ftle

__all__ = ["IslandArea", "island_area", "section_area"]

T_FTLE, THRESHOLD = 300.0, 0.05


@dataclass(frozen=True)
class IslandArea:
    """CG's island at ``E``: the fixed point ``(phi2, P2)``, the ``area`` of one island
    and its uncertainty ``area_err``, ``fraction`` (both islands over the section's area)
    and ``fraction_err``, the box's half-widths and ``n``, and ``cells`` (regular cells).
    """

    E: float
    phi2: float
    P2: float
    area: float
    area_err: float
    fraction: float
    fraction_err: float
    half_width: tuple
    n: int
    cells: int

    def to_dict(self) -> dict:
        """JSON-serialisable record."""
        d = dict(vars(self))
        d["half_width"] = list(self.half_width)
        return d


def section_area(E: float) -> float:
    """The area of the section ``phi1 = 0`` at ``E`` in ``(phi2, P2)``.

    Examples
    --------
    >>> from rotorlib.beyond.choreo_island import section_area
    >>> round(section_area(5.2), 4)
    25.2524
    """

    def width(f2: float) -> float:
        K = E - float(potential_phi(0.0, f2))
        return 2 * math.sqrt(4 * K / 3) if K > 0 else 0.0

    return float(quad(width, 0, 2 * math.pi, limit=200)[0])


def _grid(E, c2, cP, w2, wP, n):
    g2 = np.linspace(c2 - w2, c2 + w2, n)
    gP = np.linspace(cP - wP, cP + wP, n)
    ok, X = np.zeros((n, n), bool), []
    for i, a in enumerate(g2):
        K = E - float(potential_phi(0.0, a))
        for j, b in enumerate(gP):
            s = 4 * K - 3 * b * b
            if s > 0:
                ok[i, j] = True
                X.append([0.0, a, 0.5 * (math.sqrt(s) + b), b])
    lam = np.full((n, n), np.inf)
    lam[ok] = ftle(phi_to_alpha(np.array(X)), T=T_FTLE)
    return lam < THRESHOLD


def _component(reg):
    n = reg.shape[0]
    c = n // 2
    comp = np.zeros_like(reg)
    if not reg[c, c]:
        return comp
    stack = [(c, c)]
    comp[c, c] = True
    while stack:
        i, j = stack.pop()
        for a, b in ((i + 1, j), (i - 1, j), (i, j + 1), (i, j - 1)):
            if 0 <= a < n and 0 <= b < n and reg[a, b] and not comp[a, b]:
                comp[a, b] = True
                stack.append((a, b))
    return comp


def island_area(E: float, n: int = 49) -> IslandArea:
    """CG's island at ``E`` (module docstring); ``n`` odd, the grid of the final pass.
    Raises ValueError where CG is not stable or does not exist (above its fold).

    Cost: ``~ n^2 + 625`` FTLEs over ``T = 300`` (about 30 s for ``n = 49``).
    """
    from .choreo_family import cg_orbit

    o = cg_orbit(E)
    if not o.extra["stable"]:
        raise ValueError(f"CG is unstable at E = {E}: no island")
    # CG's crossing of phi1 = 0 (a1 = 0 mod pi), phi1' > 0: P2 = 0 there (its symmetry)
    _, x1 = to_section(
        list(o.state0), Section((1, 0, 0, 0), 0.0, 1, 1.0), None, 1, 50.0
    )
    y = alpha_to_phi([float(v) for v in x1])
    c2, cP = float(y[1]) % (2 * math.pi), 0.0
    if abs(float(y[3])) > 1e-9:
        raise RuntimeError(f"CG's crossing has P2 = {float(y[3])}, not 0")
    w = 0.8
    for _ in range(8):  # shrink the box until the island has >= 20 points
        comp = _component(_grid(E, c2, cP, w, w, 25))
        if comp.sum() >= 20:
            break
        w /= 3
    idx = np.argwhere(comp)
    h = 2 * w / 24
    lo, hi = idx.min(axis=0) - 2, idx.max(axis=0) + 2
    cen = (lo + hi) / 2 - 12
    w2, wP = (hi[0] - lo[0]) * h / 2, (hi[1] - lo[1]) * h / 2
    c2f, cPf = c2 + cen[0] * h, cP + cen[1] * h
    n = int(n) | 1
    reg = _grid(E, c2f, cPf, w2, wP, n)
    # the component through the grid point nearest the fixed point
    k2 = int(round((c2 - (c2f - w2)) / (2 * w2) * (n - 1)))
    kP = int(round((cP - (cPf - wP)) / (2 * wP) * (n - 1)))
    reg2 = np.roll(np.roll(reg, n // 2 - k2, 0), n // 2 - kP, 1)
    comp = np.roll(np.roll(_component(reg2), k2 - n // 2, 0), kP - n // 2, 1)
    cell = (2 * w2 / (n - 1)) * (2 * wP / (n - 1))
    pad = np.pad(comp, 1)
    inner = pad[:-2, 1:-1] & pad[2:, 1:-1] & pad[1:-1, :-2] & pad[1:-1, 2:]
    boundary = int((comp & ~inner).sum())
    area, err = float(comp.sum() * cell), float(0.5 * boundary * cell)
    S = section_area(E)
    return IslandArea(
        float(E), c2, cP, area, err, 2 * area / S, 2 * err / S, (w2, wP), n,
        int(comp.sum()),
    )  # fmt: skip
