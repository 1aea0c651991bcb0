"""The report stages: the selection report and the site amplification report in a workflow.

Each is a whole-set stage named in ``[outputs]`` (``selection_report = true``,
``amplification_report = true``) whose upstream is the stage it reports on; the report (one
self-contained HTML file and ``<stem>_files/`` with every number it shows, docs/reports.md) is
written into the stage's folder in the store and copied to the outputs. The store key is the
upstream result's key, so a report is rebuilt only when what it shows changes.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

# The stages reported on register first: registry order is pipeline order.
from stepframe.pipeline import stage_sets
from stepframe.pipeline.stages import Context, Param, Stage, register_stage
from stepframe.pipeline.store import make_key

SELECTION_REPORT_VERSION = 3  # 2: the best records' accelerograms; 3: stated correlations
AMPLIFICATION_REPORT_VERSION = 1
SELECTION_REPORT_HTML = "selection_report.html"
AMPLIFICATION_REPORT_HTML = "amplification_report.html"

AMPLIFICATION_REPORT_PARAMS: dict[str, Param] = {
    "monte_carlo": Param("int", 50, "Monte Carlo motions per checked frequency (0: none)"),
}


def _provenance(context: Context, parameters: dict[str, Any]) -> Any:
    from stepframe.pipeline.reports.provenance import collect_provenance

    workflow = context.workflow.path
    return collect_provenance(
        ["stepframe", "run", str(workflow)], parameters=parameters, workflow=workflow
    )


def _publish(folder: Path, outputs: Path) -> list[Path]:
    return stage_sets.copy_files(folder, outputs)


def _selection_report_key(context: Context) -> str:
    return make_key("selection_report", SELECTION_REPORT_VERSION, {}, context.set_keys["selection"])


def _selection_report_run(context: Context, folder: Path) -> None:
    from stepframe.pipeline.reports.selection import write_selection_report

    options = context.workflow.tables.get("selection", {})
    write_selection_report(
        context.set_dirs["selection"],
        folder / SELECTION_REPORT_HTML,
        provenance=_provenance(context, {"selection": options}),
    )


register_stage(
    Stage(
        name="selection_report",
        version=SELECTION_REPORT_VERSION,
        description="the selection report: self-contained HTML with its numbers",
        kind="set",
        params={},
        upstream=lambda workflow: ("selection",),
        set_key=_selection_report_key,
        run_set=_selection_report_run,
        publish=_publish,
        needs_records=True,
        needs_frame=True,
    )
)


def _amplification_report_key(context: Context) -> str:
    params = AMPLIFICATION_REPORT_STAGE.parameters(context.workflow)
    params["frame"] = context.workflow.frame_source
    return make_key(
        "amplification_report", AMPLIFICATION_REPORT_VERSION, params, context.set_keys["site"]
    )


def _amplification_report_run(context: Context, folder: Path) -> None:
    from stepframe.pipeline.reports.amplification import (
        AmplificationOptions,
        write_amplification_report,
    )
    from stepframe.pipeline.site import read_site_model

    params = AMPLIFICATION_REPORT_STAGE.parameters(context.workflow)
    site = read_site_model(context.set_dirs["site"] / stage_sets.SITE_JSON)
    write_amplification_report(
        site.model,
        folder / AMPLIFICATION_REPORT_HTML,
        frame=context.workflow.frame,
        options=AmplificationOptions(
            site_name=context.workflow.name or "site", monte_carlo=params["monte_carlo"]
        ),
        provenance=_provenance(context, {"site": site.to_dict(), **params}),
    )


AMPLIFICATION_REPORT_STAGE = register_stage(
    Stage(
        name="amplification_report",
        version=AMPLIFICATION_REPORT_VERSION,
        description="the site amplification report: self-contained HTML with its numbers",
        kind="set",
        params=AMPLIFICATION_REPORT_PARAMS,
        upstream=lambda workflow: ("site",),
        set_key=_amplification_report_key,
        run_set=_amplification_report_run,
        publish=_publish,
    )
)
