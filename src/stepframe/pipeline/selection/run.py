"""``select_records``: filters, scores, spectra, the chosen set, rank stability, confirmation."""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Callable, Mapping
from concurrent.futures import Executor
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from stepframe.core.execution import call_each, default_jobs, map_items
from stepframe.core.results import Failure, failures_table, set_column_dictionary
from stepframe.errors import InputError
from stepframe.pipeline.selection import confirm as confirmation
from stepframe.pipeline.selection import record_pass
from stepframe.pipeline.selection import scores as sc
from stepframe.pipeline.selection.band import FrameBand, frame_band
from stepframe.pipeline.selection.choose import Units, choose, percentile_scores
from stepframe.pipeline.selection.chosen import ChosenSet, chosen_set
from stepframe.pipeline.selection.exact import RESOLUTION, tied_across
from stepframe.pipeline.selection.filters import FilterReport, apply_filters, filter_summary
from stepframe.pipeline.selection.grouping import COLUMNS as GROUPING_COLUMNS
from stepframe.pipeline.selection.grouping import grouping_summary
from stepframe.pipeline.selection.intensity import checked_target, onset_psa_t1_g
from stepframe.pipeline.selection.memory import check_selection_memory
from stepframe.pipeline.selection.names import (
    DOMINATED,
    PEER_NAMES,
    PHYSICS_SCORES,
    SIMULATED_RESPONSE,
    TIERS,
    ranks_by_fit,
)
from stepframe.pipeline.selection.options import SelectionOptions
from stepframe.pipeline.selection.path import MODEL_COLUMNS, strong_motion_paths
from stepframe.pipeline.selection.peers import PEERS
from stepframe.pipeline.selection.ranking import RANKING_COLUMNS, Ranking, rank_candidates
from stepframe.pipeline.selection.result import SelectionResult, column_dictionary
from stepframe.pipeline.selection.samples import read_samples as _read_samples
from stepframe.pipeline.selection.spectral import (
    record_scales,
    scale_factors,
    spectral_misfit,
    target_values,
)
from stepframe.pipeline.selection.substitute import (
    SubstituteLevels,
    predicted_overturn_ratio,
    substitute_demand_ratio,
)
from stepframe.records.units import STANDARD_GRAVITY_M_S2
from stepframe.structure.frame import PortalFrame

Floats = NDArray[np.float64]
Samples = tuple[Floats, float]
RecordKey = tuple[str, str]

CANDIDATE_COLUMNS: dict[str, tuple[str, str]] = {
    "window_start_s": ("s", "start of strong motion after t0 (I_g ≥ fraction of its peak)"),
    "window_end_s": ("s", "end of strong motion after t0"),
    "omega_window_start_rad_s": ("rad/s", "fitted omega_g at the start of strong motion"),
    "omega_window_end_rad_s": ("rad/s", "fitted omega_g at the end of strong motion"),
    "enters_from_above": ("", "omega_g starts strong motion above omega_1 and ends below it"),
    **GROUPING_COLUMNS,
    **sc.SCORES,
    "substitute_overturn_ratio": (
        "",
        "max(1, 1/substitute_demand_ratio): the substitute structure's estimate of the lowest "
        "P_1*SD(T_1)/x_c that overturns the frame",
    ),
    "rank_score_percentile": ("", "percentile of the ranking score among candidates (1 best)"),
    "psa_t1_g": ("g", "PSA at T_1 (5 % damping), unscaled"),
    "scale_factor": ("", "scale factor by the scaling policy"),
    "scale_clipped": ("", "the scale factor hit scale_min or scale_max"),
    "spectral_misfit": ("", "RMS of ln(scaled PSA / target) over the misfit periods"),
    "selection_probability": (
        "",
        "share of bootstrap replicates (fit standard errors) in which the component is chosen",
    ),
    "selected": ("", "in the chosen set"),
    "control": ("", "a control of the confirmation (passed the filters, ranked lowest)"),
    "dropped_by": ("", "the filter that dropped the row (empty: passed every filter)"),
    # the ranking's columns (ranking.py)
    **RANKING_COLUMNS,
}
CONFIRMATION_COLUMNS: dict[str, tuple[str, str]] = {
    "file": ("", "record file"),
    "component": ("", "component"),
    "group": ("", "selected, control, or candidate (every candidate at equal intensity)"),
    "case": ("", "chosen-scale or equal-psa-t1"),
    "scale": ("", "scale factor applied to the record"),
    "peak_abs_x_m": ("m", "peak |x| of the frame"),
    "peak_drift_ratio": ("", "peak |x| / H_r"),
    "overturned": ("", "the frame overturned"),
    "n_stepping_episodes": ("", "lift-offs"),
    "n_impacts": ("", "touchdowns"),
    "status": ("", "simulator status"),
    "overturn_onset_ratio": (
        "",
        "lowest P_1·SD(T_1)/x_c found to overturn the frame (scan and bisection; equal-psa-t1 "
        "rows; NaN: none up to 4)",
    ),
}


def _with_dictionary(table: Any, columns: Mapping[str, tuple[str, str]]) -> Any:
    known = {**columns}
    from stepframe.stochastic.catalog_features import COLUMNS as FEATURE_COLUMNS

    for name in table.columns:
        if name not in known:
            known[name] = FEATURE_COLUMNS.get(name, ("", "from the input table"))
    set_column_dictionary(table, column_dictionary({name: known[name] for name in table.columns}))
    return table


PhysicsItem = tuple[str, dict[str, float], FrameBand, float, float, tuple[float, float]]


#: ``dropped_by`` reasons of candidates that passed the filters but could not be computed, and
#: the rule of the report that counts them.
COMPUTE_FAILURES = ("physics_failed", "samples_failed", "spectra_failed")
COMPUTED_RULE = "samples read, spectra and scores computed (the rest in failures.csv)"


def _item_name(item: PhysicsItem) -> str:
    return item[0]


def _physics_item(item: PhysicsItem) -> tuple[float, float]:
    _, row, band, xi_1, xi_levels, window = item
    return sc.physics_scores(row, band, xi_1, xi_levels, window)


def _check_table(features: Any) -> None:
    # dt_s and duration_s too: the memory estimate reads them first (a KeyError before)
    wanted = (*MODEL_COLUMNS, "file", "component", "plausible", "dt_s", "duration_s")
    missing = [c for c in wanted if c not in features]
    if missing:
        raise InputError(
            f"features table lacks columns {missing}, expected the table of "
            "stepframe.stochastic.catalog_features"
        )


