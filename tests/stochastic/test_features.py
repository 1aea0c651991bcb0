"""Record features: Vanmarcke's q by quadrature, tones, stationary eq. 6.12, envelopes, picks."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import integrate
from scipy.integrate import cumulative_trapezoid

from stepframe.errors import InputError
from stepframe.stochastic.envelope import default_envelope
from stepframe.stochastic.features import clipped_plateaus, record_features, vanmarcke_q
from stepframe.stochastic.flags import implausible
from stepframe.stochastic.model import GroundMotionModel
from stepframe.stochastic.spectra import evolutionary_spectrum, mean_square
from stepframe.stochastic.synthetic import synthetic_motions

FLAT = GroundMotionModel(20.0001, 20.0, 19.9999, 0.2, 0.2, t_max_s=1.0, t_dur_s=2.0)


@pytest.mark.parametrize("zeta", [0.02, 0.1, 0.3, 0.6, 0.9])
def test_vanmarcke_q_against_quadrature(zeta: float) -> None:
    wg = 7.0
    s = lambda w: 1.0 / ((w**2 - wg**2) ** 2 + 4 * zeta**2 * wg**2 * w**2)  # noqa: E731
    lam = [
        integrate.quad(lambda w, k=k: w**k * s(w), 0, wg, limit=500)[0]
        + integrate.quad(lambda w, k=k: w**k * s(w), wg, np.inf, limit=500)[0]
        for k in (0, 1, 2)
    ]
    assert lam[2] / lam[0] == pytest.approx(wg**2, rel=1e-7)  # E[ẏ²]/E[y²] = ω_g²
    q = math.sqrt(1 - lam[1] ** 2 / (lam[0] * lam[2]))
    assert float(vanmarcke_q(np.array([zeta]))[0]) == pytest.approx(q, rel=1e-6)


@pytest.mark.parametrize(
    "frequency", ["zero-crossing", "moment", "ridge", "wavelet-ridge", "multiwindow"]
)
def test_pure_tone_returns_its_frequency(frequency: str) -> None:
    t = np.arange(0, 30, 0.005)
    x = 0.3 * np.sin(2 * math.pi * 3.3 * t + 0.4)
    f = record_features(x, 0.005, frequency=frequency)  # type: ignore[arg-type]
    inner = f.omega_g_rad_s[20:-20]
    tol = 0.005 if frequency in ("ridge", "wavelet-ridge") else 1e-3
    np.testing.assert_allclose(inner, 2 * math.pi * 3.3, rtol=tol)
    assert float(np.median(f.alpha_g_rad_s[20:-20])) < 0.05  # a line has no bandwidth


def _band_limited_omega(model: GroundMotionModel, omega_max: float) -> float:
    """√(λ2/λ0) of eq. 6.12 cut at ``omega_max``: what a sampled record's crossings can see."""
    lam0 = integrate.quad(lambda w: model.psd(w, 0.0), 0, omega_max, limit=400)[0]
    lam2 = integrate.quad(lambda w: w**2 * model.psd(w, 0.0), 0, omega_max, limit=400)[0]
    return math.sqrt(lam2 / lam0)


def test_stationary_eq_6_12_zero_crossings_and_bandwidth() -> None:
    npts, dt, n = 30001, 0.01, 6
    _, acc = synthetic_motions(
        FLAT, duration_s=300.0, dt_s=dt, seed=21, envelope=np.ones(npts), n_realisations=n
    )
    inner = slice(20, -20)
    zc, alpha, moment = [], [], []
    for x in acc:
        f = record_features(x, dt, window_s=4.0)
        zc.append(np.mean(f.omega_g_rad_s[inner]))
        alpha.append(np.mean(f.alpha_g_rad_s[inner]))
        m = record_features(x, dt, window_s=4.0, frequency="moment")
        moment.append(np.mean(m.omega_g_rad_s[inner]))
    # Crossings faster than the sampling are lost: the expectation is ω_g less the part of
    # λ2 beyond Nyquist (0.8 % here); 6 × 300 s give about 0.5 % statistical error.
    expected = _band_limited_omega(FLAT, math.pi / dt)
    assert expected == pytest.approx(
        20.0 * math.sqrt(1 - 4 * 4.0 / (math.pi * math.pi / dt)), rel=2e-3
    )
    assert float(np.mean(zc)) == pytest.approx(expected, rel=0.015)
    assert float(np.mean(moment)) == pytest.approx(expected, rel=0.015)
    assert float(np.mean(alpha)) == pytest.approx(4.0, rel=0.15)


