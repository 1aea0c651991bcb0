"""The catalogue's stages: ``inventory`` (one item per file) and ``features`` (one per component).

``inventory`` hashes each record file (sha256 of its bytes: the key every later result hangs
from; remembered while the file is unchanged, :mod:`~stepframe.pipeline.catalogue.file_hashes`),
reads it and lists its components with their metadata. ``features`` runs the catalogue
features machinery of :mod:`stepframe.stochastic.catalog_features` on one component: the
record's ω_g(t), α_g(t), I_g(t) and the fitted Beck-Papadimitriou parameters, with the
plausibility checks. Workers read the record from its path (workers share the filesystem).

``features`` follows ``inventory`` (:attr:`~stepframe.pipeline.engine.stage.Stage.expand`): a
file's components are computed in the worker call that read it, from the record it read (a
worker keeps the last files it read, keyed by their content hash), so a run reads each file once.
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Any

from stepframe.core.paths import absolute_name, relative_name
from stepframe.errors import InputError
from stepframe.pipeline.catalogue.fit_options import ESTIMATION_FIELDS, FitOptions
from stepframe.pipeline.engine.same_content import NAME_SEPARATOR
from stepframe.pipeline.engine.stage import Context, Param, Stage, Task, params_from_options
from stepframe.pipeline.engine.store import KeyPrefix

# 2: a record made from raw counts measured after the standard processing (records.io.
# read_measured), as the commands measure it
INVENTORY_VERSION = 2
# 2: the fit's α_g reading and the example's lowest usable frequency enter the features;
# 3: each estimator's own resolution floor (column omega_floor_rad_s, the plausibility check);
# 4: t_max's envelope fit with the analytic Jacobian (the same minimum to within a millisecond:
# recomputed rather than mixed with the finite-difference fit's values in one table);
# 5: the STFT's spectral moments as one product with the trapezoid weights (equal to rounding:
# fitted parameters within a relative 2e-11 on 400 components, docs/benchmarks.md, issue 29);
# 6: a record read cut short (allow_short) flagged record_incomplete in its row; 7: raw counts
# after the standard processing (as the inventory's version 2); 8: record_clipped and
# window_long flags, t_max's envelope fitted to the frames around the motion only (a record's
# quiet coda moved it: 4.56 s, and 2.74 s with 360 s of coda appended)
FEATURES_VERSION = 8

#: Column dictionary of the inventory table: name → (unit, meaning).
INVENTORY_COLUMNS: dict[str, tuple[str, str]] = {
    "file": ("", "record file, relative to the records folder"),
    "duplicates": (
        "",
        "other files with the same bytes, '; '-separated (one item, computed once; empty: none)",
    ),
    "content_sha256": ("", "sha256 of the file's bytes (the cache key's root)"),
    "channel_index": ("", "position of the component in the file"),
    "station": ("", "station name"),
    "component": ("", "channel / component name"),
    "event": ("", "event name (empty if the file does not say)"),
    "magnitude": ("", "magnitude (empty if the file does not say)"),
    "dt_s": ("s", "sampling interval"),
    "npts": ("", "number of samples"),
    "pga_m_s2": ("m/s2", "peak absolute acceleration"),
}


class ItemFailure(Exception):
    """An item that could not be computed; the message names the step (read, features, fit)."""


def _record_options(context: Context) -> dict[str, Any]:
    records = context.workflow.records
    return dict(records.options) if records is not None else {}


def record_folder(context: Context) -> Path:
    """The folder the records are read from (the example is written into the workspace)."""
    workflow = context.workflow
    assert workflow.records is not None  # the workflow reader checked it
    if workflow.records.example is not None:
        return workflow.workspace / "examples" / workflow.records.example
    assert workflow.records.folder is not None
    return workflow.records.folder


#: What stands for the content of a file that could not be read, in its key and payload.
UNREADABLE = "unreadable"

#: Key of the records' (path, sha256) list the inventory's prepare step keeps for its tasks.
_CONTENTS = "inventory.record_contents"


def _prepare_inventory(context: Context) -> None:
    """Before a real run lists its tasks: the embedded example's files written into the
    workspace, or the records' hashes brought up to date in the workspace's cache."""
    records = context.workflow.records
    if records is not None and records.example is not None:
        from stepframe.pipeline.catalogue.example_files import write_example_files

        write_example_files(record_folder(context))
    elif records is not None:
        # kept for the task listing that follows: one listing and one hash check per run
        context.memo[_CONTENTS] = _record_contents(context, update=True)


def _record_contents(context: Context, *, update: bool = False) -> list[tuple[Path, str | OSError]]:
    """Each record file with the sha256 of its bytes (the example's hashed in memory), or the
    error that kept it from being read (no permission, gone since the listing); the folder
    listing's warnings are given by the first such call of a run."""
    workflow = context.workflow
    assert workflow.records is not None
    if workflow.records.example is not None:
        import hashlib

        from stepframe.pipeline.catalogue.example_files import example_files

        folder = record_folder(context)
        return [(folder / name, hashlib.sha256(data).hexdigest()) for name, data in example_files()]
    from stepframe.core.execution import default_jobs
    from stepframe.pipeline.catalogue.file_hashes import CACHE_NAME, readable_hashes

    paths = workflow.record_files()
    threads = context.jobs or default_jobs()
    hashes = readable_hashes(
        paths,
        workflow.workspace / CACHE_NAME,
        update=update,
        threads=threads,
        executor=context.executor,
    )
    return list(zip(paths, hashes, strict=True))


def _inventory_tasks(context: Context) -> list[Task]:
    """One task per distinct content: files with the same bytes are one item, named by the first
    (in sorted order) with the others in its ``duplicates`` column and the run's summary. A file
    that could not be read is an item of its own, keyed by its name (it has no content to key
    it by), whose reading fails with the reason: a failure of the run, listed, never the end
    of it; once readable it is keyed by its content as any other."""
    folder = record_folder(context)
    options = _record_options(context)
    names: dict[str, list[Path]] = {}
    contents = context.memo.pop(_CONTENTS, None)
    if contents is None:  # a dry run (no prepare), or the embedded example
        contents = _record_contents(context)
    tasks = []
    unreadable = []
    prefix = KeyPrefix("inventory", INVENTORY_VERSION, options)
    for path, sha in contents:
        if isinstance(sha, str):
            names.setdefault(sha, []).append(path)
            continue
        name = relative_name(path, folder)
        unreadable.append(
            Task(
                key=prefix.key(UNREADABLE, name),
                name=name,
                payload=(absolute_name(path), options, name, UNREADABLE),
                context={"file": name, "duplicates": "", "content_sha256": ""},
            )
        )
    for sha, paths in names.items():
        key = prefix.key(sha)
        first, *others = [relative_name(path, folder) for path in paths]
        tasks.append(
            Task(
                key=key,
                name=first,
                # absolute: a Dask worker's current folder is not this process's
                payload=(absolute_name(paths[0]), options, first, sha),
                context={
                    "file": first,
                    "duplicates": NAME_SEPARATOR.join(others),
                    "content_sha256": sha,
                },
                aliases=tuple(others),
            )
        )
    if unreadable:  # in the listing's order, as the others
        tasks = sorted([*tasks, *unreadable], key=lambda task: task.name)
    return tasks


#: The last files a process read: (path, record options, content sha256) → its Stream. The
#: ``features`` items of a file follow its ``inventory`` item in the same worker call, and the
#: selection's ``responses`` follow at the end of the call's group of files
#: (:data:`stepframe.pipeline.engine.chain.MAX_GROUP`): they take the records from here. A few
#: dozen records at a time, whatever the catalogue.
_LAST_READ: dict[tuple[str, str, str], Any] = {}
LAST_READ_FILES = 64


def read_record(path: str, options: dict[str, Any], sha: str) -> Any:
    """The record file at ``path`` (whose bytes hash to ``sha``) as a Stream, read once for the
    stages that follow each other on it."""
    from stepframe.records.io import read_measured

    key = (path, repr(sorted(options.items())), sha)
    stream = _LAST_READ.pop(key, None)
    if stream is None:  # raw counts after the standard processing, as every output measures
        stream = read_measured(path, **read_kwargs(options))
        while len(_LAST_READ) >= LAST_READ_FILES:
            _LAST_READ.pop(next(iter(_LAST_READ)))  # the least recently used
    _LAST_READ[key] = stream
    return stream


def read_components(payload: tuple[str, dict[str, Any], str, str]) -> list[dict[str, Any]]:
    """Inventory of one file: a row per component (worker side)."""
    import numpy as np

    path, options, name, sha = payload
    if sha == UNREADABLE:  # not read when hashed: its reason, as a read gives it now
        try:
            with open(path, "rb"):
                pass
        except OSError as error:
            reason = error.strerror or type(error).__name__
            raise ItemFailure(
                f"read: {name}: cannot read ({reason}), expected a file this run can read"
            ) from None
        raise ItemFailure(f"read: {name}: could not be read when listed, expected at the next run")
    try:
        stream = read_record(path, options, sha)
    except Exception as error:  # a reader may raise anything on a foreign file: recorded
        raise ItemFailure(f"read: {_one_line(error, path, name)}") from None
    if len(stream) == 0:
        raise ItemFailure("read: no traces in the file")
    rows = []
    for index, trace in enumerate(stream):
        info = trace.stats.get("stepframe", {})
        magnitude = info.get("magnitude")
        rows.append(
            {
                "channel_index": index,
                "station": str(trace.stats.station),
                "component": str(trace.stats.channel),
                "event": str(info.get("event") or ""),
                "magnitude": float(magnitude) if magnitude is not None else math.nan,
                "dt_s": float(trace.stats.delta),
                "npts": int(trace.stats.npts),
                "pga_m_s2": float(np.max(np.abs(trace.data))) if trace.stats.npts else math.nan,
            }
        )
    return rows


def read_kwargs(options: dict[str, Any]) -> dict[str, Any]:
    """The keyword arguments of :func:`stepframe.records.read` for a workflow's record options
    (``[records] dt_s`` is read's ``dt``)."""
    from stepframe.records.read_options import RecordReadOptions

    given = RecordReadOptions(**options).read_kwargs()
    return {name: value for name, value in given.items() if value is not None}


def _one_line(error: BaseException, path: str = "", name: str = "") -> str:
    """The error as one line; the file's absolute ``path`` written as its ``name`` in the
    records folder, so that a stored failure reads the same wherever the workspace is."""
    from stepframe.errors import InputError

    if isinstance(error, InputError):
        line = error.one_line()
    else:
        line = f"{type(error).__name__}: {error}".replace("\n", " ")
    return line.replace(path, name) if path else line


#: The ``[features]`` table: the estimation options of ``stepframe stochastic features``, with
#: their defaults, help and checks (:class:`~stepframe.pipeline.catalogue.fit_options.FitOptions`).
FEATURE_PARAMS: dict[str, Param] = params_from_options(FitOptions, ESTIMATION_FIELDS)


def _features_check(workflow: Any) -> None:
    """The ``[features]`` values, checked by building their options (file:line on error)."""
    try:
        FitOptions(**workflow.tables.get("features", {}))
    except InputError as error:
        raise workflow.lines.error(f"[features] {error.what}", "features", error.key) from None


def _lowest_usable_hz(context: Context) -> dict[str, float]:
    """File → the lowest usable frequency [Hz] its metadata states (the embedded example's)."""
    records = context.workflow.records
    if records is None or records.example is None:
        return {}
    from stepframe.pipeline.catalogue.example_files import example_name
    from stepframe.records.examples import metadata

    rows: list[dict[str, Any]] = metadata().to_dict(orient="records")  # type: ignore[assignment]
    return {example_name(row): float(row["lowest_usable_frequency_hz"]) for row in rows}


#: What a features task is made of besides its inventory row: the stage's parameters, the record
#: options, the records folder, each file's lowest usable frequency [Hz] where stated, and the
#: prefix of the stage's keys.
FeaturesArgs = tuple[dict[str, Any], dict[str, Any], str, dict[str, float], KeyPrefix]


def _features_args(context: Context) -> FeaturesArgs:
    """The :data:`FeaturesArgs` of a run (the folder absolute: a worker's current folder
    differs)."""
    params = FEATURES_STAGE.parameters(context.workflow)
    folder = str(record_folder(context).absolute())
    prefix = KeyPrefix("features", FEATURES_VERSION, params)
    return params, _record_options(context), folder, _lowest_usable_hz(context), prefix


def _feature_task(
    args: FeaturesArgs,
    inventory_key: str,
    file: str,
    duplicates: str,
    sha: str,
    row: dict[str, Any],
) -> Task:
    """The features task of one component (an inventory row of ``file``)."""
    params, options, folder, lowest, prefix = args
    index = int(row["channel_index"])
    low = lowest.get(file)
    return Task(
        key=prefix.key(inventory_key, str(index), str(low)),
        name=f"{file} [{row['component']}]",
        payload=(os.path.join(folder, file), options, index, params, low, file, sha),
        context={
            "file": file,
            "duplicates": duplicates,
            "station": row["station"],
            "component": row["component"],
        },
    )


def _features_tasks(context: Context) -> list[Task]:
    args = _features_args(context)
    inventory = context.tables["inventory"]
    # the rows as to_dict(orient="records") gives them, from whole columns: 0.05 s instead of
    # 0.7 s at 43,000 components
    columns = [str(column) for column in inventory.columns]
    values = zip(*(inventory[column].tolist() for column in columns), strict=True)
    rows = [dict(zip(columns, row, strict=True)) for row in values]
    return [
        _feature_task(
            args,
            str(row["_key"]),
            str(row["file"]),
            str(row["duplicates"]),
            str(row["content_sha256"]),
            row,
        )
        for row in rows
    ]


def expand_features(args: FeaturesArgs, inventory: Task, rows: list[dict[str, Any]]) -> list[Task]:
    """The features tasks of one inventory item, from its computed rows (worker side)."""
    file, sha = str(inventory.context["file"]), str(inventory.context["content_sha256"])
    duplicates = str(inventory.context["duplicates"])
    return [_feature_task(args, inventory.key, file, duplicates, sha, row) for row in rows]


def component_features(
    payload: tuple[str, dict[str, Any], int, dict[str, Any], float | None, str, str],
) -> list[dict[str, Any]]:
    """Features and fitted parameters of one component (worker side): one row.

    Takes the file's record (:func:`read_record`: read from its path unless this process has
    just read it), the component at its position, and calls
    :func:`stepframe.stochastic.catalog_features.component_row`.
    """
    import numpy as np

    from stepframe.stochastic.catalog_features import Options, component_row

    path, record_options, index, params, lowest_usable_hz, name, sha = payload
    try:
        trace = read_record(path, record_options, sha)[index]
    except Exception as error:  # recorded as this item's failure
        raise ItemFailure(f"read: {_one_line(error, path, name)}") from None
    options = Options(**params, record_options=tuple(sorted(record_options.items())))
    try:
        row = component_row(
            np.asarray(trace.data, dtype=np.float64),
            float(trace.stats.delta),
            options,
            lowest_usable_hz,
            incomplete=bool(trace.stats.stepframe.get("incomplete")),
        )
    except Exception as error:
        # component_row names the step that failed (features or fit) and keeps its error
        step = getattr(error, "stage", "features")
        raise ItemFailure(f"{step}: {_one_line(getattr(error, 'error', error))}") from None
    return [row]


def _features_columns() -> dict[str, tuple[str, str]]:
    from stepframe.stochastic.catalog_features import COLUMNS

    first, *rest = COLUMNS.items()  # the file, then its other names, then the features
    return dict([first, ("duplicates", INVENTORY_COLUMNS["duplicates"]), *rest])


INVENTORY_STAGE = Stage(
    name="inventory",
    version=INVENTORY_VERSION,
    description="record files: content hashes and components (no science)",
    kind="item",
    params={},
    upstream=lambda workflow: (),
    columns=lambda: INVENTORY_COLUMNS,
    tasks=_inventory_tasks,
    compute=read_components,
    needs_records=True,
    prepare=_prepare_inventory,
)

FEATURES_STAGE = Stage(
    name="features",
    version=FEATURES_VERSION,
    description="per component: ω_g(t), α_g(t), I_g(t) and the fitted B-P parameters",
    kind="item",
    params=FEATURE_PARAMS,
    upstream=lambda workflow: ("inventory",),
    columns=_features_columns,
    tasks=_features_tasks,
    compute=component_features,
    needs_records=True,
    check=_features_check,
    expand=expand_features,
    expand_args=_features_args,
)
