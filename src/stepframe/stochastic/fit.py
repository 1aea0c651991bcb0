"""Fit of the Beck-Papadimitriou parameters (ω_p, ω_s, ω_r, ξ_p, ξ_r) to a record's features.

Method (weighted least squares, two steps):

1. ω_p, ω_s, ω_r: eq. 6.10 with the record's t_max and t0 is evaluated on the frame grid and
   smoothed by the same kernel as the ω_g(t) estimate (so the fit compares like with like: a
   smoothed estimate against the smoothed model, which removes the bias of smoothing a convex
   curve), then fitted to the frames after t0 with I_g ≥ ``fit_threshold`` · max I_g (default
   0.02: the late, weak frames carry the information on ω_r) with equal weights on residuals
   scaled by √ω_model (the variance of a crossing count grows like its rate; against relative
   residuals weighted by I_g this halves the ω_r error on synthetics). ``least_squares`` runs
   over ω_p, ρ = (ω_s - ω_r)/(ω_p - ω_r) ∈ [0, 1] and f = ω_r/ω_p ∈ [0.01, 1), so
   ω_p ≥ ω_s ≥ ω_r holds by construction; ω_p stays within [0.5, 1.5] × the measured range of
   ω_g (not an extrapolation to a record start long before the motion); a bound reached is
   flagged (``omega_p_at_bound``, ``omega_s_at_bound``, ``omega_r_at_bound``,
   ``omega_not_decreasing``; meanings in :mod:`stepframe.stochastic.flags`).
2. ξ_p, ξ_r: eq. 6.11 is linear in (ω_p ξ_p, ω_r ξ_r) for a given ramp end, fitted to α_g(t) by
   weighted linear least squares; ξ = α/ω.

Standard errors: from the Jacobian, ``cov = s² (JᵀJ)⁻¹``, inflated by the number of frames per
window (``window_s / hop_s``) because neighbouring frames share one window and are not
independent; the delta method carries them to ξ. ω_s's is then calibrated on synthetics
(:data:`OMEGA_S_SE_CALIBRATION`; t_max's in the features, ``T_MAX_SE_CALIBRATION``).
``bootstrap=N`` adds moving-block bootstrap errors (blocks one window long). ``fit_quality`` is
the weighted RMS relative misfit of ω_g(t) (0 is perfect; 0.1 means 10 %).

Optional source corner ω_c (``fit_corner=True``): the time-averaged STFT spectrum divided by the
time-averaged fitted eq. 6.12 spectrum is fitted by the high-pass ``ω⁴/(ω² + ω_c²)²`` (the modulus
of the second stage of eq. 6.3 applied as a filter on the process, not on ÿ; docs/paper-notes.md)
over 0 < ω ≤ ω_s in log amplitude. It is reported, not used by eq. 6.12. It is biased low
(synthetics filtered with known corners 2, 4, 6 rad/s, 10 records each: medians 1.24, 2.23,
2.94 rad/s, i.e. -40 to -50 %) because the ω_g(t) fit has already absorbed part of the corner's
effect; treat it as an indicative, monotone measure. With fewer than 3 STFT bins up to ω_s it is
not fitted (flag ``omega_c_not_fitted``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from stepframe.core import validation
from stepframe.errors import InputError
from stepframe.stochastic.features import ZETA_MAX, RecordFeatures, kernel_mass, smooth
from stepframe.stochastic.model import AlphaReading, GroundMotionModel

if TYPE_CHECKING:
    import xarray as xr
from stepframe.stochastic.standard_errors import least_squares_covariance

#: Parameter keys of a fit, in output order.
PARAMETERS = ("omega_p_rad_s", "omega_s_rad_s", "omega_r_rad_s", "xi_p", "xi_r")
#: Range of the fitted ξ: from a floor to the largest ζ the α_g estimate reads
#: (:data:`stepframe.stochastic.features.ZETA_MAX`); ξ ≥ 1 (α_g ≥ ω_g, broadband, overdamped
#: ground filter) is valid for eq. 6.12, the synthetic motions and the mean-square methods.
_XI_RANGE = (0.005, ZETA_MAX)
#: Factor on ω_s's Jacobian standard error: ω_s = ω_g(t_max) also carries t_max's error, which
#: the fit takes as known; 1.25 is the 95th percentile of |error|/(2 SE) over 60 synthetic
#: eq. 6.12 records of each of three parameter sets (1.02 at the 90th), so that the truth lies
#: within 2 SE in ≥ 90 % of records (bench/se_coverage.py; docs/stochastic-features.md). The
#: other parameters already cover (90th percentiles 0.4-0.85).
OMEGA_S_SE_CALIBRATION = 1.25
#: Default fraction of max I_g above which frames enter the fit. It is below the duration
#: threshold because the late frames carry the information on ω_r (docs/stochastic-features.md).
DEFAULT_FIT_THRESHOLD = 0.02


@dataclass(frozen=True)
class FitResult:
    """A fitted parameter set with its uncertainties.

    Attributes
    ----------
    model
        The fitted model (t_max, t_dur, t0 from the features).
    stderr
        Standard error of each fitted value (keys of :data:`PARAMETERS`, plus ``omega_c_rad_s``
        when fitted and ``t_max_s`` when t_max came from the envelope fit of the features)
        [units of the value].
    fit_quality
        Weighted RMS relative misfit of ω_g(t) (0 is perfect).
    n_points
        Strong-motion frames used.
    flags
        Degraded results (meanings: :data:`stepframe.stochastic.flags.FLAGS`).
    bootstrap
        Bootstrap samples of (ω_p, ω_s, ω_r, ξ_p, ξ_r), shape (N, 5), or None.
    omega_fit_rad_s
        The smoothed fitted ω_g on the frame grid (what was compared with the data).
    """

    model: GroundMotionModel
    stderr: dict[str, float]
    fit_quality: float
    n_points: int
    flags: tuple[str, ...] = field(default_factory=tuple)
    bootstrap: NDArray[np.float64] | None = None
    omega_fit_rad_s: NDArray[np.float64] | None = None

    def to_dict(self) -> dict[str, Any]:
        """Flat dictionary: parameters, ``<key>_stderr``, fit quality, flags."""
        out: dict[str, Any] = {
            key: getattr(self.model, key) for key in (*PARAMETERS, "t_max_s", "t_dur_s", "t0_s")
        }
        out["fit_quality"] = self.fit_quality
        for key, value in self.stderr.items():
            out[f"{key}_stderr"] = value
        if self.model.omega_c_rad_s is not None:
            out["omega_c_rad_s"] = self.model.omega_c_rad_s
        out["alpha_reading"] = self.model.alpha_reading
        out["n_points"] = self.n_points
        out["flags"] = list(self.flags)
        return out


#: Lower bound of ω_r/ω_p in the fit: keeps ω_r inside two decades of ω_p.
_MIN_R_OVER_P = 0.01


def _psr(theta: NDArray[np.float64]) -> tuple[float, float, float]:
    """(ω_p, ω_s, ω_r) from the fit's parameters θ = (ω_p, ρ, f): ω_r = f ω_p,
    ω_s = ω_r + ρ (ω_p - ω_r); ρ = (ω_s - ω_r)/(ω_p - ω_r) ∈ [0, 1] is eq. 6.10's base."""
    p, rho, f = float(theta[0]), float(theta[1]), float(theta[2])
    r = f * p
    return p, r + rho * (p - r), r


