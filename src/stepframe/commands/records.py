"""``stepframe records``: command-line front end of :mod:`stepframe.records`.

Commands: ``info`` (metadata and intensity measures per component), ``spectrum`` (response
spectra, and geometric mean / RotD50 / RotD100 of two horizontal components) and ``catalog``
(a folder of records to a CSV table, its column dictionary and its failures).
"""

from __future__ import annotations

import argparse
import sys
from typing import Any

from stepframe.commands import (
    CommandResult,
    UserError,
    add_command,
    add_record_options,
    float_list,
    read_record_file,
)

#: Channel names of vertical components (SEED codes ending in Z are vertical too).
_VERTICAL_NAMES = {"up", "ud", "ud1", "ud2", "z", "v", "ver", "vert", "vertical", "dwn", "down"}


def register(subparsers: Any) -> None:
    """Add the ``records`` commands to ``subparsers``."""
    info = add_command(
        subparsers,
        "info",
        help="describe records: sampling, units, peaks, Arias intensity, durations",
        examples="  stepframe records info RSN8883_14383980_13849360.AT2\n"
        "  stepframe records info --format text --units gal --dt-s 0.01 acc.txt --json\n",
        run=run_info,
    )
    info.add_argument("paths", nargs="+", metavar="PATH", help="record files")
    add_record_options(info)

    spectrum = add_command(
        subparsers,
        "spectrum",
        help="response spectra (SD, PSV, PSA); geometric mean and RotD50/RotD100 of two "
        "horizontal components",
        examples="  stepframe records spectrum RSN8883_14383980_13849360.AT2 "
        "RSN8883_14383980_13849090.AT2 --periods-s 0.1,0.2,1.0 --json\n"
        "  stepframe records spectrum CE58667.V2 --damping 0.02 --plot ce58667.png\n",
        run=run_spectrum,
        description="Pseudo-spectral acceleration PSA [g], pseudo-velocity PSV [m/s] and "
        "displacement SD [m] of each component (exact piecewise-linear recurrence). With "
        "exactly two horizontal components (two files, or one file holding them; the first "
        "is h1), also their geometric mean, RotD50 and RotD100. Default periods: 91 "
        "log-spaced values from 0.01 s to 10 s (30 per decade).",
    )
    spectrum.add_argument("paths", nargs="+", metavar="PATH", help="one or two record files")
    spectrum.add_argument(
        "--periods-s", type=float_list, metavar="T1,T2,...", help="oscillator periods [s]"
    )
    spectrum.add_argument(
        "--damping",
        type=float,
        default=0.05,
        metavar="ZETA",
        help="damping ratio as a fraction (default 0.05)",
    )
    spectrum.add_argument("--plot", metavar="OUT.png", help="also draw the PSA spectra")
    add_record_options(spectrum)

    catalog = add_command(
        subparsers,
        "catalog",
        help="catalogue a folder of records: one CSV row per component with intensity measures",
        examples="  stepframe records catalog records/ -o catalog.csv\n"
        "    writes catalog.csv, catalog.columns.csv (units and meanings) and\n"
        "    catalog.failures.csv (file, stage, reason of every file it could not read)\n",
        run=run_catalog,
    )
    catalog.add_argument("folder", metavar="DIR", help="folder walked recursively")
    catalog.add_argument("-o", "--output", required=True, metavar="OUT.csv", help="table file")
    add_record_options(catalog)


def run_info(args: argparse.Namespace) -> CommandResult:
    """One row per component of every file."""
    from stepframe.records.intensity import intensity_measures

    rows = []
    for path in args.paths:
        for trace in read_record_file(path, args):
            dt = float(trace.stats.delta)
            measures = intensity_measures(trace.data, dt)
            rows.append(
                {
                    "file": path,
                    "station": trace.stats.station,
                    "component": trace.stats.channel,
                    "npts": int(trace.stats.npts),
                    "dt_s": dt,
                    "duration_s": dt * (int(trace.stats.npts) - 1),
                    "units_in": trace.stats.stepframe.units_in,
                    **{key: value for key, value in measures.items() if key != "pga_m_s2"},
                }
            )
    text = "\n".join(
        f"{r['file']} {r['station']} {r['component']}: {r['npts']} samples at {r['dt_s']} s, "
        f"units {r['units_in']}, PGA {r['pga_g']:.4g} g, PGV {r['pgv_m_s']:.4g} m/s, "
        f"PGD {r['pgd_m']:.4g} m, Arias {r['arias_m_s']:.4g} m/s, D5-95 {r['d5_95_s']:.4g} s"
        for r in rows
    )
    return CommandResult(data=rows, text=text)


def _is_vertical(channel: str) -> bool:
    name = channel.strip().lower()
    return name in _VERTICAL_NAMES or (len(name) == 3 and name.endswith("z"))


