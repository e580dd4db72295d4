"""Monodromy of pendula and breathers against independent references.

The reference (tests/conftest.py) is the textbook route — nonlinear flow plus
4x4 variational equations — integrated by heyoka at 256 or 512 bits from a
state and period computed with mpmath. Issue 2 requires agreement to 1e-10
at E = 1, 3.9, 5, 100, at log|E-4| = -30, -60, -100 in both phases, and for
breathers at E = 4.6, 9, 20. We demand 1e-12.
"""

import math

import mpmath as mp
import numpy as np
import pytest
from conftest import requires_heyoka, textbook_reference

from rotorlib.core.closed_forms import breather, pendulum
from rotorlib.orbits.floquet import (
    _monodromy,
    monodromy,
    textbook_monodromy,
    trace_monodromy,
    variational_monodromy,
)

CASES = (
    [("pendulum-E", E, "") for E in (1.0, 3.9, 5.0, 100.0)]
    + [("pendulum-log", x, ph) for x in (-30.0, -60.0, -100.0) for ph in ("lib", "rot")]
    + [("breather", E, "R") for E in (4.6, 9.0, 20.0)]
)


def _orbit(kind, value, ph):
    if kind == "pendulum-E":
        return pendulum(E=value)
    if kind == "pendulum-log":
        return pendulum(log_abs_dE=value, phase=ph)
    return breather(value, ph)


@requires_heyoka
@pytest.mark.parametrize("kind,value,ph", CASES)
def test_trace_against_textbook_multiprecision(kind, value, ph):
    # the textbook route loses ~2 log10(1/|E-4|) digits (entries ~1/eps, each amplified ~1/eps): keep 40 more
    depth = -value / math.log(10) if kind == "pendulum-log" else 0.0
    bits = max(256, int(math.ceil((2 * depth + 40) * 3.33 / 64)) * 64)
    ref, closure = textbook_reference(kind, value, ph, bits)
    assert closure < 1e-30  # the closed-form period and state are right
    orb = _orbit(kind, value, ph)
    M = monodromy(orb)
    scale = max(1.0, abs(float(ref)))
    assert abs(M.trace - float(ref)) < 1e-12 * scale, (M.trace, ref)
    M30 = monodromy(orb, digits=30)  # real128 tier: 28+ digits
    with mp.workdps(40):
        assert abs(mp.mpf(M30.trace_str) - ref) < mp.mpf(10) ** -27 * scale
    assert M30.precision == "real128" and M.precision == "float64"


@pytest.mark.parametrize("E", [1.0, 3.0, 3.9, 5.0, 9.0, 100.0])
def test_block_matrix_equals_textbook_float64(E):
    """Full 4x4 (both blocks, incl. the closed-form longitudinal block) vs scipy textbook at moderate E."""
    o = pendulum(E)
    M = monodromy(o).in_alpha_state_order()
    V = variational_monodromy(o.state0, o.period, rtol=1e-13)
    assert np.max(np.abs(M - V.matrix) / np.maximum(1, np.abs(V.matrix))) < 1e-9
    assert V.closure < 1e-10


@pytest.mark.parametrize(
    "E,fam", [(3.0, "LG"), (4.3, "LD"), (4.3, "LG"), (9.0, "R"), (20.0, "R")]
)
def test_breather_blocks_equal_textbook(E, fam):
    o = breather(E, fam)
    M = monodromy(o)
    V = variational_monodromy(o.state0, o.period, rtol=1e-13)
    Ma = M.in_alpha_state_order()
    assert np.max(np.abs(Ma - V.matrix) / np.maximum(1, np.abs(V.matrix))) < 1e-8
    assert abs(np.trace(M.longitudinal) - 2) == 0.0


def test_longitudinal_block_is_parabolic_and_transverse_symplectic():
    for kw in (
        dict(E=2.0),
        dict(log_abs_dE=-50, phase="lib"),
        dict(log_abs_dE=-50, phase="rot"),
    ):
        M = monodromy(pendulum(**kw))
        assert (
            M.longitudinal[0, 0] == 1
            and M.longitudinal[1, 1] == 1
            and M.longitudinal[1, 0] == 0
        )
        assert abs(np.linalg.det(M.transverse) - 1) < 1e-12
        assert M.residual < 1e-14


