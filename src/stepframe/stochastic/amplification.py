"""Moving-resonance amplification: the paper's spectral ratio and the response amplification.

Two different quantities, each named for what it is (DESIGN.md, The paper):

- the **spectral ratio** of eqs. 6.13-6.18, a ratio of input spectral densities R_g times
  (ω_0/ω)² between the oscillator at ω = ω_g(t_max) = ω_s and at ω_0 at t = 0, with eq. 6.19's
  first approximation (ω_pξ_p/ω_rξ_r)(ω_p/ω_s)² (eq. 6.18 at ω_0 = ω_p with α_g(t_max) = ω_rξ_r)
  and its last, (ω_p/ω_s)². It is a ratio of *mean squares* (in eq. 6.4's stationary limit
  q_11 = I²R_g/(4βω²), so with equal I and β the ratio of q_11 is exactly eq. 6.13);
- the **response amplification**, ratios of the peak RMS response computed by the exact
  covariance method (and confirmed by Monte Carlo): with the moving ω(t) (tracking or
  frame-driven) over the same oscillator held at ω_0 (``vs_fixed``), and over the stationary RMS
  at ω_0 under the peak intensity and the ground-motion parameters at t_max (``vs_stationary``).

Every result carries the model's ``alpha_reading`` (where eq. 6.11's ramp ends): eq. 6.18 uses
α_g(t_max) from it, which is ω_rξ_r only under the ``"paper"`` reading.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from stepframe.errors import InputError
from stepframe.stochastic.correlation import r_g
from stepframe.stochastic.mean_square import (
    Constant,
    FrameDriven,
    MeanSquareResult,
    Tracking,
    mean_square_response,
)
from stepframe.stochastic.model import GroundMotionModel

Floats = NDArray[np.float64]
AmplificationMethod = Literal["covariance", "monte-carlo"]
FixedPointFactor = Literal["eq-6-19-last", "eq-6-19-first", "eq-6-18", "response-vs-fixed"]


def _alpha_at_t_max(model: GroundMotionModel) -> float:
    return float(model.alpha_g(model.t0_s + model.t_max_s))


def spectral_ratio_eq_6_18(model: GroundMotionModel, omega_0_rad_s: ArrayLike) -> Floats:
    """The paper's spectral ratio 𝒜(ω_0), eq. 6.18, with α_g(t_max) from the model's reading.

    𝒜 = [(ω_0² - ω_p²)² + 4(ω_pξ_p)²ω_0²] / [4 α_g(t_max) (ω_pξ_p) ω_p²] · (ω_0/ω_s)²; with the
    ``"paper"`` reading α_g(t_max) = ω_rξ_r, as printed. Not monotone in ω_0.
    """
    w0 = np.asarray(omega_0_rad_s, dtype=np.float64)
    if not (np.all(np.isfinite(w0)) and np.all(w0 > 0)):
        raise InputError("omega_0_rad_s has values ≤ 0 or not finite, expected > 0")
    wp, ws = model.omega_p_rad_s, model.omega_s_rad_s
    alpha_p = wp * model.xi_p
    numerator = (w0**2 - wp**2) ** 2 + 4 * alpha_p**2 * w0**2
    return np.asarray(numerator / (4 * _alpha_at_t_max(model) * alpha_p * wp**2) * (w0 / ws) ** 2)


def spectral_ratio_eq_6_13(
    model: GroundMotionModel, omega_0_rad_s: ArrayLike, xi0: float = 0.0
) -> Floats:
    """Eq. 6.13 with the closed-form R_g (damping kept): R_g at ω = ω_s, t_max over R_g at ω_0,
    t = 0, times (ω_0/ω_s)². Equal to eq. 6.18 for ξ_0 = 0 (eqs. 6.15-6.17)."""
    w0 = np.asarray(omega_0_rad_s, dtype=np.float64)
    beta = xi0 * w0
    t_max = model.t0_s + model.t_max_s
    ws = model.omega_s_rad_s
    moving = r_g(ws, beta, model.omega_g(t_max), model.alpha_g(t_max))
    start = r_g(w0, beta, model.omega_p_rad_s, model.omega_p_rad_s * model.xi_p)
    return np.asarray(moving / start * (w0 / ws) ** 2)


def approx_eq_6_19_first(model: GroundMotionModel) -> float:
    """Eq. 6.19's first approximation (ω_pξ_p/ω_rξ_r)(ω_p/ω_s)² (eq. 6.18 at ω_0 = ω_p with
    α_g(t_max) = ω_rξ_r: the paper's reading)."""
    wp, ws, wr = model.omega_p_rad_s, model.omega_s_rad_s, model.omega_r_rad_s
    return (wp * model.xi_p) / (wr * model.xi_r) * (wp / ws) ** 2