def _cheap_scores(table: Any, band: FrameBand, fraction: float) -> dict[str, Any]:
    paths = strong_motion_paths(table, fraction)
    return {
        "paths": paths,
        "band_coverage": sc.band_coverage(paths, band),
        "enters_from_above": sc.enters_from_above(paths, band),
        "spectral_ratio_eq_6_18": sc.spectral_ratio_eq_6_18(table, band.omega_1_rad_s),
        "omega_p_over_s_sq": sc.omega_p_over_s_sq(table),
    }


def _physics(
    table: Any,
    rows: NDArray[np.int64],
    band: FrameBand,
    frame: PortalFrame,
    paths: Any,
    jobs: int | None,
    executor: Executor | None,
) -> tuple[Floats, Floats, list[Failure], list[int]]:
    xi_levels = sc.equivalent_damping(frame.xi_2, frame.c_r)
    records = table.to_dict(orient="records")
    items: list[PhysicsItem] = [
        (
            f"{records[i]['file']} [{records[i]['component']}]",
            {c: float(records[i][c]) for c in MODEL_COLUMNS},
            band,
            frame.xi_1,
            xi_levels,
            (float(paths.start_s[i]), float(paths.end_s[i])),
        )
        for i in rows
    ]
    outcome = map_items(
        _physics_item,
        items,
        jobs=jobs,
        executor=executor,
        stage="physics",
        name_of=_item_name,
    )
    backbone = np.full(len(table), np.nan)
    descent = np.full(len(table), np.nan)
    for k, (b, d) in zip(outcome.indices, outcome.results, strict=True):
        backbone[rows[k]] = b
        descent[rows[k]] = d
    failed = sorted(set(range(len(rows))) - set(outcome.indices))
    return backbone, descent, outcome.failures, [int(rows[k]) for k in failed]


def _perturbed(table: Any, rng: np.random.Generator) -> Any:
    """The table with its eq. 6.10-6.11 parameters redrawn from N(value, standard error),
    repaired into the model's domain (ω_p ≥ ω_s ≥ ω_r > 0, 0 < ξ < 1, 0 < t_max < t_dur)."""
    out = table.copy()
    for name in ("omega_p_rad_s", "omega_s_rad_s", "omega_r_rad_s", "xi_p", "xi_r", "t_max_s"):
        stderr = np.nan_to_num(np.asarray(table[f"{name}_stderr"], dtype=np.float64))
        value = np.asarray(table[name], dtype=np.float64)
        out[name] = value + rng.standard_normal(value.size) * np.abs(stderr)
    omegas = np.sort(
        np.maximum(out[["omega_p_rad_s", "omega_s_rad_s", "omega_r_rad_s"]].to_numpy(), 1e-3),
        axis=1,
    )[:, ::-1]
    omegas[:, 0] = np.maximum(omegas[:, 0], omegas[:, 2] * (1 + 1e-6))
    out["omega_p_rad_s"], out["omega_s_rad_s"], out["omega_r_rad_s"] = omegas.T
    for name in ("xi_p", "xi_r"):
        out[name] = np.clip(out[name], 1e-3, 0.999)
    t_dur = np.asarray(table["t_dur_s"], dtype=np.float64)
    out["t_max_s"] = np.clip(out["t_max_s"], 1e-3 * t_dur, 0.999 * t_dur)
    return out


def _units(
    table: Any, rows: NDArray[np.int64], z: Floats, unit: str, log_psa: Floats | None
) -> tuple[Units, list[list[int]]]:
    """Group candidate rows into units (components, or records by event and station); a
    unit's score is the mean of its members' finite scores (-inf when none is finite)."""
    import pandas as pd

    rows = np.asarray(rows, dtype=np.int64)
    # the grouping's keys (filters.add_grouping): a record without an event is its own event
    events = table["event_key"].astype(str).to_numpy()
    stations = table["station_key"].astype(str).to_numpy()
    if unit == "record":
        codes, _ = pd.factorize(pd.Series(table["record"].astype(str).to_numpy()[rows]))
    else:
        codes = np.arange(rows.size)
    n_units = int(codes.max()) + 1 if rows.size else 0
    if unit == "record":
        order = np.argsort(codes, kind="stable")
        bounds = np.searchsorted(codes[order], np.arange(n_units + 1))
        members = [rows[order[bounds[u] : bounds[u + 1]]].tolist() for u in range(n_units)]
    else:
        members = [[r] for r in rows.tolist()]
    values = z[rows]
    finite = np.isfinite(values)
    sums = np.bincount(codes, weights=np.where(finite, values, 0.0), minlength=n_units)
    counts = np.bincount(codes, weights=finite.astype(float), minlength=n_units)
    with np.errstate(invalid="ignore", divide="ignore"):
        unit_z = np.where(counts > 0, sums / counts, -np.inf)
    return (
        Units(
            unit_z,
            members,
            np.asarray(events, dtype=object),
            np.asarray(stations, dtype=object),
            None if log_psa is None else _unit_means(log_psa, rows, codes),
        ),
        members,
    )


def _unit_means(log_psa: Floats, rows: NDArray[np.int64], codes: NDArray[np.int64]) -> Floats:
    """Each unit's mean of its members' rows of ``log_psa`` (unit ``codes[k]`` holds
    ``rows[k]``, codes 0, 1, ... each used), equal to the bit to a mean per unit: the members
    added in the same order (first, then second, ...: a unit has one or two, and a few more
    only in a hand-made table), a vector step per member rank instead of a Python loop over
    units (21,500 means were a second of the main process at NGA-West2 size)."""
    n_units = int(codes.max()) + 1 if rows.size else 0
    order = np.argsort(codes, kind="stable")
    starts = np.searchsorted(codes[order], np.arange(n_units))
    sizes = np.bincount(codes, minlength=n_units)
    members = rows[order]
    sums = np.zeros((n_units, *log_psa.shape[1:]))
    for rank in range(int(sizes.max()) if n_units else 0):
        units = np.flatnonzero(sizes > rank)
        if rank == 0:
            sums[units] = log_psa[members[starts[units]]]
        else:
            sums[units] += log_psa[members[starts[units] + rank]]
    out: Floats = sums / sizes.reshape((-1,) + (1,) * (log_psa.ndim - 1))
    return out


