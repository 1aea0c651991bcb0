"""The dynamics job's ``ida`` stage: incremental dynamic analysis of a frame under its records.

Named in ``[outputs]`` as ``ida = true`` (with an optional ``[ida]`` table). Every component of
the inventory is run by hunt-trace-fill (:func:`stepframe.structure.ida.ida_records`:
intensities in g of PGA, scaled until overturning, refined between the last survival and the
first overturning, probed above it for resurrection); the outputs are the per-record table
(``ida.csv`` / ``ida.parquet``: first overturning, bracket, resurrections, runs, status) and
the fractiles of the overturning intensity over the records (``ida_summary.json``). The key is
the inventory's content keys, the frame and the stage's parameters, so new records, another
frame or another resolution recompute it, and nothing else does.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from stepframe.core.io import write_bytes, write_text
from stepframe.core.results import set_column_dictionary
from stepframe.core.tables import read_table, write_table
from stepframe.errors import InputError
from stepframe.pipeline.catalogue.stage import record_folder
from stepframe.pipeline.dynamics.studies import IdaOptions
from stepframe.pipeline.engine.stage import Context, Param, Stage, params_from_options
from stepframe.pipeline.engine.store import make_key, write_output_table

# 2: the command's settings and probes (one declaration with structure ida); 3: the exact
# integrator's chord-bound fast path (the same runs to rounding, recomputed rather than mixed);
# 4: a capacity below the hunt's start searched for, the probes from the traced first overturning
IDA_VERSION = 4
IDA_TABLE = "ida.csv"
IDA_SUMMARY = "ida_summary.json"

#: Column dictionary of the IDA table: name → (unit, meaning).
IDA_COLUMNS: dict[str, tuple[str, str]] = {
    "item": ("", "record file [component]"),
    "first_overturning": (
        "g",
        "lowest PGA found to overturn the frame (empty: none up to the cap)",
    ),
    "last_survival_below": ("g", "highest PGA survived below the first overturning"),
    "n_bands": ("", "separate overturning bands found (more than one: non-monotone)"),
    "resurrected": ("", "survives some PGA above one that overturned it"),
    "resurrections": ("g", "overturning -> surviving PGA pairs, ';'-separated"),
    "n_runs": ("", "simulations run for this record"),
    "status": ("", "how the trace ended (stepframe.core.results.STATUSES)"),
    "message": ("", "details of the status"),
}

#: The ``[ida]`` table: the options of ``stepframe structure ida`` over records (one
#: declaration, one default, one check: :class:`~stepframe.pipeline.dynamics.studies.IdaOptions`).
IDA_FIELDS = ("resolution_g", "max_intensity_g", "tail_s", "probe_factor", "probes")
IDA_PARAMS: dict[str, Param] = params_from_options(IdaOptions, IDA_FIELDS)


def _options(workflow: Any) -> IdaOptions:
    """The ``[ida]`` table as the command's options (an error at the key's line)."""
    try:
        return IdaOptions(**workflow.tables.get("ida", {}))
    except InputError as error:
        raise workflow.lines.error(f"[ida] {error.what}", "ida", error.key) from None


def _check(workflow: Any) -> None:
    _options(workflow)
    if workflow.records is None:
        raise workflow.lines.error("ida without a [records] table, expected one", "outputs")


def _key(context: Context) -> str:
    params = IDA_STAGE.parameters(context.workflow)
    params["frame"] = context.workflow.frame_source
    return make_key("ida", IDA_VERSION, params, *map(str, context.tables["inventory"]["_key"]))


def _run(context: Context, folder: Path) -> None:
    import pandas as pd

    from stepframe.records import read
    from stepframe.structure.ida import capacity_fractiles, ida_records, ida_table

    params = IDA_STAGE.parameters(context.workflow)
    options = _options(context.workflow)
    records = context.workflow.records
    read_options = dict(records.options) if records is not None else {}
    base = record_folder(context)
    inventory = context.tables["inventory"]
    names, motions = [], []
    for file, group in inventory.groupby("file", sort=True):
        stream = read(base / str(file), **read_options)
        for index in group["channel_index"].astype(int):
            trace = stream[index]
            names.append(f"{file} [{trace.stats.channel}]")
            motions.append((trace.data, float(trace.stats.delta)))
    settings = options.settings()
    items = ida_records(context.workflow.frame, motions, settings=settings, tail_s=options.tail_s)
    table = ida_table(items, names)
    set_column_dictionary(
        table,
        pd.DataFrame(
            [(name, unit, meaning) for name, (unit, meaning) in IDA_COLUMNS.items()],
            columns=["column", "unit", "meaning"],
        ),
    )
    write_table(table, folder / IDA_TABLE)
    summary = {
        "n_records": len(items),
        "n_overturned": int(table["first_overturning"].notna().sum()),
        "n_resurrected": int(table["resurrected"].sum()),
        "n_runs": int(table["n_runs"].sum()),
        "first_overturning_pga_g_fractiles": capacity_fractiles(items),
        "parameters": params,
    }
    write_text(folder / IDA_SUMMARY, json.dumps(summary, indent=2, allow_nan=False) + "\n")


def _publish(folder: Path, outputs: Path) -> list[Path]:
    table = read_table(folder / IDA_TABLE)
    summary = write_bytes(outputs / IDA_SUMMARY, (folder / IDA_SUMMARY).read_bytes())
    return [summary, *write_output_table(table, outputs / "ida.parquet")]


IDA_STAGE = Stage(
    name="ida",
    version=IDA_VERSION,
    description="incremental dynamic analysis (hunt-trace-fill, resurrections) per record",
    kind="set",
    params=IDA_PARAMS,
    upstream=lambda workflow: ("inventory",),
    set_key=_key,
    run_set=_run,
    publish=_publish,
    needs_records=True,
    needs_frame=True,
    check=_check,
)
