"""Jacobi functions and complete integrals near m -> 1, against mpmath."""

import mpmath as mp
import numpy as np
import pytest

from rotorlib.core.elliptic import dK_dm, ellipk_m1, jacobi_am, jacobi_sncndn


@pytest.mark.parametrize("m1", [0.9, 0.5, 0.3, 1e-3, 1e-12, 1e-20, 1e-40])
def test_sncndn_against_mpmath(m1):
    """sn to 1e-15 absolute; cn, dn to a relative error set by the conditioning of u near K."""
    K = ellipk_m1(m1)
    with mp.workdps(80):
        mm = 1 - mp.mpf(m1)
        for f in np.linspace(0.03, 3.97, 23):
            u = f * K
            s, c, d = jacobi_sncndn(u, 1 - m1, m1)
            S, C, D = (mp.ellipfun(k, u, m=mm) for k in ("sn", "cn", "dn"))
            # conditioning: ulp(u) * |d/du| relative to the value
            cond = (
                4e-16 * max(1.0, u) * (1 + float(abs(S * D / C)) if C != 0 else 1e300)
            )
            assert abs(s - float(S)) < 2e-15 * max(1.0, u)
            assert abs(c - float(C)) <= max(1e-15, cond) * float(abs(C)) + 1e-300
            assert abs(d - float(D)) <= max(
                1e-15, 4e-16 * max(1.0, u) * float(abs(S * C / D)) * 8
            ) * float(D)


def test_sncndn_deep_relative_accuracy_of_cn_mid_interval():
    """The AGM's textbook form loses cn mid-interval as m -> 1; ours keeps 1e-15 relative."""
    m1 = 1e-40
    K = ellipk_m1(m1)
    with mp.workdps(80):
        for f in (0.2, 0.3, 0.45, 0.5):
            u = f * K
            _, c, d = jacobi_sncndn(u, 1 - m1, m1)
            C = mp.ellipfun("cn", u, m=1 - mp.mpf(m1))
            assert abs(c / float(C) - 1) < 1e-14


def test_negative_parameter():
    for m in (-3.0, -0.5):
        u = np.array([0.3, 1.7, 5.0])
        s, c, d = jacobi_sncndn(u, m)
        for i, x in enumerate(u):
            assert abs(s[i] - float(mp.re(mp.ellipfun("sn", x, m=m)))) < 1e-14
            assert abs(d[i] - float(mp.re(mp.ellipfun("dn", x, m=m)))) < 1e-14


def test_K_and_derivative():
    for m1 in (0.99, 0.5, 1e-5, 1e-100):
        with mp.workdps(130):
            assert abs(ellipk_m1(m1) / float(mp.ellipk(1 - mp.mpf(m1))) - 1) < 1e-15
    for m in (1e-5, 0.3, 0.9, 1 - 1e-9):
        with mp.workdps(40):
            ref = mp.diff(lambda x: mp.ellipk(x), m)
        assert abs(dK_dm(m, 1 - m) / float(ref) - 1) < 1e-6


def test_am_continuous_and_monotone():
    m1 = 1e-8
    K = ellipk_m1(m1)
    u = np.linspace(-9 * K, 9 * K, 20001)
    a = jacobi_am(u, 1 - m1, m1)
    assert np.all(np.diff(a) > 0)
    assert abs(jacobi_am(4 * K, 1 - m1, m1) - 2 * np.pi) < 1e-12


def test_bad_parameter():
    with pytest.raises(ValueError):
        jacobi_sncndn(0.1, 1.0, 0.0)
    with pytest.raises(ValueError):
        jacobi_sncndn(0.1, 0.5, float("nan"))


@pytest.mark.parametrize("m1", ["1e-300", "1e-40", "0.3", "1", "2.5"])
def test_mp_ellipk_m1(m1):
    """K from the complementary parameter by the AGM, against mpmath's ellipk(1 - m1) evaluated with
    enough guard digits that forming 1 - m1 costs nothing."""
    from rotorlib.core.elliptic import mp_ellipk_m1

    with mp.workdps(40):
        k = mp_ellipk_m1(mp.mpf(m1))
    with mp.workdps(400):
        ref = mp.ellipk(1 - mp.mpf(m1))
    assert abs(k / ref - 1) < mp.mpf("1e-38")


def test_mp_ellipk_m1_far_beyond_float64():
    """m1 = 1e-4343 (log|E - 4| = -10000): K = log(4/sqrt(m1)) + O(m1 log m1), to 40 digits."""
    from rotorlib.core.elliptic import mp_ellipk_m1

    with mp.workdps(40):
        m1 = mp.mpf("1e-4343")
        assert abs(mp_ellipk_m1(m1) / mp.log(4 / mp.sqrt(m1)) - 1) < mp.mpf("1e-38")


@pytest.mark.parametrize(
    "m", ["0", "1e-20", "-0.05", "0.3", "0.49999", "0.5", "0.9", "0.999999"]
)
def test_mp_dK_dm(m):
    """Both branches (series below |m| = 1/2, closed form above) against numerical differentiation at 80 digits."""
    from rotorlib.core.elliptic import mp_dK_dm

    with mp.workdps(40):
        d = mp_dK_dm(mp.mpf(m), 1 - mp.mpf(m))
    with mp.workdps(80):
        ref = mp.diff(mp.ellipk, mp.mpf(m))
    assert abs(d / ref - 1) < mp.mpf("1e-37")


def test_mp_dK_dm_near_separatrix():
    """m1 = 1e-400: dK/dm = (E - m1 K)/(2 m m1) ~ 1/(2 m1) (float64 would overflow)."""
    from rotorlib.core.elliptic import mp_dK_dm

    with mp.workdps(40):
        m1 = mp.mpf("1e-400")
        assert abs(mp_dK_dm(1 - m1, m1) * 2 * m1 - 1) < mp.mpf("1e-38")
