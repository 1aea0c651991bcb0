"""Catalogues: one row per record component with metadata and intensity measures.

:func:`catalog` walks a folder tree, reads every file it can and never stops on a bad one: each
failure becomes a row of the failure table (:func:`stepframe.core.results.failures_table`: item,
stage, error type, message). :func:`write_catalog` writes the table, its column dictionary and the
failures through :func:`stepframe.core.io.atomic_write`, so a killed run leaves either the old
files or the new ones, never half a file.
"""

from __future__ import annotations

import contextlib
import warnings
from collections.abc import Iterable, Mapping
from concurrent.futures import Executor
from dataclasses import asdict, dataclass
from functools import partial
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from stepframe.core.execution import map_items
from stepframe.core.io import CSV_FLOAT_FORMAT, atomic_write, columns_path, file_sha256
from stepframe.core.jsonable import to_jsonable
from stepframe.core.results import (
    Failure,
    failures_path,
    failures_table,
    get_column_dictionary,
    no_usable_record,
    set_column_dictionary,
)
from stepframe.core.text import spreadsheet_safe
from stepframe.errors import InputError
from stepframe.records.intensity import MEASURES, trace_intensity_measures
from stepframe.records.processing import measured
from stepframe.records.spectra import psa_column
from stepframe.records.units import STANDARD_GRAVITY_M_S2

if TYPE_CHECKING:
    import pandas as pd
    from obspy import Trace

#: Periods [s] of the spectral ordinates in the table (those of the paper's Example 4 table).
CATALOG_PERIODS_S = (0.2, 1.0)
#: Damping ratio of those ordinates.
CATALOG_DAMPING = 0.05

_METADATA: dict[str, tuple[str, str]] = {
    "file": ("", "record file, as found under the catalogued folder"),
    "format": ("", "format the file was read as"),
    "event": ("", "earthquake (name or identifier) where the format gives it"),
    "station": ("", "station code or name"),
    "component": ("", "channel or component name"),
    "dt_s": ("s", "sampling interval"),
    "npts": ("", "number of samples"),
    "duration_s": ("s", "record length (npts - 1)·dt"),
    "units_in": ("", "units of the values in the file (converted to m/s² on reading)"),
    "magnitude": ("", "moment magnitude where the format gives it"),
    "repi_km": ("km", "epicentral distance where the format gives it"),
    "rrup_km": ("km", "closest distance to the rupture where the format gives it"),
    "rjb_km": ("km", "Joyner-Boore distance where the format gives it"),
    "vs30_m_s": ("m/s", "time-averaged shear-wave velocity of the top 30 m, where given"),
    "incomplete": (
        "",
        "empty for a complete record; what a record read with --allow-short lacks "
        "('3849 of 28600 samples', '1 of 3 components')",
    ),
}


def column_dictionary() -> pd.DataFrame:
    """The catalogue's columns: ``column``, ``unit``, ``meaning``."""
    import pandas as pd

    rows = [(name, unit, meaning) for name, (unit, meaning) in _METADATA.items()]
    rows += [(name, unit, meaning) for name, (unit, meaning) in MEASURES.items()]
    rows += [
        (
            psa_column(period),
            "g",
            f"pseudo-spectral acceleration at T = {period:g} s, {CATALOG_DAMPING:.0%} damping",
        )
        for period in CATALOG_PERIODS_S
    ]
    rows.append(("warnings", "", "warnings raised while reading the file, joined by '; '"))
    return pd.DataFrame(rows, columns=["column", "unit", "meaning"])


COLUMNS: list[str] = [
    *_METADATA,
    *MEASURES,
    *(psa_column(period) for period in CATALOG_PERIODS_S),
    "warnings",
]


def trace_row(trace: Trace, file: str = "", warning_text: str = "") -> dict[str, Any]:
    """The catalogue row of one record (``obspy.Trace`` in m/s²)."""
    from stepframe.records.spectra import response_spectrum

    info = trace.stats.stepframe
    dt = float(trace.stats.delta)
    row: dict[str, Any] = {
        "file": file or info.get("source_file") or "",
        "format": info.get("format"),
        "event": info.get("event"),
        "station": trace.stats.station,
        "component": trace.stats.channel,
        "dt_s": dt,
        "npts": int(trace.stats.npts),
        "duration_s": dt * (int(trace.stats.npts) - 1),
        "units_in": info.get("units_in"),
    }
    for key in ("magnitude", "repi_km", "rrup_km", "rjb_km", "vs30_m_s"):
        value = info.get(key)
        row[key] = np.nan if value is None else float(value)
    row["incomplete"] = info.get("incomplete") or ""
    trace = measured(trace)  # raw counts: every column of the same processed copy
    row.update(trace_intensity_measures(trace))
    psa = response_spectrum(trace.data, dt, CATALOG_PERIODS_S, CATALOG_DAMPING).psa_m_s2
    for period, value in zip(CATALOG_PERIODS_S, psa, strict=True):
        row[psa_column(period)] = float(value) / STANDARD_GRAVITY_M_S2
    row["warnings"] = warning_text
    return row


