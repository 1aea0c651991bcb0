"""``select_records``: filters, scores, spectra, the chosen set, rank stability, confirmation."""

from __future__ import annotations

import math
from collections.abc import Mapping
from concurrent.futures import Executor
from typing import Any

import numpy as np
from numpy.typing import NDArray

from stepframe.core.execution import default_jobs, map_items
from stepframe.core.results import Failure, failures_table, set_column_dictionary
from stepframe.errors import InputError
from stepframe.pipeline.selection import confirm as confirmation
from stepframe.pipeline.selection import record_pass
from stepframe.pipeline.selection import scores as sc
from stepframe.pipeline.selection.band import FrameBand
from stepframe.pipeline.selection.choose import Units, choose, percentile_scores
from stepframe.pipeline.selection.filters import FilterReport, apply_filters, filter_summary
from stepframe.pipeline.selection.names import PHYSICS_SCORES, RECORD_SCORES
from stepframe.pipeline.selection.options import SelectionOptions
from stepframe.pipeline.selection.path import MODEL_COLUMNS, strong_motion_paths
from stepframe.pipeline.selection.record_pass import RecordKey, Samples
from stepframe.pipeline.selection.result import SelectionResult, column_dictionary
from stepframe.pipeline.selection.spectral import (
    G_M_S2,
    scale_factors,
    spectral_misfit,
    target_spectrum,
    target_values,
)
from stepframe.pipeline.selection.substitute import (
    predicted_overturn_ratio,
    substitute_demand_ratio,
)
from stepframe.structure.frame import PortalFrame

Floats = NDArray[np.float64]

