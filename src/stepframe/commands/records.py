"""``stepframe records``: command-line front end of :mod:`stepframe.records`.

Commands: ``info`` (metadata and intensity measures per component), ``spectrum`` (response
spectra, and geometric mean / RotD50 / RotD100 of two horizontal components) and ``catalog``
(a folder of records to a CSV table, its column dictionary and its failures).
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING

from stepframe.commands import (
    CommandResult,
    UserError,
    add_command,
    add_record_options,
    check_plot,
    read_record_file,
    record_paths,
)
from stepframe.core.options import REQUIRED, add_fields, add_options, fields_given
from stepframe.errors import InputError
from stepframe.pipeline.record_spectra import SpectrumOptions
from stepframe.records.read_options import RecordReadOptions

if TYPE_CHECKING:
    from stepframe.commands import Subparsers


def register(subparsers: Subparsers) -> None:
    """Add the ``records`` commands to ``subparsers``."""
    info = add_command(
        subparsers,
        "info",
        help="describe records: sampling, units, peaks, Arias intensity, durations",
        examples="  stepframe records info RSN8883_14383980_13849360.AT2\n"
        "  stepframe records info --format text --units gal --dt-s 0.005 acc.txt --json\n"
        "  stepframe records info --example fema-p695 --component MUL009\n",
        run=run_info,
    )
    info.add_argument("paths", nargs="*", metavar="PATH", help="record files (or --example)")
    add_record_options(info)

    spectrum = add_command(
        subparsers,
        "spectrum",
        help="response spectra (SD, PSV, PSA); geometric mean and RotD50/RotD100 of two "
        "horizontal components",
        examples="  stepframe records spectrum RSN8883_14383980_13849360.AT2 "
        "RSN8883_14383980_13849090.AT2 --periods-s 0.1,0.2,1.0 --json\n"
        "  stepframe records spectrum CE58667.V2.gz --damping 0.02 --plot ce58667.png\n",
        run=run_spectrum,
        description="Pseudo-spectral acceleration PSA [g], pseudo-velocity PSV [m/s] and "
        "displacement SD [m] of each component (exact piecewise-linear recurrence). With "
        "exactly two horizontal components (two files, or one file holding them; the first "
        "is h1), also their geometric mean, RotD50 and RotD100. Default periods: 91 "
        "log-spaced values from 0.01 s to 10 s (30 per decade).",
    )
    spectrum.add_argument(
        "paths", nargs="*", metavar="PATH", help="one or two record files (or --example)"
    )
    add_fields(spectrum, SpectrumOptions, [
        "periods_s", "damping", ("--plot", None, "OUT.png", "also draw the PSA spectra"),
    ])  # fmt: skip
    add_record_options(spectrum)

    catalog = add_command(
        subparsers,
        "catalog",
        help="catalogue a folder of records: one CSV row per component with intensity measures",
        examples="  stepframe records catalog records/ -o catalog.csv\n"
        "    writes catalog.csv, catalog.columns.csv (units and meanings) and\n"
        "    catalog.failures.csv (item, stage, error type, message of each unreadable file)\n"
        "  stepframe records catalog --example fema-p695 -o fema_catalog.csv\n",
        run=run_catalog,
    )
    catalog.add_argument(
        "folder", nargs="?", metavar="DIR", help="folder walked recursively (or --example)"
    )
    add_options(catalog, (("-o", "--output"), None, "OUT.csv", "table file", REQUIRED))
    add_record_options(catalog)


def run_info(args: argparse.Namespace) -> CommandResult:
    """One row per component of every file."""
    from stepframe.pipeline.record_spectra import info_text, record_info

    rows = [
        row
        for path in record_paths(args.paths, args)
        for row in record_info(read_record_file(path, args), path or f"example {args.example}")
    ]
    return CommandResult(data=rows, text=info_text(rows))


def run_spectrum(args: argparse.Namespace) -> CommandResult:
    """Spectra of every component; RotD of two horizontal ones."""
    from stepframe.pipeline.record_spectra import record_spectra, spectra_figure, spectra_text

    if len(args.paths) > 2:
        raise UserError("records spectrum: give one or two record files")
    check_plot(args.plot)
    sources: list[str] = []
    traces = []
    for path in record_paths(args.paths, args):
        for trace in read_record_file(path, args):
            sources.append(path if path is not None else "example")
            traces.append(trace)
    options = SpectrumOptions(**fields_given(args, SpectrumOptions))
    data = record_spectra(traces, options.periods_s, options.damping)
    if args.plot:
        from stepframe.pipeline.figures import save_figure

        names = [
            Path(str(t.stats.get("stepframe", {}).get("source_file") or path)).name
            for path, t in zip(sources, traces, strict=True)
        ]
        save_figure(spectra_figure(data, record=names), args.plot)
    return CommandResult(data=data, text=spectra_text(data))


def run_catalog(args: argparse.Namespace) -> CommandResult:
    """Catalogue a folder (or the example); progress on stderr unless --json."""
    from stepframe.records.catalog import catalog_to_file

    if args.example is not None and args.folder is not None:
        raise InputError(f"a folder and --example {args.example}, expected one of them")
    if args.example is None and args.folder is None:
        raise InputError("no folder, expected a folder of records or --example fema-p695")
    read = RecordReadOptions(**fields_given(args, RecordReadOptions))
    written = catalog_to_file(
        args.folder or read_record_file(None, args), args.output,
        progress=not getattr(args, "json", False), **read.catalog_kwargs(),
    )  # fmt: skip
    return CommandResult(data=written.to_dict(), text=written.describe())
