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
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from stepframe.pipeline.selection.intensity import equal_intensity_scales

Floats = NDArray[np.float64]
OVERTURN_RATIO_RANGE = (0.5, 4.0)
#: Onset ratios scanned for overturning (log-spaced, 1.0 is the 6th).
SCAN_LEVELS = np.geomspace(OVERTURN_RATIO_RANGE[0], OVERTURN_RATIO_RANGE[1], 16)
N_RESAMPLES = 1000
#: Fewest pairs a rank correlation (ρ, Δρ, the efficiency) is computed from; fewer give NaN.
MIN_PAIRS = 4


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


def overturn_onset_ratios(
    frame: Any, records: list[tuple[Floats, float]], sd_t1_m: Floats
) -> Floats:
    """Lowest onset ratio (as :func:`equal_intensity_scales`) found to overturn the frame, per
    record; NaN when none up to 4 does, 0.5 when 0.5 already does (:func:`overturn_factors` on
    :data:`SCAN_LEVELS` from the onset scales)."""
    base = equal_intensity_scales(sd_t1_m, frame, 1.0)
    return overturn_factors(frame, records, base, SCAN_LEVELS)


#: Levels of the overturning scan simulated per round: a record that overturns in a round is
#: not simulated at the levels above it (its first overturning level is all the scan gives).
#: Most records overturn by the 8th of :data:`SCAN_LEVELS`, so the upper half is rarely run:
#: the scan cost 25 % less per record (docs/benchmarks.md, "the responses stage's cost").
SCAN_ROUND = 8


def overturn_factors(
    frame: Any, records: list[tuple[Floats, float]], base_scales: Floats, levels: Floats
) -> Floats:
    """Lowest factor on ``base_scales`` found to overturn the frame, per record; NaN when no
    level does, ``levels[0]`` when the first already does: every record simulated at the levels
    of ``levels`` (increasing) up to the first that overturns it (in rounds of
    :data:`SCAN_ROUND` levels), then the bracket below that level bisected
    (:func:`stepframe.pipeline.selection.exact.first_overturn`). The levels above a record's
    first overturning one are never read, so skipping them changes no result."""
    from stepframe.pipeline.selection.exact import first_overturn, ladder_runs

    base = np.asarray(base_scales, dtype=np.float64)
    grid = np.asarray(levels, dtype=np.float64)
    overturned = np.zeros((len(records), grid.size), dtype=bool)
    pending = np.arange(len(records))
    for first in range(0, grid.size, SCAN_ROUND):
        if not pending.size:
            break
        part = slice(first, min(first + SCAN_ROUND, grid.size))
        scan = ladder_runs(
            frame, [records[int(i)] for i in pending], base[pending], grid[part].tolist()
        )
        overturned[pending, part] = scan.overturned
        pending = pending[~scan.overturned.any(axis=1)]
    return first_overturn(frame, records, base, grid, overturned)


#: Bootstrap indices drawn and ranked at once: 1,000 resamples of 43,000 candidates at once
#: held several GB (the indices, the drawn values and their ranks); in blocks of this many
#: indices (16 MB each) the same resamples, drawn from the same stream in order, give the same
#: intervals in a few hundred MB.
BLOCK_INDICES = 2_000_000


