"""Ranking by the frame's own simulated response over a short ladder of intensities.

Every candidate is simulated (:func:`stepframe.structure.simulator.simulate_batch`, the exact
piecewise-analytic integrator) at each factor of the ladder :data:`LADDER` times its base scale
(the stated ranking intensity, :mod:`stepframe.pipeline.selection.intensity`). Two measures
come out of those runs:

- ``overturn_factor``: the lowest factor on the record's scale found to overturn the frame, up
  to the ladder's top (:func:`overturn_factor`: the ladder is the scan, extended below its
  lowest level by :data:`EXTENSION` levels when that level already overturns, then
  :data:`BISECTION_STEPS` halvings of the bracket below the first level that overturns;
  overturning is not monotone in intensity, so a bisection over the whole range could land on
  a later transition); NaN when no level overturns;
- ``simulated_response``: the geometric mean over the ladder of the peak |x| [m], a run that
  overturns counting as :func:`overturn_peak_m` (the frame's cap x_cap, or 2x* for a frame
  without one).

Order (the default ranking, most severe first): candidates that overturn the frame within the
ladder, by ``overturn_factor`` (lower first: less intensity needed), then those that never
overturn in the ladder, by ``simulated_response`` (larger first); remaining ties (equal factors,
equal responses) by candidate order. One simulation at one intensity is not a robust ranking:
near overturning a small change of intensity or of the frame flips the verdict
(docs/selection.md, "Robustness"); the margin and the ladder's average are steadier.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from stepframe.structure.frame import PortalFrame

Floats = NDArray[np.float64]
Samples = tuple[Floats, float]

#: The default ladder: factors on the stated intensity (bench/ranking_robustness.py chose it).
LADDER: tuple[float, ...] = (0.5, 0.707, 1.0, 1.414, 2.0)
#: Levels added below the ladder when its lowest level already overturns, each √2 below the
#: last (down to a quarter of the lowest).
EXTENSION = 4
#: Halvings of the bracket below the first level that overturns.
BISECTION_STEPS = 8
#: Relative resolution of the order's two keys: the width of the bisection's last bracket on
#: a ladder step of √2, (1 - 1/√2)/2^8 = 0.11 %. Two candidates whose overturning factors (or
#: both: none) and ladder means are this close are a tie (:func:`tied_across`).
RESOLUTION = (1.0 - 1.0 / math.sqrt(2.0)) / 2**BISECTION_STEPS
#: Candidates per simulation batch: a batch holds its records' scaled samples once (2,000
#: records of 6,000 samples: 96 MB).
CHUNK = 2000


def overturn_peak_m(frame: PortalFrame) -> float:
    """The peak |x| [m] an overturned run counts as: x_cap, or 2x* for a frame without a cap
    (its stepped phase cannot return from beyond x*)."""
    if frame.x_cap_m is not None and math.isfinite(frame.x_cap_m):
        return float(frame.x_cap_m)
    return 2.0 * frame.x_star_m


@dataclass(frozen=True)
class LadderRuns:
    """Peak |x| [m] (overturned runs at :func:`overturn_peak_m`), shape (n, levels), whether
    each run overturned, and per candidate the first simulator message of a failed run ("")."""

    peaks_m: Floats
    overturned: NDArray[np.bool_]
    failed: list[str]

    @property
    def response_m(self) -> Floats:
        """Geometric mean over the levels of the peaks [m] (NaN for a failed candidate)."""
        with np.errstate(divide="ignore"):
            value = np.exp(np.mean(np.log(self.peaks_m), axis=1))
        value[np.array([bool(m) for m in self.failed], dtype=bool)] = np.nan
        return np.asarray(value)


def ladder_runs(
    frame: PortalFrame, records: Sequence[Samples], base_scales: Floats, factors: Sequence[float]
) -> LadderRuns:
    """Simulate every record at ``factors`` × its base scale, in batches of :data:`CHUNK`.

    Parameters
    ----------
    frame
        The stepping frame (:class:`stepframe.structure.frame.PortalFrame`).
    records
        (ground acceleration [m/s²], dt [s]) per candidate, unscaled.
    base_scales
        Each candidate's scale at the stated intensity.
    factors
        The ladder: factors on the base scale.
    """
    from stepframe.structure.simulator import batch_summaries

    n, levels = len(records), len(factors)
    ladder = np.asarray(factors, dtype=np.float64)
    peaks = np.full((n, levels), np.nan)
    overturned = np.zeros((n, levels), dtype=bool)
    failed = [""] * n
    cap = overturn_peak_m(frame)
    for first in range(0, n, CHUNK):
        rows = range(first, min(first + CHUNK, n))
        scaled = [(records[i][0] * base_scales[i], records[i][1]) for i in rows]
        # The runs' arrays, not simulate_batch's table: a group's ranking makes some ten small
        # batches, and their tables cost about as much as the bisection's runs.
        runs = batch_summaries(frame, scaled, ladder, pairs="product")
        shape = (len(rows), levels)
        over = runs.overturned.reshape(shape)
        peak = runs.peak_abs_x_m.reshape(shape)
        peaks[rows.start : rows.stop] = np.where(over, cap, np.minimum(peak, cap))
        overturned[rows.start : rows.stop] = over
        # Each candidate's first failed run, in ladder order (pairs are record-major).
        for pair, status in enumerate(runs.status):
            i = first + pair // levels
            if status != "ok" and not failed[i]:
                failed[i] = f"{status}: {runs.messages[pair]}"
    return LadderRuns(peaks, overturned, failed)


@dataclass(frozen=True)
class ResponseRanking:
    """The simulated response of every candidate at the ranking intensity.

    Attributes
    ----------
    response_m
        ``simulated_response``: geometric mean of the peak |x| over the ladder [m].
    overturn_factor
        The lowest factor on the record's scale found to overturn the frame, up to the
        ladder's top (NaN: none).
    peak_m, overturned
        Peak |x| [m] and overturning at the stated intensity itself (factor 1; NaN and False
        when the ladder has no factor 1).
    n_overturned
        Levels of the ladder at which the candidate overturns.
    failed
        The simulator's message for a candidate with a failed run ("" otherwise).
    factors
        The ladder.
    """

    response_m: Floats
    overturn_factor: Floats
    peak_m: Floats
    overturned: NDArray[np.bool_]
    n_overturned: NDArray[np.int64]
    failed: list[str]
    factors: tuple[float, ...]

    def order(self) -> NDArray[np.int64]:
        """Candidate indices, most severe first (failed candidates last)."""
        return ranking_order(self.overturn_factor, self.response_m)

    def percentiles(self) -> Floats:
        """Each candidate's percentile in :meth:`order` (1 most severe, 0 least; NaN failed)."""
        order = self.order()
        finite = np.isfinite(self.response_m)
        count = int(finite.sum())
        out = np.full(self.response_m.size, np.nan)
        if count == 1:
            out[finite] = 1.0
        elif count > 1:
            out[order[:count]] = 1.0 - np.arange(count) / (count - 1.0)
        return out