def intensity_table(stream: Iterable[Trace]) -> pd.DataFrame:
    """The catalogue table of records already in memory (for example the example catalogue)."""
    import pandas as pd

    table = pd.DataFrame([trace_row(trace) for trace in stream], columns=COLUMNS)
    set_column_dictionary(table, column_dictionary())
    return table


#: Files in a records folder that are not records (documentation, licences, StationXML
#: inventories, metadata tables): skipped by :func:`record_files`, not reported as failures.
NOT_RECORD_SUFFIXES = (".md", ".rst", ".pdf", ".html", ".json", ".xml", ".csv", ".toml", ".py")
NOT_RECORD_PREFIXES = ("license", "licence", "readme", "provenance", "copying", "notice")
#: Files stepframe writes beside its outputs (never records), also covered by ``.csv``/``.nc``.
_OUTPUT_SUFFIXES = (".columns.csv", ".failures.csv", ".nc", ".png", ".svg", ".parquet")


def is_record_file(name: str) -> bool:
    """False for hidden files and the non-record files of a records folder (names above)."""
    lower = name.lower()
    return not (
        lower.startswith(".")
        or lower.endswith(NOT_RECORD_SUFFIXES)
        or lower.endswith(_OUTPUT_SUFFIXES)
        or lower.startswith(NOT_RECORD_PREFIXES)
    )


def distinct_contents(files: Iterable[Path]) -> tuple[list[Path], list[tuple[Path, Path]]]:
    """The files with one file per content (the first of each, in the given order), and each
    other file with the kept file it has the same bytes as.

    A record saved twice (a download kept under a second name, a copy in a subfolder) is one
    record: read twice, it would count twice wherever records are combined or ranked (a site's
    median and its standard error, a selection's candidates). The workflow merges such files by
    their content key; this is the same rule for the commands that read files directly. Files
    are compared by SHA-256; a file that cannot be opened is kept, for its reader to report.
    """
    first: dict[str, Path] = {}
    kept: list[Path] = []
    same: list[tuple[Path, Path]] = []
    for path in files:
        try:
            key = file_sha256(path)
        except OSError:
            kept.append(path)
            continue
        if key in first:
            same.append((path, first[key]))
        else:
            first[key] = path
            kept.append(path)
    return kept, same


def copy_failures(copies: Iterable[tuple[Path, Path]]) -> list[Failure]:
    """Each copy left out by :func:`distinct_contents` as a failure row: stage ``read``, error
    type ``SameContent``, naming the kept file (what every command that reads record files lists
    in its failures, so a copy is seen, not silently dropped)."""
    return [
        Failure(str(copy), "read", "SameContent", f"the same bytes as {kept}: read once")
        for copy, kept in copies
    ]


def record_files(
    path: str | PathLike[str], *, exclude: Iterable[str | PathLike[str]] = ()
) -> list[Path]:
    """Record files under ``path`` (or ``path`` itself), recursively, in walking order.

    The folder is listed by :func:`stepframe.core.paths.walk_files`, the rule every records
    folder follows: regular files only (a FIFO or a device would block or never end, a socket
    cannot be read), hidden files and folders skipped, symbolic links followed (each real
    folder walked once: a link back up the tree, a loop, is not walked again) except into
    ``/proc``, ``/sys`` or ``/dev``, a folder there refused. Skipped too: documentation,
    licences, inventories and metadata tables beside records (:func:`is_record_file`);
    stepframe's own outputs and the paths in ``exclude`` (a catalogue written inside the folder
    it scans must not be read back as a record on the next run).

    Parameters
    ----------
    path
        A folder (walked recursively) or one file.
    exclude
        Files never listed (the outputs of the run).
    """
    from stepframe.core.paths import walk_files

    root = Path(path)
    if root.is_file():
        return [root]
    if not root.exists():
        raise InputError("no such file or folder, expected a folder of records", root)
    excluded = {Path(p).resolve() for p in exclude}
    files = [file for _, file in walk_files(root) if is_record_file(file.name)]
    if excluded:
        files = [file for file in files if file.resolve() not in excluded]
    return files


