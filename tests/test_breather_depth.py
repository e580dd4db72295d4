"""Breathers at any depth below/above their separatrix E = 4.5, like pendula at E = 4.

tr M of LG, LD, R grows like |E - 4.5|^-2; we demand relative accuracy: float64
within 1e-10 (measured ~1e-14) at log|E - 4.5| = -20, -40, -200, -340 and,
past the float64 overflow of tr M (~ -350), in ``trace_str``; the 30-digit
tier within 1e-25 (the target is 1e-20). References:

* R: the textbook 4x4 variational equations in 256/384-bit arithmetic from a
  state and period built in mpmath directly from log|E - 4.5|
  (``tests/independent.py``: no BreatherEnergy, no closed-form parameters, no
  Hill reduction) -- this checks the 30-digit tier through an input path it
  does not share;
* LG, LD: float64 against the 30-digit tier (the Hill route at another
  precision).

Before the fix the float64 tr M of R was wrong in every digit by -20 (the
composition divided by a determinant computed with cancellation), and the
30-digit tier read E through float64 (relative error 3.7e-7 at -20).
"""

import json
import math
import subprocess
import sys

import mpmath as mp
import pytest
from independent import textbook_breather_R

from rotorlib.core.closed_forms import breather
from rotorlib.core.energy import breather_energy
from rotorlib.core.precision import heyoka_available
from rotorlib.orbits.floquet import monodromy

needs_heyoka = pytest.mark.skipif(not heyoka_available(), reason="heyoka not installed")


def rel(a, b):
    with mp.workdps(60):
        return float(abs(mp.mpf(a) / mp.mpf(b) - 1))


@needs_heyoka
@pytest.mark.parametrize("x,bits", [("-20", 256), ("-40", 384)])
def test_R_against_independent_textbook(x, bits):
    ref, period, closure = textbook_breather_R(x, bits)
    assert closure < 1e-14  # the reference's own period and state close the orbit
    o = breather(log_abs_dE=x, family="R")
    assert rel(monodromy(o).trace, ref) < 1e-10
    M30 = monodromy(o, digits=30)
    assert M30.precision == "real128"
    assert rel(M30.trace_str, ref) < 1e-25
    assert rel(M30.period_str, period) < 1e-25
    assert rel(monodromy(o).period, period) < 1e-14


