"""ω_g(t) by a multi-window spectral moment: each frame's window holds a fixed number of periods.

The 2-s window of the other estimators resolves nothing below about 2π/2 s = π rad/s; a frame's
band (Example 4: 0.65-6.46 rad/s) lies mostly below it. Here every frame gets a window of
``periods`` cycles of its own frequency (constant Q), never shorter than ``window_s``, so the
estimate is the 2-s one where the motion is fast and reaches down to ``2π·periods/T`` on a record
of T seconds where it is slow.

Method (all sums on the frame grid, every window a unit-sum Hann kernel of length L):

1. Each frame's bin collects its samples: the count, the zero crossings (the crossing positions of
   :func:`stepframe.stochastic.transforms.crossing_positions`), Σx² and Σẋ², ẋ the FFT derivative
   of the record extended by its mirror image (exact up to Nyquist, and no step at the ends).
2. A ladder of window lengths L_k = ``window_s``·2^(k/4) up to the record length: every bin series
   is smoothed by every window in one batched FFT convolution.
3. A pilot frequency: π × the crossing rate at the shortest L_k holding 4·``periods`` crossings
   (twice what the estimate needs: a steadier rate, and less tied to the frame's own
   fluctuations). The frame's window is L(t) = 2π·``periods``/pilot, clipped to
   [``window_s``, record length].
4. The estimate: ω_g(t)² = Σ w ẋ²/Î² ÷ Σ w x²/Î² over the window L(t), where Î²(s) is the mean
   square around bin s over twice that window (the envelope's trend). For the eq. 6.12 process
   E[ẏ²]/E[y²] = ω_g² whatever α_g (as for the crossing rate, Rice's formula); dividing by the
   envelope's trend keeps the strong part of a window from outweighing its weak part (a
   window of tens of seconds would otherwise report the strong motion's frequency late into the
   coda), while local fades still weigh less, which halves the spread of the crossing count at
   equal window. Values between ladder rungs are interpolated geometrically in L.
5. The floor: a window centred at t lies inside the record (the cone of influence) when its
   half-length is at most t's distance d(t) to the nearer end, so the lowest frequency resolved
   at t is 2π·``periods``/max(``window_s``, 2 d(t)); over the record, 2π·``periods``/T.

Bias (measured, docs/stochastic-features.md): the ratio of two windowed sums is biased high in
the mean by a few per cent when the window holds few independent cycles (+5 % at three periods
on a stationary process with ξ = 0.3, +11-14 % with ξ = 1; the medians are within 3 %); an
amplitude A(t) changing within the window adds (A'/A)² to ẋ²/x² (+0.8 % for a 1 rad/s tone
under a 120-s Hann where it rises fastest); where ω_g falls by a large factor within three of
its own periods, the window's smoothing raises the estimate, and the fit does not know the
longer windows (it models the ``window_s`` kernel only).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from stepframe.stochastic.transforms import crossing_positions, hann_kernel

#: Cycles of the local frequency in each frame's window (constant Q). Three: fewer raise the
#: ratio bias and the spread at low frequency (two: +10 % and 0.39 on a stationary ξ = 0.3
#: process at 1 rad/s against +7 % and 0.24 with three); more lengthen the windows where ω_g
#: falls (docs/stochastic-features.md).
DEFAULT_PERIODS = 3.0
#: Ratio of successive window lengths of the ladder (four rungs per doubling).
LADDER_RATIO = 2.0**0.25
#: The pilot frequency is read at the shortest window holding this many times the crossings
#: the estimate's window needs.
PILOT_FACTOR = 2.0
#: The envelope's trend that divides the energies is the mean square over this many cycles of
#: the pilot frequency, and over at least SHORTEST_TREND_FRAMES frames.
TREND_PERIODS = 10.0
SHORTEST_TREND_FRAMES = 4


@dataclass(frozen=True)
class MultiwindowFrequency:
    """ω_g(t) of :func:`multiwindow_frequency` on the frame grid.

    Attributes
    ----------
    omega_rad_s
        ω_g [rad/s] per frame (NaN where the window holds no energy, or where even the longest
        window holds fewer zero crossings than the cycles it needs).
    window_s
        Length of the Hann window each frame used [s].
    floor_rad_s
        Lowest frequency the estimator resolves at each frame [rad/s] (cone of influence).
    """

    omega_rad_s: NDArray[np.float64]
    window_s: NDArray[np.float64]
    floor_rad_s: NDArray[np.float64]


def resolution_floor(
    time_s: NDArray[np.float64], duration_s: float, window_s: float, periods: float
) -> NDArray[np.float64]:
    """Lowest frequency [rad/s] with ``periods`` cycles in a window centred at each time that
    stays inside the record of ``duration_s`` seconds (never a window under ``window_s``)."""
    edge = np.clip(np.minimum(time_s, duration_s - time_s), 0.0, None)
    return np.asarray(2 * math.pi * periods / np.maximum(window_s, 2 * edge))


def derivative(data: NDArray[np.float64], dt_s: float) -> NDArray[np.float64]:
    """dx/dt [units of x per s] by FFT of the record extended by its mirror image.

    The even extension ``x, reversed x`` is continuous where it wraps, so the derivative is
    exact up to Nyquist away from the two ends; zero padding instead would put a step at each
    end of a record that does not start and end at zero, and the step's derivative spreads
    energy at every frequency over tens of seconds of a slow record.
    """
    import scipy.fft as sfft

    n = data.size
    spectrum = sfft.rfft(np.concatenate([data, data[::-1]]))
    spectrum *= 1j * 2 * math.pi * sfft.rfftfreq(2 * n, dt_s)
    spectrum[-1] = 0.0  # the Nyquist bin's derivative is not defined for a real series
    return np.asarray(sfft.irfft(spectrum, 2 * n)[:n])


def _ladder(shortest_s: float, window_s: float, longest_s: float) -> NDArray[np.float64]:
    """Window lengths window_s·LADDER_RATIO^k (window_s itself among them) from the last at or
    below ``shortest_s`` to the first at or above ``longest_s``."""
    step = math.log(LADDER_RATIO)
    first = min(0, math.floor(math.log(shortest_s / window_s) / step))
    last = max(0, math.ceil(math.log(longest_s / window_s) / step))
    return np.asarray(window_s * LADDER_RATIO ** np.arange(first, last + 1, dtype=float))


def _smoothed(
    series: NDArray[np.float64], kernels: list[NDArray[np.float64]]
) -> NDArray[np.float64]:
    """Each row of ``series`` (shape (s, n)) convolved with each kernel, centred: (k, s, n)."""
    import scipy.fft as sfft

    n = series.shape[-1]
    half = max(k.size // 2 for k in kernels)
    nfft = sfft.next_fast_len(n + half + 1, real=True)
    bank = np.zeros((len(kernels), nfft))
    for i, k in enumerate(kernels):
        centre = k.size // 2
        bank[i, : k.size - centre] = k[centre:]  # lags 0 .. +half at the start,
        bank[i, nfft - centre :] = k[:centre]  # negative lags wrapped to the end
    product = sfft.rfft(bank, axis=-1)[:, None, :] * sfft.rfft(series, nfft, axis=-1)[None, :, :]
    return np.asarray(sfft.irfft(product, nfft, axis=-1)[..., :n])


def _at_length(
    values: NDArray[np.float64], ladder: NDArray[np.float64], length_s: NDArray[np.float64]
) -> NDArray[np.float64]:
    """values[k, j] (ladder rung k, frame j) at each frame's length, geometric interpolation
    between the two rungs around it (the rung itself where the length is on one)."""
    position = np.interp(np.log(length_s), np.log(ladder), np.arange(ladder.size, dtype=float))
    low = np.floor(position).astype(int)
    high = np.minimum(low + 1, ladder.size - 1)
    share = position - low
    frames = np.arange(values.shape[1])
    below, above = values[low, frames], values[high, frames]
    with np.errstate(divide="ignore", invalid="ignore"):
        between = np.exp((1 - share) * np.log(below) + share * np.log(above))
    return np.asarray(np.where(share > 0, between, below))


def multiwindow_frequency(
    data: NDArray[np.float64],
    dt_s: float,
    time_s: NDArray[np.float64],
    window_s: float,
    periods: float = DEFAULT_PERIODS,
) -> MultiwindowFrequency:
    """ω_g(t) [rad/s] at the frame centres ``time_s`` (uniform, from 0) by the multi-window
    moment of the module docstring.

    Parameters
    ----------
    data, dt_s
        The record [m/s²] and its sampling interval [s].
    time_s
        Frame centres [s] (the STFT frame grid: 0, hop, 2·hop, ...).
    window_s
        The shortest window [s] (the features' smoothing window).
    periods
        Cycles of the local frequency in each window.
    """
    frames = time_s.size
    hop = float(time_s[1] - time_s[0]) if frames > 1 else dt_s
    duration = (data.size - 1) * dt_s
    bins = np.minimum(np.rint(np.arange(data.size) * (dt_s / hop)).astype(int), frames - 1)
    crossing_bins = np.minimum(
        np.rint(crossing_positions(data) * (dt_s / hop)).astype(int), frames - 1
    )
    energy = np.bincount(bins, data * data, frames)
    per_bin = np.vstack(
        [
            np.bincount(bins, minlength=frames).astype(np.float64),
            np.bincount(crossing_bins, minlength=frames).astype(np.float64),
            energy,
        ]
    )
    shortest = min(window_s, SHORTEST_TREND_FRAMES * hop)
    ladder = _ladder(shortest, window_s, max(duration, window_s))
    kernels = [hann_kernel(length, hop) for length in ladder]
    samples, crossed, energy_sum = _smoothed(per_bin, kernels).transpose(1, 0, 2)
    samples = np.maximum(samples, 1e-300)  # FFT round-off around empty bins
    rate = np.clip(crossed, 0.0, None) / (samples * dt_s)  # crossings per second
    mean_square = np.clip(energy_sum, 0.0, None) / samples

    # Pilot: the shortest rung with PILOT_FACTOR times the crossings the estimate needs.
    enough = rate * ladder[:, None] >= PILOT_FACTOR * 2 * periods
    rung = np.where(enough.any(axis=0), np.argmax(enough, axis=0), ladder.size - 1)
    with np.errstate(divide="ignore"):
        cycle_s = 2 * math.pi / (math.pi * rate[rung, np.arange(frames)])  # one pilot period
    length = np.clip(periods * cycle_s, window_s, ladder[-1])
    trend = _at_length(mean_square, ladder, np.clip(TREND_PERIODS * cycle_s, shortest, ladder[-1]))
    scale = np.where(trend > 0, 1.0 / np.where(trend > 0, trend, 1.0), 0.0)
    slope = derivative(data, dt_s)
    slope_energy = np.bincount(bins, slope * slope, frames)
    weighted = np.asarray(np.vstack([energy, slope_energy]) * scale, dtype=np.float64)
    used = ladder >= window_s * (1 - 1e-9)  # the estimate's windows are never shorter
    kept = [kernel for kernel, keep in zip(kernels, used, strict=True) if keep]
    low, high = _smoothed(weighted, kept).transpose(1, 0, 2)
    with np.errstate(divide="ignore", invalid="ignore"):
        omega = np.sqrt(np.where(low > 0, np.clip(high, 0.0, None) / low, np.nan))
    # Fewer crossings than `periods` cycles hold even in the longest window: no frequency the
    # record resolves (a baseline offset, for one, leaves none, and the energy of the offset
    # would pass for a slow motion).
    cycles = rate[-1] * ladder[-1] / 2
    estimate = np.where(cycles >= periods, _at_length(omega, ladder[used], length), np.nan)
    return MultiwindowFrequency(
        estimate,
        length,
        resolution_floor(time_s, duration, window_s, periods),
    )


__all__ = [
    "DEFAULT_PERIODS",
    "MultiwindowFrequency",
    "derivative",
    "multiwindow_frequency",
    "resolution_floor",
]
