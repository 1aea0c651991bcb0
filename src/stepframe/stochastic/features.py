"""Time-varying features of a record: I_g(t), t_max, t_dur, ω_g(t), α_g(t), P and S arrivals.

All features are given on the STFT frame grid (frame centres every ``hop_s`` from the record start)
and smoothed over one window of ``window_s`` (default 2 s), stated for each:

- ``I_g(t)``: RMS acceleration, ``I_g² = Σ w_n² x_n² / Σ w_n²`` with the Hann window w of the STFT
  centred on the frame (zeros outside the record): exactly ``(1/π)∫_0^∞ S dω`` of the STFT.
- ``t_max``: time of max I_g, by default the peak of a gamma envelope fitted to I_g(t) (robust to
  its random fluctuations; ``peak_method="argmax"`` takes the raw maximum), with a standard
  error from the fit's Jacobian (inflated by the frames per window, as in
  :mod:`stepframe.stochastic.fit`).
- ``t_dur``: last time I_g ≥ ``threshold · max I_g`` (after which it stays below). Both are
  measured from the time origin ``t0_s``; the default threshold is the default envelope's,
  :data:`stepframe.stochastic.envelope.DEFAULT_DURATION_THRESHOLD`.
- ``ω_g(t)``:
  ``"zero-crossing"`` (default): π × the density of zero crossings (both directions), the crossing
  times interpolated linearly between samples and smoothed by a unit-area Hann kernel of
  ``window_s`` (normalised by the kernel's mass inside the record). Exact in expectation for the
  eq. 6.12 process (up-crossing rate ω_g/2π whatever α_g) and for a chirp (crossings at phase kπ).
  ``"ridge"``: frequency of the STFT maximum (parabolic interpolation); the peak of eq. 6.12 lies at
  √(ω_g² - 2α_g²), so it is biased low for broad bands.
  ``"moment"``: √(λ2/λ0 - σ_w²) from STFT spectral moments, σ_w² the window's own spread; exact for
  eq. 6.12 (E[ẏ²]/E[y²] = ω_g²) up to leakage.
  ``"wavelet-ridge"``: the maximum of the Morlet spectrum (160 log-spaced bands), the dearest
  step of the ladder zero crossings → STFT ridge → wavelet ridge; biased like the STFT ridge.
  ``"multiwindow"``: √(Σ w ẋ² / Σ w x²) (the moment E[ẏ²]/E[y²] = ω_g², energies divided by
  the envelope's trend) over a Hann window of three periods of the local frequency, never
  shorter than ``window_s``: the only one that resolves ω_g below 2π/``window_s``, down to
  6π/T on a record of T seconds (:mod:`stepframe.stochastic.multiwindow`).
- Resolution floor (``omega_floor_rad_s``, per frame): the lowest ω_g the estimator resolves
  there: 2π/``window_s`` (one cycle per window) for the STFT and zero-crossing estimators; for
  ``"wavelet-ridge"`` its lowest band 12π/T (six cycles in a record of T s, at least 0.2 rad/s)
  or, nearer the record's ends, the cone of influence √2·6/d (d the time to the nearer end); for
  ``"multiwindow"`` three cycles in a window centred on the frame and inside the record (the
  cone of influence), 6π/max(``window_s``, 2 × the distance to the nearer record end).
- ``α_g(t)``: from the local spectral width: Vanmarcke's ``q² = 1 - λ1²/(λ0 λ2)`` of the STFT
  (λ2 corrected by σ_w²) inverted through q(ζ) of eq. 6.12 (closed form, :func:`vanmarcke_q`),
  ``α_g = ζ ω_g``.
- P onset and S arrival: minima of Maeda's AIC with a quantisation floor, see
  :func:`pick_arrivals`. The default origin (``t0="auto"``) is the P onset when its pick is
  reliable (SNR ≥ :data:`P_PICK_MIN_SNR` after ≥ :data:`P_PICK_MIN_NOISE_S` of pre-event
  noise), else the record start; ``t0_source`` says which.

Frames whose estimate is undefined (no crossing in the window) hold NaN; the fit uses only the
strong-motion frames (I_g ≥ threshold · max). Degraded results are listed in ``flags``.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Literal, Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

from stepframe.core import validation
from stepframe.core.memory import check_memory
from stepframe.errors import InputError
from stepframe.stochastic.envelope import DEFAULT_DURATION_THRESHOLD
from stepframe.stochastic.methods import DEFAULT_FREQUENCY_METHOD, FrequencyMethod
from stepframe.stochastic.standard_errors import least_squares_covariance
from stepframe.stochastic.transforms import (
    DEFAULT_HOP_S,
    DEFAULT_WINDOW_S,
    FftBackend,
    crossing_positions,
    hann_kernel,
    record_samples,
    stft_grid,
    stft_power,
    stft_power_blocks,
)

if TYPE_CHECKING:
    import xarray as xr
    from obspy import Trace

#: Share of the strong-motion frames whose ω_g lies below the estimator's floor above which
#: the features are flagged ``omega_below_floor`` (a few frames below it are noise).
BELOW_FLOOR_SHARE = 0.1

#: Plateaus (runs of at least :data:`CLIP_RUN` identical samples) at the record's largest or
#: smallest value that mark it ``record_clipped``: an instrument at its full scale holds its
#: limit over several samples on several cycles. Of the 161 components of the project's real and
#: format test files, none has a run of even 2 identical samples at an extreme.
CLIP_PLATEAUS = 2
CLIP_RUN = 3


def clipped_plateaus(data: NDArray[np.float64]) -> int:
    """How many runs of ≥ :data:`CLIP_RUN` identical samples equal max or min of ``data``."""
    count = 0
    for extreme in (np.max(data), np.min(data)):
        at = np.concatenate([[False], data == extreme, [False]])
        edges = np.flatnonzero(np.diff(at.astype(np.int8)))
        runs = edges[1::2] - edges[::2]
        count += int(np.count_nonzero(runs >= CLIP_RUN))
    return count


#: Longest smoothing window, in units of t_max, whose I_g(t) still places the peak: beyond it the
#: window smears the rise, t_max and t_dur come out late and the Jacobian standard error of t_max
#: shrinks as the bias grows (synthetic eq. 6.12 records, t_max = 5 s, 30 seeds: truth within
#: 2 SE in 97 % at a 10-s window, 67 % at 20 s, 37 % at 30 s, where t_max was 6.0 ± 0.37 s).
WINDOW_PER_T_MAX = 2.0

TimeOrigin = Literal["auto", "start", "p-pick"]
TIME_ORIGINS: tuple[TimeOrigin, ...] = ("auto", "start", "p-pick")
PeakMethod = Literal["envelope", "argmax"]


@dataclass(frozen=True)
class RecordFeatures:
    """Features of one record on the frame grid (see the module docstring for definitions).

    Attributes
    ----------
    time_s
        Frame centres from the record start [s].
    intensity
        I_g(t) [m/s²] (RMS).
    omega_g_rad_s, alpha_g_rad_s
        ω_g(t) and α_g(t) [rad/s] (NaN where undefined).
    peak_intensity
        max I_g [m/s²].
    t0_s
        Time origin in record time [s] (P onset or 0).
    t_max_s, t_dur_s
        Time of max I_g and end of strong motion, from ``t0_s`` [s].
    p_onset_s, s_arrival_s
        Picked arrivals in record time [s] (None when not asked or not found).
    t_max_stderr_s
        Standard error of ``t_max_s`` from the envelope fit [s] (None with
        ``peak_method="argmax"`` or when the envelope fit failed).
    t0_source
        What ``t0_s`` is: ``"p-pick"`` (the picked P onset) or ``"start"`` (the record start).
    p_pick_snr
        Confidence of the P pick: RMS over 2 s after it over the RMS before it (None when no
        onset was picked or asked for).
    omega_kernel
        Smoothing kernel of ω_g on the frame grid (sums to 1), used by the fit's forward model.
    omega_floor_rad_s
        Lowest ω_g the estimator resolves at each frame [rad/s] (module docstring; None: the
        fixed-window rule 2π/``window_s``, see :meth:`resolution_floor`).
    omega_window_s
        Length of the window behind each frame's ω_g [s] where it differs from frame to frame
        (``"multiwindow"``; None: ``window_s`` everywhere). Neighbouring frames share data over
        that length, which the fit's standard errors and smoothed model assume is ``window_s``.
    """

    time_s: NDArray[np.float64]
    intensity: NDArray[np.float64]
    omega_g_rad_s: NDArray[np.float64]
    alpha_g_rad_s: NDArray[np.float64]
    peak_intensity: float
    t0_s: float
    t_max_s: float
    t_dur_s: float
    dt_s: float
    window_s: float
    hop_s: float
    frequency_method: str
    threshold: float
    omega_kernel: NDArray[np.float64]
    nyquist_rad_s: float
    p_onset_s: float | None = None
    s_arrival_s: float | None = None
    flags: tuple[str, ...] = field(default_factory=tuple)
    t_max_stderr_s: float | None = None
    t0_source: str = "start"
    p_pick_snr: float | None = None
    omega_floor_rad_s: NDArray[np.float64] | None = None
    omega_window_s: NDArray[np.float64] | None = None

    def strong_motion(self) -> NDArray[np.bool_]:
        """Frames after t0 with I_g ≥ threshold · max I_g."""
        return np.asarray(
            (self.time_s >= self.t0_s) & (self.intensity >= self.threshold * self.peak_intensity)
        )

    def resolution_floor(self) -> NDArray[np.float64]:
        """Lowest ω_g resolved at each frame [rad/s] (2π/``window_s`` when none was stated)."""
        if self.omega_floor_rad_s is not None:
            return self.omega_floor_rad_s
        return np.full(self.time_s.shape, fixed_window_floor(self.window_s))

    @property
    def usable_floor_rad_s(self) -> float:
        """Lowest ω_g the estimator resolves anywhere in the record [rad/s]."""
        return float(np.min(self.resolution_floor()))

    def to_dataset(self) -> xr.Dataset:
        """The features as an ``xarray.Dataset`` (dim ``time``), scalars in ``attrs``."""
        import xarray as xr

        time = ("time", self.time_s, {"units": "s", "long_name": "time from record start"})
        return xr.Dataset(
            {
                "intensity": ("time", self.intensity, {"units": "m/s2", "long_name": "I_g (RMS)"}),
                "omega_g": ("time", self.omega_g_rad_s, {"units": "rad/s"}),
                "omega_g_floor": (
                    "time",
                    self.resolution_floor(),
                    {"units": "rad/s", "long_name": "lowest omega_g resolved"},
                ),
                "alpha_g": ("time", self.alpha_g_rad_s, {"units": "rad/s"}),
            },
            coords={"time": time},
            attrs={
                "peak_intensity_m_s2": self.peak_intensity,
                "t0_s": self.t0_s,
                "t0_source": self.t0_source,
                "t_max_s": self.t_max_s,
                "t_dur_s": self.t_dur_s,
                "window_s": self.window_s,
                "frequency_method": self.frequency_method,
                "duration_threshold": self.threshold,
                "flags": ",".join(self.flags),
            },
        )


def vanmarcke_q(zeta: NDArray[np.float64]) -> NDArray[np.float64]:
    """Vanmarcke's bandwidth q = √(1 - λ1²/(λ0 λ2)) of the eq. 6.12 spectrum, ζ = α_g/ω_g > 0.

    Uses λ2/λ0 = ω_g² and λ1/λ0 = ω_g (2/π) arccos(ζ)/√(1-ζ²) (one-sided moments), which for
    ζ > 1 continues analytically to ω_g (2/π) arccosh(ζ)/√(ζ²-1) and equals 2ω_g/π at ζ = 1
    (checked against quadrature in the tests, ζ from 0.02 to 2.5). q rises monotonically from 0
    to 1, so ζ can be read back from a measured q for broadband (ζ ≥ 1) motion too.
    """
    z = np.asarray(zeta, dtype=np.float64)
    with np.errstate(invalid="ignore", divide="ignore"):
        below = np.arccos(np.minimum(z, 1.0)) / np.sqrt(1.0 - np.minimum(z, 1.0) ** 2)
        above = np.arccosh(np.maximum(z, 1.0)) / np.sqrt(np.maximum(z, 1.0) ** 2 - 1.0)
    ratio = (2.0 / math.pi) * np.where(z < 1.0, below, np.where(z > 1.0, above, 1.0))
    return np.asarray(np.sqrt(np.maximum(1.0 - ratio**2, 0.0)))


#: Largest bandwidth ratio ζ = α_g/ω_g read from a measured q (q = 0.918 there; above it q
#: changes too little with ζ for a noisy STFT estimate to resolve).
ZETA_MAX = 3.0
_ZETA_TABLE = np.linspace(1e-3, ZETA_MAX, 1600)
_Q_TABLE = vanmarcke_q(_ZETA_TABLE)


def fixed_window_floor(window_s: float) -> float:
    """Lowest frequency [rad/s] a fixed window of ``window_s`` resolves: one cycle in it."""
    return 2 * math.pi / window_s


def smooth(
    values: NDArray[np.float64],
    kernel: NDArray[np.float64],
    mass: NDArray[np.float64] | None = None,
) -> NDArray[np.float64]:
    """Kernel average normalised by the kernel's mass inside the series (no edge loss).

    ``mass`` is :func:`kernel_mass` of the series' length, when the caller keeps it: a fit
    smooths many series of one length with one kernel.
    """
    num = np.convolve(values, kernel, mode="same")
    den = kernel_mass(values.size, kernel) if mass is None else mass
    return np.asarray(num / den)


def kernel_mass(size: int, kernel: NDArray[np.float64]) -> NDArray[np.float64]:
    """The kernel's mass inside a series of ``size`` samples, at each sample: the
    denominator of :func:`smooth`."""
    return np.asarray(np.convolve(np.ones(size), kernel, mode="same"))


def crossing_density(
    data: NDArray[np.float64], dt_s: float, frames: NDArray[np.float64], window_s: float
) -> NDArray[np.float64]:
    """Zero crossings per second (both directions) at ``frames`` [s], Hann-smoothed.

    The crossings are binned on the samples and smoothed by :func:`smooth`'s kernel average,
    linearly interpolated between samples at ``frames``; the average is evaluated at the
    samples the frames need only (:func:`smooth_at`), so the work and the memory scale with
    the frames, not with the samples times the kernel.
    """
    n = data.size
    position = crossing_positions(data)
    idx = np.minimum(position.astype(np.int64), n - 2)  # a crossing at the last sample
    frac = position - idx
    # Split each crossing between the two neighbouring samples (linear binning): smooth, unbiased.
    counts = np.asarray(
        np.bincount(idx, 1.0 - frac, minlength=n) + np.bincount(idx + 1, frac, minlength=n),
        dtype=np.float64,
    )
    del position, idx, frac
    kernel = hann_kernel(window_s, dt_s)
    # np.interp on the sample times: a frame on a sample takes that sample's value.
    where = np.clip(np.asarray(frames, dtype=np.float64) / dt_s, 0.0, n - 1.0)
    nearest = np.rint(where)
    where = np.where(np.abs(where - nearest) < 1e-9, nearest, where)
    low = np.minimum(np.floor(where).astype(np.int64), n - 2)
    share = where - low
    needed = np.unique(np.concatenate([low, low[share > 0] + 1]))
    rate = smooth_at(counts, kernel, needed) / dt_s
    at_low = rate[np.searchsorted(needed, low)]
    at_high = rate[np.searchsorted(needed, np.where(share > 0, low + 1, low))]
    return np.asarray(np.where(share > 0, at_low * (1.0 - share) + at_high * share, at_low))


def smooth_at(
    values: NDArray[np.float64], kernel: NDArray[np.float64], at: NDArray[np.int64]
) -> NDArray[np.float64]:
    """:func:`smooth` of ``values`` at the indices ``at`` only (odd, symmetric ``kernel``):
    the kernel average over the samples inside the series, a block of indices at a time.

    The samples around each index are rows of a window view of the series padded with a
    kernel's half of zeros at each end (and the mask of samples inside, of the ones padded
    alike): the same rows as gathering each index's offsets, clipping them and zeroing those
    outside, at a fraction of the cost (:func:`crossing_density` 2.4 → 0.9 ms per component of
    the benchmark catalogue, the same values; docs/benchmarks.md, issue 29).
    """
    half = kernel.size // 2
    padded = np.zeros(values.size + 2 * half)
    padded[half : half + values.size] = values
    mask = np.zeros(values.size + 2 * half)
    mask[half : half + values.size] = 1.0
    rows_of = np.lib.stride_tricks.sliding_window_view(padded, kernel.size)
    inside_of = np.lib.stride_tricks.sliding_window_view(mask, kernel.size)
    out = np.empty(at.size)
    step = max(1, (1 << 21) // kernel.size)  # 16 MB of gathered values per block
    for start in range(0, at.size, step):
        rows = at[start : start + step]
        out[start : start + step] = (rows_of[rows] @ kernel) / (inside_of[rows] @ kernel)
    return out


def moment_weights(omega: NDArray[np.float64]) -> NDArray[np.float64]:
    """Weights of the trapezoid rule in ω times ω⁰, ω¹, ω², shape (m, 3): ``psd @ weights``
    holds λ0, λ1, λ2 of each frame (:func:`spectral_moments`)."""
    step = np.diff(omega)
    trapezoid = np.zeros(omega.size)
    trapezoid[:-1] += 0.5 * step
    trapezoid[1:] += 0.5 * step
    return np.stack([trapezoid, trapezoid * omega, trapezoid * omega**2], axis=1)


def spectral_moments(
    omega: NDArray[np.float64],
    psd: NDArray[np.float64],
    weights: NDArray[np.float64] | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """λ0, λ1, λ2 of the one-sided S at each frame (trapezoid in ω) [(m/s²)²·(rad/s)^k].

    One matrix product with the trapezoid weights times ω^k (:func:`moment_weights`, given
    or computed here) instead of a trapezoid per moment: the same sums but for rounding (the
    largest relative difference on the benchmark catalogue: docs/benchmarks.md, issue 29), at
    a fraction of the cost (three passes of temporaries over frames × frequencies each).
    """
    weights = moment_weights(omega) if weights is None else weights
    lam = np.asarray(psd @ weights, dtype=np.float64)
    return lam[..., 0], lam[..., 1], lam[..., 2]


def window_spread_rad_s(window: NDArray[np.float64], dt_s: float) -> float:
    """RMS spectral spread σ_w of a window's power response [rad/s] (Parseval of w')."""
    dw = np.diff(window) / dt_s
    return math.sqrt(float(np.sum(dw**2)) / float(np.sum(window**2)))


#: Smallest P-onset signal-to-noise ratio (RMS over ``_SNR_WINDOW_S`` after the pick over the
#: RMS before it) for the pick to be used as the time origin by ``t0="auto"``.
P_PICK_MIN_SNR = 3.0
#: Shortest pre-event section [s] (before the pick, after any leading constant run) for a pick
#: to count as reliable: the noise level before it must be measured, not guessed.
P_PICK_MIN_NOISE_S = 1.0
#: Largest RMS ratio of the second half of the pre-event section over its first half for a
#: reliable pick (pre-event noise is steady; a smoothly rising motion is not).
P_PICK_MAX_NOISE_GROWTH = 2.0
#: Largest RMS of the pre-event section over the record's peak |x| for a reliable pick.
P_PICK_MAX_NOISE_FRACTION = 0.01
_SNR_WINDOW_S = 2.0


@dataclass(frozen=True)
class Arrivals:
    """Picked P onset and S arrival in record time [s] (None when not found), and the pick's
    confidence: ``p_snr`` (RMS over 2 s after the onset over the RMS of the pre-event section
    before it, floored at the quantisation noise), ``noise_s`` (that section's length [s]) and
    ``noise_growth`` (RMS of its second half over its first half) and ``noise_fraction`` (its
    RMS over the record's peak |x|)."""

    p_onset_s: float | None
    s_arrival_s: float | None
    p_snr: float = math.nan
    noise_s: float = 0.0
    noise_growth: float = math.nan
    noise_fraction: float = math.nan

    @property
    def reliable(self) -> bool:
        """A P onset with SNR ≥ :data:`P_PICK_MIN_SNR` after ≥ :data:`P_PICK_MIN_NOISE_S` of
        pre-event noise that is steady (RMS of its second half < :data:`P_PICK_MAX_NOISE_GROWTH`
        × that of its first half; a motion rising smoothly from zero, without noise before it,
        has no onset an AIC can place), and quiet: its RMS < :data:`P_PICK_MAX_NOISE_FRACTION`
        × the record's peak (a record cut at the trigger starts in the motion itself)."""
        return (
            self.p_onset_s is not None
            and self.p_snr >= P_PICK_MIN_SNR
            and self.noise_s >= P_PICK_MIN_NOISE_S
            and self.noise_growth < P_PICK_MAX_NOISE_GROWTH
            and self.noise_fraction < P_PICK_MAX_NOISE_FRACTION
        )


def quantum(data: NDArray[np.float64]) -> float:
    """Quantisation step of the samples: the smallest non-zero difference between neighbours
    (0 when all samples are equal)."""
    steps = np.abs(np.diff(data))
    steps = steps[steps > 0]
    return float(steps.min()) if steps.size else 0.0


def aic_curve(segment: NDArray[np.float64], noise_variance: float) -> NDArray[np.float64]:
    """Maeda's AIC, ``k log σ²(x[:k]) + (n - k - 1) log σ²(x[k:])``, for k = 1 .. n - 1
    (index k - 1), each variance raised by ``noise_variance``.

    Maeda (1985), "A method for reading and checking phase times in auto-processing system of
    seismic wave data", Zisin 38, 365-379. The floor keeps the logarithm finite where a section
    is constant (zero padding, or quiet samples quantised to one value, where obspy's
    ``aic_simple`` gives -inf and the minimum lands on the segment edge); with the
    quantisation step q, q²/12 is the variance rounding adds to any signal.
    """
    x = segment - segment.mean()
    n = x.size
    k = np.arange(1, n, dtype=np.float64)
    c1 = np.cumsum(x)[:-1]
    c2 = np.cumsum(x * x)[:-1]
    left = np.maximum(c2 / k - (c1 / k) ** 2, 0.0)
    rest = n - k
    r1 = x.sum() - c1
    r2 = float(np.sum(x * x)) - c2
    right = np.maximum(r2 / rest - (r1 / rest) ** 2, 0.0)
    with np.errstate(divide="ignore"):
        return np.asarray(
            k * np.log(left + noise_variance) + (rest - 1) * np.log(right + noise_variance)
        )


def pick_arrivals(data: NDArray[np.float64], dt_s: float, peak_time_s: float) -> Arrivals:
    """P onset and S arrival in record time [s] by AIC minima (:func:`aic_curve`), with the P
    pick's confidence.

    P: the AIC minimum over the record start .. the peak of I_g (the change from pre-event
    noise to signal), after skipping a leading run of identical samples (zero padding: it holds
    no noise to compare with). S: the AIC minimum over P + 0.5 s .. the peak + 1 s. A minimum on
    a segment edge (within 2 % of its length) is no onset. Obspy's Baer-Kradolfer picker was
    tried first and rejected: on PEER records with long quiet pre-event sections it triggered on
    the noise (RSN 8883: 2.6 s for an onset at about 24 s).
    """
    rate = 1.0 / dt_s
    peak = min(data.size, round(peak_time_s * rate))
    floor = quantum(data) ** 2 / 12.0
    moved = np.flatnonzero(data != data[0])
    lead = int(moved[0]) if moved.size else data.size

    def onset(lo: int, hi: int) -> int | None:
        segment = data[lo:hi]
        if segment.size < 20:
            return None
        aic = aic_curve(segment, floor)
        finite = np.isfinite(aic)
        if not finite.any():
            return None
        k = int(np.argmin(np.where(finite, aic, np.inf))) + 1
        edge = max(2, segment.size // 50)
        return lo + k if edge <= k < segment.size - edge else None

    p_index = onset(lead, peak)
    if p_index is None:
        return Arrivals(None, None)
    after = data[p_index : p_index + max(2, round(_SNR_WINDOW_S * rate))]
    before = data[lead:p_index]
    noise = math.sqrt(float(np.var(before)) + floor)
    signal = math.sqrt(float(np.mean((after - before.mean()) ** 2)))
    snr = signal / noise if noise > 0 else math.inf
    half = before.size // 2
    growth = (
        math.sqrt((float(np.var(before[half:])) + floor) / (float(np.var(before[:half])) + floor))
        if half >= 2
        else math.nan
    )
    s_index = onset(p_index + round(0.5 * rate), min(data.size, peak + round(rate)))
    return Arrivals(
        p_index * dt_s,
        None if s_index is None else s_index * dt_s,
        snr,
        (p_index - lead) * dt_s,
        growth,
        noise / max(float(np.abs(data - before.mean()).max()), 1e-300),
    )


@dataclass(frozen=True)
class FrameSpectra:
    """What an ω_g estimator may use: the record and its STFT on the frame grid.

    Attributes
    ----------
    data, dt_s
        The samples [m/s²] and their interval [s].
    window_s, hop_s
        Smoothing window and frame spacing [s].
    time_s
        Frame centres [s], shape ``(n,)``.
    omega
        STFT frequencies ω ≥ 0 [rad/s], shape ``(m,)``.
    window
        The STFT window (samples).
    omega_moment_rad_s
        √(λ2/λ0 - σ_w²) per frame [rad/s] (NaN where undefined).
    spectrum
        Computes the two-sided PSD, shape ``(n, m)``: :attr:`psd`, computed when an estimator
        first asks for it (frames × frequencies is the largest array of the features: on a
        long record, several times the record's size).
    """

    data: NDArray[np.float64]
    dt_s: float
    window_s: float
    hop_s: float
    time_s: NDArray[np.float64]
    omega: NDArray[np.float64]
    window: NDArray[np.float64]
    omega_moment_rad_s: NDArray[np.float64]
    spectrum: Callable[[], NDArray[np.float64]] = field(repr=False, compare=False)

    @functools.cached_property
    def psd(self) -> NDArray[np.float64]:
        """STFT two-sided PSD, shape ``(n, m)`` [(m/s²)²·s/rad] (computed on first use)."""
        return self.spectrum()


@dataclass(frozen=True)
class FrequencyEstimate:
    """An estimator's ω_g(t) [rad/s] on the frame grid (NaN where undefined), the smoothing
    kernel it applied (unit sum, on the frame grid), which the fit applies to the model too,
    the lowest ω_g it resolves at each frame [rad/s] (None: one cycle per ``window_s``) and,
    when its window changes from frame to frame, each frame's window length [s]."""

    omega_g_rad_s: NDArray[np.float64]
    kernel: NDArray[np.float64]
    floor_rad_s: NDArray[np.float64] | None = None
    window_s: NDArray[np.float64] | None = None


class FrequencyEstimator(Protocol):
    """An ω_g(t) estimator: frame spectra in, :class:`FrequencyEstimate` out."""

    __name__: str

    def __call__(self, frames: FrameSpectra, /) -> FrequencyEstimate: ...


def zero_crossing_estimate(frames: FrameSpectra) -> FrequencyEstimate:
    """π × the smoothed density of zero crossings (module docstring)."""
    rate = crossing_density(frames.data, frames.dt_s, frames.time_s, frames.window_s)
    return FrequencyEstimate(
        np.where(rate > 0, math.pi * rate, np.nan), hann_kernel(frames.window_s, frames.hop_s)
    )


def moment_estimate(frames: FrameSpectra) -> FrequencyEstimate:
    """√(λ2/λ0 - σ_w²) of the STFT frame (module docstring)."""
    kernel = _power_kernel(frames.window, frames.dt_s, frames.hop_s)
    return FrequencyEstimate(frames.omega_moment_rad_s, kernel)


def ridge_estimate(frames: FrameSpectra) -> FrequencyEstimate:
    """Frequency of the STFT maximum, parabolic interpolation (module docstring)."""
    kernel = _power_kernel(frames.window, frames.dt_s, frames.hop_s)
    return FrequencyEstimate(_ridge(frames.omega, frames.psd), kernel)


def wavelet_ridge_estimate(frames: FrameSpectra) -> FrequencyEstimate:
    """Maximum of the Morlet spectrum (module docstring)."""
    from stepframe.stochastic.transforms import cone_of_influence

    omega_g = _wavelet_ridge(frames.data, frames.dt_s, frames.hop_s, frames.time_s.size)
    # The Morlet's time support shrinks with frequency; no single kernel describes it, so the
    # fit compares unsmoothed (its Gaussian time spread, 6/ω, is under a second above 1 Hz).
    # Its floor: its lowest band, and the bands clear of the record's ends (cone of influence).
    duration = (frames.data.size - 1) * frames.dt_s
    lowest = _wavelet_ridge_lowest_band(frames.data.size, frames.dt_s)
    cone = cone_of_influence(frames.time_s, duration, _RIDGE_MORLET_Q)
    return FrequencyEstimate(omega_g, np.ones(1), np.maximum(lowest, cone))


def multiwindow_estimate(frames: FrameSpectra) -> FrequencyEstimate:
    """Moment over windows of three local periods, at least ``window_s`` (module docstring)."""
    from stepframe.stochastic.multiwindow import multiwindow_frequency

    found = multiwindow_frequency(frames.data, frames.dt_s, frames.time_s, frames.window_s)
    # Where a frame's window is longer than window_s, the fit's model is smoothed less than
    # the estimate (docs/stochastic-features.md measures what that costs).
    kernel = hann_kernel(frames.window_s, frames.hop_s)
    return FrequencyEstimate(found.omega_rad_s, kernel, found.floor_rad_s, found.window_s)


#: The ω_g(t) estimators by name (:data:`stepframe.stochastic.methods.FrequencyMethod` names them).
FREQUENCY_ESTIMATORS: dict[str, FrequencyEstimator] = {
    "zero-crossing": zero_crossing_estimate,
    "ridge": ridge_estimate,
    "moment": moment_estimate,
    "wavelet-ridge": wavelet_ridge_estimate,
    "multiwindow": multiwindow_estimate,
}
#: Names of the registered estimators, cheap to dear.
FREQUENCY_METHODS: tuple[str, ...] = tuple(FREQUENCY_ESTIMATORS)


def _estimator(frequency: str | FrequencyEstimator) -> FrequencyEstimator:
    if callable(frequency):
        return frequency
    try:
        return FREQUENCY_ESTIMATORS[frequency]
    except (KeyError, TypeError):
        raise InputError(
            f"frequency = {frequency!r}, expected one of {FREQUENCY_METHODS} or an estimator"
        ) from None


def _estimator_name(frequency: str | FrequencyEstimator) -> str:
    return frequency if isinstance(frequency, str) else getattr(frequency, "__name__", "custom")


#: Memory of the features beside the record [bytes per sample], per estimator, measured on
#: records of 6·10⁵ and 3·10⁶ samples at dt = 5 ms (docs/benchmarks.md, "Memory"): the
#: estimators that work on the samples hold a few record-long arrays at once; the multiwindow
#: estimator's smoothing bank holds one per rung of its ladder.
FEATURES_BYTES_PER_SAMPLE = {
    "zero-crossing": 48.0,
    "moment": 48.0,
    "ridge": 48.0,
    "multiwindow": 420.0,
    "wavelet-ridge": 120.0,
}
#: Memory of the features whatever the record's length [bytes]: a block of STFT frames and
#: the fit's small arrays.
FEATURES_FIXED_BYTES = 64 * 1024**2


def features_memory_bytes(
    npts: int,
    dt_s: float,
    frequency: FrequencyMethod | FrequencyEstimator = DEFAULT_FREQUENCY_METHOD,
    *,
    window_s: float = DEFAULT_WINDOW_S,
    hop_s: float = DEFAULT_HOP_S,
) -> float:
    """The peak memory :func:`record_features` needs beside the record [bytes] (an estimate:
    :data:`FEATURES_BYTES_PER_SAMPLE` per sample; the whole PSD, frames × frequencies, for
    the estimators that read it, and the Morlet bands for the wavelet ridge; a custom
    estimator is counted as one that reads the PSD)."""
    name = _estimator_name(frequency)
    per_sample = FEATURES_BYTES_PER_SAMPLE.get(name, 48.0)
    frames = npts * dt_s / max(hop_s, dt_s) + 1
    bins = 2 ** max(math.ceil(math.log2(max(window_s / dt_s, 1.0))), 4) // 2 + 1
    need = FEATURES_FIXED_BYTES + per_sample * npts
    if name == "ridge" or name not in FEATURES_BYTES_PER_SAMPLE:
        need += 2.2 * 8 * frames * bins  # the PSD and its power temporaries
    if name == "wavelet-ridge":
        need += 2 * 8 * frames * 160  # the bands' power, and the ridge's weighted copy
    return need


def record_features(
    record_or_array: Trace | ArrayLike,
    dt_s: float | None = None,
    *,
    frequency: FrequencyMethod | FrequencyEstimator = DEFAULT_FREQUENCY_METHOD,
    t0: TimeOrigin = "auto",
    window_s: float = DEFAULT_WINDOW_S,
    hop_s: float = DEFAULT_HOP_S,
    threshold: float = DEFAULT_DURATION_THRESHOLD,
    omega_max_rad_s: float | None = None,
    fft: FftBackend = "scipy",
    peak_method: PeakMethod = "envelope",
    incomplete: bool | None = None,
) -> RecordFeatures:
    """Features of one record (definitions and smoothing in the module docstring).

    Parameters
    ----------
    record_or_array
        ``obspy.Trace`` in m/s², or an array (then ``dt_s`` [s] is needed).
    dt_s
        Sampling interval [s] of an array; given with a Trace, it overrides the trace's.
    frequency
        ω_g estimator: a name of :data:`FREQUENCY_ESTIMATORS`
        (:data:`~stepframe.stochastic.methods.DEFAULT_FREQUENCY_METHOD`, ``"zero-crossing"``, by
        default; ``"ridge"``, ``"moment"``, ``"wavelet-ridge"``, ``"multiwindow"``) or a
        :class:`FrequencyEstimator`.
    t0
        Time origin: ``"auto"`` (default: the picked P onset when the pick is reliable,
        :attr:`Arrivals.reliable`, else the record start), ``"start"`` (record start) or
        ``"p-pick"`` (the picked P onset whatever its confidence; the record start, flagged
        ``p_pick_failed``, when no onset is found). ``t0_source`` of the result says which.
    window_s, hop_s
        Smoothing window and frame spacing [s].
    threshold
        Fraction of max I_g that ends strong motion (t_dur).
    omega_max_rad_s
        Highest frequency of interest [rad/s]: an error if above the Nyquist frequency.
    fft
        FFT of the STFT: ``"pyfftw"`` or ``"scipy"``.
    peak_method
        t_max as the peak of a gamma envelope fitted to I_g (``"envelope"``, default:
        :func:`peak_time_by_envelope`) or the raw argmax of I_g (``"argmax"``).
    incomplete
        Whether the record was read cut short (flagged ``record_incomplete``); None: a Trace's
        own mark (``stats.stepframe.incomplete``), an array's none.

    Raises
    ------
    InputError
        Bad record (too short, constant, NaNs), dt too coarse for ``omega_max_rad_s``, bad options.
    """
    _estimator(frequency)  # a bad name fails before any work
    if t0 not in TIME_ORIGINS:
        raise InputError(f"t0 = {t0!r}, expected one of {TIME_ORIGINS}")
    if peak_method not in ("envelope", "argmax"):
        raise InputError(f"peak_method = {peak_method!r}, expected 'envelope' or 'argmax'")
    if not 0 < threshold < 1:
        raise InputError(f"threshold = {threshold}, expected 0 < threshold < 1")
    data, dt = record_samples(record_or_array, dt_s)
    # Finite and at most 10⁶ s (a window longer than the record is refused further on).
    validation.length("window_s", window_s)
    validation.length("hop_s", hop_s)
    check_memory(
        features_memory_bytes(data.size, dt, frequency, window_s=window_s, hop_s=hop_s),
        f"computing the features of {data.size} samples ({_estimator_name(frequency)})",
        "a shorter record"
        + (
            ""
            if _estimator_name(frequency) == "zero-crossing"
            else ", or --frequency zero-crossing"
        ),
    )
    if omega_max_rad_s is not None:
        validation.positive("omega_max_rad_s", omega_max_rad_s)
    nyquist = math.pi / dt
    if omega_max_rad_s is not None and omega_max_rad_s > nyquist:
        raise InputError(
            f"dt = {dt} s gives a Nyquist frequency of {nyquist:.4g} rad/s, below the requested "
            f"band up to {omega_max_rad_s:.4g} rad/s, expected dt < π/omega_max"
        )
    flags: list[str] = []
    # A record read cut short (--allow-short) says so in every output made from it: its strong
    # motion's end, t_dur and the late ω_g(t) may lie in what is missing.
    if incomplete is None:
        stats = getattr(record_or_array, "stats", None)
        incomplete = stats is not None and bool(stats.get("stepframe", {}).get("incomplete"))
    if incomplete:
        flags.append("record_incomplete")
    # A record clipped at the instrument's full scale lost its peaks: its I_g(t) and spectrum
    # are those of the clipped signal (ξ_p 0.71 for 0.096 on a synthetic clipped at 1/14 of
    # its peak, with no flag before).
    if clipped_plateaus(data) >= CLIP_PLATEAUS:
        flags.append("record_clipped")
    # The frames' spectral moments, a block of frames at a time: the PSD itself (frames ×
    # frequencies) is computed whole only for an estimator that asks for it.
    grid = stft_grid(data.size, dt, window_s=window_s, hop_s=hop_s)
    time_s, omega, window = grid.time_s, grid.omega_rad_s, grid.window
    lam0, lam1, lam2 = (np.empty(time_s.size) for _ in range(3))
    weights = moment_weights(omega)
    for frames, block in stft_power_blocks(data, dt, grid, fft=fft):
        lam0[frames], lam1[frames], lam2[frames] = spectral_moments(omega, block, weights)
    hop = float(time_s[1] - time_s[0]) if time_s.size > 1 else dt
    intensity = np.sqrt(np.maximum(lam0 / math.pi, 0.0))
    peak = float(intensity.max())
    spread2 = window_spread_rad_s(window, dt) ** 2
    with np.errstate(invalid="ignore", divide="ignore"):
        m2 = np.where(lam0 > 0, lam2 / lam0, np.nan) - spread2
        m1 = np.where(lam0 > 0, lam1 / lam0, np.nan)
        omega_moment = np.sqrt(np.where(m2 > 0, m2, np.nan))
        q = np.sqrt(np.clip(1.0 - m1**2 / m2, 0.0, 1.0))
    zeta = np.interp(q, _Q_TABLE, _ZETA_TABLE)
    estimate = _estimator(frequency)(
        FrameSpectra(
            data, dt, window_s, hop, time_s, omega, window, omega_moment,
            spectrum=functools.partial(_whole_psd, data, dt, window_s, hop_s, fft),
        )
    )  # fmt: skip
    omega_g, omega_kernel = estimate.omega_g_rad_s, estimate.kernel
    floor = (
        np.full(time_s.shape, fixed_window_floor(window_s))
        if estimate.floor_rad_s is None
        else np.asarray(estimate.floor_rad_s, dtype=np.float64)
    )
    alpha_g = zeta * np.where(np.isfinite(omega_moment), omega_moment, omega_g)
    p_onset = s_arrival = None
    t0_s = 0.0
    i_peak = int(np.argmax(intensity))
    t_peak = float(time_s[i_peak])
    t_peak_se: float | None = None
    if peak_method == "envelope":
        fitted_peak = peak_time_by_envelope(time_s, intensity, window_s)
        if fitted_peak is None or not time_s[0] < fitted_peak[0] < time_s[-1]:
            flags.append("envelope_fit_failed")
        else:
            t_peak, t_peak_se = fitted_peak
    t0_source = "start"
    p_snr: float | None = None
    if t0 in ("p-pick", "auto"):
        arrivals = pick_arrivals(data, dt, float(time_s[i_peak]))
        p_onset, s_arrival = arrivals.p_onset_s, arrivals.s_arrival_s
        p_snr = None if p_onset is None else arrivals.p_snr
        usable = p_onset is not None and p_onset < t_peak
        if t0 == "auto":
            usable = usable and arrivals.reliable
        if usable:
            assert p_onset is not None
            t0_s, t0_source = p_onset, "p-pick"
        else:
            p_onset = None
            if t0 == "p-pick":
                flags.append("p_pick_failed")
    t_max = t_peak - t0_s
    if t_max <= 0:
        t_max = hop
        flags.append("peak_at_origin")
    elif window_s > WINDOW_PER_T_MAX * t_max:
        flags.append("window_long")
        t_peak_se = None  # it would not cover the window's bias (WINDOW_PER_T_MAX)
    above = np.flatnonzero(intensity >= threshold * peak)
    t_dur = float(time_s[above[-1]]) - t0_s
    if above[-1] == time_s.size - 1:
        flags.append("duration_truncated")
    if t_dur <= t_max:
        t_dur = t_max + hop
        flags.append("duration_at_floor")
    strong = (time_s >= t0_s) & (intensity >= threshold * peak)
    finite = np.isfinite(omega_g[strong])
    if finite.sum() < 5:
        flags.append("few_frequency_estimates")
    else:
        if np.nanmax(omega_g[strong]) > 0.5 * nyquist:
            flags.append("band_limited")
        resolved = omega_g[strong][finite] >= floor[strong][finite]
        if np.mean(~resolved) > BELOW_FLOOR_SHARE:
            flags.append("omega_below_floor")
    return RecordFeatures(
        time_s=time_s,
        intensity=np.asarray(intensity),
        omega_g_rad_s=np.asarray(omega_g, dtype=np.float64),
        alpha_g_rad_s=np.asarray(alpha_g, dtype=np.float64),
        peak_intensity=peak,
        t0_s=t0_s,
        t_max_s=t_max,
        t_dur_s=t_dur,
        dt_s=dt,
        window_s=window_s,
        hop_s=hop,
        frequency_method=_estimator_name(frequency),
        threshold=threshold,
        omega_kernel=omega_kernel,
        nyquist_rad_s=nyquist,
        p_onset_s=p_onset,
        s_arrival_s=s_arrival,
        flags=tuple(flags),
        t_max_stderr_s=t_peak_se,
        t0_source=t0_source,
        p_pick_snr=p_snr,
        omega_floor_rad_s=floor,
        omega_window_s=estimate.window_s,
    )


def _whole_psd(
    data: NDArray[np.float64], dt_s: float, window_s: float, hop_s: float, fft: FftBackend
) -> NDArray[np.float64]:
    """The record's whole STFT PSD (:func:`~stepframe.stochastic.transforms.stft_power`)."""
    return stft_power(data, dt_s, window_s=window_s, hop_s=hop_s, fft=fft)[2]


#: Factor on the envelope fit's Jacobian standard error of t_max, so that the truth lies within
#: 2 SE in ≥ 90 % of synthetic eq. 6.12 records: the 90th and 95th percentiles of |error|/(2 SE)
#: over 60 records of each of three parameter sets were ≤ 1.41 and ≤ 1.62; 1.6 still left one
#: set of 40 other seeds at 88 %, so 2.0 (bench/se_coverage.py; docs/stochastic-features.md).
#: Since the fit keeps only the frames around the motion (:data:`ENVELOPE_SPAN`), whose quiet
#: frames had shrunk s², the Jacobian error is about 1.3 times larger and the factor 1.5 (t_max
#: within 2 SE in 100 % of seeds 1000-1039 and 5000-5039 of all three sets).
T_MAX_SE_CALIBRATION = 1.5


#: Fraction of max I_g that bounds the frames the envelope is fitted to (a window beyond the
#: first and last frame at or above it): the fit does not depend on how much quiet record
#: surrounds the motion.
ENVELOPE_SPAN = 0.05


class _GammaEnvelope:
    """Residuals of the gamma envelope P·(τ/τ_p)^a·exp(a(1 - τ/τ_p)), τ = t - onset, against I_g,
    over its peak, and their analytic Jacobian in x = (onset, τ_p, P, a).

    With u = τ/τ_p and g = ln u + 1 - u the shape is s = exp(a·g) for t > onset and 0 before;
    ∂s/∂u = s·a·(1/u - 1), ∂u/∂onset = -1/τ_p, ∂u/∂τ_p = -u/τ_p, ∂s/∂a = s·g. Before the onset
    the curve is flat zero and every derivative is zero (the one-sided limit at u → 0⁺ is zero
    for a > 1 and unbounded below it; no sample lies exactly at the onset in practice). The
    trust-region solver asks the residuals and the Jacobian at the same point: the shared
    terms are kept for that point.
    """

    def __init__(self, time_s: NDArray[np.float64], intensity: NDArray[np.float64]) -> None:
        self.time_s = time_s
        self.intensity = intensity
        self.scale = float(np.max(intensity))
        self._at: bytes = b""
        self._terms: tuple[NDArray[np.float64], ...] = ()

    def _terms_at(self, x: NDArray[np.float64]) -> tuple[NDArray[np.float64], ...]:
        key = np.asarray(x, dtype=np.float64).tobytes()
        if key != self._at:
            onset, rise, _, a = x
            u = np.maximum(self.time_s - onset, 0.0) / rise
            after = u > 0
            safe_u = np.where(after, u, 1.0)
            g = np.where(after, np.log(safe_u) + 1.0 - u, 0.0)
            shape = np.where(after, np.exp(a * g), 0.0)
            self._at, self._terms = key, (u, safe_u, g, shape)
        return self._terms

    def residual(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """(P·s - I_g)/max I_g at the frames [-]."""
        shape = self._terms_at(x)[3]
        return np.asarray((x[2] * shape - self.intensity) / self.scale)

    def jacobian(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """∂ residual/∂x, frames × 4 [1/s, 1/s, 1/(I_g unit), -]."""
        _, rise, amp, a = x
        u, safe_u, g, shape = self._terms_at(x)
        ds_du = shape * a * (1.0 / safe_u - 1.0)  # zero before the onset, where shape is zero
        jac = np.empty((u.size, 4))
        jac[:, 0] = -amp * ds_du / rise
        jac[:, 1] = -amp * ds_du * u / rise
        jac[:, 2] = shape
        jac[:, 3] = amp * shape * g
        return np.asarray(jac / self.scale)


def peak_time_by_envelope(
    time_s: NDArray[np.float64], intensity: NDArray[np.float64], window_s: float = DEFAULT_WINDOW_S
) -> tuple[float, float] | None:
    """Peak time [s] of the gamma envelope P·(τ/τ_p)^a·exp(a(1 - τ/τ_p)), τ = t - onset, fitted
    to I_g(t) by least squares (onset, peak time, P, a free), and its standard error [s];
    None when the fit fails.

    The envelope averages the random fluctuations of I_g around its peak, which make the raw
    argmax wander by about a window either side (20 % median error of t_max on synthetics).
    The standard error is ``s² (JᵀJ)⁻¹`` carried to onset + τ_p, inflated by the number of
    frames used per ``window_s`` (frames closer than a window share data), then multiplied by
    :data:`T_MAX_SE_CALIBRATION`: the residuals of I_g about the envelope are correlated over
    more than a window and the envelope shape is not the record's, so the Jacobian error alone
    covered the truth within 2 SE in only 72-82 % of synthetic eq. 6.12 records.

    The trust-region fit uses the analytic Jacobian (:class:`_GammaEnvelope`): one residual
    pass per iteration instead of five with finite differences, 8.1 → 5.3 ms per component
    with the same peak times (within 0.8 ms on 400 components; docs/benchmarks.md, issue 29).
    MINPACK's Levenberg-Marquardt on a sine transform of the bounds (what the eq. 6.10 fit
    uses) was 2.6 ms but ended in another local minimum on 15 % of those components (peak
    times up to 1.6 s apart), so it is not used here.
    """
    from scipy.optimize import least_squares

    i_peak = int(np.argmax(intensity))
    peak = float(intensity[i_peak])
    t_peak = float(time_s[i_peak])
    rising = np.flatnonzero(intensity[: i_peak + 1] < 0.05 * peak)
    onset0 = float(time_s[rising[-1]]) if rising.size else float(time_s[0]) - 1.0
    onset0 = min(onset0, t_peak - 0.5)

    # The frames from a window before I_g first reaches ENVELOPE_SPAN of its peak to a window
    # after it last does: quiet frames beyond add residuals of about zero, which shrank s² and
    # thinned the ~200 frames kept to a few on the rise (a 40-s record, t_max 4.56 ± 0.93 s,
    # gave 2.74 ± 0.16 s with its quiet coda to 400 s).
    above = np.flatnonzero(intensity >= ENVELOPE_SPAN * peak)
    span = (time_s >= time_s[above[0]] - window_s) & (time_s <= time_s[above[-1]] + window_s)
    time_s, intensity = time_s[span], intensity[span]
    # A smooth 4-parameter curve: ~200 frames fix it as well as all of them, at a fraction of
    # the cost.
    stride = max(1, time_s.size // 200)
    time_s, intensity = time_s[::stride], intensity[::stride]
    envelope = _GammaEnvelope(time_s, intensity)
    x0 = np.array([onset0, t_peak - onset0, peak, 2.0])
    lower = [float(time_s[0]) - 60.0, 1e-3, 0.0, 0.05]
    upper = [t_peak, float(time_s[-1] - time_s[0]) + 60.0, 10 * peak, 50.0]
    try:
        # Tolerances of 1e-6 locate the peak to well under a frame; tighter only costs time.
        result = least_squares(
            envelope.residual, x0, jac=envelope.jacobian, bounds=(lower, upper), method="trf",
            ftol=1e-6, xtol=1e-6,
        )  # fmt: skip
    except ValueError:
        return None
    if not result.success:
        return None
    spacing = float(time_s[1] - time_s[0]) if time_s.size > 1 else window_s
    inflation = max(1.0, window_s / spacing)
    cov = least_squares_covariance(np.asarray(result.jac, dtype=np.float64), result.fun, inflation)
    grad = np.array([1.0, 1.0, 0.0, 0.0])  # ∂(onset + τ_p)/∂x
    se = math.sqrt(max(float(grad @ cov @ grad), 0.0))
    return float(result.x[0] + result.x[1]), T_MAX_SE_CALIBRATION * se


def _power_kernel(window: NDArray[np.float64], dt_s: float, hop_s: float) -> NDArray[np.float64]:
    """The STFT's time weighting w² resampled on the frame grid (unit sum)."""
    t = (np.arange(window.size) - window.size // 2) * dt_s
    half = max(1, int(t[-1] // hop_s))
    grid = np.arange(-half, half + 1) * hop_s
    k = np.interp(grid, t, window**2)
    return np.asarray(k / k.sum())


#: Relative bandwidth ω/σ of the wavelet-ridge estimator's Morlet bands.
_RIDGE_MORLET_Q = 6.0


def _wavelet_ridge_lowest_band(npts: int, dt_s: float) -> float:
    """The wavelet ridge's lowest band [rad/s]: q cycles in the record, at least 0.2 rad/s."""
    return max(2 * math.pi / (npts * dt_s) * _RIDGE_MORLET_Q, 0.2)


def _wavelet_ridge(
    data: NDArray[np.float64], dt_s: float, hop_s: float, n_frames: int
) -> NDArray[np.float64]:
    """Ridge of the Morlet spectrum on the frame grid, parabola in log ω through three bands."""
    from stepframe.stochastic.transforms import wavelet_power

    nyquist = math.pi / dt_s
    low = _wavelet_ridge_lowest_band(data.size, dt_s)
    omega = np.geomspace(low, 0.8 * nyquist, 160)
    _, omega, psd = wavelet_power(
        data, dt_s, hop_s=hop_s, omega_rad_s=omega, morlet_q=_RIDGE_MORLET_Q
    )
    # Ridge of |u|² = S·2σ_j/√π ∝ S·ω (the band's power, not its density): a line's band power
    # peaks at its frequency, while its density (divided by σ_j ∝ ω_j) peaks ~1/q² lower.
    psd = psd[:n_frames] * omega[None, :]
    k = np.clip(np.argmax(psd, axis=1), 1, omega.size - 2)
    rows = np.arange(psd.shape[0])
    with np.errstate(divide="ignore"):
        y0, y1, y2 = (np.log(psd[rows, k + j]) for j in (-1, 0, 1))
    denom = y0 - 2 * y1 + y2
    ok = np.isfinite(denom) & (denom < 0)
    shift = np.where(ok, 0.5 * (y0 - y2) / np.where(ok, denom, -1.0), 0.0)
    log_step = math.log(omega[1] / omega[0])
    out = omega[k] * np.exp(np.clip(shift, -0.5, 0.5) * log_step)
    return np.asarray(np.where(psd[rows, k] > 0, out, np.nan))


def _ridge(omega: NDArray[np.float64], psd: NDArray[np.float64]) -> NDArray[np.float64]:
    """Frequency of the maximum of each frame, refined by a parabola through three bins."""
    k = np.clip(np.argmax(psd[:, 1:], axis=1) + 1, 1, omega.size - 2)
    rows = np.arange(psd.shape[0])
    y0, y1, y2 = psd[rows, k - 1], psd[rows, k], psd[rows, k + 1]
    denom = y0 - 2 * y1 + y2
    shift = np.where(denom < 0, 0.5 * (y0 - y2) / np.where(denom < 0, denom, -1.0), 0.0)
    d_omega = omega[1] - omega[0]
    out = omega[k] + np.clip(shift, -0.5, 0.5) * d_omega
    return np.asarray(np.where(y1 > 0, out, np.nan))
