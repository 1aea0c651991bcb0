"""Compiled kernels of the moving-resonance index (:mod:`stepframe.pipeline.dynamics.resonance`):
the closeness of the record's band spectrum to the frame's frequency, the index's half-cycle
sums in one call over the history (:func:`resonance_sums`), and the passes of the resonator
bank that gives the band spectrum (:mod:`~stepframe.pipeline.dynamics.resonator_bank`).

Compiled because the index is a few operations per sample: written with numpy it was some
sixty calls over the history and the frames × bands table, 1.2-2.3 ms of fixed costs per
candidate against an exact simulation of 0.2-0.7 ms (docs/benchmarks.md, issue 26). The steps
and their names are those of the module docstring of
:mod:`~stepframe.pipeline.dynamics.resonance`; the closeness's cells (:func:`_frame_ends`) and
its place on the band grid (:func:`_band_place`) have one home each: :func:`closeness_many`
(which the numpy-facing :func:`~stepframe.pipeline.dynamics.resonance.closeness` calls) reads
them at each sample, :func:`resonance_sums` sums the same interpolation over runs of samples
in closed form (tests/pipeline/test_moving_resonance.py holds both to the definition).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from stepframe.core.jit import njit
from stepframe.structure._frequency_kernel import interval_work, swing_frequencies, zero_crossings


@njit(cache=True)
def frame_peaks(psd: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """The largest S of each frame (row) and its band (the first, on ties)."""
    n_frames, n_bands = psd.shape
    peak = np.empty(n_frames)
    ridge = np.empty(n_frames, dtype=np.int64)
    for f in range(n_frames):
        best, where = psd[f, 0], 0
        for b in range(1, n_bands):
            if psd[f, b] > best:
                best, where = psd[f, b], b
        peak[f], ridge[f] = best, where
    return peak, ridge


@njit(cache=True, inline="always")
def _frame_ends(
    psd: NDArray[np.float64],
    peak: NDArray[np.float64],
    ratio: NDArray[np.float64],
    reach: int,
    row: int,
    col: int,
    w_frac: float,
) -> tuple[float, float]:
    """c at frames ``row`` and ``row + 1`` for ω_f at ``col + w_frac`` on the band grid: the
    cells' ratios (max S within ``reach`` bands over the frame's peak, 1 for a frame without
    energy), filled in ``ratio`` where still negative, interpolated linearly in ln ω. Inlined
    into its callers (a compiled call with arrays costs some 50 ns of reference counting)."""
    n_bands = psd.shape[1]
    for f in range(row, row + 2):
        for b in range(col, col + 2):
            if ratio[f, b] < 0.0:
                best = psd[f, b]
                for c in range(max(0, b - reach), min(n_bands, b + reach + 1)):
                    best = max(best, psd[f, c])
                ratio[f, b] = best / (peak[f] if peak[f] > 0.0 else 1.0)
    low = ratio[row, col] * (1 - w_frac) + ratio[row, col + 1] * w_frac
    high = ratio[row + 1, col] * (1 - w_frac) + ratio[row + 1, col + 1] * w_frac
    return low, high


@njit(cache=True, inline="always")
def _band_place(
    omega_f: float, log_low: float, log_high: float, log_step: float, n_bands: int
) -> tuple[int, float]:
    """The band below ω_f on the grid and ω_f's fraction of the way to the next, in ln ω; ω_f
    outside the grid read at its nearer edge."""
    log_omega = math.log(omega_f) if omega_f > 0.0 else -math.inf
    band_pos = (min(max(log_omega, log_low), log_high) - log_low) / log_step
    col = min(int(band_pos), n_bands - 2)
    return col, band_pos - col


@njit(cache=True, inline="always")
def _closeness_tables(
    psd: NDArray[np.float64], omega_rad_s: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.float64], float, float, float]:
    """What the closeness reads besides S: each frame's peak and ridge band
    (:func:`frame_peaks`), the table of cell ratios, none computed yet (negative:
    :func:`_frame_ends` fills them as it needs them), and ln ω of the grid's two ends and its
    step (:func:`_band_place`)."""
    n_bands = psd.shape[1]
    peak, ridge_band = frame_peaks(psd)
    log_low = math.log(omega_rad_s[0])
    log_high = math.log(omega_rad_s[n_bands - 1])
    return (
        peak,
        ridge_band,
        np.full(psd.shape, -1.0),
        log_low,
        log_high,
        (log_high - log_low) / (n_bands - 1),
    )


@njit(cache=True)
def closeness_many(
    psd: NDArray[np.float64],
    frame_times_s: NDArray[np.float64],
    omega_rad_s: NDArray[np.float64],
    reach: int,
    time_s: NDArray[np.float64],
    omega_f_rad_s: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """c(t) at each (time, ω_f), and the record's ridge (the band of the largest S at the
    nearest frame, the later one halfway) [rad/s] there.

    The ratio of a cell (frame f, band b) is max S(·, f) over the bands within ``reach`` of b,
    over the frame's peak (1 for a frame without energy); c is that ratio interpolated linearly
    in time between frames and in ln ω between bands; ω_f outside the grid is read at its
    nearer edge, a time outside the frames at the nearer frame. Only the cells the samples
    fall between are computed (ω_f moves slowly: a few bands of each frame).
    """
    n_frames, n_bands = psd.shape
    peak, ridge_band, ratio, log_low, log_high, log_step = _closeness_tables(psd, omega_rad_s)
    t0, frame_dt = frame_times_s[0], frame_times_s[1] - frame_times_s[0]
    near = np.empty(time_s.size)
    ridge = np.empty(time_s.size)
    last_omega, last_row = math.nan, -1
    col, w_frac, low, high = 0, 0.0, 0.0, 0.0
    for i in range(time_s.size):
        position = min(max((time_s[i] - t0) / frame_dt, 0.0), n_frames - 1.0)
        row = min(int(position), n_frames - 2)
        omega_f = omega_f_rad_s[i]
        # ω_f is constant over a measured half-cycle and the samples run through each frame
        # interval in turn: the two ends of the interpolation in time change only with them.
        if omega_f != last_omega or row != last_row:
            if omega_f != last_omega:
                col, w_frac = _band_place(omega_f, log_low, log_high, log_step, n_bands)
                last_omega = omega_f
            low, high = _frame_ends(psd, peak, ratio, reach, row, col, w_frac)
            last_row = row
        t_frac = position - row
        near[i] = low * (1 - t_frac) + high * t_frac
        ridge[i] = omega_rad_s[ridge_band[int(position + 0.5)]]
    return near, ridge


@njit(cache=True)
def _half_cycle_end(
    crossings: NDArray[np.int64], first: int, start: int, n: int
) -> tuple[int, int]:
    """The last sample of the half-cycle that begins at ``start`` (the next start after it, a
    crossing's next sample, or n - 1), and the index of that crossing; the search begins at
    crossing ``first`` (the crossings ascend, so each is passed once)."""
    k = first
    while k < crossings.size and crossings[k] + 1 <= start:
        k += 1
    if k < crossings.size:
        return int(min(crossings[k] + 1, n - 1)), k
    return n - 1, k


@njit(cache=True, inline="always")
def _sum_of(values: NDArray[np.float64], first: int, stop: int) -> float:
    """Σ values[first:stop] in four interleaved partial sums: one running sum waits for each
    addition to finish (four cycles), four keep the adder busy (the work over a half-cycle,
    some 100 samples, was a sixth of the index's pass)."""
    sum_0 = sum_1 = sum_2 = sum_3 = 0.0
    i = first
    while i + 4 <= stop:
        sum_0 += values[i]
        sum_1 += values[i + 1]
        sum_2 += values[i + 2]
        sum_3 += values[i + 3]
        i += 4
    total = (sum_0 + sum_1) + (sum_2 + sum_3)
    while i < stop:
        total += values[i]
        i += 1
    return total


@njit(cache=True)
def resonance_sums(
    x_m: NDArray[np.float64],
    v_m_s: NDArray[np.float64],
    phase: NDArray[np.int8],
    record_acc_m_s2: NDArray[np.float64],
    dt_s: float,
    p_1: float,
    p_2: float,
    overturns: bool,
    backbone: NDArray[np.float64],
    psd: NDArray[np.float64],
    hop: int,
    omega_rad_s: NDArray[np.float64],
    reach: int,
    band_low_rad_s: float,
    band_high_rad_s: float,
    near_ln: float,
) -> NDArray[np.float64]:
    """The sums the moving-resonance measures are ratios of, from the n samples of motion of a
    simulation's history: its zero crossings, ω_f
    (:func:`~stepframe.structure._frequency_kernel.swing_frequencies`, the law only where ω_f
    needs it), the ground acceleration the frame felt (the scaled record, then zeros) and its
    work, the closeness, depth and ridge offset. ``backbone`` is (ω₁, ω₂, x_c, x*); frame f of
    ``psd`` is at sample f·``hop``, and the frames cover the n samples.

    Half-cycle k runs over the intervals from its first sample (0, then each zero crossing's
    next sample, before the last sample) to the next half-cycle's; its work W_k is the sum of
    its intervals' work, W_k⁺ = max(W_k, 0), and its means of c, d and ln²(ω_ridge/ω_f) the mean
    over its intervals of each interval's two ends' mean (steps 3-5 of the resonance module):
    Σ over its samples less half its two end samples, over its intervals.

    The sums over samples are taken a run at a time: within one half-cycle, one frame interval
    and one nearest frame, with ω_f constant (a measured half-cycle; a sample at a time where the
    law gives ω_f), d and the ridge offset are constant and c is linear in the sample's place in
    the frame interval (:func:`closeness_many`'s interpolation, the same cells,
    :func:`_frame_ends`), so their sums are closed forms. Some 900 runs a record instead of
    7,000 samples: the per-sample loop cost half the index (docs/benchmarks.md, issue 26).

    Returns
    -------
    numpy.ndarray
        Σ c_k d_k W_k⁺, Σ d_k W_k⁺, Σ W_k⁺, Σ c_k W_k⁺, Σ off_k d_k W_k⁺, the number of
        half-cycles, of those that stepped, the net work Σ W over all intervals, and min ω_f.
    """
    n = x_m.size
    crossings, crossing_times = zero_crossings(x_m, v_m_s, dt_s)
    omega_f_path = swing_frequencies(
        x_m, v_m_s, phase, dt_s, crossings, crossing_times, False, overturns,
        backbone[0], backbone[1], backbone[2], backbone[3], False,
    )[0]  # fmt: skip
    felt = np.zeros(n)
    shared = min(n, record_acc_m_s2.size)
    felt[:shared] = record_acc_m_s2[:shared]
    work = interval_work(x_m, v_m_s, phase, felt, dt_s, p_1, p_2)
    n_frames, n_bands = psd.shape
    peak, ridge_band, ratio, log_low, log_high, log_step = _closeness_tables(psd, omega_rad_s)
    depth_span = math.log(band_high_rad_s / band_low_rad_s) - near_ln
    log_grid = np.log(omega_rad_s)
    halfway = (hop + 1) // 2  # the first place in a frame interval nearer the next frame
    sums = np.zeros(9)
    lowest = math.inf
    last_omega = math.nan
    col, w_frac, depth, log_inside = 0, 0.0, 0.0, 0.0
    start, next_crossing = 0, 0
    row = 0  # the frame interval of the run's first sample: the runs ascend, so it only grows
    while start < n - 1:
        end, next_crossing = _half_cycle_end(crossings, next_crossing, start, n)
        cycle_work = _sum_of(work, start, end)
        phases = 0  # any phase but 0 leaves a bit set (an OR, which vectorizes; a search did not)
        for i in range(start, end + 1):
            phases |= phase[i]
        stepped = phases != 0
        # Σ over the samples start..end of c, d and the offset, and half their end values.
        near_total = depth_total = offset_total = 0.0
        near_ends = depth_ends = offset_ends = 0.0
        i = start
        while i <= end:
            omega_f = omega_f_path[i]
            while row < n_frames - 2 and i >= (row + 1) * hop:
                row += 1
            first_place = i - row * hop
            nearest = row + 1 if first_place >= halfway else row
            last = end
            if row < n_frames - 2:
                last = min(last, row * hop + hop - 1)
            if nearest == row:
                last = min(last, row * hop + halfway - 1)
            j = i
            while j < last and omega_f_path[j + 1] == omega_f:
                j += 1
            if omega_f != last_omega:
                col, w_frac = _band_place(omega_f, log_low, log_high, log_step, n_bands)
                drop = math.log(band_high_rad_s / max(omega_f, 1e-300))
                depth = min(max((drop - near_ln) / depth_span, 0.0), 1.0)
                log_inside = math.log(min(max(omega_f, band_low_rad_s), band_high_rad_s))
                lowest = min(lowest, omega_f)
                last_omega = omega_f
            low, high = _frame_ends(psd, peak, ratio, reach, row, col, w_frac)
            offset = (log_grid[ridge_band[nearest]] - log_inside) ** 2
            count = j - i + 1
            # Σ of the places i - row·hop over the run, in frame intervals.
            place_sum = 0.5 * (first_place + j - row * hop) * count / hop
            near_total += count * low + (high - low) * place_sum
            depth_total += count * depth
            offset_total += count * offset
            if i == start:
                near_ends += 0.5 * (low + (high - low) * first_place / hop)
                depth_ends += 0.5 * depth
                offset_ends += 0.5 * offset
            if j == end:
                near_ends += 0.5 * (low + (high - low) * (j - row * hop) / hop)
                depth_ends += 0.5 * depth
                offset_ends += 0.5 * offset
            i = j + 1
        count = end - start
        pumped = max(cycle_work, 0.0)
        moved = (depth_total - depth_ends) / count * pumped
        cycle_near = (near_total - near_ends) / count
        sums[0] += moved * cycle_near
        sums[1] += moved
        sums[2] += pumped
        sums[3] += pumped * cycle_near
        sums[4] += moved * ((offset_total - offset_ends) / count)
        sums[5] += 1.0
        sums[6] += 1.0 if stepped else 0.0
        sums[7] += cycle_work
        start = end
    sums[8] = lowest
    return sums


@njit(cache=True, fastmath=True)
def bank_energies(
    data: NDArray[np.floating],
    weights: NDArray[np.floating],
    powers: NDArray[np.floating],
    scale: NDArray[np.floating],
    n_frames: int,
) -> NDArray[np.floating]:
    """S = scale_j |W⁺ + W⁻|² at every frame (every hop = len(weights) - 1 samples of ``data``,
    followed by zeros up to the last frame): W⁺ stepped forwards from rest before the first
    sample, W⁻ backwards from rest after the last (:mod:`~.resonator_bank`; ``weights`` and
    ``powers`` of its ``_frame_step``, real and imaginary parts of each pass side by side, the
    bands last so that every loop over them runs on contiguous memory). Computed and returned
    in the precision of ``data`` (the arguments share it): single for the decimated bank,
    double for the reference at the record's rate."""
    hop = weights.shape[0] - 1
    n_bands = scale.size
    real = data.dtype
    causal_re = np.zeros((n_frames, n_bands), real)
    causal_im = np.zeros((n_frames, n_bands), real)
    z_re, z_im = np.zeros(n_bands, real), np.zeros(n_bands, real)
    in_re, in_im = np.empty(n_bands, real), np.empty(n_bands, real)
    for f in range(1, n_frames):
        first = (f - 1) * hop
        in_re[:] = 0.0
        in_im[:] = 0.0
        for k in range(min(hop + 1, data.size - first)):
            sample = data[first + k]
            for j in range(n_bands):
                in_re[j] += weights[k, j] * sample
                in_im[j] += weights[k, n_bands + j] * sample
        for j in range(n_bands):
            re = powers[0, j] * z_re[j] - powers[1, j] * z_im[j] + in_re[j]
            im = powers[0, j] * z_im[j] + powers[1, j] * z_re[j] + in_im[j]
            z_re[j], z_im[j] = re, im
            causal_re[f, j], causal_im[f, j] = re, im
    out = np.empty((n_frames, n_bands), real)
    z_re[:] = 0.0
    z_im[:] = 0.0
    for f in range(n_frames - 1, -1, -1):
        if f < n_frames - 1:
            first = f * hop
            in_re[:] = 0.0
            in_im[:] = 0.0
            for k in range(min(hop + 1, data.size - first)):
                sample = data[first + k]
                for j in range(n_bands):
                    in_re[j] += weights[k, 2 * n_bands + j] * sample
                    in_im[j] += weights[k, 3 * n_bands + j] * sample
            for j in range(n_bands):
                re = powers[2, j] * z_re[j] - powers[3, j] * z_im[j] + in_re[j]
                im = powers[2, j] * z_im[j] + powers[3, j] * z_re[j] + in_im[j]
                z_re[j], z_im[j] = re, im
        for j in range(n_bands):
            re = causal_re[f, j] + z_re[j]
            im = causal_im[f, j] + z_im[j]
            out[f, j] = scale[j] * (re * re + im * im)
    return out


@njit(cache=True)
def triangle_decimated(data: NDArray[np.float64], factor: int, n_out: int) -> NDArray[np.float64]:
    """``n_out`` samples, every ``factor``-th of ``data`` smoothed by the centred triangle of
    2·factor - 1 taps (two boxcars of ``factor`` samples, unit sum; zeros beyond the ends):
    sample m is Σ_k (factor - |k|)/factor² · data[m·factor + k]."""
    n = data.size
    out = np.zeros(n_out)
    norm = 1.0 / (factor * factor)
    for m in range(min(n_out, -(-(n + factor - 1) // factor))):
        centre = m * factor
        total = factor * data[centre] if centre < n else 0.0
        for k in range(1, factor):
            weight = factor - k
            if 0 <= centre - k < n:
                total += weight * data[centre - k]
            if centre + k < n:
                total += weight * data[centre + k]
        out[m] = total * norm
    return out
