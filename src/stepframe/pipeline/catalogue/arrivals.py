"""The HTML summary of what arrived in a scheduled run: the ``arrivals_report`` stage.

A nightly run over an inbox measures what is new (``measures``, ``rotd50``, ``features``); this
page says what that was, in the run that brought it: the components measured in the latest run
(the rows whose ``processed_utc``, the start of the run that measured them, is the latest),
their intensity measures and spectra, their RotD50 and fitted parameters when those stages are
asked for too, and a line per earlier run with its count. Its size grows with what arrived in
one run, not with the catalogue. It sees the records folder as it is now: with ``[outputs]
history`` the output tables keep the files that left it (``present = false``), the page does
not. The items in the records folder that have no result (a file that cannot be read, a
component that cannot be measured: those of the latest run and those still there from earlier
runs) are named with their stage; why is in each output's ``.failures.csv`` (with first and last
seen times and a ``new`` mark when the workflow keeps a history). Its key is the keys of the rows
it shows and of the items without a result: a run that brings nothing leaves the last summary in
place, and the page names the run it describes. A run that only removes files changes the folder
it shows: the page is made again, still naming the latest run that measured something, without
what left (its components, its items without a result).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from stepframe.pipeline.catalogue.measures import STANDARD_PERIODS_S, psa_column
from stepframe.pipeline.engine.stage import Context, Stage
from stepframe.pipeline.engine.store import make_key

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.figure import Figure as MplFigure

    from stepframe.pipeline.reports.document import Report, Section

# 3: the items without a result are the records folder's (they always were: the latest run's and
# those left from earlier runs), said so; a run that only removed a failed file showed "none"
# beside an earlier run's arrivals as if that run had had none; 4: a shipped workflow's
# provenance names it as it is run
ARRIVALS_VERSION = 4
ARRIVALS_HTML = "arrivals_report.html"

#: Spectra drawn per figure (more are in the table and its CSV).
MAX_SPECTRA = 40

#: The measures shown on the page (all are in the CSV beside it).
PAGE_COLUMNS = (
    "file",
    "component",
    "event",
    "pga_g",
    "pgv_m_s",
    "pgd_m",
    "arias_m_s",
    "d5_95_s",
    psa_column(0.2),
    psa_column(1.0),
    psa_column(3.0),
    "processing",
)
#: The RotD50 columns shown on the page.
PAIR_COLUMNS = ("record", "station", "components", "pga_rotd50_g", "pgv_rotd50_m_s",
                "pgd_rotd50_m", psa_column(1.0).replace("psa_", "psa_rotd50_"))  # fmt: skip


def _upstream(workflow: Any) -> tuple[str, ...]:
    """``measures``, and ``rotd50`` and ``features`` when the workflow asks for them."""
    return ("measures", *(name for name in ("rotd50", "features") if name in workflow.outputs))


def without_result(context: Context) -> list[tuple[str, str]]:
    """(stage, item) of the items in the records folder that have no result (this run's tasks:
    every item there now), in the inventory and the stages the page shows (an item whose file
    could not be read is named once, by the inventory)."""
    found: list[tuple[str, str]] = []
    for name in ("inventory", *_upstream(context.workflow)):
        table = context.tables.get(name)
        done = set() if table is None else set(map(str, table["_key"]))
        found += [(name, task.name) for task in context.item_tasks.get(name, [])
                  if task.key not in done]  # fmt: skip
    return found


def _key(context: Context) -> str:
    from stepframe.pipeline.catalogue.measures_stage import measure_options

    keys = [
        str(key)
        for name in _upstream(context.workflow)
        for key in sorted(map(str, context.tables[name]["_key"]))
    ]
    # and when each was measured: the page shows the rows of the latest run that measured
    # something, which a run recomputing them (--force measures) changes without a new key
    for name in ("measures", "rotd50"):
        table = context.tables.get(name)
        if table is not None and "processed_utc" in table:
            keys += sorted(
                f"{k}@{t}" for k, t in zip(table["_key"], table["processed_utc"], strict=True)
            )
    keys += sorted(f"{stage}:{item}" for stage, item in without_result(context))
    params = {"measures": vars(measure_options(context.workflow)), "name": context.workflow.name}
    return make_key("arrivals_report", ARRIVALS_VERSION, params, *keys)


def spectra_figure(measures: pd.DataFrame, rotd50: pd.DataFrame | None) -> MplFigure:
    """PSA [g] against period of each component (at most :data:`MAX_SPECTRA`), RotD50 of each
    pair in black."""
    import numpy as np
    from matplotlib.figure import Figure
    from matplotlib.ticker import FormatStrFormatter

    fig = Figure(figsize=(9.5, 4.6), layout="constrained")
    ax = fig.add_subplot()
    periods = np.asarray(STANDARD_PERIODS_S)
    for _, row in measures.head(MAX_SPECTRA).iterrows():
        values = [row[psa_column(t)] for t in STANDARD_PERIODS_S]
        ax.loglog(
            periods,
            values,
            lw=1.0,
            alpha=0.8,
            label=f"{Path(str(row['file'])).name} [{row['component']}]",
        )
    if rotd50 is not None:
        styles = ("-", "--", ":", "-.")  # black lines told apart by their dashes
        for i, (_, row) in enumerate(rotd50.head(MAX_SPECTRA).iterrows()):
            values = [row[psa_column(t).replace("psa_", "psa_rotd50_")] for t in STANDARD_PERIODS_S]
            ax.loglog(periods, values, color="k", lw=2.0, ls=styles[i % len(styles)],
                      label=f"RotD50 {row['record']}")  # fmt: skip
    ax.set_xlabel("period T [s]")
    ax.set_ylabel("PSA [g], 5 % damping")
    for axis in (ax.xaxis, ax.yaxis):
        axis.set_major_formatter(FormatStrFormatter("%g"))  # 0.01 and 10, not 10⁻² and 10¹
    ax.set_title("Response spectra of the components that arrived", fontsize=10)
    ax.grid(True, which="both", lw=0.3)
    if len(ax.get_lines()) <= 12:
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    return fig


def overview_figure(measures: pd.DataFrame, latest: Any) -> MplFigure:
    """PGA [g] against D5-95 [s] of every component in the records folder, this run's
    highlighted."""
    from matplotlib.figure import Figure
    from matplotlib.ticker import FormatStrFormatter

    fig = Figure(figsize=(8.0, 4.2), layout="constrained")
    ax = fig.add_subplot()
    new = measures["processed_utc"] == latest
    ax.semilogy(
        measures.loc[~new, "d5_95_s"],
        measures.loc[~new, "pga_g"],
        "o",
        color="0.7",
        ms=4,
        label="earlier runs",
    )
    ax.semilogy(
        measures.loc[new, "d5_95_s"],
        measures.loc[new, "pga_g"],
        "o",
        color="C3",
        ms=6,
        label="this run",
    )
    ax.set_xlabel("significant duration D5-95 [s]")
    ax.set_ylabel("PGA [g]")
    for axis in (ax.yaxis.set_major_formatter, ax.yaxis.set_minor_formatter):
        axis(FormatStrFormatter("%g"))  # 0.3, 0.4 rather than 3×10⁻¹
    ax.set_title("Every component in the records folder", fontsize=10)
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=8)
    return fig


@dataclass(frozen=True)
class Arrivals:
    """What the latest run brought, out of the tables of every run so far.

    Attributes
    ----------
    latest
        The run's ``processed_utc`` (UTC, ISO 8601).
    measures
        Every component in the records folder.
    new, new_pairs
        This run's rows of ``measures`` and ``rotd50`` (None without ``rotd50``).
    runs
        Components measured per run, latest first.
    failed
        (stage, item) of the items in the records folder without a result.
    """

    latest: str
    measures: pd.DataFrame
    new: pd.DataFrame
    new_pairs: pd.DataFrame | None
    runs: pd.DataFrame
    failed: tuple[tuple[str, str], ...] = ()

    @property
    def records(self) -> int:
        """Records (station and event) among this run's components."""
        return len(self.new[["station", "event"]].drop_duplicates())


