"""The families born from CG at its resonances, summarised for chapter 10a: writes
``book/data/cg_resonance_families.json``.

For each family of ``rotorlib.beyond.choreo_resonance.family_names()`` (the 1/4 ones are
CZ2, CZ1: their special points come from ``rotorlib.beyond.choreo_z3``, ~2 min each):
the range of energies it spans and why it ends there, its special points (kind, E,
description), its stable windows, the period at its birth and at its far end, its
largest energy, and the choreography symmetry of a member next to its birth. The
chapter reads this file and recomputes one family as a spot check.
Run: ``nice -n 10 .venv/bin/python scripts/choreo_resonance_data.py`` (~5 min).
"""

from __future__ import annotations

import json
import pathlib

from rotorlib.beyond import choreo_resonance as cr

OUT = pathlib.Path(__file__).parents[1] / "book/data/cg_resonance_families.json"


def main():
    out = {}
    for name in cr.family_names():
        out[name] = cr.summary(name)
        print(name, out[name]["E_min"], out[name]["E_max"], flush=True)
    OUT.write_text(json.dumps(out, indent=1) + "\n")


if __name__ == "__main__":
    main()
