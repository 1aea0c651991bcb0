"""``stepframe report``: self-contained HTML reports (site amplification, record selection).

Each report is one HTML file that opens offline in any browser, with the CSV/JSON of every number
it shows in ``<stem>_files/`` beside it and its provenance (versions, command, input files with
SHA-256, parameters, date, cores). The work is :mod:`stepframe.pipeline.reports.make`; heavy
imports happen inside the ``run`` functions.
"""

from __future__ import annotations

import argparse
from typing import Any

from stepframe.commands import CommandResult, add_command
from stepframe.core.options import add_fields, add_options, fields_given
from stepframe.pipeline.reports.make import AmplificationReportOptions as Options
from stepframe.pipeline.site import SITE_PARAMETERS

#: The report's options after the site's parameters, per help group.
RECORDS = ("records", "t0", "record_format", "units", "site_name")
FRAME = ("frame", "delta_star_m")
ANALYSIS = ("alpha_reading", "xi0", "monte_carlo", "seed", "n_steps", "peak_intensity_m_s2")

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
    site = amplification.add_argument_group("site (either the parameters or --records)")
    add_fields(site, Options, (*SITE_PARAMETERS, *RECORDS))
    add_fields(amplification.add_argument_group("frame (optional)"), Options, FRAME)
    add_fields(amplification, Options, ANALYSIS)
    add_options(
        amplification,
        (("-o", "--out"), None, "OUT.html", "HTML file", "amplification_report.html"),
    )
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

    out = make_amplification_report(args.out, Options(**fields_given(args, Options)))
    return CommandResult(*report_summary(out))


def run_selection(args: argparse.Namespace) -> CommandResult:
    """Write the selection report of a selection output folder."""
    from stepframe.pipeline.reports.make import make_selection_report, report_summary

    return CommandResult(*report_summary(make_selection_report(args.outdir, args.out)))
