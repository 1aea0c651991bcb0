"""Amplification: eqs. 6.13-6.19 for the paper's site, response amplification, adjusted δ*."""

from __future__ import annotations

import math

import numpy as np
import pytest

from stepframe.errors import InputError
from stepframe.stochastic.amplification import (
    adjusted_fixed_point,
    approx_eq_6_19_first,
    approx_eq_6_19_last,
    cross_fitted_peaks,
    response_amplification,
    spectral_ratio_eq_6_13,
    spectral_ratio_eq_6_18,
    stationary_rms,
)
from stepframe.stochastic.mean_square import FrameDriven
from stepframe.stochastic.model import GroundMotionModel


def _site(reading: str = "paper", **kwargs: float) -> GroundMotionModel:
    times = {"t_max_s": 5.0, "t_dur_s": 20.0} | kwargs
    return GroundMotionModel.from_hz(
        7.43,
        3.12,
        1.11,
        0.096,
        0.655,
        alpha_reading=reading,
        **times,  # type: ignore[arg-type]
    )


def test_printed_5_67_is_the_last_approximation_of_eq_6_19() -> None:
    site = _site()
    assert approx_eq_6_19_last(site) == pytest.approx((7.43 / 3.12) ** 2, rel=1e-14)
    assert round(approx_eq_6_19_last(site), 2) == 5.67
    first = (7.43 * 0.096) / (1.11 * 0.655) * (7.43 / 3.12) ** 2
    assert approx_eq_6_19_first(site) == pytest.approx(first, rel=1e-14)
    assert approx_eq_6_19_first(site) == pytest.approx(5.5637, abs=1e-4)


def test_eq_6_18_at_f_p_is_the_first_approximation_under_the_paper_reading() -> None:
    paper, printed = _site("paper"), _site("eq-6-11")
    wp = paper.omega_p_rad_s
    assert float(spectral_ratio_eq_6_18(paper, wp)) == pytest.approx(
        approx_eq_6_19_first(paper), rel=1e-13
    )
    # eq. 6.11 as printed: α_g(t_max) = α_p + (α_r - α_p) t_max/t_dur
    alpha_p, alpha_r = wp * 0.096, 2 * math.pi * 1.11 * 0.655
    alpha_t_max = alpha_p + (alpha_r - alpha_p) * 5.0 / 20.0
    expected = approx_eq_6_19_last(printed) * alpha_p / alpha_t_max
    assert float(spectral_ratio_eq_6_18(printed, wp)) == pytest.approx(expected, rel=1e-13)
    assert float(spectral_ratio_eq_6_18(printed, wp)) == pytest.approx(5.6439, abs=1e-4)


@pytest.mark.parametrize("reading", ["paper", "eq-6-11"])
def test_eq_6_18_follows_from_eq_6_13_with_the_closed_form_r_g(reading: str) -> None:
    site = _site(reading)
    f0 = np.geomspace(0.1, 10.0, 41)
    np.testing.assert_allclose(
        spectral_ratio_eq_6_13(site, 2 * np.pi * f0, xi0=0.0),
        spectral_ratio_eq_6_18(site, 2 * np.pi * f0),
        rtol=1e-12,
    )


def test_eq_6_18_is_dimensionless_and_not_monotone() -> None:
    site = _site()
    in_hz = GroundMotionModel(7.43, 3.12, 1.11, 0.096, 0.655, 5.0, 20.0, alpha_reading="paper")
    f0 = np.geomspace(0.1, 10.0, 200)
    ratio = spectral_ratio_eq_6_18(site, 2 * np.pi * f0)
    np.testing.assert_allclose(spectral_ratio_eq_6_18(in_hz, f0), ratio, rtol=1e-12)
    slope = np.diff(ratio)
    assert np.any(slope > 0) and np.any(slope < 0)
    # ω_0 → 0 gives 0 (the (ω_0/ω_s)² factor), large ω_0 grows like ω_0⁶
    assert ratio[0] < 0.05 < 100 < ratio[-1]


def test_response_amplification_is_one_without_frequency_shift() -> None:
    """ω_p = ω_s: ω_g is constant until t_max, so tracking is the fixed oscillator until then;
    with ω_s = ω_r too little changes later, and the ratio is 1 to the accuracy of the run."""
    steady = GroundMotionModel.from_hz(5.0, 5.0, 4.999, 0.1, 0.1, t_max_s=5.0, t_dur_s=20.0)
    result = response_amplification(steady, 2 * np.pi * np.array([2.0, 5.0]), 0.05)
    np.testing.assert_allclose(result.vs_fixed, 1.0, rtol=1e-3)
    assert result.omega_path == "tracking" and result.alpha_reading == "eq-6-11"


