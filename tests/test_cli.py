"""The command line: JSON fields, cross-checks, and clean refusal of bad input."""

import json
import math
import subprocess
import sys

import mpmath as mp
import pytest
from conftest import requires_heyoka, textbook_reference

from rotorlib.core.closed_forms import pendulum
from rotorlib.orbits.floquet import monodromy


def run(*args):
    p = subprocess.run(
        [sys.executable, "-m", "rotorlib", *args],
        capture_output=True,
        text=True,
        timeout=300,
    )
    return p.returncode, p.stdout, p.stderr


@requires_heyoka
def test_trace_json_against_independent_reference():
    """Issue 2 must-show: the CLI agrees with the multiprecision textbook reference to 1e-10."""
    rc, out, err = run("trace", "pendulum", "--E", "1", "3.9", "5", "100", "--json")
    assert rc == 0, err
    recs = json.loads(out)
    assert [r["family"] for r in recs] == ["pendulum"] * 4
    for r, E in zip(recs, (1.0, 3.9, 5.0, 100.0)):
        ref, _ = textbook_reference("pendulum-E", E, "")
        assert abs(r["trace"] - float(ref)) < 1e-10 * max(1, abs(float(ref)))
        # the JSON rule: E is a number, as in every command (it was the string "1.0")
        assert isinstance(r["E"], float) and r["E"] == E and r["period"] > 0
    for ph in ("lib", "rot"):
        rc, out, err = run(
            "trace",
            "pendulum",
            "--log-dE",
            "-30",
            "-60",
            "-100",
            "--phase",
            ph,
            "--json",
        )
        assert rc == 0, err
        for r, x in zip(json.loads(out), (-30.0, -60.0, -100.0)):
            bits = max(
                256, int(math.ceil((2 * -x / math.log(10) + 40) * 3.33 / 64)) * 64
            )
            ref, _ = textbook_reference("pendulum-log", x, ph, bits)
            assert abs(r["trace"] - float(ref)) < 1e-10 * max(1, abs(float(ref)))
            with mp.workdps(80):
                assert (
                    abs(
                        mp.mpf(r["E_str"])
                        - (4 + (1 if ph == "rot" else -1) * mp.exp(x))
                    )
                    < mp.exp(x) * 1e-15
                )
    rc, out, err = run("trace", "breather", "--E", "4.6", "9", "20", "--json")
    assert rc == 0, err
    for r, E in zip(json.loads(out), (4.6, 9.0, 20.0)):
        ref, _ = textbook_reference("breather", E, "R")
        assert r["breather_family"] == "R"
        assert abs(r["trace"] - float(ref)) < 1e-10 * max(1, abs(float(ref)))


@requires_heyoka
def test_trace_digits_30_deep_rotation():
    """Issue 7 target: --digits 30 at log(E-4) = -60 correct to 20 digits."""
    rc, out, err = run(
        "trace",
        "pendulum",
        "--phase",
        "rot",
        "--log-dE",
        "-60",
        "--digits",
        "30",
        "--json",
    )
    assert rc == 0, err
    r = json.loads(out)
    ref, _ = textbook_reference("pendulum-log", -60.0, "rot", 384)
    with mp.workdps(40):
        assert abs(mp.mpf(r["trace_str"]) - ref) < mp.mpf(10) ** -20
    assert r["precision"] == "real128"


def test_table_output():
    rc, out, err = run("trace", "pendulum", "--E", "2")
    assert rc == 0 and "trace" in out.splitlines()[0]


@pytest.mark.parametrize(
    "args",
    [
        ("trace", "pendulum", "--E", "-1"),
        ("trace", "pendulum", "--E", "4"),
        ("trace", "pendulum", "--E", "nan"),
        ("trace", "pendulum", "--E", "inf"),
        ("trace", "pendulum", "--E", "abc"),
        ("trace", "pendulum", "--log-dE", "-30"),
        ("trace", "pendulum", "--log-dE", "2", "--phase", "lib"),
        (
            "trace",
            "pendulum",
            "--log-dE",
            "-900",
            "--phase",
            "rot",
        ),  # float64 tier: below its range
        ("trace", "pendulum", "--log-dE", "-1e6", "--phase", "lib"),
        ("trace", "pendulum", "--log-dE", "-inf", "--phase", "rot"),
        ("trace", "pendulum", "--E", "-1e6"),
        ("trace", "pendulum", "--E", "4.000000000000000000000000"),
        ("trace", "breather", "--E", "4.50000"),
        ("trace", "breather", "--log-dE", "-800", "--family", "R"),
        ("trace", "pendulum", "--E", "3", "--phase", "rot"),
        ("trace", "breather", "--E", "4.5"),
        ("trace", "breather", "--E", "4.3", "--phase", "rot"),
        ("trace", "breather", "--E", "4.3", "--family", "R"),
        ("trace", "breather", "--E", "3.5", "--family", "LD"),
        ("trace", "comet", "--E", "1"),
        ("trace", "pendulum"),
        ("trace", "pendulum", "--E", "1", "--digits", "0"),
        ("nosuchcommand",),
        (),
        ("orbit", "ISl9", "--E", "4"),  # a transition with no followed family
        ("orbit", "XYl1", "--E", "4"),  # no such label
        ("orbit", "PDr2", "--E", "4.6"),  # past the family's fold
        ("orbit", "ISl2", "--E", "3"),  # below the birth
        ("orbit", "ISl2", "--E", "nan"),
        ("orbit", "ISl2", "--E", "-1"),
        ("orbit", "PDb", "--E", "9.5"),  # above the breather's period doubling
        ("bifurcations", "--phase", "lib", "--n-max", "0"),
        ("bifurcations", "--phase", "sideways"),
    ],
)
def test_bad_input_one_line_nonzero(args):
    rc, out, err = run(*args)
    assert rc != 0
    lines = [ln for ln in err.strip().splitlines() if ln.strip()]
    assert len(lines) == 1 and "Traceback" not in err, err
    assert lines[0].startswith("rotorlib: error:")


