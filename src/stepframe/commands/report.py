"""``stepframe report``: self-contained HTML reports (site amplification, record selection).

Each report is one HTML file that opens offline in any browser, with the CSV/JSON of every number
it shows in ``<stem>_files/`` beside it and its provenance (versions, command, input files with
SHA-256, parameters, date, cores). Heavy imports happen inside the ``run`` functions.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import Any

from stepframe.commands import CommandResult, UserError, add_command, positive_float
from stepframe.errors import InputError

HELP = "self-contained HTML reports: site amplification, record selection"

AMPLIFICATION_EXAMPLES = """\
  # the paper's site from its parameters, with the Example 4 frame and a design displacement
  stepframe structure frame-template > frame.toml
  stepframe report amplification --fp-hz 7.43 --fs-hz 3.12 --fr-hz 1.11 --xi-p 0.096 \\
      --xi-r 0.655 --t-max-s 5 --t-dur-s 20 --alpha-at-tmax paper \\
      --frame frame.toml --delta-star-m 0.25 -o paper_site.html
  # a site from a folder of its records (every component fitted, usable fits combined)
  stepframe report amplification --records records/ --site-name "RSN 8883" -o x.html
"""

SELECTION_EXAMPLES = """\
  # the output folder of stepframe select, or stepframe-demo/ once stepframe demo has run
  stepframe report selection stepframe-demo/           writes stepframe-demo/selection_report.html
  stepframe report selection stepframe-demo/ -o sel.html --json
