"""rotorlib.core.compare: the one rule by which the book judges the paper's numbers."""

import json
import math

import mpmath as mp
import pytest

from rotorlib.core import compare as cmp


@pytest.mark.parametrize(
    "paper, ours, verdict, status",
    [
        ("230.76", 230.7646, "agrees", "reproduced"),
        ("230.77", 230.7646, "last digit off by +1", "not correctly rounded"),
        ("230.76", 230.7688, "truncated", "not correctly rounded"),
        ("203.76", 230.7646, "typo", "wrong"),  # two adjacent digits transposed
        ("2.8611e-11", 2.86114e-11, "agrees", "reproduced"),
        ("2.8611e-11", 2.9611e-11, "typo", "wrong"),  # one wrong digit
        ("7.5", 9.1, "DIFFERS", "wrong"),
        ("15.13", 15.19, "DIFFERS", "wrong"),  # last digit off by 6: not rounding
        (
            "0.0002424",
            0.00024,
            "DIFFERS",
            "wrong",
        ),  # a wrong digit and the last off by 4
    ],
)
def test_printed_digits_are_the_claim(paper, ours, verdict, status):
    c = cmp.claim("x", paper, ours, section="§5")
    assert c.verdict == verdict
    assert c.status == status
    assert not c.approx


def test_mpf_keeps_its_digits():
    with mp.workdps(40):
        ours = mp.mpf("8.968972046849596248158139")
    assert cmp.claim("E_PD", "8.96897204684959624815814", ours).verdict == "agrees"
    assert cmp.claim("E_PD", "8.96897204684959624815813", ours).verdict != "agrees"


def test_tolerance_claims_are_approximate():
    ok = cmp.claim("slope ratio", "7.99", 8.0, rel=0.01)
    far = cmp.claim("E", "8.27", 8.2755, tol=1e-3)
    assert (ok.verdict, ok.status, ok.approx) == ("agrees", "reproduced", True)
    assert (far.verdict, far.status, far.approx) == ("DIFFERS", "wrong", True)
    assert ok.tolerance == pytest.approx(0.0799)


def test_not_evaluable():
    c = cmp.claim("x", "1.5", None, note="no member there")
    assert c.status == "not evaluable" and c.ours == "-"


def test_records_round_differences_below_round_off():
    a = cmp.claim("x", "1.00", 1.0 + 1e-14, tol=0.01)
    b = cmp.claim("x", "1.00", 1.0 + 2e-14, tol=0.01)
    ra, rb = json.loads(cmp.records([a], "ch")), json.loads(cmp.records([b], "ch"))
    assert ra == rb  # round-off does not reach the record
    assert ra[0]["chapter"] == "ch" and ra[0]["status"] == "reproduced"
    nan = json.loads(cmp.records([cmp.claim("y", "2", None)], "ch"))[0]
    assert nan["difference"] is None and nan["tolerance"] is None


def test_markdown_table():
    md = cmp.markdown([cmp.claim("a|b", "1.5", 1.5)])
    lines = md.splitlines()
    assert lines[0].startswith("| section | quantity | paper | ours")
    assert "a\\|b" in lines[2]  # pipes escaped
    md2 = cmp.markdown([["x", 1e-3, "8.9"]], ["name", "diff", "E"])
    assert md2.splitlines()[2] == "| x | 1.0e-03 | 8.9 |"


def test_check():
    assert cmp.check(1e-12, 1e-10) == "agrees"
    assert cmp.check(1e-9, 1e-10) == "DIFFERS"
    assert cmp.check(math.nan, 1.0) == "DIFFERS"


def test_rounded_and_sig_are_machine_independent():
    # two floats that differ in the last bits round to the same printed value
    a, b = 1.0013164193630415, 1.0013164193630413
    assert cmp.rounded(a, 12) == cmp.rounded(b, 12) == 1.00131641936
    assert cmp.sig(a, 8) == cmp.sig(b, 8) == "1.0013164"
    assert cmp.rounded(4.440892098500626e-16, 6, atol=1e-12) == 0.0
    assert cmp.rounded({"x": [2.0000000001, "s", 3]}, 3) == {"x": [2.0, "s", 3]}
    assert cmp.sig(2.86158152420e-11, 5) == "2.8616e-11"
    with pytest.raises(ValueError):
        cmp.rounded(1.0, 0)


