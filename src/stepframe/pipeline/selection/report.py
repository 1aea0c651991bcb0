"""The selection report: the frame's band, the chosen records' paths, scores, spectra, confirmation.

What it shows (issue 14): the frame's period-amplitude backbone and band; each selected record's
fitted ω_g(t) against the band over time with its strong-motion window; the accelerograms of
the three best; the score table
(sortable); the selected set's spectra against the target (median and ±σ) with scale factors; the
confirmation (score against simulated peak response at equal intensity, the rank correlation,
selected against controls); what each filter dropped; the failures. It reads the selection
folder through :func:`~stepframe.pipeline.selection.report_folder.read_selection_folder` and
draws only what the folder holds, saying what is missing.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from concurrent.futures import Executor
from functools import partial
from os import PathLike
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from stepframe.errors import InputError
from stepframe.pipeline.reports import figures
from stepframe.pipeline.reports.document import (
    Figure,
    FigureJob,
    Note,
    Report,
    Section,
    Table,
    draw_figures,
    write_report,
)
from stepframe.pipeline.reports.provenance import Provenance, collect_provenance, command_line
from stepframe.pipeline.selection.options import SelectionOptions
from stepframe.pipeline.selection.ranking import tie_line
from stepframe.pipeline.selection.report_folder import SelectionOutputs, read_selection_folder
from stepframe.pipeline.selection.report_resonance import resonance_runs, resonance_section
from stepframe.pipeline.selection.result import confirmation_level
from stepframe.stochastic.model import MODEL_FIELDS, GroundMotionModel

TWO_PI = 2 * math.pi

#: Periods of the spectra figure [s].
SPECTRUM_PERIODS_S = np.geomspace(0.05, 10.0, 60)

#: Records whose accelerograms are drawn (the best first).
N_ACCELEROGRAMS = 3
#: A table longer than this is drawn on the page by its first rows only (all of it in its CSV).
PAGE_ROWS = 50

#: Columns that name the filter that dropped a candidate (first present wins).
DROPPED_COLUMNS = ("dropped_by", "filter", "dropped_by_filter")

#: Columns of the fitted ground-motion model in the selection table.
MODEL_COLUMNS = MODEL_FIELDS[:-1]  # without t0_s

#: A record loader: (selection row, folder) → obspy Trace in m/s², or None when not found.
RecordLoader = Callable[[dict[str, Any], Path], Any]


def _name(row: dict[str, Any]) -> str:
    name = Path(str(row["file"])).name
    component = row.get("component")
    if component is not None and not (isinstance(component, float) and math.isnan(component)):
        name += f" [{component}]"
    return name


def _components(table: pd.DataFrame) -> list[str]:
    if "component" not in table.columns:
        return [""] * len(table)
    return ["" if pd.isna(value) else str(value) for value in table["component"]]


def _frame(summary: dict[str, Any], folder: Path) -> Any:
    """The frame from the summary: a table of PortalFrame fields or a frame file path."""
    value = summary.get("frame")
    if value is None:
        value = summary.get("frame_file")
    if value is None:
        return None
    if isinstance(value, dict):
        from stepframe.structure.frame import PortalFrame

        fields = set(PortalFrame.__dataclass_fields__)
        return PortalFrame(**{k: v for k, v in value.items() if k in fields})
    from stepframe.structure.frame_file import read_frame_file

    path = Path(str(value))
    return read_frame_file(path if path.is_absolute() else folder / path)


def _band(summary: dict[str, Any], frame: Any, where: Path) -> tuple[float, float]:
    band = summary.get("band_rad_s")
    if band is not None:
        try:
            lo, hi = (float(band[0]), float(band[1]))
        except (TypeError, ValueError, IndexError):
            raise InputError(
                f"band_rad_s = {band!r}, expected [low, high] in rad/s", where / "selection.json"
            ) from None
        if not (math.isfinite(lo) and math.isfinite(hi) and 0 < lo < hi):
            raise InputError(
                f"band_rad_s = {band!r}, expected 0 < low < high [rad/s]", where / "selection.json"
            )
        return lo, hi
    if frame is None:
        raise InputError(
            "no band_rad_s and no frame, expected the frame's band in the summary",
            where / "selection.json",
        )
    # The selection's own default band (frame_band: ω at 0.8 x* up to ω_1); the report once
    # used A half-way from x_c to x* here, a band the selection never ranked on.
    from stepframe.pipeline.dynamics.resonance import default_band

    return default_band(frame)


def load_record(row: dict[str, Any], folder: Path) -> Any:
    """The selected component as a Trace: by its identity when the selection records it
    (:func:`~stepframe.pipeline.selection.identity.find_record`: gone or changed is an error);
    else a file beside the folder, or the example catalogue."""
    from stepframe.pipeline.selection.identity import find_record, records_identity

    records = records_identity(folder)
    if records is not None and isinstance(row.get("content_sha256"), str):
        return find_record(row, folder, records)
    file = str(row["file"])
    component = row.get("component")
    component = None if component is None or pd.isna(component) else str(component)
    candidates = [Path(file), folder / file]
    for path in candidates:
        if path.is_file():
            from stepframe.records.io import read_measured

            stream = read_measured(path, component=component)
            return stream[0]
    return _example_trace(file, component)


def _example_trace(file: str, component: str | None) -> Any:
    """The example component named ``file`` (its one name, ``RSN174_IMPVALL_H-E11230.AT2``,
    bare or under a folder), or None."""
    from stepframe.records.examples import fema_p695

    stream, _ = _examples_cache(fema_p695)
    key = Path(file).name
    for trace in stream:
        if trace.stats.stepframe.source_file == key and (
            component is None or trace.stats.channel == component
        ):
            return trace
    return None


_EXAMPLES: dict[str, Any] = {}


def _examples_cache(loader: Callable[[], Any]) -> Any:
    if "fema" not in _EXAMPLES:
        _EXAMPLES["fema"] = loader()
    return _EXAMPLES["fema"]


def _target(summary: dict[str, Any]) -> tuple[Any, Any] | None:
    """The run's target spectrum as the selection stored it, ``(periods [s], PSA [g])``
    (``selection.json`` ``target``, :func:`stepframe.pipeline.selection.spectral.target_record`:
    the numbers the run scaled and checked against), or None without one."""
    data = summary.get("target")
    if not isinstance(data, dict) or "periods_s" not in data or "sa_g" not in data:
        return None
    return np.asarray(data["periods_s"], dtype=float), np.asarray(data["sa_g"], dtype=float)


def _strong_window(row: dict[str, Any], model: GroundMotionModel) -> tuple[float, float]:
    for start, end in (
        ("strong_motion_start_s", "strong_motion_end_s"),
        ("window_start_s", "window_end_s"),
    ):
        if start in row and end in row and np.isfinite([row[start], row[end]]).all():
            return float(row[start]), float(row[end])
    return model.t0_s, model.t0_s + model.t_dur_s


def _model(row: dict[str, Any]) -> GroundMotionModel | None:
    if not all(key in row and pd.notna(row[key]) for key in MODEL_COLUMNS):
        return None
    p, s, r, xi_p, xi_r, t_max, t_dur = (float(row[key]) for key in MODEL_COLUMNS)
    t0 = float(row["t0_s"]) if "t0_s" in row and pd.notna(row["t0_s"]) else 0.0
    return GroundMotionModel(p, s, r, xi_p, xi_r, t_max, t_dur, t0_s=t0)


def _dropped(candidates: pd.DataFrame) -> tuple[pd.DataFrame, str | None]:
    column = next((c for c in DROPPED_COLUMNS if c in candidates.columns), None)
    if column is None:
        return pd.DataFrame({"filter": [], "dropped": [], "examples": []}), None
    reason = candidates[column].astype(object).fillna("").astype(str).str.strip()
    rows = []
    for name, group in candidates[reason != ""].groupby(reason[reason != ""], sort=True):
        files = [Path(str(f)).name for f in group["file"]]
        rows.append(
            {
                "filter": name,
                "dropped": len(files),
                "examples": ", ".join(files[:3]) + (" ..." if len(files) > 3 else ""),
            }
        )
    passed = int((reason == "").sum())
    rows.append({"filter": "(passed every filter)", "dropped": passed, "examples": ""})
    return pd.DataFrame(rows), column


def _equal_intensity(table: pd.DataFrame, candidates: pd.DataFrame, rank_by: str) -> pd.DataFrame:
    """The rows simulated at equal intensity, with the ranking score joined from the candidates."""
    if "case" in table.columns:
        equal = table["case"].astype(str).str.startswith("equal")
        if equal.any():
            table = table[equal]
    if rank_by not in table.columns and rank_by in candidates.columns:
        keys = [k for k in ("file", "component") if k in table.columns and k in candidates.columns]
        scores = candidates[[*keys, rank_by]].drop_duplicates(keys)
        table = table.merge(scores, on=keys, how="left")
    return table


def _stated_correlations(summary: dict[str, Any], rank_by: str) -> str:
    """The run's own Spearman ρ of the ranking score with each simulated response, with their
    bootstrap intervals (selection.json), as one line; "" when the run states none."""
    rows = summary.get("correlations")
    if not isinstance(rows, list):
        return ""
    parts = []
    for row in rows:
        if not isinstance(row, dict) or row.get("score") != rank_by:
            continue
        values = [row.get(k) for k in ("spearman", "low", "high")]
        if not all(isinstance(v, int | float) and math.isfinite(v) for v in values):
            continue
        rho, low, high = (float(v) for v in values)  # type: ignore[arg-type]
        response = str(row.get("response", "")).replace("_", " ")
        parts.append(f"ρ = {rho:.2f} [{low:.2f}, {high:.2f}] with {response} (n = {row.get('n')})")
    if not parts:
        return ""
    return (
        f"Spearman, {rank_by}, 95 % bootstrap intervals, at {confirmation_level(summary)}: "
        + "; ".join(parts)
    )


def _confirmation(
    table: pd.DataFrame, summary: dict[str, Any], selected: set[tuple[str, str]]
) -> tuple[list[Figure | Table | Note | FigureJob], dict[str, Any]]:
    from scipy.stats import spearmanr

    rank_by = str(summary.get("rank_by", "score"))
    score = rank_by if rank_by in table.columns else ("score" if "score" in table.columns else None)
    response = next(
        (c for c in table.columns if "drift" in c),
        next((c for c in table.columns if c.startswith("peak_")), None),
    )
    if score is None or response is None:
        return [Note("The confirmation table has no score or peak-response column to compare.")], {}
    # the chosen set is the selection's (file, component): the equal-intensity rows are all
    # group "candidate"
    keys = zip(table["file"].astype(str), _components(table), strict=True)
    chosen = np.array([key in selected for key in keys], dtype=bool)
    ok = np.isfinite(table[score].to_numpy(float)) & np.isfinite(table[response].to_numpy(float))
    x = table[score].to_numpy(float)[ok]
    y = table[response].to_numpy(float)[ok]
    # a rank correlation needs three points and some spread in both (else it is undefined)
    spread = x.size >= 3 and np.ptp(x) > 0 and np.ptp(y) > 0
    rho = float(spearmanr(x, y).statistic) if spread else math.nan
    medians = {
        "selected": float(np.median(y[chosen[ok]])) if chosen[ok].any() else math.nan,
        "controls": float(np.median(y[~chosen[ok]])) if (~chosen[ok]).any() else math.nan,
    }
    stated = summary.get("medians") or {}
    if response == "peak_drift_ratio" and "peak_abs_x_m" in table.columns:
        response = "peak_abs_x_m"  # the response the command prints (m)
        y = table[response].to_numpy(float)[ok]
    if stated.get("equal_psa_t1_peak_x_m_selected") is not None and response == "peak_abs_x_m":
        # the numbers the command printed (selected against the controls)
        # a median of no control (every candidate chosen) is absent from the summary: NaN
        medians = {
            "selected": float(stated["equal_psa_t1_peak_x_m_selected"]),
            "controls": float(stated.get("equal_psa_t1_peak_x_m_control", math.nan)),
        }
    numbers = {
        "score": score,
        "response": response,
        "spearman_rho": rho,
        "n": int(x.size),
        "median_response_selected": medians["selected"],
        "median_response_controls": medians["controls"],
    }
    items: list[Figure | Table | Note | FigureJob] = [
        FigureJob(
            partial(
                figures.confirmation_figure,
                x,
                y,
                chosen[ok],
                score_name=score,
                response_name=response,
                rho=rho,
            ),
            key="confirmation",
            title="Score against simulated peak response at equal intensity",
            alt=(
                f"Scatter of {score} against {response} for {x.size} records, selected in red, "
                f"Spearman rank correlation {_or_not_run(rho, '.2f')}"
            ),
            how_to_read=(
                "Each dot is one record simulated at the same intensity, so frequency content is "
                "what differs. A score that predicts the response puts the dots on a rising "
                "trend (ρ near 1) and the red (selected) dots high; ρ near 0 means the score "
                "does not predict the simulated response."
            ),
        ),
        Table(
            "confirmation_summary",
            "Selected against controls",
            pd.DataFrame(_medians_rows(medians, stated, response)),
            f"Median simulated {response} of the selected and of the controls (as many "
            f"candidates, ranked lowest) at the confirmation's {confirmation_level(summary)} "
            "and, where the run states it, at the chosen scale; Spearman "
            f"ρ({score}, {response}) at the confirmation's intensity = {_or_not_run(rho, '.3g')}"
            f", n = {x.size}",
            {
                "group": "which records",
                "at": "the intensity: the confirmation's equal PSA(T_1), or each record at its "
                "chosen scale",
                f"median_{response}": "median of the simulated response",
                "overturned": "how many of the group overturn the frame there",
            },
        ),
    ]
    stated = summary.get("correlations")
    if isinstance(stated, list) and stated and all(isinstance(row, dict) for row in stated):
        items.append(
            Table(
                "correlations",
                "Each ranking and standard intensity measure against the simulated response",
                pd.DataFrame(stated),
                "Spearman ρ of each ranking (the run's own, the scores it computed, the standard "
                "intensity measures at the same equal PSA(T_1)) with each simulated response, "
                "with its bootstrap interval, the paired difference Δρ from the run's ranking, "
                "and the efficiency (selection.json). The run's own simulated ranking is judged "
                "here on the frame it was ranked with; docs/selection.md judges every ranking "
                "against perturbed frames.",
                {
                    "spearman": "Spearman rank correlation",
                    "low": "interval low",
                    "high": "high",
                    "delta": "ρ minus the run's ranking's ρ, same candidates (paired bootstrap "
                    "interval: delta_low, delta_high)",
                    "efficiency": "dispersion of ln response given ln value (smaller: more "
                    "efficient); peaks of runs that stand, overturning ratios of runs that "
                    "overturn",
                },
            )
        )
    return items, numbers


Items = list[Figure | Table | Note | FigureJob]


def _medians_rows(
    medians: dict[str, float], stated: dict[str, Any], response: str
) -> list[dict[str, Any]]:
    """The rows of "Selected against controls": the medians at the confirmation's equal
    intensity (against the controls when the run states its medians, else every other
    candidate), and the run's stated medians at the chosen scale with the overturned counts
    (absent from a folder of an earlier run)."""
    others = "controls" if stated else "controls / others"
    column = f"median_{response}"
    rows: list[dict[str, Any]] = [
        {"group": "selected", "at": "equal PSA(T_1)", column: _or_not_run(medians["selected"])},
        {"group": others, "at": "equal PSA(T_1)", column: _or_not_run(medians["controls"])},
    ]
    if "equal_psa_t1_overturned_selected" in stated:
        rows[0]["overturned"] = stated["equal_psa_t1_overturned_selected"]
        rows[1]["overturned"] = stated["equal_psa_t1_overturned_control"]
    if "chosen_scale_overturned_selected" in stated and response == "peak_abs_x_m":
        for group, name in (("selected", "selected"), (others, "control")):
            rows.append(
                {
                    "group": group,
                    "at": "chosen scale",
                    column: _or_not_run(stated.get(f"chosen_scale_peak_x_m_{name}")),
                    "overturned": stated[f"chosen_scale_overturned_{name}"],
                }
            )
    return rows


def _or_not_run(value: Any, spec: str | None = None) -> Any:
    """A number, or "not run" for a value the run did not compute (NaN, None)."""
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "not run"
    return format(value, spec) if spec else value


def band_section(summary: dict[str, Any], frame: Any, band: tuple[float, float]) -> Section:
    """The frame's period-amplitude backbone with its band, and the band's numbers."""
    from stepframe.structure.plots import backbone_figure

    items: Items = []
    given = summary.get("band")
    details: dict[str, Any] = given if isinstance(given, dict) else {}
    a_max = summary.get("a_max_m", details.get("a_max_m"))
    hz = f"{band[0] / TWO_PI:.3g}-{band[1] / TWO_PI:.3g} Hz"
    if frame is None and details.get("level_amplitudes_m") and details.get("level_omegas_rad_s"):
        items.append(
            FigureJob(
                partial(figures.backbone_points_figure, details, band),
                key="backbone",
                title="Period-amplitude backbone and band",
                alt=(
                    "The frame's frequency at the amplitude levels of the selection, falling from "
                    f"f_1 towards the band's lower edge, band {hz} shaded"
                ),
                how_to_read=(
                    "Once the frame steps (A > x_c) its period lengthens with amplitude. The "
                    "points are the amplitude levels the selection evaluated; the shaded band "
                    "is the range of frequencies the frame passes through up to A_max."
                ),
            )
        )
    elif frame is not None:
        items.append(
            FigureJob(
                partial(
                    backbone_figure,
                    frame,
                    band,
                    a_max_m=None if a_max is None else float(a_max),
                    frame_name=str(summary.get("frame_name", "frame")),
                ),
                key="backbone",
                title="Period-amplitude backbone and band",
                alt=(
                    "Frequency 1/T(A) of the frame against amplitude A, falling from f_1 at "
                    f"uplift towards zero at x*, band {hz} shaded"
                ),
                how_to_read=(
                    "Once the frame steps (A > x_c) its period lengthens with amplitude and its "
                    "frequency falls towards zero at overturning (x*). The shaded band is the "
                    "range of frequencies the frame passes through up to A_max: a record whose "
                    "dominant frequency sweeps down through it can keep it in moving resonance."
                ),
            )
        )
    else:
        items.append(Note("The selection summary names no frame: only the band is shown."))
    if details:
        scalars = {k: v for k, v in details.items() if isinstance(v, int | float | str)}
        items.append(
            Table(
                "band",
                "The band",
                pd.DataFrame({"quantity": list(scalars), "value": list(scalars.values())}),
                "As the selection run computed it (selection.json)",
                {"quantity": "name (unit in the name)", "value": "its value"},
            )
        )
    return Section("The frame's band", items)


#: The ranking a selection uses when none is named (what the paths' note says of it).
DEFAULT_RANK_BY = SelectionOptions().rank_by


def paths_section(
    rows: list[dict[str, Any]], names: list[str], band: tuple[float, float]
) -> Section:
    """Each selected record's fitted ω_g(t) against the band and its strong-motion window."""
    paths = []
    for row, name in zip(rows, names, strict=True):
        model = _model(row)
        if model is not None:
            paths.append((name, model, _strong_window(row, model)))
    if not paths:
        return Section(
            "Dominant-frequency paths of the selected records",
            [Note("The selection table carries no fitted parameters to draw.")],
        )
    figure = FigureJob(
        partial(figures.omega_paths_figure, paths, band),
        key="omega_paths",
        title="Selected records' ω_g(t) against the band",
        alt=(
            f"{len(paths)} small plots of fitted dominant frequency against time, each "
            "with the band and the strong-motion window shaded"
        ),
        how_to_read=(
            "Each panel is one selected record: its fitted dominant frequency ω_g(t)/2π "
            "(eq. 6.10) on a log scale, the frame's band in light blue and the "
            "strong-motion window in yellow. A candidate that sweeps down through the "
            "band while the motion is strong matches the frame's softening; recorded "
            "motions' fitted paths rarely reach a flexible frame's band, which is why the "
            "default ranking does not stand on these paths: it simulates the frame under "
            f"each candidate ({DEFAULT_RANK_BY}; docs/selection.md)."
        ),
    )
    return Section("Dominant-frequency paths of the selected records", [figure])