def _drop_single_components(
    table: Any, dropped_by: NDArray[np.object_], reports: list[FilterReport]
) -> None:
    """``unit="record"``: keep only records (:mod:`.grouping`) with exactly two horizontal
    components left, so that every chosen record is a pair; one left is ``one_component``, more
    than two (the same record in several files) ``not_a_pair``."""
    import pandas as pd

    key = pd.Series(table["record"].astype(str).to_numpy())
    alive = dropped_by == ""
    sizes = key.map(key[alive].value_counts()).fillna(0).to_numpy()
    for name, rule, bad in (
        ("one_component", "both horizontal components of the record passed", sizes < 2),
        ("not_a_pair", "the record has two horizontal components, not more", sizes > 2),
    ):
        drop = alive & bad
        if name == "not_a_pair" and not drop.any():
            continue
        dropped_by[drop] = name
        reports.append(FilterReport(name, rule, int(drop.sum()), int((dropped_by == "").sum())))


def _spectra(
    table: Any,
    dropped_by: NDArray[np.object_],
    spec: record_pass.PassSpec,
    out: tuple[Floats, Floats, Floats],
    records: Mapping[RecordKey, Samples] | None,
    parallel: tuple[int | None, Executor | None],
    responses: Mapping[RecordKey, Mapping[str, Any]] | None,
) -> tuple[dict[int, record_pass.Outcome], list[Failure]]:
    """The passing candidates' record pass (:mod:`.record_pass`: in the workers, or stored by
    the ``responses`` stage for this very pass): PSA (5 %) at T_1 and the misfit periods into
    ``table["psa_t1_g"]`` and ``out[0]``, SD(T_1, ξ_1) into ``out[1]``, SD at the substitute
    structure's levels into ``out[2]`` (when the pass computes them), and the peers
    (:mod:`~stepframe.pipeline.selection.peers`) into the table; the outcomes by row (with the
    ranking's and the confirmation's simulations when the pass ran them). Rows without samples
    or spectra get their ``dropped_by`` reason."""
    psa, sd_t1, sd_levels = out
    jobs, executor = parallel
    passing = np.flatnonzero(dropped_by == "")
    digest = record_pass.spec_digest(spec) if responses else ""
    files = table["file"].astype(str).to_numpy()
    components = table["component"].astype(str).to_numpy()
    results: list[record_pass.Outcome] = []
    todo = []
    for row in passing.tolist():
        entry = responses.get((files[row], components[row])) if responses else None
        if entry is not None and entry["spec"] == digest:
            results.append(record_pass.from_stored(row, entry))
        else:
            todo.append(row)
    computed = map_items(
        record_pass.record_pass,
        record_pass.items(table, todo, records, spec, jobs or default_jobs()),
        jobs=jobs,
        executor=executor,
        chunk_size=1,
        stage="spectra",
        name_of=record_pass.item_name,
    )
    results += [entry for entries in computed.results for entry in entries]
    from stepframe.records.spectra import pseudo_acceleration_m_s2

    psa_t1 = np.full(len(table), np.nan)
    peer_values = {name: np.full(len(table), np.nan) for name in PEERS}
    lost: dict[str, list[Failure]] = {"samples": [], "spectra": []}
    outcomes: dict[int, record_pass.Outcome] = {}
    for result in results:
        if result.failure is not None:
            lost[result.failure.stage].append(result.failure)
            dropped_by[result.row] = f"{result.failure.stage}_failed"
            continue
        assert result.sd_5 is not None and result.peers is not None
        values = pseudo_acceleration_m_s2(spec.groups[0][0], result.sd_5)
        psa_t1[result.row] = values[0] / STANDARD_GRAVITY_M_S2
        psa[result.row] = values[1:]
        sd_t1[result.row] = result.sd_t1_m
        if result.sd_levels is not None:
            sd_levels[result.row] = result.sd_levels
        for name, value in result.peers.items():
            peer_values[name][result.row] = value
        outcomes[result.row] = result
    table["psa_t1_g"] = psa_t1
    for name, peer in peer_values.items():
        table[name] = peer
    missing = np.flatnonzero((dropped_by == "") & ~np.isfinite(psa_t1))
    dropped_by[missing] = "spectra_failed"
    return outcomes, [*lost["samples"], *lost["spectra"], *computed.failures]


@dataclass
class Candidates:
    """The candidates of a run as the steps of :func:`select_records` fill them in.

    Attributes
    ----------
    table
        One row per component: the features, then each step's columns (CANDIDATE_COLUMNS).
    band
        The frame's band.
    paths
        Each row's fitted ω_g(t) in strong motion.
    dropped_by
        Per row, the filter (or failed computation) that dropped it; empty while it is in.
    reports
        What each filter dropped, in order.
    failures
        Rows that could not be computed (item, stage, error).
    """

    table: Any
    band: FrameBand
    paths: Any
    dropped_by: NDArray[np.object_]
    reports: list[FilterReport]
    failures: list[Failure] = field(default_factory=list)

    @property
    def passing(self) -> NDArray[np.int64]:
        """Rows still in."""
        return np.flatnonzero(self.dropped_by == "")

    @property
    def summary_line(self) -> str:
        """What each filter dropped, in one line."""
        return filter_summary(self.reports, len(self.table))


@dataclass(frozen=True)
class Spectra:
    """The record spectra of the passing candidates: PSA at the misfit periods, SD(T_1, ξ_1),
    SD at the substitute structure's levels (NaN unless the substitute score is asked for), the
    record pass's outcomes by row (:mod:`.record_pass`: numbers, no samples), and the samples
    of the few rows this process reads (:meth:`load`: the chosen set and its controls; every
    candidate only where a step needs them together, such as a record's two components)."""

    periods_s: Floats
    psa: Floats
    sd_levels: Floats
    levels: SubstituteLevels
    samples: dict[int, Samples]
    sd_t1_m: Floats
    outcomes: dict[int, record_pass.Outcome] = field(default_factory=dict)
    sources: tuple[Mapping[RecordKey, Samples] | None, Mapping[str, Any] | None] = (None, None)

    def load(self, table: Any, rows: Any) -> list[Failure]:
        """Read the samples of ``rows`` this process does not hold yet (into :attr:`samples`);
        the rows whose samples could not be had."""
        missing = np.array([int(i) for i in rows if int(i) not in self.samples], dtype=np.int64)
        if not missing.size:
            return []
        more, failures = _read_samples(table, missing, *self.sources)
        self.samples.update(more)
        return failures


@dataclass(frozen=True)
class Choice:
    """The chosen set: its rows, the controls and the ranking's units."""

    chosen_rows: list[int]
    control_rows: list[int]
    n_units: int
    log_psa: Floats | None
    log_target: Floats | None