def _psr_jacobian(theta: NDArray[np.float64]) -> NDArray[np.float64]:
    """∂(ω_p, ω_s, ω_r)/∂(ω_p, ρ, f) for the delta method."""
    p, rho, f = float(theta[0]), float(theta[1]), float(theta[2])
    return np.array([[1.0, 0.0, 0.0], [f + rho * (1 - f), p * (1 - f), p * (1 - rho)], [f, 0.0, p]])


def _omega_curve(
    theta: NDArray[np.float64], tau: NDArray[np.float64], t_max_s: float
) -> NDArray[np.float64]:
    """Eq. 6.10 from θ = (ω_p, ρ, f); ρ = 0 (ω_s = ω_r) and ρ = 1 (ω_s = ω_p) are regular."""
    p, rho, f = float(theta[0]), float(theta[1]), float(theta[2])
    r = f * p
    return np.asarray(r + (p - r) * np.power(rho, tau / t_max_s))


#: Floor on ρ in the derivative ∂ρ^x/∂ρ = xρ^(x-1), which diverges at ρ = 0 for 0 < x < 1: a fit
#: that reaches the bound (flagged ``omega_s_at_bound``) keeps a finite slope there, at most
#: about 1e150·ω_p, whose square still fits in a float.
_RHO_FLOOR = 1e-150