def approx_eq_6_19_last(model: GroundMotionModel) -> float:
    """Eq. 6.19's last approximation (ω_p/ω_s)², the paper's "5.67" for its site."""
    return (model.omega_p_rad_s / model.omega_s_rad_s) ** 2


@dataclass(frozen=True)
class ResponseAmplification:
    """Response amplification per oscillator frequency ω_0.

    Attributes
    ----------
    omega_0_rad_s
        Small-amplitude frequencies [rad/s].
    xi0
        Damping ratio at ω_0.
    omega_path
        ``"tracking"`` or ``"frame"``.
    alpha_reading
        The model's reading of eq. 6.11.
    method
        ``"covariance"`` or ``"monte-carlo"``.
    vs_fixed, vs_stationary
        max σ_x(moving) / max σ_x(held at ω_0), and / the stationary σ_x at ω_0 under the peak
        intensity and θ_g(t_max).
    peak_rms_moving_m, peak_rms_fixed_m, stationary_rms_m
        The three RMS values [m] for the given intensity.
    vs_fixed_band, vs_stationary_band
        Monte Carlo confidence intervals (shape (n, 2)) or None.
    moving, fixed
        The underlying mean-square results.
    """

    omega_0_rad_s: Floats
    xi0: float
    omega_path: str
    alpha_reading: str
    method: AmplificationMethod
    vs_fixed: Floats
    vs_stationary: Floats
    peak_rms_moving_m: Floats
    peak_rms_fixed_m: Floats
    stationary_rms_m: Floats
    moving: MeanSquareResult
    fixed: MeanSquareResult
    vs_fixed_band: Floats | None = None
    vs_stationary_band: Floats | None = None

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary (arrays as lists)."""
        out: dict[str, Any] = {
            "omega_0_rad_s": self.omega_0_rad_s,
            "f0_hz": self.omega_0_rad_s / (2 * math.pi),
            "xi0": self.xi0,
            "omega_path": self.omega_path,
            "alpha_reading": self.alpha_reading,
            "method": self.method,
            "response_amplification_vs_fixed": self.vs_fixed,
            "response_amplification_vs_stationary": self.vs_stationary,
            "peak_rms_moving_m": self.peak_rms_moving_m,
            "peak_rms_fixed_m": self.peak_rms_fixed_m,
            "stationary_rms_m": self.stationary_rms_m,
            "status": self.moving.status,
            "message": self.moving.message,
        }
        if self.vs_fixed_band is not None and self.vs_stationary_band is not None:
            out["response_amplification_vs_fixed_band"] = self.vs_fixed_band
            out["response_amplification_vs_stationary_band"] = self.vs_stationary_band
            out["n_realisations"] = self.moving.n_realisations
            out["seed"] = self.moving.seed
            out["confidence"] = self.moving.confidence
        return out


def stationary_rms(
    model: GroundMotionModel, omega_0_rad_s: ArrayLike, xi0: float, peak_intensity: float
) -> Floats:
    """Stationary σ_x [m] at ω_0 under I_g = ``peak_intensity`` [m/s²] and θ_g(t_max)."""
    w0 = np.asarray(omega_0_rad_s, dtype=np.float64)
    if not xi0 > 0:
        raise InputError(f"xi0 = {xi0}: no stationary response without damping, expected > 0")
    t_max = model.t0_s + model.t_max_s
    beta = xi0 * w0
    rg = r_g(w0, beta, model.omega_g(t_max), model.alpha_g(t_max))
    return np.asarray(peak_intensity * np.sqrt(rg / (4 * beta * w0**2)))


def response_amplification(
    model: GroundMotionModel,
    omega_0_rad_s: ArrayLike | None,
    xi0: float,
    *,
    frame: FrameDriven | None = None,
    method: AmplificationMethod = "covariance",
    peak_intensity: float = 1.0,
    time_s: ArrayLike | None = None,
    n_realisations: int = 500,
    seed: int | None = None,
    confidence: float = 0.95,
) -> ResponseAmplification:
    """Response amplification by moving resonance, vs the fixed oscillator and vs stationary.

    Parameters
    ----------
    model
        Ground-motion model (its ``alpha_reading`` is reported).
    omega_0_rad_s
        Small-amplitude frequencies [rad/s] for the tracking path ω_0·ω_g(t)/ω_p; None with
        ``frame`` (then ω_0 = 2π/T(0)).
    xi0
        Damping ratio at ω_0 (> 0).
    frame
        Frame-driven ω(t) instead of tracking.
    method
        ``"covariance"`` (exact, default) or ``"monte-carlo"`` (moving and fixed runs share the
        seed: common random numbers; peaks by :func:`cross_fitted_peaks`; bootstrap percentile
        intervals of the ratios, :data:`N_BOOTSTRAP` resamples).
    peak_intensity
        max I_g of the default envelope [m/s²] (matters only for the frame-driven path).
    time_s, n_realisations, seed, confidence
        As in :func:`mean_square_response`.
    """
    if method not in ("covariance", "monte-carlo"):
        raise InputError(f"method = {method!r}, expected 'covariance' or 'monte-carlo'")
    moving_spec: Tracking | FrameDriven
    if frame is not None and omega_0_rad_s is not None:
        raise InputError(
            "omega_0_rad_s and frame both given, expected one of them (a frame's ω_0 is 2π/T(0); "
            "the given frequencies would be ignored)"
        )
    if frame is not None:
        moving_spec = frame
    elif omega_0_rad_s is None:
        raise InputError("omega_0_rad_s is None and no frame given, expected one of them")
    else:
        moving_spec = Tracking(omega_0_rad_s)
    mc = method == "monte-carlo"
    kwargs: dict[str, Any] = {
        "method": method,
        "time_s": time_s,
        "peak_intensity": peak_intensity,
        "n_realisations": n_realisations,
        "seed": seed,
        "confidence": confidence,
        "keep_samples": mc,
    }
    moving = mean_square_response(model, moving_spec, xi0, **kwargs)
    omega_0 = moving.omega_0_rad_s
    fixed = mean_square_response(model, Constant(omega_0), xi0, **kwargs)
    stat = stationary_rms(model, omega_0, xi0, peak_intensity)
    band_fixed = band_stat = None
    if mc:
        peak_moving, peak_fixed, vs_fixed, vs_stationary, band_fixed, band_stat = (
            _monte_carlo_ratios(moving, fixed, stat, confidence, seed)
        )
    else:
        peak_moving, peak_fixed = moving.peak_rms_m, fixed.peak_rms_m
        vs_fixed = np.asarray(peak_moving / peak_fixed)
        vs_stationary = np.asarray(peak_moving / stat)
    return ResponseAmplification(
        omega_0_rad_s=omega_0,
        xi0=xi0,
        omega_path=moving.omega_path,
        alpha_reading=model.alpha_reading,
        method=method,
        vs_fixed=vs_fixed,
        vs_stationary=vs_stationary,
        peak_rms_moving_m=peak_moving,
        peak_rms_fixed_m=peak_fixed,
        stationary_rms_m=stat,
        moving=moving,
        fixed=fixed,
        vs_fixed_band=band_fixed,
        vs_stationary_band=band_stat,
    )


def cross_fitted_peaks(samples_x2: Floats) -> tuple[Floats, Floats]:
    """Peak of E[x²] over time from Monte Carlo samples without the max-of-noise bias.

    The maximum of a noisy sample curve over many times is biased upwards (by about one
    standard error: 4 % in RMS at N = 300). Cross-fitting removes it: the realisations are split
    in two halves, each half picks the time of its own maximum, and the other half's values at
    that time are averaged; the estimate is the mean of those N values. Because the true curve
    is flat at its peak, what remains is a small downward bias of second order.

    Parameters
    ----------
    samples_x2
        x² per oscillator, realisation and time, shape (n_osc, N, n_t).

    Returns
    -------
    peak : numpy.ndarray
        Estimated max_t E[x²], shape (n_osc,).
    values : numpy.ndarray
        The N per-realisation values whose mean is ``peak``, shape (n_osc, N).
    """
    n = samples_x2.shape[1]
    half = n // 2
    first, second = samples_x2[:, :half], samples_x2[:, half:]
    k_first = np.nanargmax(np.mean(first, axis=1), axis=1)
    k_second = np.nanargmax(np.mean(second, axis=1), axis=1)
    rows = np.arange(samples_x2.shape[0])
    values = np.concatenate([first[rows, :, k_second], second[rows, :, k_first]], axis=1)
    return np.asarray(np.mean(values, axis=1)), np.asarray(values)


#: Bootstrap resamples of the Monte Carlo intervals of the amplification ratios.
N_BOOTSTRAP = 400


def _candidates(samples_x2: Floats, fraction: float = 0.6) -> list[Floats]:
    """Per oscillator, the times whose mean x² is ≥ ``fraction`` of the peak: the only ones a
    resample's maximum can realistically fall on (keeps the bootstrap small)."""
    mean = np.mean(samples_x2, axis=1)
    return [samples_x2[i][:, mean[i] >= fraction * np.nanmax(mean[i])] for i in range(len(mean))]