def filtered_candidates(
    features: Any,
    frame: PortalFrame,
    options: SelectionOptions,
    sources: tuple[Mapping[RecordKey, Samples] | None, Mapping[str, Any] | None] = (None, None),
) -> Candidates:
    """Step 1: the frame's band, each record's path through it and the cheap scores, then the
    records (components grouped) and the filters (docs/selection.md, "Candidates")."""
    table = features.reset_index(drop=True).copy()
    band = frame_band(
        frame,
        a_max_m=options.a_max_m,
        design_displacement_m=options.design_displacement_m,
        x_star_fraction=options.x_star_fraction,
        n_levels=options.n_levels,
    )
    cheap = _cheap_scores(table, band, options.strong_motion_fraction)
    paths = cheap["paths"]
    table["window_start_s"] = paths.start_s
    table["window_end_s"] = paths.end_s
    table["omega_window_start_rad_s"] = paths.omega_start_rad_s
    table["omega_window_end_rad_s"] = paths.omega_end_rad_s
    for name in ("enters_from_above", "band_coverage", "spectral_ratio_eq_6_18",
                 "omega_p_over_s_sq"):  # fmt: skip
        table[name] = cheap[name]
    dropped_by, reports = apply_filters(table, options, band, paths, sources)
    candidates = Candidates(table, band, paths, dropped_by, reports)
    if candidates.passing.size == 0:
        raise InputError(
            f"every candidate was filtered out ({candidates.summary_line}), expected some left"
        )
    return candidates


def _named(options: SelectionOptions) -> set[str]:
    """The tiers a run names: its ranking, its prefilter and its extra scores."""
    return {options.rank_by, options.prefilter, *options.scores}


def physics_scores(
    candidates: Candidates,
    frame: PortalFrame,
    options: SelectionOptions,
    parallel: tuple[int | None, Executor | None],
) -> None:
    """Step 2 (when the run names them: they are dominated, docs/selection.md): the fitted
    model's backbone and descent amplifications."""
    table = candidates.table
    if not _named(options) & set(PHYSICS_SCORES):
        return
    table["backbone_amplification"] = np.nan
    table["descent_amplification"] = np.nan
    backbone, descent, fails, failed_rows = _physics(
        table, candidates.passing, candidates.band, frame, candidates.paths, *parallel
    )
    table["backbone_amplification"] = backbone
    table["descent_amplification"] = descent
    candidates.failures += fails
    candidates.dropped_by[failed_rows] = "physics_failed"


def spectra_and_substitute(
    candidates: Candidates,
    options: SelectionOptions,
    sources: tuple[Mapping[RecordKey, Samples] | None, Mapping[str, Any] | None],
    parallel: tuple[int | None, Executor | None],
    responses: Mapping[RecordKey, Mapping[str, Any]] | None = None,
) -> Spectra:
    """Step 3: the passing records' one pass in the workers (:mod:`.record_pass`: PSA at T_1
    and the misfit periods, SD(T_1, ξ_1), the peers, SD at the substitute levels when the
    substitute score is named, and the simulations that depend on the record alone); the
    substitute structure's scores."""
    table, band = candidates.table, candidates.band
    _, periods, levels, spec = record_pass.selection_inputs(band.frame, options, sources[1])
    substitute = "substitute_demand_ratio" in _named(options)
    table["psa_t1_g"] = np.nan
    psa = np.full((len(table), periods.size), np.nan)
    sd_t1 = np.full(len(table), np.nan)
    sd_levels = np.full((len(table), levels.periods_s.size), np.nan)
    outcomes: dict[int, record_pass.Outcome] = {}
    if spec is not None:
        outcomes, fails = _spectra(
            table, candidates.dropped_by, spec, (psa, sd_t1, sd_levels), sources[0], parallel,
            responses,
        )  # fmt: skip
        candidates.failures += fails
    if substitute:
        table["substitute_demand_ratio"] = substitute_demand_ratio(sd_levels, levels)
        table["substitute_overturn_ratio"] = predicted_overturn_ratio(
            table["substitute_demand_ratio"].to_numpy()
        )
    _count_compute_failures(candidates, options)
    if options.unit == "record":
        _drop_single_components(table, candidates.dropped_by, candidates.reports)
    return Spectra(periods, psa, sd_levels, levels, {}, sd_t1, outcomes, sources)


def _count_compute_failures(candidates: Candidates, options: SelectionOptions) -> None:
    """Report the candidates that passed the filters but could not be computed; none left is
    an error naming the first failure."""
    dropped_by = candidates.dropped_by
    failed = int(np.isin(dropped_by, COMPUTE_FAILURES).sum())
    if not failed:
        return
    left = int((dropped_by == "").sum())
    candidates.reports.append(FilterReport("computed", COMPUTED_RULE, failed, left))
    if left == 0:
        failures = candidates.failures
        first = f"; first failure: {failures[0].item}: {failures[0].message}" if failures else ""
        raise InputError(
            f"no candidate could be computed ({candidates.summary_line}{first}), expected "
            f"readable records for {options.rank_by} (records= or the files by path), or "
            "rank_by a score of the fit"
        )


def rank_and_scale(
    candidates: Candidates,
    spectra: Spectra,
    frame: PortalFrame,
    options: SelectionOptions,
    target: Any,
) -> tuple[Floats, Floats | None, Floats | None, Ranking]:
    """Step 4: each passing candidate's scale factor by the scaling policy and its misfit to
    the target (one factor per record with ``unit="record"``: :func:`scale_records`), then the
    ranking at the stated intensity (:mod:`.ranking`: the simulated
    response by default); returns the ranking's percentiles (1 best), the log spectra the
    choice matches (None without a target) and the ranking."""
    table, band = candidates.table, candidates.band
    psa = spectra.psa
    psa_t1 = table["psa_t1_g"].to_numpy() * STANDARD_GRAVITY_M_S2
    target_t1 = None if target is None else target.sa_m_s2(band.period_1_s)
    target_psa = None if target is None else target_values(target, spectra.periods_s)
    scales, clipped = scale_factors(
        options.scale, psa_t1, psa, target_t1, target_psa, (options.scale_min, options.scale_max)
    )
    table["scale_factor"] = scales
    table["scale_clipped"] = clipped
    table["spectral_misfit"] = (
        spectral_misfit(psa, scales, target_psa) if target_psa is not None else np.nan
    )
    log_psa = None
    if target_psa is not None:
        with np.errstate(divide="ignore", invalid="ignore"):
            log_psa = np.log(scales[:, None] * psa)
    if options.unit == "record":  # one factor per record, before the ranking uses it
        log_psa = scale_records(candidates, spectra, options, target, log_psa)
    ranking = _rank(candidates, spectra, frame, options)
    z = ranking.z
    table["rank_score_percentile"] = z
    return z, log_psa, None if target_psa is None else np.log(target_psa), ranking


