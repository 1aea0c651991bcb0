"""``stepframe demo``: the main job on the embedded example catalogue.

Record selection by moving resonance (docs/selection.md) on the 100 FEMA P695 components with the
paper's Example 4 frame (:data:`stepframe.structure.frame_file.FRAME_TEMPLATE`): features,
selection of 10 components, confirmation by simulation; the tables, a figure of the three best
records and the selection report (self-contained HTML, docs/reports.md) go to the output folder.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from stepframe.commands import CommandResult, add_command
from stepframe.errors import InputError

N_SELECTED = 10


def register(subparsers: Any) -> None:
    """Add ``demo`` to the top-level commands."""
    parser = add_command(
        subparsers,
        "demo",
        help="select records by moving resonance for the paper's Example 4 frame from the "
        "embedded FEMA P695 records, and confirm by simulation",
        examples="  stepframe demo\n  stepframe demo -o results --json\n",
        run=run,
    )
    parser.add_argument(
        "-o",
        "--out-dir",
        default="stepframe-demo",
        metavar="DIR",
        help="output folder (default: %(default)s)",
    )
    parser.add_argument("--jobs", type=int, help="worker processes (default: all CPUs)")


def run(args: argparse.Namespace) -> CommandResult:
    """Features, selection and confirmation on the example catalogue; tables, figure, report."""
    import tomllib

    from stepframe.commands.select import summary_text
    from stepframe.pipeline.reports.provenance import collect_provenance
    from stepframe.pipeline.reports.selection import write_selection_report
    from stepframe.pipeline.selection.inputs import select_from_catalogue
    from stepframe.pipeline.selection.options import SelectionOptions
    from stepframe.records.examples import fema_p695
    from stepframe.structure.frame_file import FRAME_TEMPLATE, frame_from_mapping

    out_dir = Path(args.out_dir)
    if out_dir.exists() and not out_dir.is_dir():
        raise InputError(
            "exists and is not a directory, expected a directory for the outputs", out_dir
        )
    if args.jobs is not None and args.jobs < 1:
        raise InputError(f"--jobs {args.jobs}, expected ≥ 1")
    frame = frame_from_mapping(tomllib.loads(FRAME_TEMPLATE))
    options = SelectionOptions(n=N_SELECTED, confirm=True)
    result = select_from_catalogue(frame, options, example=True, jobs=args.jobs)
    paths = result.write(out_dir)
    stream, table = fema_p695()
    files = ("fema_p695/" + table["file"].astype(str)).tolist()
    channels = [str(trace.stats.channel) for trace in stream]
    rows = [
        next(
            i
            for i, (f, c) in enumerate(zip(files, channels, strict=True))
            if f == row.file and c == row.component
        )
        for row in result.selection.head(3).itertuples()
    ]
    figure = out_dir / "selected_records.png"
    _draw_records(stream, table, rows, figure)
    report = write_selection_report(
        out_dir,
        provenance=collect_provenance(
            parameters={"frame": "Example 4 (FRAME_TEMPLATE)", **options.to_dict()}
        ),
    )
    data = result.to_dict()
    data["outputs"] = {name: str(path) for name, path in paths.items()}
    data["figure"] = str(figure)
    data["report"] = str(report)
    text = summary_text(result, out_dir) + f"\nfigure: {figure}\nreport: {report}"
    return CommandResult(data=data, text=text)


def _draw_records(stream: Any, table: Any, rows: list[int], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from stepframe.records.units import STANDARD_GRAVITY_M_S2

    fig, axes = plt.subplots(len(rows), 1, figsize=(9, 2.4 * len(rows)), sharex=False)
    for ax, row in zip(axes, rows, strict=True):
        trace = stream[row]
        ax.plot(trace.times(), trace.data / STANDARD_GRAVITY_M_S2, lw=0.6, color="k")
        meta = table.iloc[row]
        ax.set_title(
            f"{meta.event} {meta.year}, {meta.station} ({meta.component_name})", fontsize=9
        )
        ax.set_ylabel("acceleration [g]")
    axes[-1].set_xlabel("time [s]")
    fig.tight_layout()
    from stepframe.core.io import atomic_write

    try:
        with atomic_write(path, "wb") as out:  # nothing half-written, even on an error
            fig.savefig(out, dpi=110, format="png")
    finally:
        plt.close(fig)
