"""``stepframe report amplification`` and ``selection``: self-contained HTML reports, each one
file that opens offline with the CSV/JSON of its numbers and its provenance beside it
(:func:`stepframe.pipeline.amplification.report.make_amplification_report`,
:func:`stepframe.pipeline.selection.report.make_selection_report`)."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from stepframe.commands import CommandResult, add_command
from stepframe.core.options import add_fields, add_options, options_from
from stepframe.pipeline.amplification.analysis import SITE_PARAMETERS
from stepframe.pipeline.amplification.analysis import AmplificationReportOptions as Options
from stepframe.pipeline.engine.run_options import RunOptions

if TYPE_CHECKING:
    from stepframe.commands import Subparsers

#: The report's options after the site's parameters, per help group.
RECORDS = ("records", "t0", "record_format", "units", "site_name")
FRAME = ("frame", "delta_star_m")
ANALYSIS = (
    "alpha_reading", "xi0", "monte_carlo", "seed", "n_steps", "peak_intensity_m_s2",
    "f_min_hz", "f_max_hz", "n_frequencies", "grid_only", "band", "band_samples",
)  # fmt: skip


def register(subparsers: Subparsers) -> None:
    """Add ``amplification`` and ``selection`` to the ``report`` group."""
    amplification = add_command(subparsers, "amplification", run_amplification)
    site = amplification.add_argument_group("site (either the parameters or --records)")
    add_fields(site, Options, (*SITE_PARAMETERS, *RECORDS))
    add_fields(amplification.add_argument_group("frame (optional)"), Options, FRAME)
    add_fields(amplification, Options, ANALYSIS)
    add_fields(amplification, RunOptions, ["jobs"])
    add_options(
        amplification, (("-o", "--out"), None, "OUT.html", "HTML file", "amplification_report.html")
    )
    selection = add_command(subparsers, "selection", run_selection)
    selection.add_argument("outdir", metavar="OUTDIR", help="the selection output folder")
    add_options(
        selection, (("-o", "--out"), None, "OUT.html", "default: OUTDIR/selection_report.html")
    )


def run_amplification(args: argparse.Namespace) -> CommandResult:
    """Site amplification report (eqs. 6.18-6.19, response amplification, frame).

    Examples
    --------
    # the paper's site from its parameters, with the Example 4 frame and a design displacement
    stepframe structure frame-template > frame.toml
    stepframe report amplification --fp-hz 7.43 --fs-hz 3.12 --fr-hz 1.11 --xi-p 0.096 \\
        --xi-r 0.655 --t-max-s 5 --t-dur-s 20 --alpha-at-tmax paper \\
        --frame frame.toml --delta-star-m 0.25 -o paper_site.html
    # a site from a folder of its records (every component fitted, usable fits combined),
    # its band by the delta method (11 curves instead of the Monte Carlo band's 512)
    stepframe report amplification --records records/ --site-name "RSN 8883" --band delta -o x.html
    """
    from stepframe.pipeline.amplification.report import make_amplification_report
    from stepframe.pipeline.reports.document import report_summary

    jobs = options_from(args, RunOptions).jobs  # checked before any record is read
    out = make_amplification_report(args.out, options_from(args, Options), jobs=jobs)
    return CommandResult(*report_summary(out))


def run_selection(args: argparse.Namespace) -> CommandResult:
    """Record selection report from the output folder of `stepframe select`.

    Examples
    --------
    # the output folder of stepframe select, or stepframe-demo/ once stepframe demo has run
    stepframe report selection stepframe-demo/           writes stepframe-demo/selection_report.html
    stepframe report selection stepframe-demo/ -o sel.html --json
    """
    from stepframe.pipeline.reports.document import report_summary
    from stepframe.pipeline.selection.report import make_selection_report

    out = make_selection_report(args.outdir, args.out)
    return CommandResult(*report_summary(out))
