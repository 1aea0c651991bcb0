"""The selection job's stages: ``responses``, ``selection`` and ``selection_report``.

``responses`` is the selection's work on each record (:mod:`.record_pass`: the spectra at the
frame's periods with the peers, the ranking's simulations at the record's own scale and, with
confirmation, the simulation at equal intensity), per component and stored, so a new record
costs its own pass only; it follows ``features``
(:attr:`~stepframe.pipeline.engine.stage.Stage.expand`), a group of files at a time, on the
records the worker has just read. ``selection`` calls
:func:`stepframe.pipeline.selection.run.select_records` on the ``features`` table (joined with
the inventory's event and magnitude, and the example catalogue's metadata) and the stored
responses; ``selection_report`` writes the report of that selection (docs/reports.md) into the
stage's folder, keyed by the selection's key, so it is rebuilt only when what it shows changes.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from stepframe.core.io import publish_copy, replace_folder_copy
from stepframe.errors import InputError
from stepframe.pipeline.catalogue.stage import record_folder
from stepframe.pipeline.engine.stage import Context, Stage, Task
from stepframe.pipeline.engine.store import KeyPrefix, make_key
from stepframe.pipeline.reports.provenance import workflow_provenance
from stepframe.pipeline.selection.result import SELECTION_REPORT_HTML

# 2: default rank_by substitute_demand_ratio; 3: records grouped, verticals left out, the
# chosen set's spectra, code check, response and motions; 4: records by identity; 5: ranked by
# the simulated response at a stated intensity; 6: the frame in selection.json; 7: the ranking's
# estimate and budget in CPU seconds of one core (the same on every machine); 8: the exact
# integrator's chord-bound fast path (its runs the same to rounding), the bootstrap's kernel; 9:
# the ranking's ties (ranking_tie, ranking.tie), the confirmation's intensity and the chosen
# scale's overturned counts in the medians; 10: a tier ranking's intensity without the
# simulation's ladder (it simulates nothing); 11: a metadata filter's text counts the candidates
# without a value
SELECTION_VERSION = 11
# 2: the peers and the ranking's simulations in the pass; 3: the exact integrator's chord-bound
# fast path (the same runs to rounding: recomputed rather than mixed with the former kernel's);
# 4: raw counts ranked and simulated after the standard processing (records.io.read_measured)
RESPONSES_VERSION = 4
# 2: the best records' accelerograms; 3: stated correlations; 4: the run's spectra and check,
# the chosen set at its scale, chosen records marked, "not run"; 5: records by identity; 6: the
# ranking's sections; 7: the ranking intensity in the summary box; 8: the frame from
# selection.json (the moving-resonance section runs); 9: that section at the ranking intensity;
# 10: its simulations by the integrator's chord-bound fast path (the same to rounding); 11: the
# ranking's tie, the selected against the controls at both intensities; 12: the target as the
# selection stored it where the report recomputes the spectra, "—" for a ρ that is not a number,
# and a shipped workflow's provenance names it as it is run; 13: the moving-resonance section's
# spectrum from the two-sided resonator bank, not the Morlet wavelet (issue 26)
SELECTION_REPORT_VERSION = 13


def _selection_options(workflow: Any) -> Any:
    from stepframe.pipeline.selection import SelectionOptions

    given = workflow.tables.get("selection", {})
    try:
        return SelectionOptions.from_dict(given)
    except InputError as error:
        raise workflow.lines.error(f"[selection] {error.what}", "selection", error.key) from None


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
        *map(str, context.tables["responses"]["_key"]),
    )


def _selection_run(context: Context, folder: Path) -> None:
    from stepframe.pipeline.selection import select_records

    features = context.tables["features"].drop(columns=["_key"])
    # select_records re-reads records by path (the chosen set): give it absolute paths (joined
    # as text: a Path per row cost seconds at 43,000 rows)
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
    stored = context.tables["responses"].drop(columns=["_key"]).to_dict(orient="records")
    kwargs: dict[str, Any] = {
        "jobs": context.jobs,
        "executor": context.executor,
        "responses": {(prefix + str(r["file"]), str(r["component"])): r for r in stored},
    }
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
    # replaced whole: a run choosing fewer records, or without confirmation, leaves no file of
    # an earlier one (motions/ of records no longer chosen, confirmation.csv)
    return replace_folder_copy(folder, outputs / "selection")


#: What a responses task is made of besides its component: the pass the workflow's selection
#: needs (None: none), its digest, the record options, the records folder (absolute) and the
#: prefix of the stage's keys.
ResponsesArgs = tuple[Any, str, dict[str, Any], str, KeyPrefix]


def _responses_args(context: Context) -> ResponsesArgs:
    """The :data:`ResponsesArgs` of a run."""
    from stepframe.pipeline.selection import record_pass

    workflow = context.workflow
    records = dict(workflow.records.options) if workflow.records is not None else {}
    spec = record_pass.selection_inputs(workflow.frame, _selection_options(workflow), records)[3]
    digest = record_pass.spec_digest(spec) if spec is not None else ""
    prefix = KeyPrefix("responses", RESPONSES_VERSION, {"spec": digest})
    return spec, digest, records, str(record_folder(context).absolute()), prefix


def _response_task(
    args: ResponsesArgs,
    features_key: str,
    file: str,
    component: str,
    sha: str,
) -> Task:
    spec, digest, options, folder, prefix = args
    return Task(
        key=prefix.key(features_key),
        name=f"{file} [{component}]",
        payload=(f"{folder}{os.sep}{file}", options, component, sha, spec, digest),
        context={"file": file, "component": component},
    )


def _responses_tasks(context: Context) -> list[Task]:
    args = _responses_args(context)
    if args[0] is None:
        return []
    features = context.tables["features"]
    inventory = context.tables["inventory"]
    # whole columns as lists: iterating a Series of Arrow strings costs a call per value
    sha = dict(zip(inventory["file"].tolist(), inventory["content_sha256"].tolist(), strict=True))
    return [
        _response_task(args, str(key), str(file), str(component), str(sha[file]))
        for key, file, component in zip(
            features["_key"].tolist(),
            features["file"].tolist(),
            features["component"].tolist(),
            strict=True,
        )
    ]


def expand_responses(args: ResponsesArgs, features: Task, rows: list[dict[str, Any]]) -> list[Task]:
    """The responses task of one component, from its features task (worker side)."""
    if args[0] is None or not rows:
        return []
    file, component = str(features.context["file"]), str(features.context["component"])
    return [_response_task(args, features.key, file, component, str(features.payload[-1]))]


def compute_responses(payloads: list[Any]) -> list[list[dict[str, Any]] | Exception]:
    """The record pass of a group of components (worker side): the records from
    :func:`~stepframe.pipeline.catalogue.stage.read_record` (read just before for their
    features), simulated together; per component its stored row, or why it failed."""
    from stepframe.pipeline.catalogue.stage import ItemFailure, read_record
    from stepframe.pipeline.selection import record_pass

    spec, digest = payloads[0][4], payloads[0][5]
    out: list[list[dict[str, Any]] | Exception] = [ItemFailure("not computed")] * len(payloads)
    members = []
    for k, (path, options, component, sha, *_) in enumerate(payloads):
        try:
            samples = record_pass.component_samples(
                read_record(path, options, sha), path, component
            )
        except Exception as error:  # recorded as this item's failure
            out[k] = ItemFailure(f"samples: {error}")
            continue
        members.append(record_pass.Component(k, path, component, True, samples))
    for outcome in record_pass.record_pass((tuple(members), spec)):
        if outcome.failure is not None:
            out[outcome.row] = ItemFailure(f"{outcome.failure.stage}: {outcome.failure.message}")
        else:
            out[outcome.row] = [record_pass.stored(outcome, digest)]
    return out


RESPONSES_COLUMNS: dict[str, tuple[str, str]] = {
    "file": ("", "record file, relative to the records folder"),
    "component": ("", "channel / component name"),
    "spec": ("", "digest of the pass (periods, dampings, frame, intensities) it was computed for"),
    "sd_5": ("m", "SD at T_1 and the misfit periods, 5 % damping (JSON list)"),
    "sd_t1_m": ("m", "SD(T_1, xi_1)"),
    "sd_levels": ("m", "SD at the substitute structure's levels (JSON list; empty: not named)"),
    "npts": ("", "samples of the record"),
    "dt_s": ("s", "sampling interval"),
    "simulations": (
        "",
        "JSON: the peers, the ranking's simulated response at the record's own scale and the "
        "equal-intensity simulation with its overturning ratio (null: not run in the pass)",
    ),
    "ranking_s": ("s", "time of the ranking's simulations (its share of its group's)"),
    "equal_s": ("s", "time of the equal-intensity simulation (its share of its group's)"),
}

RESPONSES_STAGE = Stage(
    name="responses",
    version=RESPONSES_VERSION,
    description="per component: the spectra, peers and simulated responses the selection uses",
    kind="item",
    params={},
    upstream=lambda workflow: ("features",),
    columns=lambda: RESPONSES_COLUMNS,
    tasks=_responses_tasks,
    compute_many=compute_responses,
    needs_records=True,
    needs_frame=True,
    check=_selection_check,
    expand=expand_responses,
    expand_args=_responses_args,
)

SELECTION_STAGE = Stage(
    name="selection",
    version=SELECTION_VERSION,
    description="records ranked by their moving-resonance match to the frame",
    kind="set",
    params={},
    upstream=lambda workflow: ("features", "responses"),
    set_key=_selection_key,
    run_set=_selection_run,
    publish=_selection_publish,
    needs_records=True,
    needs_frame=True,
    check=_selection_check,
    free_params=True,
)


def _publish_report(folder: Path, outputs: Path) -> list[Path]:
    return publish_copy(folder, outputs)


def _selection_report_key(context: Context) -> str:
    return make_key("selection_report", SELECTION_REPORT_VERSION, {}, context.set_keys["selection"])


def _selection_report_run(context: Context, folder: Path) -> None:
    from stepframe.pipeline.selection.report import write_selection_report

    options = context.workflow.tables.get("selection", {})
    write_selection_report(
        context.set_dirs["selection"],
        folder / SELECTION_REPORT_HTML,
        provenance=workflow_provenance(context.workflow.path, {"selection": options}),
        # the figures and the best records' simulations on the run's workers
        jobs=context.jobs,
        executor=context.executor,
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
