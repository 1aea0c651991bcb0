"""The catalogue's nightly-job stages: ``measures``, ``rotd50`` and ``waveforms``.

``measures`` (one item per component, beside ``features``): PGA, PGV, PGD, Arias, D5-95 and the
PSA at the NGA-West2 periods (:func:`stepframe.pipeline.catalogue.measures.component_measures`).
``rotd50`` (one item per pair of horizontal components of one record): RotD50 of PGA, PGV, PGD
and PSA (:func:`~stepframe.pipeline.catalogue.measures.pair_measures`). Components are grouped
into records as the selection groups them (:func:`stepframe.pipeline.selection.grouping.
group_records`: PEER's RSN, a K-NET/KiK-net file's station and origin time, the header's station
and event, else the file), so the two AT2 files of a PEER record make one; a record with exactly
two horizontal components has a pair. ``waveforms`` (whole set, on
request) writes each component after the same processing as SAC (acceleration in SAC's nm/s²)
with an index table.
All three follow the ``[measures]`` table (:class:`~stepframe.pipeline.catalogue.measures.
MeasureOptions`). Rows carry ``processed_utc``, the start of the run that measured them (the
run's ``started_utc``, the time a workflow with ``[outputs] history`` also writes as the
``first_seen_utc`` of what that run found first): the ``arrivals_report`` stage
(:mod:`stepframe.pipeline.catalogue.arrivals`) tells from it what arrived in a run.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from stepframe.errors import InputError
from stepframe.pipeline.catalogue.measures import MeasureOptions
from stepframe.pipeline.catalogue.stage import ItemFailure, _one_line, read_kwargs, record_folder
from stepframe.pipeline.engine.stage import Context, Param, Stage, Task, params_from_options
from stepframe.pipeline.engine.store import make_key

MEASURES_VERSION = 1
ROTD50_VERSION = 1
WAVEFORMS_VERSION = 1

#: The ``[measures]`` table (declared once, on :class:`MeasureOptions`).
MEASURE_PARAMS: dict[str, Param] = params_from_options(
    MeasureOptions, ("processing", "highpass_hz")
)
WAVEFORMS_FOLDER = "waveforms"
WAVEFORMS_INDEX = "index.csv"
#: SAC's dependent-variable code for acceleration, whose unit is nm/s² (SAC manual, IDEP).
SAC_IACC = 8
SAC_NM_PER_M = 1e9


def measure_options(workflow: Any) -> MeasureOptions:
    """The ``[measures]`` table as :class:`MeasureOptions` (errors at the key's line)."""
    try:
        return MeasureOptions(**workflow.tables.get("measures", {}))
    except InputError as error:
        raise workflow.lines.error(f"[measures] {error.what}", "measures", error.key) from None


def _check(workflow: Any) -> None:
    measure_options(workflow)


def _params(context: Context) -> dict[str, Any]:
    """The ``[measures]`` values every stage here keys its results by."""
    from dataclasses import asdict

    return asdict(measure_options(context.workflow))


def run_stamp(context: Context) -> str:
    """The run's start (UTC, ISO 8601): the ``processed_utc`` of every row the run computes,
    the same for ``measures`` and ``rotd50`` (and the history's seen time), so the
    ``arrivals_report`` can tell this run's rows from earlier ones."""
    if not context.started_utc:
        raise ValueError("a context without its run's start, expected one made by run_workflow")
    return context.started_utc


def _record_options(context: Context) -> dict[str, Any]:
    records = context.workflow.records
    return dict(records.options) if records is not None else {}


def _read_component(path: str, record_options: dict[str, Any], index: int, name: str) -> Any:
    """Component ``index`` of the file at ``path`` (``name`` in the records folder, which a
    failure names instead of the absolute path)."""
    from stepframe.records import read

    try:
        return read(path, **read_kwargs(record_options))[index]
    except Exception as error:  # a reader may raise anything on a foreign file: recorded
        raise ItemFailure(f"read: {_one_line(error, path, name)}") from None


def _measures_tasks(context: Context) -> list[Task]:
    params = _params(context)
    options = _record_options(context)
    folder = record_folder(context)
    stamp = run_stamp(context)  # one per run: the rows computed now share it
    tasks = []
    for row in context.tables["inventory"].to_dict(orient="records"):
        index = int(row["channel_index"])
        key = make_key("measures", MEASURES_VERSION, params, str(row["_key"]), str(index))
        tasks.append(
            Task(
                key=key,
                name=f"{row['file']} [{row['component']}]",
                payload=(
                    str((folder / str(row["file"])).absolute()),
                    options,
                    index,
                    params,
                    stamp,
                    str(row["file"]),
                ),
                context={
                    "file": row["file"],
                    "duplicates": row["duplicates"],
                    "station": row["station"],
                    "component": row["component"],
                    "event": row["event"],
                },
            )
        )
    return tasks


def component_row(
    payload: tuple[str, dict[str, Any], int, dict[str, Any], str, str],
) -> list[dict[str, Any]]:
    """The measures of one component (worker side): one row."""
    from stepframe.pipeline.catalogue.measures import component_measures

    path, record_options, index, params, stamp, name = payload
    trace = _read_component(path, record_options, index, name)
    try:
        row = component_measures(trace, MeasureOptions(**params))
    except Exception as error:  # recorded as this item's failure
        raise ItemFailure(f"measures: {_one_line(error)}") from None
    return [{**row, "processed_utc": stamp}]


def _measure_columns() -> dict[str, tuple[str, str]]:
    from stepframe.pipeline.catalogue.measures import measure_columns

    return measure_columns()


def record_pairs(inventory: Any) -> list[tuple[str, dict[str, Any], dict[str, Any]]]:
    """The pairs of horizontal components of each record of an inventory table.

    Records are grouped as the selection groups them
    (:func:`stepframe.pipeline.selection.grouping.group_records`); a record has a pair when it
    has exactly two horizontal components. Each pair is (record name, h1, h2), in inventory
    order (file, then position in the file): h1 first.
    """
    from stepframe.pipeline.selection.grouping import group_records

    grouping = group_records(inventory)
    records: dict[str, list[dict[str, Any]]] = {}
    rows = inventory.to_dict(orient="records")
    for row, record, vertical in zip(rows, grouping.record, grouping.vertical, strict=True):
        if not vertical:
            records.setdefault(str(record), []).append(row)
    pairs = []
    for record, horizontal in records.items():
        if len(horizontal) == 2:
            pairs.append((record, horizontal[0], horizontal[1]))
    return pairs


def _rotd50_tasks(context: Context) -> list[Task]:
    params = _params(context)
    options = _record_options(context)
    folder = record_folder(context)
    stamp = run_stamp(context)
    tasks = []
    for record, h1, h2 in record_pairs(context.tables["inventory"]):
        parts = [
            (str((folder / str(r["file"])).absolute()), int(r["channel_index"]), str(r["file"]))
            for r in (h1, h2)
        ]
        key = make_key(
            "rotd50",
            ROTD50_VERSION,
            params,
            str(h1["_key"]),
            str(h1["channel_index"]),
            str(h2["_key"]),
            str(h2["channel_index"]),
        )
        files = h1["file"] if h1["file"] == h2["file"] else f"{h1['file']};{h2['file']}"
        components = f"{h1['component']};{h2['component']}"
        tasks.append(
            Task(
                key=key,
                name=f"{files} [{components}]",
                payload=(parts, options, params, stamp),
                context={
                    "record": record,
                    "files": files,
                    "station": h1["station"],
                    "event": h1["event"],
                    "components": components,
                },
            )
        )
    return tasks


def pair_row(
    payload: tuple[list[tuple[str, int, str]], dict[str, Any], dict[str, Any], str],
) -> list[dict[str, Any]]:
    """RotD50 of one pair of horizontal components (worker side): one row."""
    from stepframe.pipeline.catalogue.measures import pair_measures

    parts, record_options, params, stamp = payload
    h1, h2 = (_read_component(path, record_options, index, name) for path, index, name in parts)
    try:
        row = pair_measures(h1, h2, MeasureOptions(**params))
    except Exception as error:
        raise ItemFailure(f"rotd50: {_one_line(error)}") from None
    return [{**row, "processed_utc": stamp}]


def _rotd50_columns() -> dict[str, tuple[str, str]]:
    from stepframe.pipeline.catalogue.measures import rotd50_columns

    return rotd50_columns()


MEASURES_STAGE = Stage(
    name="measures",
    version=MEASURES_VERSION,
    description="per component: PGA, PGV, PGD, Arias, D5-95, PSA at the NGA-West2 periods",
    kind="item",
    params=MEASURE_PARAMS,
    upstream=lambda workflow: ("inventory",),
    columns=_measure_columns,
    tasks=_measures_tasks,
    compute=component_row,
    needs_records=True,
    check=_check,
)

ROTD50_STAGE = Stage(
    name="rotd50",
    version=ROTD50_VERSION,
    description="per pair of horizontal components: RotD50 of PGA, PGV, PGD and PSA "
    "(follows [measures])",
    kind="item",
    params={},
    upstream=lambda workflow: ("inventory",),
    columns=_rotd50_columns,
    tasks=_rotd50_tasks,
    compute=pair_row,
    needs_records=True,
    check=_check,
)


# -- processed waveforms, on request ------------------------------------------------------------


def _waveforms_key(context: Context) -> str:
    inventory = context.tables["inventory"]
    return make_key(
        "waveforms", WAVEFORMS_VERSION, _params(context), *sorted(map(str, inventory["_key"]))
    )


def _safe(name: str) -> str:
    """A file-name part: letters, digits, ``.``, ``_`` and ``-`` kept, anything else ``_``."""
    return "".join(c if c.isalnum() or c in "._-" else "_" for c in name)


def _waveforms_run(context: Context, folder: Path) -> None:
    """Each component after the ``[measures]`` processing, as SAC (acceleration, IDEP = IACC,
    in SAC's nm/s²), and ``index.csv`` (a component that cannot be read is left out and listed
    with its reason)."""
    import pandas as pd
    from obspy.core.util import AttribDict

    from stepframe.core.io import atomic_write
    from stepframe.pipeline.catalogue.measures import processed

    options = measure_options(context.workflow)
    record_options = _record_options(context)
    source = record_folder(context)
    rows = []
    for row in context.tables["inventory"].to_dict(orient="records"):
        relative = f"{row['file']}.{_safe(str(row['component']))}.sac"
        entry = {
            "file": row["file"],
            "station": row["station"],
            "component": row["component"],
            "event": row["event"],
            "waveform": "",
            "processing": "",
            "reason": "",
        }
        try:
            trace = _read_component(
                str(source / str(row["file"])),
                record_options,
                int(row["channel_index"]),
                str(row["file"]),
            )
            work = processed(trace, options)
        except (ItemFailure, InputError) as error:
            entry["reason"] = str(error)
            rows.append(entry)
            continue
        done = work.stats.stepframe.processing[len(trace.stats.stepframe.processing) :]
        entry["processing"] = ";".join(str(step["step"]) for step in done)
        target = folder / relative
        target.parent.mkdir(parents=True, exist_ok=True)
        plain = work.copy()
        del plain.stats.stepframe  # SAC has no place for it; index.csv keeps what matters
        # SAC's own unit for acceleration (idep = IACC) is nm/s²: any SAC reader, stepframe's
        # included, then knows what the samples are
        plain.data = plain.data * SAC_NM_PER_M
        plain.stats.sac = AttribDict({"idep": SAC_IACC})
        with atomic_write(target, "wb") as out:
            plain.write(out, format="SAC")
        entry["waveform"] = relative
        rows.append(entry)
    with atomic_write(folder / WAVEFORMS_INDEX) as out:
        pd.DataFrame(rows).to_csv(out, index=False, lineterminator="\n")


def _waveforms_publish(folder: Path, outputs: Path) -> list[Path]:
    """The waveforms folder replaced as a whole (a record gone from the inbox goes too)."""
    import shutil

    from stepframe.core.io import staged_folder

    outputs.mkdir(parents=True, exist_ok=True)
    with staged_folder(outputs / WAVEFORMS_FOLDER) as staging:
        shutil.copytree(folder, staging, dirs_exist_ok=True)
    return [outputs / WAVEFORMS_FOLDER / WAVEFORMS_INDEX]


WAVEFORMS_STAGE = Stage(
    name="waveforms",
    version=WAVEFORMS_VERSION,
    description="each component after the [measures] processing, as SAC (nm/s², IACC) with an "
    "index",
    kind="set",
    params={},
    upstream=lambda workflow: ("inventory",),
    set_key=_waveforms_key,
    run_set=_waveforms_run,
    publish=_waveforms_publish,
    needs_records=True,
    check=_check,
    latest_set_only=True,  # a file arriving would store the whole folder's waveforms again
)


__all__ = [
    "MEASURES_STAGE",
    "ROTD50_STAGE",
    "WAVEFORMS_STAGE",
    "component_row",
    "measure_options",
    "pair_row",
    "record_pairs",
]
