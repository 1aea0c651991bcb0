"""Confirmation by simulation: the exact stepping simulator on the chosen set and on every candidate.

Two runs through :func:`stepframe.structure.simulator.simulate_batch`:

- the selected records and as many controls (candidates that passed the filters, ranked lowest)
  at the chosen scale;
- every candidate at a common intensity, equal PSA at T_1 = 2π/ω_1 (damping ξ_1): scaled so that
  the linear frame's peak P_1·SD(T_1) is ``onset_ratio`` · x_c, so that frequency content is
  what differs. There the overturning intensity is also found by bisection: the smallest such
  ratio at which the frame overturns (``overturn_onset_ratio``; NaN if it does not below 4).

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
BISECTION_STEPS = 10
OVERTURN_RATIO_RANGE = (0.5, 4.0)
N_RESAMPLES = 1000


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
    """Smallest onset ratio (as :func:`equal_intensity_scales`) that overturns the frame, per
    record, by bisection to 2^-10 of the range; NaN when 4 does not overturn it, the lower end
    of the range when 0.5 already does."""
    low = np.full(len(records), OVERTURN_RATIO_RANGE[0])
    high = np.full(len(records), OVERTURN_RATIO_RANGE[1])
    top = run_batch(frame, records, equal_intensity_scales(sd_t1_m, frame, 1.0) * high)
    never = ~top.table["overturned"].to_numpy(dtype=bool)
    for _ in range(BISECTION_STEPS):
        middle = 0.5 * (low + high)
        run = run_batch(frame, records, equal_intensity_scales(sd_t1_m, frame, 1.0) * middle)
        over = run.table["overturned"].to_numpy(dtype=bool)
        high = np.where(over, middle, high)
        low = np.where(over, low, middle)
    return np.asarray(np.where(never, np.nan, high))


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

    def rho(a: Floats, b: Floats) -> Floats:
        ra = np.asarray(rankdata(a, axis=-1), dtype=np.float64)
        rb = np.asarray(rankdata(b, axis=-1), dtype=np.float64)
        ra -= ra.mean(axis=-1, keepdims=True)
        rb -= rb.mean(axis=-1, keepdims=True)
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.asarray(
                (ra * rb).sum(axis=-1) / np.sqrt((ra**2).sum(axis=-1) * (rb**2).sum(axis=-1))
            )

    value = float(rho(xs, ys))
    rng = np.random.default_rng(seed)
    picks = rng.integers(0, n, size=(n_resamples, n))
    samples = rho(xs[picks], ys[picks])
    samples = samples[np.isfinite(samples)]
    if samples.size == 0:
        return value, math.nan, math.nan, n
    tail = 50.0 * (1.0 - level)
    low, high = np.percentile(samples, [tail, 100.0 - tail])
    return value, float(low), float(high), n
