"""The tiers below the simulation on the fidelity ladder, and the prefilter that uses them.

A tier is any ranking cheaper than simulating the frame: the closed forms of the fit
(``band_coverage``, ``omega_p_over_s_sq``, eq. 6.18), the fit's covariance scores
(``backbone_amplification``, ``descent_amplification``), the substitute structure
(``substitute_demand_ratio``) and the standard intensity measures
(:mod:`stepframe.pipeline.selection.peers`). Each is read at the ranking intensity (a peer that
scales with the record, S_a or FIV3, is multiplied by the record's scale), signed so that larger
is more severe.

The prefilter ranks the candidates by a tier and simulates only its best K. By default
(``prefilter = "auto"``) every candidate is simulated while the estimated cost of doing so
(:func:`estimated_exact_s`, CPU seconds of one core: the same on every machine, so the plan and
selection.json do not depend on the machine's CPUs) stays under the budget; above it the run
prefilters with
:data:`DEFAULT_PREFILTER` and K = :data:`PREFILTER_SHARE` of the candidates (at least
:data:`MIN_K_PER_N` × n): the tier and share that kept every one of the exact top 10 in 12
frame × catalogue cases of bench/ranking_tiers.py (docs/selection.md, "Tiers"). No tier does
that with a small K: the exact top n of a stepping frame is decided by how close a record comes
to overturning it, which no intensity measure reads, so a prefilter saves little, and the
budget (1,200 CPU s by default, 10 minutes on 2 cores: about 350,000 candidates of 6,000
samples) is set so that a catalogue the size of NGA-West2 is ranked exactly.
"""

from __future__ import annotations

import math
from concurrent.futures import Executor
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from stepframe.pipeline.selection.names import PEER_NAMES

Floats = NDArray[np.float64]

#: The tier the automatic prefilter ranks by, and the share of the candidates it keeps: N_p over
#: the band kept every one of the exact top 10 within its best 91 % of the candidates in every
#: case measured (median 49 %; bench/ranking_tiers.py).
DEFAULT_PREFILTER = "n_p_band"
PREFILTER_SHARE = 0.91
#: The prefilter keeps at least this many candidates per chosen one.
MIN_K_PER_N = 10
#: CPU seconds of the exact simulation per input sample and run on one core (bench/bench_ranking.py:
#: 0.26 ms for a 6,000-sample record with its 10 s tail at 0.01 s, 7,000 samples).
SIMULATION_S_PER_SAMPLE = 3.7e-8


def tier_values(table: Any, name: str, base_scales: Floats) -> Floats:
    """The tier ``name``'s values at the ranking intensity, larger more severe."""
    from stepframe.pipeline.selection.peers import at_intensity

    values = np.asarray(table[name], dtype=np.float64)
    if name in PEER_NAMES:
        return at_intensity(name, values, base_scales)
    return values


def estimated_exact_s(samples: int, runs: int) -> float:
    """Estimated CPU time of simulating ``samples`` input samples (records plus their tails)
    ``runs`` times each, on one core [s].

    CPU time, not wall time over the cores at hand: the plan it decides, and selection.json
    that records it, are then the same on every machine (a laptop and a 64-core server rank a
    catalogue the same way)."""
    return samples * runs * SIMULATION_S_PER_SAMPLE


