"""One JSON rule in every command: numbers are float64 JSON numbers, the digits beyond
float64 are ``*_str`` decimal strings, ``null`` (with ``*_note``) where float64 cannot
hold a value, never ``nan``; one ``--digits`` range and message everywhere."""

from __future__ import annotations

import json
import math

import mpmath as mp
import pytest

from rotorlib.cli import main
from rotorlib.core.precision import DIGITS_RANGE, check_digits, json_number


def _run(capsys, *argv):
    status = main(list(argv))
    out = capsys.readouterr()
    assert status == 0, out.err
    assert "NaN" not in out.out and "Infinity" not in out.out
    return json.loads(out.out)


def _numeric(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


#: Fields that are not numbers and are null when there is nothing to report (an atlas
#: orbit that is not a choreography; a special point's rotation number where none
#: applies, its member off a branch, its location where it failed); the
#: null-with-a-note rule is for quantities.
NULLABLE = {"choreography", "rotation", "member", "located"}


def _check_rule(obj):
    """Every value obeys the rule; returns the number of quantities checked."""
    n = 0
    if isinstance(obj, list):
        return sum(_check_rule(v) for v in obj)
    for k, v in obj.items():
        if k.endswith("_str"):
            vals = v if isinstance(v, list) else [v]
            assert all(isinstance(s, str) for s in vals), (k, v)
            assert not any(s.strip().lower() in ("nan", "inf", "-inf") for s in vals)
        elif k.endswith("_note"):
            assert isinstance(
                v, str
            )  # stability_note is "" when there is nothing to say
        elif isinstance(v, str):
            assert not _numeric(v), f"{k} = {v!r}: a number given as a string"
        elif isinstance(v, float):
            assert math.isfinite(v)
            n += 1
        elif v is None and k not in NULLABLE:
            assert obj.get(k + "_note"), f"{k} is null without a note"
        elif isinstance(v, (list, dict)):
            n += _check_rule(v) if isinstance(v, dict) else 0
    return n


#: The fields of every special point in ``family --json`` (one type for every family).
POINT_KEYS = {"kind", "E", "located", "description", "rotation", "families"}


@pytest.mark.parametrize(
    "label, lo, hi", [("IS^l_1", "3.99", "4.1"), ("CG", "5", "5.4")]
)
def test_family_special_points_are_one_type(capsys, label, lo, hi):
    """``family --json``: every special point of a newborn family and of a
    choreography has the same fields, its member nested, and obeys the rule."""
    rec = _run(capsys, "family", label, "--E-range", lo, hi, "--json")
    _check_rule(rec)
    assert rec["special_points"]
    for p in rec["special_points"]:
        assert (
            POINT_KEYS | {"branch", "index", "member"}
            <= set(p)
            <= POINT_KEYS | {"branch", "index", "member", "E_str"}
        )
        assert p["member"]["E"] == p["E"] and isinstance(p["located"], str)


def test_json_number_rule():
    assert json_number("E", 1.0, "1.0") == {"E": 1.0}
    rec = json_number("trace", math.inf, "1e400")
    assert rec["trace"] is None and rec["trace_str"] == "1e400" and rec["trace_note"]
    rec = json_number("x", math.nan)
    assert rec["x"] is None and "undefined" in rec["x_note"]


def test_trace_types_agree_with_atlas(capsys):
    r = _run(capsys, "trace", "pendulum", "--E", "1", "--json")
    assert r["E"] == 1.0 and "E_str" not in r  # a number, as in atlas (was "1.0")
    assert isinstance(r["period"], float) and isinstance(r["trace"], float)
    _check_rule(r)
    a = _run(capsys, "atlas", "--E", "5", "--t-max", "3", "--json")
    _check_rule(a)
    assert all(isinstance(o["E"], float) and isinstance(o["period"], float) for o in a)


def test_trace_extended_keeps_digits_in_str(capsys):
    r = _run(
        capsys,
        "trace",
        "pendulum",
        "--E",
        "3.99999999999999999999",
        "--digits",
        "30",
        "--json",
    )
    _check_rule(r)
    assert r["E"] == 4.0 and r["E_str"] == "3.99999999999999999999"
    assert isinstance(r["trace"], float) and isinstance(r["period"], float)
    with mp.workdps(40):
        assert abs(mp.mpf(r["trace_str"]) - r["trace"]) < 1e-15
        assert len(r["trace_str"].replace(".", "").lstrip("0")) >= 25


def test_breather_overflow_is_null_with_note(capsys):
    r = _run(capsys, "trace", "breather", "--log-dE", "-400", "--family", "R", "--json")
    _check_rule(r)
    assert r["trace"] is None and "float64" in r["trace_note"]
    assert abs(mp.mpf(r["trace_str"])) > mp.mpf("1e308")


def test_bifurcations_period_is_a_number_as_in_trace(capsys):
    recs = _run(capsys, "bifurcations", "--n-max", "1", "--kind", "IS", "--json")
    assert isinstance(recs, list) and len(recs) == 2
    _check_rule(recs)
    for r in recs:
        assert isinstance(r["period"], float) and isinstance(r["E"], float)
        assert isinstance(r["log_abs_dE"], float)
        assert abs(float(r["E_str"]) - r["E"]) < 1e-15
    b = _run(capsys, "bifurcations", "--family", "breather", "--json")
    _check_rule(b)
    assert isinstance(b, list) and all(isinstance(r["period"], float) for r in b)


def test_bifurcations_extended(capsys):
    recs = _run(
        capsys,
        "bifurcations",
        "--n-max",
        "1",
        "--kind",
        "IS",
        "--phase",
        "lib",
        "--digits",
        "25",
        "--json",
    )
    _check_rule(recs)
    r = recs[0]
    assert isinstance(r["period"], float) and len(r["period_str"]) > 20
    assert isinstance(r["log_abs_dE"], float) and len(r["log_abs_dE_str"]) > 20


def test_orbit_at_E4_has_no_nan(capsys):
    status = main(["orbit", "ISl2", "--E", "4", "--json"])
    out = capsys.readouterr().out
    assert status == 0 and "nan" not in out.lower()
    r = json.loads(out)
    _check_rule(r)
    assert r["E"] == 4.0 and r["log_abs_dE"] is None and r["log_abs_dE_note"]


@pytest.mark.parametrize(
    "argv",
    [
        ["trace", "pendulum", "--E", "1"],
        ["bifurcations"],
        ["bifurcations", "--family", "breather"],
        ["orbit", "ISl2", "--E", "4"],
        ["atlas", "--E", "5", "--t-max", "3"],
    ],
)
@pytest.mark.parametrize("digits", ["0", "1001"])
def test_one_digits_range_and_message(capsys, argv, digits):
    assert main(argv + ["--digits", digits]) == 2
    err = capsys.readouterr().err.strip()
    lo, hi = DIGITS_RANGE
    assert err == (
        f"rotorlib: error: --digits must be an integer from {lo} to {hi}, got {digits}"
    )
    with pytest.raises(ValueError, match=f"from {lo} to {hi}"):
        check_digits(int(digits))