def arrivals_of(
    measures: pd.DataFrame,
    rotd50: pd.DataFrame | None,
    failed: tuple[tuple[str, str], ...] = (),
) -> Arrivals:
    """This run's rows (those with the latest ``processed_utc``) and the count of every run."""
    latest = str(measures["processed_utc"].max())
    new = measures[measures["processed_utc"] == latest].drop(columns=["_key"], errors="ignore")
    new_pairs = None
    if rotd50 is not None:
        this_run = rotd50["processed_utc"] == latest
        new_pairs = rotd50[this_run].drop(columns=["_key"], errors="ignore")
    runs = measures.groupby("processed_utc").size().rename("components").reset_index()
    runs = runs.sort_values("processed_utc")[::-1]
    return Arrivals(latest, measures, new, new_pairs, runs, failed)


def _summary(arrivals: Arrivals) -> list[tuple[str, str]]:
    new = arrivals.new
    top = new.iloc[int(new["pga_g"].to_numpy().argmax())]
    pairs = arrivals.new_pairs
    return [
        ("Run", f"{arrivals.latest} (UTC): the latest run that measured something"),
        (
            "Arrived in this run",
            f"{len(new)} components of {arrivals.records} records"
            + (f", {len(pairs)} horizontal pairs" if pairs is not None else ""),
        ),
        (
            "In the records folder",
            f"{len(arrivals.measures)} components, measured over {len(arrivals.runs)} runs",
        ),
        (
            "Without a result in the records folder",
            _failed_line(arrivals.failed) if arrivals.failed else "none",
        ),
        (
            "Largest PGA of this run",
            f"{top['pga_g']:.3g} g ({Path(str(top['file'])).name} [{top['component']}])",
        ),
        ("Processing", ", ".join(sorted({str(p) or "none (as read)" for p in new["processing"]}))),
    ]


