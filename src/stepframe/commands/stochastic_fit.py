"""``stepframe stochastic fit`` and ``stepframe stochastic features``.

``fit`` estimates the Beck-Papadimitriou parameters of one record (every component of the file),
draws the record, I_g(t) and the evolutionary PSD with ω_g(t) and the fitted curve, and writes the
PSD and features as NetCDF. ``features`` does the same for every file of a folder (or the
embedded example catalogue) and writes one CSV row per component plus a failure table. The work
is done by :mod:`stepframe.pipeline.fitted_files`; heavy imports happen inside the ``run``
functions.
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from stepframe.commands import (
    CommandResult,
    add_command,
    add_record_options,
    check_plot,
    read_record_file,
    record_options,
)
from stepframe.core.options import REQUIRED, add_fields, add_options, fields_given
from stepframe.pipeline.fit_options import FitOptions
from stepframe.stochastic.methods import SPECTRUM_METHOD_NAMES

if TYPE_CHECKING:
    from stepframe.commands import Subparsers

FIT_EXAMPLES = """\
  stepframe stochastic fit RSN8883_14383980_13849360.AT2
  stepframe stochastic fit RSN8883_14383980_13849360.AT2 --t0 p-pick --frequency ridge --json
  stepframe stochastic fit RSN8883_14383980_13849360.AT2 --spectrum wavelet \\
      --plot rec.png --out rec.nc
  stepframe stochastic fit --format text --units gal --dt-s 0.005 acc.txt --bootstrap 20
  stepframe stochastic fit RSN8883_14383980_13849360.AT2 --corner --json
  stepframe stochastic fit --example fema-p695 --component MUL009 --json
"""
FEATURES_EXAMPLES = """\
  stepframe stochastic features records/ -o features.csv
  stepframe stochastic features --example fema-p695 -o fema_features.csv --jobs 2
  stepframe stochastic features records/ -o f.csv --format at2 --t0 p-pick --json
"""


#: The FitOptions fields of ``features``, in the order of its help (``fit`` takes them all).
ESTIMATION = ("frequency", "t0", "omega_max_rad_s", "window_s")


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
    fit.add_argument("record", nargs="?", metavar="RECORD", help="accelerogram file (or --example)")
    add_fields(fit, FitOptions, ESTIMATION)
    add_options(
        fit,
        ("--spectrum", SPECTRUM_METHOD_NAMES, None, "evolutionary PSD drawn and written "
         "(default stft)", "stft"),
    )  # fmt: skip
    add_fields(fit, FitOptions, ("bootstrap", "seed", "corner"))
    add_options(
        fit,
        ("--plot", None, "OUT.png", "draw record, I_g(t) and the PSD"),
        ("--out", None, "OUT.nc", "write the PSD and features (NetCDF)"),
    )
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
    add_options(
        features,
        ("--example", ("fema-p695",), None, "use the embedded example catalogue instead"),
        (("-o", "--output"), None, "OUT.csv", "CSV table", REQUIRED),
        ("--jobs", int, "N", "processes"),
    )
    add_fields(features, FitOptions, ESTIMATION)
    add_record_options(features)


def run_fit(args: argparse.Namespace) -> CommandResult:
    """Fit every component of the record file."""
    from stepframe.pipeline.fitted_files import check_output_folder, fit_file

    options = FitOptions(**fields_given(args, FitOptions))
    check_plot(args.plot)
    check_output_folder(args.out)
    fitted = fit_file(
        read_record_file(args.record, args), options, path=args.record,
        file=args.record or f"example {args.example}", spectrum_method=args.spectrum,
        out=args.out, spectrum=args.plot is not None,
    )  # fmt: skip
    if args.plot:
        from stepframe.pipeline.figures import save_figure

        save_figure(fitted.figure(), args.plot)
    return CommandResult(data=fitted.to_dict(), text=fitted.describe())


def run_features(args: argparse.Namespace) -> CommandResult:
    """Features table of a folder (or the example catalogue)."""
    from stepframe.pipeline.fitted_files import features_to_file

    written = features_to_file(
        args.output, FitOptions(**fields_given(args, ESTIMATION)), folder=args.folder,
        example=args.example, record_options=record_options(args), jobs=args.jobs,
    )  # fmt: skip
    return CommandResult(data=written.to_dict(), text=written.describe())