def test_intensity_is_the_stft_mean_square_and_envelope_times() -> None:
    model = GroundMotionModel.from_hz(5, 2.5, 0.8, 0.3, 0.3, t_max_s=6.0, t_dur_s=18.0, t0_s=2.0)
    t = np.arange(0, 40, 0.005)
    phase = cumulative_trapezoid(model.omega_g(t), t, initial=0)
    envelope = default_envelope(t, model.t_max_s, model.t_dur_s, 3.0, t0_s=model.t0_s)
    x = envelope * np.cos(phase)
    f = record_features(x, 0.005, t0="start")
    spec = evolutionary_spectrum(x, 0.005)
    np.testing.assert_allclose(f.intensity**2, mean_square(spec), rtol=1e-12)
    # A chirp under an envelope: I_g = envelope/√2; times from the record start (t0 = 0).
    assert f.peak_intensity == pytest.approx(3.0 / math.sqrt(2), rel=0.01)
    assert f.t_max_s == pytest.approx(2.0 + 6.0, rel=0.02)
    assert f.t_dur_s == pytest.approx(2.0 + 18.0, rel=0.01)
    assert f.t0_s == 0.0 and f.flags == ()


def test_p_pick_sets_the_time_origin() -> None:
    rng = np.random.default_rng(4)
    dt = 0.01
    t = np.arange(0, 40, dt)
    noise = 1e-4 * rng.standard_normal(t.size)
    model = GroundMotionModel.from_hz(8, 3, 1, 0.2, 0.3, t_max_s=4.0, t_dur_s=12.0, t0_s=6.0)
    _, acc = synthetic_motions(model, duration_s=t[-1] + dt / 2, dt_s=dt, seed=3)
    f = record_features(acc[0] + noise, dt, t0="p-pick")
    assert f.p_onset_s is not None
    assert f.p_onset_s == pytest.approx(6.0, abs=0.6)
    assert f.t0_s == f.p_onset_s
    assert f.s_arrival_s is not None and f.p_onset_s < f.s_arrival_s < 6.0 + 8.0
    assert f.t_max_s == pytest.approx(4.0, abs=1.5)


def test_degraded_results_are_flagged() -> None:
    t = np.arange(0, 20, 0.01)
    rising = np.sin(2 * math.pi * 2.0 * t) * (t / 20.0)  # still growing at the end
    assert "duration_truncated" in record_features(rising, 0.01).flags
    near_nyquist = np.sin(2 * math.pi * 40.0 * t) * np.hanning(t.size)  # 40 Hz at dt 0.01
    assert "band_limited" in record_features(near_nyquist, 0.01).flags


def test_a_clipped_record_is_flagged_and_not_plausible() -> None:
    """A synthetic eq. 6.12 motion clipped at 1/14 of its peak (an instrument at full scale)
    fitted ξ_p = 0.71 for 0.096 with no flag; the same motion unclipped, or with only its one
    largest sample repeated (a tie, not a plateau), is not flagged."""
    model = GroundMotionModel.from_hz(7.43, 3.12, 1.11, 0.096, 0.655, t_max_s=5.0, t_dur_s=20.0)
    _, acc = synthetic_motions(model, duration_s=40.0, dt_s=0.005, seed=3)
    motion = acc[0]
    limit = float(np.max(np.abs(motion))) / 14
    clipped = record_features(np.clip(motion, -limit, limit), 0.005)
    assert "record_clipped" in clipped.flags
    assert implausible(clipped.flags) == ["record_clipped"]
    assert "record_clipped" not in record_features(motion, 0.005).flags
    tie = motion.copy()
    k = int(np.argmax(tie))
    tie[k + 1] = tie[k]  # two equal samples at the maximum: rounding, not clipping
    assert clipped_plateaus(tie) == 0
    plateau = motion.copy()
    plateau[k - 1 : k + 2] = plateau[k]  # one plateau of 3: one cycle, not yet a clipped record
    assert clipped_plateaus(plateau) == 1
    assert "record_clipped" not in record_features(plateau, 0.005).flags


def test_a_window_long_against_t_max_is_flagged_without_a_t_max_error() -> None:
    """A 30-s window on t_max = 5 s gave t_max ≈ 6.0 ± 0.37 s (truth within 2 SE in 37 % of
    synthetic records) with no flag; at twice t_max and below the SE is kept."""
    model = GroundMotionModel.from_hz(7.43, 3.12, 1.11, 0.096, 0.655, t_max_s=5.0, t_dur_s=20.0)
    _, acc = synthetic_motions(model, duration_s=40.0, dt_s=0.005, seed=5)
    long = record_features(acc[0], 0.005, window_s=30.0, t0="start")
    assert "window_long" in long.flags and long.t_max_stderr_s is None
    assert implausible(long.flags) == []  # a caveat: the numbers are estimates, biased late
    usual = record_features(acc[0], 0.005, window_s=2.0, t0="start")
    assert "window_long" not in usual.flags
    assert usual.t_max_stderr_s is not None and usual.t_max_stderr_s > 0


