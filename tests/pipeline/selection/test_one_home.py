"""One computation, one home: each computation the selection shares with another part of the
package is checked against an independent computation (a closed form, a second method or a
published value), not merely against its other caller."""

from __future__ import annotations

import math

import numpy as np

from stepframe.records.spectra import response_spectrum
from stepframe.records.units import STANDARD_GRAVITY_M_S2
from stepframe.structure.frame import PortalFrame

# The paper's Example 3 frame (test_parts.py's), with ξ_1 = 5 %.
FRAME = PortalFrame(6.4581, 0.6445, 1.1884, 1.268, 0.1387, 0.05, 0.0, 0.19, 0.95)


def _record() -> tuple[np.ndarray, float]:
    """A decaying two-tone motion [m/s²], 20 s at 100 Hz."""
    dt = 0.01
    t = np.arange(2000) * dt
    acc = np.exp(-0.2 * t) * (2.0 * np.sin(2 * np.pi * 1.1 * t) + np.sin(2 * np.pi * 0.37 * t))
    return acc, dt


def test_standard_gravity_is_the_cgpm_value_everywhere_the_selection_converts_g() -> None:
    """9.80665 m/s² (CGPM 1901, exact); the selection's target in g, its PSA(T_1) in g and the
    peers' S_a in g all divide by it (they had three private copies, and the IDA a literal)."""
    from stepframe.pipeline.selection.options import SelectionOptions
    from stepframe.pipeline.selection.peers import PeerPeriods, record_peers
    from stepframe.pipeline.selection.spectral import target_spectrum

    assert STANDARD_GRAVITY_M_S2 == 9.80665
    target = target_spectrum(SelectionOptions(target_s_ds_g=1.0, target_s_d1_g=0.6))
    assert target is not None
    # ASCE 7-22 two-period: S_a = S_D1/T between T_s and T_L, in m/s² with standard gravity
    assert math.isclose(target.sa_m_s2(2.0), 0.3 * 9.80665, rel_tol=1e-12)
    acc, dt = _record()
    period_1 = 2 * math.pi / FRAME.omega_1_rad_s
    peers = record_peers(acc, dt, PeerPeriods(period_1, 3.0))
    psa_g = response_spectrum(acc, dt, [period_1], 0.05).psa_m_s2[0] / 9.80665
    assert math.isclose(peers["sa_t1_g"], psa_g, rel_tol=1e-9)


def test_equal_intensity_puts_the_scaled_records_linear_peak_at_r_times_the_onset() -> None:
    """The equal-intensity scale (one home, intensity.equal_intensity_scales, which the ranking
    and the confirmation both call) checked on the scaled record itself: its own SD(T_1, ξ_1),
    computed again by the Nigam-Jennings spectrum, times P_1 is r·x_c, and its PSA(T_1, ξ_1) is
    r times the onset PSA ω_1²x_c/P_1 (6.4581²·0.19/1.1884 m/s² = 0.6800 g, by hand)."""
    from stepframe.pipeline.selection.intensity import (
        RankingIntensity,
        equal_intensity_scales,
        onset_psa_t1_g,
    )

    onset_g = 6.4581**2 * 0.19 / 1.1884 / 9.80665
    assert math.isclose(onset_psa_t1_g(FRAME), onset_g, rel_tol=1e-12)
    assert math.isclose(onset_g, 0.67995, abs_tol=5e-5)
    acc, dt = _record()
    period_1 = 2 * math.pi / FRAME.omega_1_rad_s
    sd = response_spectrum(acc, dt, [period_1], FRAME.xi_1).sd_m
    for ratio in (0.5, 1.0, 2.5):
        scale = float(equal_intensity_scales(sd, FRAME, ratio)[0])
        scaled = response_spectrum(scale * acc, dt, [period_1], FRAME.xi_1)
        assert math.isclose(FRAME.p_1 * scaled.sd_m[0], ratio * FRAME.x_c_m, rel_tol=1e-9)
        assert math.isclose(scaled.psa_g[0], ratio * onset_g, rel_tol=1e-9)
        ranking = RankingIntensity("equal-psa-t1", "none", ratio, None, onset_g, ())
        base = ranking.base_scales(FRAME, sd, np.array([np.nan]), np.ones(1))
        assert base[0] == scale


