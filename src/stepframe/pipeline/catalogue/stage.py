"""The catalogue's stages: ``inventory`` (one item per file) and ``features`` (one per component).

``inventory`` hashes each record file (sha256 of its bytes: the key every later result hangs
from), reads it and lists its components with their metadata. ``features`` runs the catalogue
features machinery of :mod:`stepframe.stochastic.catalog_features` on one component: the
record's ω_g(t), α_g(t), I_g(t) and the fitted Beck-Papadimitriou parameters, with the
plausibility checks. Workers read the record from its path (workers share the filesystem).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from stepframe.errors import InputError
from stepframe.pipeline.catalogue.fit_options import ESTIMATION_FIELDS, FitOptions
from stepframe.pipeline.engine.same_content import NAME_SEPARATOR
from stepframe.pipeline.engine.stage import Context, Param, Stage, Task, params_from_options
from stepframe.pipeline.engine.store import file_sha256, make_key

INVENTORY_VERSION = 1
# 2: the fit's α_g reading and the example's lowest usable frequency enter the features;
# 3: each estimator's own resolution floor (column omega_floor_rad_s, the plausibility check)
FEATURES_VERSION = 3

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


def _write_example(context: Context) -> None:
    """The embedded example's files, written into the workspace before the inventory reads them."""
    records = context.workflow.records
    if records is not None and records.example is not None:
        from stepframe.pipeline.catalogue.example_files import write_example_files

        write_example_files(record_folder(context))


def _record_contents(context: Context) -> list[tuple[Path, str]]:
    """Each record file with the sha256 of its bytes (the example's hashed in memory)."""
    workflow = context.workflow
    assert workflow.records is not None
    if workflow.records.example is not None:
        import hashlib

        from stepframe.pipeline.catalogue.example_files import example_files

        folder = record_folder(context)
        return [(folder / name, hashlib.sha256(data).hexdigest()) for name, data in example_files()]
    return [(path, file_sha256(path)) for path in workflow.record_files()]


def _inventory_tasks(context: Context) -> list[Task]:
    """One task per distinct content: files with the same bytes are one item, named by the first
    (in sorted order) with the others in its ``duplicates`` column and the run's summary."""
    folder = record_folder(context)
    options = _record_options(context)
    names: dict[str, list[Path]] = {}
    for path, sha in _record_contents(context):
        names.setdefault(sha, []).append(path)
    tasks = []
    for sha, paths in names.items():
        key = make_key("inventory", INVENTORY_VERSION, options, sha)
        first, *others = [path.relative_to(folder).as_posix() for path in paths]
        tasks.append(
            Task(
                key=key,
                name=first,
                # absolute: a Dask worker's current folder is not this process's
                payload=(str(paths[0].absolute()), options, first),
                context={
                    "file": first,
                    "duplicates": NAME_SEPARATOR.join(others),
                    "content_sha256": sha,
                },
                aliases=tuple(others),
            )
        )
    return tasks


def read_components(payload: tuple[str, dict[str, Any], str]) -> list[dict[str, Any]]:
    """Inventory of one file: a row per component (worker side)."""
    import numpy as np

    from stepframe.records import read

    path, options, name = payload
    try:
        stream = read(path, **read_kwargs(options))
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


def _features_tasks(context: Context) -> list[Task]:
    inventory = context.tables["inventory"]
    params = FEATURES_STAGE.parameters(context.workflow)
    options = _record_options(context)
    folder = record_folder(context)
    lowest = _lowest_usable_hz(context)
    tasks = []
    for row in inventory.to_dict(orient="records"):
        index = int(row["channel_index"])
        low = lowest.get(str(row["file"]))
        key = make_key("features", FEATURES_VERSION, params, str(row["_key"]), str(index), str(low))
        path = str((folder / str(row["file"])).absolute())
        tasks.append(
            Task(
                key=key,
                name=f"{row['file']} [{row['component']}]",
                payload=(path, options, index, params, low, str(row["file"])),
                context={
                    "file": row["file"],
                    "duplicates": row["duplicates"],
                    "station": row["station"],
                    "component": row["component"],
                },
            )
        )
    return tasks


def component_features(
    payload: tuple[str, dict[str, Any], int, dict[str, Any], float | None, str],
) -> list[dict[str, Any]]:
    """Features and fitted parameters of one component (worker side): one row.

    Reads the file from its path, takes the component at its position and calls
    :func:`stepframe.stochastic.catalog_features.component_row`.
    """
    import numpy as np

    from stepframe.records import read
    from stepframe.stochastic.catalog_features import Options, component_row

    path, record_options, index, params, lowest_usable_hz, name = payload
    try:
        trace = read(path, **read_kwargs(record_options))[index]
    except Exception as error:  # recorded as this item's failure
        raise ItemFailure(f"read: {_one_line(error, path, name)}") from None
    options = Options(**params, record_options=tuple(sorted(record_options.items())))
    try:
        row = component_row(
            np.asarray(trace.data, dtype=np.float64),
            float(trace.stats.delta),
            options,
            lowest_usable_hz,
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
    prepare=_write_example,
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
)