@requires_heyoka
def test_bifurcations_digits_uses_extended_precision():
    """One precision control: --digits 30 re-locates the roots in real128; float64 agrees to 1e-12."""
    rc, out, err = run(
        "bifurcations",
        "--phase",
        "rot",
        "--kind",
        "PD",
        "--n-max",
        "3",
        "--digits",
        "30",
        "--json",
    )
    assert rc == 0, err
    ext = json.loads(out)
    rc, out, err = run(
        "bifurcations", "--phase", "rot", "--kind", "PD", "--n-max", "3", "--json"
    )
    f64 = json.loads(out)
    assert [r["label"] for r in ext] == ["PD^r_1", "PD^r_2", "PD^r_3"]
    for a, b in zip(ext, f64):
        assert a["precision"] == "real128" and b["precision"] == "float64"
        assert len(a["log_abs_dE_str"].lstrip("-").replace(".", "")) >= 25
        assert abs(a["log_abs_dE"] - b["log_abs_dE"]) < 1e-12 * max(
            1, abs(b["log_abs_dE"])
        )


@pytest.mark.parametrize(
    "args,reason",
    [
        (("--log-dE", "-1e6", "--phase", "lib"), "below the float64 range"),
        (("--log-dE", "-1E+3", "--phase", "lib"), "below the float64 range"),
        (("--log-dE", "-inf", "--phase", "lib"), "must be finite"),
        (("--E", "-1e6"), "E must be >= 0"),
        (("--E", "-.5"), "E must be >= 0"),
    ],
)
def test_negative_numbers_reach_the_library(args, reason):
    """argparse alone reads only -123 and -1.5 as numbers; -1e6, -1E+3, -.5, -inf must reach the
    energy validation and be refused there with its reason (not "expected at least one argument")."""
    rc, out, err = run("trace", "pendulum", *args)
    assert rc == 2 and reason in err and len(err.strip().splitlines()) == 1, err


@requires_heyoka
def test_negative_numbers_any_notation_computed():
    """-.5 (float64) and -1E+3 (beyond float64, --digits 30) give the library's values for the same x."""

    rc, out, err = run(
        "trace", "pendulum", "--log-dE", "-.5", "--phase", "lib", "--json"
    )
    assert rc == 0, err
    assert (
        json.loads(out)["trace"]
        == monodromy(pendulum(log_abs_dE=-0.5, phase="lib")).trace
    )
    rc, out, err = run(
        "trace",
        "pendulum",
        "--log-dE",
        "-1E+3",
        "--phase",
        "rot",
        "--digits",
        "30",
        "--json",
    )
    assert rc == 0, err
    rec = json.loads(out)
    # -1E+3 is the float64 -1000 exactly: a number, no log_abs_dE_str (no more digits)
    assert rec["log_abs_dE"] == -1000.0 and "log_abs_dE_str" not in rec
    assert rec["E"] == 4.0 and rec["E_str"].startswith("4 + 5.0759588975494")
    ref = monodromy(pendulum(log_abs_dE=-1000, phase="rot"), digits=30).trace_str
    assert rec["trace_str"] == ref and rec["trace"] == float(ref)


def test_E0_and_tiny_E_marginal_documented():
    """E = 0 (1:1 resonance, M = identity) and E = 1e-300 (tr M = 4 - 2.9e-903) are 'marginal' with a note;
    the command's help says what that means."""
    rc, out, err = run("trace", "pendulum", "--E", "0", "1e-300", "--json")
    assert rc == 0, err
    r0, r1 = json.loads(out)
    assert r0["stability"] == r1["stability"] == "marginal" and r0["trace"] == 4.0
    assert (
        "1:1 resonance" in r0["stability_note"]
        and "2.86e-903 > 0 (stable)" in r1["stability_note"]
    )
    assert r1["E"] == 1e-300 and "E_str" not in r1
    rc, out, err = run("trace", "-h")
    text = " ".join(out.split())
    assert rc == 0 and "marginal" in text and "1:1 resonance" in text and "-1e4" in text