def test_frequencies_beside_a_frame_are_an_error_not_ignored() -> None:
    """With a frame, ω_0 is 2π/T(0): frequencies given too were silently dropped, and the
    result was the frame's whatever ω_0 asked for."""
    frame = FrameDriven(lambda amplitude: 1.0)
    grid = np.linspace(0.0, 40.0, 401)
    with pytest.raises(InputError, match="omega_0_rad_s and frame both given"):
        response_amplification(_site(), [2 * np.pi * 5.0], 0.05, frame=frame, time_s=grid)
    alone = response_amplification(_site(), None, 0.05, frame=frame, time_s=grid)
    assert alone.omega_0_rad_s[0] == pytest.approx(2 * np.pi)
    np.testing.assert_allclose(alone.vs_fixed, 1.0, rtol=1e-10)  # a constant period


def test_slow_envelope_reaches_the_stationary_rms() -> None:
    """Constant ω_g, α_g and a very slow envelope: peak RMS → stationary RMS at the peak."""
    steady = GroundMotionModel(20.0, 20.0, 10.0, 0.1, 0.2, t_max_s=200.0, t_dur_s=700.0)
    grid = np.linspace(0.0, 300.0, 4001)
    w0 = 2 * np.pi * np.array([1.0, 3.0])
    result = response_amplification(steady, w0, 0.05, time_s=grid, peak_intensity=2.0)
    np.testing.assert_allclose(result.vs_stationary, 1.0, rtol=2e-3)
    np.testing.assert_allclose(
        result.stationary_rms_m, stationary_rms(steady, w0, 0.05, 2.0), rtol=1e-14
    )


def test_monte_carlo_confirms_the_covariance_amplification() -> None:
    site = _site("eq-6-11")
    w0 = 2 * np.pi * np.array([2.0, 7.43])
    grid = np.linspace(0.0, 16.0, 321)
    cov = response_amplification(site, w0, 0.05, time_s=grid)
    mc = response_amplification(
        site, w0, 0.05, time_s=grid, method="monte-carlo", n_realisations=400, seed=7
    )
    assert mc.vs_fixed_band is not None and mc.vs_stationary_band is not None
    for i in range(2):
        assert mc.vs_fixed_band[i, 0] <= cov.vs_fixed[i] <= mc.vs_fixed_band[i, 1]
        assert mc.vs_stationary_band[i, 0] <= cov.vs_stationary[i] <= mc.vs_stationary_band[i, 1]
    # at ω_0 = ω_p tracking keeps the oscillator on ω_g(t): far above the fixed oscillator
    assert cov.vs_fixed[1] > 5
    summary = mc.to_dict()
    assert summary["n_realisations"] == 400 and summary["method"] == "monte-carlo"


def test_cross_fitting_removes_the_max_of_noise_bias() -> None:
    """A flat true curve (E[x²] = 1 at every time): the plain max is biased, cross-fitting not."""
    rng = np.random.default_rng(0)
    samples = rng.standard_normal((200, 100, 50)) ** 2  # 200 trials, N = 100, 50 times
    plain = samples.mean(axis=1).max(axis=1)
    fitted, values = cross_fitted_peaks(samples)
    assert values.shape == (200, 100)
    assert plain.mean() > 1.2  # about two standard errors high
    assert fitted.mean() == pytest.approx(1.0, abs=0.03)  # se of the mean of 200: 0.01


def test_adjusted_fixed_point_scales_with_the_root_of_a_mean_square_ratio() -> None:
    site = _site()
    delta = 0.12
    last = adjusted_fixed_point(delta, site)
    assert last == pytest.approx(delta * (7.43 / 3.12), rel=1e-14)
    first = adjusted_fixed_point(delta, site, factor="eq-6-19-first")
    assert first == pytest.approx(delta * math.sqrt(approx_eq_6_19_first(site)), rel=1e-14)
    at_fp = adjusted_fixed_point(delta, site, factor="eq-6-18", omega_0_rad_s=site.omega_p_rad_s)
    assert at_fp == pytest.approx(first, rel=1e-12)
    w0 = 2 * math.pi * 2.0
    response = adjusted_fixed_point(
        delta, site, factor="response-vs-fixed", omega_0_rad_s=w0, xi0=0.05
    )
    ratio = response_amplification(site, [w0], 0.05).vs_fixed[0]
    assert response == pytest.approx(delta * ratio, rel=1e-12)
    with pytest.raises(InputError, match="needs omega_0_rad_s"):
        adjusted_fixed_point(delta, site, factor="eq-6-18")
    # an input the factor does not read is refused, not ignored
    with pytest.raises(InputError, match="does not read omega_0_rad_s or xi0, expected neither"):
        adjusted_fixed_point(delta, site, omega_0_rad_s=2.0, xi0=0.05)
    with pytest.raises(InputError, match="'eq-6-18' does not read xi0, expected only omega_0"):
        adjusted_fixed_point(delta, site, factor="eq-6-18", omega_0_rad_s=2.0, xi0=0.05)
    with pytest.raises(InputError, match="delta_star_m"):
        adjusted_fixed_point(-1.0, site)
    with pytest.raises(InputError, match="factor"):
        adjusted_fixed_point(delta, site, factor="bogus")  # type: ignore[arg-type]
