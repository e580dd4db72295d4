"""What the scripts that write a data product in book/data/ share.

Each such script (``atlas_families``, ``atlas_sweep``, ``atlas_cascade``,
``newborn_slopes``, ``rotational_members``, ``quantum_spectra``) takes the same command
line, ``--workers N`` (processes, at least 1) and ``--out PATH``, and the JSON ones write
their record the same way. Imported as ``data_product`` (the scripts' own folder is first
on ``sys.path`` when they run).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path


def arguments(name: str, doc: str, out: Path, argv=None) -> argparse.Namespace | None:
    """The script's ``--workers`` and ``--out``; ``None`` (after one line on stderr) when
    ``--workers`` is below 1, for the script to exit with status 2."""
    ap = argparse.ArgumentParser(description=doc.splitlines()[0])
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--out", type=Path, default=out)
    args = ap.parse_args(argv)
    if args.workers < 1:
        print(f"{name}: --workers must be >= 1", file=sys.stderr)
        return None
    return args


def write_json(name: str, out: Path, data: dict, what: str, t0: float) -> None:
    """Write ``data`` to ``out`` (indented JSON) and say what was written and how long the
    script took since ``t0`` (``time.perf_counter()``)."""
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(data, indent=1) + "\n")
    print(f"{name}: {what} written to {out} in {time.perf_counter() - t0:.0f} s")