def test_band_levels_lie_on_the_period_amplitude_law_at_log_spaced_frequencies() -> None:
    """The band's levels (one home, band.band_levels, read by the physics scores' frame_band and
    the substitute structure): the forward law T(A_k) (quarter periods in closed form, not the
    bisection that found A_k) gives back 2π/ω_k, ω_k log-spaced from ω_1 to ω(0.8 x*), and the
    ends are x_c and A_max."""
    from stepframe.pipeline.selection.band import frame_band
    from stepframe.pipeline.selection.substitute import substitute_levels
    from stepframe.structure.period_amplitude import period_amplitude

    band = frame_band(FRAME, n_levels=7)
    amplitudes, omegas = band.level_amplitudes_m, band.level_omegas_rad_s
    assert amplitudes[0] == FRAME.x_c_m and amplitudes[-1] == 0.8 * FRAME.x_star_m
    ratios = omegas[1:] / omegas[:-1]
    np.testing.assert_allclose(ratios, ratios[0], rtol=1e-12)
    assert math.isclose(omegas[0], 6.4581, rel_tol=1e-12)
    period_low = period_amplitude(FRAME, 0.8 * FRAME.x_star_m)
    assert math.isclose(omegas[-1], 2 * math.pi / period_low, rel_tol=1e-12)
    inner = period_amplitude(FRAME, amplitudes[1:-1])
    np.testing.assert_allclose(inner, 2 * math.pi / omegas[1:-1], rtol=1e-9)
    levels = substitute_levels(band, 7)
    np.testing.assert_array_equal(levels.amplitudes_m, amplitudes)
    np.testing.assert_allclose(levels.periods_s, 2 * math.pi / omegas, rtol=1e-9)


def test_fiv3_integrates_the_filtered_record_as_an_independent_trapezoid_does() -> None:
    """FIV3's window integral now reads the record velocity of records.integration (it had its
    own cumulative trapezoid): checked against FIV3 written out with scipy's
    cumulative_trapezoid, and the velocity of a linear-in-time acceleration against its closed
    form (exact for a record linear between samples)."""
    from scipy.integrate import cumulative_trapezoid
    from scipy.signal import butter, find_peaks, lfilter

    from stepframe.pipeline.selection.peers import FIV_ALPHA, FIV_BETA, fiv3_m_s
    from stepframe.records.integration import velocity_m_s

    t = np.arange(101) * 0.01
    np.testing.assert_allclose(velocity_m_s(3.0 * t, 0.01), 1.5 * t**2, rtol=1e-12, atol=1e-15)
    acc, dt = _record()
    period = 1.2
    b, a = butter(2, FIV_BETA / period, fs=1.0 / dt)
    velocity = cumulative_trapezoid(lfilter(b, a, acc), dx=dt, initial=0.0)
    time = np.arange(acc.size) * dt
    starts = time[time + FIV_ALPHA * period <= time[-1]]
    fiv = np.interp(starts + FIV_ALPHA * period, time, velocity) - velocity[: starts.size]
    peaks = np.sort(fiv[find_peaks(fiv)[0]])[::-1][:3]
    troughs = np.sort(fiv[find_peaks(-fiv)[0]])[:3]
    expected = max(np.sum(peaks), abs(np.sum(troughs)))
    assert math.isclose(fiv3_m_s(acc, dt, period), expected, rel_tol=1e-10)
    assert math.isnan(fiv3_m_s(acc[:5], dt, period))  # shorter than the window


def test_the_selections_psa_is_the_step_responses_overshoot() -> None:
    """PSA = ω²SD has one home (records.spectra.pseudo_acceleration_m_s2: the response spectrum,
    RotD, the peers and the selection's PSA(T_1) each wrote it out): a step a0 in ground
    acceleration gives PSA = a0·(1 + exp(-πζ/√(1-ζ²))) at every period (the step response's
    first overshoot), read through the peers' S_a(T_1), Sa_avg and the home itself."""
    from stepframe.pipeline.selection.peers import PeerPeriods, record_peers
    from stepframe.records.spectra import peak_displacements_m, pseudo_acceleration_m_s2

    a0, dt = 2.5, 0.0005
    acc = np.full(40001, a0)
    overshoot_g = a0 * (1 + math.exp(-math.pi * 0.05 / math.sqrt(1 - 0.05**2))) / 9.80665
    peers = record_peers(acc, dt, PeerPeriods(0.5, 1.5))
    assert math.isclose(peers["sa_t1_g"], overshoot_g, rel_tol=3e-4)
    assert math.isclose(peers["sa_avg_g"], overshoot_g, rel_tol=3e-4)
    periods = np.array([0.5, 1.0, 2.0])
    sd = peak_displacements_m(acc, dt, periods, 0.05)
    psa = pseudo_acceleration_m_s2(periods, sd) / 9.80665
    np.testing.assert_allclose(psa, overshoot_g, rtol=3e-4)
    assert math.isclose(float(pseudo_acceleration_m_s2(2 * math.pi, 0.25)), 0.25, rel_tol=1e-15)