def _rank(
    candidates: Candidates, spectra: Spectra, frame: PortalFrame, options: SelectionOptions
) -> Ranking:
    """The ranking at the stated intensity; rows whose simulation failed are dropped (and in
    failures.csv)."""
    table = candidates.table

    def load(rows: list[int]) -> None:  # where the workers could not rank: read here
        candidates.failures.extend(spectra.load(table, rows))

    ranking, failures, failed = rank_candidates(
        table, candidates.passing, spectra.samples, spectra.sd_t1_m, frame, options,
        spectra.outcomes, load,
    )  # fmt: skip
    candidates.failures += failures
    if failed:
        candidates.dropped_by[failed] = "simulation_failed"
        left = int((candidates.dropped_by == "").sum())
        rule = "simulated at the ranking intensity (the rest in failures.csv)"
        candidates.reports.append(FilterReport("simulated", rule, len(failed), left))
        if left == 0:
            raise InputError(
                f"no candidate could be simulated ({candidates.summary_line}; first failure: "
                f"{failures[0].item}: {failures[0].message}), expected records the frame's "
                "simulator accepts"
            )
    return ranking


def _picker(options: SelectionOptions, log_target: Floats | None) -> Callable[[Units], list[int]]:
    def pick(candidates: Units) -> list[int]:
        return choose(
            candidates,
            options.n,
            weight=options.spectral_weight,
            log_target=log_target,
            max_per_event=options.max_per_event,
            max_per_station=options.max_per_station,
        )

    return pick


def choose_set(
    candidates: Candidates,
    z: Floats,
    log_psa: Floats | None,
    log_target: Floats | None,
    options: SelectionOptions,
) -> Choice:
    """Step 5: the units (components or records), the chosen n under the caps and the spectral
    match, and as many controls (the lowest ranked units not chosen)."""
    table = candidates.table
    units, members = _units(table, candidates.passing, z, options.unit, log_psa)
    if len(members) < options.n:
        what = "records" if options.unit == "record" else "candidates"
        raise InputError(
            f"n = {options.n} but only {len(members)} {what} left ({candidates.summary_line}), "
            f"expected n ≤ {len(members)}"
        )
    chosen = _picker(options, log_target)(units)
    order = np.argsort(units.z, kind="stable")
    taken = set(chosen)
    controls = [int(u) for u in order if u not in taken][: len(chosen)]
    chosen_rows = [i for u in chosen for i in members[u]]
    control_rows = [i for u in controls for i in members[u]]
    return Choice(chosen_rows, control_rows, len(chosen), log_psa, log_target)


def rank_stability(
    candidates: Candidates,
    frame: PortalFrame,
    choice: Choice,
    options: SelectionOptions,
    parallel: tuple[int | None, Executor | None],
) -> None:
    """Step 6: redraw the fitted parameters from their standard errors, rescore, choose again;
    each candidate's share of replicates in which it is chosen (one batch for all replicates,
    so a process pool starts once)."""
    import pandas as pd

    table, band, passing = candidates.table, candidates.band, candidates.passing
    counts = np.zeros(len(table))
    replicates = options.n_bootstrap
    if not ranks_by_fit(options.rank_by):
        # The record's response and spectrum do not depend on the fit: every replicate would
        # rank alike and choose this set (1 for it, 0 for the rest), so none is drawn.
        counts[choice.chosen_rows] = replicates
        replicates = 0
    rng = np.random.default_rng(options.seed)
    if replicates:
        drawn = pd.concat(
            [_perturbed(table.iloc[passing].reset_index(drop=True), rng)
             for _ in range(replicates)],
            ignore_index=True,
        )  # fmt: skip
        if options.rank_by in PHYSICS_SCORES:
            paths = strong_motion_paths(drawn, options.strong_motion_fraction)
            b, d, _, _ = _physics(drawn, np.arange(len(drawn)), band, frame, paths, *parallel)
            all_values = b if options.rank_by == "backbone_amplification" else d
        else:
            cheap = _cheap_scores(drawn, band, options.strong_motion_fraction)
            all_values = np.asarray(cheap[options.rank_by], dtype=np.float64)
        pick = _picker(options, choice.log_target)
        for values in all_values.reshape(options.n_bootstrap, passing.size):
            z_b = np.full(len(table), np.nan)
            z_b[passing] = percentile_scores(values)
            units_b, members_b = _units(table, passing, z_b, options.unit, choice.log_psa)
            for u in pick(units_b):
                counts[members_b[u]] += 1
    probability = np.full(len(table), np.nan)
    if options.n_bootstrap:
        probability[passing] = counts[passing] / options.n_bootstrap
    table["selection_probability"] = probability


def _mark_choice(candidates: Candidates, choice: Choice) -> None:
    """The table's ``selected``, ``control`` and ``dropped_by`` columns."""
    table = candidates.table
    table["selected"] = False
    table.loc[choice.chosen_rows, "selected"] = True
    table["control"] = False
    table.loc[choice.control_rows, "control"] = True
    table["dropped_by"] = candidates.dropped_by


def _selection_table(table: Any, chosen_rows: list[int], rank_by: str) -> Any:
    """The chosen rows, in the order chosen, the most telling columns first."""
    selection = table.loc[chosen_rows].copy()
    selection.insert(0, "rank", np.arange(1, len(chosen_rows) + 1))
    selection.insert(1, "score", selection[rank_by].to_numpy())
    keep_first = [
        "rank", "file", "component", "station", "score", "scale_factor",
        "selection_probability", "rank_score_percentile", "ranking_scale", SIMULATED_RESPONSE,
        "ranking_peak_x_m", "ranking_overturned", "ladder_overturns", *PEERS, *sc.SCORES,
        "enters_from_above",
        "psa_t1_g", "spectral_misfit",
    ]  # fmt: skip
    keep = [c for c in keep_first if c in selection.columns]
    selection = selection[keep + [c for c in selection.columns if c not in keep]]
    return selection.reset_index(drop=True)