@dataclass(frozen=True)
class _ReadOptions:
    """Record options for every file of a catalogue (picklable: sent to workers)."""

    format: str | None = None
    units: str | None = None
    dt_s: float | None = None
    inventory: str | None = None
    component: str | None = None
    #: Read limits given by the user (``max_abs_g``, ``max_bytes`` of :func:`~.io.read`).
    limits: tuple[tuple[str, float], ...] = ()
    allow_short: bool = False


def _names_of(trace: Any) -> tuple[str, ...]:
    """How a warning names a component: its id, or its channel as a reader writes it."""
    channel = str(trace.stats.channel)
    return (trace.id, f"[{channel}]", f"channel {channel}", f"component {channel}")


def _warnings_of(trace: Any, stream: Any, texts: list[str]) -> str:
    """The warnings of one component: those naming it, and those naming no component of the
    file (each row repeated every component's warnings before)."""
    own = []
    for text in texts:
        named = [other for other in stream if any(n in text for n in _names_of(other))]
        if not named or any(other is trace for other in named):
            own.append(text)
    return "; ".join(own)


def _catalog_file(file: Path, options: _ReadOptions) -> tuple[list[dict[str, Any]], list[Failure]]:
    """The rows of one file's components, and the failures of components it could not measure.

    A file that cannot be read raises (the executor records it at stage ``read``).
    """
    from stepframe.records.io import read
    from stepframe.records.processing import measured_stream

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        # Raw counts: PGA and PSA columns of the same processed copy (one policy).
        stream = measured_stream(
            read(
                file,
                format=options.format,
                units=options.units,
                dt=options.dt_s,
                inventory=options.inventory,
                component=options.component,
                allow_short=options.allow_short,
                **dict(options.limits),  # type: ignore[arg-type]  # max_abs_g: float, max_bytes: int
            )
        )
    texts = [str(w.message).replace("\n", " ") for w in caught]
    rows: list[dict[str, Any]] = []
    failures: list[Failure] = []
    for trace in stream:
        try:
            rows.append(trace_row(trace, str(file), _warnings_of(trace, stream, texts)))
        except Exception as exc:  # one component must not stop the batch: record it, go on
            where = f"{file} [{trace.stats.channel}]"
            failures.append(Failure.from_exception(where, "measures", exc))
    return rows, failures


