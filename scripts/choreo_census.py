"""Every symmetric choreography with T <= 16 at a set of energies, and its family (a data product).

Writes book/data/choreographies_T16.json. For each energy of ENERGIES the census of
symmetric periodic orbits with period <= T_MAX (``rotorlib.beyond.atlas.census``) is taken and
each orbit tested with ``rotorlib.beyond.choreo.choreography_of`` (``x(T/3) = C x(0)`` modulo
the lattice). Each choreography not already on a family found before is followed with the
engine through 3 <= E <= 8 (pseudo-arclength as ``rotorlib.beyond.atlas_families``,
through folds, ``tr M`` of every member, folds and crossings of 4 and 0 located; a family
stops where its period exceeds 40) and the reduced trace ``tr DP`` of every member
is computed (``rotorlib.beyond.choreo.reduced_trace``: order 6 for the D6 rotating waves, 3 for
the others); the families are labelled CZk (non-rotating, Z3 only), CRk (rotating), CXk
(other D6 rotating waves). CG and CT are recognised (``rotorlib.api.name_choreography``) and not
followed here: ``rotorlib.beyond.choreo_family`` follows them. Chapter 10 (choreographies) reads
the file and checks it: CG and CT against its own family, and the census orbit of every
other family re-integrated (it closes and is a choreography).

Each family labelled CZ1, CZ2 or CR1 also gets its special points located to 30 digits
(``rotorlib.beyond.choreo_z3.z3_points(label, 30)``: real128, with its agreement with float64).
Then the touches of CG (``tr M`` = 4 at theta = pi/3, 0 at theta = pi/6, no change of
stability): a census just below and just above each (T up to 1 or 2 periods of CG), the
near-resonant orbits found (``|tr M - 4| < 1e-3``, period within 30 % of T or 2T)
and each one's family followed with the engine up in energy to where it ends
(``touches``).

Scope: T <= 16 at E = 4.6 and 5.6 (chapter 9's census at 5.45 is read from its own data
product by the chapter); at most 150 continuation steps of 0.05 each way. The censuses are
cached in /tmp (choreo_census_<E>_<T_MAX>.pickle) so that a rerun of the families is cheap.
About ten minutes of two cores. Re-run after changing rotorlib.beyond.atlas, the engine or
rotorlib.beyond.choreo: python scripts/choreo_census.py
"""

from __future__ import annotations

import json
import pickle
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import replace
from fractions import Fraction
from pathlib import Path

import numpy as np

from rotorlib.api import name_choreography
from rotorlib.beyond import atlas
from rotorlib.beyond.choreo import choreography_of, reduced_trace
from rotorlib.beyond.choreo_family import special_points
from rotorlib.beyond.choreo_z3 import Z3_FAMILIES, z3_points
from rotorlib.core.flow import flow
from rotorlib.orbits.continuation import PALC, ContinuationOptions, continuation, member
from rotorlib.orbits.shooting import residual

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "book" / "data" / "choreographies_T16.json"
ENERGIES = (4.6, 5.6)
T_MAX = 16.0
WINDOW = (3.0, 8.0)
STEP = 0.05
T_CAP = 40.0  # a family whose period grows beyond this is stopped ("period")
TOUCHES = (("pi/3", 1, 0.005), ("pi/6", 2, 0.001))  # CG's point, periods of CG, dE


def _census(E, t_max, pool):
    cache = Path(f"/tmp/choreo_census_{E}_{t_max}.pickle")
    if cache.is_file():
        return pickle.loads(cache.read_bytes())
    a = atlas.census(E, t_max, executor=pool, name=False)
    cache.write_bytes(pickle.dumps(a))
    return a


def _half_shift(x0, T):
    """``max |x(T/2) + x(0)|`` modulo the lattice: 0 for ``x(t + T/2) = -x(t)``."""
    d = np.array([float(v) for v in flow(list(x0), T / 2)]) + np.array(x0)
    n = np.array([[2.0, 0.0], [-1.0, 1.0]]) @ d[:2] / (2 * np.pi)
    return float(
        max(np.max(np.abs(n - np.round(n))) * 2 * np.pi, np.max(np.abs(d[2:])))
    )


