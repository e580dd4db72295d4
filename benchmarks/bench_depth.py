"""Cost of tr M far from float64: the Hill integration runs to u = K ~ |log|E - sep||/2.

Run ``.venv/bin/python benchmarks/bench_depth.py``. Prints (never asserts) the
time of one ``rotorlib.orbits.floquet.monodromy`` call per depth, tier and family, the
minimum over ``repeats`` calls after a warm-up (JIT compilation excluded),
and K. Accuracy at these depths is tested in ``tests/test_extremes.py`` and
``tests/test_breather_depth.py``.

This module imports ``rotorlib``; ``rotorlib`` never imports it.
"""

from __future__ import annotations

import argparse
import time

from rotorlib.core.closed_forms import breather, pendulum
from rotorlib.orbits.floquet import monodromy

CASES = (
    ("pendulum", "lib", -60),
    ("pendulum", "rot", -60),
    ("pendulum", "lib", -700),
    ("pendulum", "lib", -800),
    ("pendulum", "rot", -800),
    ("pendulum", "lib", -10000),
    ("pendulum", "rot", -10000),
    ("breather", "R", -20),
    ("breather", "R", -40),
    ("breather", "R", -200),
    ("breather", "LG", -200),
    ("breather", "R", -800),
)


def _orbit(kind, ph, x):
    return (
        pendulum(log_abs_dE=x, phase=ph)
        if kind == "pendulum"
        else breather(log_abs_dE=x, family=ph)
    )


def timed(orbit, digits, repeats):
    monodromy(orbit, digits=digits)
    best = float("inf")
    for _ in range(repeats):
        t0 = time.perf_counter()
        monodromy(orbit, digits=digits)
        best = min(best, time.perf_counter() - t0)
    return best


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args(argv)
    print(
        f"{'orbit':<10}{'':4}{'log|E-sep|':>11}{'K':>10}{'float64 [s]':>13}{'real128 [s]':>13}"
    )
    for kind, ph, x in CASES:
        o = _orbit(kind, ph, x)
        t64 = (
            f"{timed(o, None, args.repeats):.4f}"
            if o.energy.in_float64_range
            else "refused"
        )
        t128 = timed(o, 30, args.repeats)
        print(f"{kind:<10}{ph:4}{x:>11}{o.K:>10.1f}{t64:>13}{t128:>13.3f}")


if __name__ == "__main__":
    main()
