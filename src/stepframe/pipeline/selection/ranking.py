"""The ranking step of ``select_records``: every candidate at the stated intensity, by the frame's
simulated response (or by a tier when asked), with the plan that says what was simulated.

docs/selection.md, "Ranking by the simulated response": the intensity
(:mod:`~stepframe.pipeline.selection.intensity`), the plan (every candidate, or a prefilter's
best K: :mod:`~stepframe.pipeline.selection.tiers`), the ladder and the order
(:mod:`~stepframe.pipeline.selection.exact`).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from stepframe.core.results import Failure
from stepframe.core.text import number_text
from stepframe.errors import InputError
from stepframe.pipeline.selection.choose import percentile_scores
from stepframe.pipeline.selection.exact import (
    BISECTION_STEPS,
    LADDER,
    ResponseRanking,
    simulated_response,
)
from stepframe.pipeline.selection.intensity import RankingIntensity, ranking_intensity
from stepframe.pipeline.selection.names import SIMULATED_RESPONSE
from stepframe.pipeline.selection.peers import PEERS
from stepframe.pipeline.selection.tiers import Plan, best_rows, plan, tier_values

Floats = NDArray[np.float64]

#: Columns the ranking adds to candidates.csv (name → unit, meaning).
RANKING_COLUMNS: dict[str, tuple[str, str]] = {
    "ranking_scale": ("", "the record's scale factor at the ranking intensity"),
    "simulated": ("", "simulated for the ranking (every candidate, or the prefilter's best K)"),
    SIMULATED_RESPONSE: (
        "m",
        "geometric mean over the ladder of the simulated peak |x| (an overturned run counts as "
        "x_cap); ranks the candidates that never overturn in the ladder, larger first",
    ),
    "overturn_factor": (
        "",
        "the lowest factor on ranking_scale found to overturn the frame, up to the ladder's top "
        "(ranked first, lower first; empty: the frame stands at every ladder level)",
    ),
    "ranking_peak_x_m": ("m", "simulated peak |x| at the ranking intensity itself"),
    "ranking_overturned": ("", "the frame overturned at the ranking intensity itself"),
    "ladder_overturns": ("", "ladder levels at which the frame overturned"),
    "ranking_tie": (
        "",
        "the ranking does not tell it from a candidate on the other side of the chosen set's "
        "edge (the simulated ranking: overturn_factor and simulated_response within 0.11 %, "
        "the bisection's resolution; a tier: equal values)",
    ),
    **{name: (peer.unit, peer.meaning) for name, peer in PEERS.items()},
}
#: The simulator's free-vibration tail counted in the cost estimate [s].
TAIL_S = 10.0


@dataclass(frozen=True)
class Ranking:
    """What the ranking did: its intensity, its plan, each row's percentile (1 best), how many
    candidates it simulated and how long that took."""

    intensity: RankingIntensity
    plan: Plan
    z: Floats
    n_simulated: int
    seconds: float

    def summary(self) -> dict[str, Any]:
        """``ranking_intensity`` and ``ranking`` of selection.json."""
        return {
            "ranking_intensity": self.intensity.to_dict(),
            "ranking": {
                **self.plan.to_dict(),
                "n_simulated": self.n_simulated,
                "simulation_s": self.seconds,
            },
        }


def rank_candidates(
    table: Any,
    passing: NDArray[np.int64],
    samples: dict[int, tuple[Floats, float]],
    sd_t1_m: Floats,
    frame: Any,
    options: Any,
    simulated: Mapping[int, Any] | None = None,
    load: Callable[[list[int]], None] | None = None,
) -> tuple[Ranking, list[Failure], list[int]]:
    """Rank the passing rows of ``table`` at the options' intensity.

    Parameters
    ----------
    table
        The candidates, with ``psa_t1_g``, ``scale_factor`` and the tiers' columns; the ranking
        columns (:data:`RANKING_COLUMNS`) are added.
    passing
        Rows still in.
    samples
        Row → (ground acceleration [m/s²], dt [s]) of the rows this process holds.
    sd_t1_m
        SD(T_1, ξ_1) per row [m] (the onset ratio's measure).
    frame, options
        The frame and the run's options.
    simulated
        Row → the record pass's outcome (:class:`~stepframe.pipeline.selection.record_pass.
        Outcome`): its ``npts``, ``dt_s`` and, when the workers simulated the row at this very
        base scale, its ``ranked`` response (used as it is: each candidate's simulation depends
        on its record alone).
    load
        Called with the rows to simulate here whose samples ``samples`` lacks, to read them in.

    Returns
    -------
    Ranking, failures, failed rows
        The ranking, the rows whose simulation failed (item, stage, error) and their indices.
    """
    intensity = ranking_intensity(options, frame, LADDER)
    base = intensity.base_scales(
        frame,
        sd_t1_m,
        table["psa_t1_g"].to_numpy(dtype=np.float64),
        table["scale_factor"].to_numpy(dtype=np.float64),
    )
    table["ranking_scale"] = base
    for name in ("simulated", "ranking_overturned"):
        table[name] = False
    for name in (SIMULATED_RESPONSE, "overturn_factor", "ranking_peak_x_m"):
        table[name] = np.nan
    table["ladder_overturns"] = -1
    z = np.full(len(table), np.nan)
    if options.rank_by != SIMULATED_RESPONSE:
        # a tier alone: its values at the ranking intensity, nothing simulated
        the_plan = plan(options, int(passing.size), 0, len(LADDER))
        values = tier_values(table, options.rank_by, base)[passing]
        _check_ranks_something(options.rank_by, values, int(options.n))
        z[passing] = percentile_scores(values)
        return Ranking(intensity, the_plan, z, 0, 0.0), [], []
    failures: list[Failure] = []
    done = {
        int(i): outcome
        for i, outcome in (simulated or {}).items()
        if outcome.ranked is not None and outcome.ranked["base"] == base[i]
    }
    need = [int(i) for i in passing if math.isfinite(base[i]) and i not in done]
    if load is not None and need:
        load(need)
    usable = np.array(
        [i for i in passing if math.isfinite(base[i]) and (i in samples or i in done)], dtype=int
    )
    for i in sorted(set(passing.tolist()) - set(usable.tolist())):
        failures.append(_failure(table, i, f"ranking scale {base[i]:g}, expected a finite factor"))
    tail = sum(
        npts + TAIL_S / dt_s for npts, dt_s in (_size(i, samples, simulated) for i in usable)
    )
    # at most the ladder's runs and the bisection's, per candidate
    the_plan = plan(options, int(usable.size), int(tail), len(LADDER) + BISECTION_STEPS)
    rows = usable
    if the_plan.method == "prefilter":
        assert the_plan.tier is not None and the_plan.k is not None
        values = tier_values(table, the_plan.tier, base)[usable]
        rows = usable[np.sort(best_rows(values, the_plan.k))]
    start = time.perf_counter()
    response, seconds = _responses(frame, rows, samples, base, done)
    seconds += time.perf_counter() - start
    table.loc[rows, "simulated"] = True
    table.loc[rows, SIMULATED_RESPONSE] = response.response_m
    table.loc[rows, "overturn_factor"] = response.overturn_factor
    table.loc[rows, "ranking_peak_x_m"] = response.peak_m
    table.loc[rows, "ranking_overturned"] = response.overturned
    table.loc[rows, "ladder_overturns"] = response.n_overturned
    z[rows] = response.percentiles()
    failed = [int(i) for i, message in zip(rows, response.failed, strict=True) if message]
    failures += [_failure(table, i, response.failed[list(rows).index(i)]) for i in failed]
    bad = sorted(set(passing.tolist()) - set(usable.tolist())) + failed
    return Ranking(intensity, the_plan, z, int(rows.size), seconds), failures, bad


def _check_ranks_something(name: str, values: Floats, n: int) -> None:
    """A tier whose value is the same for every candidate (or undefined for all) ranks nothing:
    the chosen set would be the first n in file order. An error, not a silent pick (FEMA P695
    against Example 4's band: no fitted ω_g path enters it, ``band_coverage`` 0 for all 100)."""
    finite = values[np.isfinite(values)]
    # equal to rounding: a peer scaled to a common intensity is one number times a ratio
    if values.size <= n or (finite.size and np.ptp(finite) > 1e-12 * np.max(np.abs(finite))):
        return
    what = f"{finite[0]:g} for every one" if finite.size else "undefined for every one"
    raise InputError(
        f"rank_by = {name!r} is {what} of the {values.size} candidates, so it ranks nothing, "
        "expected a ranking that tells them apart (the default simulated_response, or another "
        "tier: docs/selection.md)"
    )


def _size(
    row: int, samples: Mapping[int, tuple[Floats, float]], simulated: Mapping[int, Any] | None
) -> tuple[int, float]:
    """A row's samples and dt [s], from its samples or its record pass."""
    if row in samples:
        return samples[row][0].size, samples[row][1]
    assert simulated is not None
    return simulated[row].npts, simulated[row].dt_s


def _responses(
    frame: Any,
    rows: NDArray[np.int64],
    samples: Mapping[int, tuple[Floats, float]],
    base: Floats,
    done: Mapping[int, Any],
) -> tuple[ResponseRanking, float]:
    """The simulated response of ``rows``: the workers' where they ran it (``done``), the rest
    simulated here; and the workers' seconds."""
    here = np.array([i for i in rows if i not in done], dtype=np.int64)
    local = simulated_response(frame, [samples[i] for i in here], base[here])
    position = {int(i): k for k, i in enumerate(here)}
    n = len(rows)
    response_m, factor, peak = np.full(n, np.nan), np.full(n, np.nan), np.full(n, np.nan)
    overturned = np.zeros(n, dtype=bool)
    n_overturned = np.zeros(n, dtype=np.int64)
    failed = [""] * n
    seconds = 0.0
    for j, i in enumerate(rows):
        if int(i) in done:
            entry = done[int(i)].ranked
            response_m[j], factor[j] = entry["response_m"], entry["overturn_factor"]
            peak[j], overturned[j] = entry["peak_m"], entry["overturned"]
            n_overturned[j], failed[j] = entry["n_overturned"], entry["failed"]
            seconds += float(done[int(i)].seconds[0])
            continue
        k = position[int(i)]
        response_m[j], factor[j] = local.response_m[k], local.overturn_factor[k]
        peak[j], overturned[j] = local.peak_m[k], local.overturned[k]
        n_overturned[j], failed[j] = local.n_overturned[k], local.failed[k]
    ranking = ResponseRanking(
        response_m, factor, peak, overturned, n_overturned, failed, local.factors
    )
    return ranking, seconds


def _failure(table: Any, row: int, message: str) -> Failure:
    name = f"{table['file'].iat[row]} [{table['component'].iat[row]}]"
    return Failure(name, "ranking", "SimulationError", message)


def _number(value: Any, digits: str = ".2f") -> str:
    return number_text(value, digits)


def tie_line(summary: dict[str, Any]) -> str | None:
    """The tie across the chosen set's edge, for people (the summary, the report); None when
    the ranking told the chosen from the rest."""
    tie = (summary.get("ranking") or {}).get("tie")
    if not isinstance(tie, dict):
        return None
    chosen, other = int(tie["n_chosen"]), int(tie["n_other"])
    factor = tie.get("overturn_factor")
    if "score" in tie:  # a tier: equal values
        keys, below = f"their {tie['score']} values are equal", "by candidate order"
    else:
        keys = (
            f"each overturns the frame from ×{factor:.3g} of its ranking scale and their "
            "ladder means are"
            if isinstance(factor, int | float)
            else "their overturning factors and ladder means are"
        ) + f" within {100 * float(tie['resolution']):.2g} %, the bisection's resolution"
        below = "by differences below it"
    return (
        f"tie: the ranking does not tell {chosen} of the chosen from {other} other candidates "
        f"({keys}): which {chosen} of these {chosen + other} are chosen is decided {below} "
        "(candidates.csv: ranking_tie)"
    )


def ranking_lines(summary: dict[str, Any]) -> list[str]:
    """For people (the demo's summary, the report): the stated intensity, what was simulated,
    the chosen set against the rest at that intensity, the run's ranking against the best
    standard intensity measures at the confirmation's equal PSA(T_1), and the tiers' recall of
    the exact top n. Empty parts are left out (a run ranked by a tier, without confirmation)."""
    lines = []
    intensity = summary.get("ranking_intensity") or {}
    ranking = summary.get("ranking") or {}
    if intensity:
        lines.append(f"ranked at: {intensity.get('text')}")
    if ranking:
        seconds = ranking.get("simulation_s")
        lines.append(
            f"ranking: {ranking.get('text')}"
            + (f"; simulations {seconds:.2g} s" if isinstance(seconds, int | float) else "")
        )
    versus = ranking.get("chosen_vs_rest") or {}
    if versus:
        from stepframe.pipeline.selection.intensity import intensity_level

        # Which intensity, said on the line: the chosen set's own scale is another.
        level = intensity_level(str(intensity.get("text") or ""))
        # every candidate chosen: no rest, and no median of it (absent from the summary)
        rest = (
            f"the other {versus['n_rest']} candidates "
            f"{_number(versus.get('peak_x_m_rest'), '.3g')} m ({versus['overturned_rest']} "
            "overturn)"
            if versus.get("n_rest")
            else "no other candidate (every candidate was chosen)"
        )
        lines.append(
            "at the ranking intensity"
            + (f" ({level})" if level else "")
            + ": the chosen reach a median peak |x| of "
            f"{_number(versus['peak_x_m_chosen'], '.3g')} m ({versus['overturned_chosen']} of "
            f"{versus['n_chosen']} overturn), {rest}"
        )
    rank_by = summary.get("rank_by")
    entries = [e for e in summary.get("correlations") or [] if isinstance(e, dict)]
    for response in ("peak_drift", "overturn_margin"):
        mine = next(
            (e for e in entries if e["score"] == rank_by and e["response"] == response), None
        )
        peers = sorted(
            (e for e in entries if e["response"] == response and e["score"] != rank_by
             and isinstance(e.get("spearman"), int | float) and math.isfinite(e["spearman"])),
            key=lambda e: -e["spearman"],
        )[:3]  # fmt: skip
        if mine is None or not peers:
            continue
        best = "; ".join(
            f"{e['score']} {_number(e['spearman'])} (Δρ {_number(e.get('delta'))} "
            f"[{_number(e.get('delta_low'))}, {_number(e.get('delta_high'))}])"
            for e in peers
        )
        lines.append(
            f"ρ with {response.replace('_', ' ')} at equal PSA(T_1) (the frame ranked with; "
            f"perturbed frames: docs/selection.md): {rank_by} {_number(mine.get('spearman'))} "
            f"[{_number(mine.get('low'))}, {_number(mine.get('high'))}]; next best {best}"
        )
    tiers = [
        t
        for t in summary.get("tiers") or []
        if isinstance(t, dict) and isinstance(t.get("spearman"), int | float)
        and math.isfinite(t["spearman"])
    ]  # fmt: skip
    if tiers:
        best_tiers = sorted(tiers, key=lambda t: -float(t["spearman"]))[:3]
        lines.append(
            "tiers closest to the exact ranking, ρ and recall of its top n within their top "
            "n/2n/5n/10n: "
            + "; ".join(
                f"{t['tier']} {_number(t['spearman'])}, "
                + "/".join(_number(t.get(f"recall_at_{m}n"), ".1f") for m in (1, 2, 5, 10))
                for t in best_tiers
            )
        )
    return lines