def _touch_family(o, E_end):
    """The family of the near-resonant orbit ``o`` followed up in energy (PALC, small
    steps) until it turns: ``(E of its located fold, period there)`` or ``(None, None)``."""
    sh = residual(o.extra["problem"], o.extra["u"], o.E)
    factor = float(Fraction(o.period / float(sh.t1)).limit_denominator(48))
    prob = replace(o.extra["problem"], factor=factor)
    opts = ContinuationOptions(
        max_steps=200, E_range=(o.E - 0.05, E_end), jump=0.05, folds=True
    )
    alg = PALC(ds=2e-4, ds_max=2e-3, ds_min=1e-12, u_floor=1.0)
    for d in (1, -1):
        b = continuation(
            prob, replace(alg, direction=d), opts, [member(prob, o.extra["u"], o.E)]
        )
        folds = [p for p in b.special_points if p.kind == "fold" and p.located]
        if folds and float(folds[0].member.E) > o.E:
            m = folds[0].member
            return float(m.E), float(factor * m.t1)
    return None, None


def touches(pool):
    """Near-resonant orbits just below and above CG's touches (see the docstring)."""
    out = []
    cg = {p.description: p.member for p in special_points("CG")}
    for key, mult, dE in TOUCHES:
        (q,) = [m for k, m in cg.items() if key in k]
        for side in (-1, 1):
            E = round(q.E + side * dE, 6)
            T_cg = float(q.period)  # CG's period at the touch
            a = _census(E, round(mult * T_cg * 1.05, 2), pool)
            found = []
            for o in a.orbits:
                if abs(o.period - mult * T_cg) < 0.3 * mult and abs(o.trace - 4) < 1e-3:
                    if choreography_of(o.state0, o.period) is not None:
                        continue  # CG itself (tr M near 4 at theta = pi/3)
                    E_f, T_f = _touch_family(o, q.E + 0.002)
                    found.append(
                        {
                            "period": o.period,
                            "trace": o.trace,
                            "fixed_sets": list(o.extra["fixed_sets"]),
                            "state0": list(o.state0),
                            "half_shift": _half_shift(o.state0, o.period),
                            "ends_at_E": E_f,
                            "period_at_end": T_f,
                        }
                    )
            out.append(
                {
                    "touch": key,
                    "E_touch": q.E,
                    "period_touch": T_cg,
                    "periods_of_CG": mult,
                    "E": E,
                    "t_max": round(mult * T_cg * 1.05, 2),
                    "n_orbits": len(a.orbits),
                    "orbits": found,
                }
            )
            print(f"touch {key} at E = {E}: {len(found)} near-resonant", flush=True)
    return out


def _z3_points(label):
    """The family's special points to 30 digits in this file's format: ``kind`` the
    point's description, ``E``, ``period``, the traces and ``u`` of the float64 location
    (the birth at CG: of CG's point located again in real128, with CG's float64 ``u``),
    ``E_str`` of the real128 one, their ``agreement`` and the ``check``."""
    out = []
    for p, q in zip(z3_points(label), z3_points(label, 30)):  # float64, real128
        v = q.member if p.description.startswith("born") else p.member
        out.append(
            {
                "kind": p.description,
                "branch": p.branch,
                "E": float(v.E),
                "E_str": q.E_str,
                "period": float(v.period),
                "trace_reduced": float(v.trace_reduced),
                "trace": float(v.trace),
                "agreement": abs(q.E - p.E),
                "check": q.located,
                "u": float(p.member.u),
            }
        )
    return out


def _on(fam, E, T, rel=2e-3):
    """Whether ``(E, T)`` lies on the family's curve (linear interpolation)."""
    for i in range(len(fam["E"]) - 1):
        a, b = fam["E"][i], fam["E"][i + 1]
        if min(a, b) <= E <= max(a, b) and a != b:
            Ti = fam["period"][i] + (E - a) / (b - a) * (
                fam["period"][i + 1] - fam["period"][i]
            )
            if abs(Ti - T) < rel * T:
                return True
    return False


def follow(o, lo, hi, step, T_cap):
    """The family of the atlas orbit ``o`` through ``lo <= E <= hi`` in both directions
    (as ``rotorlib.beyond.atlas_families.families``, but up to the period ``T_cap``)."""
    sh = residual(o.extra["problem"], o.extra["u"], o.E)
    factor = float(Fraction(o.period / float(sh.t1)).limit_denominator(48))
    prob = replace(o.extra["problem"], factor=factor)
    m0 = member(prob, o.extra["u"], o.E, traces=True)
    opts = ContinuationOptions(
        max_steps=150,
        E_range=(lo, hi),
        t_max=T_cap,
        jump=0.05,
        traces=True,
        folds=True,
    )
    ds = step / max(hi, 1.0)
    alg = PALC(ds=ds, ds_max=ds, ds_min=1e-10, u_floor=1.0)
    back, fwd = (
        continuation(prob, replace(alg, direction=d), opts, [m0]) for d in (-1, 1)
    )
    ms = list(back.members[::-1]) + list(fwd.members[1:])
    pts = [
        (p.kind, float(p.member.E))
        for p in list(back.special_points) + list(fwd.special_points)
        if p.located and p.kind != "E"
    ]
    return prob, ms, sorted(pts, key=lambda v: v[1]), (back.stop, fwd.stop)