@needs_heyoka
def test_cli_R_digits30_against_independent_textbook():
    """``trace breather --log-dE -20 -40 --family R --digits 30``: 20 digits at least (measured 30)."""
    p = subprocess.run(
        [
            sys.executable,
            "-m",
            "rotorlib",
            *"trace breather --log-dE -20 -40 --family R --digits 30 --json".split(),
        ],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert p.returncode == 0, p.stderr
    recs = json.loads(p.stdout)
    for rec, (x, bits) in zip(recs, (("-20", 256), ("-40", 384))):
        ref, period, _ = textbook_breather_R(x, bits)
        assert rec["precision"] == "real128" and rec["breather_family"] == "R"
        assert rel(rec["trace_str"], ref) < 1e-20
        assert rel(rec["period_str"], period) < 1e-20
        with mp.workdps(60):  # E - 4.5 = e^x visible in the decimal E
            assert (
                abs((mp.mpf(rec["E_str"]) - mp.mpf("4.5")) / mp.exp(int(x)) - 1) < 1e-28
            )


@needs_heyoka
@pytest.mark.parametrize("family", ["LG", "LD", "R"])
@pytest.mark.parametrize("x", [-20.0, -40.0, -200.0, -340.0])
def test_float64_relative_at_depth(family, x):
    o = breather(log_abs_dE=x, family=family)
    ref = monodromy(o, digits=30).trace_str
    M = monodromy(o)
    assert math.isfinite(M.trace) and rel(M.trace, ref) < 1e-10
    assert abs(math.log(abs(M.trace)) + 2 * x) < 12  # tr M ~ |E - 4.5|^-2


@needs_heyoka
@pytest.mark.parametrize("family", ["LG", "R"])
@pytest.mark.parametrize("x", [-400.0, -700.0])
def test_float64_past_overflow_of_trace(family, x):
    """tr M ~ e^(-2x) overflows float64 below x ~ -350: ``trace`` is inf, ``trace_str`` keeps 16 digits."""
    o = breather(log_abs_dE=x, family=family)
    M = monodromy(o)
    assert math.isinf(M.trace) and M.stability == "unstable"
    assert rel(M.trace_str, monodromy(o, digits=30).trace_str) < 1e-10


@needs_heyoka
def test_beyond_float64_range_extended_only():
    o = breather(log_abs_dE=-800, family="R")
    with pytest.raises(ValueError, match="float64 range"):
        monodromy(o)
    a = monodromy(o, digits=30).trace_str
    b = monodromy(o, digits=40).trace_str  # heyoka multiprecision
    assert rel(a, b) < 1e-25
    with mp.workdps(30):
        assert abs(mp.log(abs(mp.mpf(a))) - 1600) < 12


@pytest.mark.parametrize("family", ["LG", "LD", "R"])
@pytest.mark.parametrize("x", [-1.0, -40.0, -300.0])
def test_closed_form_parameters_without_cancellation(family, x):
    """m, m1, shape (A^2, D^2, lam^2) and nu in float64 against the textbook formulas at 400 digits
    (there the cancellations of 1 - S, 3 - S, Q + E - 6 cost nothing): one rounding near 4.5. At x = -1
    the float64 E = 4.5 -/+ e^-1 itself carries 1e-16, amplified ~10x through E - 4 or Q - E + 6."""
    tol = 4e-16 if x <= -40 else 1e-14
    p = breather(log_abs_dE=x, family=family).params
    with mp.workdps(400):
        E = mp.mpf(9) / 2 + (1 if family == "R" else -1) * mp.exp(x)
        if family == "R":
            Q = mp.sqrt(E * (E - 4))
            ref = dict(
                m=(Q - E + 6) / (2 * Q),
                m1=(Q + E - 6) / (2 * Q),
                nu=mp.sqrt(Q),
                shape=mp.sqrt(E / (E - 4)),
            )
        else:
            S = mp.sqrt(9 - 2 * E)
            den = (1 + S) * (3 + S)
            ref = dict(
                m=(1 - S) * (3 - S) / den,
                m1=8 * S / den,
                nu=mp.sqrt(den / 2) / 2,
                shape=(3 - S) / (1 + S) if family == "LG" else (1 - S) / (3 + S),
            )
        for key, v in ref.items():
            assert abs(p[key] / v - 1) < tol, key


def test_LG_near_zero_energy_parameters():
    """E = 1e-300: A^2 = (3 - S)/(1 + S) ~ E/6 would be 0 in float64 from S; 2E/den keeps it."""
    p = breather(E="1e-300", family="LG").params
    with mp.workdps(700):
        E = mp.mpf("1e-300")
        S = mp.sqrt(9 - 2 * E)
        assert abs(p["shape"] / ((3 - S) / (1 + S)) - 1) < 4e-16
        assert abs(p["m"] / ((1 - S) * (3 - S) / ((1 + S) * (3 + S))) - 1) < 4e-16


def test_breather_energy_carries_distance():
    en = breather_energy(log_abs_dE="-40", family="R")
    assert en.E == 4.5 and en.eps == math.exp(-40) and en.log_abs_dE == -40.0
    assert en.given == ("log_abs_dE", "-40")
    with mp.workdps(50):
        v = en.mp_values(45)
        assert abs(v["eps"] / mp.exp(-40) - 1) < mp.mpf("1e-44")
        assert abs(v["E"] - 4.5 - mp.exp(-40)) < mp.mpf("1e-44")
    en = breather_energy(E="4.49999999999999999999", family="LD")
    assert en.family == "LD" and en.eps == 1e-20 and en.E == 4.5
    for bad in (
        dict(E="4.5"),
        dict(E="4.50000", family="R"),
        dict(log_abs_dE=-0.5, family="LD"),
        dict(log_abs_dE=2.0, family="LG"),
        dict(E="3.99999999999999999999", family="LD"),
        dict(E="4.5000000000000000000001", family="LG"),
    ):
        with pytest.raises(ValueError):
            breather_energy(**bad)