def test_bound_checks_and_prints_only_the_bound():
    assert cmp.bound(5.1e-12, 1e-10) == cmp.bound(-9.9e-11, 1e-10) == "< 1e-10"
    with pytest.raises(AssertionError, match="not below"):
        cmp.bound(2e-10, 1e-10)
    with pytest.raises(AssertionError):
        cmp.bound(float("nan"), 1e-10)


def test_glue_needs_digits_for_floats():
    with pytest.raises(ValueError, match="digits"):
        cmp.glue("k", [1.5, 2.0])


def test_table_difference_hides_round_off():
    a = cmp.claim("x", "4.0000211", 4.0000211 + 4e-16)
    b = cmp.claim("x", "4.0000211", 4.0000211 - 3e-16)
    assert cmp.markdown([a]) == cmp.markdown([b])
    assert "< 1e-09" in cmp.markdown([a])
    c = cmp.claim("x", "4.0000212", 4.0000211)
    assert "+1e-07" in cmp.markdown([c])


# ------------------------------------------------------------ categories of the ledger


@pytest.mark.parametrize(
    "paper, ours, category",
    [
        ("230.76", 230.7646, "reproduced"),
        ("230.77", 230.7646, "misrounded"),
        ("230.76", 230.7688, "misrounded"),  # truncated
        ("203.76", 230.7646, "typo"),
        ("7.5", 9.1, "error"),
    ],
)
def test_category_derived_from_the_verdict(paper, ours, category):
    assert cmp.claim("x", paper, ours).category == category


def test_category_given_overrides_and_is_recorded():
    c = cmp.claim(
        "4 - E(PD^l_5)",
        "2.8611e-11",
        2.8616e-11,
        category="inherited",
        inherits="Table I, PD^l_5: tau",
    )
    assert c.verdict == "DIFFERS" and c.status == "wrong"  # the numbers still decide
    assert c.category == "inherited"
    rec = json.loads(cmp.records([c], "ch"))[0]
    assert rec["category"] == "inherited"
    assert rec["inherits"] == "Table I, PD^l_5: tau"
    d = cmp.claim(
        "fan PD^l",
        "1.81",
        1.9943,
        rel=0.01,
        category="definition",
        cause="the fan of PD^l_1 alone",
    )
    assert d.cause == "the fan of PD^l_1 alone" and d.category == "definition"


def test_records_of_default_claims_keep_their_old_keys():
    """Stored notebooks glue these records: a claim without the new arguments must
    give exactly the keys it gave before categories existed."""
    rec = json.loads(cmp.records([cmp.claim("x", "7.6341", 7.63404)], "ch"))[0]
    assert set(rec) == {
        "approx",
        "cause",
        "chapter",
        "difference",
        "note",
        "ours",
        "paper",
        "quantity",
        "section",
        "status",
        "tolerance",
        "verdict",
    }


@pytest.mark.parametrize(
    "bad", [dict(category="wrong"), dict(category="inherited"), dict(inequality="<")]
)
def test_bad_category_arguments_raise(bad):
    with pytest.raises(ValueError):
        cmp.claim("x", "1.5", 1.5, **bad)


def test_inequality_claims():
    holds = cmp.claim("first instability E(IS^l_1)", "3.9", 3.9312, inequality=">=")
    assert (holds.verdict, holds.category, holds.status) == (
        "holds",
        "inequality",
        "reproduced",
    )
    fails = cmp.claim("x", "3.9", 3.5, inequality=">=")
    assert (fails.verdict, fails.category) == ("fails", "error")
    slack = cmp.claim("x", "3.9", 3.89, inequality=">=", tol=0.05)
    assert slack.verdict == "holds"
    below = cmp.claim("x", "3.9", 3.95, inequality="<=")
    assert below.verdict == "fails"
    assert json.loads(cmp.records([holds], "ch"))[0]["rule"] == "bound"


# ----------------------------------------------------------------- family labels