def catalog(
    path: str | PathLike[str],
    *,
    format: str | None = None,
    units: str | None = None,
    dt_s: float | None = None,
    inventory: str | PathLike[str] | None = None,
    component: str | None = None,
    jobs: int | None = 1,
    executor: Executor | None = None,
    progress: bool | str = False,
    exclude: Iterable[str | PathLike[str]] = (),
    limits: Mapping[str, float] | None = None,
    allow_short: bool = False,
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Catalogue every record under a folder: one row per component.

    Parameters
    ----------
    path
        Folder walked recursively (or a single file).
    format, units, dt_s, inventory, component
        Record options applied to every file (see :func:`stepframe.records.read`); None sniffs.
    jobs, executor
        Where the files are read (:func:`stepframe.core.execution.map_items`): by default one
        at a time in this process.
    progress
        Count, rate and ETA on stderr (see :func:`~stepframe.core.execution.map_items`).
    limits
        Read limits overriding the defaults of :func:`stepframe.records.read` (``max_abs_g``
        [g], ``max_bytes``).
    exclude
        Files not to catalogue (the run's own outputs when they are inside ``path``).
    allow_short
        Catalogue records cut short instead of recording them as failures (see
        :func:`stepframe.records.read`); their ``incomplete`` column says what they lack.

    Returns
    -------
    table : pandas.DataFrame
        Columns :data:`COLUMNS` (unit in each name); column dictionary in
        ``stepframe.core.results.get_column_dictionary(table)``.
    failures : pandas.DataFrame
        :func:`stepframe.core.results.failures_table` (``item``, ``stage`` — ``read`` or
        ``measures`` —, ``error_type``, ``message``) of every file or component that could not
        be catalogued, and of each file with the same bytes as an earlier one (catalogued once:
        error type ``SameContent``, :func:`distinct_contents`).
    """
    import pandas as pd

    # A record saved twice is one row (the rule of every reader of record files).
    files, copies = distinct_contents(record_files(path, exclude=exclude))
    options = _ReadOptions(
        format,
        units,
        dt_s,
        None if inventory is None else str(inventory),
        component,
        tuple(sorted((limits or {}).items())),
        allow_short,
    )
    outcome = map_items(
        partial(_catalog_file, options=options),
        files,
        jobs=jobs,
        executor=executor,
        stage="read",
        progress="catalog" if progress is True else progress,
        # the line counts what the failures table holds: copies and unmeasured components too
        failures_in=lambda result: len(result[1]),
        settled_failures=len(copies),
    )
    per_file: dict[int, list[Failure]] = {
        index: found for index, (_, found) in zip(outcome.indices, outcome.results, strict=True)
    }
    # Failures come in input order: they belong to the indices that gave no result.
    succeeded = set(outcome.indices)
    failed = [index for index in range(len(files)) if index not in succeeded]
    read_failures = dict(zip(failed, outcome.failures, strict=True))
    failures = copy_failures(copies) + [
        failure
        for index in range(len(files))
        for failure in ([read_failures[index]] if index in read_failures else per_file[index])
    ]
    rows = [row for found, _ in outcome.results for row in found]
    table = pd.DataFrame(rows, columns=COLUMNS)
    set_column_dictionary(table, column_dictionary())
    return table, failures_table(failures)


def output_paths(out: str | PathLike[str]) -> tuple[Path, Path, Path]:
    """``OUT.csv``, ``<stem>.columns.csv`` and ``<stem>.failures.csv`` beside it."""
    target = Path(out)
    return (
        target,
        columns_path(target),
        failures_path(target),
    )


def check_output(out: str | PathLike[str]) -> tuple[Path, Path, Path]:
    """The output paths of :func:`write_catalog`, refused before any work if they cannot be written.

    Raises
    ------
    InputError
        The folder does not exist, or one of the paths is a folder.
    """
    paths = output_paths(out)
    if not paths[0].parent.is_dir():
        raise InputError("output folder does not exist, expected an existing folder", paths[0])
    for target in paths:
        if target.is_dir():
            raise InputError("is a folder, expected a file name for the output", target)
    return paths


def write_catalog(
    table: pd.DataFrame, failures: pd.DataFrame, out: str | PathLike[str]
) -> tuple[Path, Path, Path]:
    """Write the table, its column dictionary and the failures, together.

    All three are written to temporaries beside their targets first; only when every one is
    complete are they renamed, failures and columns first and the table last, so a run killed
    while writing leaves the previous outputs untouched, and one that fails leaves no
    temporary. Files get the user's umask; text cells are spreadsheet-safe.
    """
    paths = check_output(out)
    dictionary = get_column_dictionary(table)
    frames = (table, column_dictionary() if dictionary is None else dictionary, failures)
    with contextlib.ExitStack() as stack:
        # Entered table first, so exited (renamed) last.
        for frame, target in zip(frames, paths, strict=True):
            stream = stack.enter_context(atomic_write(target))
            spreadsheet_safe(frame).to_csv(stream, index=False, float_format=CSV_FLOAT_FORMAT)
    return paths


@dataclass(frozen=True)
class CatalogFiles:
    """What :func:`catalog_to_file` wrote, and the counts."""

    table: Path
    columns: Path
    failures: Path
    n_components: int
    n_failures: int

    def to_dict(self) -> dict[str, Any]:
        """Output paths, then counts (docs/cli.md)."""
        data: dict[str, Any] = to_jsonable(asdict(self))  # the fields in order, paths as text
        return data

    def describe(self) -> str:
        """One line: counts and where they went."""
        return (
            f"{self.n_components} components catalogued in {self.table} (columns: "
            f"{self.columns}); {self.n_failures} failures in {self.failures}"
        )


def catalog_to_file(
    source: str | PathLike[str] | Iterable[Trace], out: str | PathLike[str], **options: Any
) -> CatalogFiles:
    """Catalogue a folder (:func:`catalog`) or the traces of a stream, and write the outputs.

    The outputs are checked before the work (:func:`check_output`) and, when inside the
    folder, not catalogued themselves.

    Parameters
    ----------
    source
        A folder of record files, or traces (an ``obspy.Stream``, e.g. the example catalogue).
    out
        The CSV table (:func:`write_catalog` writes its column dictionary and failures beside).
    **options
        Keyword arguments of :func:`catalog` (read options, ``progress``, ``limits``) for a
        folder.
    """
    outputs = check_output(out)
    if isinstance(source, str | PathLike):
        table, failures = catalog(source, exclude=outputs, **options)
        if len(table) == 0:  # a folder with no usable record is an error (docs/cli.md)
            raise no_usable_record(failures, source, out)
    else:
        table, failures = intensity_table(source), failures_table([])
    paths = write_catalog(table, failures, out)
    return CatalogFiles(*paths, n_components=len(table), n_failures=len(failures))