def _marked_candidates(outputs: SelectionOutputs) -> pd.DataFrame:
    """candidates.csv with a ``selected`` column (the chosen rows marked) when it has none."""
    selection = outputs.tables["selection"]
    candidates = outputs.tables["candidates"]
    if "selected" in candidates.columns:
        return candidates
    chosen = set(zip(selection["file"].astype(str), _components(selection), strict=True))
    keys = zip(candidates["file"].astype(str), _components(candidates), strict=True)
    candidates = candidates.copy()
    candidates.insert(1, "selected", [key in chosen for key in keys])
    return candidates


def scores_section(outputs: SelectionOutputs, candidates: pd.DataFrame, rank_by: str) -> Section:
    """The ranking (its stated intensity, what was simulated, the chosen set against the rest
    at that intensity, the tiers against the run's exact ranking), then the chosen set and
    every candidate with its scores and peers, as sortable tables."""
    from stepframe.pipeline.selection.ranking import ranking_lines

    summary = outputs.summary
    items: Items = [Note(line) for line in ranking_lines(summary)[:3]]
    tie = tie_line(summary)
    if tie:
        items.append(Note(tie[0].upper() + tie[1:]))
    versus = (summary.get("ranking") or {}).get("chosen_vs_rest")
    if isinstance(versus, dict) and versus:
        items.append(
            Table(
                "chosen_vs_rest",
                "The chosen set against the rest, simulated at the ranking intensity",
                pd.DataFrame(
                    [
                        {
                            "group": group,
                            "candidates": versus[f"n_{key}"],
                            # a group of none (every candidate chosen) has no median: empty
                            "median_simulated_response_m": versus.get(
                                f"simulated_response_m_{key}"
                            ),
                            "median_peak_x_m": versus.get(f"peak_x_m_{key}"),
                            "overturned": versus[f"overturned_{key}"],
                        }
                        for group, key in (("chosen", "chosen"), ("the rest", "rest"))
                    ]
                ),
                "The same simulations that ranked them (candidates.csv: simulated_response, "
                "ranking_peak_x_m, ranking_overturned)",
                {
                    "median_simulated_response_m": "median over the group of the ladder's "
                    "geometric-mean peak |x| [m]",
                    "median_peak_x_m": "median peak |x| at the ranking intensity itself [m]",
                    "overturned": "how many overturn the frame at the ranking intensity",
                },
            )
        )
    tiers = summary.get("tiers")
    if isinstance(tiers, list) and tiers:
        # A tier with the same value for every candidate has neither ρ nor recall (JSON leaves
        # them out): say why its row is empty.
        ranks_nothing = [str(t.get("tier")) for t in tiers if t.get("spearman") is None]
        empty = (
            f"; {', '.join(ranks_nothing)}: the same value for every candidate at the ranking "
            "intensity, so no order to compare"
            if ranks_nothing
            else ""
        )
        items.append(
            Table(
                "tiers",
                "The cheaper rankings (tiers) against this run's exact ranking",
                pd.DataFrame(tiers),
                "Spearman ρ of each tier with the simulated ranking, and the share of its top n "
                "found in each tier's top K (K = n, 2n, 5n, 10n); docs/selection.md publishes "
                f"the same for a family of frames{empty}",
                {
                    "spearman": "Spearman ρ with the exact ranking (95 % bootstrap interval: "
                    "low, high)",
                    "recall_at_1n": "share of the exact top n in the tier's top n",
                    "recall_at_10n": "share of the exact top n in the tier's top 10n",
                },
            )
        )
    items += [
        Table(
            "selection",
            "Selected records",
            outputs.tables["selection"],
            f"The chosen set, ranked by {rank_by}",
            outputs.columns.get("selection", {}),
            sortable=True,
        ),
        *_long_table(
            Table(
                "candidates",
                "Every candidate and its scores",
                candidates,
                "All candidates with the simulated response, every score and standard "
                "intensity measure, and the filter that dropped them",
                outputs.columns.get("candidates", {}),
                sortable=True,
            ),
            _best_first(candidates, rank_by),
            "best ranked first, the chosen ones at the top",
        ),
    ]
    return Section("Ranking and scores", items)