"""

SITE_OPTIONS = ("fp_hz", "fs_hz", "fr_hz", "xi_p", "xi_r", "t_max_s", "t_dur_s")


def register(subparsers: Any) -> None:
    """Add the ``report`` group and its two commands to the top-level commands."""
    group = subparsers.add_parser(
        "report", help=HELP, description=HELP, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    sub = group.add_subparsers(dest="subcommand", metavar="SUBCOMMAND")
    group.set_defaults(_group_parser=group)
    amplification = add_command(
        sub,
        "amplification",
        help="site amplification report (eqs. 6.18-6.19, response amplification, frame)",
        examples=AMPLIFICATION_EXAMPLES,
        run=run_amplification,
    )
    site = amplification.add_argument_group("site (either the parameters or --records)")
    site.add_argument("--fp-hz", type=positive_float, metavar="F", help="P-wave dominant f_p [Hz]")
    site.add_argument("--fs-hz", type=positive_float, metavar="F", help="S-wave dominant f_s [Hz]")
    site.add_argument("--fr-hz", type=positive_float, metavar="F", help="surface-wave f_r [Hz]")
    site.add_argument("--xi-p", type=positive_float, metavar="X", help="bandwidth ratio ξ_p")
    site.add_argument("--xi-r", type=positive_float, metavar="X", help="bandwidth ratio ξ_r")
    site.add_argument("--t-max-s", type=positive_float, metavar="T", help="time of peak I_g [s]")
    site.add_argument("--t-dur-s", type=positive_float, metavar="T", help="strong duration [s]")
    site.add_argument("--records", metavar="DIR", help="a folder of the site's record files")
    site.add_argument(
        "--t0",
        choices=("auto", "start", "p-pick"),
        default="auto",
        help="with --records: time origin, the picked P onset when reliable, else the record "
        "start (auto, the default), or one of them",
    )
    site.add_argument("--format", metavar="NAME", help="with --records: file format if not sniffed")
    site.add_argument(
        "--units", metavar="UNIT", help="with --records: units if the files lack them"
    )
    site.add_argument("--site-name", default=None, metavar="NAME", help="named in titles")
    frame = amplification.add_argument_group("frame (optional)")
    frame.add_argument(
        "--frame", metavar="FRAME.toml", help="frame file: band and frame-driven run"
    )
    frame.add_argument(
        "--delta-star-m",
        type=positive_float,
        metavar="D",
        help="the frame's design displacement δ* [m] (stepframe structure design)",
    )
    amplification.add_argument(
        "--alpha-at-tmax",
        choices=("eq-6-11", "paper"),
        default="eq-6-11",
        help="α_g ramp ends at t_dur (eq. 6.11 as printed, default) or at t_max (the paper)",
    )
    amplification.add_argument(
        "--xi0", type=float, default=0.05, metavar="X", help="oscillator damping (default 0.05)"
    )
    amplification.add_argument(
        "--monte-carlo",
        type=int,
        default=50,
        metavar="N",
        help="synthetic motions at each of 4 Monte Carlo frequencies (default 50; 0: none)",
    )
    amplification.add_argument("--seed", type=int, default=1, help="Monte Carlo seed (default 1)")
    amplification.add_argument(
        "--n-steps", type=int, default=2000, metavar="N", help="time steps (default 2000)"
    )
    amplification.add_argument(
        "--peak-intensity-m-s2",
        type=positive_float,
        default=None,
        metavar="I",
        help="peak I_g [m/s²] of the frame-driven run (default: the records' median, else 1)",
    )
    amplification.add_argument(
        "-o", "--out", default="amplification_report.html", metavar="OUT.html", help="HTML file"
    )
    selection = add_command(
        sub,
        "selection",
        help="record selection report from the output folder of `stepframe select`",
        examples=SELECTION_EXAMPLES,
        run=run_selection,
    )
    selection.add_argument("outdir", metavar="OUTDIR", help="the selection output folder")
    selection.add_argument(
        "-o",
        "--out",
        default=None,
        metavar="OUT.html",
        help="default: OUTDIR/selection_report.html",
    )


def _parameters(args: argparse.Namespace, names: tuple[str, ...]) -> dict[str, Any]:
    return {name: getattr(args, name) for name in names if getattr(args, name, None) is not None}


def _command(words: list[str], parameters: dict[str, Any]) -> str:
    """The command line that reproduces the report (options as parsed, defaults included)."""
    import shlex

    for name, value in parameters.items():
        words += [f"--{name.replace('_', '-')}", str(value)]
    return shlex.join(words)


def run_amplification(args: argparse.Namespace) -> CommandResult:
    """Build the site (parameters or records), compute and write the amplification report."""
    from stepframe.pipeline.reports.amplification import (
        AmplificationOptions,
        write_amplification_report,
    )
    from stepframe.pipeline.reports.provenance import collect_provenance
    from stepframe.stochastic.model import GroundMotionModel

    given = [name for name in SITE_OPTIONS if getattr(args, name) is not None]
    site: Any
    inputs: list[str] = []
    if args.records is not None:
        if given:
            raise UserError(
                f"--records with --{given[0].replace('_', '-')}, expected either the site "
                "parameters or --records"
            )
        from stepframe.pipeline.reports.site import site_from_records

        site = site_from_records(
            args.records,
            alpha_reading=args.alpha_at_tmax,
            t0=args.t0,
            record_format=args.format,
            units=args.units,
        )
        inputs.append(args.records)
        name = args.site_name or Path(args.records).resolve().name
    else:
        missing = [n for n in SITE_OPTIONS if getattr(args, n) is None]
        if missing:
            raise InputError(
                f"missing --{missing[0].replace('_', '-')}, expected all of "
                + ", ".join("--" + n.replace("_", "-") for n in SITE_OPTIONS)
                + " or --records DIR"
            )
        site = GroundMotionModel.from_hz(
            args.fp_hz,
            args.fs_hz,
            args.fr_hz,
            args.xi_p,
            args.xi_r,
            t_max_s=args.t_max_s,
            t_dur_s=args.t_dur_s,
            alpha_reading=args.alpha_at_tmax,
        )
        name = args.site_name or "site"
    if not (math.isfinite(args.xi0) and 0 < args.xi0 < 1):
        raise InputError(f"--xi0 {args.xi0}, expected a damping fraction 0 < ξ0 < 1 (e.g. 0.05)")
    if args.monte_carlo < 0 or args.monte_carlo == 1:
        raise InputError(f"--monte-carlo {args.monte_carlo}, expected 0 (none) or N ≥ 2")
    if args.n_steps < 100:
        raise InputError(f"--n-steps {args.n_steps}, expected at least 100")
    frame = None
    if args.frame is not None:
        from stepframe.structure.frame_file import read_frame_file

        frame = read_frame_file(args.frame)
        inputs.append(args.frame)
    elif args.delta_star_m is not None:
        raise InputError("--delta-star-m without --frame, expected --frame FRAME.toml with it")
    options = AmplificationOptions(
        site_name=name,
        xi0=args.xi0,
        monte_carlo=args.monte_carlo,
        seed=args.seed,
        n_steps=args.n_steps,
        peak_intensity_m_s2=args.peak_intensity_m_s2,
        delta_star_m=args.delta_star_m,
        t0=args.t0,
    )
    parameters = _parameters(
        args,
        (
            *SITE_OPTIONS,
            "records",
            "t0",
            "frame",
            "delta_star_m",
            "alpha_at_tmax",
            "xi0",
            "monte_carlo",
            "seed",
            "n_steps",
            "peak_intensity_m_s2",
        ),
    )
    command = _command(["stepframe", "report", "amplification"], parameters | {"out": args.out})
    provenance = collect_provenance(command, inputs=inputs, parameters=parameters)
    out = write_amplification_report(
        site, args.out, frame=frame, options=options, provenance=provenance
    )
    return _written(out)


def run_selection(args: argparse.Namespace) -> CommandResult:
    """Write the selection report of a selection output folder."""
    from stepframe.pipeline.reports.provenance import collect_provenance
    from stepframe.pipeline.reports.selection import write_selection_report
    from stepframe.pipeline.reports.selection_folder import read_selection_folder

    outputs = read_selection_folder(args.outdir)  # checks the folder before anything is hashed
    words = ["stepframe", "report", "selection", args.outdir]
    command = _command(words, {} if args.out is None else {"out": args.out})
    provenance = collect_provenance(
        command, inputs=outputs.files, parameters={"outdir": args.outdir}
    )
    out = write_selection_report(args.outdir, args.out, provenance=provenance)
    return _written(out)


def _written(out: Path) -> CommandResult:
    from stepframe.pipeline.reports.document import data_folder_of

    folder = data_folder_of(out)
    size = out.stat().st_size
    data = {"report": str(out), "data_folder": str(folder), "size_bytes": size}
    return CommandResult(data, f"report: {out} ({size / 1e3:.0f} kB); its numbers: {folder}/")