def test_bad_input() -> None:
    x = np.sin(np.arange(0, 20, 0.01))
    with pytest.raises(InputError, match="Nyquist"):
        record_features(x, 0.01, omega_max_rad_s=400.0)
    with pytest.raises(InputError, match="frequency"):
        record_features(x, 0.01, frequency="hilbert")  # type: ignore[arg-type]
    with pytest.raises(InputError, match="t0"):
        record_features(x, 0.01, t0="s-pick")  # type: ignore[arg-type]
    with pytest.raises(InputError, match="threshold"):
        record_features(x, 0.01, threshold=1.5)
    with pytest.raises(InputError, match="NaN"):
        record_features(np.r_[x, np.nan], 0.01)


def test_each_estimator_states_its_floor() -> None:
    """The lowest ω_g each estimator resolves on a 60-s record (docs/stochastic-features.md):
    one cycle per 2-s window for the STFT and crossing estimators, the wavelet ridge's lowest
    band (six cycles in the record) inside its cone of influence, three cycles in a window
    inside the record for multiwindow."""
    dt = 0.01
    t = np.arange(0, 60 + dt / 2, dt)
    x = np.sin(2 * math.pi * 2.0 * t) * np.hanning(t.size)
    for name in ("zero-crossing", "ridge", "moment"):
        f = record_features(x, dt, frequency=name)  # type: ignore[arg-type]
        np.testing.assert_allclose(f.resolution_floor(), math.pi)
    ridge = record_features(x, dt, frequency="wavelet-ridge")
    assert ridge.usable_floor_rad_s == pytest.approx(12 * math.pi / (t.size * dt), rel=1e-9)
    one_second = int(np.argmin(np.abs(ridge.time_s - 1.0)))  # √2·6/1 s = 8.49 rad/s: the cone
    assert float(ridge.resolution_floor()[one_second]) == pytest.approx(6 * math.sqrt(2))
    window = record_features(x, dt, frequency="multiwindow")
    assert window.usable_floor_rad_s == pytest.approx(6 * math.pi / 60.0, rel=1e-9)
    assert float(window.to_dataset()["omega_g_floor"].min()) == window.usable_floor_rad_s


@pytest.mark.parametrize("a", [0.6, 2.0, 7.5])
def test_gamma_envelope_jacobian_matches_central_differences(a: float) -> None:
    from stepframe.stochastic.features import _GammaEnvelope

    time_s = np.linspace(0.0, 40.0, 201)
    intensity = 3.0 * np.exp(-(((time_s - 12.0) / 6.0) ** 2)) + 0.1
    envelope = _GammaEnvelope(time_s, intensity)
    x = np.array([2.3, 8.0, 2.5, a])
    analytic = envelope.jacobian(x)
    numeric = np.empty_like(analytic)
    for k in range(4):
        step = np.zeros(4)
        step[k] = 1e-6 * max(1.0, abs(x[k]))
        numeric[:, k] = (envelope.residual(x + step) - envelope.residual(x - step)) / (2 * step[k])
    after = time_s > x[0] + 0.05  # the kink at the onset has no two-sided derivative
    np.testing.assert_allclose(analytic[after], numeric[after], rtol=1e-5, atol=1e-7)
    assert np.all(analytic[time_s < x[0]] == 0.0)