def _long_table(table: Table, ordered: pd.DataFrame, order: str) -> list[Table]:
    """``table`` on the page, or, past :data:`PAGE_ROWS` rows, its first rows in ``ordered``'s
    order on the page and the whole table as CSV only: a page of 43,000 rows is unreadable
    (and tens of megabytes)."""
    if len(table.frame) <= PAGE_ROWS:
        return [table]
    top = Table(
        f"{table.key}_top",
        f"{table.title}: the first {PAGE_ROWS} of {len(table.frame)}",
        ordered.head(PAGE_ROWS),
        f"{table.caption}; {order} (all {len(table.frame)} rows in {table.key}.csv)",
        table.columns,
        sortable=table.sortable,
    )
    return [top, dataclasses.replace(table, on_page=False)]


def _best_first(candidates: pd.DataFrame, rank_by: str) -> pd.DataFrame:
    """The candidates, chosen ones first, then best ranked first (by the ranking percentile, or
    the ranking score itself when the folder has no percentile)."""
    rank = "rank_score_percentile" if "rank_score_percentile" in candidates.columns else rank_by
    keys = [c for c in ("selected", rank) if c in candidates.columns]
    if not keys:
        return candidates
    return candidates.sort_values(keys, ascending=False, kind="stable", na_position="last")


