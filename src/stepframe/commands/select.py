"""``stepframe select``: record selection by moving resonance (docs/selection.md)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from stepframe.commands import (
    CommandResult,
    InputError,
    add_command,
    add_record_options,
    float_list,
    positive_float,
    record_options,
)

EXAMPLES = """\
  stepframe structure frame-template > FRAME.toml
  stepframe select --frame FRAME.toml --example fema-p695 -n 10 --confirm -o picks
  stepframe select --frame FRAME.toml --example fema-p695 -n 7 --magnitude-min 6.5 \\
      --scale psa-at-t1 -o picks
  stepframe select --frame FRAME.toml --example fema-p695 -n 7 --target-s-ds-g 1.0 \\
      --target-s-d1-g 0.6 --scale target-mse --spectral-weight 0.5 -o picks --json
  # from a folder of record files: DIR instead of --example, with --metadata CSV for the filters
"""

#: Command-line option → SelectionOptions field, for the options that map one to one.
_DIRECT = (
    "rank_by",
    "scale",
    "unit",
    "spectral_weight",
    "a_max_m",
    "x_star_fraction",
    "strong_motion_fraction",
    "n_bootstrap",
    "seed",
    "magnitude_min",
    "magnitude_max",
    "distance_min_km",
    "distance_max_km",
    "distance_metric",
    "vs30_min_m_s",
    "vs30_max_m_s",
    "d5_95_min_s",
    "d5_95_max_s",
    "pga_min_g",
    "pga_max_g",
    "max_per_event",
    "max_per_station",
    "target_s_ds_g",
    "target_s_d1_g",
    "target_csv",
    "scale_min",
    "scale_max",
    "confirm_onset_ratio",
)


def register(subparsers: Any) -> None:
    """Add ``select`` to the top-level commands."""
    from stepframe.pipeline.selection.names import (
        DISTANCE_METRICS,
        RANKABLE,
        SCALE_POLICIES,
        UNITS,
    )

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
    parser.add_argument("-n", type=int, required=True, help="how many components (or records)")
    parser.add_argument("-o", "--out-dir", required=True, metavar="OUTDIR", help="output folder")
    parser.add_argument(
        "--rank-by",
        choices=RANKABLE,
        default="backbone_amplification",
        help="ranking score (default: %(default)s)",
    )
    parser.add_argument(
        "--scale",
        choices=SCALE_POLICIES,
        default="none",
        help="scaling policy (default: %(default)s)",
    )
    parser.add_argument(
        "--unit",
        choices=UNITS,
        default="component",
        help="select components, or records with both components",
    )
    parser.add_argument("--confirm", action="store_true", help="confirm by simulation")
    parser.add_argument("--options", metavar="TOML", help="a file with a [selection] table")
    parser.add_argument(
        "--metadata",
        metavar="CSV",
        help="catalogue metadata joined on column 'file' (for the filters)",
    )
    parser.add_argument("--jobs", type=int, help="worker processes (default: all CPUs)")
    band = parser.add_argument_group("the frame's band")
    band.add_argument("--a-max-m", type=positive_float, help="amplitude limit A_max [m]")
    band.add_argument(
        "--design",
        metavar="CASE.toml",
        help="quasi-dynamic design input: A_max = design displacement δ*",
    )
    band.add_argument(
        "--x-star-fraction",
        type=positive_float,
        default=0.8,
        help="A_max = fraction·x* otherwise (default: %(default)s)",
    )
    band.add_argument(
        "--strong-motion-fraction",
        type=positive_float,
        default=0.3,
        help="strong motion: I_g ≥ fraction of its peak (default: %(default)s)",
    )
    filters = parser.add_argument_group("filters and caps")
    for name, unit in (
        ("magnitude", ""),
        ("distance", "_km"),
        ("vs30", "_m_s"),
        ("d5_95", "_s"),
        ("pga", "_g"),
    ):
        for end in ("min", "max"):
            flag = f"--{name.replace('_', '-')}-{end}{unit.replace('_', '-')}"
            filters.add_argument(flag, dest=f"{name}_{end}{unit}", type=float)
    filters.add_argument("--distance-metric", choices=DISTANCE_METRICS, default="rrup")
    filters.add_argument(
        "--lowest-usable-below-band",
        action="store_true",
        help="drop records whose lowest usable frequency is above the band",
    )
    filters.add_argument(
        "--keep-implausible",
        action="store_true",
        help="rank fits that fail the plausibility checks too",
    )
    filters.add_argument(
        "--exclude",
        action="append",
        default=[],
        metavar="FILE_OR_RSN",
        help="leave out (repeat, or comma-separated)",
    )
    filters.add_argument("--max-per-event", type=int)
    filters.add_argument("--max-per-station", type=int)
    spectral = parser.add_argument_group("target spectrum and scaling")
    spectral.add_argument("--target-s-ds-g", type=positive_float, help="two-period S_DS [g]")
    spectral.add_argument("--target-s-d1-g", type=positive_float, help="two-period S_D1 [g]")
    spectral.add_argument("--target-csv", metavar="CSV", help="tabulated target: period_s,sa_g")
    spectral.add_argument("--target-periods-s", type=float_list, metavar="LOW,HIGH")
    spectral.add_argument("--spectral-weight", type=float, default=0.0)
    spectral.add_argument("--scale-min", type=positive_float, default=0.25)
    spectral.add_argument("--scale-max", type=positive_float, default=4.0)
    rest = parser.add_argument_group("uncertainty and confirmation")
    rest.add_argument("--n-bootstrap", type=int, default=10)
    rest.add_argument("--seed", type=int, default=0)
    rest.add_argument(
        "--confirm-onset-ratio",
        type=positive_float,
        default=1.0,
        help="equal intensity: P_1·SD(T_1)/x_c of every record (default 1)",
    )
    add_record_options(parser)


def options_from_args(args: argparse.Namespace) -> Any:
    """The :class:`SelectionOptions` of the command line (over an optional [selection] file)."""
    from stepframe.core.io import read_toml
    from stepframe.pipeline.selection.options import SelectionOptions

    values: dict[str, Any] = {}
    if args.options:
        data, _ = read_toml(args.options, "a TOML file with a [selection] table")
        table = data.get("selection")
        if not isinstance(table, dict):
            raise InputError("no [selection] table, expected one", args.options)
        values.update(table)
    defaults = _parser_defaults()
    for name in _DIRECT:
        value = getattr(args, name)
        if value is not None and (name not in values or value != defaults.get(name)):
            values[name] = value
    values["n"] = args.n
    if args.confirm:
        values["confirm"] = True
    if args.keep_implausible:
        values["require_plausible"] = False
    if args.lowest_usable_below_band:
        values["lowest_usable_below_band"] = True
    exclude = [word.strip() for item in args.exclude for word in item.split(",") if word.strip()]
    if exclude:
        values["exclude"] = exclude
    if args.target_periods_s is not None:
        values["target_periods_s"] = args.target_periods_s
    if args.design:
        values["design_displacement_m"] = design_displacement_m(args.design)
    return SelectionOptions.from_dict(values, where=args.options or "selection options")


def _parser_defaults() -> dict[str, Any]:
    return {
        "rank_by": "backbone_amplification",
        "scale": "none",
        "unit": "component",
        "spectral_weight": 0.0,
        "x_star_fraction": 0.8,
        "strong_motion_fraction": 0.3,
        "n_bootstrap": 10,
        "seed": 0,
        "distance_metric": "rrup",
        "scale_min": 0.25,
        "scale_max": 4.0,
        "confirm_onset_ratio": 1.0,
    }


def design_displacement_m(path: str) -> float:
    """δ* of a quasi-dynamic design input file (closed form for a two-period spectrum)."""
    from stepframe.structure.design_spectrum import TwoPeriodSpectrum
    from stepframe.structure.quasi_dynamic import design_displacement, read_case

    case = read_case(path)
    if isinstance(case.spectrum, TwoPeriodSpectrum):
        result = design_displacement(case.stepping_map, case.spectrum, "closed-form")
    else:
        result = design_displacement(case.stepping_map, case.spectrum, "search")
    if result.delta_m is None or not result.delta_m > 0:
        raise InputError(
            f"the design gives no positive design displacement (status {result.status}), "
            "expected one to bound the band (or give --a-max-m)",
            path,
        )
    return float(result.delta_m)


def run(args: argparse.Namespace) -> CommandResult:
    """Features of the catalogue, selection, optional confirmation; tables in OUTDIR."""
    from stepframe.pipeline.selection.inputs import select_from_catalogue
    from stepframe.pipeline.selection.spectral import target_spectrum
    from stepframe.structure.frame_file import read_frame_file

    frame = read_frame_file(args.frame)
    options = options_from_args(args)
    target_spectrum(options)  # an unreadable target is reported before the features are run
    out_dir = Path(args.out_dir)
    if out_dir.exists() and not out_dir.is_dir():
        raise InputError("exists and is not a directory, expected an output folder", out_dir)
    if args.jobs is not None and args.jobs < 1:
        raise InputError(f"--jobs {args.jobs}, expected ≥ 1")
    result = select_from_catalogue(
        frame,
        options,
        example=args.example is not None,
        catalogue=args.catalogue,
        metadata=args.metadata,
        record_options=_record_options(args),
        jobs=args.jobs,
    )
    paths = result.write(out_dir)
    data = result.to_dict()
    data["outputs"] = {name: str(path) for name, path in paths.items()}
    return CommandResult(data=data, text=summary_text(result, paths["selection"].parent))


def _record_options(args: argparse.Namespace) -> dict[str, Any]:
    # The shared record options (read limits included), without the unset ones.
    return {k: v for k, v in record_options(args).items() if v is not None}


def summary_text(result: Any, out_dir: Path) -> str:
    """A short human summary: band, chosen records, the confirmation's correlation, outputs."""
    low, high = result.band_rad_s
    lines = [
        f"band: {low:.3g} to {high:.3g} rad/s (T {6.2832 / high:.3g} to {6.2832 / low:.3g} s); "
        f"{result.summary['filter_summary']}",
        f"chosen by {result.summary['rank_by']} ({result.status}: {result.message}):",
    ]
    for row in result.selection.itertuples():
        name = str(row.file).rsplit("/", 1)[-1]
        lines.append(
            f"  {row.rank:2d}. {name} [{row.component}]  score {row.score:.4g}  "
            f"scale {row.scale_factor:.3g}  P(in set) {row.selection_probability:.2f}"
        )
    for entry in result.summary.get("correlations", []):
        if entry["score"] == result.summary["rank_by"]:
            lines.append(
                f"confirmation: Spearman({entry['score']}, {entry['response']}) = "
                f"{entry['spearman']:.2f} [{entry['low']:.2f}, {entry['high']:.2f}], "
                f"n = {entry['n']}"
            )
    medians = result.summary.get("medians") or {}
    if medians:
        lines.append(
            "median peak |x| at equal PSA(T_1): selected "
            f"{medians['equal_psa_t1_peak_x_m_selected']:.3g} m, controls "
            f"{medians['equal_psa_t1_peak_x_m_control']:.3g} m"
        )
    lines.append(
        f"outputs: {out_dir}/ (selection.csv, candidates.csv, confirmation.csv, "
        "failures.csv, columns.csv, selection.json)"
    )
    return "\n".join(lines)