def select_records(
    features: Any,
    frame: PortalFrame,
    options: SelectionOptions,
    *,
    records: Mapping[RecordKey, Samples] | None = None,
    jobs: int | None = None,
    executor: Executor | None = None,
    record_options: Mapping[str, Any] | None = None,
    responses: Mapping[RecordKey, Mapping[str, Any]] | None = None,
) -> SelectionResult:
    """Select records by moving resonance for ``frame`` (docs/selection.md).

    The steps, each a function of this module: the candidates and their filters, the physics
    scores, the spectra and the substitute structure's scores, the ranking and scaling, the
    choice, its stability under the fits' errors, and the confirmation by simulation.

    Parameters
    ----------
    features
        The features table of :func:`stepframe.stochastic.catalog_features.catalog_features`
        (one row per component), optionally joined with metadata columns for the filters
        (``magnitude``, ``rrup_km``, ``vs30_m_s``, ``pga_g``, ``event``, ``station``, ``rsn``...).
    frame
        The stepping frame.
    options
        The run's options.
    records
        (file, component) → (ground acceleration [m/s²], dt [s]) for the spectra and the
        confirmation; None re-reads each file by its path with :func:`stepframe.records.read`
        (``record_options`` passed on). Not needed when neither scaling, a target nor the
        confirmation is asked for.
    jobs, executor
        Parallelism of the per-candidate steps (:func:`stepframe.core.execution.map_items`).
    responses
        (file, component) → the stored outcome of the record pass
        (:func:`.record_pass.stored`), as the workflow's ``responses`` stage computed it; a
        candidate without one, or with one of another pass, is computed in the workers here.

    Returns
    -------
    SelectionResult

    Raises
    ------
    InputError
        A features table without the model columns; a run whose memory estimate passes the
        budget (:mod:`.memory`); every candidate filtered out; fewer candidates left than
        ``options.n`` (the message says how many passed each filter).
    """
    _check_table(features)
    target = checked_target(options, frame)  # an unreadable target fails before any work
    workers = 1 if jobs == 1 and executor is None else (jobs or default_jobs())
    check_selection_memory(features, records, workers, int(options.n))
    parallel = (jobs, executor)
    candidates = filtered_candidates(features, frame, options, (records, record_options))
    physics_scores(candidates, frame, options, parallel)
    spectra = spectra_and_substitute(
        candidates, options, (records, record_options), parallel, responses
    )
    z, log_psa, log_target, ranking = rank_and_scale(candidates, spectra, frame, options, target)
    choice = choose_set(candidates, z, log_psa, log_target, options)
    rank_stability(candidates, frame, choice, options, parallel)
    _mark_choice(candidates, choice)
    chosen = chosen_outcome(candidates, spectra, choice, frame, options, target,
                            (records, record_options))  # fmt: skip
    result = _result(candidates, spectra, choice, frame, options, ranking, parallel)
    return with_chosen(result, chosen)


def _result(
    candidates: Candidates,
    spectra: Spectra,
    choice: Choice,
    frame: PortalFrame,
    options: SelectionOptions,
    ranking: Ranking,
    parallel: tuple[int | None, Executor | None] = (1, None),
) -> SelectionResult:
    """Step 7: the confirmation by simulation (when asked) and the result's tables; the
    bootstrap intervals of the tiers and of the confirmation in the workers (``parallel``)."""
    import pandas as pd

    table, band, failures = candidates.table, candidates.band, candidates.failures
    status, message = (
        "ok",
        (
            f"{len(choice.chosen_rows)} components chosen by {options.rank_by} at "
            f"{ranking.intensity.describe()}"
        ),
    )
    if choice.n_units < options.n:
        status = "degraded"
        message = f"only {choice.n_units} of {options.n} could be chosen under the caps"
    if failures:
        status = "degraded"
        message += f"; {len(failures)} component(s) failed (failures.csv)"
    confirm_table = pd.DataFrame(columns=list(CONFIRMATION_COLUMNS))
    correlations: list[dict[str, Any]] = []
    medians: dict[str, Any] = {}
    throughput = math.nan
    if options.confirm:
        sd_t1 = spectra.sd_t1_m  # SD(T_1, ξ_1), the confirmation's intensity measure
        confirm_table, correlations, medians, throughput = _confirm(
            table, frame, spectra, (choice.chosen_rows, choice.control_rows), sd_t1, options,
            parallel,
        )  # fmt: skip
    summary = {
        "rank_by": options.rank_by,
        "scale": options.scale,
        "band": band.to_dict(),
        # the frame ranked with, so that a report made later simulates the same frame
        "frame": {k: v for k, v in dataclasses.asdict(frame).items() if v is not None},
        "substitute": spectra.levels.to_dict(),
        "filters": [r.to_dict() for r in candidates.reports],
        "filter_summary": candidates.summary_line,
        "correlations": correlations,
        "medians": medians,
        "confirmation_samples_per_s": throughput,
        "options": options.to_dict(),
        **ranking_summary(
            table, candidates.passing, choice.chosen_rows, ranking, options, parallel
        ),
    }
    selection_columns = {
        "rank": (
            "",
            "order in which the choice picked it (1 first: greedy under the caps and the "
            "spectral objective; the score's own rank among the candidates may differ)",
        ),
        "score": ("", f"the ranking score ({options.rank_by})"),
        **CANDIDATE_COLUMNS,
    }
    return SelectionResult(
        _with_dictionary(
            _selection_table(table, choice.chosen_rows, options.rank_by), selection_columns
        ),
        _with_dictionary(table, CANDIDATE_COLUMNS),
        _with_dictionary(confirm_table, CONFIRMATION_COLUMNS),
        failures_table(failures),
        (band.omega_low_rad_s, band.omega_1_rad_s),
        status,
        message,
        summary,
    )


def ranking_summary(
    table: Any,
    passing: NDArray[np.int64],
    chosen: list[int],
    ranking: Ranking,
    options: SelectionOptions,
    parallel: tuple[int | None, Executor | None] = (1, None),
) -> dict[str, Any]:
    """``ranking_intensity`` (the stated intensity), ``ranking`` (what was simulated, and the
    chosen set's simulated response against the rest at that intensity) and ``tiers`` (each
    tier against this run's exact ranking, when every candidate was simulated; their bootstrap
    intervals in the workers, ``parallel``)."""
    from stepframe.pipeline.selection.tiers import agreement, tier_values

    out = ranking.summary()
    in_set = np.zeros(len(table), dtype=bool)
    in_set[chosen] = True
    if ranking.plan.method == "tier":
        # one key, the tier's value (its percentile): only equal values tie
        none = np.full(len(table), np.nan)
        tied = tied_across(none, ranking.z, in_set, resolution=0.0)
        _tie(out, table, tied, in_set, none, score=options.rank_by)
        out["tiers"] = []
        return out
    simulated = table["simulated"].to_numpy(dtype=bool)
    rest = simulated & ~in_set
    response = table[SIMULATED_RESPONSE].to_numpy(dtype=np.float64)
    peak = table["ranking_peak_x_m"].to_numpy(dtype=np.float64)
    over = table["ranking_overturned"].to_numpy(dtype=bool)
    out["ranking"]["chosen_vs_rest"] = {
        "simulated_response_m_chosen": _median(response, in_set & simulated),
        "simulated_response_m_rest": _median(response, rest),
        "peak_x_m_chosen": _median(peak, in_set & simulated),
        "peak_x_m_rest": _median(peak, rest),
        "overturned_chosen": int((over & in_set).sum()),
        "overturned_rest": int((over & rest).sum()),
        "n_chosen": int((in_set & simulated).sum()),
        "n_rest": int(rest.sum()),
    }
    factor = table["overturn_factor"].to_numpy(dtype=np.float64)
    tied = tied_across(factor, np.where(simulated, response, np.nan), in_set)
    _tie(out, table, tied, in_set, factor, RESOLUTION)
    rows = np.asarray([i for i in passing if simulated[i]], dtype=np.int64)
    if ranking.plan.method != "exact" or rows.size < 4:
        out["tiers"] = []
        return out
    base = table["ranking_scale"].to_numpy(dtype=np.float64)
    named = _named(options)
    tiers = {
        name: tier_values(table, name, base)[rows]
        for name in TIERS
        if name in table.columns and (name not in DOMINATED or name in named)
    }
    out["tiers"] = agreement(ranking.z[rows], tiers, options.n, parallel)
    return out