def confirmation_section(
    outputs: SelectionOutputs,
    candidates: pd.DataFrame,
    rank_by: str,
    numbers: dict[str, Any],
    summary_lines: list[tuple[str, str]],
) -> Section:
    """The simulated response of the selected records against the controls and the candidates
    at equal intensity, and the stated correlations (or a note that it was not run)."""
    table = outputs.tables.get("confirmation")
    if table is None or table.empty:
        numbers["confirmation"] = "not run"
        summary_lines.append(("Confirmation", "not run (the run had no --confirm)"))
        return Section(
            "Confirmation by simulation",
            [Note("Not run: this selection was not confirmed by simulation (--confirm runs it).")],
        )
    summary = outputs.summary
    selection = outputs.tables["selection"]
    chosen = set(zip(selection["file"].astype(str), _components(selection), strict=True))
    equal = _equal_intensity(table, candidates, rank_by)
    items, confirmation_numbers = _confirmation(equal, summary, chosen)
    items += _long_table(
        Table(
            "confirmation",
            "Confirmation table",
            outputs.tables["confirmation"],
            "Simulated response of the selected records and the controls",
            outputs.columns.get("confirmation", {}),
            sortable=True,
        ),
        outputs.tables["confirmation"],
        "the selected records and the controls first",
    )
    numbers["confirmation"] = confirmation_numbers
    stated = _stated_correlations(summary, rank_by)
    if stated:
        summary_lines.append(("Confirmation", stated))
    elif confirmation_numbers:
        summary_lines.append(
            (
                "Confirmation",
                f"Spearman ρ = {_or_not_run(confirmation_numbers['spearman_rho'], '.2f')} "
                f"({confirmation_numbers['score']} vs {confirmation_numbers['response']}, "
                f"n = {confirmation_numbers['n']})",
            )
        )
    return Section("Confirmation by simulation", items)