CANDIDATE_COLUMNS: dict[str, tuple[str, str]] = {
    "window_start_s": ("s", "start of strong motion after t0 (I_g ≥ fraction of its peak)"),
    "window_end_s": ("s", "end of strong motion after t0"),
    "omega_window_start_rad_s": ("rad/s", "fitted omega_g at the start of strong motion"),
    "omega_window_end_rad_s": ("rad/s", "fitted omega_g at the end of strong motion"),
    "enters_from_above": ("", "omega_g starts strong motion above omega_1 and ends below it"),
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
    missing = [c for c in (*MODEL_COLUMNS, "file", "component", "plausible") if c not in features]
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
    columns = set(table.columns)
    files = table["file"].astype(str).to_numpy()
    events = table["event"].astype(str).to_numpy() if "event" in columns else files
    stations = table["station"].astype(str).to_numpy() if "station" in columns else files
    if unit == "record":
        codes, _ = pd.factorize(pd.Series(events[rows]) + "\x1f" + pd.Series(stations[rows]))
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
    unit_psa = None if log_psa is None else np.array([log_psa[m].mean(axis=0) for m in members])
    return (
        Units(
            unit_z,
            members,
            np.asarray(events, dtype=object),
            np.asarray(stations, dtype=object),
            unit_psa,
        ),
        members,
    )


def _drop_single_components(
    table: Any, dropped_by: NDArray[np.object_], reports: list[FilterReport]
) -> None:
    """``unit="record"``: drop components whose record (event, station) has no other component
    left, so that every chosen record has both horizontal components."""
    import pandas as pd

    files = table["file"].astype(str)
    events = table["event"].astype(str) if "event" in table.columns else files
    stations = table["station"].astype(str) if "station" in table.columns else files
    key = pd.Series(events.to_numpy() + "\x1f" + stations.to_numpy())
    alive = dropped_by == ""
    sizes = key[alive].value_counts()
    single = alive & (key.map(sizes).fillna(0).to_numpy() < 2)
    dropped_by[single] = "one_component"
    reports.append(
        FilterReport(
            "one_component",
            "both components of the record passed",
            int(single.sum()),
            int((dropped_by == "").sum()),
        )
    )


def _spectra(
    table: Any,
    dropped_by: NDArray[np.object_],
    spec: record_pass.PassSpec,
    out: tuple[Floats, Floats],
    records: Mapping[RecordKey, Samples] | None,
    parallel: tuple[int | None, Executor | None],
    responses: Mapping[RecordKey, Mapping[str, Any]] | None,
) -> tuple[dict[int, dict[str, Any]], tuple[int, float], list[Failure]]:
    """The passing candidates' record pass (:mod:`.record_pass`: in the workers, or stored by the
    ``responses`` stage for this very pass): PSA (5 %) at T_1 and the misfit periods into
    ``table["psa_t1_g"]`` and ``out[0]``, SD at the substitute structure's levels into
    ``out[1]`` (SD(T_1, ξ_1) first). Rows without samples or spectra get their ``dropped_by``
    reason. With confirmation also each candidate's simulation at equal intensity: returned by
    row, with the samples simulated and the seconds it took (summed over workers)."""
    psa, sd_levels = out
    jobs, executor = parallel
    passing = np.flatnonzero(dropped_by == "")
    digest = record_pass.spec_digest(spec) if responses else ""
    files = table["file"].astype(str).to_numpy()
    components = table["component"].astype(str).to_numpy()
    known: list[record_pass.Outcome] = []
    costs: list[tuple[int, float]] = []
    todo = []
    for row in passing.tolist():
        entry = responses.get((files[row], components[row])) if responses else None
        if entry is not None and entry["spec"] == digest:
            outcome, cost = record_pass.from_stored(row, entry)
            known.append(outcome)
            costs.append(cost)
        else:
            todo.append(row)
    workers = jobs or default_jobs()
    computed = map_items(
        record_pass.record_pass,
        record_pass.items(table, todo, records, spec, workers),
        jobs=jobs,
        executor=executor,
        chunk_size=1,
        stage="spectra",
        name_of=record_pass.item_name,
    )
    costs += [cost for _, cost in computed.results]
    with_t1 = spec.groups[0][0]
    omega_sq = (2.0 * math.pi / with_t1) ** 2
    psa_t1 = np.full(len(table), np.nan)
    lost: dict[str, list[Failure]] = {"samples": [], "spectra": []}
    equal: dict[int, dict[str, Any]] = {}
    simulated = (sum(cost[0] for cost in costs), sum(cost[1] for cost in costs))
    for result in [*known, *(entry for entries, _ in computed.results for entry in entries)]:
        if result.failure is not None:
            lost[result.failure.stage].append(result.failure)
            dropped_by[result.row] = f"{result.failure.stage}_failed"
            continue
        assert result.sd_5 is not None and result.sd_levels is not None
        values = omega_sq * result.sd_5
        psa_t1[result.row] = values[0] / G_M_S2
        psa[result.row] = values[1:]
        sd_levels[result.row] = result.sd_levels
        if result.equal is not None:
            equal[result.row] = result.equal
    table["psa_t1_g"] = psa_t1
    missing = np.flatnonzero((dropped_by == "") & ~np.isfinite(psa_t1))
    dropped_by[missing] = "spectra_failed"
    failures = [*lost["samples"], *lost["spectra"], *computed.failures]
    return equal, simulated, failures


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
        Parallelism of the per-candidate stages (:func:`stepframe.core.execution.map_items`).
    responses
        (file, component) → the stored outcome of the record pass
        (:func:`.record_pass.stored`), as the workflow's ``responses`` stage computed it; a
        candidate without one, or with one of another pass, is computed here.

    Returns
    -------
    SelectionResult

    Raises
    ------
    InputError
        A features table without the model columns; every candidate filtered out; fewer
        candidates left than ``options.n`` (the message says how many passed each filter).
    """
    import pandas as pd

    _check_table(features)
    target = target_spectrum(options)  # an unreadable target fails before any work
    table = features.reset_index(drop=True).copy()
    band, periods, levels, spec = record_pass.selection_inputs(frame, options, record_options)
    cheap = _cheap_scores(table, band, options.strong_motion_fraction)
    paths = cheap["paths"]
    table["window_start_s"] = paths.start_s
    table["window_end_s"] = paths.end_s
    table["omega_window_start_rad_s"] = paths.omega_start_rad_s
    table["omega_window_end_rad_s"] = paths.omega_end_rad_s
    for name in (
        "enters_from_above",
        "band_coverage",
        "spectral_ratio_eq_6_18",
        "omega_p_over_s_sq",
    ):
        table[name] = cheap[name]
    dropped_by, reports = apply_filters(table, options, band, paths)
    summary_line = filter_summary(reports, len(table))
    failures: list[Failure] = []
    passing = np.flatnonzero(dropped_by == "")
    if passing.size == 0:
        raise InputError(f"every candidate was filtered out ({summary_line}), expected some left")
    needs_physics = options.rank_by in PHYSICS_SCORES or options.confirm
    table["backbone_amplification"] = np.nan
    table["descent_amplification"] = np.nan
    if needs_physics:
        backbone, descent, fails, failed_rows = _physics(
            table, passing, band, frame, paths, jobs, executor
        )
        table["backbone_amplification"] = backbone
        table["descent_amplification"] = descent
        failures += fails
        dropped_by[failed_rows] = "physics_failed"
    table["psa_t1_g"] = np.nan
    psa = np.full((len(table), periods.size), np.nan)
    sd_levels = np.full((len(table), levels.periods_s.size), np.nan)
    equal: dict[int, dict[str, Any]] = {}
    simulated = (0, 0.0)
    if spec is not None:
        equal, simulated, fails = _spectra(
            table,
            dropped_by,
            spec,
            (psa, sd_levels),
            records,
            (jobs, executor),
            responses,
        )
        failures += fails
    table["substitute_demand_ratio"] = substitute_demand_ratio(sd_levels, levels)
    table["substitute_overturn_ratio"] = predicted_overturn_ratio(
        table["substitute_demand_ratio"].to_numpy()
    )
    sd_t1 = sd_levels[:, 0]  # SD(T_1, ξ_1), the confirmation's intensity measure
    failed = int(np.isin(dropped_by, COMPUTE_FAILURES).sum())
    if failed:
        left = int((dropped_by == "").sum())
        reports.append(FilterReport("computed", COMPUTED_RULE, failed, left))
        summary_line = filter_summary(reports, len(table))
        if left == 0:
            first = (
                f"; first failure: {failures[0].item}: {failures[0].message}" if failures else ""
            )
            raise InputError(
                f"no candidate could be computed ({summary_line}{first}), expected readable "
                f"records for {options.rank_by} (records= or the files by path), or rank_by a "
                "score of the fit"
            )
    if options.unit == "record":
        _drop_single_components(table, dropped_by, reports)
        summary_line = filter_summary(reports, len(table))
    passing = np.flatnonzero(dropped_by == "")
    score = np.asarray(table[options.rank_by], dtype=np.float64)
    z = np.full(len(table), np.nan)
    z[passing] = percentile_scores(score[passing])
    table["rank_score_percentile"] = z
    psa_t1 = table["psa_t1_g"].to_numpy() * G_M_S2
    target_t1 = None if target is None else target.sa_m_s2(band.period_1_s)
    target_psa = None if target is None else target_values(target, periods)
    scales, clipped = scale_factors(
        options.scale, psa_t1, psa, target_t1, target_psa, (options.scale_min, options.scale_max)
    )
    table["scale_factor"] = scales
    table["scale_clipped"] = clipped
    table["spectral_misfit"] = (
        spectral_misfit(psa, scales, target_psa) if target_psa is not None else np.nan
    )
    log_psa = None
    log_target = None
    if target_psa is not None:
        with np.errstate(divide="ignore", invalid="ignore"):
            log_psa = np.log(scales[:, None] * psa)
        log_target = np.log(target_psa)
    units, members = _units(table, passing, z, options.unit, log_psa)
    if len(members) < options.n:
        what = "records" if options.unit == "record" else "candidates"
        raise InputError(
            f"n = {options.n} but only {len(members)} {what} left ({summary_line}), expected "
            f"n ≤ {len(members)}"
        )

    def pick(candidates: Units) -> list[int]:
        return choose(
            candidates,
            options.n,
            weight=options.spectral_weight,
            log_target=log_target,
            max_per_event=options.max_per_event,
            max_per_station=options.max_per_station,
        )

    chosen = pick(units)
    chosen_rows = [i for u in chosen for i in members[u]]
    # Rank stability: redraw the fitted parameters, rescore, choose again (one batch for all
    # replicates, so a process pool starts once).
    counts = np.zeros(len(table))
    rng = np.random.default_rng(options.seed)
    replicates = [
        _perturbed(table.iloc[passing].reset_index(drop=True), rng)
        for _ in range(options.n_bootstrap)
    ]
    if replicates:
        drawn = pd.concat(replicates, ignore_index=True)
        if options.rank_by in RECORD_SCORES:
            # The record's spectrum does not depend on the fit: every replicate ranks alike.
            all_values = np.tile(score[passing], options.n_bootstrap)
        elif options.rank_by in PHYSICS_SCORES:
            b, d, _, _ = _physics(
                drawn,
                np.arange(len(drawn)),
                band,
                frame,
                strong_motion_paths(drawn, options.strong_motion_fraction),
                jobs,
                executor,
            )
            all_values = b if options.rank_by == "backbone_amplification" else d
        else:
            all_values = np.asarray(
                _cheap_scores(drawn, band, options.strong_motion_fraction)[options.rank_by],
                dtype=np.float64,
            )
        for values in all_values.reshape(options.n_bootstrap, passing.size):
            z_b = np.full(len(table), np.nan)
            z_b[passing] = percentile_scores(values)
            units_b, members_b = _units(table, passing, z_b, options.unit, log_psa)
            for u in pick(units_b):
                counts[members_b[u]] += 1
    probability = np.full(len(table), np.nan)
    if options.n_bootstrap:
        probability[passing] = counts[passing] / options.n_bootstrap
    table["selection_probability"] = probability
    table["selected"] = False
    table.loc[chosen_rows, "selected"] = True
    order = np.argsort(units.z, kind="stable")
    taken = set(chosen)
    controls = [int(u) for u in order if u not in taken][: len(chosen)]
    control_rows = [i for u in controls for i in members[u]]
    table["control"] = False
    table.loc[control_rows, "control"] = True
    table["dropped_by"] = dropped_by
    selection = table.loc[chosen_rows].copy()
    selection.insert(0, "rank", np.arange(1, len(chosen_rows) + 1))
    selection.insert(1, "score", selection[options.rank_by].to_numpy())
    keep_first = [
        "rank",
        "file",
        "component",
        "station",
        "score",
        "scale_factor",
        "selection_probability",
        "rank_score_percentile",
        *sc.SCORES,
        "enters_from_above",
        "psa_t1_g",
        "spectral_misfit",
    ]
    keep = [c for c in keep_first if c in selection.columns]
    selection = selection[keep + [c for c in selection.columns if c not in keep]]
    selection = selection.reset_index(drop=True)
    status, message = "ok", f"{len(chosen_rows)} components chosen by {options.rank_by}"
    if len(chosen) < options.n:
        status = "degraded"
        message = f"only {len(chosen)} of {options.n} could be chosen under the caps"
    if failures:
        status = "degraded"
        message += f"; {len(failures)} component(s) failed (failures.csv)"
    confirm_table = pd.DataFrame(columns=list(CONFIRMATION_COLUMNS))
    correlations: list[dict[str, Any]] = []
    medians: dict[str, Any] = {}
    throughput = math.nan
    if options.confirm:
        confirm_table, correlations, medians, throughput = _confirm(
            table,
            frame,
            (records, record_options),
            (equal, simulated),
            chosen_rows,
            control_rows,
            sd_t1,
            options,
            (jobs, executor),
        )
    summary = {
        "rank_by": options.rank_by,
        "scale": options.scale,
        "band": band.to_dict(),
        "substitute": levels.to_dict(),
        "filters": [r.to_dict() for r in reports],
        "filter_summary": summary_line,
        "correlations": correlations,
        "medians": medians,
        "confirmation_samples_per_s": throughput,
        "options": options.to_dict(),
    }
    return SelectionResult(
        _with_dictionary(
            selection,
            {
                "rank": ("", "rank in the set (1 best)"),
                "score": ("", f"the ranking score ({options.rank_by})"),
                **CANDIDATE_COLUMNS,
            },
        ),
        _with_dictionary(table, CANDIDATE_COLUMNS),
        _with_dictionary(confirm_table, CONFIRMATION_COLUMNS),
        failures_table(failures),
        (band.omega_low_rad_s, band.omega_1_rad_s),
        status,
        message,
        summary,
    )


def _confirm(
    table: Any,
    frame: PortalFrame,
    sources: tuple[Mapping[RecordKey, Samples] | None, Mapping[str, Any] | None],
    candidate_runs: tuple[dict[int, dict[str, Any]], tuple[int, float]],
    chosen: list[int],
    controls: list[int],
    sd_t1: Floats,
    options: SelectionOptions,
    parallel: tuple[int | None, Executor | None],
) -> tuple[Any, list[dict[str, Any]], dict[str, Any], float]:
    """The confirmation: the chosen set and its controls simulated here at their chosen scale
    (their records read again: 2n of them), every candidate's equal-intensity run as the record
    pass computed it (``candidate_runs``: rows by table row, and samples and seconds simulated),
    then the correlations and medians."""
    import pandas as pd

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
    run = confirmation.run_batch(frame, _load(table, pair, *sources), scales)
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
    by_row, (samples, seconds) = candidate_runs
    run_equal = pd.DataFrame([by_row[i] for i in candidates])
    equal = run_equal["scale"].to_numpy(dtype=np.float64)
    onset = run_equal.pop("overturn_onset_ratio").to_numpy(dtype=np.float64)
    equal_rows = rows_of(candidates, "candidate", "equal-psa-t1", equal, run_equal)
    equal_rows["overturn_onset_ratio"] = onset
    frames.append(equal_rows)
    result = pd.concat(frames, ignore_index=True)
    result = result[[c for c in CONFIRMATION_COLUMNS if c in result.columns]]
    peak = equal_rows["peak_abs_x_m"].to_numpy(dtype=np.float64)
    margin = -np.where(np.isnan(onset), OVER_RANGE_TOP, onset)
    # The bootstraps are independent (tens of seconds each at 43,000 candidates): on the workers
    pairs = [
        (name, response, table[name].to_numpy(dtype=np.float64)[candidates], y, options.seed + k)
        for k, name in enumerate([*sc.SCORES, "psa_t1_g"])
        for response, y in (("peak_drift", peak), ("overturn_margin", margin))
    ]
    outcome = map_items(
        _spearman_item,
        [(values, y, seed) for _, _, values, y, seed in pairs],
        jobs=parallel[0],
        executor=parallel[1],
        chunk_size=1,
        stage="correlations",
    )
    if outcome.failures:
        raise RuntimeError(f"correlations: {outcome.failures[0].message}")
    correlations = [
        {"score": name, "response": response, "spearman": rho, "low": low, "high": high, "n": n}
        for (name, response, *_), (rho, low, high, n) in zip(pairs, outcome.results, strict=True)
    ]
    is_chosen = np.isin(candidates, chosen)
    is_control = np.isin(candidates, controls)
    overturned = run_equal["overturned"].to_numpy(dtype=bool)
    chosen_peak = run.table["peak_abs_x_m"].to_numpy(dtype=np.float64)
    in_set = np.arange(len(pair)) < len(chosen)
    medians = {
        "equal_psa_t1_peak_x_m_selected": _median(peak, is_chosen),
        "equal_psa_t1_peak_x_m_control": _median(peak, is_control),
        "equal_psa_t1_overturned_selected": int(overturned[is_chosen].sum()),
        "equal_psa_t1_overturned_control": int(overturned[is_control].sum()),
        "chosen_scale_peak_x_m_selected": _median(chosen_peak, in_set),
        "chosen_scale_peak_x_m_control": _median(chosen_peak, ~in_set),
        "n_selected": len(chosen),
        "n_control": len(controls),
        "n_equal_intensity": len(candidates),
    }
    return result, correlations, medians, samples / seconds if seconds > 0 else math.inf


OVER_RANGE_TOP = confirmation.OVERTURN_RATIO_RANGE[1] * 2.0


def _spearman_item(item: tuple[Floats, Floats, int]) -> tuple[float, float, float, int]:
    """A :func:`map_items` worker: :func:`confirm.spearman_interval` of (score, response, seed)."""
    return confirmation.spearman_interval(*item)


def _load(
    table: Any,
    rows: list[int],
    records: Mapping[RecordKey, Samples] | None,
    record_options: Mapping[str, Any] | None,
) -> list[Samples]:
    """The samples of a few rows, in this process (from ``records``, else their files)."""
    cache: dict[str, Any] = {}
    out = []
    for row in rows:
        file, component = str(table["file"].iat[row]), str(table["component"].iat[row])
        if records is not None:
            acc, dt = records[(file, component)]
        else:
            acc, dt = record_pass.read_samples(file, component, record_options or {}, cache)
        out.append((np.asarray(acc, dtype=np.float64), float(dt)))
    return out


def _median(values: Floats, mask: NDArray[np.bool_]) -> float:
    """Median of ``values[mask]``; NaN for an empty selection."""
    return float(np.median(values[mask])) if mask.any() else math.nan
