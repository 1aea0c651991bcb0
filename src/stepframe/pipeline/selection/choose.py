"""Choosing the set: greedy selection plus one-for-one swaps on a combined objective.

The objective of a set S of units (components, or records with both components) is

    J(S) = mean_{u∈S} z_u - w · misfit(S),

with z_u the unit's ranking score as a percentile among the candidates (0 worst, 1 best, so
scores on any scale combine), w the spectral weight, and misfit(S) the RMS over periods of
ln(geometric mean of the set's scaled PSA / target) (0 without a target). Greedy adds the unit
that raises J most, subject to the caps per event and per station; then one-for-one swaps replace
a chosen unit by an unchosen one while J improves. Ties break by candidate order, so the result
is deterministic.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

Floats = NDArray[np.float64]
MAX_SWAP_ROUNDS = 100


@dataclass(frozen=True)
class Units:
    """Candidate units: their scores, members (candidate rows), the event and station of every
    row (indexed by row), and per unit the mean over members of ln(s·PSA), shape
    (n_units, n_periods)."""

    z: Floats
    members: list[list[int]]
    events: NDArray[np.object_]
    stations: NDArray[np.object_]
    log_psa: Floats | None

    def events_of(self, unit: int) -> list[str]:
        """Events of the unit's members."""
        return [str(e) for e in self.events[self.members[unit]]]

    def stations_of(self, unit: int) -> list[str]:
        """Stations of the unit's members."""
        return [str(s) for s in self.stations[self.members[unit]]]


def _fits(
    unit: int,
    units: Units,
    events: Counter[str],
    stations: Counter[str],
    max_event: int | None,
    max_station: int | None,
) -> bool:
    if max_event is not None:
        extra = Counter(units.events_of(unit))
        if any(events[e] + k > max_event for e, k in extra.items()):
            return False
    if max_station is not None:
        extra = Counter(units.stations_of(unit))
        if any(stations[s] + k > max_station for s, k in extra.items()):
            return False
    return True


def objective(chosen: list[int], units: Units, weight: float, log_target: Floats | None) -> float:
    """J(S) of a list of unit indices."""
    if not chosen:
        return -np.inf
    value = float(np.mean(units.z[chosen]))
    if weight > 0 and units.log_psa is not None and log_target is not None:
        mean_log = units.log_psa[chosen].mean(axis=0)
        value -= weight * float(np.sqrt(np.mean((mean_log - log_target) ** 2)))
    return value


def choose(
    units: Units,
    n: int,
    *,
    weight: float = 0.0,
    log_target: Floats | None = None,
    max_per_event: int | None = None,
    max_per_station: int | None = None,
) -> list[int]:
    """Indices of the chosen units, best first (greedy order, then swaps in place).

    Returns fewer than ``n`` when the caps leave fewer feasible units.
    """
    order = np.argsort(-units.z, kind="stable")
    use_spectra = weight > 0 and units.log_psa is not None and log_target is not None
    chosen: list[int] = []
    events: Counter[str] = Counter()
    stations: Counter[str] = Counter()

    def add(u: int) -> None:
        chosen.append(u)
        events.update(units.events_of(u))
        stations.update(units.stations_of(u))

    if not use_spectra:
        for u in order:
            if len(chosen) == n:
                break
            if _fits(int(u), units, events, stations, max_per_event, max_per_station):
                add(int(u))
        return chosen
    while len(chosen) < n:
        best, best_value = -1, -np.inf
        for u in order:
            u = int(u)
            if u in chosen or not _fits(u, units, events, stations, max_per_event, max_per_station):
                continue
            value = objective([*chosen, u], units, weight, log_target)
            if value > best_value + 1e-12:
                best, best_value = u, value
        if best < 0:
            break
        add(best)
    for _ in range(MAX_SWAP_ROUNDS):
        current = objective(chosen, units, weight, log_target)
        improved = False
        for position in range(len(chosen)):
            rest = chosen[:position] + chosen[position + 1 :]
            events_rest = Counter(e for u in rest for e in units.events_of(u))
            stations_rest = Counter(s for u in rest for s in units.stations_of(u))
            for u in order:
                u = int(u)
                if u in chosen or not _fits(
                    u, units, events_rest, stations_rest, max_per_event, max_per_station
                ):
                    continue
                trial = [*rest[:position], u, *rest[position:]]
                value = objective(trial, units, weight, log_target)
                if value > current + 1e-12:
                    chosen[position] = u
                    current = value
                    improved = True
                    break
            if improved:
                break
        if not improved:
            break
    return chosen


def percentile_scores(values: Floats) -> Floats:
    """Each value's percentile among the finite values (0 lowest, 1 highest; ties averaged);
    NaN stays NaN."""
    from scipy.stats import rankdata

    out = np.full(values.shape, np.nan)
    finite = np.isfinite(values)
    count = int(finite.sum())
    if count == 1:
        out[finite] = 1.0
    elif count > 1:
        out[finite] = (rankdata(values[finite]) - 1.0) / (count - 1.0)
    return out