def _monte_carlo_ratios(
    moving: MeanSquareResult,
    fixed: MeanSquareResult,
    stationary_m: Floats,
    confidence: float,
    seed: int | None,
) -> tuple[Floats, Floats, Floats, Floats, Floats, Floats]:
    """Cross-fitted peaks, and bootstrap percentile intervals of the two ratios.

    Each resample draws the realisations of each half with replacement from that half (the same
    ones for the moving and the fixed run: common random numbers, so the ratio is much tighter
    than either peak) and repeats the cross-fitting, so the interval includes the randomness of
    the peak's time.
    """
    m1, _ = cross_fitted_peaks(moving.samples["x2"])
    m2, _ = cross_fitted_peaks(fixed.samples["x2"])
    vs_fixed = np.sqrt(m1 / m2)
    vs_stat = np.sqrt(m1) / stationary_m
    rng = np.random.default_rng(None if seed is None else [seed, 1])
    tail = 100 * (1 - confidence) / 2
    near1, near2 = _candidates(moving.samples["x2"]), _candidates(fixed.samples["x2"])
    n = moving.samples["x2"].shape[1]
    band_fixed = np.empty((m1.size, 2))
    band_stat = np.empty((m1.size, 2))
    for i in range(m1.size):
        ratios_fixed = np.empty(N_BOOTSTRAP)
        ratios_stat = np.empty(N_BOOTSTRAP)
        half = n // 2
        for b in range(N_BOOTSTRAP):
            # resample within each half, so that the halves stay independent as in the estimate
            pick = np.concatenate([rng.integers(0, half, half), rng.integers(half, n, n - half)])
            p1 = cross_fitted_peaks(near1[i][None, pick])[0][0]
            p2 = cross_fitted_peaks(near2[i][None, pick])[0][0]
            ratios_fixed[b] = math.sqrt(p1 / p2)
            ratios_stat[b] = math.sqrt(p1) / stationary_m[i]
        band_fixed[i] = np.percentile(ratios_fixed, [tail, 100 - tail])
        band_stat[i] = np.percentile(ratios_stat, [tail, 100 - tail])
    return np.sqrt(m1), np.sqrt(m2), vs_fixed, vs_stat, band_fixed, band_stat