def ranking_order(overturn_factor: Floats, response_m: Floats) -> NDArray[np.int64]:
    """Indices, most severe first: finite ``overturn_factor`` ascending, then the others by
    ``response_m`` descending, then by index; NaN responses (failed runs) last."""
    failed = np.isnan(response_m)
    over = np.isfinite(overturn_factor) & ~failed
    factor = np.where(over, overturn_factor, np.inf)
    response = np.where(failed, -np.inf, response_m)
    index = np.arange(response.size)
    return np.asarray(np.lexsort((index, -response, factor, failed)), dtype=np.int64)


def tied_across(
    overturn_factor: Floats,
    response_m: Floats,
    chosen: NDArray[np.bool_],
    resolution: float = RESOLUTION,
) -> NDArray[np.bool_]:
    """The candidates the order does not tell apart across the chosen set's edge: each chosen
    candidate tied with one not chosen, and each such other, where a tie is overturning
    factors within ``resolution`` of each other (or neither overturning) and ladder means
    within it too. NaN responses (not ranked, failed) are never tied.

    Parameters
    ----------
    overturn_factor, response_m
        The two keys per candidate (:class:`ResponseRanking`; NaN factor: never overturns).
        A ranking by one value (a tier) passes NaN factors and its values as the responses.
    chosen
        The chosen set's mask.
    resolution
        Relative difference below which two keys are equal (0: only equal values).
    """
    factor = np.asarray(overturn_factor, dtype=np.float64)
    response = np.asarray(response_m, dtype=np.float64)
    ranked = np.isfinite(response)
    inside = np.flatnonzero(chosen & ranked)
    outside = np.flatnonzero(~chosen & ranked)
    tied = np.zeros(response.size, dtype=bool)
    if not inside.size or not outside.size:
        return tied

    def close(a: float, b: Floats) -> NDArray[np.bool_]:
        return np.asarray(np.abs(a - b) <= resolution * np.abs(np.minimum(a, b)))

    # one chosen candidate at a time against all the others: memory of one candidate list (a
    # set of n against 43,000 candidates at once would hold n × 43,000 of each temporary)
    never = np.isnan(factor)
    others_factor, others_response, others_never = (
        factor[outside],
        response[outside],
        never[outside],
    )
    hit = np.zeros(outside.size, dtype=bool)
    for i in inside:
        same_factor = others_never if never[i] else close(factor[i], others_factor)
        pairs = close(response[i], others_response) & same_factor
        if pairs.any():
            tied[i] = True
            hit |= pairs
    tied[outside[hit]] = True
    return tied


