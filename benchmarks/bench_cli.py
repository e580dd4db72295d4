"""Wall time of one command line, as a user runs it, against another checkout.

Issue 11 asks that ``python -m rotorlib orbit ISl6 --E 4`` (real128) be no slower than
it was when the issue was filed. A wall time on a shared machine moves by 20 % from one
minute to the next, so a figure measured on another day is no yardstick: this script
runs the command in this checkout and in another one (``--against``, e.g. a
``git worktree`` of the commit the issue was filed at), alternating between them, and
prints the median, smallest and largest wall time of each, with the median of
``python -c "import rotorlib"`` (interpreter start and imports). It also says whether
both printed the same table, so a speed-up that moved a number shows up here too::

    git worktree add /tmp/filed c3b4371
    .venv/bin/python benchmarks/bench_cli.py --against /tmp/filed [--repeat 10]
    .venv/bin/python benchmarks/bench_cli.py -- trace pendulum --log-dE -40 --digits 30

Each checkout is run with its own directory first on ``PYTHONPATH`` and this
interpreter; times are printed, never asserted.

heyoka (>= 7.10) keeps the code it compiles on disk (``~/.cache/heyoka``), so only the
first run on a machine pays for LLVM: one run per checkout before the timed ones keeps
that out of the figures. ``--cold`` times every run with an empty cache instead, which
is what a user sees the first time (``orbit ISl6 --E 4``: 2.0-2.5 s cold against
1.0-1.2 s warm on the 2-core machine of the book's CI).
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DEFAULT = ["orbit", "ISl6", "--E", "4"]
#: ``python -c`` prelude for --cold: the command with heyoka's disk cache in a new,
#: empty directory (its argument: that directory, then the command's arguments).
COLD = (
    "import runpy, sys, heyoka; heyoka.llvm_state.set_diskcache_path(sys.argv[1]); "
    "sys.argv = ['rotorlib', *sys.argv[2:]]; "
    "runpy.run_module('rotorlib', run_name='__main__', alter_sys=True)"
)


def run(root: Path, argv: list[str]) -> tuple[float, str]:
    """Wall seconds and output of ``python argv``, ``root`` first on the path."""
    env = dict(os.environ, PYTHONPATH=str(root))
    t0 = time.perf_counter()
    out = subprocess.run(
        [sys.executable, *argv], cwd=root, env=env, capture_output=True, text=True
    )
    seconds = time.perf_counter() - t0
    if out.returncode:
        raise SystemExit(
            f"{root}: {' '.join(argv)} failed: {out.stderr.strip()[-300:]}"
        )
    return seconds, out.stdout


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--against", type=Path, help="another checkout of the repository")
    ap.add_argument("--repeat", type=int, default=8, help="runs per checkout (8)")
    ap.add_argument(
        "--cold", action="store_true", help="every run with an empty heyoka disk cache"
    )
    ap.add_argument("command", nargs="*", help="rotorlib arguments (orbit ISl6 --E 4)")
    args = ap.parse_args()
    if args.repeat < 1:
        raise SystemExit("--repeat must be at least 1")
    roots = [ROOT] + ([args.against.resolve()] if args.against else [])
    for r in roots:
        if not (r / "rotorlib" / "__init__.py").is_file():
            raise SystemExit(f"{r} is not a checkout of this repository (no rotorlib/)")
    words = args.command or DEFAULT
    cmd = ["-m", "rotorlib", *words]
    imp = ["-c", "import rotorlib"]
    times = {r: {"command": [], "import": []} for r in roots}
    outputs = {}
    for r in roots:  # warm the file-system and JIT caches, keep the output
        outputs[r] = run(r, cmd)[1]
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(args.repeat):
            for r in roots:  # alternate, so both see the same machine
                if args.cold:
                    cache = Path(tmp, f"{k}-{roots.index(r)}")
                    argv = ["-c", COLD, str(cache), *words]
                else:
                    argv = cmd
                times[r]["command"].append(run(r, argv)[0])
                times[r]["import"].append(run(r, imp)[0])

    cache = "empty heyoka cache" if args.cold else "warm heyoka cache"
    print(
        f"python {' '.join(cmd)}: wall seconds over {args.repeat} alternating runs "
        f"({cache})"
    )
    print(f"{'checkout':<40} {'median':>7} {'min':>7} {'max':>7} {'import':>7}")
    for r in roots:
        t = times[r]["command"]
        i = statistics.median(times[r]["import"])
        print(
            f"{str(r):<40} {statistics.median(t):7.3f} {min(t):7.3f} {max(t):7.3f} "
            f"{i:7.3f}"
        )
    if len(roots) == 2:
        a, b = (statistics.median(times[r]["command"]) for r in roots)
        same = outputs[roots[0]] == outputs[roots[1]]
        same = "yes" if same else "NO"
        print(f"this checkout / other: {a / b:.3f}; same output: {same}")


if __name__ == "__main__":
    main()