def filters_section(
    outputs: SelectionOutputs, candidates: pd.DataFrame, numbers: dict[str, Any]
) -> Section:
    """What each filter dropped, and the records the run could not process."""
    dropped, column = _dropped(candidates)
    grouping = outputs.summary.get("grouping")
    intro: Items = []
    if isinstance(grouping, dict):
        from stepframe.pipeline.selection.grouping import grouping_line

        intro.append(Note(grouping_line(grouping).replace("records: ", "Records: ", 1) + "."))
        numbers["grouping"] = grouping
    warned = [r["warning"] for r in outputs.summary.get("filters", []) if "warning" in r]
    intro += [Note(str(text), "warning") for text in warned]
    items: Items = [
        *intro,
        Table(
            "filters",
            "What each filter dropped",
            dropped,
            f"Counted from candidates.csv column '{column}'" if column else "No filter column",
            {
                "filter": "the filter",
                "dropped": "candidates it dropped",
                "examples": "the first few",
            },
        ),
    ]
    failures = outputs.tables.get("failures")
    if failures is not None:
        items.append(
            Table(
                "failures",
                "Failures",
                failures,
                "Records the run could not process (each recorded, none stopped the run)",
                outputs.columns.get("failures", {}),
            )
        )
        numbers["n_failures"] = len(failures)
    return Section("Filters and failures", items)


