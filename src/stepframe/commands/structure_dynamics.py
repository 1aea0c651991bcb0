"""Commands of ``stepframe structure``: ``harmonic``, ``bifurcation`` and ``ida``.

The studies are :mod:`stepframe.pipeline.dynamics`; this module parses and prints.
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
    save_plot,
)
from stepframe.core.options import add_fields, add_options, fields_given

if TYPE_CHECKING:
    from stepframe.commands import Subparsers
    from stepframe.structure.frame import PortalFrame

HARMONIC_EXAMPLES = """\
  stepframe structure harmonic --frame FRAME.toml --amplitude-g 0.25 --omega-rad-s 7.854
  stepframe structure harmonic --block 0.25,1.0 --amplitude-g 0.3 --omega-rad-s 16 \\
      --periods 200 --orbit 1 --json --plot portrait.png
"""

BIFURCATION_EXAMPLES = """\
  stepframe structure bifurcation --frame FRAME.toml --omega-rad-s 7.854 \\
      --amplitudes-g 0.05,0.5,200 --initial 50 --periods 100 --plot diagram.png
  stepframe structure bifurcation --block 0.25,1.0 --amplitude-g 0.3 --omegas-rad-s 5,40,100
"""

IDA_EXAMPLES = """\
  stepframe structure ida --frame FRAME.toml --fema-p695 100 --resolution-g 0.001 --plot ida.png
  stepframe structure ida --frame FRAME.toml RSN8883_14383980_13849360.AT2 --json
  stepframe structure ida --block 0.25,1.0 --pulse cosine --omega-rad-s 10.6,16
"""


def register(subparsers: Subparsers) -> None:
    """Add ``harmonic``, ``bifurcation`` and ``ida`` to ``subparsers``."""
    from stepframe.pipeline.dynamics import (
        BifurcationOptions,
        FrameSource,
        HarmonicOptions,
        IdaOptions,
    )

    harmonic = add_command(
        subparsers,
        "harmonic",
        help="response to harmonic ground acceleration (closed form), periodic orbits",
        description=(
            "Integrate the frame under ground acceleration A cos(ωt) in closed form (no sampling "
            "error) from rest or a given state; with --orbit N, find the period-N orbit by "
            "Newton on the stroboscopic map from the final state and report its Floquet "
            "multipliers."
        ),
        examples=HARMONIC_EXAMPLES,
        run=run_harmonic,
    )
    bif = add_command(
        subparsers,
        "bifurcation",
        help="brute-force bifurcation diagram over the forcing amplitude (all cores)",
        description=(
            "For every amplitude and every initial state, iterate the stroboscopic map for "
            "--periods forcing periods and keep the last 20 points; report the fraction of "
            "initial states that overturn and the orbit periods found."
        ),
        examples=BIFURCATION_EXAMPLES,
        run=run_bifurcation,
    )
    ida = add_command(
        subparsers,
        "ida",
        help="incremental dynamic analysis by hunt-trace-fill, with resurrection detection",
        description=(
            "Raise each record's PGA until the frame overturns, trace every change of outcome "
            "to --resolution-g, probe up to twice the first overturning for resurrection, and "
            "report the overturning PGA per record with fractiles. With --pulse, the items are "
            "one-cycle pulses at each --omega-rad-s and intensities are in units of the static "
            "uplift acceleration γ₁/P₂."
        ),
        examples=IDA_EXAMPLES,
        run=run_ida,
    )
    for parser, options, plot in (
        (harmonic, HarmonicOptions, "phase portrait"),
        (bif, BifurcationOptions, "draw the diagram"),
        (ida, IdaOptions, "draw the IDA curves"),
    ):
        frame = parser.add_mutually_exclusive_group(required=True)
        add_fields(frame, FrameSource)
        if parser is ida:
            parser.add_argument("records", nargs="*", metavar="RECORD", help="accelerogram files")
        add_fields(parser, options)
        add_options(parser, ("--plot", None, "OUT.png", plot))
    add_record_options(ida)


def run_harmonic(args: argparse.Namespace) -> CommandResult:
    """Simulate, optionally find an orbit, summarise."""
    from stepframe.pipeline.dynamics import HarmonicOptions, harmonic_study

    check_plot(args.plot)
    study = harmonic_study(_frame(args), HarmonicOptions(**fields_given(args, HarmonicOptions)))
    return save_plot(CommandResult(study.to_dict(), study.describe()), args.plot, study.figure)


def run_bifurcation(args: argparse.Namespace) -> CommandResult:
    """Brute-force diagram over amplitudes or frequencies; summary per value."""
    from stepframe.pipeline.dynamics import BifurcationOptions, bifurcation_sweep

    check_plot(args.plot)
    options = BifurcationOptions(**fields_given(args, BifurcationOptions))
    sweep = bifurcation_sweep(_frame(args), options)
    return save_plot(CommandResult(sweep.to_dict(), sweep.describe()), args.plot, sweep.figure)


def run_ida(args: argparse.Namespace) -> CommandResult:
    """Hunt-trace-fill over records or pulses."""
    from stepframe.pipeline.dynamics import IdaOptions, ida_study

    check_plot(args.plot)
    frame = _frame(args)
    records = [(path, read_record_file(path, args)) for path in args.records]
    study = ida_study(frame, IdaOptions(**fields_given(args, IdaOptions)), records)
    return save_plot(CommandResult(study.to_dict(), study.describe()), args.plot, study.figure)


def _frame(args: argparse.Namespace) -> PortalFrame:
    """The frame of --frame or --block (:class:`~stepframe.pipeline.dynamics.FrameSource`)."""
    from stepframe.pipeline.dynamics import FrameSource

    return FrameSource(**fields_given(args, FrameSource)).portal_frame()
