"""``stepframe stochastic fit`` and ``stepframe stochastic features``.

``fit`` estimates the Beck-Papadimitriou parameters of one record (every component of the file),
draws the record, I_g(t) and the evolutionary PSD with ω_g(t) and the fitted curve, and writes the
PSD and features as NetCDF. ``features`` does the same for every file of a folder (or the
embedded example catalogue) and writes one CSV row per component plus a failure table.
Heavy imports happen inside the ``run`` functions.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path
from typing import Any

from stepframe.commands import (
    CommandResult,
    add_command,
    add_record_options,
    positive_float,
    read_record_file,
)
from stepframe.errors import InputError

FIT_EXAMPLES = """\
  stepframe stochastic fit RSN8883_14383980_13849360.AT2
  stepframe stochastic fit rec.AT2 --t0 p-pick --frequency ridge --json
  stepframe stochastic fit rec.AT2 --spectrum wavelet --plot rec.png --out rec.nc
  stepframe stochastic fit --format text --units g --dt-s 0.01 acc.txt --bootstrap 200
  stepframe stochastic fit rec.AT2 --corner --json
"""
FEATURES_EXAMPLES = """\
  stepframe stochastic features records/ -o features.csv
  stepframe stochastic features --example fema-p695 -o fema_features.csv --jobs 2
  stepframe stochastic features records/ -o f.csv --format at2 --t0 p-pick --json
"""

#: Keys of the parameter set printed by ``fit`` (plus ``<key>_stderr`` for fitted values).
FIT_KEYS = (
    "omega_p_rad_s",
    "omega_s_rad_s",
    "omega_r_rad_s",
    "xi_p",
    "xi_r",
    "t_max_s",
    "t_dur_s",
    "t0_s",
    "fit_quality",
)


def register(subparsers: Any) -> None:
    """Add ``fit`` and ``features`` to the ``stochastic`` group."""
    fit = add_command(
        subparsers,
        "fit",
        help="fit the Beck-Papadimitriou ground-motion parameters to a record",
        description=(
            "Estimate I_g(t), ω_g(t), α_g(t) of a record and fit ω_p, ω_s, ω_r [rad/s], ξ_p, ξ_r "
            "of eqs. 6.10-6.11, with standard errors; t_max, t_dur [s] are measured from t0."
        ),
        examples=FIT_EXAMPLES,
        run=run_fit,
    )
    fit.add_argument("record", metavar="RECORD", help="accelerogram file")
    _add_estimation_options(fit)
    fit.add_argument(
        "--spectrum",
        choices=("stft", "wavelet", "parametric"),
        default="stft",
        help="evolutionary PSD drawn and written (default stft)",
    )
    fit.add_argument("--bootstrap", type=int, default=0, metavar="N", help="bootstrap refits")
    fit.add_argument("--seed", type=int, default=None, help="seed of the bootstrap")
    fit.add_argument(
        "--corner",
        action="store_true",
        help="also estimate the source corner ω_c [rad/s] (indicative: biased 40-50 %% low)",
    )
    fit.add_argument("--plot", metavar="OUT.png", help="draw record, I_g(t) and the PSD")
    fit.add_argument("--out", metavar="OUT.nc", help="write the PSD and features (NetCDF)")
    add_record_options(fit)

    features = add_command(
        subparsers,
        "features",
        help="features and fitted parameters of every record in a folder",
        description=(
            "One CSV row per component (parameters with units in the column names, max I_g, "
            "ω_max - ω_min, fit quality, P onset used); failures go to <OUT>_failures.csv."
        ),
        examples=FEATURES_EXAMPLES,
        run=run_features,
    )
    features.add_argument("folder", nargs="?", metavar="DIR", help="folder of record files")
    features.add_argument(
        "--example", choices=("fema-p695",), help="use the embedded example catalogue instead"
    )
    features.add_argument("-o", "--output", required=True, metavar="OUT.csv", help="CSV table")
    features.add_argument("--jobs", type=int, default=None, metavar="N", help="processes")
    _add_estimation_options(features)
    add_record_options(features)


def _add_estimation_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--frequency",
        choices=("zero-crossing", "ridge", "moment", "wavelet-ridge"),
        default="zero-crossing",
        help="ω_g(t) estimator, fast to dear (default zero-crossing)",
    )
    parser.add_argument(
        "--t0",
        choices=("start", "p-pick"),
        default="start",
        help="time origin of eqs. 6.10-6.11: record start (default) or picked P onset",
    )
    parser.add_argument(
        "--omega-max-rad-s",
        type=positive_float,
        default=None,
        metavar="W",
        help="highest frequency of interest [rad/s]: error if above the record's Nyquist",
    )
    parser.add_argument(
        "--window-s",
        type=positive_float,
        default=2.0,
        metavar="S",
        help="STFT window and smoothing length [s] (default 2)",
    )


def _check_output(path: str | None) -> None:
    """Fail before any work if an output's folder does not exist."""
    if path is not None and not Path(path).resolve().parent.is_dir():
        raise InputError("output folder does not exist, expected an existing folder", path)


