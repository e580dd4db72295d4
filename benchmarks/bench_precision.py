"""Speed against accuracy: work-precision measurements for tr M and for a bifurcation.

Run ``.venv/bin/python benchmarks/bench_precision.py`` (``--quick`` for fewer
repeats). It prints the tables that ``book/12_precision.ipynb`` draws
(time, error, integrator steps per method and setting) and checks the
targets of issue 7, printing (never asserting) the outcome.

Every error is measured against a reference computed at much higher
precision (the Hill reduction with heyoka in ``REF_DIGITS``-digit
arithmetic; ``tests/test_precision.py`` checks that reference against the
independent textbook 4x4 variational route in 512-bit arithmetic). Every
time is the minimum over ``repeats`` calls after one warm-up call (so JIT
compilation is excluded), averaged over the energies of the set.

This module imports ``rotorlib``; ``rotorlib`` never imports it.
"""

from __future__ import annotations

import argparse
import math
import time
from dataclasses import dataclass

import mpmath as mp

from rotorlib.core.closed_forms import pendulum
from rotorlib.core.flow import monodromy_matrix
from rotorlib.core.precision import FLOAT64, Tier, heyoka_available, precision_tier
from rotorlib.orbits.floquet import monodromy, textbook_monodromy, variational_monodromy
from rotorlib.orbits.hill import hill_problem, solve_hill

#: Digits of the reference computation (heyoka multiprecision, ~260 bits).
REF_DIGITS = 70

#: Energies "deep in the cascade": log|E - 4| in [-22, -21], both phases.
CASCADE = (
    (-21.0012, "lib"),
    (-21.5, "lib"),
    (-22.0, "lib"),
    (-21.0012, "rot"),
    (-21.5, "rot"),
    (-22.0, "rot"),
)
#: Deeper energies (the textbook float64 route is meaningless there).
DEEP = ((-60.0, "lib"), (-60.0, "rot"), (-200.0, "lib"), (-200.0, "rot"))


@dataclass(frozen=True)
class Method:
    """One point of a work-precision diagram: a method at one setting.

    ``run(orbit)`` returns ``(trace, steps)`` with ``trace`` a float or a
    decimal string carrying every computed digit.
    """

    method: str
    setting: str
    precision: str
    run: object
    repeats: int = 3
    max_energies: int = 99


def _tm(orbit, **kw):
    M = monodromy(orbit, **kw)
    return (M.trace_str if M.precision != "float64" else M.trace), None


def _hill(orbit, backend, precision, tol=None, digits=None):
    """Hill reduction, returning the trace and the integrator steps."""
    prob = hill_problem(orbit, digits)
    # mpmath works at digits + 5 working digits: "mpmath21" is digits 16
    d = int(precision[6:]) - 5 if backend == "mpmath" else Tier(precision)
    sol = solve_hill(prob, d, tol, integrator=backend)
    with mp.workdps(80):
        d = mp.mpf(sol.delta_exact) if precision != "float64" else mp.mpf(sol.delta)
        t = d * d if prob.repeats == 2 else 2 + d
        return (mp.nstr(t, 60) if precision != "float64" else float(t)), sol.steps


def _textbook(orbit, method, rtol=1e-12):
    if method == "heyoka":  # heyoka's Taylor method in float64 (no step count)
        return float(monodromy_matrix(list(orbit.state0), orbit.period, FLOAT64)[2]), 0
    V = variational_monodromy(orbit.state0, orbit.period, rtol=rtol)
    return V.trace, V.steps


