"""The stored quantum spectra: data products of ``scripts/quantum_spectra.py``.

``book/data/quantum/spectrum_hbar{h}.npz`` holds, for one ``hbar`` and every sector of
S3 x Z2, every level below ``E_max = 8`` (an E1/E2 level once), its change when the
plane-wave cut-off is lowered (``errors``), its residual bound (``residuals``) and the
sector's cut-off and basis size; ``book/data/quantum/cost.json`` the measured time and
peak memory of each run. Keys of the npz: ``hbar``, ``E_max`` and, per sector ``S``,
``S_levels``, ``S_errors``, ``S_residuals`` and ``S_info`` = ``[cutoff, cutoff_step,
basis_size, plane_waves, convergence, top_check]``.

:func:`stored_spectrum` returns them as the :class:`rotorlib.beyond.quantum.Spectrum` /
:class:`rotorlib.beyond.quantum.SectorSpectrum` that :func:`rotorlib.beyond.quantum.spectrum` computes, and
:func:`recheck` recomputes one window of a stored sector (what the tests do for each
product, instead of recomputing everything). Precision: the stored float64 values, as
computed (levels to ~1e-12, see ``errors`` and ``residuals``).
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path

import numpy as np

from . import quantum as q
from . import quantum_solver as qs

__all__ = ["data_dir", "stored_hbars", "stored_spectrum", "stored_cost", "recheck"]


def data_dir() -> Path:
    """``$ROTORLIB_QUANTUM_DATA`` if set, else ``book/data/quantum`` of the repository."""
    env = os.environ.get("ROTORLIB_QUANTUM_DATA")
    return (
        Path(env) if env else Path(__file__).resolve().parents[2] / "book/data/quantum"
    )


def _path(hbar: float) -> Path:
    return data_dir() / f"spectrum_hbar{float(hbar):g}.npz"


def stored_hbars() -> tuple[float, ...]:
    """The ``hbar`` of every stored spectrum, largest first.

    Examples
    --------
    >>> 0.03 in stored_hbars()
    True
    """
    out = []
    for p in data_dir().glob("spectrum_hbar*.npz"):
        out.append(float(p.stem.removeprefix("spectrum_hbar")))
    return tuple(sorted(out, reverse=True))


def _sector(data, hbar: float, sector: str) -> q.SectorSpectrum:
    info = data[f"{sector}_info"]
    return q.SectorSpectrum(
        hbar=hbar,
        sector=sector,
        row=0,
        E_max=float(data["E_max"]),
        levels=data[f"{sector}_levels"],
        cutoff=float(info[0]),
        basis_size=int(info[2]),
        plane_waves=int(info[3]),
        convergence=float(info[4]),
        method="stored (scripts/quantum_spectra.py)",
        errors=data[f"{sector}_errors"],
        residuals=data[f"{sector}_residuals"],
        top_check=float(info[5]),
    )


def stored_spectrum(
    hbar: float, sector: str | None = None
) -> q.Spectrum | q.SectorSpectrum:
    """The stored spectrum at ``hbar``: all six sectors (a :class:`rotorlib.beyond.quantum.Spectrum`),
    or one (a :class:`rotorlib.beyond.quantum.SectorSpectrum`).

    Raises ``ValueError`` for an ``hbar`` not stored (the message lists those that are)
    or an unknown sector.

    Examples
    --------
    >>> s = stored_spectrum(0.03, "A1")
    >>> s.sector, len(s.levels) == len(s.errors), bool(s.convergence < 1e-9)
    ('A1', True, True)
    """
    try:
        h = float(hbar)
    except (TypeError, ValueError):
        raise ValueError(f"hbar must be a number, not {hbar!r}") from None
    if sector is not None and sector not in q.SECTORS:
        raise ValueError(
            f"unknown sector {sector!r}: choose one of {', '.join(q.SECTORS)}"
        )
    have = stored_hbars()
    match = [x for x in have if math.isclose(x, h, rel_tol=1e-9)]
    if not match:
        raise ValueError(
            f"no stored spectrum at hbar = {hbar}; stored: "
            f"{', '.join(f'{x:g}' for x in have) or 'none'} (scripts/quantum_spectra.py)"
        )
    with np.load(_path(match[0])) as data:
        if sector is not None:
            return _sector(data, match[0], sector)
        secs = tuple(_sector(data, match[0], s) for s in q.SECTORS)
        return q.Spectrum(hbar=match[0], E_max=float(data["E_max"]), sectors=secs)


def stored_cost() -> dict:
    """The measured cost of each stored run (``cost.json``: per hbar and sector, wall
    and CPU seconds, peak MiB, levels and block size)."""
    p = data_dir() / "cost.json"
    return json.loads(p.read_text()) if p.exists() else {}


def recheck(hbar: float, sector: str, E0: float, n: int = 50) -> tuple[int, float]:
    """Recompute about ``n`` stored levels of one sector around ``E0`` (a fresh block
    at the stored cut-off, one window between two stored levels, counted by inertia).

    Returns ``(count, largest difference)``; raises ``ValueError`` if the recomputed
    count differs from the stored one (a level lost or doubled).

    Examples
    --------
    >>> k, d = recheck(0.03, "B2", 5.45, n=10)
    >>> k, bool(d < 1e-9)
    (10, True)
    """
    s = stored_spectrum(hbar, sector)
    if not isinstance(s, q.SectorSpectrum):  # for mypy: one sector was asked for
        raise TypeError
    lev = s.levels
    if len(lev) < n + 2:
        raise ValueError(f"only {len(lev)} stored levels in {sector}")
    i = int(np.clip(np.searchsorted(lev, E0) - n // 2, 1, len(lev) - n - 1))
    lo, hi = 0.5 * (lev[i - 1] + lev[i]), 0.5 * (lev[i + n - 1] + lev[i + n])
    Hs = q.sector_block(s.hbar, sector, s.cutoff, 0)[0]
    w, (n_lo, n_hi) = qs.sliced_levels(Hs, np.array([lo, hi]))
    if n_lo != i or n_hi != i + n:
        raise ValueError(
            f"inertia counts {n_lo}, {n_hi} at the window's edges; stored: {i}, {i + n}"
        )
    return len(w.levels), float(np.max(np.abs(w.levels - lev[i : i + n])))
