"""The selection job's stages: ``selection`` and ``selection_report``.

``selection`` calls :func:`stepframe.pipeline.selection.run.select_records` on the ``features``
table (joined with the inventory's event and magnitude, and the example catalogue's metadata);
``selection_report`` writes the report of that selection (docs/reports.md) into the stage's
folder, keyed by the selection's key, so it is rebuilt only when what it shows changes.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from stepframe.core.io import copy_files
from stepframe.errors import InputError
from stepframe.pipeline.catalogue.stage import record_folder
from stepframe.pipeline.engine.stage import Context, Stage
from stepframe.pipeline.engine.store import make_key
from stepframe.pipeline.reports.provenance import workflow_provenance

# 2: default rank_by substitute_demand_ratio; 3: records grouped, verticals left out, the
# chosen set's spectra, code check, response and motions; 4: records by identity; 5: ranked by
# the simulated response at a stated intensity
SELECTION_VERSION = 5
# 2: the best records' accelerograms; 3: stated correlations; 4: the run's spectra and check,
# the chosen set at its scale, chosen records marked, "not run"; 5: records by identity; 6: the
# ranking's sections; 7: the ranking intensity in the summary box
SELECTION_REPORT_VERSION = 7
SELECTION_REPORT_HTML = "selection_report.html"


def _selection_options(workflow: Any) -> Any:
    from stepframe.pipeline.selection import SelectionOptions

    given = workflow.tables.get("selection", {})
    try:
        return SelectionOptions.from_dict(given)
    except InputError as error:
        raise workflow.lines.error(f"[selection] {error.what}", "selection") from None


def _selection_check(workflow: Any) -> None:
    if workflow.records is None:
        raise workflow.lines.error("selection without a [records] table, expected one", "outputs")
    _selection_options(workflow)


def _selection_key(context: Context) -> str:
    table = context.tables["features"]
    return make_key(
        "selection",
        SELECTION_VERSION,
        {
            "options": context.workflow.tables.get("selection", {}),
            "frame": context.workflow.frame_source,
        },
        *map(str, table["_key"]),
    )


def _selection_run(context: Context, folder: Path) -> None:
    from stepframe.pipeline.selection import select_records

    features = context.tables["features"].drop(columns=["_key"])
    # select_records re-reads records by path (spectra, confirmation): give it absolute paths
    folder_of_records = record_folder(context).absolute()
    features["file"] = [str(folder_of_records / name) for name in features["file"]]
    inventory = context.tables["inventory"]
    extra = inventory[["file", "component", "event", "magnitude"]].copy()
    extra["file"] = [str(folder_of_records / name) for name in extra["file"]]
    features = features.merge(extra, on=["file", "component"], how="left")
    records = context.workflow.records
    if records is not None and records.example is not None:
        from stepframe.pipeline.catalogue.example_files import example_metadata

        features = _join_new_columns(features, example_metadata(folder_of_records))
    kwargs: dict[str, Any] = {"jobs": context.jobs, "executor": context.executor}
    if records is not None and records.options:
        kwargs["record_options"] = dict(records.options)
    result = select_records(
        features, context.workflow.frame, _selection_options(context.workflow), **kwargs
    )
    # a timing is a fact of this run, not of the selection: the run log keeps it (byte-stable
    # outputs, docs/workflows.md)
    throughput = result.summary.pop("confirmation_samples_per_s", None)
    simulation_s = (result.summary.get("ranking") or {}).pop("simulation_s", None)
    context.facts["selection"] = {
        "confirmation_samples_per_s": throughput,
        "ranking_simulation_s": simulation_s,
    }
    hashes = dict(zip(inventory["file"], inventory["content_sha256"], strict=True))
    result = result.with_record_identity(folder_of_records, hashes, _records_identity(context))
    result.write(folder)


def _records_identity(context: Context) -> dict[str, Any]:
    """Where the records are, as the workflow names them (its folder relative to the workflow
    file's, or the example), and the options they are read with."""
    records = context.workflow.records
    assert records is not None  # checked before the run
    options = dict(records.options)
    if records.example is not None:
        return {"example": records.example, "options": options}
    assert records.folder is not None
    try:
        folder = records.folder.relative_to(context.workflow.path.parent).as_posix()
    except ValueError:  # an absolute folder elsewhere: as the user gave it
        folder = records.folder.as_posix()
    return {"folder": folder, "options": options}


def _join_new_columns(table: Any, extra: Any) -> Any:
    """``table`` with the columns of ``extra`` it lacks, matched on ``file``."""
    new = [c for c in extra.columns if c not in table.columns]
    return table.merge(extra[["file", *new]], on="file", how="left")


def _selection_publish(folder: Path, outputs: Path) -> list[Path]:
    return copy_files(folder, outputs / "selection")


SELECTION_STAGE = Stage(
    name="selection",
    version=SELECTION_VERSION,
    description="records ranked by their moving-resonance match to the frame",
    kind="set",
    params={},
    upstream=lambda workflow: ("features",),
    set_key=_selection_key,
    run_set=_selection_run,
    publish=_selection_publish,
    needs_records=True,
    needs_frame=True,
    check=_selection_check,
    free_params=True,
)


def _publish_report(folder: Path, outputs: Path) -> list[Path]:
    return copy_files(folder, outputs)


def _selection_report_key(context: Context) -> str:
    return make_key("selection_report", SELECTION_REPORT_VERSION, {}, context.set_keys["selection"])


def _selection_report_run(context: Context, folder: Path) -> None:
    from stepframe.pipeline.selection.report import write_selection_report

    options = context.workflow.tables.get("selection", {})
    write_selection_report(
        context.set_dirs["selection"],
        folder / SELECTION_REPORT_HTML,
        provenance=workflow_provenance(context.workflow.path, {"selection": options}),
    )


SELECTION_REPORT_STAGE = Stage(
    name="selection_report",
    version=SELECTION_REPORT_VERSION,
    description="the selection report: self-contained HTML with its numbers",
    kind="set",
    params={},
    upstream=lambda workflow: ("selection",),
    set_key=_selection_report_key,
    run_set=_selection_report_run,
    publish=_publish_report,
    needs_records=True,
    needs_frame=True,
)