class _OmegaResiduals:
    """Residuals of the eq. 6.10 fit and their analytic Jacobian in θ = (ω_p, ρ, f).

    With ω(τ) = r + (p - r)ρ^x, x = τ/t_max, r = fp, and the smoothing S linear with S(1) = 1,
    the smoothed model is m = r + (p - r)·S(ρ^x) and its derivatives are

        ∂m/∂p = f + (1 - f)·S(ρ^x),   ∂m/∂ρ = (1 - f)p·S(xρ^(x-1)),   ∂m/∂f = p(1 - S(ρ^x)).

    The residuals are √w (o - m)/√m on the fitted frames (crossing counts are roughly Poisson:
    variance ∝ rate), whose derivative is -√w (o + m)/(2 m^(3/2)) · ∂m. Two smoothings per
    iteration where a finite-difference Jacobian needs four; S(ρ^x) is kept from the residual
    for the Jacobian at the same θ (the solver asks for both).
    """

    def __init__(
        self,
        tau: NDArray[np.float64],
        obs: NDArray[np.float64],
        weight: NDArray[np.float64],
        use: NDArray[np.bool_],
        kernel: NDArray[np.float64],
        t_max_s: float,
    ) -> None:
        self.x = tau / t_max_s
        self.moving = self.x > 0.0
        self.x_moving = self.x[self.moving]
        self.observed = obs[use]
        self.sw = np.sqrt(weight[use])
        self.use = use
        self.kernel = kernel
        # smooth's denominator, the same at every iteration (a third of smooth's cost)
        self.mass = kernel_mass(self.x.size, kernel)
        self._key: tuple[float, float, float] | None = None
        self._decay = np.empty(0)

    def _smoothed_decay(self, theta: NDArray[np.float64]) -> NDArray[np.float64]:
        """S(ρ^x) on the fitted frames."""
        key = (float(theta[0]), float(theta[1]), float(theta[2]))
        if key != self._key:
            self._decay = smooth(np.power(key[1], self.x), self.kernel, self.mass)[self.use]
            self._key = key
        return self._decay

    def model(self, theta: NDArray[np.float64]) -> NDArray[np.float64]:
        """m(θ), the smoothed eq. 6.10 on the fitted frames [rad/s]."""
        p, f = float(theta[0]), float(theta[2])
        return np.asarray(f * p + (1.0 - f) * p * self._smoothed_decay(theta))

    def residual(self, theta: NDArray[np.float64]) -> NDArray[np.float64]:
        """√w (o - m)/√m on the fitted frames."""
        model = self.model(theta)
        return np.asarray(self.sw * (self.observed - model) / np.sqrt(model))

    def jacobian(self, theta: NDArray[np.float64]) -> NDArray[np.float64]:
        """∂(residual)/∂(ω_p, ρ, f), shape (fitted frames, 3)."""
        p, rho, f = float(theta[0]), max(float(theta[1]), _RHO_FLOOR), float(theta[2])
        decay = self._smoothed_decay(theta)
        model = f * p + (1.0 - f) * p * decay
        slope = np.zeros_like(self.x)
        slope[self.moving] = self.x_moving * np.power(rho, self.x_moving - 1.0)
        d_rho = (1.0 - f) * p * smooth(slope, self.kernel, self.mass)[self.use]
        d_model = np.column_stack([f + (1.0 - f) * decay, d_rho, p * (1.0 - decay)])
        factor = -self.sw * (self.observed + model) / (2.0 * model * np.sqrt(model))
        return np.asarray(d_model * factor[:, None])


