"""The band of global chaos (paper §9): sections, microcanonical sampling, FTLEs, executor path."""

from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from rotorlib.core.system import energy_alpha, energy_phi, potential_alpha, rhs_phi
from rotorlib.paper import chaos as ch


def test_shell_sampling_is_microcanonical():
    E = 4.7
    x = ch.sample_energy_shell(E, 20000, seed=3)
    assert np.max(np.abs(energy_alpha(x) - E)) < 1e-12
    # independent: uniform points in a phase-space box, kept when |H - E| < w (a thin shell)
    rng = np.random.default_rng(5)
    pm1, pm2 = 2 * np.sqrt(E), 2 * np.sqrt(E / 3)
    box = rng.uniform(
        [0, 0, -pm1, -pm2], [np.pi, 2 * np.pi, pm1, pm2], size=(1_500_000, 4)
    )
    shell = box[np.abs(energy_alpha(box) - E) < 0.02]
    assert len(shell) > 5000
    Va, Vb = (
        potential_alpha(x[:, 0], x[:, 1]),
        potential_alpha(shell[:, 0], shell[:, 1]),
    )
    err = np.sqrt(Va.var() / len(Va) + Vb.var() / len(Vb))
    assert abs(Va.mean() - Vb.mean()) < 4 * err + 0.01
    # the momentum angle: p1^2/4 / K is cos^2 of a uniform angle, mean 1/2
    K = E - Va
    assert abs(np.mean(x[:, 2] ** 2 / 4 / K) - 0.5) < 0.01


def test_section_hits_match_scipy():
    E = 5.4
    x0 = ch.section_initial_conditions(E, 3, 2)[1]
    assert abs(energy_phi(x0) - E) < 1e-12 and 2 * x0[2] - x0[3] > 0
    h = ch._section_one((x0, 3, 1e3))
    assert np.all(
        np.abs(np.mod(h[:, 0] + np.pi, 2 * np.pi) - np.pi) < 1e-10
    )  # phi1 = 0 mod 2 pi
    assert np.all(2 * h[:, 2] - h[:, 3] > 0)

    def ev(t, y):
        return np.sin(0.5 * y[0])

    sol = solve_ivp(
        rhs_phi, (1e-6, 60.0), x0, method="DOP853", rtol=1e-12, atol=1e-13, events=ev
    )
    hits = sol.y_events[0]
    hits = hits[2 * hits[:, 2] - hits[:, 3] > 0][:3]
    assert np.allclose(hits[:, 1:], h[:, 1:], atol=1e-7)


def test_ftle_regular_vs_chaotic():
    lam_reg = ch.ftle(ch.sample_energy_shell(0.5, 5, seed=1), T=300.0)
    lam_cha = ch.ftle(ch.sample_energy_shell(5.45, 5, seed=1), T=300.0)
    assert np.all(lam_reg < 0.05) and np.all(lam_cha > 0.1)


def test_pmap_process_pool_matches_serial():
    kw = dict(N=6, T=40.0, threshold=0.05, seed=2, chunk=4)
    serial = ch.chaotic_fraction([5.45, 2.0], **kw)
    with ProcessPoolExecutor(max_workers=2) as ex:
        pooled = ch.chaotic_fraction([5.45, 2.0], executor=ex, **kw)
    for a, b in zip(serial.ftles, pooled.ftles):
        assert np.array_equal(a, b)
    assert np.array_equal(serial.fraction, pooled.fraction)
    with ProcessPoolExecutor(max_workers=2) as ex:
        s = ch.poincare_section(5.4, n_phi=2, n_p=2, n_hits=5, executor=ex)
    assert len(s.phi2) == 4 and all(len(p) == 5 for p in s.phi2)


def test_bad_input():
    with pytest.raises(ValueError):
        ch.sample_energy_shell(-1.0, 10)
    with pytest.raises(ValueError):
        ch.sample_energy_shell(5.0, 0)
    with pytest.raises(ValueError):
        ch.chaotic_fraction([5.0], threshold=0.0)
    with pytest.raises(ValueError):
        ch.poincare_section(float("nan"))


def test_amplitude_branch_passes_the_fold():
    b = ch.amplitude_branch("PD^r_2", 4.54)
    exits = [p for p in b.special_points if p.kind in ("IS", "PD")]
    assert b.stop == "event" and exits[0].kind == "IS"
    assert (
        abs(float(exits[0].member.E) - 4.55) < 0.005
    )  # paper: PD^r_2 unstable from ~4.55
    # the member at the exit closes under scipy and has tr M = 4 (independent 4x4 route)
    from rotorlib.orbits.floquet import variational_monodromy

    m = exits[0].member
    v = variational_monodromy(
        np.array(b.state(m), float), b.problem.factor * float(m.t1)
    )
    assert v.closure < 1e-8 and abs(v.trace - 4.0) < 1e-5


def test_band_families():
    """Rotational daughters followed with the engine: IS^r_2 stays below the band and becomes
    unstable at the energy of chapter 08 (paper: 4.02); PD^r_1 is in the band and unstable there;
    bad input raises."""
    r2, p1 = ch.band_families(["IS^r_2", "PD^r_1"], dE_stop=1.7)
    assert (
        not r2.reaches_band
        and r2.E_max < 4.5
        and r2.exit_level == 0.0
        and r2.stays_unstable
    )
    assert abs(r2.exit_E - 4.02) < 0.01
    assert p1.reaches_band and len(p1.band_trace) > 0 and np.all(p1.band_trace > 4)
    with pytest.raises(ValueError):
        ch.band_families(["IS^l_1"])


@pytest.mark.slow
def test_pdr6_real128_exit():
    """PD^r_6 (born 2.5e-10 above E = 4), real128 throughout: tr M enters the window, stays >= 0
    and leaves through 4 at E - 4 = 1.55e-9 (the member there has tr M = 4); float64 tr M of the
    same members is round-off."""
    from rotorlib.core.flow import monodromy_matrix

    (r,) = ch.band_families(["PD^r_6"], dE_stop=3e-9)
    b = r.branch
    assert b.tier.name == "real128" and b.trace[0] < 4 and np.all(b.trace >= 0)
    assert (
        r.exit_level == 4.0
        and r.stays_unstable
        and abs(r.exit_E - 4 - 1.5513e-9) < 2e-13
    )
    assert np.all(np.abs(np.diff(b.t1)) < 1e-3)
    m = b.members[-1]
    tr64 = monodromy_matrix(
        [float(v) for v in b.state(m)], b.problem.factor * float(m.t1)
    )[2]
    assert abs(tr64 - float(m.trace)) > 1.0  # float64 tr M is round-off
