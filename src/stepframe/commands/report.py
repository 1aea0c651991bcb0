"""``stepframe report``: self-contained HTML reports (site amplification, record selection).

Each report is one HTML file that opens offline in any browser, with the CSV/JSON of every number
it shows in ``<stem>_files/`` beside it and its provenance (versions, command, input files with
SHA-256, parameters, date, cores). The work is :mod:`stepframe.pipeline.reports.make`; heavy
imports happen inside the ``run`` functions.
"""

from __future__ import annotations

import argparse
from typing import Any

from stepframe.commands import ALPHA_OPTION, CommandResult, add_command, add_options, positive_float

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
    add_options(
        amplification.add_argument_group("site (either the parameters or --records)"),
        ("--fp-hz", positive_float, "F", "P-wave dominant f_p [Hz]"),
        ("--fs-hz", positive_float, "F", "S-wave dominant f_s [Hz]"),
        ("--fr-hz", positive_float, "F", "surface-wave f_r [Hz]"),
        ("--xi-p", positive_float, "X", "bandwidth ratio ξ_p"),
        ("--xi-r", positive_float, "X", "bandwidth ratio ξ_r"),
        ("--t-max-s", positive_float, "T", "time of peak I_g [s]"),
        ("--t-dur-s", positive_float, "T", "strong duration [s]"),
        ("--records", None, "DIR", "a folder of the site's record files"),
        ("--t0", ("auto", "start", "p-pick"), None, "with --records: time origin, the picked P "
         "onset when reliable, else the record start (auto, the default), or one of them", "auto"),
        ("--format", None, "NAME", "with --records: file format if not sniffed"),
        ("--units", None, "UNIT", "with --records: units if the files lack them"),
        ("--site-name", None, "NAME", "named in titles"),
    )  # fmt: skip
    add_options(
        amplification.add_argument_group("frame (optional)"),
        ("--frame", None, "FRAME.toml", "frame file: band and frame-driven run"),
        ("--delta-star-m", positive_float, "D", "the frame's design displacement δ* [m] "
         "(stepframe structure design)"),
    )  # fmt: skip
    add_options(
        amplification,
        ALPHA_OPTION,
        ("--xi0", float, "X", "oscillator damping (default 0.05)", 0.05),
        ("--monte-carlo", int, "N", "synthetic motions at each of 4 Monte Carlo frequencies "
         "(default 50; 0: none)", 50),
        ("--seed", int, None, "Monte Carlo seed (default 1)", 1),
        ("--n-steps", int, "N", "time steps (default 2000)", 2000),
        ("--peak-intensity-m-s2", positive_float, "I", "peak I_g [m/s²] of the frame-driven run "
         "(default: the records' median, else 1)"),
        (("-o", "--out"), None, "OUT.html", "HTML file", "amplification_report.html"),
    )  # fmt: skip
    selection = add_command(
        sub,
        "selection",
        help="record selection report from the output folder of `stepframe select`",
        examples=SELECTION_EXAMPLES,
        run=run_selection,
    )
    selection.add_argument("outdir", metavar="OUTDIR", help="the selection output folder")
    add_options(
        selection,
        (("-o", "--out"), None, "OUT.html", "default: OUTDIR/selection_report.html"),
    )


def run_amplification(args: argparse.Namespace) -> CommandResult:
    """Build the site (parameters or records), compute and write the amplification report."""
    from stepframe.pipeline.reports.make import make_amplification_report, report_summary
    from stepframe.pipeline.site import SITE_PARAMETERS

    out = make_amplification_report(
        args.out, parameters={name: getattr(args, name) for name in SITE_PARAMETERS},
        records=args.records, t0=args.t0, record_format=args.format, units=args.units,
        site_name=args.site_name, frame=args.frame, delta_star_m=args.delta_star_m,
        alpha_reading=args.alpha_at_tmax, xi0=args.xi0, monte_carlo=args.monte_carlo,
        seed=args.seed, n_steps=args.n_steps, peak_intensity_m_s2=args.peak_intensity_m_s2,
    )  # fmt: skip
    return CommandResult(*report_summary(out))


def run_selection(args: argparse.Namespace) -> CommandResult:
    """Write the selection report of a selection output folder."""
    from stepframe.pipeline.reports.make import make_selection_report, report_summary

    return CommandResult(*report_summary(make_selection_report(args.outdir, args.out)))