def _label(families, found):
    """Name the families other than CG and CT: ``CZk`` (non-rotating, Z3 symmetry only),
    ``CRk`` (rotating), ``CXk`` (D6 rotating waves other than CG), ``k`` in the order of
    their period at the energy where the census found them; the census orbits on a
    family take its label."""
    groups = {}
    for f in families:
        key = "CR" if f["rotating"] else "CX" if f["sixth"] else "CZ"
        groups.setdefault(key, []).append(f)
    for key, fs in groups.items():
        fs.sort(key=lambda f: (f["found_at"], f["found_period"]))
        for k, f in enumerate(fs, 1):
            f["label"] = f"{key}{k}"
    for c in found:
        if c["label"] == "choreography":
            for f in families:
                if (
                    _on(f, c["E"], c["period"])
                    and f["sixth"] == c["choreography"]["sixth"]
                ):
                    c["label"] = f["label"]


def _family(args):
    """Follow one census orbit (a process-pool task): the family's record."""
    o, c, E = args
    prob, ms, pts, stops = follow(o, *WINDOW, STEP, T_CAP)
    order = 6 if c.sixth else 3
    trp = []
    for m in ms:
        T = float(prob.factor * m.t1)
        tr = reduced_trace(prob.state(m.u, m.w), T, order=order, power=c.power)[0]
        trp.append(float(tr))
    Es = [float(m.E) for m in ms]
    Ts = [float(prob.factor * m.t1) for m in ms]
    return {
        "found_at": E,
        "found_period": o.period,
        "label": "choreography",
        "sixth": c.sixth,
        "rotating": c.rotating,
        "power": c.power,
        "fixed_sets": list(o.extra["fixed_sets"]),
        "u0": float(o.extra["u"]),
        "E": Es,
        "period": Ts,
        "trace": [float(m.trace) for m in ms],
        "trace_reduced": trp,
        "points": [[k, v] for k, v in pts],
        "stops": list(stops),
    }


def _write(found, families, t0, touch=()):
    data = {
        "energies": list(ENERGIES),
        "t_max": T_MAX,
        "window": list(WINDOW),
        "step": STEP,
        "choreographies": found,
        "families": families,
        "touches": list(touch),
        "seconds": round(time.perf_counter() - t0),
    }
    OUT.write_text(json.dumps(data, indent=1) + "\n")


def main():
    t0 = time.perf_counter()
    found, tasks = [], []
    with ProcessPoolExecutor(2) as pool:
        for E in ENERGIES:  # 1. the censuses
            a = _census(E, T_MAX, pool)
            for o in a.orbits:
                c = choreography_of(o.state0, o.period)
                if c is None:
                    continue
                label = name_choreography(E, c, o.period)
                found.append(
                    {
                        "E": E,
                        "label": label,
                        "period": o.period,
                        "trace": o.trace,
                        "state0": list(o.state0),
                        "fixed_sets": list(o.extra["fixed_sets"]),
                        "choreography": c.to_dict(),
                    }
                )
                print(f"E = {E}: {label} T = {o.period:.6f} {c}", flush=True)
                if label not in ("CG", "CT"):  # those: rotorlib.beyond.choreo_family
                    tasks.append((o, c, E))
        _write(found, [], t0)
        families = []  # 2. their families, merged where one contains another's orbit
        for fam in pool.map(_family, tasks):
            if any(
                _on(f, fam["found_at"], fam["found_period"])
                and f["sixth"] == fam["sixth"]
                for f in families
            ):
                continue
            families.append(fam)
            print(
                f"  family from E = {fam['found_at']}, T = {fam['found_period']:.6f}: "
                f"E {min(fam['E']):.4f}..{max(fam['E']):.4f}, "
                f"points {fam['points']}, stops {fam['stops']}",
                flush=True,
            )
        _label(families, found)
        z3 = [f for f in families if f["label"] in Z3_FAMILIES]
        for f, pts in zip(z3, pool.map(_z3_points, [f["label"] for f in z3])):
            f["special_points"] = pts
        touch = touches(pool)
    _write(found, families, t0, touch)
    print(f"wrote {OUT} ({len(found)} choreographies, {len(families)} families)")


if __name__ == "__main__":
    np.seterr(all="ignore")
    main()