def test_envelope_peak_time_recovers_a_known_gamma_envelope_and_the_finite_difference_fit() -> None:
    """A noisy gamma envelope with peak at onset + τ_p = 3 + 9 s: the fit finds 12 s within a
    tenth of a second, and the same minimum as the trust-region fit with finite differences
    (the former solver, an independent recomputation) to a millisecond."""
    from scipy.optimize import least_squares

    from stepframe.stochastic.features import _GammaEnvelope, peak_time_by_envelope

    rng = np.random.default_rng(7)
    time_s = np.arange(0.0, 60.0, 0.1)
    u = np.maximum(time_s - 3.0, 0.0) / 9.0
    with np.errstate(divide="ignore"):
        shape = np.where(u > 0, np.exp(2.5 * (np.log(np.where(u > 0, u, 1.0)) + 1.0 - u)), 0.0)
    intensity = 4.0 * shape * (1.0 + 0.15 * rng.standard_normal(time_s.size)) + 0.01
    found = peak_time_by_envelope(time_s, intensity, 2.0)
    assert found is not None
    t_max, se = found
    assert abs(t_max - 12.0) < 0.1
    assert 0.0 < se < 1.0
    # the frames the fit uses: a window around those at ≥ 5 % of the peak (ENVELOPE_SPAN)
    above = np.flatnonzero(intensity >= 0.05 * intensity.max())
    span = (time_s >= time_s[above[0]] - 2.0) & (time_s <= time_s[above[-1]] + 2.0)
    time_s, intensity = time_s[span], intensity[span]
    stride = max(1, time_s.size // 200)
    envelope = _GammaEnvelope(time_s[::stride], intensity[::stride])
    peak = float(intensity.max())
    t_peak = float(time_s[np.argmax(intensity)])
    rising = np.flatnonzero(intensity[: np.argmax(intensity) + 1] < 0.05 * peak)
    onset0 = min(float(time_s[rising[-1]]), t_peak - 0.5)
    former = least_squares(
        envelope.residual,
        [onset0, t_peak - onset0, peak, 2.0],
        bounds=([time_s[0] - 60.0, 1e-3, 0.0, 0.05], [t_peak, time_s[-1] + 60.0, 10 * peak, 50.0]),
        method="trf",
        ftol=1e-6,
        xtol=1e-6,
    )
    assert abs(former.x[0] + former.x[1] - t_max) < 1e-3


def test_envelope_fit_does_not_depend_on_the_quiet_record_around_the_motion() -> None:
    """A 40-s synthetic record with its own quiet coda continued to 400 s gave t_max 2.74 ±
    0.16 s for 4.56 ± 0.93 s (the ~200 frames kept were 2 s apart, and the coda's near-zero
    residuals shrank s²); appending silence must change neither t_max nor its SE."""
    model = GroundMotionModel.from_hz(7.43, 3.12, 1.11, 0.096, 0.655, t_max_s=5.0, t_dur_s=20.0)
    _, acc = synthetic_motions(model, duration_s=40.0, dt_s=0.005, seed=3)
    short = record_features(acc[0], 0.005, t0="start")
    padded = record_features(np.concatenate([acc[0], np.zeros(72_000)]), 0.005, t0="start")
    assert short.t_max_stderr_s is not None and padded.t_max_stderr_s is not None
    assert padded.t_max_s == pytest.approx(short.t_max_s, abs=1e-6)
    assert padded.t_max_stderr_s == pytest.approx(short.t_max_stderr_s, rel=1e-6)
    assert short.t_max_s == pytest.approx(5.0, abs=2 * short.t_max_stderr_s)


def test_smooth_at_is_the_kernel_average_inside_the_series() -> None:
    """smooth_at at chosen indices (the ends included) is the gather of each index's
    neighbours, zero outside the series, times the kernel over the kernel's mass inside, bit
    for bit, and smooth's full convolution to rounding."""
    from stepframe.stochastic.features import kernel_mass, smooth, smooth_at
    from stepframe.stochastic.transforms import hann_kernel

    rng = np.random.default_rng(3)
    values = rng.normal(size=500)
    kernel = hann_kernel(0.6, 0.01)  # 61 samples, wider than the first and last indices' room
    at = np.array([0, 1, 29, 30, 31, 250, 469, 470, 498, 499])
    half = kernel.size // 2
    where = at[:, None] + np.arange(-half, half + 1)[None, :]
    inside = (where >= 0) & (where < values.size)
    gathered = np.where(inside, values[np.clip(where, 0, values.size - 1)], 0.0)
    expected = (gathered @ kernel) / (inside.astype(np.float64) @ kernel)
    found = smooth_at(values, kernel, at)
    assert found.tobytes() == expected.tobytes()
    np.testing.assert_allclose(found, smooth(values, kernel)[at], rtol=1e-12, atol=1e-15)
    # smooth with the kernel's mass kept by the caller (the fit's way) is smooth, bit for bit
    kept = smooth(values, kernel, kernel_mass(values.size, kernel))
    assert kept.tobytes() == smooth(values, kernel).tobytes()
    assert kernel_mass(values.size, kernel)[250] == pytest.approx(1.0, rel=1e-14)  # unit sum


def test_spectral_moments_are_the_trapezoid_rule() -> None:
    """λ0, λ1, λ2 by one product are np.trapezoid of S·ω^k to rounding, and exact where the
    trapezoid is: a flat S = 1 on ω from 2 to 10 has λ0 = 8 and λ1 = (10² - 2²)/2 = 48."""
    from stepframe.stochastic.features import spectral_moments

    omega = np.linspace(2.0, 10.0, 33)
    rng = np.random.default_rng(5)
    psd = rng.random((7, omega.size))
    lam = spectral_moments(omega, psd)
    for k in range(3):
        np.testing.assert_allclose(lam[k], np.trapezoid(psd * omega**k, omega), rtol=1e-13)
    flat = spectral_moments(omega, np.ones((1, omega.size)))
    assert flat[0][0] == pytest.approx(8.0, rel=1e-15)
    assert flat[1][0] == pytest.approx(48.0, rel=1e-15)
