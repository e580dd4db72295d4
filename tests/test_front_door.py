"""The front door: rotorlib.orbit / family / transition / census and the result protocol."""

from __future__ import annotations

import json
import math
import re
import subprocess
import sys
from pathlib import Path

import pytest

import rotorlib

ROOT = Path(__file__).resolve().parents[1]
PROTOCOL = (
    "label",
    "E",
    "period",
    "trace",
    "multipliers",
    "stability",
    "state0",
    "digits",
)
STRINGS = ("E_str", "period_str", "trace_str", "state0_str")


def _protocol(res):
    for k in PROTOCOL + STRINGS:
        assert hasattr(res, k), k
    assert res.stability in ("stable", "unstable", "marginal")
    mu = res.multipliers
    assert len(mu) == 4 and abs(mu[2] * mu[3] - 1) < 1e-9
    assert abs((mu[2] + mu[3]).real - (float(res.trace) - 2)) < 1e-9 * max(
        1, abs(res.trace)
    )
    d = res.to_dict()
    text = json.dumps(d, allow_nan=False)  # never nan/inf in JSON
    assert json.loads(text)["label"] == res.label


@pytest.mark.parametrize(
    "label,E",
    [
        ("pendulum", 3.9),
        ("pendulum", 4.5),
        ("R", 5.0),
        ("LG", 4.2),
        ("LD", 4.2),
        ("IS^l_2", 4.0),
        ("ISl1", 4.1),
        ("PD^b", 8.9),
    ],
)
def test_orbit_protocol(label, E):
    _protocol(rotorlib.orbit(label, E))


def test_orbit_digits_are_one_knob():
    o = rotorlib.orbit("pendulum", "3.9", digits=30)
    assert o.digits >= 29 and len(re.sub(r"[^0-9]", "", o.period_str)) >= o.digits
    o64 = rotorlib.orbit("pendulum", 3.9)
    assert o64.digits == 15 and abs(float(o.trace_str) - o64.trace) < 1e-12
    d = o.to_dict()
    assert isinstance(d["E"], float) and isinstance(d["period"], float)
    assert isinstance(d["period_str"], str)  # digits beyond float64 as decimal strings
    assert "period_str" not in o64.to_dict()  # float64: numbers only


@pytest.mark.parametrize(
    "call,match",
    [
        (lambda: rotorlib.orbit("bogus", 3.0), "unknown orbit label"),
        (
            lambda: rotorlib.orbit("pendulum", 3.0, digits=0),
            "digits must be an integer",
        ),
        (lambda: rotorlib.orbit("pendulum", -1.0), "E"),
        (lambda: rotorlib.orbit("CG", 6.0), "fold"),
        (lambda: rotorlib.family("IS^l_1", (3.99, 3.9)), "lo < hi"),
        (lambda: rotorlib.family("CG", (5.0, float("inf"))), "two finite energies"),
        (lambda: rotorlib.family("CZ1", (float("nan"), 5.0)), "two finite energies"),
        (lambda: rotorlib.family("pendulumX", (3.9, 3.99)), "unknown family label"),
        (lambda: rotorlib.transition("XYl1"), "label"),
    ],
)
def test_bad_input_is_a_value_error(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_family_stays_inside_its_range():
    b = rotorlib.family("IS^l_1", (4.0, 4.2))
    assert len(b.members) >= 3
    assert all(4.0 <= float(m.E) <= 4.2 for m in b.members)
    assert b.reason
    for m in b.members:
        _protocol(m)


def test_transition_protocol():
    tr = rotorlib.transition("IS^l_2", digits=20)
    _protocol(tr)
    assert tr.kind == "IS" and tr.stability == "marginal"
    assert abs(float(tr.E_str) - tr.E) < 1e-15 and len(tr.E_str.replace(".", "")) >= 20


def test_census_orbits_are_periodic_orbits():
    a = rotorlib.census(4.3, 6.0)
    assert a.orbits and all(isinstance(o, rotorlib.PeriodicOrbit) for o in a.orbits)
    for o in a.orbits:
        _protocol(o)
        assert o.period <= 6.0 and math.isclose(o.E, 4.3)


def test_census_to_dict():
    """``Atlas.to_dict()``: the census as JSON (strict: no nan), each orbit as the
    ``orbit`` command prints it, the labels the registry gave (``CG`` at 4.3)."""
    a = rotorlib.census(4.3, 6.0)
    d = a.to_dict()
    assert json.loads(json.dumps(d, allow_nan=False)) == d
    assert (d["E"], d["t_max"], d["grid"]) == (4.3, 6.0, a.grid)
    assert d["orbits"] == [json.loads(json.dumps(o.to_dict())) for o in a.orbits]
    assert [r["label"] for r in d["orbits"]][:2] == ["pendulum", "CG"]
    assert d["orbits"][1]["choreography"]["sixth"]


def test_readme_ten_lines_is_the_example_file():
    readme = (ROOT / "README.md").read_text()
    block = re.search(
        r"## Python in 10 lines.*?```python\n(.*?)```", readme, re.S
    ).group(1)
    code = (ROOT / "examples" / "ten_lines.py").read_text()
    assert block == code
    assert (
        len([ln for ln in code.splitlines() if ln.strip()]) <= 11
    )  # import + 10 lines


def test_ten_lines_run():
    r = subprocess.run(
        [sys.executable, str(ROOT / "examples" / "ten_lines.py")],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert r.returncode == 0, r.stderr[-2000:]
    assert len(r.stdout.splitlines()) == 6


def test_five_tasks_checks_pass():
    pytest.importorskip("heyoka")
    r = subprocess.run(
        [sys.executable, str(ROOT / "examples" / "five_tasks.py")],
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-2000:]
    assert "all checks passed" in r.stdout