def trace_methods(quick=False, mpmath_tier=True):
    """The methods and settings of the tr M work-precision diagram."""
    hy = heyoka_available()
    ms = []
    for rtol in (1e-6, 1e-8, 1e-10, 1e-12, 1e-13):
        ms.append(
            Method(
                "textbook scipy DOP853 (4x4, whole period)",
                f"rtol={rtol:g}",
                "float64",
                lambda o, r=rtol: _textbook(o, "scipy", r),
                repeats=1 if quick else 2,
            )
        )
    if hy:
        ms.append(
            Method(
                "textbook heyoka float64 (4x4, whole period)",
                "tol=eps",
                "float64",
                lambda o: _textbook(o, "heyoka"),
            )
        )
    for rtol in (1e-6, 1e-8, 1e-10, 1e-12, None):
        ms.append(
            Method(
                "Hill reduction, scipy DOP853",
                f"rtol={rtol or 1e-13:g}",
                "float64",
                lambda o, r=rtol: _hill(o, "scipy", "float64", r),
            )
        )
    if hy:
        for tol in (1e-6, 1e-9, 1e-12, None):
            ms.append(
                Method(
                    "Hill reduction, heyoka float64",
                    "tol=" + (f"{tol:g}" if tol else "eps"),
                    "float64",
                    lambda o, t=tol: _hill(o, "heyoka", "float64", t),
                    repeats=3 if quick else 7,
                )
            )
        for tol in (1e-20, 1e-25, None):
            ms.append(
                Method(
                    "Hill reduction, heyoka real128",
                    "tol=" + (f"{tol:g}" if tol else "eps"),
                    "real128",
                    lambda o, t=tol: _hill(o, "heyoka", "real128", t, digits=30),
                )
            )
        for digits in (40, 50):
            _, prec = precision_tier(digits)
            ms.append(
                Method(
                    "Hill reduction, heyoka multiprecision",
                    f"digits={digits} ({prec})",
                    prec,
                    lambda o, d=digits, p=prec: _hill(o, "heyoka", p, None, digits=d),
                    repeats=1 if quick else 2,
                )
            )
    if mpmath_tier:
        ms.append(
            Method(
                "Hill reduction, mpmath odefun",
                "digits=16 (mpmath21)",
                "mpmath21",
                lambda o: _hill(o, "mpmath", "mpmath21", None, digits=16),
                repeats=1,
                max_energies=1,
            )
        )
    return ms


def reference_trace(x, phase, digits=REF_DIGITS):
    """tr M at ``log|E - 4| = x`` with ``digits`` digits (Hill reduction, heyoka multiprecision)."""
    M = monodromy(pendulum(log_abs_dE=x, phase=phase), digits=digits)
    with mp.workdps(digits + 10):
        return mp.mpf(M.trace_str)


def _timed(f, repeats):
    f()  # warm-up (JIT compilation, caches)
    best, out = math.inf, None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = f()
        best = min(best, time.perf_counter() - t0)
    return best, out


def work_precision(energies=CASCADE, methods=None, refs=None, quick=False):
    """Measure every method on every energy.

    Returns
    -------
    list of dict
        One row per method and setting: ``method``, ``setting``, ``precision``,
        ``time`` (seconds per energy: minimum over repeats, mean over energies),
        ``error`` (max over energies of ``|tr M - reference|``), ``steps``
        (mean integrator steps per energy) and ``n_energies``.
    """
    methods = trace_methods(quick) if methods is None else methods
    orbits = [pendulum(log_abs_dE=x, phase=ph) for x, ph in energies]
    if refs is None:
        refs = [reference_trace(x, ph) for x, ph in energies]
    rows = []
    for meth in methods:
        times, errs, steps = [], [], []
        for orb, ref in list(zip(orbits, refs))[: meth.max_energies]:
            t, (tr, st) = _timed(lambda: meth.run(orb), meth.repeats)
            with mp.workdps(REF_DIGITS + 10):
                err = abs(mp.mpf(tr) - ref) if math.isfinite(float(tr)) else mp.inf
            times.append(t)
            errs.append(float(err))
            steps.append(st)
        rows.append(
            dict(
                method=meth.method,
                setting=meth.setting,
                precision=meth.precision,
                time=sum(times) / len(times),
                error=max(errs),
                steps=None if steps[0] is None else sum(steps) / len(steps),
                n_energies=len(times),
            )
        )
    return rows


# --------------------------------------------------------------------------- locating a bifurcation

#: IS^l_7 (paper Table 1: log(4 - E) = -21.0012): a bracket containing it and no other root of Delta = c.
IS_L7 = dict(label="IS^l_7", phase="lib", bracket=(-21.1, -20.9), paper=-21.0012)


def _delta_float(x, phase, backend, tol=None):
    return solve_hill(
        hill_problem(pendulum(log_abs_dE=x, phase=phase)),
        tol=tol,
        integrator=backend,
    ).delta


def _target(phase, bracket):
    """``Delta`` at the root (+2 or -2 for an IS transition): the value of ``|Delta|>=2`` side."""
    d = _delta_float(bracket[0], phase, "heyoka" if heyoka_available() else "scipy")
    return 2.0 if d > 0 else -2.0


