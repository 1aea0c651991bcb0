"""``stepframe select``: record selection by moving resonance (docs/selection.md).

The options are the fields of :class:`~stepframe.pipeline.selection.options.SelectionOptions`
(the ``[selection]`` table of ``--options`` and of workflows reads the same names); the run is
:func:`~stepframe.pipeline.selection.inputs.select_to_folder`.
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from stepframe.commands import add_command, add_record_options
from stepframe.core.options import REQUIRED, add_fields, add_options, fields_given, options_from
from stepframe.pipeline.selection.options import SelectionOptions
from stepframe.records.read_options import RecordSource

if TYPE_CHECKING:
    from stepframe.commands import Subparsers
    from stepframe.core.options import OptionRow
    from stepframe.pipeline.selection.inputs import SelectionFolder

#: The options per help group: SelectionOptions fields, and (as option rows) the options that are
#: not fields.
FIELDS: dict[str | None, tuple[str | OptionRow, ...]] = {
    None: (
        "rank_by", "scale", "unit", "confirm",
        ("--options", None, "TOML", "a file with a [selection] table"),
        ("--metadata", None, "CSV", "catalogue metadata joined on column 'file' (for the filters)"),
        ("--jobs", int, None, "worker processes (default: all CPUs)"),
    ),
    "the frame's band": (
        "a_max_m",
        ("--design", None, "CASE.toml",
         "quasi-dynamic design input: A_max = design displacement δ*"),
        "x_star_fraction", "strong_motion_fraction",
    ),
    "filters and caps": (
        *(f"{name}_{end}{unit}" for name, unit in (
            ("magnitude", ""), ("distance", "_km"), ("vs30", "_m_s"), ("d5_95", "_s"), ("pga", "_g")
        ) for end in ("min", "max")),
        "distance_metric", "lowest_usable_below_band", "require_plausible",
        ("--exclude", list, "FILE_OR_RSN", "leave out (repeat, or comma-separated)"),
        "max_per_event", "max_per_station",
    ),
    "target spectrum and scaling": (
        "target_s_ds_g", "target_s_d1_g", "target_csv", "target_periods_s", "spectral_weight",
        "scale_min", "scale_max",
    ),
    "uncertainty and confirmation": ("n_bootstrap", "seed", "confirm_onset_ratio"),
    "ranking (docs/selection.md)": (
        "rank_onset_ratio", "rank_psa_t1_g", "prefilter", "prefilter_k", "exact_budget_s", "scores",
    ),
}  # fmt: skip


def register(subparsers: Subparsers) -> None:
    """Add ``select`` to the top-level commands."""
    parser = add_command(subparsers, "select", run_select)
    parser.add_argument("--frame", required=True, metavar="FRAME.toml", help="frame file")
    source = parser.add_mutually_exclusive_group(required=True)
    source.add_argument("catalogue", nargs="?", metavar="DIR", help="folder of record files")
    source.add_argument("--example", choices=["fema-p695"], help="the embedded example catalogue")
    add_options(
        parser,
        ("-n", int, None, "how many components (or records)", REQUIRED),
        (("-o", "--out-dir"), None, "OUTDIR", "output folder", REQUIRED),
    )
    for title, rows in FIELDS.items():
        group = parser if title is None else parser.add_argument_group(title)
        add_fields(group, SelectionOptions, rows)
    add_record_options(parser)


def options_from_args(args: argparse.Namespace) -> SelectionOptions:
    """The :class:`SelectionOptions` of the command line (over an optional [selection] file)."""
    from stepframe.pipeline.dynamics.design import design_displacement_m
    from stepframe.pipeline.selection.options import selection_options

    values = {"n": args.n}
    for rows in FIELDS.values():
        values.update(fields_given(args, rows))
    exclude = [word.strip() for item in args.exclude for word in item.split(",") if word.strip()]
    if exclude:
        values["exclude"] = exclude
    if args.design:
        values["design_displacement_m"] = design_displacement_m(args.design)
    return selection_options(args.options, values)


def run_select(args: argparse.Namespace) -> SelectionFolder:
    """Select records by moving resonance for a stepping frame, confirm by simulation.

    Examples
    --------
    stepframe structure frame-template > FRAME.toml
    stepframe select --frame FRAME.toml --example fema-p695 -n 10 --confirm -o picks
    stepframe select --frame FRAME.toml --example fema-p695 -n 7 --magnitude-min 6.5 \\
        --scale psa-at-t1 -o picks
    stepframe select --frame FRAME.toml --example fema-p695 -n 7 --target-s-ds-g 1.0 \\
        --target-s-d1-g 0.6 --scale target-mse --spectral-weight 0.5 -o picks --json
    # from a folder of record files: DIR instead of --example, with --metadata CSV for the filters
    """
    from stepframe.pipeline.selection.inputs import select_to_folder

    return select_to_folder(
        args.frame, options_from_args(args), args.out_dir, source=options_from(args, RecordSource),
        catalogue=args.catalogue, metadata=args.metadata, jobs=args.jobs,
    )  # fmt: skip
