"""Fit of the B-P parameters: chirps (deterministic), recovery over seeds, errors, bad input."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest
from scipy import signal
from scipy.integrate import cumulative_trapezoid
from scipy.optimize import least_squares

from stepframe.errors import InputError
from stepframe.stochastic import fit
from stepframe.stochastic.envelope import default_envelope
from stepframe.stochastic.features import record_features, smooth
from stepframe.stochastic.fit import fit_model
from stepframe.stochastic.model import GroundMotionModel
from stepframe.stochastic.spectra import evolutionary_spectrum
from stepframe.stochastic.synthetic import synthetic_motions

SETS = {
    "paper-site": GroundMotionModel.from_hz(7.43, 3.12, 1.11, 0.096, 0.655, 5.0, 20.0),
    "stiff": GroundMotionModel.from_hz(10, 4, 1.5, 0.2, 0.4, t_max_s=8.0, t_dur_s=25.0),
    "soft": GroundMotionModel.from_hz(5, 2.5, 0.8, 0.3, 0.3, t_max_s=4.0, t_dur_s=15.0),
}


def _chirp(model: GroundMotionModel, dt: float = 0.005) -> np.ndarray:
    t = np.arange(0, 45, dt)
    phase = cumulative_trapezoid(model.omega_g(t), t, initial=0)
    return np.asarray(default_envelope(t, model.t_max_s, model.t_dur_s) * np.cos(phase))


def _relative_errors(fitted: GroundMotionModel, true: GroundMotionModel) -> np.ndarray:
    keys = ("omega_p_rad_s", "omega_s_rad_s", "omega_r_rad_s", "xi_p", "xi_r")
    return np.array([getattr(fitted, k) / getattr(true, k) - 1 for k in keys])


@pytest.mark.parametrize("name", list(SETS))
@pytest.mark.parametrize(
    "frequency", ["zero-crossing", "ridge", "moment", "wavelet-ridge", "multiwindow"]
)
def test_chirp_following_eq_6_10_is_recovered(name: str, frequency: str) -> None:
    true = SETS[name]
    features = record_features(_chirp(true), 0.005, frequency=frequency)  # type: ignore[arg-type]
    result = fit_model(features)
    fitted = result.model
    err = np.abs(_relative_errors(fitted, true)[:3])
    assert np.all(err < 0.05), err
    assert result.fit_quality < 0.02  # ω_g(t) follows eq. 6.10: RMS misfit under 2 %
    if frequency == "zero-crossing":  # exact in expectation: what it achieves
        assert np.all(err < 0.012), err
        assert result.fit_quality < 0.008  # measured 0.0009-0.0057
    assert features.t_max_s == pytest.approx(true.t_max_s, rel=0.015)


@pytest.mark.parametrize("name", list(SETS))
def test_recovery_over_20_seeds(name: str) -> None:
    """Median relative errors over 20 realisations (full study: docs/stochastic-features.md)."""
    true = SETS[name]
    _, acc = synthetic_motions(true, duration_s=45.0, dt_s=0.01, n_realisations=20, seed=2024)
    errors, stderrs, t_max, t_max_se = [], [], [], []
    for x in acc:
        result = fit_model(record_features(x, 0.01, t0="start"))  # origin known: no pre-event
        errors.append(_relative_errors(result.model, true))
        stderrs.append(result.stderr["omega_s_rad_s"])
        t_max.append(result.model.t_max_s)
        t_max_se.append(result.stderr["t_max_s"])
    median = np.median(np.abs(errors), axis=0)
    assert median[1] <= 0.15, median  # the targets ...
    assert median[0] <= 0.30 and median[2] <= 0.30, median
    assert median[1] <= 0.11 and median[0] <= 0.17, median  # ... and what the estimator achieves
    # Standard errors describe the scatter over seeds (within a factor of 2.5).
    spread = np.std(np.array(errors)[:, 1]) * true.omega_s_rad_s
    assert 0.4 < float(np.median(stderrs)) / spread < 2.5
    # t_max (envelope fit): unbiased within 8 %, its standard error describes the scatter.
    assert float(np.median(t_max)) == pytest.approx(true.t_max_s, rel=0.08)
    assert 0.4 < float(np.median(t_max_se)) / float(np.std(t_max)) < 2.5


def test_bootstrap_errors_and_to_dict() -> None:
    true = SETS["paper-site"]
    _, acc = synthetic_motions(true, duration_s=40.0, dt_s=0.01, seed=9)
    result = fit_model(record_features(acc[0], 0.01), bootstrap=30, seed=1)
    assert result.bootstrap is not None and result.bootstrap.shape == (30, 5)
    out = result.to_dict()
    for key in ("omega_p_rad_s", "omega_s_rad_s", "omega_r_rad_s", "xi_p", "xi_r"):
        assert out[f"{key}_stderr"] > 0
        assert 0 < out[f"{key}_bootstrap_stderr"] < out[key]
    assert out["alpha_reading"] == "eq-6-11"
    assert 0 <= out["fit_quality"] < 0.5
    assert np.all(result.bootstrap[:, 0] >= result.bootstrap[:, 1])  # ω_p ≥ ω_s in every refit


def test_corner_frequency_of_a_high_passed_motion() -> None:
    """ω_c of ω⁴/(ω² + ω_c²)² (critically damped 2nd-order high-pass) applied to synthetics.

    The estimate is documented as biased low (-40 to -50 %): assert that range and that it
    follows the true corner.
    """
    true = GroundMotionModel.from_hz(5, 2.5, 1.5, 0.4, 0.5, t_max_s=5.0, t_dur_s=20.0)
    dt = 0.01
    _, acc = synthetic_motions(true, duration_s=60.0, dt_s=dt, n_realisations=4, seed=3)
    medians = []
    for wc in (2.0, 4.0):
        b, a = signal.bilinear([1.0, 0.0, 0.0], [1.0, 2 * wc, wc**2], fs=1 / dt)
        estimates = []
        for x in acc:
            y = signal.lfilter(b, a, x)
            spectrum = evolutionary_spectrum(y, dt, window_s=8.0)
            result = fit_model(record_features(y, dt), fit_corner=True, spectrum=spectrum)
            assert result.model.omega_c_rad_s is not None
            assert result.stderr["omega_c_rad_s"] > 0
            estimates.append(result.model.omega_c_rad_s)
        medians.append(float(np.median(estimates)))
        assert 0.4 * wc < medians[-1] < 1.05 * wc
    assert medians[1] > 1.5 * medians[0]


def test_corner_not_resolved_is_flagged() -> None:
    true = SETS["stiff"]
    _, acc = synthetic_motions(true, duration_s=20.0, dt_s=0.01, seed=4)
    spectrum = evolutionary_spectrum(acc[0], 0.01, window_s=0.5)  # bins 12.6 rad/s apart
    result = fit_model(record_features(acc[0], 0.01), fit_corner=True, spectrum=spectrum)
    assert result.model.omega_c_rad_s is None and "omega_c_not_fitted" in result.flags


def test_alpha_reading_paper_ends_the_ramp_at_t_max() -> None:
    features = record_features(_chirp(SETS["stiff"]), 0.005)
    result = fit_model(features, alpha_reading="paper")
    assert result.model.alpha_reading == "paper"
    assert float(result.model.alpha_g(features.t_max_s)) == pytest.approx(
        result.model.omega_r_rad_s * result.model.xi_r
    )


def test_bad_input() -> None:
    t = np.arange(0, 6, 0.01)
    short = np.sin(2 * math.pi * 3 * t) * np.exp(-((t - 3) ** 2) * 40)  # a blip: few frames
    features = record_features(short, 0.01)
    with pytest.raises(InputError, match="frames"):
        fit_model(features, fit_threshold=0.999)
    with pytest.raises(InputError, match="bootstrap"):
        fit_model(features, bootstrap=-1)
    offset = np.sin(2 * math.pi * 2 * t) * np.exp(-(((t - 3) / 1.5) ** 2)) + 5.0  # no crossings
    with pytest.raises(InputError, match="baseline offset"):
        fit_model(record_features(offset, 0.01))
    with pytest.raises(InputError, match="spectrum"):
        fit_model(features, fit_corner=True)


def _omega_problem(seed: int) -> tuple[fit._OmegaResiduals, tuple[Any, ...]]:
    """The eq. 6.10 fit's residuals on one synthetic paper-site record, and _fit_omega's args."""
    _, acc = synthetic_motions(SETS["paper-site"], duration_s=45.0, dt_s=0.01, seed=seed)
    features = record_features(acc[0], 0.01)
    tau = np.maximum(features.time_s - features.t0_s, 0.0)
    obs = features.omega_g_rad_s
    use = (features.time_s >= features.t0_s) & np.isfinite(obs)
    obs = np.where(np.isfinite(obs), obs, 0.0)
    weight = np.ones_like(obs)
    args = (tau, obs, weight, use, features.omega_kernel, features.t_max_s)
    start = fit._start(obs, tau, use, features.t_max_s)
    p_bounds = (0.5 * float(obs[use].min()), 1.5 * float(obs[use].max()))
    return fit._OmegaResiduals(*args), (*args, start, p_bounds)


@pytest.mark.parametrize("theta", [(60.0, 0.4, 0.3), (35.0, 0.05, 0.6), (80.0, 0.95, 0.02)])
def test_analytic_jacobian_matches_central_differences(theta: tuple[float, float, float]) -> None:
    residuals, _ = _omega_problem(3)
    point = np.array(theta)
    analytic = residuals.jacobian(point)
    steps = 1e-6 * np.array([point[0], 1.0, 1.0])
    numeric = np.column_stack(
        [
            (residuals.residual(point + h) - residuals.residual(point - h)) / (2 * h[k])
            for k, h in enumerate(np.diag(steps))
        ]
    )
    scale = np.max(np.abs(numeric), axis=0)
    assert np.max(np.abs(analytic - numeric) / scale) < 1e-6


def test_smoothed_model_is_the_smoothed_curve() -> None:
    """m = r + (p - r)·S(ρ^x) (S linear, S(1) = 1) equals smoothing eq. 6.10 itself."""
    residuals, args = _omega_problem(4)
    tau, _, _, use, kernel, t_max = args[:6]
    theta = np.array([55.0, 0.3, 0.25])
    direct = smooth(fit._omega_curve(theta, tau, t_max), kernel)[use]
    np.testing.assert_allclose(residuals.model(theta), direct, rtol=1e-13)


@pytest.mark.parametrize("seed", [5, 6, 7])
def test_fit_reaches_the_bounded_least_squares_minimum(seed: int) -> None:
    """The LM fit ends at a cost no higher than scipy's trf with a finite-difference Jacobian
    (the former method, run here as the reference) on the same bounded problem."""
    residuals, args = _omega_problem(seed)
    theta, jacobian, residual = fit._fit_omega(*args)
    start, p_bounds = args[6], args[7]
    lower = [p_bounds[0], 0.0, fit._MIN_R_OVER_P]
    upper = [p_bounds[1], 1.0, 1.0 - 1e-9]
    reference = least_squares(
        residuals.residual, np.clip(start, np.add(lower, 1e-9), np.subtract(upper, 1e-9)),
        bounds=(lower, upper), x_scale=[float(start[0]), 0.1, 0.1], method="trf",
        jac="3-point", ftol=1e-10, xtol=1e-10,
    )  # fmt: skip
    assert residual @ residual <= (reference.fun @ reference.fun) * (1 + 1e-6)
    np.testing.assert_allclose(theta, reference.x, rtol=1e-3)
    np.testing.assert_allclose(jacobian, residuals.jacobian(theta))