def _atomic_path(target: Path) -> Path:
    """A temporary name beside ``target`` with the same suffix (formats follow the suffix)."""
    return target.with_name(f".{target.stem}.{os.getpid()}.tmp{target.suffix}")


def run_fit(args: argparse.Namespace) -> CommandResult:
    """Fit every component of the record file."""
    from stepframe.stochastic.features import record_features
    from stepframe.stochastic.fit import fit_model
    from stepframe.stochastic.spectra import evolutionary_spectrum

    if args.bootstrap < 0:
        raise InputError(f"--bootstrap {args.bootstrap}, expected an integer ≥ 0")
    _check_output(args.plot)
    _check_output(args.out)
    stream = read_record_file(args.record, args)
    if (args.plot or args.out) and len(stream) != 1:
        raise InputError(
            f"{len(stream)} components in the file, expected one for --plot/--out "
            "(choose it with --component)",
            args.record,
        )
    results = []
    for trace in stream:
        try:
            features = record_features(
                trace,
                frequency=args.frequency,
                t0=args.t0,
                window_s=args.window_s,
                omega_max_rad_s=args.omega_max_rad_s,
            )
            corner_spectrum = None
            if args.corner:
                # An 8-s window resolves 0.8 rad/s below ω_s (the 2-s default only 3.1 rad/s).
                duration_s = trace.stats.npts * trace.stats.delta
                corner_window_s = max(args.window_s, min(8.0, duration_s))
                corner_spectrum = evolutionary_spectrum(trace, window_s=corner_window_s)
            fitted = fit_model(
                features,
                bootstrap=args.bootstrap,
                seed=args.seed,
                fit_corner=args.corner,
                spectrum=corner_spectrum,
            )
        except InputError as error:
            source = (trace.stats.get("stepframe") or {}).get("source_file")
            if source and error.what.startswith(str(source)):
                raise  # the message already names the file and the component
            channel = f"component {trace.stats.channel}: " if trace.stats.channel else ""
            raise InputError(f"{channel}{error.what}", args.record) from None
        data: dict[str, Any] = {"file": args.record, "component": trace.stats.channel}
        full = fitted.to_dict()
        for key in FIT_KEYS:
            data[key] = full[key]
        if args.corner:
            data["omega_c_rad_s"] = fitted.model.omega_c_rad_s  # None: not resolved (flagged)
        for key, value in fitted.stderr.items():
            data[f"{key}_stderr"] = value
        data["max_intensity_m_s2"] = features.peak_intensity
        data["p_onset_s"] = features.p_onset_s
        data["s_arrival_s"] = features.s_arrival_s
        data["alpha_reading"] = fitted.model.alpha_reading
        data["frequency_method"] = args.frequency
        data["flags"] = list(fitted.flags)
        results.append(data)
        if args.plot or args.out:
            # The parametric PSD refits with the same options: the model printed is the one drawn.
            spectrum = evolutionary_spectrum(
                trace,
                method=args.spectrum,
                window_s=args.window_s,
                t0=args.t0,
                frequency=args.frequency,
            )
            if args.out:
                _write_netcdf(Path(args.out), spectrum, features, fitted, data)
            if args.plot:
                _plot(Path(args.plot), trace, spectrum, features, fitted)
    text = "\n\n".join(_describe(r) for r in results)
    return CommandResult(data=results[0] if len(results) == 1 else results, text=text)


def _describe(result: dict[str, Any]) -> str:
    lines = [f"{result['file']} {result['component']}:"]
    keys = (*FIT_KEYS, "omega_c_rad_s") if result.get("omega_c_rad_s") is not None else FIT_KEYS
    for key in keys:
        se = result.get(f"{key}_stderr")
        value = result[key]
        suffix = f" ± {se:.3g}" if se is not None else ""
        lines.append(f"  {key:16s} {value:.4g}{suffix}")
    if result["flags"]:
        lines.append(f"  flags: {', '.join(result['flags'])}")
    return "\n".join(lines)


