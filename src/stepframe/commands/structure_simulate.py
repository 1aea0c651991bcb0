"""Commands of ``stepframe structure``: ``simulate`` (one record) and ``frame-template``."""

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
from stepframe.core.options import add_fields, fields_given
from stepframe.pipeline.response import SimulateOptions

if TYPE_CHECKING:
    from stepframe.commands import Subparsers

SIMULATE_EXAMPLES = """\
  stepframe structure frame-template > FRAME.toml
  stepframe structure simulate --frame FRAME.toml RSN8883_14383980_13849360.AT2 --scale 6
  stepframe structure simulate --frame FRAME.toml --example fema-p695 --component MUL009 --scale 2
  stepframe structure simulate --frame FRAME.toml RSN8883_14383980_13849360.AT2 --scale 6 \\
      --tail-s 30 --json --plot response.png
"""

TEMPLATE_EXAMPLES = """\
  stepframe structure frame-template > FRAME.toml     then edit FRAME.toml
"""


def register(subparsers: Subparsers) -> None:
    """Add ``simulate`` and ``frame-template`` to ``subparsers``."""
    simulate = add_command(
        subparsers,
        "simulate",
        help="stepping response of a frame to one record (exact piecewise-analytic)",
        description=(
            "Integrate the stepping portal frame of FRAME.toml (eqs. 4.11-4.12 with impact at "
            "touchdown) exactly under RECORD times --scale, then a free-vibration tail; report "
            "peaks, stepping episodes, impacts, residual displacement and overturning."
        ),
        examples=SIMULATE_EXAMPLES,
        run=run_simulate,
    )
    simulate.add_argument(
        "record", nargs="?", metavar="RECORD", help="accelerogram file, one component, or --example"
    )
    add_fields(simulate, SimulateOptions, [
        "frame", "scale", "tail_s", ("--plot", None, "OUT.png", "draw x(t) with the phases"),
    ])  # fmt: skip
    add_record_options(simulate)
    add_command(
        subparsers,
        "frame-template",
        help="print a commented FRAME.toml (the paper's Example 4 frame)",
        examples=TEMPLATE_EXAMPLES,
        run=run_frame_template,
    )


def run_frame_template(args: argparse.Namespace) -> CommandResult:
    """The template as text, or ``{"frame_toml": ...}`` with --json."""
    from stepframe.structure.frame_file import frame_template

    text = frame_template()
    return CommandResult(data={"frame_toml": text}, text=text.rstrip("\n"))


def run_simulate(args: argparse.Namespace) -> CommandResult:
    """Read the frame and the record, simulate, summarise (and plot)."""
    from stepframe.pipeline.response import simulate_file

    check_plot(args.plot)
    simulated = simulate_file(
        SimulateOptions(**fields_given(args, SimulateOptions)),
        lambda: read_record_file(args.record, args),
        name=args.record or f"example {args.example} {args.component}",
        record_history=args.plot is not None,
    )
    result = CommandResult(simulated.to_dict(), simulated.describe())
    return save_plot(result, args.plot, simulated.figure)