def selection_report(
    outputs: SelectionOutputs,
    *,
    provenance: Provenance,
    record_loader: RecordLoader = load_record,
    jobs: int | None = 1,
    executor: Executor | None = None,
) -> Report:
    """Assemble the selection report from a read selection folder (no file written).

    Its sections in order (docs/reports.md): the frame's band, the selected records'
    ω_g(t) paths, the best records' accelerograms, the scores, the spectra of the set, the
    confirmation by simulation, moving resonance in the best records' simulations, the filters
    and failures. The figures and the moving-resonance simulations are independent of each
    other: they are made in one batch (:func:`~stepframe.pipeline.reports.document.draw_figures`,
    on the workers of ``jobs`` or ``executor``; default this process).
    """
    summary = outputs.summary
    folder = outputs.folder
    selection = outputs.tables["selection"]
    candidates = _marked_candidates(outputs)
    frame = _frame(summary, folder)
    band = _band(summary, frame, folder)
    rows: list[dict[str, Any]] = selection.to_dict(orient="records")  # type: ignore[assignment]
    names = [_name(row) for row in rows]
    rank_by = str(summary.get("rank_by", "score"))
    numbers: dict[str, Any] = {
        "band_rad_s": list(band),
        "band_hz": [band[0] / TWO_PI, band[1] / TWO_PI],
        "rank_by": rank_by,
        "n_selected": len(rows),
        "n_candidates": len(candidates),
        "selected": names,
    }
    summary_lines = [
        (
            "Frame's band",
            f"{band[0] / TWO_PI:.3g}-{band[1] / TWO_PI:.3g} Hz ({band[0]:.3g}-{band[1]:.3g} rad/s)",
        ),
        ("Ranked by", rank_by),
        *(
            [("Ranked at", str(intensity["text"]))]
            if isinstance(intensity := summary.get("ranking_intensity"), dict)
            and intensity.get("text")
            else []
        ),
        ("Selected", f"{len(rows)} of {len(candidates)} candidates"),
        *([("Tie", tie.removeprefix("tie: "))] if (tie := tie_line(summary)) else []),
        ("Scaling", str(summary.get("scale", summary.get("scaling", "none")))),
    ]
    best = rows[:N_ACCELEROGRAMS]

    def load(row: dict[str, Any]) -> Any:
        return record_loader(row, folder)

    drawn = [
        band_section(summary, frame, band),
        paths_section(rows, names, band),
        Section(
            "Accelerograms of the best records",
            _accelerogram_items(best, names, folder, record_loader, numbers),
        ),
        scores_section(outputs, candidates, rank_by),
        spectra_section(outputs, rows, names, band, record_loader, numbers, summary_lines),
        chosen_scale_section(summary, numbers, summary_lines),
        confirmation_section(outputs, candidates, rank_by, numbers, summary_lines),
    ]
    runs, missing = resonance_runs(
        best, names, [_ranking_scale_of(row) for row in best], frame, band, load
    )
    sections, measured = draw_figures(drawn, runs, jobs=jobs, executor=executor)
    sections += [
        resonance_section(frame, measured, missing, numbers),
        filters_section(outputs, candidates, numbers),
    ]
    return Report(
        title="Record selection report",
        subtitle=(
            "Records whose dominant frequency sweeps the stepping frame's band (moving resonance)"
        ),
        summary=summary_lines,
        sections=sections,
        provenance=provenance,
        numbers=numbers,
    )


def spectra_section(
    outputs: SelectionOutputs,
    rows: list[dict[str, Any]],
    names: list[str],
    band: tuple[float, float],
    record_loader: RecordLoader,
    numbers: dict[str, Any],
    summary_lines: list[tuple[str, str]],
) -> Section:
    """The set's scaled spectra against the target and the code's check: the run's own
    ``spectra.csv`` when it wrote one (the numbers the command printed), else recomputed from
    the records."""
    summary = outputs.summary
    target = summary.get("target")
    if isinstance(target, dict):
        summary_lines.append(("Target", str(target.get("describe", target.get("kind")))))
    check = summary.get("code_check")
    if isinstance(check, dict) and "line" in check:
        summary_lines.append(("Code check", str(check["line"])))
        numbers["code_check"] = {k: check[k] for k in ("passes", "lowest_ratio", "lowest_at_s")}
    elif isinstance(check, dict) and "not_run" in check:
        summary_lines.append(("Code check", f"not run ({check['not_run']})"))
        numbers["code_check"] = "not run"
    spectra = outputs.tables.get("spectra")
    if spectra is not None and not spectra.empty:
        items = _run_spectra_items(spectra, summary, band, numbers)
    else:
        items = _spectra_items(rows, names, outputs.folder, summary, band, record_loader, numbers)
    return Section("Spectra of the selected set", items)