def _tie(
    out: dict[str, Any],
    table: Any,
    tied: NDArray[np.bool_],
    in_set: NDArray[np.bool_],
    factor: Floats,
    resolution: float = 0.0,
    score: str | None = None,
) -> None:
    """candidates.csv's ``ranking_tie`` and, when some candidates tie across the chosen set's
    edge, ``ranking.tie`` (counts, the resolution, the common overturning factor if any, the
    tier's name for a ranking by a tier's equal values)."""
    table["ranking_tie"] = tied
    if not tied.any():
        return
    tie: dict[str, Any] = {
        "n_chosen": int((tied & in_set).sum()),
        "n_other": int((tied & ~in_set).sum()),
        "resolution": resolution,
    }
    common = np.unique(factor[tied])
    if common.size == 1 and math.isfinite(common[0]):  # one overturning factor for all
        tie["overturn_factor"] = float(common[0])
    if score is not None:
        tie["score"] = score
    out["ranking"]["tie"] = tie


def _confirm(
    table: Any,
    frame: PortalFrame,
    spectra: Spectra,
    pair_rows: tuple[list[int], list[int]],
    sd_t1: Floats,
    options: SelectionOptions,
    parallel: tuple[int | None, Executor | None],
) -> tuple[Any, list[dict[str, Any]], dict[str, Any], float]:
    """The confirmation: the chosen set and its controls simulated here at their chosen scale
    (their records read again: 2n of them), every candidate's equal-intensity run as the record
    pass computed it in the workers, then the correlations and medians."""
    import pandas as pd

    chosen, controls = pair_rows
    frames = []

    def rows_of(indices: list[int], group: str, case: str, scales: Floats, run: Any) -> Any:
        out = run.drop(columns=["record", "scale"]).copy()
        out.insert(0, "file", table["file"].to_numpy()[indices])
        out.insert(1, "component", table["component"].to_numpy()[indices])
        out.insert(2, "group", group)
        out.insert(3, "case", case)
        out.insert(4, "scale", scales)
        return out

    pair = chosen + controls
    scales = table["scale_factor"].to_numpy()[pair]
    spectra.load(table, pair)
    run = confirmation.run_batch(frame, [spectra.samples[i] for i in pair], scales)
    chosen_run = rows_of(pair, "selected", "chosen-scale", scales, run.table)
    chosen_run.loc[len(chosen) :, "group"] = "control"
    frames.append(chosen_run)
    candidates = [
        int(i)
        for i in np.flatnonzero(table["dropped_by"].to_numpy() == "")
        if np.isfinite(sd_t1[i]) and sd_t1[i] > 0
    ]
    if not candidates:
        raise InputError("no candidate has a positive SD(T_1), expected one to confirm")
    outcomes = [spectra.outcomes[i] for i in candidates]
    run_equal = pd.DataFrame([outcome.equal for outcome in outcomes])
    equal = run_equal["scale"].to_numpy(dtype=np.float64)
    onset = run_equal.pop("overturn_onset_ratio").to_numpy(dtype=np.float64)
    equal_rows = rows_of(candidates, "candidate", "equal-psa-t1", equal, run_equal)
    equal_rows["overturn_onset_ratio"] = onset
    frames.append(equal_rows)
    result = pd.concat(frames, ignore_index=True)
    result = result[[c for c in CONFIRMATION_COLUMNS if c in result.columns]]
    peak = equal_rows["peak_abs_x_m"].to_numpy(dtype=np.float64)
    margin = -np.where(np.isnan(onset), OVER_RANGE_TOP, onset)
    over_equal = equal_rows["overturned"].to_numpy(dtype=bool)
    correlations = compared_rankings(
        _compared_values(table, candidates, equal, options),
        {"peak_drift": peak, "overturn_margin": margin},
        {"peak_drift": np.where(over_equal, np.nan, peak), "overturn_margin": onset},
        options.rank_by,
        options.seed,
        parallel,
    )
    is_chosen = np.isin(candidates, chosen)
    is_control = np.isin(candidates, controls)
    overturned = run_equal["overturned"].to_numpy(dtype=bool)
    chosen_peak = run.table["peak_abs_x_m"].to_numpy(dtype=np.float64)
    chosen_over = run.table["overturned"].to_numpy(dtype=bool)
    in_set = np.arange(len(pair)) < len(chosen)
    medians = {
        "equal_psa_t1_onset_ratio": float(options.confirm_onset_ratio),
        "equal_psa_t1_g": float(options.confirm_onset_ratio * onset_psa_t1_g(frame)),
        "equal_psa_t1_peak_x_m_selected": _median(peak, is_chosen),
        "equal_psa_t1_peak_x_m_control": _median(peak, is_control),
        "equal_psa_t1_overturned_selected": int(overturned[is_chosen].sum()),
        "equal_psa_t1_overturned_control": int(overturned[is_control].sum()),
        "chosen_scale_peak_x_m_selected": _median(chosen_peak, in_set),
        "chosen_scale_peak_x_m_control": _median(chosen_peak, ~in_set),
        "chosen_scale_overturned_selected": int(chosen_over[in_set].sum()),
        "chosen_scale_overturned_control": int(chosen_over[~in_set].sum()),
        "n_selected": len(chosen),
        "n_control": len(controls),
        "n_equal_intensity": len(candidates),
    }
    simulated = sum(outcome.npts for outcome in outcomes)
    seconds = sum(outcome.seconds[1] for outcome in outcomes)
    return result, correlations, medians, simulated / seconds if seconds > 0 else math.inf