def _write_netcdf(
    target: Path, spectrum: Any, features: Any, fitted: Any, summary: dict[str, Any]
) -> None:
    import numpy as np
    import xarray as xr

    frames = features.to_dataset().rename({"time": "frame_time"})
    dataset = xr.merge([spectrum.to_dataset(name="psd"), frames], combine_attrs="override")
    dataset.attrs = {}
    dataset["omega_g_fit"] = (
        "frame_time",
        np.asarray(fitted.model.omega_g(features.time_s)),
        {"units": "rad/s", "long_name": "fitted ω_g (eq. 6.10)"},
    )
    for key, value in summary.items():
        if isinstance(value, float | int | str) and not isinstance(value, bool):
            dataset.attrs[key] = value
        elif isinstance(value, list):
            dataset.attrs[key] = ",".join(str(v) for v in value)
    dataset.attrs["spectrum_method"] = str(spectrum.attrs["method"])
    tmp = _atomic_path(target)
    try:
        dataset.to_netcdf(tmp, engine="h5netcdf")
        os.replace(tmp, target)
    finally:
        tmp.unlink(missing_ok=True)


def _plot(target: Path, trace: Any, spectrum: Any, features: Any, fitted: Any) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    time = np.arange(trace.stats.npts) * trace.stats.delta
    fig, axes = plt.subplots(3, 1, figsize=(8, 9), sharex=True, constrained_layout=True)
    axes[0].plot(time, trace.data, lw=0.5, color="k")
    axes[0].set_ylabel("acceleration [m/s²]")
    axes[0].set_title(f"{trace.stats.station} {trace.stats.channel}")
    axes[1].plot(features.time_s, features.intensity, color="C0")
    axes[1].set_ylabel("I_g(t) [m/s²]")
    for ax in axes[:2]:
        ax.axvline(features.t0_s, color="0.5", ls=":", lw=1)
        ax.axvline(features.t0_s + features.t_max_s, color="C3", ls="--", lw=1)
    omega = spectrum["omega"].values
    shown = omega <= min(float(omega.max()), 4 * fitted.model.omega_p_rad_s)
    values = np.log10(np.maximum(spectrum.values[:, shown].T, 1e-30))
    top = float(values.max())
    mesh = axes[2].pcolormesh(
        spectrum["time"].values, omega[shown], values, shading="auto", vmin=top - 4, vmax=top
    )
    fig.colorbar(mesh, ax=axes[2], label="log10 S [(m/s²)²·s/rad]")
    axes[2].plot(features.time_s, features.omega_g_rad_s, color="w", lw=1, label="ω_g measured")
    axes[2].plot(
        features.time_s,
        fitted.model.omega_g(features.time_s),
        color="C1",
        lw=2,
        label="ω_g fitted (eq. 6.10)",
    )
    axes[2].set_ylabel("ω [rad/s]")
    axes[2].set_xlabel("time from record start [s]")
    axes[2].legend(loc="upper right")
    tmp = _atomic_path(target)
    try:
        fig.savefig(tmp, dpi=110, format=target.suffix.lstrip(".") or "png")
        os.replace(tmp, target)
    finally:
        plt.close(fig)
        tmp.unlink(missing_ok=True)


def run_features(args: argparse.Namespace) -> CommandResult:
    """Features table of a folder (or the example catalogue)."""
    from stepframe.stochastic.catalog_features import catalog_features

    if (args.folder is None) == (args.example is None):
        raise InputError("give a folder DIR or --example fema-p695, expected exactly one")
    if args.jobs is not None and args.jobs < 1:
        raise InputError(f"--jobs {args.jobs}, expected ≥ 1")
    _check_output(args.output)
    output = Path(args.output)
    failures_path = output.with_name(f"{output.stem}_failures.csv")
    options = {
        key: value
        for key, value in {
            "format": args.format,
            "units": args.units,
            "dt": args.dt_s,
            "inventory": args.inventory,
            "component": args.component,
        }.items()
        if value is not None
    }
    common = {
        "n_jobs": args.jobs,
        "progress": True,
        "frequency": args.frequency,
        "t0": args.t0,
        "window_s": args.window_s,
        "omega_max_rad_s": args.omega_max_rad_s,
    }
    if args.example:
        from stepframe.records.examples import fema_p695

        stream, table = fema_p695()
        rows, failures = catalog_features(
            stream, lowest_usable_hz=list(table["lowest_usable_frequency_hz"]), **common
        )
    else:
        rows, failures = catalog_features(args.folder, record_options=options, **common)
    for target, frame in ((output, rows), (failures_path, failures)):
        tmp = _atomic_path(target)
        try:
            frame.to_csv(tmp, index=False)
            os.replace(tmp, target)
        finally:
            tmp.unlink(missing_ok=True)
    summary = {
        "components": len(rows),
        "plausible": int(rows["plausible"].sum()) if len(rows) else 0,
        "failures": len(failures),
        "output": str(output),
        "failures_output": str(failures_path),
    }
    text = (
        f"{summary['components']} components ({summary['plausible']} plausible) -> {output}; "
        f"{summary['failures']} failures -> {failures_path}"
    )
    return CommandResult(data=summary, text=text)
