"""Confirmation by simulation: the exact stepping simulator on the chosen set and every candidate.

Two runs through :func:`stepframe.structure.simulator.simulate_batch`:

- the selected records and as many controls (candidates that passed the filters, ranked lowest)
  at the chosen scale;
- every candidate at a common intensity, equal PSA at T_1 = 2π/ω_1 (damping ξ_1): scaled so that
  the linear frame's peak P_1·SD(T_1) is ``onset_ratio`` · x_c, so that frequency content is
  what differs. There the overturning intensity is also found (scan, then bisection): the
  lowest such ratio found to overturn the frame (``overturn_onset_ratio``; NaN if none up to 4).

Then the rank correlation (Spearman, with a percentile bootstrap interval over candidates) of
every score with the simulated peak drift at equal intensity and with the overturning margin
(the negated overturning ratio, so that a positive correlation means "the score predicts
damage" for both).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

Floats = NDArray[np.float64]
BISECTION_STEPS = 8
OVERTURN_RATIO_RANGE = (0.5, 4.0)
#: Onset ratios scanned for overturning (log-spaced, 1.0 is the 6th).
SCAN_LEVELS = np.geomspace(OVERTURN_RATIO_RANGE[0], OVERTURN_RATIO_RANGE[1], 16)
N_RESAMPLES = 1000
#: Values drawn per block of bootstrap resamples (memory: a few arrays of this many floats).
BOOTSTRAP_BLOCK = 1 << 21


@dataclass(frozen=True)
class Simulated:
    """Summaries of a batch and how many input samples per second it ran at."""

    table: Any
    samples_per_s: float


def run_batch(frame: Any, records: list[tuple[Floats, float]], scales: Floats) -> Simulated:
    """:func:`simulate_batch` with ``pairs="zip"``, timed."""
    from stepframe.structure.simulator import simulate_batch

    start = time.perf_counter()
    table = simulate_batch(frame, records, scales, pairs="zip")
    seconds = time.perf_counter() - start
    samples = sum(acc.size for acc, _ in records)
    return Simulated(table, samples / seconds if seconds > 0 else math.inf)


def equal_intensity_scales(sd_t1_m: Floats, frame: Any, onset_ratio: float) -> Floats:
    """Scale factors giving P_1·SD(T_1) = onset_ratio · x_c for each record."""
    with np.errstate(divide="ignore"):
        return np.asarray(onset_ratio * frame.x_c_m / (frame.p_1 * sd_t1_m))


def overturn_onset_ratios(
    frame: Any, records: list[tuple[Floats, float]], sd_t1_m: Floats
) -> Floats:
    """Lowest onset ratio (as :func:`equal_intensity_scales`) found to overturn the frame, per
    record; NaN when none up to 4 does, 0.5 when 0.5 already does.

    Overturning is not monotone in intensity (a stronger scaling can leave the frame standing),
    so a bisection alone could land on a later transition: the ratios are first scanned on
    :data:`SCAN_LEVELS` (16 log-spaced levels from 0.5 to 4, 1 among them), then the interval
    below the first level that overturns is bisected (8 halvings).
    """
    n = len(records)
    base = equal_intensity_scales(sd_t1_m, frame, 1.0)
    first = np.full(n, -1)
    for k, level in enumerate(SCAN_LEVELS):
        over = run_batch(frame, records, base * level).table["overturned"].to_numpy(dtype=bool)
        first = np.where((first < 0) & over, k, first)
    found = first > 0
    low = np.where(found, SCAN_LEVELS[np.maximum(first - 1, 0)], np.nan)
    high = np.where(found, SCAN_LEVELS[np.maximum(first, 0)], np.nan)
    if found.any():
        subset = [records[i] for i in np.flatnonzero(found)]
        lo, hi = low[found], high[found]
        for _ in range(BISECTION_STEPS):
            middle = 0.5 * (lo + hi)
            over = run_batch(frame, subset, base[found] * middle).table["overturned"]
            over = over.to_numpy(dtype=bool)
            hi = np.where(over, middle, hi)
            lo = np.where(over, lo, middle)
        high[found] = hi
    high[first == 0] = SCAN_LEVELS[0]
    return np.asarray(high)


def _correlation(ra: Floats, rb: Floats) -> Floats:
    """Pearson's correlation of ranks along the last axis (Spearman's ρ of what was ranked)."""
    ra = np.asarray(ra, dtype=np.float64)
    rb = np.asarray(rb, dtype=np.float64)
    ra = ra - ra.mean(axis=-1, keepdims=True)
    rb = rb - rb.mean(axis=-1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.asarray(
            (ra * rb).sum(axis=-1) / np.sqrt((ra**2).sum(axis=-1) * (rb**2).sum(axis=-1))
        )


def _resampled_ranks(ids: NDArray[np.int64], picks: NDArray[np.int64]) -> Floats:
    """Average ranks (ties share the mean rank, as ``rankdata``) of each row of ``ids[picks]``,
    ``ids`` the values' positions among the distinct values in sorted order."""
    values = int(ids.max()) + 1
    picked = ids[picks]
    rows = picked.shape[0]
    flat = (picked + values * np.arange(rows)[:, None]).ravel()
    counts = np.bincount(flat, minlength=rows * values).reshape(rows, values)
    below = np.cumsum(counts, axis=1) - counts
    average = below + 1 + (counts - 1) / 2.0
    return np.take_along_axis(average, picked, axis=1)


def spearman_interval(
    x: Floats, y: Floats, seed: int, n_resamples: int = N_RESAMPLES, level: float = 0.95
) -> tuple[float, float, float, int]:
    """Spearman's ρ of finite pairs, its percentile bootstrap interval, and the pair count.

    NaN values (in either) are left out; ±inf are kept (ranked at the ends). Fewer than 4 pairs
    or a constant variable give NaN.
    """
    from scipy.stats import rankdata

    keep = ~(np.isnan(x) | np.isnan(y))
    xs, ys = x[keep], y[keep]
    n = int(xs.size)
    if n < 4:
        return math.nan, math.nan, math.nan, n

    value = float(_correlation(rankdata(xs), rankdata(ys)))
    # The ranks of a resample from the value counts of the resample (bincount and cumulative
    # sum per resample: O(n) where rankdata sorts, O(n log n)); the same average ranks, as
    # exact half-integers, so the same numbers. Resamples in blocks of about BOOTSTRAP_BLOCK
    # values (the generator gives the same draws in blocks as in one call).
    x_ids = np.unique(xs, return_inverse=True)[1]
    y_ids = np.unique(ys, return_inverse=True)[1]
    rng = np.random.default_rng(seed)
    block = max(1, BOOTSTRAP_BLOCK // n)
    parts = []
    for start in range(0, n_resamples, block):
        picks = rng.integers(0, n, size=(min(block, n_resamples - start), n))
        parts.append(_correlation(_resampled_ranks(x_ids, picks), _resampled_ranks(y_ids, picks)))
    samples = np.concatenate(parts)
    samples = samples[np.isfinite(samples)]
    if samples.size == 0:
        return value, math.nan, math.nan, n
    tail = 50.0 * (1.0 - level)
    low, high = np.percentile(samples, [tail, 100.0 - tail])
    return value, float(low), float(high), n
