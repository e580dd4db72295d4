"""Level statistics of the stored quantum spectra, window by window (a data product).

    .venv/bin/python scripts/quantum_statistics.py [--workers 2] [--out PATH]
        [--hbar H ...]     # only these hbar; the other rows are kept from --out

Writes book/data/quantum_statistics.json: for every stored hbar and every energy window
(``WINDOWS``; those beyond a spectrum's E_max are skipped), the statistics of
``rotorlib.beyond.quantum_windows.window_statistics`` -- <r> with block-bootstrap and
iid errors and lag-1 correlation (pooled and per sector), the Berry-Robnik fraction
fitted to the spacings unfolded with the library's Weyl law, Sigma^2(L), and the
classical regular fraction predicted from book/data/regular_fraction.json. The spectra
are book/data/quantum_spectra.npz (hbar = 0.03 below E = 8, 0.02 below 6.5), replaced or
joined by every spectrum stored for ``rotorlib.beyond.quantum_data`` (hbar = 0.03, 0.02,
0.014, 0.01 below E = 8). Chapter 11 reads the file and recomputes one window. Each
row depends only on its hbar and window (the same seed for every row), so ``--hbar``
recomputes the rows of a new spectrum and keeps the others: the same file as a full run.
"""

from __future__ import annotations

import json
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from data_product import arguments, write_json  # noqa: E402

from rotorlib.beyond.quantum import SECTORS  # noqa: E402
from rotorlib.beyond.quantum_statistics import load_regular_fraction  # noqa: E402
from rotorlib.beyond.quantum_windows import window_statistics  # noqa: E402

#: The windows of the chapter's table, then those that try to break its conclusion.
WINDOWS = (
    (1.0, 2.0),
    (2.0, 3.0),
    (3.0, 4.0),
    (4.0, 4.5),
    (4.5, 5.33),
    (5.33, 5.6),
    (5.6, 6.5),
    (6.5, 8.0),
    (2.5, 3.0),
    (3.0, 3.27),
    (5.6, 5.87),
    (7.0, 8.0),
)
SETTINGS = dict(block=10, n_boot=1000, n_boot_fit=60, seed=31)
OUT = ROOT / "book" / "data" / "quantum_statistics.json"


def stored_spectra() -> dict[float, tuple[float, dict]]:
    """``{hbar: (E_max, {sector: levels})}``: the dense spectra of
    book/data/quantum_spectra.npz, replaced or joined by every sparse spectrum stored."""
    d = np.load(ROOT / "book" / "data" / "quantum_spectra.npz")
    out = {}
    for tag in ("h0.03", "h0.02"):
        h, E_max = (float(x) for x in d[f"{tag}_meta"])
        out[h] = (E_max, {s: d[f"{tag}_{s}"] for s in SECTORS})
    try:
        from rotorlib.beyond import quantum_data as qd
    except ImportError:
        return out
    for h in qd.stored_hbars():
        sp = qd.stored_spectrum(h)
        out[float(h)] = (float(sp.E_max), {x.sector: x.levels for x in sp.sectors})
    return dict(sorted(out.items(), reverse=True))


def _task(args):
    h, lev, window, regular = args
    return window_statistics(lev, h, [window], regular, **SETTINGS)[0].to_dict()


def main(argv=None) -> int:
    only = sys.argv[1:] if argv is None else list(argv)
    hb = []
    if "--hbar" in only:  # split off --hbar H ... before the shared arguments
        k = only.index("--hbar")
        while k + 1 < len(only) and not only[k + 1].startswith("--"):
            hb.append(float(only.pop(k + 1)))
        only.pop(k)
        if not hb:
            print(
                "quantum_statistics: --hbar needs at least one value", file=sys.stderr
            )
            return 2
    args = arguments("quantum_statistics", __doc__, OUT, only)
    if args is None:
        return 2
    t0 = time.perf_counter()
    regular = load_regular_fraction(ROOT / "book" / "data" / "regular_fraction.json")
    spectra = stored_spectra()
    if any(not any(np.isclose(h, x) for x in spectra) for h in hb):
        print(f"quantum_statistics: stored hbar are {list(spectra)}", file=sys.stderr)
        return 2
    keep = []
    if hb:  # the rows of the other hbar, as the file has them
        old = json.loads(args.out.read_text())["statistics"]
        keep = [r for r in old if not any(np.isclose(r["hbar"], h) for h in hb)]
    tasks = [
        (h, lev, w, regular)
        for h, (E_max, lev) in spectra.items()
        for w in WINDOWS
        if w[1] <= E_max + 1e-9 and (not hb or any(np.isclose(h, x) for x in hb))
    ]
    if args.workers > 1:
        with ProcessPoolExecutor(args.workers) as ex:
            new = list(ex.map(_task, tasks))
    else:
        new = [_task(t) for t in tasks]
    order = {
        (h, w): i for i, (h, w) in enumerate((h, w) for h in spectra for w in WINDOWS)
    }
    rows = sorted(keep + new, key=lambda r: order[(r["hbar"], (r["a"], r["b"]))])
    data = {
        "settings": SETTINGS,
        "windows": [list(w) for w in WINDOWS],
        "spectra": {f"{h:g}": E_max for h, (E_max, _) in spectra.items()},
        "seconds": round(time.perf_counter() - t0, 1),
        "statistics": rows,
    }
    write_json("quantum_statistics", args.out, data, f"{len(rows)} windows", t0)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