OVER_RANGE_TOP = confirmation.OVERTURN_RATIO_RANGE[1] * 2.0


def _compared_values(
    table: Any, rows: list[int], scales: Floats, options: SelectionOptions
) -> dict[str, Floats]:
    """The rankings the confirmation compares, on ``rows`` at the confirmation's intensity
    (``scales``), larger more severe: the run's ranking, the scores it computed (the dominated
    ones only when named) and every peer (scaled: S_a(T_1) is then the same for all)."""
    from stepframe.pipeline.selection.peers import at_intensity

    named = _named(options)
    out: dict[str, Floats] = {}
    for name in (SIMULATED_RESPONSE, *TIERS):
        if name not in table.columns or (name in DOMINATED and name not in named):
            continue
        values = table[name].to_numpy(dtype=np.float64)[rows]
        if name in PEER_NAMES:
            values = at_intensity(name, values, scales)
        if np.isfinite(values).any():
            out[name] = values
    return out


def compared_rankings(
    values: dict[str, Floats],
    responses: dict[str, Floats],
    efficiency_responses: dict[str, Floats],
    reference: str,
    seed: int,
    parallel: tuple[int | None, Executor | None] = (1, None),
) -> list[dict[str, Any]]:
    """Each ranking against each simulated response: Spearman ρ with its bootstrap interval,
    the paired difference Δρ from the ``reference`` ranking with its interval, and the
    efficiency (the dispersion of ln response given ln |value|, :func:`confirm.efficiency`,
    over ``efficiency_responses``: peaks of the runs that stay up, overturning ratios of those
    that overturn). Each entry is independent, its bootstrap drawn from its own seed (``seed``
    plus the ranking's position): they run in the workers (``parallel``, one batch), with the
    same numbers whatever the number of workers."""
    base = values.get(reference)
    calls = [
        functools.partial(
            _compared_entry,
            (name, response, reference),
            x,
            None if name == reference else base,
            (y, efficiency_responses[response]),
            seed + k,
        )
        for k, (name, x) in enumerate(values.items())
        for response, y in responses.items()
    ]
    jobs, executor = parallel
    return call_each(calls, jobs=jobs, executor=executor, stage="confirmation")


def _compared_entry(
    names: tuple[str, str, str],
    x: Floats,
    base: Floats | None,
    ys: tuple[Floats, Floats],
    seed: int,
) -> dict[str, Any]:
    """One entry of :func:`compared_rankings`: ranking ``names[0]`` (values ``x``) against
    response ``names[1]`` (values ``ys[0]``; ``ys[1]`` for the efficiency), with Δρ from
    ``names[2]`` (values ``base``; None: not compared)."""
    name, response, reference = names
    y, y_efficiency = ys
    rho, low, high, n = confirmation.spearman_interval(x, y, seed)
    entry: dict[str, Any] = {
        "score": name, "response": response, "spearman": rho, "low": low, "high": high, "n": n,
    }  # fmt: skip
    if base is not None:
        delta = confirmation.paired_delta_rho(x, base, y, seed)
        entry.update(delta_vs=reference, delta=delta[0], delta_low=delta[1])
        entry["delta_high"] = delta[2]
    sigma, count = confirmation.efficiency(np.abs(x), y_efficiency)
    entry.update(efficiency=sigma, efficiency_n=count)
    return entry


def _median(values: Floats, mask: NDArray[np.bool_]) -> float:
    """Median of ``values[mask]``; NaN for an empty selection."""
    return float(np.median(values[mask])) if mask.any() else math.nan


# What goes in and out (issue 25): one scale factor per record, and the chosen set's outcome.


def scale_records(
    candidates: Candidates,
    spectra: Spectra,
    options: SelectionOptions,
    target: Any,
    log_psa: Floats | None,
) -> Floats | None:
    """Step 4b (``unit="record"``): one scale factor per record from its pair's spectrum
    (``pair_spectrum``), written over both components' ``scale_factor``, ``scale_clipped``
    and ``spectral_misfit``; returns the rows' ln scaled PSA (the pair's) for the choice."""
    table = candidates.table
    if options.scale == "none" and target is None:
        return log_psa
    records = table["record"].astype(str).to_numpy()
    members: dict[str, list[int]] = {}
    for i in candidates.passing:
        members.setdefault(records[i], []).append(int(i))
    groups = list(members.values())
    # a pair's spectrum needs both records at once: read here (the rows the pass computed)
    candidates.failures += spectra.load(table, candidates.passing)
    scales, clipped, misfit, pair_log = record_scales(
        groups,
        spectra.samples,
        spectra.periods_s,
        candidates.band.period_1_s,
        options.scale,
        target,
        (options.scale_min, options.scale_max),
        options.pair_spectrum,
    )
    out = None if log_psa is None else log_psa.copy()
    for k, rows in enumerate(groups):
        table.loc[rows, "scale_factor"] = scales[k]
        table.loc[rows, "scale_clipped"] = bool(clipped[k])
        table.loc[rows, "spectral_misfit"] = misfit[k]
        if out is not None:
            out[rows] = pair_log[k]
    return out


def chosen_outcome(
    candidates: Candidates,
    spectra: Spectra,
    choice: Choice,
    frame: PortalFrame,
    options: SelectionOptions,
    target: Any,
    sources: tuple[Mapping[RecordKey, Samples] | None, Mapping[str, Any] | None],
) -> ChosenSet:
    """Step 8: the chosen set's scaled spectra, the code's check, what it does to the frame at
    the chosen scale, and its motions (:func:`.chosen.chosen_set`)."""
    table = candidates.table
    if spectra.sources == (None, None):  # no pass ran (ranked by a score of the fit)
        spectra = dataclasses.replace(spectra, sources=sources)
    spectra.load(table, choice.chosen_rows)  # unread: chosen_set says so
    return chosen_set(
        table, choice.chosen_rows, spectra.samples, frame, candidates.band, options, target,
        spectra.periods_s,
    )  # fmt: skip


def with_chosen(result: SelectionResult, chosen: ChosenSet) -> SelectionResult:
    """The result with the chosen set's outcome: its summary keys, ``spectra.csv``, the
    motions to export, the grouping of the files, and the warnings."""
    result.summary.update(chosen.summary)
    result.summary["grouping"] = grouping_summary(result.candidates)
    result.spectra = chosen.spectra
    result.motions = chosen.motions
    return result