def adjusted_fixed_point(
    delta_star_m: float,
    model: GroundMotionModel,
    *,
    factor: FixedPointFactor = "eq-6-19-last",
    omega_0_rad_s: float | None = None,
    xi0: float | None = None,
) -> float:
    """The quasi-dynamic fixed point δ* adjusted for moving resonance [m].

    The spectral factors (eqs. 6.18-6.19) are ratios of mean squares (module docstring), so the
    displacement amplitude δ* scales with their square root: δ*_adj = √𝒜 · δ*. The response
    amplification ``"response-vs-fixed"`` is already a ratio of RMS values: δ*_adj = 𝒜_r · δ*
    (assuming the same peak factor with and without moving resonance). Derivation in
    docs/paper-notes.md ("Amplification factor").

    Parameters
    ----------
    delta_star_m
        The unadjusted fixed point δ* [m] (> 0), e.g. from ``stepframe structure design``.
    model
        The site's ground-motion model.
    factor
        ``"eq-6-19-last"`` ((ω_p/ω_s)²), ``"eq-6-19-first"``, ``"eq-6-18"`` (at ``omega_0_rad_s``)
        or ``"response-vs-fixed"`` (covariance method at ``omega_0_rad_s`` and ``xi0``, tracking).
    omega_0_rad_s
        The frame's small-amplitude frequency [rad/s] (for ``"eq-6-18"`` and the response).
    xi0
        Its damping ratio (for the response).
    """
    if not (math.isfinite(delta_star_m) and delta_star_m > 0):
        raise InputError(f"delta_star_m = {delta_star_m}, expected a positive displacement [m]")
    # What each factor reads; anything else given would be ignored (an error, not a no-op).
    reads = {"eq-6-19-last": (), "eq-6-19-first": (), "eq-6-18": ("omega_0_rad_s",),
             "response-vs-fixed": ("omega_0_rad_s", "xi0")}  # fmt: skip
    given = {"omega_0_rad_s": omega_0_rad_s, "xi0": xi0}
    unused = [name for name, value in given.items() if value is not None]
    unused = [name for name in unused if name not in reads.get(factor, given)]
    if unused:
        raise InputError(
            f"factor = {factor!r} does not read {' or '.join(unused)}, expected "
            f"{'only omega_0_rad_s' if reads[factor] else 'neither'} (eq. 6.19 reads the site "
            "alone, eq. 6.18 the site at omega_0_rad_s)"
        )
    if factor == "eq-6-19-last":
        return math.sqrt(approx_eq_6_19_last(model)) * delta_star_m
    if factor == "eq-6-19-first":
        return math.sqrt(approx_eq_6_19_first(model)) * delta_star_m
    if omega_0_rad_s is None:
        raise InputError(f"factor = {factor!r} needs omega_0_rad_s, expected a frequency [rad/s]")
    if factor == "eq-6-18":
        return math.sqrt(float(spectral_ratio_eq_6_18(model, omega_0_rad_s))) * delta_star_m
    if factor == "response-vs-fixed":
        if xi0 is None:
            raise InputError("factor = 'response-vs-fixed' needs xi0, expected a damping ratio")
        ratio = response_amplification(model, [omega_0_rad_s], xi0).vs_fixed[0]
        return float(ratio) * delta_star_m
    raise InputError(
        f"factor = {factor!r}, expected 'eq-6-19-last', 'eq-6-19-first', 'eq-6-18' or "
        "'response-vs-fixed'"
    )