@dataclass(frozen=True)
class Plan:
    """Which candidates the ranking simulates, and why (``ranking`` in selection.json).

    Attributes
    ----------
    method
        ``"exact"`` (every candidate simulated), ``"prefilter"`` (the best ``k`` by ``tier``)
        or ``"tier"`` (ranked by a tier alone, nothing simulated for the ranking).
    tier, k
        The prefilter's tier and K (None for ``exact``).
    estimated_s, budget_s
        The estimated CPU time of simulating every candidate on one core and the budget [s].
    reason
        One line for people.
    """

    method: str
    tier: str | None
    k: int | None
    estimated_s: float
    budget_s: float
    reason: str

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready (``k`` absent unless prefiltered: a count is a number or absent)."""
        data: dict[str, Any] = {
            "method": self.method,
            "tier": self.tier,
            "k": self.k,
            "estimated_exact_s": self.estimated_s,
            "budget_s": self.budget_s,
            "text": self.reason,
        }
        if self.k is None:
            del data["k"]
        return data


def plan(options: Any, n_candidates: int, samples: int, runs: int) -> Plan:
    """The ranking's plan for ``n_candidates`` records of ``samples`` input samples in all,
    each simulated at most ``runs`` times."""
    estimate = estimated_exact_s(samples, runs)
    budget = float(options.exact_budget_s)
    if options.rank_by != "simulated_response":
        return Plan(
            "tier", options.rank_by, None, estimate, budget,
            f"ranked by the tier {options.rank_by} at the ranking intensity (not simulated)",
        )  # fmt: skip
    k = options.prefilter_k or max(
        MIN_K_PER_N * options.n, math.ceil(PREFILTER_SHARE * n_candidates)
    )
    if options.prefilter == "none" or (
        options.prefilter == "auto" and (estimate <= budget or k >= n_candidates)
    ):
        within = f" within the budget {budget:g} CPU s" if estimate <= budget else ""
        why = f"every candidate simulated ({n_candidates}; estimated {estimate:.3g} CPU s{within})"
        return Plan("exact", None, None, estimate, budget, why)
    tier = DEFAULT_PREFILTER if options.prefilter == "auto" else options.prefilter
    k = min(k, n_candidates)
    if options.prefilter == "auto":
        why = (
            f"estimated {estimate:.3g} CPU s for all {n_candidates} candidates, over the budget "
            f"{budget:g} CPU s: the best {k} by {tier} simulated"
        )
    else:
        why = f"prefiltered as asked: the best {k} of {n_candidates} by {tier} simulated"
    return Plan("prefilter", tier, k, estimate, budget, why)


def best_rows(values: Floats, k: int) -> NDArray[np.int64]:
    """Indices of the ``k`` largest finite ``values`` (ties by index), then NaNs by index."""
    key = np.where(np.isnan(values), -np.inf, values)
    order = np.lexsort((np.arange(key.size), -key))
    return np.asarray(order[:k], dtype=np.int64)


def recall(exact_top: NDArray[np.int64], values: Floats, k: int) -> float:
    """Share of ``exact_top`` (indices of the exact ranking's top N) among the best ``k`` by
    ``values``."""
    if exact_top.size == 0:
        return math.nan
    return float(np.isin(exact_top, best_rows(values, k)).mean())


#: K as multiples of N in the recall of the exact top N.
RECALL_MULTIPLES = (1, 2, 5, 10)


def agreement(
    exact: Floats,
    tiers: dict[str, Floats],
    n: int,
    parallel: tuple[int | None, Executor | None] = (1, None),
) -> list[dict[str, Any]]:
    """Each tier against the exact ranking of the same candidates: Spearman ρ with it and the
    recall of the exact top ``n`` inside the tier's top K = m·n (m in :data:`RECALL_MULTIPLES`).

    Parameters
    ----------
    exact
        The exact ranking's percentile per candidate (1 most severe; all finite).
    tiers
        Tier name → its values at the ranking intensity (larger more severe), same candidates.
    n
        The size of the chosen set.
    parallel
        (jobs, executor) of the Spearman intervals' bootstraps (independent, each from seed 0:
        the same numbers on any number of workers; default this process).
    """
    import functools

    from stepframe.core.execution import call_each
    from stepframe.pipeline.selection.confirm import spearman_interval

    top = best_rows(exact, n)
    rows = []
    jobs, executor = parallel
    intervals = call_each(
        [functools.partial(spearman_interval, values, exact, 0) for values in tiers.values()],
        jobs=jobs,
        executor=executor,
        stage="tiers",
    )
    for (name, values), (rho, low, high, count) in zip(tiers.items(), intervals, strict=True):
        row: dict[str, Any] = {"tier": name, "spearman": rho, "low": low, "high": high, "n": count}
        finite = values[np.isfinite(values)]
        ranks = finite.size > 1 and bool(np.ptp(finite) > 0)
        for m in RECALL_MULTIPLES:
            # a tier that gives every candidate the same value ranks nothing (S_a(T_1) at equal
            # S_a(T_1)): its "top K" would be candidate order
            row[f"recall_at_{m}n"] = recall(top, values, m * n) if ranks else math.nan
        rows.append(row)
    return rows