def _run_spectra_items(
    spectra: pd.DataFrame,
    summary: dict[str, Any],
    band: tuple[float, float],
    numbers: dict[str, Any],
) -> Items:
    """The figure and tables of ``spectra.csv``: the units' scaled spectra, their mean, the
    target and, with a code target, its suite check."""
    periods = spectra["period_s"].to_numpy(float)
    units = [c for c in spectra.columns if c not in ("period_s", "target_g", "mean_g")]
    psa = spectra[units].to_numpy(float).T
    target = (periods, spectra["target_g"].to_numpy(float)) if "target_g" in spectra else None
    described = summary.get("set_spectra") or {}
    damping = float(described.get("damping", 0.05))
    stated = summary.get("code_check")
    check: dict[str, Any] = stated if isinstance(stated, dict) and "line" in stated else {}
    has_check = bool(check)
    fraction_range = None
    if has_check:
        low, high = (float(t) for t in check["period_range_s"])
        fraction_range = (float(check["fraction"]), (low, high))
    measure = described.get("measure", "component")
    items: Items = [
        FigureJob(
            partial(
                figures.spectra_figure,
                periods,
                psa,
                units,
                target=target,
                band_period_s=(TWO_PI / band[1], TWO_PI / band[0]),
                damping=damping,
                mean_g=spectra["mean_g"].to_numpy(float),
                check=fraction_range,
            ),
            key="spectra",
            title="Scaled spectra against the target",
            alt=(
                f"Pseudo-spectral acceleration of {len(units)} scaled {measure} spectra with "
                "their median, ±σ and mean" + (" and the target spectrum" if target else "")
            ),
            how_to_read=(
                f"Grey lines are the chosen set's spectra after scaling ({measure}: "
                + ("each component" if measure == "component" else "one per record, its pair")
                + "); black is their median and dashed the median times e^±σ, blue their mean "
                "(the average the codes check). "
                + (
                    str((summary.get("target") or {}).get("describe", "The target"))
                    + " is red"
                    + (
                        "; the dotted red line is the share of it the mean must reach over the "
                        "code's period range."
                        if fraction_range
                        else "."
                    )
                    if target is not None
                    else "The run had no target spectrum."
                )
                + " The shaded periods correspond to the frame's band."
            ),
        ),
        Table(
            "scale_factors",
            "Scale factors",
            pd.DataFrame(
                {
                    "unit": list((summary.get("scale_factors") or {}).keys()),
                    "scale_factor": list((summary.get("scale_factors") or {}).values()),
                }
            ),
            str(
                summary.get("scale_rule", "The factor each record's acceleration was multiplied by")
            ),
            {"unit": "record or component", "scale_factor": "amplitude scale factor [-]"},
        ),
        Table(
            "spectra",
            "Spectra of each unit",
            spectra,
            f"scaled PSA [g] at {damping:.0%} damping (spectra.csv of the run)",
            {
                "period_s": "oscillator period [s]",
                "target_g": "target [g]",
                "mean_g": "mean of the set [g]",
            }
            | dict.fromkeys(units, "scaled PSA [g]"),
            on_page=False,
        ),
    ]
    if summary.get("set_misfit") is not None:
        items.append(
            Note(
                f"Set misfit {float(summary['set_misfit']):.3g}: RMS over the misfit periods of "
                "ln(geometric mean of the scaled spectra / target)."
            )
        )
    if has_check:
        items.append(Note(str(check["line"]), "note" if check["passes"] else "warning"))
        items += [Note(str(note)) for note in check.get("notes", [])]
        items.append(
            Table(
                "code_check",
                "The code's check, period by period",
                pd.DataFrame({"period_s": check["periods_s"], "mean_over_target": check["ratio"]}),
                f"{check['clause']}: the mean must reach {float(check['fraction']):.0%} of the "
                "target at every period of the range",
                {"period_s": "period [s]", "mean_over_target": "mean of the set / target"},
            )
        )
    numbers["spectra_records"] = units
    return items


def chosen_scale_section(
    summary: dict[str, Any], numbers: dict[str, Any], summary_lines: list[tuple[str, str]]
) -> Section:
    """What the chosen set does to the frame at the chosen scale (the simulator on each chosen
    component), and the run's warnings."""
    response = summary.get("chosen_response")
    title = "The chosen set at its scale"
    if not isinstance(response, dict) or not response.get("n"):
        numbers["chosen_response"] = "not run"
        return Section(title, [Note("Not run: this selection folder has no chosen_response.")])
    counts = (
        f"of {response['n']} components, {response['linear']} stay linear, "
        f"{response['steps']} step, {response['overturns']} overturn the frame"
    )
    summary_lines.append(("At the chosen scale", counts))
    numbers["chosen_response"] = {k: response[k] for k in ("n", "linear", "steps", "overturns")}
    items: Items = [
        Note(
            f"Simulated at the chosen scale ({summary.get('scale_rule', 'as recorded')}): "
            f"{counts} (x_c = {float(response['x_c_m']):.3g} m)."
        ),
        Table(
            "chosen_response",
            "Each chosen component at its scale factor",
            pd.DataFrame(response["rows"]),
            "The exact simulator on each chosen component as it will be used",
            {
                "file": "record file",
                "component": "component",
                "record": "record",
                "scale": "scale factor [-]",
                "peak_abs_x_m": "peak |x| of the frame [m]",
                "state": "linear (no lift-off), steps, or overturns",
            },
        ),
    ]
    items += [Note(str(text), "warning") for text in summary.get("warnings", [])]
    return Section(title, items)


def _scale_of(row: dict[str, Any]) -> float:
    scale = row.get("scale_factor", 1.0)
    return 1.0 if scale is None or pd.isna(scale) else float(scale)


def _ranking_scale_of(row: dict[str, Any]) -> float:
    """The record's factor at the ranking intensity (``ranking_scale``: where the ranking saw
    it respond), else its scale factor."""
    scale = row.get("ranking_scale")
    if scale is None or pd.isna(scale) or not float(scale) > 0:
        return _scale_of(row)
    return float(scale)


def _accelerogram_items(
    rows: list[dict[str, Any]],
    names: list[str],
    folder: Path,
    record_loader: RecordLoader,
    numbers: dict[str, Any],
) -> list[Figure | Table | Note | FigureJob]:
    """The best records' time series, as scaled for the selection."""
    from stepframe.records.units import STANDARD_GRAVITY_M_S2

    drawn, missing = [], []
    for row, name in zip(rows, names, strict=False):
        trace = record_loader(row, folder)
        if trace is None:
            missing.append(name)
            continue
        acceleration_g = trace.data * _scale_of(row) / STANDARD_GRAVITY_M_S2
        drawn.append((name, trace.times(), acceleration_g))
    if not drawn:
        return [Note("None of the best records' files could be found: no accelerogram drawn.")]
    numbers["accelerogram_records"] = [name for name, _, _ in drawn]
    items: list[Figure | Table | Note | FigureJob] = [
        FigureJob(
            partial(figures.accelerograms_figure, drawn),
            key="accelerograms",
            title=f"The {len(drawn)} best records' accelerograms",
            alt=f"{len(drawn)} panels of ground acceleration in g against time in s, best first",
            how_to_read=(
                "Ground acceleration of the best-ranked records, in g after their scale factor, "
                "best first: the motions the frame is driven by in the confirmation."
            ),
        )
    ]
    if missing:
        items.append(Note(f"Not found, not drawn: {', '.join(missing)}.", "warning"))
    return items