def overturn_factor(
    frame: PortalFrame,
    records: Sequence[Samples],
    base_scales: Floats,
    factors: Sequence[float],
    overturned: NDArray[np.bool_],
) -> Floats:
    """The lowest factor on each record's base scale found to overturn the frame up to the
    ladder's top (NaN: none), from the ladder's verdicts ``overturned`` (n, levels): the
    ladder is the scan, extended below it (:data:`EXTENSION` levels) for the records whose
    lowest level already overturns, and the bracket below the first overturning level is
    bisected (:func:`first_overturn`)."""
    ladder = np.asarray(factors, dtype=np.float64)
    below = (ladder[0] / np.sqrt(2.0) ** np.arange(1, EXTENSION + 1))[::-1]
    base = np.asarray(base_scales, dtype=np.float64)
    grid = np.concatenate([below, ladder])
    verdict = np.zeros((len(records), grid.size), dtype=bool)
    verdict[:, below.size :] = overturned
    rows = np.flatnonzero(overturned[:, 0])
    if rows.size:
        runs = ladder_runs(frame, [records[int(i)] for i in rows], base[rows], below)
        verdict[rows, : below.size] = runs.overturned
    # Records whose lowest ladder level stands were not simulated below it: their scan starts
    # at the ladder (the extension's verdicts stay False and are skipped).
    start = np.where(overturned[:, 0], 0, below.size)
    shifted = np.where(np.arange(grid.size)[None, :] >= start[:, None], verdict, False)
    return first_overturn(frame, records, base, grid, shifted)


def first_overturn(
    frame: PortalFrame,
    records: Sequence[Samples],
    base_scales: Floats,
    grid: Floats,
    overturned: NDArray[np.bool_],
) -> Floats:
    """The lowest factor on each record's base scale found to overturn the frame, from the
    verdicts ``overturned`` (n, len(grid)) of an increasing scan ``grid``: the grid's first
    level when it already overturns, NaN when none does, else the bracket below the first
    level that overturns bisected :data:`BISECTION_STEPS` times (overturning is not monotone in
    intensity, so a bisection over the whole range could land on a later transition)."""
    base = np.asarray(base_scales, dtype=np.float64)
    first = np.where(overturned.any(axis=1), np.argmax(overturned, axis=1), -1)
    out = np.where(first == 0, grid[0], np.nan)
    bracketed = np.flatnonzero(first > 0)
    if bracketed.size:
        low = grid[first[bracketed] - 1]
        high = grid[first[bracketed]]
        subset = [records[int(i)] for i in bracketed]
        for _ in range(BISECTION_STEPS):
            middle = 0.5 * (low + high)
            runs = ladder_runs(frame, subset, base[bracketed] * middle, (1.0,))
            hit = runs.overturned[:, 0]
            high = np.where(hit, middle, high)
            low = np.where(hit, low, middle)
        out[bracketed] = high
    return np.asarray(out)


def simulated_response(
    frame: PortalFrame,
    records: Sequence[Samples],
    base_scales: Floats,
    factors: Sequence[float] = LADDER,
) -> ResponseRanking:
    """Simulate every candidate over the ladder, then bisect the overturning factor of those
    that overturn in it (module docstring).

    Parameters
    ----------
    frame
        The stepping frame.
    records
        (ground acceleration [m/s²], dt [s]) per candidate, unscaled.
    base_scales
        Each candidate's scale factor at the stated ranking intensity.
    factors
        The ladder (default :data:`LADDER`).
    """
    base = np.asarray(base_scales, dtype=np.float64)
    runs = ladder_runs(frame, records, base, factors)
    response = runs.response_m
    overturn = np.full(len(records), np.nan)
    rows = np.flatnonzero(runs.overturned.any(axis=1) & np.isfinite(response))
    if rows.size:
        overturn[rows] = overturn_factor(
            frame, [records[int(i)] for i in rows], base[rows], factors, runs.overturned[rows]
        )
    failed = list(runs.failed)
    ladder = tuple(float(f) for f in factors)
    at_one = [k for k, f in enumerate(ladder) if math.isclose(f, 1.0)]
    if at_one:
        peak = runs.peaks_m[:, at_one[0]].copy()
        over = runs.overturned[:, at_one[0]].copy()
    else:
        peak = np.full(len(records), np.nan)
        over = np.zeros(len(records), dtype=bool)
    return ResponseRanking(
        response,
        overturn,
        peak,
        over,
        runs.overturned.sum(axis=1).astype(np.int64),
        failed,
        ladder,
    )