def _fit_omega(
    tau: NDArray[np.float64],
    obs: NDArray[np.float64],
    weight: NDArray[np.float64],
    use: NDArray[np.bool_],
    kernel: NDArray[np.float64],
    t_max_s: float,
    start: NDArray[np.float64],
    p_bounds: tuple[float, float],
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """θ = (ω_p, ρ, f) of eq. 6.10 fitted to ω_g(t) within bounds; the residuals' Jacobian and
    the residuals at the solution.

    MINPACK's Levenberg-Marquardt runs on θ = middle + half·sin(u), which keeps θ within the
    bounds, with the analytic Jacobian: its loop is compiled, a fifth of the cost per iteration
    of ``trf`` (bounds handled in Python) on this 3-parameter problem. The sine's slope vanishes
    at a bound, where LM creeps, so a solution in a flagged bound region is finished by ``trf``
    from there (two iterations for most). Half the cost of the former ``trf`` with a
    finite-difference Jacobian, at costs within 1e-6 of it (docs/benchmarks.md, issue 29).
    """
    from scipy.optimize import least_squares

    fit = _OmegaResiduals(tau, obs, weight, use, kernel, t_max_s)
    lower = np.array([p_bounds[0], 0.0, _MIN_R_OVER_P])
    upper = np.array([p_bounds[1], 1.0, 1.0 - 1e-9])
    half = 0.5 * (upper - lower)
    middle = lower + half

    def theta_of(u: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.asarray(middle + half * np.sin(u))

    def residual_u(u: NDArray[np.float64]) -> NDArray[np.float64]:
        return fit.residual(theta_of(u))

    def jacobian_u(u: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.asarray(fit.jacobian(theta_of(u)) * (half * np.cos(u))[None, :])

    x0 = np.clip(start, lower + 1e-9, upper - 1e-9)
    tol = 1e-6  # parameters to ~1e-6 relative: far below their standard errors
    found = least_squares(
        residual_u, np.arcsin((x0 - middle) / half), jac=jacobian_u, method="lm", x_scale=1.0,
        ftol=tol, xtol=tol,
    )  # fmt: skip
    theta = theta_of(found.x)
    if _bound_flags(theta, p_bounds):
        x1 = np.clip(theta, lower + 1e-9, upper - 1e-9)
        found = least_squares(
            fit.residual, x1, jac=fit.jacobian, bounds=(lower, upper),
            x_scale=[float(x1[0]), 0.1, 0.1], method="trf", ftol=tol, xtol=tol,
        )  # fmt: skip
        theta = np.asarray(found.x, dtype=np.float64)
    return theta, fit.jacobian(theta), fit.residual(theta)


def _bound_flags(theta: NDArray[np.float64], p_bounds: tuple[float, float]) -> list[str]:
    """The flags of a fit whose θ = (ω_p, ρ, f) lies at or near a bound of the search."""
    p, rho, f = float(theta[0]), float(theta[1]), float(theta[2])
    flags = []
    if f >= 0.999:
        flags.append("omega_not_decreasing")
    if p >= 0.999 * p_bounds[1] or p <= 1.001 * p_bounds[0]:
        flags.append("omega_p_at_bound")
    if rho <= 1e-3 or rho >= 0.999:
        flags.append("omega_s_at_bound")
    if f <= 1.001 * _MIN_R_OVER_P:
        flags.append("omega_r_at_bound")
    return flags


def _start(
    obs: NDArray[np.float64], tau: NDArray[np.float64], use: NDArray[np.bool_], t_max: float
) -> NDArray[np.float64]:
    """Starting θ = (ω_p, ρ, f) from early, near-peak and late frames."""
    values, times = obs[use], tau[use]
    early = values[times <= max(0.25 * t_max, float(times.min()) + 1e-9)]
    late = values[times >= float(np.quantile(times, 0.75))]
    near = values[np.abs(times - t_max) <= max(0.2 * t_max, 1e-9)]
    r = float(np.median(late))
    s = float(np.median(near)) if near.size else float(np.median(values))
    p = float(np.max(early)) if early.size else s
    s = max(s, r)
    p = max(p, s * 1.01)
    return np.array([p, (s - r) / (p - r) if p > r else 0.5, r / p])


def _alpha_design(tau: NDArray[np.float64], ramp_s: float) -> NDArray[np.float64]:
    f = np.minimum(tau / ramp_s, 1.0)
    return np.column_stack([1.0 - f, f])


def fit_model(
    features: RecordFeatures,
    *,
    alpha_reading: AlphaReading = "eq-6-11",
    bootstrap: int = 0,
    seed: int | None = None,
    fit_corner: bool = False,
    spectrum: xr.DataArray | None = None,
    fit_threshold: float = DEFAULT_FIT_THRESHOLD,
) -> FitResult:
    """Fit (ω_p, ω_s, ω_r, ξ_p, ξ_r) of eqs. 6.10-6.11 to a record's features.

    Parameters
    ----------
    features
        From :func:`stepframe.stochastic.features.record_features`.
    alpha_reading
        Where the α_g ramp ends: ``"eq-6-11"`` (t_dur, default) or ``"paper"`` (t_max).
    bootstrap
        Number of moving-block bootstrap refits (0: none).
    seed
        Seed of the bootstrap.
    fit_corner
        Also fit a source corner frequency ω_c; needs ``spectrum`` (the STFT DataArray).
    spectrum
        STFT evolutionary spectrum of the record (:func:`evolutionary_spectrum`).
    fit_threshold
        Frames after t0 with I_g ≥ ``fit_threshold`` · max I_g enter the fit.

    Raises
    ------
    InputError
        Fewer than 5 strong-motion frames with a frequency estimate (record too short or too
        quiet for the window), bad options.
    """
    # Each refit keeps its parameters and resamples every frame's residual (float64 each).
    replicate_bytes = 8 * (8 + 2 * features.time_s.size)
    bootstrap = validation.count("bootstrap", bootstrap, bytes_each=replicate_bytes, low=0)
    seed = validation.seed("seed", seed)
    if fit_corner and spectrum is None:
        raise InputError("fit_corner needs the record's STFT spectrum, expected spectrum=...")
    flags = list(features.flags)
    tau = np.maximum(features.time_s - features.t0_s, 0.0)
    obs = features.omega_g_rad_s
    # Equal weights: the zero-crossing noise does not depend on the amplitude, and weighting by
    # I_g starves the late frames that fix ω_r (median ω_r error 30-48 % instead of 13-26 %).
    weight = np.ones_like(features.intensity)
    if not 0 < fit_threshold < 1:
        raise InputError(f"fit_threshold = {fit_threshold}, expected 0 < fit_threshold < 1")
    strong = (features.time_s >= features.t0_s) & (
        features.intensity >= fit_threshold * features.peak_intensity
    )
    use = strong & np.isfinite(obs)
    n, n_strong = int(use.sum()), int(strong.sum())
    if n < 5 and n_strong >= 5:
        # Frames strong enough but no ω_g: no zero crossings (or no spectral peak) in them.
        raise InputError(
            f"{n} of {n_strong} frames above the fit threshold have a frequency estimate, "
            "expected ≥ 5 (does the record oscillate about zero? a baseline offset leaves no "
            "zero crossings)"
        )
    if n < 5:
        raise InputError(
            f"{n} frames above the fit threshold with a frequency estimate, expected ≥ 5 "
            "(record too short or too quiet for the window)"
        )
    obs_filled = np.where(np.isfinite(obs), obs, 0.0)
    t_max = features.t_max_s
    kernel = features.omega_kernel
    start = _start(obs_filled, tau, use, t_max)
    # ω_g(t) of eq. 6.10 stays within [ω_r, ω_p]: keep ω_p near the measured range, not an
    # extrapolation to a record start long before the motion (seen on real records: 1e9 rad/s).
    measured = obs[use]
    p_bounds = (0.5 * float(measured.min()), 1.5 * float(measured.max()))
    theta, jac, fun = _fit_omega(tau, obs_filled, weight, use, kernel, t_max, start, p_bounds)
    p, s, r = _psr(theta)
    flags.extend(_bound_flags(theta, p_bounds))
    inflation = max(1.0, features.window_s / features.hop_s)
    cov_theta = least_squares_covariance(jac, fun, inflation)
    to_psr = _psr_jacobian(theta)
    cov_psr = to_psr @ cov_theta @ to_psr.T
    omega_fit = smooth(_omega_curve(theta, tau, t_max), kernel)
    fit_quality = math.sqrt(
        float(np.sum(weight[use] * ((obs[use] - omega_fit[use]) / omega_fit[use]) ** 2))
        / float(np.sum(weight[use]))
    )

    ramp = features.t_dur_s if alpha_reading == "eq-6-11" else t_max
    alpha_use = use & np.isfinite(features.alpha_g_rad_s)
    if alpha_use.sum() < 3:
        raise InputError(f"{int(alpha_use.sum())} frames with a bandwidth estimate, expected ≥ 3")
    design = _alpha_design(tau[alpha_use], ramp)
    sw = np.sqrt(weight[alpha_use])
    solution = np.linalg.lstsq(design * sw[:, None], features.alpha_g_rad_s[alpha_use] * sw)
    coef: NDArray[np.float64] = np.asarray(solution[0], dtype=np.float64)
    resid = (features.alpha_g_rad_s[alpha_use] - design @ coef) * sw
    cov_a = least_squares_covariance(design * sw[:, None], resid, inflation)
    xi_p, xi_r = float(coef[0] / p), float(coef[1] / r)
    se_p, se_r = math.sqrt(max(cov_psr[0, 0], 0.0)), math.sqrt(max(cov_psr[2, 2], 0.0))
    se_xi_p = math.sqrt(cov_a[0, 0] / p**2 + (coef[0] * se_p / p**2) ** 2)
    se_xi_r = math.sqrt(cov_a[1, 1] / r**2 + (coef[1] * se_r / r**2) ** 2)
    clipped_p, clipped_r = np.clip([xi_p, xi_r], *_XI_RANGE)
    if (clipped_p, clipped_r) != (xi_p, xi_r):
        flags.append("xi_clipped")
    stderr = {
        "omega_p_rad_s": se_p,
        "omega_s_rad_s": OMEGA_S_SE_CALIBRATION * math.sqrt(max(cov_psr[1, 1], 0.0)),
        "omega_r_rad_s": se_r,
        "xi_p": se_xi_p,
        "xi_r": se_xi_r,
    }
    if features.t_max_stderr_s is not None:
        stderr["t_max_s"] = features.t_max_stderr_s
    omega_c = None
    if fit_corner:
        corner = _fit_corner(spectrum, features, (p, s, r, clipped_p, clipped_r))
        if corner is None:
            flags.append("omega_c_not_fitted")
        else:
            omega_c, stderr["omega_c_rad_s"] = corner
    # p > r is guaranteed by the lower bound on p - s; float() drops numpy scalar types.
    model = GroundMotionModel(
        float(p),
        float(s),
        float(r),
        float(clipped_p),
        float(clipped_r),
        t_max_s=t_max,
        t_dur_s=features.t_dur_s,
        t0_s=features.t0_s,
        alpha_reading=alpha_reading,
        omega_c_rad_s=omega_c,
    )
    samples = None
    if bootstrap:
        samples = _bootstrap(
            features, theta, p_bounds, omega_fit, use, weight, kernel, tau, coef, ramp,
            bootstrap, seed,
        )  # fmt: skip
        boot_se = np.std(samples, axis=0, ddof=1)
        for key, value in zip(PARAMETERS, boot_se, strict=True):
            stderr[f"{key}_bootstrap"] = float(value)
    return FitResult(
        model=model,
        stderr=stderr,
        fit_quality=fit_quality,
        n_points=n,
        flags=tuple(flags),
        bootstrap=samples,
        omega_fit_rad_s=omega_fit,
    )


def _bootstrap(
    features: RecordFeatures,
    theta: NDArray[np.float64],
    p_bounds: tuple[float, float],
    omega_fit: NDArray[np.float64],
    use: NDArray[np.bool_],
    weight: NDArray[np.float64],
    kernel: NDArray[np.float64],
    tau: NDArray[np.float64],
    coef: NDArray[np.float64],
    ramp: float,
    count: int,
    seed: int | None,
) -> NDArray[np.float64]:
    """Moving-block bootstrap of relative residuals (blocks one window long)."""
    rng = np.random.default_rng(seed)
    idx = np.flatnonzero(use)
    rel = features.omega_g_rad_s[idx] / omega_fit[idx] - 1.0
    alpha_model = _alpha_design(tau[idx], ramp) @ coef
    alpha_res = np.nan_to_num(features.alpha_g_rad_s[idx] - alpha_model)
    block = max(1, min(idx.size, round(features.window_s / features.hop_s)))
    out = np.empty((count, 5))
    for b in range(count):
        starts = rng.integers(0, idx.size - block + 1, size=math.ceil(idx.size / block))
        pick = (starts[:, None] + np.arange(block)[None, :]).ravel()[: idx.size]
        obs = omega_fit.copy()
        obs[idx] = omega_fit[idx] * (1.0 + rel[pick])
        theta_b, _, _ = _fit_omega(tau, obs, weight, use, kernel, features.t_max_s, theta, p_bounds)
        p, s, r = _psr(theta_b)
        alpha_b = alpha_model + alpha_res[pick]
        design = _alpha_design(tau[idx], ramp)
        sw = np.sqrt(weight[idx])
        c_b, *_ = np.linalg.lstsq(design * sw[:, None], alpha_b * sw)
        # The same clipping as the estimate: a refit with ω_r → 0 must not give ξ_r → ∞.
        xi_b = np.clip([c_b[0] / p, c_b[1] / r], *_XI_RANGE)
        out[b] = (p, s, r, xi_b[0], xi_b[1])
    return out


def _fit_corner(
    spectrum: Any, features: RecordFeatures, params: tuple[float, float, float, float, float]
) -> tuple[float, float] | None:
    """ω_c of the high-pass ω⁴/(ω² + ω_c²)² between the record's and the model's mean spectra."""
    from scipy.optimize import least_squares

    p, s, r, xi_p, xi_r = params
    model = GroundMotionModel(
        p, s, r, xi_p, xi_r, features.t_max_s, features.t_dur_s, t0_s=features.t0_s
    )
    omega = np.asarray(spectrum["omega"].values, dtype=np.float64)
    times = np.asarray(spectrum["time"].values, dtype=np.float64)
    observed = np.asarray(spectrum.values, dtype=np.float64).mean(axis=0)
    intensity = np.interp(times, features.time_s, features.intensity)
    fitted = model.psd(omega[None, :], times[:, None], intensity[:, None]).mean(axis=0)
    # The corner acts below the dominant frequencies: compare the spectra up to ω_s.
    band = (omega > 0) & (omega <= s) & (observed > 0) & (fitted > 0)
    if band.sum() < 3:
        return None  # too few bins below ω_s: the corner is not resolved (flagged by the caller)
    log_ratio = np.log(observed[band] / fitted[band])

    def residual(x: NDArray[np.float64]) -> NDArray[np.float64]:
        wc = math.exp(float(x[0]))
        w = omega[band]
        return np.asarray(log_ratio - x[1] - np.log(w**4 / (w**2 + wc**2) ** 2))

    result = least_squares(residual, [math.log(0.3 * r), 0.0])
    cov = least_squares_covariance(result.jac, result.fun)
    wc = math.exp(float(result.x[0]))
    return wc, wc * math.sqrt(max(float(cov[0, 0]), 0.0))