def test_numerics_md_table_deep_libration():
    """book/numerical_notes.md: true tr M = 3.99999868, 4.00002111, 4.00005659 at log(4-E) = -10.1183, -21.0012, -27.5529."""
    for x, ref in (
        (-10.1183, 3.99999868),
        (-21.0012, 4.00002111),
        (-27.5529, 4.00005659),
    ):
        t = trace_monodromy(pendulum(log_abs_dE=x, phase="lib"))
        assert abs(t - ref) < 5e-9


def test_textbook_method_fails_near_separatrix():
    """The scipy textbook route at rtol 1e-12 is off by >1e3 at log(4-E) = -21 (book/numerical_notes.md); ours is not."""
    o = pendulum(log_abs_dE=-21.0012, phase="lib")
    V = variational_monodromy(o.state0, o.period, rtol=1e-12)
    t = trace_monodromy(o)
    assert abs(V.trace - t) > 1e3 and abs(t - 4.00002111) < 1e-8


def test_small_energy_limit():
    """E -> 0: transverse frequency sqrt(3) over the period 2 pi/sqrt(3): tr M -> 4 (linear limit)."""
    for E in (0.0, 1e-12, 1e-6):
        M = monodromy(pendulum(E))
        assert abs(M.trace - 4.0) < 1e-9 + 10 * E
        assert abs(M.period - 2 * math.pi / math.sqrt(3)) < 1e-6


def test_multipliers():
    M = monodromy(pendulum(5.0))  # unstable
    mu = M.multipliers
    assert abs(mu[0] * mu[1] - 1) < 1e-13 and not M.stable
    M = monodromy(pendulum(1.0))  # stable
    assert abs(abs(M.multipliers[0]) - 1) < 1e-13 and M.stable


def test_mpmath_backend_independent_integrator():
    """mpmath's Taylor integrator (no heyoka) reproduces the real128 value at E = 5."""
    o = pendulum(5.0)
    a = _monodromy(o, 20, "mpmath")
    b = monodromy(o)
    assert abs(float(a.trace_str) - b.trace) < 1e-12
    assert a.backend == "mpmath"


def test_bad_precision_requests():
    o = pendulum(1.0)
    with pytest.raises(ValueError):
        monodromy(o, digits=0)
    with pytest.raises(ValueError):
        _monodromy(o, 30, "scipy")
    with pytest.raises(ValueError):
        _monodromy(o, None, "fortran")
    with pytest.raises(TypeError):  # one precision argument: digits
        monodromy(o, backend="scipy")


def test_every_route_returns_one_monodromy_with_digits():
    """The block route, the variational route (float64 scipy, heyoka tiers) and the
    textbook reference return one type; ``digits`` is their one precision argument."""
    import mpmath as mp

    from rotorlib.orbits.floquet import Monodromy

    o = pendulum(E=3.9)
    block = monodromy(o, digits=30)
    var64 = variational_monodromy(o.state0, o.period)
    with mp.workdps(40):
        s0 = ["0", "0", "0", mp.nstr(mp.sqrt(mp.mpf("15.6") / 3), 40)]
        per = mp.nstr(o.closed_form(40)["period"], 40)
    var30 = variational_monodromy(s0, per, digits=30)
    tb = textbook_monodromy(o, digits=40)
    for M in (block, var64, var30, tb):
        assert type(M) is Monodromy and M.stability == "stable"
    assert (var30.precision, tb.precision) == ("real128", "mp160")
    assert var64.basis == ("a1", "a2", "p1", "p2") and var64.transverse is None
    assert np.allclose(
        var64.in_alpha_state_order(), block.in_alpha_state_order(), atol=1e-9
    )
    with mp.workdps(40):
        ref = mp.mpf(block.trace_str)
        assert abs(mp.mpf(var30.trace_str) - ref) < mp.mpf("1e-28")
        assert abs(mp.mpf(tb.trace_str) - ref) < mp.mpf("1e-28")
    assert var30.closure < 1e-25 and var64.closure < 1e-9 and var64.steps > 0
    with pytest.raises(TypeError):  # the integrator follows digits
        variational_monodromy(o.state0, o.period, method="heyoka")
    with pytest.raises(TypeError):
        textbook_monodromy(o, bits=256)
