"""``stepframe select``: record selection by moving resonance (docs/selection.md).

The options are the fields of :class:`~stepframe.pipeline.selection.options.SelectionOptions`
(the ``[selection]`` table of ``--options`` and of workflows reads the same names); the run is
:func:`~stepframe.pipeline.selection.inputs.select_to_folder`.
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from stepframe.commands import add_command, add_record_options
from stepframe.core.options import (
    REQUIRED,
    add_fields,
    add_options,
    by_flags,
    fields_given,
    options_from,
)
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
        ("--jobs", int, None, "worker processes (default: all CPUs, or STEPFRAME_JOBS)"),
    ),
    "the frame's band": (
        "a_max_m",
        ("--design", None, "CASE.toml",
         "quasi-dynamic design input: A_max = design displacement δ*"),
        "x_star_fraction", "strong_motion_fraction",
    ),
    "records, filters and caps": (
        "verticals",
        *(f"{name}_{end}{unit}" for name, unit in (
            ("magnitude", ""), ("distance", "_km"), ("vs30", "_m_s"), ("d5_95", "_s"),
            ("pga", "_g"), ("pgv", "_m_s"), ("psa_t1", "_g"), ("arias", "_m_s"),
        ) for end in ("min", "max")),
        "distance_metric", "lowest_usable_below_band", "require_plausible",
        ("--exclude", list, "RECORD", "leave out a record (RSN174 or 174), file name or path "
         "(repeat, or comma-separated)"),
        "exclude_unmatched", "max_per_event", "max_per_station",
    ),
    "target spectrum, code check and scaling": (
        "target_s_ds_g", "target_s_d1_g", "target_t_l_s", "target_ec8", "target_ground",
        "target_ag_g", "target_importance", "target_damping", "target_csv", "target_code",
        "pair_spectrum", "target_periods_s", "spectral_weight", "scale_min", "scale_max",
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
    parser.add_argument(
        "catalogue",
        nargs="*",
        metavar="DIR",
        help="folders of record files (symlinked sub-folders followed)",
    )
    parser.add_argument(
        "--example", choices=["fema-p695"],
        help="the embedded example catalogue (alone, or beside folders)",
    )  # fmt: skip
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
    from stepframe.errors import InputError
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
    try:
        return selection_options(args.options, values)
    except InputError as error:
        # a value the command line gave is named by its flag, as every command does
        if error.key not in values or not error.what.startswith(f"{error.key} = "):
            raise
        # the refused key only: the others a message names may have come from an options file
        flag = "--" + error.key.replace("_", "-")
        raise InputError(by_flags(error.what, {error.key: flag})) from None


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
    stepframe select --frame FRAME.toml --example fema-p695 -n 7 --unit record \\
        --target-ec8 type1 --target-ground C --target-ag-g 0.25 --scale target-mse \\
        --exclude RSN174 -o picks-ec8
    # from folders of record files: DIR... instead of (or beside) --example, with --metadata CSV
    # the chosen motions, scaled, are in OUTDIR/motions/ (manifest.csv, AT2 and one-column text)
    """
    from stepframe.pipeline.selection.inputs import select_to_folder

    return select_to_folder(
        args.frame, options_from_args(args), args.out_dir, source=options_from(args, RecordSource),
        catalogue=args.catalogue, metadata=args.metadata, jobs=args.jobs,
    )  # fmt: skip
