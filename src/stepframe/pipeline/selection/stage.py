"""The selection job's stages: ``selection`` and ``selection_report``.

``selection`` calls :func:`stepframe.pipeline.selection.run.select_records` on the ``features``
table (joined with the inventory's event and magnitude, and the example catalogue's metadata);
``selection_report`` writes the report of that selection (docs/reports.md) into the stage's
folder, keyed by the selection's key, so it is rebuilt only when what it shows changes.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from stepframe.core.io import copy_files
from stepframe.errors import InputError
from stepframe.pipeline.catalogue.stage import record_folder
from stepframe.pipeline.engine.stage import Context, Stage
from stepframe.pipeline.engine.store import make_key
from stepframe.pipeline.reports.provenance import workflow_provenance

SELECTION_VERSION = 2  # 2: default rank_by substitute_demand_ratio
SELECTION_REPORT_VERSION = 3  # 2: the best records' accelerograms; 3: stated correlations
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
    # (joined as text: a Path per row cost seconds at 43,000 rows)
    folder_of_records = record_folder(context).absolute()
    prefix = f"{folder_of_records}{os.sep}"
    inventory = context.tables["inventory"]
    extra = inventory[["file", "component", "event", "magnitude"]]
    features = features.merge(extra, on=["file", "component"], how="left")
    features["file"] = prefix + features["file"].astype(str)
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
    result.write(folder)


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