def _resamples(rng: np.random.Generator, n: int, n_resamples: int) -> Iterator[NDArray[Any]]:
    """The bootstrap's index arrays (resamples × n) in blocks of rows, in drawing order: the
    concatenation equals ``rng.integers(0, n, size=(n_resamples, n))`` drawn at once."""
    rows = max(1, BLOCK_INDICES // max(n, 1))
    for start in range(0, n_resamples, rows):
        yield rng.integers(0, n, size=(min(rows, n_resamples - start), n))


class _TieGroups:
    """A variable's order and its groups of equal values, for ranking its resamples.

    A resample's ranks follow from how often each candidate is drawn without sorting it again:
    in the variable's order, a group of equal values drawn T times in all, after S draws of
    smaller values, has the average rank S + (T + 1)/2 (ties averaged, as
    ``scipy.stats.rankdata``), computed by the compiled
    :func:`~stepframe.pipeline.selection._bootstrap_kernel.resampled_rhos`.
    Ranking each resample by sorting was 75 % of the selection stage at 1,000 candidates
    (docs/benchmarks.md, "the confirmation's bootstrap by counts").
    """

    def __init__(self, values: Floats) -> None:
        self.order = np.argsort(values, kind="stable").astype(np.int64)
        ordered = values[self.order]
        fresh = np.concatenate([[True], ordered[1:] != ordered[:-1]])
        self.group = (np.cumsum(fresh) - 1).astype(np.int64)  # group of each position
        self.n_groups = int(self.group[-1]) + 1


def _resampled_rhos(
    variables: list[_TieGroups], pairs: list[tuple[int, int]], rng: np.random.Generator,
    n_resamples: int,
) -> NDArray[np.float64]:  # fmt: skip
    """Spearman's ρ of each ``pairs`` of ``variables`` in each bootstrap resample (resamples ×
    pairs), the resamples drawn by :func:`_resamples` from ``rng``."""
    from stepframe.pipeline.selection._bootstrap_kernel import resampled_rhos

    n = variables[0].order.size
    orders = np.stack([v.order for v in variables])
    groups = np.stack([v.group for v in variables])
    n_groups = np.array([v.n_groups for v in variables], dtype=np.int64)
    pair_array = np.array(pairs, dtype=np.int64)
    return np.concatenate(
        [
            resampled_rhos(picks.astype(np.int64, copy=False), orders, groups, n_groups, pair_array)
            for picks in _resamples(rng, n, n_resamples)
        ]
    )


def spearman_interval(
    x: Floats, y: Floats, seed: int, n_resamples: int = N_RESAMPLES, level: float = 0.95
) -> tuple[float, float, float, int]:
    """Spearman's ρ of finite pairs, its percentile bootstrap interval, and the pair count.

    NaN values (in either) are left out; ±inf are kept (ranked at the ends). Fewer than
    :data:`MIN_PAIRS` pairs or a constant variable give NaN.
    """
    keep = ~(np.isnan(x) | np.isnan(y))
    xs, ys = x[keep], y[keep]
    n = int(xs.size)
    if n < MIN_PAIRS:
        return math.nan, math.nan, math.nan, n
    value = float(_rank_rho(xs, ys))
    rng = np.random.default_rng(seed)
    samples = _resampled_rhos([_TieGroups(xs), _TieGroups(ys)], [(0, 1)], rng, n_resamples)[:, 0]
    samples = samples[np.isfinite(samples)]
    if samples.size == 0:
        return value, math.nan, math.nan, n
    tail = 50.0 * (1.0 - level)
    low, high = np.percentile(samples, [tail, 100.0 - tail])
    return value, float(low), float(high), n


def _rank_rho(a: Floats, b: Floats) -> Floats:
    """Spearman ρ along the last axis (ties averaged)."""
    from scipy.stats import rankdata

    ra = np.asarray(rankdata(a, axis=-1), dtype=np.float64)
    rb = np.asarray(rankdata(b, axis=-1), dtype=np.float64)
    ra -= ra.mean(axis=-1, keepdims=True)
    rb -= rb.mean(axis=-1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.asarray(
            (ra * rb).sum(axis=-1) / np.sqrt((ra**2).sum(axis=-1) * (rb**2).sum(axis=-1))
        )


def paired_delta_rho(
    x: Floats, reference: Floats, y: Floats, seed: int, n_resamples: int = N_RESAMPLES
) -> tuple[float, float, float, int]:
    """ρ(x, y) - ρ(reference, y) on the candidates where all three are not NaN, with its
    percentile bootstrap interval (95 %; each resample draws the same candidates for both,
    so the interval is of the paired difference), and the count."""
    keep = ~(np.isnan(x) | np.isnan(reference) | np.isnan(y))
    xs, rs, ys = x[keep], reference[keep], y[keep]
    n = int(xs.size)
    if n < MIN_PAIRS or np.ptp(xs) == 0 or np.ptp(rs) == 0 or np.ptp(ys) == 0:
        return math.nan, math.nan, math.nan, n
    value = float(_rank_rho(xs, ys) - _rank_rho(rs, ys))
    rng = np.random.default_rng(seed)
    rhos = _resampled_rhos(
        [_TieGroups(xs), _TieGroups(rs), _TieGroups(ys)], [(0, 2), (1, 2)], rng, n_resamples
    )
    samples = rhos[:, 0] - rhos[:, 1]
    samples = samples[np.isfinite(samples)]
    if samples.size == 0:
        return value, math.nan, math.nan, n
    low, high = np.percentile(samples, [2.5, 97.5])
    return value, float(low), float(high), n


def efficiency(measure: Floats, response: Floats) -> tuple[float, int]:
    """Dispersion of ln(response) given ln(measure): the standard deviation of the residuals
    of the least-squares line ln(response) = a + b·ln(measure) (two parameters fitted), over
    the pairs where both are positive and finite; NaN for fewer than 4 pairs. Smaller is more
    efficient (the criterion of probabilistic seismic demand analysis: Luco and Cornell 2007,
    "Structure-specific scalar intensity measures for near-source and ordinary earthquake
    ground motions", Earthquake Spectra 23(2):357-392)."""
    m = np.asarray(measure, dtype=np.float64)
    r = np.asarray(response, dtype=np.float64)
    keep = np.isfinite(m) & np.isfinite(r) & (m > 0) & (r > 0)
    n = int(keep.sum())
    x, y = np.log(m[keep]), np.log(r[keep])
    if n < MIN_PAIRS or np.ptp(x) < 1e-9:
        # a measure that does not vary (S_a(T_1) at equal S_a(T_1)) explains nothing
        return math.nan, n
    slope, intercept = np.polyfit(x, y, 1)
    residual = y - (intercept + slope * x)
    return float(np.sqrt(np.sum(residual**2) / (n - 2))), n