def _spectra_items(
    rows: list[dict[str, Any]],
    names: list[str],
    folder: Path,
    summary: dict[str, Any],
    band: tuple[float, float],
    record_loader: RecordLoader,
    numbers: dict[str, Any],
) -> list[Figure | Table | Note | FigureJob]:
    from stepframe.records.spectra import response_spectrum

    damping = float(summary.get("damping", 0.05))
    target = _target(summary)
    # the spectra on the target's periods, where it has one (the run's own grid)
    periods = SPECTRUM_PERIODS_S if target is None else target[0]
    spectra = []
    used = []
    scales = []
    missing = []
    for row, name in zip(rows, names, strict=True):
        trace = record_loader(row, folder)
        if trace is None:
            missing.append(name)
            continue
        scale = _scale_of(row)
        result = response_spectrum(trace.data, trace.stats.delta, periods, damping)
        spectra.append(result.psa_g * scale)
        used.append(name)
        scales.append(scale)
    if not spectra:
        return [Note("None of the selected records' files could be found: no spectra drawn.")]
    psa = np.vstack(spectra)
    items: list[Figure | Table | Note | FigureJob] = [
        FigureJob(
            partial(
                figures.spectra_figure,
                periods,
                psa,
                used,
                target=target,
                band_period_s=(TWO_PI / band[1], TWO_PI / band[0]),
                damping=damping,
            ),
            key="spectra",
            title="Scaled spectra against the target",
            alt=(
                f"Pseudo-spectral acceleration of {len(used)} scaled records from "
                f"{periods[0]:.3g} to {periods[-1]:.3g} s "
                "with their median and ±σ" + (" and the target spectrum" if target else "")
            ),
            how_to_read=(
                "Grey lines are the selected records after scaling; black is their median and "
                "dashed the median times e^±σ (log standard deviation). "
                + (
                    "Red is the target spectrum; the set matches it where the median follows it."
                    if target
                    else "The run had no target spectrum."
                )
                + " The shaded periods correspond to the frame's band."
            ),
        ),
        Table(
            "scale_factors",
            "Scale factors",
            pd.DataFrame({"record": used, "scale_factor": scales}),
            "The factor each record's acceleration was multiplied by",
            {"record": "record [component]", "scale_factor": "amplitude scale factor [-]"},
        ),
    ]
    logs = np.log(psa)
    sigma = np.std(logs, axis=0, ddof=1) if len(used) > 1 else np.zeros(periods.size)
    median = np.exp(np.median(logs, axis=0))
    statistics = pd.DataFrame(
        {
            "period_s": periods,
            "median_psa_g": median,
            "minus_sigma_psa_g": median * np.exp(-sigma),
            "plus_sigma_psa_g": median * np.exp(sigma),
            "sigma_ln": sigma,
        }
    )
    if target is not None:
        statistics["target_psa_g"] = target[1]
    items.append(
        Table(
            "spectra_statistics",
            "Median and ±σ of the scaled spectra",
            statistics,
            f"PSA [g] at {damping:.0%} damping; σ is the standard deviation of ln PSA",
            {
                "period_s": "oscillator period [s]",
                "median_psa_g": "median scaled PSA [g]",
                "minus_sigma_psa_g": "median · e^-σ [g]",
                "plus_sigma_psa_g": "median · e^σ [g]",
                "sigma_ln": "standard deviation of ln PSA [-]",
                "target_psa_g": "target spectrum [g]",
            },
        )
    )
    table = pd.DataFrame(psa.T, columns=used)
    table.insert(0, "period_s", periods)
    items.append(
        Table(
            "spectra",
            "Spectra of each record",
            table,
            f"scaled PSA [g] of each selected record at {damping:.0%} damping",
            {"period_s": "oscillator period [s]"} | dict.fromkeys(used, "scaled PSA [g]"),
            on_page=False,
        )
    )
    if missing:
        items.append(Note(f"Not found, not drawn: {', '.join(missing)}.", "warning"))
    numbers["spectra_records"] = used
    return items


def write_selection_report(
    selection_dir: str | PathLike[str],
    out_html: str | PathLike[str] | None = None,
    *,
    provenance: Provenance,
    record_loader: RecordLoader = load_record,
    jobs: int | None = 1,
    executor: Executor | None = None,
) -> Path:
    """Write the selection report of a selection folder, all or nothing.

    Parameters
    ----------
    selection_dir
        The output folder of ``stepframe select``.
    out_html
        The HTML file (default: ``selection_report.html`` in ``selection_dir``).
    provenance
        From :func:`stepframe.pipeline.reports.provenance.collect_provenance`.
    record_loader
        Finds a selected record's trace (default: files, then the example catalogue).
    jobs, executor
        Where the figures and the moving-resonance simulations are made
        (:func:`stepframe.core.execution.map_items`; default this process).

    Returns
    -------
    pathlib.Path
        The HTML file.

    Raises
    ------
    InputError
        A missing or half-complete selection folder.
    """
    outputs = read_selection_folder(selection_dir)
    target = Path(selection_dir) / "selection_report.html" if out_html is None else Path(out_html)
    report = selection_report(
        outputs, provenance=provenance, record_loader=record_loader, jobs=jobs, executor=executor
    )
    return write_report(report, target)


def make_selection_report(selection_dir: str, out_html: str | None = None) -> Path:
    """The selection report of a selection output folder (default file: its
    ``selection_report.html``); the folder is checked before anything is hashed."""
    outputs = read_selection_folder(selection_dir)
    command = command_line(
        ["stepframe", "report", "selection", selection_dir],
        {} if out_html is None else {"out": out_html},
    )
    provenance = collect_provenance(
        command, inputs=outputs.files, parameters={"outdir": selection_dir}
    )
    return write_selection_report(selection_dir, out_html, provenance=provenance)
