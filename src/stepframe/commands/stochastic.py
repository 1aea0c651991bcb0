"""``stepframe stochastic``: ``fit`` (one record), ``features`` (a folder, one CSV row per
component; :mod:`stepframe.pipeline.catalogue.fitted_files`) and ``amplify``
(:mod:`stepframe.pipeline.amplification.study`)."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from stepframe.commands import UserError, add_command, add_record_options
from stepframe.core.options import (
    REQUIRED,
    Once,
    add_fields,
    add_options,
    options_from,
)
from stepframe.pipeline.amplification.analysis import SITE_PARAMETERS, AmplifyOptions
from stepframe.pipeline.amplification.study import AmplifyStudy, amplify_study
from stepframe.pipeline.catalogue.fit_options import FitOptions
from stepframe.pipeline.engine.run_options import RunOptions
from stepframe.records.read_options import RecordSource
from stepframe.stochastic.methods import SPECTRUM_METHOD_NAMES

if TYPE_CHECKING:
    from stepframe.commands import Subparsers
    from stepframe.pipeline.catalogue.fitted_files import FeaturesFiles, FittedFile

#: The FitOptions fields of ``features``, in the order of its help (``fit`` takes them all).
ESTIMATION = ("frequency", "t0", "omega_max_rad_s", "window_s", "fft", "alpha_reading")

#: The analysis options of ``amplify``, after the site's and the oscillator's.
ANALYSIS = (
    "alpha_reading", "peak_intensity_m_s2", "monte_carlo", "seed", "n_steps", "f_min_hz",
    "f_max_hz", "n_frequencies",
)  # fmt: skip


def register(subparsers: Subparsers) -> None:
    """Add ``fit``, ``features`` and ``amplify`` to the ``stochastic`` group."""
    fit = add_command(subparsers, "fit", run_fit, plot="draw record, I_g(t) and the PSD")
    fit.add_argument("record", nargs="?", metavar="RECORD", help="accelerogram file (or --example)")
    add_fields(fit, FitOptions, ESTIMATION)
    add_options(
        fit,
        ("--spectrum", SPECTRUM_METHOD_NAMES, None, "evolutionary PSD drawn and written "
         "(default stft; with --plot or --out)"),
    )  # fmt: skip
    add_fields(fit, FitOptions, ("bootstrap", "seed", "corner"))
    add_options(fit, ("--out", None, "OUT.nc", "write the PSD and features (NetCDF)"))
    add_record_options(fit)
    features = add_command(subparsers, "features", run_features)
    features.add_argument("folder", nargs="?", metavar="DIR", help="folder of record files")
    add_options(
        features,
        ("--example", ("fema-p695",), None, "use the embedded example catalogue instead"),
        (("-o", "--output"), None, "OUT.csv", "CSV table", REQUIRED),
    )
    add_fields(features, RunOptions, ["jobs"])
    add_fields(features, FitOptions, ESTIMATION)
    add_record_options(features)
    parser = add_command(
        subparsers, "amplify", run_amplify, plot="draw both amplifications, 0.1-10 Hz"
    )
    site = parser.add_argument_group("site (either the parameters or --record)")
    add_fields(site, AmplifyOptions, SITE_PARAMETERS)
    add_fields(site, AmplifyOptions, ["record"], action=Once)
    add_fields(site, AmplifyOptions, ["t0"])
    oscillator = parser.add_argument_group("oscillator (either --f0-hz or --frame)")
    add_fields(oscillator, AmplifyOptions, ["f0_hz", "frame", "xi0"])
    add_fields(parser, AmplifyOptions, ANALYSIS)
    add_record_options(parser)


def run_fit(args: argparse.Namespace) -> FittedFile:
    """Fit the Beck-Papadimitriou ground-motion parameters to a record.

    Estimate I_g(t), ω_g(t), α_g(t) of a record and fit ω_p, ω_s, ω_r [rad/s], ξ_p, ξ_r of
    eqs. 6.10-6.11, with standard errors; t_max, t_dur [s] are measured from t0.

    Examples
    --------
    stepframe stochastic fit RSN8883_14383980_13849360.AT2
    stepframe stochastic fit RSN8883_14383980_13849360.AT2 --t0 p-pick --frequency ridge --json
    stepframe stochastic fit RSN8883_14383980_13849360.AT2 --spectrum wavelet \\
        --plot rec.png --out rec.nc
    stepframe stochastic fit --format text --units gal --dt-s 0.005 acc.txt --bootstrap 20
    stepframe stochastic fit RSN8883_14383980_13849360.AT2 --corner --json
    stepframe stochastic fit --example fema-p695 --component MUL009 --json
    """
    from stepframe.pipeline.catalogue.fitted_files import check_output_folder, fit_file

    options, source = options_from(args, FitOptions), options_from(args, RecordSource)
    check_output_folder(args.out)
    if args.spectrum is not None and args.plot is None and args.out is None:
        # The evolutionary PSD is only drawn (--plot) or written (--out): the fit ignores it.
        raise UserError(
            f"--spectrum {args.spectrum} without --plot or --out, expected one of them (the "
            "spectrum is drawn or written, the fit does not use it)"
        )
    return fit_file(
        source.read(args.record), options, path=args.record, file=source.name(args.record),
        spectrum_method=args.spectrum or "stft", out=args.out, spectrum=args.plot is not None,
    )  # fmt: skip


def run_features(args: argparse.Namespace) -> FeaturesFiles:
    """Features and fitted parameters of every record in a folder.

    One CSV row per component (parameters with units in the column names, max I_g,
    ω_max - ω_min, fit quality, P onset used); failures go to <OUT>.failures.csv, the column
    dictionary to <OUT>.columns.csv.

    Examples
    --------
    stepframe stochastic features records/ -o features.csv
    stepframe stochastic features --example fema-p695 -o fema_features.csv --jobs 2
    stepframe stochastic features records/ -o f.csv --format at2 --t0 p-pick --json
    """
    from stepframe.pipeline.catalogue.fitted_files import features_to_file

    return features_to_file(
        args.output, options_from(args, FitOptions), folder=args.folder,
        source=options_from(args, RecordSource), jobs=options_from(args, RunOptions).jobs,
        progress=not getattr(args, "json", False),
    )  # fmt: skip


def run_amplify(args: argparse.Namespace) -> AmplifyStudy:
    """Moving-resonance amplification: eqs. 6.18-6.19 and the response amplification.

    Spectral ratio of eq. 6.18 at f0, eq. 6.19's first and last approximations, and the
    response amplification (peak RMS with the moving frequency over the fixed oscillator and
    over the stationary RMS) by the exact covariance method. With --alpha-at-tmax paper, eqs.
    6.18-6.19 need no envelope times: without --t-max-s and --t-dur-s only they are computed
    (the response amplification is then null).

    Examples
    --------
    # the paper's site (eq. 6.19: 5.67) and an oscillator at 3.12 Hz
    stepframe stochastic amplify --fp-hz 7.43 --fs-hz 3.12 --fr-hz 1.11 --xi-p 0.096 \\
        --xi-r 0.655 --t-max-s 5 --t-dur-s 20 --f0-hz 3.12 --alpha-at-tmax paper
    # eqs. 6.18-6.19 alone: with the paper's α_g(t_max) = ω_r ξ_r they need no envelope times
    stepframe stochastic amplify --fp-hz 7.43 --fs-hz 3.12 --fr-hz 1.11 --xi-p 0.096 \\
        --xi-r 0.655 --f0-hz 3.12 --alpha-at-tmax paper
    # with the envelope, confirmed by 500 Monte Carlo motions, the figure over 0.1-10 Hz
    stepframe stochastic amplify --fp-hz 7.43 --fs-hz 3.12 --fr-hz 1.11 --xi-p 0.096 \\
        --xi-r 0.655 --t-max-s 5 --t-dur-s 20 --f0-hz 2 --monte-carlo 500 --seed 1 --plot a.png
    # parameters estimated from a record, a frame file for ω(t) = 2π/T(A), JSON output
    stepframe stochastic amplify --record RSN8883_14383980_13849360.AT2 --frame frame.toml --json
    # the site from a component of the embedded example catalogue
    stepframe stochastic amplify --example fema-p695 --component MUL009 --f0-hz 2
    """
    return amplify_study(
        options_from(args, AmplifyOptions), source=options_from(args, RecordSource),
        figure=args.plot is not None,
    )  # fmt: skip
