"""``stepframe records``: command-line front end of :mod:`stepframe.records`."""

from __future__ import annotations

import argparse
from typing import Any

from stepframe.commands import CommandResult, add_command, add_record_options, read_record_file


def register(subparsers: Any) -> None:
    """Add the ``records`` commands to ``subparsers``."""
    info = add_command(
        subparsers,
        "info",
        help="describe records: sampling, units, peaks",
        examples="  stepframe records info RSN8883_14383980_13849360.AT2\n"
        "  stepframe records info --format text --units gal --dt-s 0.01 acc.txt --json\n",
        run=run_info,
    )
    info.add_argument("paths", nargs="+", metavar="PATH", help="record files")
    add_record_options(info)


def run_info(args: argparse.Namespace) -> CommandResult:
    """One row per component of every file."""
    import numpy as np

    from stepframe.records.units import STANDARD_GRAVITY_M_S2

    rows = []
    for path in args.paths:
        for trace in read_record_file(path, args):
            rows.append(
                {
                    "file": path,
                    "station": trace.stats.station,
                    "component": trace.stats.channel,
                    "npts": int(trace.stats.npts),
                    "dt_s": float(trace.stats.delta),
                    "duration_s": float(trace.stats.delta * (trace.stats.npts - 1)),
                    "units_in": trace.stats.stepframe.units_in,
                    "pga_g": float(np.max(np.abs(trace.data)) / STANDARD_GRAVITY_M_S2),
                }
            )
    text = "\n".join(
        f"{r['file']} {r['station']} {r['component']}: {r['npts']} samples at {r['dt_s']} s, "
        f"units {r['units_in']}, PGA {r['pga_g']:.4g} g"
        for r in rows
    )
    return CommandResult(data=rows, text=text)
