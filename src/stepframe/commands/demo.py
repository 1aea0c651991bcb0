"""``stepframe demo``: the main job on the embedded example catalogue.

Until the pipeline exists it lists the 100 FEMA P695 components and draws three of them; the
selection run replaces it as the stages land.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from stepframe.commands import CommandResult, add_command
from stepframe.errors import InputError

LISTED_COLUMNS = [
    "event",
    "year",
    "station",
    "component_name",
    "magnitude",
    "rrup_km",
    "vs30_m_s",
    "npts",
    "dt_s",
    "pga_g",
]


def register(subparsers: Any) -> None:
    """Add ``demo`` to the top-level commands."""
    parser = add_command(
        subparsers,
        "demo",
        help="run the main job on the embedded example catalogue (FEMA P695 records)",
        examples="  stepframe demo\n  stepframe demo --out-dir results --json\n",
        run=run,
    )
    parser.add_argument(
        "--out-dir",
        default="stepframe-demo",
        metavar="DIR",
        help="where figures are written (default: %(default)s)",
    )


def run(args: argparse.Namespace) -> CommandResult:
    """List the example catalogue and write a figure of three records."""
    from stepframe.records.examples import fema_p695

    out_dir = Path(args.out_dir)
    if out_dir.exists() and not out_dir.is_dir():
        raise InputError(
            "exists and is not a directory, expected a directory for the figures", out_dir
        )
    stream, table = fema_p695()
    out_dir.mkdir(parents=True, exist_ok=True)
    figure = out_dir / "example_records.png"
    _draw_records(stream, table, [0, 40, 80], figure)
    listing = table[LISTED_COLUMNS]
    data = {
        "records": listing.to_dict(orient="records"),
        "figure": str(figure),
        "n_records": len(listing),
    }
    text = listing.to_string(index=False, float_format=lambda v: f"{v:.4g}")
    source = "PEER NGA database, FEMA P695 record sets"
    text += f"\n\n{len(listing)} components ({source}); figure: {figure}"
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
