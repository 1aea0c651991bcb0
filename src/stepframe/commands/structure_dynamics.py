"""Commands of ``stepframe structure``: ``harmonic``, ``bifurcation`` and ``ida``.

The studies are :mod:`stepframe.pipeline.dynamics`; this module parses and prints.
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from stepframe.commands import (
    REQUIRED,
    CommandResult,
    add_command,
    add_options,
    add_record_options,
    check_plot,
    float_range,
    non_negative_float,
    positive_float,
    positive_floats,
    positive_int,
    read_record_file,
    save_plot,
)

if TYPE_CHECKING:
    from stepframe.commands import Subparsers

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
    add_options(
        harmonic,
        ("--amplitude-g", non_negative_float, "R", "amplitude A/g [-] (g = 9.81 m/s²)", REQUIRED),
        ("--omega-rad-s", positive_float, "W", "forcing circular frequency [rad/s]", REQUIRED),
        ("--periods", positive_int, "N", "forcing periods simulated (default 100)", 100),
        ("--x0-m", float, None, "initial x [m]", 0.0),
        ("--v0-m-s", float, None, "initial ẋ [m/s]", 0.0),
        ("--orbit", positive_int, "N", "find the period-N orbit from the final state"),
        ("--plot", None, "OUT.png", "phase portrait"),
    )
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
    add_options(
        bif,
        (
            "--omega-rad-s",
            positive_float,
            "W",
            "forcing circular frequency [rad/s] (sweeping --amplitudes-g)",
        ),
        ("--amplitudes-g", float_range, "LO,HI,N", "N amplitudes from LO to HI [g]"),
        (
            "--amplitude-g",
            non_negative_float,
            "R",
            "forcing amplitude [g] (sweeping --omegas-rad-s)",
        ),
        ("--omegas-rad-s", float_range, "LO,HI,N", "N circular frequencies from LO to HI [rad/s]"),
        (
            "--initial",
            positive_int,
            "N",
            "initial states (seeded, spread over |x| < x*; default 50)",
            50,
        ),
        ("--periods", positive_int, "N", "forcing periods per run (default 100)", 100),
        ("--jobs", positive_int, None, "worker processes (default: all cores)"),
        ("--plot", None, "OUT.png", "draw the diagram"),
    )
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
    add_options(
        ida,
        ("--fema-p695", positive_int, "N", "use the first N of the embedded FEMA P695 components"),
        ("--pulse", ("cosine", "sine"), None, "one-cycle pulse instead"),
        (
            "--omega-rad-s",
            positive_floats,
            "W1,W2",
            "pulse circular frequencies [rad/s] (with --pulse)",
        ),
        (
            "--resolution-g",
            positive_float,
            "D",
            "width of each traced outcome change (default 0.01)",
            0.01,
        ),
        ("--max-g", positive_float, "S", "largest intensity hunted (default 5)", 5.0),
        (
            "--tail-s",
            non_negative_float,
            "T",
            "free vibration after each record [s] (default 10)",
            10.0,
        ),
        ("--plot", None, "OUT.png", "draw the IDA curves"),
    )
    add_record_options(ida)


def _frame_options(parser: argparse.ArgumentParser) -> None:
    group = parser.add_mutually_exclusive_group(required=True)
    add_options(
        group,
        ("--frame", None, "FRAME.toml", "frame file (see frame-template)"),
        (
            "--block",
            positive_floats,
            "B,H",
            "Housner's rigid block of half-width B and half-height H [m]",
        ),
    )


def run_harmonic(args: argparse.Namespace) -> CommandResult:
    """Simulate, optionally find an orbit, summarise."""
    from stepframe.pipeline.dynamics import frame_or_block, harmonic_study

    check_plot(args.plot)
    study = harmonic_study(
        frame_or_block(args.frame, args.block), args.amplitude_g, args.omega_rad_s,
        periods=args.periods, x0_m=args.x0_m, v0_m_s=args.v0_m_s, orbit=args.orbit,
    )  # fmt: skip
    return save_plot(CommandResult(study.to_dict(), study.describe()), args.plot, study.figure)


def run_bifurcation(args: argparse.Namespace) -> CommandResult:
    """Brute-force diagram over amplitudes or frequencies; summary per value."""
    from stepframe.pipeline.dynamics import bifurcation_sweep, frame_or_block

    check_plot(args.plot)
    sweep = bifurcation_sweep(
        frame_or_block(args.frame, args.block), omega_rad_s=args.omega_rad_s,
        amplitudes_g=args.amplitudes_g, amplitude_g=args.amplitude_g,
        omegas_rad_s=args.omegas_rad_s, initial=args.initial, periods=args.periods,
        jobs=args.jobs,
    )  # fmt: skip
    return save_plot(CommandResult(sweep.to_dict(), sweep.describe()), args.plot, sweep.figure)


def run_ida(args: argparse.Namespace) -> CommandResult:
    """Hunt-trace-fill over records or pulses."""
    from stepframe.pipeline.dynamics import frame_or_block, ida_study

    check_plot(args.plot)
    frame = frame_or_block(args.frame, args.block)
    study = ida_study(
        frame, records=[(path, read_record_file(path, args)) for path in args.records],
        fema_p695=args.fema_p695, pulse=args.pulse, omegas_rad_s=args.omega_rad_s,
        resolution_g=args.resolution_g, max_g=args.max_g, tail_s=args.tail_s,
    )  # fmt: skip
    return save_plot(CommandResult(study.to_dict(), study.describe()), args.plot, study.figure)