def locate_methods(quick=False):
    """``(name, precision, locate(bracket, phase, c) -> (x as mpf, evaluations))``."""
    from scipy.optimize import brentq

    def float_locator(backend):
        def run(br, phase, c):
            n = [0]

            def f(x):
                n[0] += 1
                return _delta_float(x, phase, backend) - c

            return mp.mpf(brentq(f, *br, xtol=1e-15, rtol=1e-15)), n[0]

        return run

    def textbook_locator(br, phase, c):
        n = [0]

        def f(x):
            n[0] += 1
            o = pendulum(log_abs_dE=x, phase=phase)
            return variational_monodromy(o.state0, o.period, rtol=1e-12).trace - c * c

        fa, fb = f(br[0]), f(br[1])
        if fa * fb > 0:
            return None, n[0]  # no sign change: the method cannot bracket the root
        return mp.mpf(brentq(f, *br, xtol=1e-15, rtol=1e-15)), n[0]

    def mp_locator(digits):
        from rotorlib.paper.bifurcations import delta_mp

        def run(br, phase, c):
            n = [0]
            with mp.workdps(digits + 10):

                def f(x):
                    n[0] += 1
                    return delta_mp(x, phase, digits) - c

                x = mp.findroot(
                    f,
                    (mp.mpf(br[0]), mp.mpf(br[1])),
                    solver="anderson",
                    tol=mp.mpf(10) ** (2 - digits),
                    maxsteps=60,
                    verify=False,
                )
                return +x, n[0]

        return run

    out = [
        ("textbook scipy DOP853 rtol=1e-12", "float64", textbook_locator),
        ("Hill, scipy float64 + brentq", "float64", float_locator("scipy")),
    ]
    if heyoka_available():
        out += [
            ("Hill, heyoka float64 + brentq", "float64", float_locator("heyoka")),
            ("Hill, heyoka real128 + Anderson-Bjorck", "real128", mp_locator(30)),
            (
                "Hill, heyoka mp + Anderson-Bjorck",
                precision_tier(45)[1],
                mp_locator(45),
            ),
        ]
    return out


def reference_root(case=IS_L7, digits=REF_DIGITS, near=None):
    """The transition at ``digits`` digits (secant from ``near``, default the float64 root)."""
    from rotorlib.paper.bifurcations import refine_mp

    c = _target(case["phase"], case["bracket"])
    if near is None:
        from scipy.optimize import brentq

        near = brentq(
            lambda x: _delta_float(x, case["phase"], "heyoka") - c,
            *case["bracket"],
            xtol=1e-15,
        )
    x, _ = refine_mp(near, case["phase"], c, digits=digits, maxiter=12)
    return x


def bifurcation_work_precision(case=IS_L7, ref=None, quick=False):
    """Locate ``case`` with each method; error in ``log|E - 4|`` against ``ref`` and time."""
    c = _target(case["phase"], case["bracket"])
    ref = reference_root(case) if ref is None else ref
    rows = []
    for name, prec, run in locate_methods(quick):
        t0 = time.perf_counter()
        x, n = run(case["bracket"], case["phase"], c)
        t = time.perf_counter() - t0
        with mp.workdps(REF_DIGITS + 10):
            err = None if x is None else float(abs(mp.mpf(x) - ref))
        rows.append(
            dict(
                method=name,
                precision=prec,
                time=t,
                error=err,
                evaluations=n,
                x=None if x is None else mp.nstr(x, 35),
            )
        )
    return rows


# --------------------------------------------------------------------------- targets and printing


def per_energy_time(x=-21.5, phase="rot", n=200):
    """Seconds per float64 ``rotorlib.orbits.floquet.monodromy`` call after warm-up (min over 5 batches of ``n``)."""
    orb = pendulum(log_abs_dE=x, phase=phase)
    monodromy(orb)
    best = math.inf
    for _ in range(5):
        t0 = time.perf_counter()
        for _ in range(n):
            monodromy(orb)
        best = min(best, (time.perf_counter() - t0) / n)
    return best