def run_spectrum(args: argparse.Namespace) -> CommandResult:
    """Spectra of every component; RotD of two horizontal ones."""
    import numpy as np

    from stepframe.errors import InputError
    from stepframe.records.spectra import DEFAULT_PERIODS_S, response_spectrum

    if len(args.paths) > 2:
        raise UserError("records spectrum: give one or two record files")
    periods = np.asarray(
        DEFAULT_PERIODS_S if args.periods_s is None else args.periods_s, dtype=float
    )
    traces = [trace for path in args.paths for trace in read_record_file(path, args)]
    components = []
    for trace in traces:
        result = response_spectrum(trace.data, float(trace.stats.delta), periods, args.damping)
        components.append(
            {
                "component": trace.stats.channel,
                "station": trace.stats.station,
                "psa_g": result.psa_g,
                "psv_m_s": result.psv_m_s,
                "sd_m": result.sd_m,
            }
        )
    data: dict[str, Any] = {
        "period_s": periods,
        "damping": args.damping,
        "components": components,
    }
    horizontal = [t for t in traces if not _is_vertical(t.stats.channel)]
    if len(horizontal) == 2:
        from stepframe.records.rotd import rotd_spectrum

        h1, h2 = horizontal
        if float(h1.stats.delta) != float(h2.stats.delta):
            raise InputError(
                f"horizontal components sampled at {h1.stats.delta} s and {h2.stats.delta} s, "
                "expected the same sampling interval"
            )
        rotd = rotd_spectrum(h1.data, h2.data, float(h1.stats.delta), periods, args.damping)
        data.update(
            h1=h1.stats.channel,
            h2=h2.stats.channel,
            geomean_g=rotd.in_g("geomean"),
            rotd50_g=rotd.in_g("rotd50"),
            rotd100_g=rotd.in_g("rotd100"),
        )
    if args.plot:
        _plot(data, args.plot)
    return CommandResult(data=data, text=_spectrum_text(data))


def _spectrum_text(data: dict[str, Any]) -> str:
    names = [c["component"] for c in data["components"]]
    header = ["period_s"] + [f"psa_g[{n}]" for n in names]
    columns = [data["period_s"]] + [c["psa_g"] for c in data["components"]]
    for key in ("geomean_g", "rotd50_g", "rotd100_g"):
        if key in data:
            header.append(key)
            columns.append(data[key])
    lines = [f"damping {data['damping']}", "  ".join(f"{h:>12}" for h in header)]
    for i in range(len(data["period_s"])):
        lines.append("  ".join(f"{float(col[i]):12.5g}" for col in columns))
    return "\n".join(lines)


def _plot(data: dict[str, Any], out: str) -> None:
    import os
    import tempfile
    from pathlib import Path

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from stepframe.errors import InputError

    target = Path(out)
    if not target.parent.is_dir():
        raise InputError("plot folder does not exist, expected an existing folder", target)
    figure, axes = plt.subplots(figsize=(6.4, 4.2), layout="constrained")
    for component in data["components"]:
        axes.plot(data["period_s"], component["psa_g"], label=component["component"], lw=1)
    for key, label in (("rotd50_g", "RotD50"), ("rotd100_g", "RotD100")):
        if key in data:
            axes.plot(data["period_s"], data[key], label=label, lw=2)
    axes.set(
        xscale="log",
        xlabel="period T [s]",
        ylabel="PSA [g]",
        title=f"pseudo-spectral acceleration, damping {data['damping']:g}",
    )
    axes.grid(True, which="both", alpha=0.3)
    axes.legend()
    handle, temporary = tempfile.mkstemp(
        prefix=f".{target.name}.", suffix=".png", dir=target.parent
    )
    os.close(handle)
    try:
        figure.savefig(temporary, dpi=120)
        os.replace(temporary, target)
    finally:
        plt.close(figure)
        Path(temporary).unlink(missing_ok=True)


def run_catalog(args: argparse.Namespace) -> CommandResult:
    """Catalogue a folder; progress on stderr unless --json."""
    from stepframe.records.catalog import catalog, check_output, write_catalog

    outputs = check_output(args.output)  # before the work, not after it
    show_progress = not getattr(args, "json", False)

    def progress(number: int, total: int, file: str) -> None:
        print(f"[{number}/{total}] {file}", file=sys.stderr, flush=True)

    table, failures = catalog(
        args.folder,
        format=args.format,
        units=args.units,
        dt_s=args.dt_s,
        inventory=args.inventory,
        component=args.component,
        progress=progress if show_progress else None,
        exclude=outputs,
    )
    paths = write_catalog(table, failures, args.output)
    data = {
        "table": str(paths[0]),
        "columns": str(paths[1]),
        "failures": str(paths[2]),
        "n_components": len(table),
        "n_failures": len(failures),
    }
    text = (
        f"{len(table)} components catalogued in {paths[0]} (columns: {paths[1]}); "
        f"{len(failures)} failures in {paths[2]}"
    )
    return CommandResult(data=data, text=text)