def _failed_line(failed: tuple[tuple[str, str], ...]) -> str:
    """The items without a result, by stage, a few named."""
    by_stage: dict[str, list[str]] = {}
    for stage, item in failed:
        by_stage.setdefault(stage, []).append(item)
    parts = []
    for stage, items in by_stage.items():
        shown = ", ".join(items[:3]) + (f" and {len(items) - 3} more" if len(items) > 3 else "")
        parts.append(f"{len(items)} at {stage} ({shown})")
    return "; ".join(parts) + ": why in the .failures.csv tables"


def _meanings(columns: dict[str, tuple[str, str]]) -> dict[str, str]:
    return {name: f"{text} [{unit}]" if unit else text for name, (unit, text) in columns.items()}


def arrived_section(arrivals: Arrivals, features: pd.DataFrame | None) -> Section:
    """This run's components: their spectra, measures, RotD50 and fits."""
    from stepframe.pipeline.catalogue.measures import measure_columns, rotd50_columns
    from stepframe.pipeline.reports.document import Note, Section, Table, figure_from_matplotlib

    new, pairs = arrivals.new, arrivals.new_pairs
    meaning = _meanings(measure_columns())
    items: list[Any] = [
        figure_from_matplotlib(
            spectra_figure(new, pairs),
            key="spectra",
            title="Response spectra of this run's components",
            alt=f"PSA in g against period of the {len(new)} components of the run "
            f"{arrivals.latest}",
            how_to_read=(
                "Each coloured line is one component's 5 %-damped PSA at the 21 NGA-West2 "
                "periods (0.01-10 s); black lines, told apart by their dashes, are the RotD50 of "
                "the horizontal pairs. "
                f"At most {MAX_SPECTRA} of each are drawn; the table has them all."
            ),
        ),
        Table("arrived", "Components measured in this run",
              new[[c for c in PAGE_COLUMNS if c in new.columns]],
              "Intensity measures and PSA at three periods (every column: arrived_all.csv)",
              meaning, sortable=True),
        Table("arrived_all", "Every measure of this run's components", new, "all columns",
              meaning, on_page=False),
    ]  # fmt: skip
    if pairs is not None:
        pair_meaning = _meanings(rotd50_columns())
        items += [
            Table("arrived_rotd50", "RotD50 of this run's horizontal pairs",
                  pairs[[c for c in PAIR_COLUMNS if c in pairs.columns]],
                  "RotD50 (every period: arrived_rotd50_all.csv)", pair_meaning, sortable=True),
            Table("arrived_rotd50_all", "RotD50 of this run's pairs, every period", pairs,
                  "all columns", pair_meaning, on_page=False),
        ]  # fmt: skip
    if features is not None:
        items.append(_fits_table(new, features))
    items.append(
        Note(
            "Files that could not be read or measured are named in the summary at the top, not "
            "here: each output's failures table (measures.failures.csv, features.failures.csv) "
            "says why, with when each was first and last seen when the workflow keeps a history."
        )
    )
    return Section("Arrived in this run", items)


def history_section(arrivals: Arrivals) -> Section:
    """This run among every component in the records folder, and the count of every run."""
    from stepframe.pipeline.reports.document import Section, Table, figure_from_matplotlib

    measures = arrivals.measures
    return Section(
        "The records folder",
        [
            figure_from_matplotlib(
                overview_figure(measures, arrivals.latest),
                key="overview",
                title="This run among every component in the records folder",
                alt=f"PGA against D5-95 of {len(measures)} components, this run's "
                f"{len(arrivals.new)} in red",
                how_to_read=(
                    "Each point is one component; red ones arrived in this run. A point far "
                    "from the others (a PGA of several g, a duration of a fraction of a second) "
                    "is worth a look at its file."
                ),
            ),
            Table("runs", "Runs with arrivals", arrivals.runs,
                  "Components measured per run, latest first",
                  {"processed_utc": "start of the run (UTC)",
                   "components": "components measured"}),
        ],
    )  # fmt: skip


