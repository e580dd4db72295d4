"""scripts/make_ledger.py: categories, causes, tolerances and merging of the ledger's rows."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

from rotorlib.core import compare as cmp

ROOT = Path(__file__).resolve().parents[1]
_spec = importlib.util.spec_from_file_location(
    "make_ledger", ROOT / "scripts/make_ledger.py"
)
ml = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(ml)


def _rec(*args, **kw):
    return json.loads(cmp.records([cmp.claim(*args, **kw)], "ch"))[0]


def test_sign_of_off_by_k_is_spelled_out():
    up = _rec("PD^l_1: tau", "7.6341", 7.63404)
    down = _rec("PD^l_4: tau", "26.5517", 26.55182)
    assert ml.category_of(up) == "misrounded"
    assert ml.cause_text(up, "misrounded").startswith(
        "last digit +1: the paper's is 1 unit above"
    )
    assert "2 units below" in ml.cause_text(_rec("x", "26.5516", 26.5518), "misrounded")
    assert "below" in ml.cause_text(down, "misrounded")


def test_old_records_get_their_category_from_the_verdict():
    rec = _rec("x", "203.76", 230.7646)
    assert "category" not in rec and ml.category_of(rec) == "typo"


def test_tolerance_meaning_per_row():
    assert "half a unit in the last digit" in ml.tolerance_text(
        _rec("x", "7.6341", 7.63404)
    )
    assert "1% of the value" in ml.tolerance_text(_rec("x", "7.99", 8.0, rel=0.01))
    assert ml.tolerance_text(_rec("x", "0", 1e-12, tol=1e-10)) == "tolerance ± 1e-10"
    assert "bound" in ml.tolerance_text(_rec("x", "3.9", 3.93, inequality=">="))


def test_repeated_claims_are_merged():
    a = (
        Path("03.ipynb"),
        "t",
        dict(_rec("IS^l_7: tau", "29.0524", 29.05234), anchor=""),
    )
    b = (
        Path("10.ipynb"),
        "t",
        dict(_rec("IS^l_7: period tau", "29.0524", 29.05234), anchor=""),
    )
    c = (
        Path("06.ipynb"),
        "t",
        dict(_rec("-log(4 - E(IS^l_8))", "22.1116", 22.11153), anchor=""),
    )
    d = (
        Path("03.ipynb"),
        "t",
        dict(_rec("PD^r_6: log|E-4|", "-22.1116", -22.11153), anchor=""),
    )
    groups = ml.merge([a, b, c, d])
    assert [len(g) for g in groups] == [
        2,
        1,
        1,
    ]  # IS^l_8 and PD^r_6 are different claims


def test_pretty_typesets_labels_and_symbols():
    assert ml.pretty("tau of IS^l_9 <= 3") == r"τ of $\mathrm{IS}^\ell_{9}$ ≤ 3"
    assert ml.pretty("log|E-4|") == "log\\|E-4\\|"


def test_ledger_page_is_up_to_date():
    assert ml.main(["--check"]) == 0, "run: python scripts/make_ledger.py"