def trace_digits_check(x=-60.0, phase="rot", digits=30):
    """``trace --digits 30`` at ``x`` against the independent 512-bit textbook computation.

    Returns ``(trace_str, reference_str, agreeing significant digits)``.
    """
    import json
    import subprocess
    import sys

    out = subprocess.run(
        [
            sys.executable,
            "-m",
            "rotorlib",
            "trace",
            "pendulum",
            "--phase",
            phase,
            "--log-dE",
            repr(x),
            "--digits",
            str(digits),
            "--json",
        ],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    rec = json.loads(out)
    tr = rec.get("trace_str", rec["trace"])  # the digits beyond float64
    ref = textbook_reference(x, phase)
    with mp.workdps(160):
        diff = abs(mp.mpf(tr) - mp.mpf(ref.trace_str))
        agree = (
            float(-mp.log10(diff / abs(mp.mpf(ref.trace_str)))) if diff else math.inf
        )
    return tr, ref.trace_str, agree


def textbook_reference(x, phase, bits=512):
    """Independent tr M: 4x4 variational equations over one period, heyoka ``mp<bits>``.

    State and period at G from mpmath (``E = 4 -+ exp(x)`` at high precision,
    ``p2 = sqrt(4E/3)``, period ``4K(E/4)/sqrt3`` or ``2 kappa K(kappa^2)/sqrt3``
    with ``kappa^2 = 4/E``); no Hill reduction and no closed-form orbit involved.
    """
    return textbook_monodromy(
        pendulum(log_abs_dE=float(x), phase=phase), Tier(f"mp{bits}")
    )


def _fmt_rows(rows, cols):
    w = {c: max(len(c), *(len(_cell(r[c])) for r in rows)) for c in cols}
    lines = ["  ".join(c.ljust(w[c]) for c in cols)]
    lines += ["  ".join(_cell(r[c]).ljust(w[c]) for c in cols) for r in rows]
    return "\n".join(lines)


def _cell(v):
    if v is None:
        return "-"
    if isinstance(v, float):
        return f"{v:.3g}"
    return str(v)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer repeats")
    ap.add_argument(
        "--no-mpmath", action="store_true", help="skip the slow mpmath tier"
    )
    args = ap.parse_args(argv)

    print(
        f"# tr M work-precision, log|E-4| in [-22, -21], both phases ({len(CASCADE)} energies)"
    )
    rows = work_precision(
        CASCADE, trace_methods(args.quick, not args.no_mpmath), quick=args.quick
    )
    print(
        _fmt_rows(
            rows,
            ["method", "setting", "precision", "time", "error", "steps", "n_energies"],
        )
    )
    print(f"\n# tr M work-precision, deeper: {DEEP}")
    deep_methods = [
        m
        for m in trace_methods(args.quick, False)
        if "rtol=1e-6" not in m.setting or "textbook" not in m.method
    ]
    rows_deep = work_precision(DEEP, deep_methods, quick=args.quick)
    print(
        _fmt_rows(
            rows_deep, ["method", "setting", "precision", "time", "error", "steps"]
        )
    )

    print(
        f"\n# locating {IS_L7['label']} (bracket {IS_L7['bracket']}); error in log|E-4|"
    )
    brows = bifurcation_work_precision(IS_L7, quick=args.quick)
    print(
        _fmt_rows(brows, ["method", "precision", "time", "error", "evaluations", "x"])
    )

    print("\n# targets (issue 7)")
    hey = [
        r
        for r in rows
        if r["method"] == "Hill reduction, heyoka float64" and r["setting"] == "tol=eps"
    ]
    tb = [
        r
        for r in rows
        if r["method"].startswith("textbook scipy") and r["setting"] == "rtol=1e-12"
    ][0]
    f64 = (
        hey[0]
        if hey
        else [
            r
            for r in rows
            if r["method"] == "Hill reduction, scipy DOP853"
            and r["setting"] == "rtol=1e-13"
        ][0]
    )
    deep64 = [
        r
        for r in rows_deep
        if r["method"] == f64["method"] and r["setting"] == f64["setting"]
    ][0]
    print(
        f"float64 tr M error, log|E-4| in [-22,-21]: {f64['error']:.2e}  (target 1e-11) "
        f"-> {f64['error'] < 1e-11}"
    )
    print(
        f"float64 tr M error at log|E-4| = -60, -200: {deep64['error']:.2e}  -> {deep64['error'] < 1e-11}"
    )
    print(
        f"time per energy: {f64['method']} {f64['time'] * 1e3:.3f} ms, textbook scipy rtol=1e-12 "
        f"{tb['time'] * 1e3:.1f} ms (error {tb['error']:.1e}) -> {f64['time'] <= tb['time']}"
    )
    if heyoka_available():
        t = per_energy_time()
        print(
            f"rotorlib.orbits.floquet.monodromy float64 (heyoka) per energy after warm-up: {t * 1e3:.3f} ms "
            f"(target < 1 ms) -> {t < 1e-3}"
        )
    tr, ref, agree = trace_digits_check()
    print(f"trace pendulum --phase rot --log-dE -60 --digits 30: {tr}")
    print(f"independent textbook 4x4, 512-bit:                 {ref[:40]}")
    print(f"agreeing significant digits: {agree:.1f} (target 20) -> {agree >= 20}")


if __name__ == "__main__":
    main()
