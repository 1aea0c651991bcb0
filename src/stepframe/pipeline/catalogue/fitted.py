"""Fitted records, the outputs of ``stepframe stochastic fit`` and ``features``.

:func:`fit_record` estimates the features of one record component and fits the
Beck-Papadimitriou parameters (:mod:`stepframe.stochastic.features`, then
:mod:`stepframe.stochastic.fit`);

:func:`fitted_dataset` puts its evolutionary PSD, measured features and fitted ω_g(t) in one
``xarray.Dataset`` (NetCDF: :func:`write_fitted`, :func:`read_fitted`); :func:`fit_table` gathers
fitted records into a table with a column dictionary. A whole catalogue's features come from the
one entry point :func:`stepframe.stochastic.catalog_features.catalog_features`;
:func:`write_features` writes its table and failure table.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING, Any

from stepframe.core.results import set_column_dictionary, write_failures
from stepframe.core.tables import read_dataset, write_dataset, write_table
from stepframe.errors import InputError
from stepframe.pipeline.catalogue.fit_options import FitOptions
from stepframe.stochastic.model import MODEL_FIELDS

if TYPE_CHECKING:
    import pandas as pd
    import xarray as xr
    from obspy import Stream, Trace

    from stepframe.stochastic.features import RecordFeatures
    from stepframe.stochastic.fit import FitResult
    from stepframe.stochastic.methods import SpectrumMethod

#: Keys of the parameter set printed by ``fit`` (plus ``<key>_stderr`` for fitted values).
FIT_KEYS = (*MODEL_FIELDS, "fit_quality")

#: Column dictionary of a fit table: column → (unit, meaning); ``<key>_stderr`` columns follow
#: their key's unit.
FIT_COLUMNS: dict[str, tuple[str, str]] = {
    "file": ("", "record file"),
    "component": ("", "channel / component name"),
    "omega_p_rad_s": ("rad/s", "P-wave dominant frequency (eq. 6.10)"),
    "omega_s_rad_s": ("rad/s", "S-wave dominant frequency, ω_g at t_max"),
    "omega_r_rad_s": ("rad/s", "surface-wave dominant frequency (late asymptote)"),
    "xi_p": ("", "bandwidth ratio at the start"),
    "xi_r": ("", "bandwidth ratio at the end"),
    "t_max_s": ("s", "time of peak intensity after t0"),
    "t_dur_s": ("s", "end of strong motion after t0"),
    "t0_s": ("s", "time origin in record time"),
    "fit_quality": ("", "weighted RMS relative misfit of ω_g(t)"),
    "omega_c_rad_s": ("rad/s", "source corner frequency (indicative), empty if not fitted"),
    "max_intensity_m_s2": ("m/s2", "max I_g"),
    "t0_source": ("", "what t0 is: p-pick (picked P onset) or start (record start)"),
    "p_onset_s": ("s", "picked P onset in record time (empty if none)"),
    "p_pick_snr": ("", "P pick confidence: RMS 2 s after it / RMS before (empty if none)"),
    "s_arrival_s": ("s", "picked S arrival in record time (empty if none)"),
    "alpha_reading": ("", "reading of eq. 6.11 (eq-6-11 or paper)"),
    "frequency_method": ("", "ω_g(t) estimator"),
    "flags": ("", "degraded results, ';'-separated"),
}


@dataclass(frozen=True)
class FittedRecord:
    """One fitted record component.

    Attributes
    ----------
    summary
        The flat result (what ``fit --json`` prints): file, component, :data:`FIT_KEYS`, their
        standard errors, max I_g, arrivals, reading, estimator, flags.
    features, fitted
        The measured features and the fit.
    options
        How it was fitted.
    """

    summary: dict[str, Any]
    features: RecordFeatures = field(repr=False)
    fitted: FitResult = field(repr=False)
    options: FitOptions = field(default_factory=FitOptions)

    def to_dict(self) -> dict[str, Any]:
        """The flat result (a copy of :attr:`summary`)."""
        return dict(self.summary)

    def describe(self) -> str:
        """The parameters with their standard errors, and flags, as text."""
        return _describe(self.summary)


def _describe(result: dict[str, Any]) -> str:
    """A fitted record as text: the parameters with their standard errors, and flags."""
    lines = [" ".join(str(result[key]) for key in ("file", "component") if result[key]) + ":"]
    keys = (*FIT_KEYS, "omega_c_rad_s") if result.get("omega_c_rad_s") is not None else FIT_KEYS
    for key in keys:
        se = result.get(f"{key}_stderr")
        boot = result.get(f"{key}_bootstrap_stderr")
        value = result[key]
        suffix = f" ± {se:.3g}" if se is not None else ""
        if boot is not None:
            suffix += f" (bootstrap ± {boot:.3g})"
        if key.endswith("_rad_s") and value is not None:
            # `stochastic amplify` takes Hz (--fp-hz ...): show both.
            suffix += f"  = {value / (2 * math.pi):.4g} Hz"
        lines.append(f"  {key:16s} {value:.4g}{suffix}")
    source = result.get("t0_source")
    if source is not None:
        origin = "picked P onset" if source == "p-pick" else "record start"
        lines.append(f"  time origin      {origin} (t0 = {result.get('t0_s', 0.0):.3g} s)")
    if result["flags"]:
        from stepframe.stochastic.flags import FLAGS, describe

        lines.append("  flags:")
        for flag, line in zip(result["flags"], describe(result["flags"]), strict=True):
            bad = " [not plausible]" if FLAGS.get(flag, (False, ""))[0] else ""
            lines.append(f"    {line}{bad}")
    return "\n".join(lines)


def fit_record(
    trace: Trace, options: FitOptions | None = None, *, file: str | PathLike[str] = ""
) -> FittedRecord:
    """Features and Beck-Papadimitriou fit of one component.

    Parameters
    ----------
    trace
        The component, an ``obspy.Trace`` in m/s².
    options
        Estimator, time origin, window [s], band limit [rad/s], bootstrap, corner.
    file
        The record file, named in errors and in the summary.

    Raises
    ------
    InputError
        The record cannot be fitted (the message names the file and component).
    """
    from stepframe.stochastic.features import record_features
    from stepframe.stochastic.fit import fit_model
    from stepframe.stochastic.spectra import evolutionary_spectrum

    opts = options or FitOptions()
    try:
        features = record_features(
            trace, frequency=opts.frequency, t0=opts.t0, window_s=opts.window_s,
            omega_max_rad_s=opts.omega_max_rad_s, fft=opts.fft,
        )  # fmt: skip
        corner_spectrum = None
        if opts.corner:
            # An 8-s window resolves 0.8 rad/s below ω_s (the 2-s default only 3.1 rad/s).
            duration_s = trace.stats.npts * trace.stats.delta
            corner_window_s = max(opts.window_s, min(8.0, duration_s))
            corner_spectrum = evolutionary_spectrum(trace, window_s=corner_window_s)
        fitted = fit_model(
            features, bootstrap=opts.bootstrap, seed=opts.seed, fit_corner=opts.corner,
            spectrum=corner_spectrum, alpha_reading=opts.alpha_reading,
        )  # fmt: skip
    except InputError as error:
        source = (trace.stats.get("stepframe") or {}).get("source_file")
        if source and error.what.startswith(str(source)):
            raise  # the message already names the file and the component
        channel = f"component {trace.stats.channel}: " if trace.stats.channel else ""
        raise InputError(f"{channel}{error.what}", file or None) from None
    data: dict[str, Any] = {"file": str(file), "component": trace.stats.channel}
    full = fitted.to_dict()
    for key in FIT_KEYS:
        data[key] = full[key]
    if opts.corner:
        data["omega_c_rad_s"] = fitted.model.omega_c_rad_s  # None: not resolved (flagged)
    for key, value in fitted.stderr.items():
        data[f"{key}_stderr"] = value
    data["max_intensity_m_s2"] = features.peak_intensity
    data["t0_source"] = features.t0_source
    data["p_onset_s"] = features.p_onset_s
    data["p_pick_snr"] = features.p_pick_snr
    data["s_arrival_s"] = features.s_arrival_s
    data["alpha_reading"] = fitted.model.alpha_reading
    data["frequency_method"] = features.frequency_method
    data["flags"] = list(fitted.flags)
    return FittedRecord(data, features, fitted, opts)


def fit_records(
    stream: Stream | Sequence[Trace],
    options: FitOptions | None = None,
    *,
    file: str | PathLike[str] = "",
) -> list[FittedRecord]:
    """:func:`fit_record` on every component of a record file."""
    return [fit_record(trace, options, file=file) for trace in stream]


def record_spectrum(
    trace: Trace, record: FittedRecord, method: SpectrumMethod = "stft"
) -> xr.DataArray:
    """The evolutionary PSD of a fitted record (the parametric one refits with its options)."""
    from stepframe.stochastic.spectra import evolutionary_spectrum

    opts = record.options
    return evolutionary_spectrum(
        trace, method=method, window_s=opts.window_s, t0=opts.t0, frequency=opts.frequency
    )


def fitted_dataset(spectrum: xr.DataArray, record: FittedRecord) -> xr.Dataset:
    """PSD (``time``, ``omega``), features (``frame_time``) and the fitted ω_g(t) in one Dataset.

    Scalars of the summary become attributes (lists joined with commas), with
    ``spectrum_method``.
    """
    import numpy as np
    import xarray as xr

    features, fitted = record.features, record.fitted
    frames = features.to_dataset().rename({"time": "frame_time"})
    dataset = xr.merge([spectrum.to_dataset(name="psd"), frames], combine_attrs="override")
    dataset.attrs = {}
    dataset["omega_g_fit"] = (
        "frame_time",
        np.asarray(fitted.model.omega_g(features.time_s)),
        {"units": "rad/s", "long_name": "fitted ω_g (eq. 6.10)"},
    )
    for key, value in record.summary.items():
        if isinstance(value, float | int | str) and not isinstance(value, bool):
            dataset.attrs[key] = value
        elif isinstance(value, list):
            dataset.attrs[key] = ",".join(str(v) for v in value)
    dataset.attrs["spectrum_method"] = str(spectrum.attrs["method"])
    return dataset


def write_fitted(dataset: xr.Dataset, path: str | PathLike[str]) -> Path:
    """Write a fitted-record dataset as NetCDF (atomically); :func:`read_fitted` reads it."""
    return write_dataset(dataset, path)


def read_fitted(path: str | PathLike[str]) -> xr.Dataset:
    """A dataset written by :func:`write_fitted`, loaded into memory."""
    return read_dataset(path, "a fitted record (NetCDF)")


def fit_table(records: Iterable[FittedRecord]) -> pd.DataFrame:
    """One row per fitted record, columns with units, column dictionary in ``attrs``."""
    import pandas as pd

    rows = []
    for record in records:
        row = {key: (math.nan if value is None else value) for key, value in record.summary.items()}
        row["flags"] = ";".join(record.summary["flags"])
        rows.append(row)
    names = list(FIT_COLUMNS)
    extra = sorted({key for row in rows for key in row} - set(names))
    table = pd.DataFrame(rows, columns=[*names, *extra])
    for name in ("omega_c_rad_s", "p_onset_s", "s_arrival_s"):
        table[name] = table[name].astype("float64")
    dictionary = [(name, unit, meaning) for name, (unit, meaning) in FIT_COLUMNS.items()]
    for name in extra:
        base = name.removesuffix("_bootstrap_stderr").removesuffix("_stderr")
        unit = FIT_COLUMNS.get(base, ("", ""))[0]
        dictionary.append((name, unit, f"standard error of {base}"))
    set_column_dictionary(table, pd.DataFrame(dictionary, columns=["column", "unit", "meaning"]))
    return table


def write_features(
    table: pd.DataFrame, failures: pd.DataFrame, output: str | PathLike[str]
) -> tuple[Path, Path]:
    """Write the features table (with ``X.columns.csv``) and its failures (``X.failures.csv``).

    Read the table back with :func:`stepframe.core.tables.read_table`.
    """
    target = Path(output)
    write_table(table, target)
    return target, write_failures(failures, target)


__all__ = [
    "FIT_COLUMNS",
    "FIT_KEYS",
    "FitOptions",
    "FittedRecord",
    "fit_record",
    "fit_records",
    "fit_table",
    "fitted_dataset",
    "read_fitted",
    "record_spectrum",
    "write_features",
    "write_fitted",
]
