"""``stepframe records``: ``info``, ``spectrum`` and ``catalog`` (:mod:`stepframe.records`)."""

from __future__ import annotations

import argparse
import functools
from pathlib import Path
from typing import TYPE_CHECKING

from stepframe.commands import CommandResult, UserError, add_command, add_record_options
from stepframe.core.options import REQUIRED, add_fields, add_options, options_from
from stepframe.pipeline.catalogue.record_spectra import (
    SpectrumOptions,
    info_text,
    record_info,
    record_spectra,
    spectra_figure,
    spectra_text,
)
from stepframe.records.read_options import RecordSource

if TYPE_CHECKING:
    from stepframe.commands import Subparsers
    from stepframe.records.catalog import CatalogFiles


def register(subparsers: Subparsers) -> None:
    """Add the ``records`` commands to ``subparsers``."""
    info = add_command(subparsers, "info", run_info)
    info.add_argument("paths", nargs="*", metavar="PATH", help="record files (or --example)")
    add_record_options(info)
    spectrum = add_command(subparsers, "spectrum", run_spectrum, plot="also draw the PSA spectra")
    spectrum.add_argument(
        "paths", nargs="*", metavar="PATH", help="one or two record files (or --example)"
    )
    add_fields(spectrum, SpectrumOptions, ["periods_s", "damping"])
    add_record_options(spectrum)
    catalog = add_command(subparsers, "catalog", run_catalog)
    catalog.add_argument(
        "folder", nargs="?", metavar="DIR", help="folder walked recursively (or --example)"
    )
    add_options(catalog, (("-o", "--output"), None, "OUT.csv", "table file", REQUIRED))
    add_record_options(catalog)


def run_info(args: argparse.Namespace) -> CommandResult:
    """Describe records: sampling, units, peaks, Arias intensity, durations.

    Examples
    --------
    stepframe records info RSN8883_14383980_13849360.AT2
    stepframe records info --format text --units gal --dt-s 0.005 acc.txt --json
    stepframe records info --example fema-p695 --component MUL009
    """
    source = options_from(args, RecordSource)
    paths = source.paths(args.paths)
    rows = [row for p in paths for row in record_info(source.read(p), source.name(p))]
    return CommandResult(data=rows, text=info_text(rows))


def run_spectrum(args: argparse.Namespace) -> CommandResult:
    """Response spectra (SD, PSV, PSA); geometric mean and RotD50/RotD100 of two horizontal
    components.

    Pseudo-spectral acceleration PSA [g], pseudo-velocity PSV [m/s] and displacement SD [m]
    of each component (exact piecewise-linear recurrence). With exactly two horizontal
    components (two files, or one file holding them; the first is h1), also their geometric
    mean, RotD50 and RotD100. Default periods: 91 log-spaced values from 0.01 s to 10 s (30 per
    decade).

    Examples
    --------
    stepframe records spectrum RSN8883_14383980_13849360.AT2 RSN8883_14383980_13849090.AT2 \\
        --periods-s 0.1,0.2,1.0 --json
    stepframe records spectrum CE58667.V2.gz --damping 0.02 --plot ce58667.png
    """
    if len(args.paths) > 2:
        raise UserError("records spectrum: give one or two record files")
    source = options_from(args, RecordSource)
    if len(args.paths) == 2:
        _refuse_same_content(args.paths)
    traces = [(path, trace) for path in source.paths(args.paths) for trace in source.read(path)]
    options = options_from(args, SpectrumOptions)
    data = record_spectra([t for _, t in traces], options.periods_s, options.damping)
    names = [
        Path(str(trace.stats.get("stepframe", {}).get("source_file") or path or "example")).name
        for path, trace in traces
    ]
    figure = functools.partial(spectra_figure, data, record=names)
    return CommandResult(data, spectra_text(data), figure)


def _refuse_same_content(paths: list[str]) -> None:
    """Two files with the same bytes are one component read twice (the catalogue's rule: one
    content is one item): its RotD100 would be √2 times its PSA."""
    from stepframe.records.catalog import distinct_contents

    _, copies = distinct_contents([Path(p) for p in paths])
    for copy, kept in copies:
        same = "given twice" if copy == kept else f"the same bytes as {kept}: read once"
        raise UserError(f"{copy}: {same}, expected two components of one record")


def run_catalog(args: argparse.Namespace) -> CatalogFiles:
    """Catalogue a folder of records: one CSV row per component with intensity measures.

    Examples
    --------
    stepframe records catalog records/ -o catalog.csv
      writes catalog.csv, catalog.columns.csv (units and meanings) and
      catalog.failures.csv (item, stage, error type, message of each unreadable file)
    stepframe records catalog --example fema-p695 -o fema_catalog.csv
    """
    from stepframe.records.catalog import catalog_to_file

    source = options_from(args, RecordSource)
    return catalog_to_file(
        source.folder_or_example(args.folder), args.output,
        progress=not getattr(args, "json", False), **source.catalog_kwargs(),
    )  # fmt: skip