@pytest.mark.parametrize(
    "label, tex",
    [
        ("IS^l_1", r"$\mathrm{IS}^\ell_{1}$"),
        ("ISl1", r"$\mathrm{IS}^\ell_{1}$"),
        ("IS^l_{1}", r"$\mathrm{IS}^\ell_{1}$"),
        ("IS^ℓ_1", r"$\mathrm{IS}^\ell_{1}$"),
        ("PD^r_2", r"$\mathrm{PD}^r_{2}$"),
        ("PDr2", r"$\mathrm{PD}^r_{2}$"),
        ("IS^r_{12}", r"$\mathrm{IS}^r_{12}$"),
        ("ISr12", r"$\mathrm{IS}^r_{12}$"),
        ("PDb", r"$\mathrm{PD}^b$"),
        ("PD^b", r"$\mathrm{PD}^b$"),
        ("IS^r", r"$\mathrm{IS}^r$"),
        ("IS^l_n", r"$\mathrm{IS}^\ell_{n}$"),
        ("IS^l_{4n-k}", r"$\mathrm{IS}^\ell_{4n-k}$"),
        ("IS^{l,r}_n", r"$\mathrm{IS}^{\ell,r}_{n}$"),
    ],
)
def test_label_tex(label, tex):
    assert cmp.label_tex(label) == tex
    assert cmp.label_tex(label, delimiters=False) == tex.strip("$")


@pytest.mark.parametrize("label", ["IS^l_1", "PDb", "IS^{l,r}_n", "PD^r_{12}"])
def test_label_tex_is_mathtext(label):
    from matplotlib.mathtext import MathTextParser

    MathTextParser("path").parse(cmp.label_tex(label))  # raises on bad mathtext


@pytest.mark.parametrize(
    "bad", ["XYl1", "ISl", "ISq2", "PD^b_1", "", "IS^l_1 x", 3, None]
)
def test_label_tex_rejects(bad):
    with pytest.raises(ValueError):
        cmp.label_tex(bad)


def test_label_tex_agrees_with_parse_label():
    from rotorlib.paper.bifurcations import parse_label

    for label in ("IS^l_3", "ISl3", "IS^l_{3}", "PDr2", "PD^r_7"):
        kind, phase, n = parse_label(label)
        letter = r"\ell" if phase == "lib" else "r"
        assert cmp.label_tex(label) == rf"$\mathrm{{{kind}}}^{letter}_{{{n}}}$"


def test_typeset_labels_in_text():
    t = cmp.typeset_labels("IS^l_9 tau, PD^r_6 and ISl6; fan PD^l; PDb; PDw8 ISkr")
    assert t == (
        r"$\mathrm{IS}^\ell_{9}$ tau, $\mathrm{PD}^r_{6}$ and $\mathrm{IS}^\ell_{6}$; "
        r"fan $\mathrm{PD}^\ell$; $\mathrm{PD}^b$; PDw8 ISkr"
    )
    kept = r"$\mathrm{IS}^\ell_1$ and `ISl1`"
    assert cmp.typeset_labels(kept) == kept


def test_markdown_typeset_and_compact():
    c = cmp.claim("IS^l_9: tau", "33.3356", 35.33554, section="Table I")
    default = cmp.markdown([c])
    assert "IS^l_9" in default and "$" not in default  # unchanged unless asked
    compact = cmp.markdown([c], compact=True).splitlines()
    assert compact[0] == "| quantity | paper | ours | verdict |"
    assert compact[2].startswith(r"| $\mathrm{IS}^\ell_{9}$: tau | 33.3356 | 35.3355 |")
    rows = cmp.markdown([["PD^r_2", 1.5e-3]], ["family", "E - 4"], typeset=True)
    assert rows.splitlines()[2] == r"| $\mathrm{PD}^r_{2}$ | 1.5e-03 |"


def test_answer_to_an_open_question_is_its_own_class():
    """An answer to one of the paper's open questions is never scored as reproduced:
    its status is its own, whatever the numbers; the numbers still give the verdict."""
    from rotorlib.core.compare import CATEGORIES, STATUSES, claim

    far = claim("edge", "5.33", 5.3153, tol=0.005, category="answer")
    near = claim("edge", "5.33", 5.331, tol=0.005, category="answer")
    assert "answer" in CATEGORIES and "answer to an open question" in STATUSES
    assert (far.verdict, far.status) == ("DIFFERS", "answer to an open question")
    assert (near.verdict, near.status) == ("agrees", "answer to an open question")
    assert claim("edge", "5.33", 5.331, tol=0.005).status == "reproduced"
