"""Commands of ``stepframe structure``: ``simulate`` (one record) and ``frame-template``."""

from __future__ import annotations

import argparse
from typing import Any

from stepframe.commands import (
    CommandResult,
    UserError,
    add_command,
    add_record_options,
    positive_float,
    read_record_file,
)

SIMULATE_EXAMPLES = """\
  stepframe structure frame-template > FRAME.toml
  stepframe structure simulate --frame FRAME.toml RSN8883_14383980_13849360.AT2 --scale 6
  stepframe structure simulate --frame FRAME.toml RSN8883_14383980_13849360.AT2 --scale 6 \\
      --tail-s 30 --json --plot response.png
"""

TEMPLATE_EXAMPLES = """\
  stepframe structure frame-template > FRAME.toml     then edit FRAME.toml
"""


def register(subparsers: Any) -> None:
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
    simulate.add_argument("record", metavar="RECORD", help="accelerogram file (one component)")
    simulate.add_argument(
        "--frame", required=True, metavar="FRAME.toml", help="frame file (see frame-template)"
    )
    simulate.add_argument(
        "--scale", type=positive_float, default=1.0, metavar="S", help="record scale factor [-]"
    )
    simulate.add_argument(
        "--tail-s",
        type=_non_negative_float,
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


def _non_negative_float(text: str) -> float:
    import math

    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"{text!r} is not a number, expected seconds ≥ 0"
        ) from None
    if not (math.isfinite(value) and value >= 0):
        raise argparse.ArgumentTypeError(f"{text!r}, expected seconds ≥ 0")
    return value


def run_frame_template(args: argparse.Namespace) -> CommandResult:
    """The template as text, or ``{"frame_toml": ...}`` with --json."""
    from stepframe.structure.frame_file import frame_template

    text = frame_template()
    return CommandResult(data={"frame_toml": text}, text=text.rstrip("\n"))


def _one_trace(stream: Any, path: str) -> Any:
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

    import numpy as np

    from stepframe.errors import InputError
    from stepframe.structure.frame_file import read_frame_file
    from stepframe.structure.simulator import DEFAULT_TAIL_S, simulate

    frame = read_frame_file(args.frame)
    trace = _one_trace(read_record_file(args.record, args), args.record)
    dt_s = float(trace.stats.delta)
    samples = np.asarray(trace.data, dtype=float)
    bad = np.flatnonzero(~np.isfinite(samples))
    if bad.size:
        raise InputError(
            f"sample {bad[0]} (t = {bad[0] * dt_s:g} s) is {samples[bad[0]]} ({bad.size} "
            "non-finite samples), expected finite accelerations",
            args.record,
        )
    tail_s = DEFAULT_TAIL_S if args.tail_s is None else float(args.tail_s)
    result = simulate(
        frame,
        samples,
        dt_s,
        scale=float(args.scale),
        tail_s=tail_s,
        record_history=args.plot is not None,
    )
    summary = result.summary.to_dict()
    data: dict[str, Any] = {
        "record": args.record,
        "component": str(trace.stats.channel),
        "npts": int(trace.stats.npts),
        "dt_s": dt_s,
        "scale": float(args.scale),
        "pga_m_s2": float(np.max(np.abs(trace.data))) * float(args.scale),
        "tail_s": tail_s,
        "frame": {
            **frame.to_dict(),
            "x_star_m": frame.x_star_m,
            "uplift_acceleration_m_s2": frame.uplift_acceleration_m_s2,
        },
        **summary,
        "episodes": result.episode_records(),
    }
    if args.plot is not None:
        name = os.path.basename(args.record)
        _plot(result, frame, args.plot, title=f"{name} × {args.scale:g}")
        data["plot"] = args.plot
    return CommandResult(data=data, text=_text(data))


def _text(data: dict[str, Any]) -> str:
    drift = data["peak_drift_ratio"]
    lines = [
        f"{data['record']} [{data['component']}] × {data['scale']:g}: {data['npts']} samples at "
        f"{data['dt_s']:g} s, PGA {data['pga_m_s2']:.4g} m/s², tail {data['tail_s']:g} s",
        f"peak |x| {data['peak_abs_x_m']:.6g} m at {data['peak_time_s']:.4f} s"
        + ("" if drift is None else f" (drift ratio {drift:.4g})"),
        f"x_c {data['frame']['x_c_m']:.6g} m, x* {data['frame']['x_star_m']:.6g} m; "
        f"{data['n_stepping_episodes']} stepping episodes, {data['n_impacts']} impacts",
        f"residual x {data['residual_x_m']:.6g} m",
        (
            f"OVERTURNED at {data['overturn_time_s']:.4f} s"
            if data["overturned"]
            else "not overturned"
        )
        + ("" if data["status"] == "ok" else f"; numerical status: {data['status']}"),
    ]
    if "plot" in data:
        lines.append(f"plot written to {data['plot']}")
    return "\n".join(lines)


def _plot(result: Any, frame: Any, out: str, *, title: str) -> None:
    """x(t) with the stepped samples highlighted and ±x_c, ±x* marked; written atomically."""
    import os
    import tempfile

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    history = result.history
    time_s = history["time"].to_numpy()
    x_m = history["x"].to_numpy()
    stepped = history["phase"].to_numpy() != 0
    fig, ax = plt.subplots(figsize=(9, 4))
    ax.plot(time_s, x_m, lw=0.7, color="0.3", label="x (unstepped)")
    ax.plot(time_s, np.where(stepped, x_m, np.nan), lw=1.4, color="tab:red", label="stepped")
    for level, style, name in ((frame.x_c_m, ":", "±x_c"), (frame.x_star_m, "--", "±x*")):
        ax.axhline(level, ls=style, color="tab:blue", lw=0.8, label=name)
        ax.axhline(-level, ls=style, color="tab:blue", lw=0.8)
    if result.summary.overturned:
        ax.axvline(result.summary.overturn_time_s, color="k", lw=0.8, label="overturned")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("x [m]")
    ax.set_title(title)
    ax.legend(loc="upper right", fontsize="small")
    fig.tight_layout()
    directory = os.path.dirname(os.path.abspath(out))
    handle, temporary = tempfile.mkstemp(suffix=".png", dir=directory)
    os.close(handle)
    try:
        fig.savefig(temporary, dpi=120)
        os.replace(temporary, out)
    finally:
        plt.close(fig)
        if os.path.exists(temporary):
            os.remove(temporary)
