"""Fitted records to files: a record file's fit (NetCDF, figure) and a catalogue's features table.

What ``stepframe stochastic fit`` and ``stepframe stochastic features`` run: :func:`fit_file`
fits every component of a record file and, for one component, writes its PSD, features and
fitted ω_g(t) as NetCDF; :func:`features_to_file` runs the features of a folder (or the embedded
example catalogue) and writes the table, its column dictionary and its failures. Both check their
outputs before the work.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING, Any

from stepframe.core.jsonable import to_jsonable
from stepframe.errors import InputError
from stepframe.pipeline.catalogue.fitted import (
    FitOptions,
    FittedRecord,
    fit_records,
    fitted_dataset,
    record_spectrum,
    write_features,
    write_fitted,
)
from stepframe.records.read_options import RecordSource

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure
    from obspy import Stream, Trace

    from stepframe.stochastic.methods import SpectrumMethod


def check_output_folder(path: str | PathLike[str] | None) -> None:
    """Fail before any work if an output's folder does not exist."""
    if path is not None and not Path(path).resolve().parent.is_dir():
        raise InputError("output folder does not exist, expected an existing folder", path)
    if path is not None and Path(path).is_dir():  # before the work, not at the final rename
        raise InputError("output target is a directory, expected a file name", path)


@dataclass(frozen=True)
class FittedFile:
    """The fits of a record file's components, and the drawn PSD of a one-component file.

    Attributes
    ----------
    records
        One :class:`~stepframe.pipeline.catalogue.fitted.FittedRecord` per component.
    trace, spectrum
        The one component and its evolutionary PSD (None unless asked for).
    out
        The NetCDF file written (``fit_file(..., out=...)``; None when none was).
    """

    records: list[FittedRecord]
    trace: Trace | None = None
    spectrum: xr.DataArray | None = None
    out: Path | None = None

    def to_dict(self) -> list[dict[str, Any]]:
        """One object per component, whatever the file holds (docs/cli.md)."""
        return [record.to_dict() for record in self.records]

    def describe(self) -> str:
        """Each component's parameters, a blank line between components, then the NetCDF file
        written, if any (as a figure's ``plot written to``)."""
        text = "\n\n".join(record.describe() for record in self.records)
        return text if self.out is None else f"{text}\nPSD and features written to {self.out}"

    def figure(self) -> Figure:
        """The record, I_g(t) and the PSD with ω_g(t) and the fitted curve."""
        from stepframe.stochastic.plots import fit_figure

        if self.trace is None or self.spectrum is None:
            raise InputError("no spectrum computed, expected fit_file(..., spectrum=True)")
        record = self.records[0]
        return fit_figure(self.trace, self.spectrum, record.features, record.fitted)


def fit_file(
    stream: Stream,
    options: FitOptions,
    *,
    file: str,
    path: str | None = None,
    spectrum_method: SpectrumMethod = "stft",
    out: str | PathLike[str] | None = None,
    spectrum: bool = False,
) -> FittedFile:
    """Fit every component of ``stream``; with ``out`` (or ``spectrum``), its one component's PSD.

    Parameters
    ----------
    stream
        The record file's components (m/s²).
    options
        How to fit (:class:`~stepframe.pipeline.catalogue.fitted.FitOptions`).
    file
        The record's name in the results (its file, or ``example fema-p695``).
    path
        The file read, named in errors (None for an example catalogue).
    spectrum_method
        The evolutionary PSD written and drawn.
    out
        NetCDF file of the PSD, the features and the fitted ω_g(t) (one component only).
    spectrum
        Compute the PSD for a figure (one component only).
    """
    check_output_folder(out)
    wanted = spectrum or out is not None
    if wanted and len(stream) != 1:
        raise InputError(
            f"{len(stream)} components in the file, expected one for --plot/--out "
            "(choose it with --component)",
            path,
        )
    records = fit_records(stream, options, file=file)
    if not wanted:
        return FittedFile(records)
    # The parametric PSD refits with the same options: the model printed is the one drawn.
    psd = record_spectrum(stream[0], records[0], spectrum_method)
    if out is not None:
        write_fitted(fitted_dataset(psd, records[0]), out)
    return FittedFile(records, stream[0], psd, None if out is None else Path(out))


@dataclass(frozen=True)
class FeaturesFiles:
    """What :func:`features_to_file` wrote, and the counts."""

    table: Path
    columns: Path
    failures: Path
    n_components: int
    n_plausible: int
    n_failures: int

    def to_dict(self) -> dict[str, Any]:
        """Output paths, then counts (the keys of ``records catalog --json``, docs/cli.md)."""
        data: dict[str, Any] = to_jsonable(asdict(self))  # the fields in order, paths as text
        return data

    def describe(self) -> str:
        """One line: counts and where they went."""
        return (
            f"{self.n_components} components ({self.n_plausible} plausible) -> {self.table}; "
            f"{self.n_failures} failures -> {self.failures}"
        )


def features_to_file(
    output: str,
    options: FitOptions | None = None,
    *,
    folder: str | None = None,
    source: RecordSource | None = None,
    jobs: int | None = None,
    progress: bool = True,
) -> FeaturesFiles:
    """Features table of a folder or of the embedded example catalogue, written to ``output``.

    Parameters
    ----------
    output
        The CSV table; its column dictionary goes to ``<output>.columns.csv``, its failures to
        ``<output>.failures.csv``.
    options
        The estimation options (:data:`~stepframe.pipeline.catalogue.fit_options.
        ESTIMATION_FIELDS`; the fit's bootstrap and corner are not run for a catalogue).
    folder, source
        A folder of record files, or a source naming the example catalogue (exactly one); the
        source's read options are those of the folder's files.
    jobs, progress
        Worker processes, and a progress bar on stderr.
    """
    from stepframe.core.results import no_usable_record
    from stepframe.core.tables import columns_path

    source = source or RecordSource()
    if (folder is None) == (source.example is None):
        raise InputError("give a folder DIR or --example fema-p695, expected exactly one")
    if jobs is not None and jobs < 1:
        raise InputError(f"--jobs {jobs}, expected ≥ 1")
    check_output_folder(output)
    from stepframe.stochastic.catalog_features import catalog_features

    opts = options or FitOptions()
    common: dict[str, Any] = {"n_jobs": jobs, "progress": progress, **opts.catalog_kwargs()}
    if source.example is not None:
        # the example's traces carry their lowest usable frequency for the band check
        rows, failures = catalog_features(source.read(None), **common)
    else:
        assert folder is not None
        options_given = {k: v for k, v in source.read_kwargs().items() if v is not None}
        rows, failures = catalog_features(folder, record_options=options_given, **common)
    if len(rows) == 0:
        raise no_usable_record(failures, folder or source.example, output)
    table, failures_file = write_features(rows, failures, output)
    return FeaturesFiles(
        table, columns_path(table), failures_file, len(rows), int(rows["plausible"].sum()),
        len(failures),
    )  # fmt: skip


__all__ = ["FeaturesFiles", "FittedFile", "check_output_folder", "features_to_file", "fit_file"]