def arrivals_report(
    measures: pd.DataFrame,
    *,
    rotd50: pd.DataFrame | None = None,
    features: pd.DataFrame | None = None,
    failed: tuple[tuple[str, str], ...] = (),
    name: str = "",
    provenance: Any,
) -> Report:
    """The summary of the latest run's arrivals (see the module docstring).

    Parameters
    ----------
    measures
        The ``measures`` table (with ``processed_utc``).
    rotd50
        The ``rotd50`` table, or None.
    features
        The ``features`` table, or None (its fits are joined on file and component).
    failed
        (stage, item) of the records folder's items without a result (:func:`without_result`).
    name
        The workflow's name, for the title.
    provenance
        How the page was made.
    """
    from stepframe.pipeline.reports.document import Report

    arrivals = arrivals_of(measures, rotd50, failed)
    new, pairs = arrivals.new, arrivals.new_pairs
    return Report(
        title=f"What arrived: {name}" if name else "What arrived",
        subtitle=f"Records measured in the run of {arrivals.latest} (UTC)",
        summary=_summary(arrivals),
        sections=[arrived_section(arrivals, features), history_section(arrivals)],
        provenance=provenance,
        numbers={
            "run_utc": arrivals.latest,
            "components": len(new),
            "records": arrivals.records,
            "pairs": None if pairs is None else len(pairs),
            "components_in_folder": len(measures),
            "runs": len(arrivals.runs),
            "largest_pga_g": float(new["pga_g"].max()),
            "without_result": [{"stage": stage, "item": item} for stage, item in arrivals.failed],
        },
    )


def _fits_table(new: pd.DataFrame, features: pd.DataFrame) -> Any:
    """The fitted parameters of this run's components [Hz], joined on file and component."""
    import math

    from stepframe.pipeline.reports.document import Table

    fits = features.drop(columns=["_key"], errors="ignore")
    joined = new[["file", "component"]].merge(fits, on=["file", "component"], how="left")
    out = joined[["file", "component"]].copy()
    for key, label in (
        ("omega_p_rad_s", "f_p_hz"),
        ("omega_s_rad_s", "f_s_hz"),
        ("omega_r_rad_s", "f_r_hz"),
    ):
        out[label] = joined[key] / (2 * math.pi)
    for key in ("xi_p", "xi_r", "t_max_s", "t_dur_s", "plausible", "implausible_reason"):
        if key in joined.columns:
            out[key] = joined[key]
    return Table(
        "arrived_fits",
        "Fitted Beck-Papadimitriou parameters of this run's components",
        out,
        "From the features stage (empty where its fit failed)",
        {
            "f_p_hz": "ω_p/2π [Hz]",
            "f_s_hz": "ω_s/2π [Hz]",
            "f_r_hz": "ω_r/2π [Hz]",
            "plausible": "passes the plausibility checks",
        },
        sortable=True,
    )


def _run(context: Context, folder: Path) -> None:
    from stepframe.pipeline.catalogue.measures_stage import measure_options
    from stepframe.pipeline.reports.document import write_report
    from stepframe.pipeline.reports.provenance import workflow_provenance

    workflow = context.workflow
    tables = context.tables
    parameters = {"measures": vars(measure_options(workflow))}
    report = arrivals_report(
        tables["measures"],
        rotd50=tables.get("rotd50") if "rotd50" in workflow.outputs else None,
        features=tables.get("features") if "features" in workflow.outputs else None,
        failed=tuple(without_result(context)),
        name=workflow.name,
        provenance=workflow_provenance(workflow.path, parameters),
    )
    write_report(report, folder / ARRIVALS_HTML)


def _publish(folder: Path, outputs: Path) -> list[Path]:
    from stepframe.core.io import publish_copy

    return publish_copy(folder, outputs)


ARRIVALS_REPORT_STAGE = Stage(
    name="arrivals_report",
    version=ARRIVALS_VERSION,
    description="HTML summary of the latest run's arrivals: measures, spectra, RotD50, fits",
    kind="set",
    params={},
    upstream=_upstream,
    set_key=_key,
    run_set=_run,
    publish=_publish,
    needs_records=True,
    latest_set_only=True,  # one page per run with arrivals would pile up in the store
)


__all__ = [
    "ARRIVALS_REPORT_STAGE",
    "Arrivals",
    "arrivals_of",
    "arrivals_report",
    "overview_figure",
    "spectra_figure",
    "without_result",
]
