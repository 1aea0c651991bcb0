"""``stepframe structure``: ``design`` (:mod:`stepframe.pipeline.dynamics.design`), ``simulate`` one
record (:mod:`stepframe.pipeline.dynamics.response`), ``frame-template``, and the dynamics studies
``harmonic``, ``bifurcation``, ``ida`` (:mod:`stepframe.pipeline.dynamics.studies`)."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from stepframe.commands import CommandResult, add_command, add_record_options
from stepframe.core.options import add_fields, fields_given, options_from
from stepframe.errors import InputError
from stepframe.pipeline.dynamics import design, studies
from stepframe.pipeline.dynamics.response import SimulatedComponent, SimulateOptions, simulate_file
from stepframe.pipeline.dynamics.studies import (
    BifurcationOptions,
    FrameSource,
    HarmonicOptions,
    IdaOptions,
)
from stepframe.records.read_options import RecordSource

if TYPE_CHECKING:
    from stepframe.commands import Subparsers

#: The DesignOptions fields per help group of ``design`` (after --input and --template).
DESIGN_GROUPS = {
    "pier (override [pier] of --input)": design.PIER_KEYS,
    "two-period spectrum (override [spectrum])": design.SPECTRUM_KEYS,
    "damping (override [damping]; one of --beta/--xi/--c-r)": (
        *design.DAMPING_KEYS,
        "damping_method",
    ),
    "map constants instead of a pier (override [map])": design.MAP_KEYS,
}


def register(subparsers: Subparsers) -> None:
    """Add the ``structure`` commands to ``subparsers``."""
    design_parser = add_command(
        subparsers, "design", run_design, plot="draw the cobweb of the iteration"
    )
    add_fields(design_parser, design.DesignOptions, [
        "input", ("--template", bool, None, "print a commented input file and exit"),
    ])  # fmt: skip
    for title, names in DESIGN_GROUPS.items():
        add_fields(design_parser.add_argument_group(title), design.DesignOptions, names)
    add_fields(design_parser, design.DesignOptions, [
        "branch", ("--trace", bool, None, "print every iterate (i, δ, K, T)"),
        "delta0_m", "method", "max_iterations",
    ])  # fmt: skip
    simulate = add_command(
        subparsers, "simulate", run_simulate,
        plot="draw x(t) with the phases, and ω_f(t) over the record's spectrum",
    )  # fmt: skip
    simulate.add_argument(
        "record", nargs="?", metavar="RECORD", help="accelerogram file, one component, or --example"
    )
    add_fields(simulate, SimulateOptions)
    add_record_options(simulate)
    add_command(subparsers, "frame-template", run_frame_template)
    harmonic = add_command(subparsers, "harmonic", run_harmonic, plot="phase portrait")
    bif = add_command(subparsers, "bifurcation", run_bifurcation, plot="draw the diagram")
    ida = add_command(subparsers, "ida", run_ida, plot="draw the IDA curves")
    for parser, options in (
        (harmonic, HarmonicOptions),
        (bif, BifurcationOptions),
        (ida, IdaOptions),
    ):
        add_fields(parser.add_mutually_exclusive_group(required=True), FrameSource)
        if parser is ida:
            parser.add_argument("records", nargs="*", metavar="RECORD", help="accelerogram files")
        add_fields(parser, options)
    add_record_options(ida)


def run_design(args: argparse.Namespace) -> CommandResult:
    """Quasi-dynamic design displacement: fixed points, stability, iteration, SE.

    Inputs come from a TOML file (--input, see --template) or from options; options given on
    the command line override the file's values. The command prints the map constants (w, λ_1,
    λ_2), the closed-form fixed points δ_1*..δ_4* (eqs. 2.9, 2.14) with their multipliers,
    stability and branch check, the fixed points of the full map found numerically, the traced
    AASHTO/Priestley iteration from each start, and the design answer δ*, T* and stepping
    effectiveness SE.

    Examples
    --------
    # Example 2 of the paper (two-column steel frame), β = 0.8, W_col = 0 (the paper leaves it out):
    stepframe structure design --weight-super-n 1.472e6 --weight-col-n 0 \\
        --weight-total-n 2.807e6 --footing-length-m 8.839 --block-width-m 1.166 \\
        --height-m 29.944 --sds-g 1.038 --sd1-g 0.456 --beta 0.8 --delta0-m 0.00254,0.3048
    # The paper's Table 1 (Example 2, caption constants, long-branch formula forced), full trace:
    stepframe structure design --w-per-m 0.136737 --lambda-2-sqrt-m 0.381964 --sds-g 1.038 \\
        --sd1-g 0.456 --beta 0.8 --delta0-m 0.00254,0.3048 --branch long --max-iterations 19 --trace
    # From a file, β from the velocity ratio at impact (eq. 4.17, Eurocode 8 reduction):
    stepframe structure design --template > pier.toml
    stepframe structure design --input pier.toml --c-r 0.9 --plot cobweb.png --json
    """
    if args.template:
        # the template is printed alone: an option beside it would be ignored (no design runs)
        import dataclasses

        declared = {
            f.name: f.metadata.get("flag") for f in dataclasses.fields(design.DesignOptions)
        }
        given = [declared[name] or name for name in fields_given(args, design.DesignOptions)]
        given += [name for name in ("plot", "trace") if getattr(args, name)]
        if given:
            flags = ", ".join(
                name if name.startswith("--") else "--" + name.replace("_", "-") for name in given
            )
            raise InputError(
                f"--template with {flags}, expected --template alone (it prints the input file "
                "and runs nothing)"
            )
        text = design.DESIGN_TEMPLATE
        return CommandResult({"template": text}, text.rstrip("\n"))
    result = design.design_run(options_from(args, design.DesignOptions))
    return CommandResult(result.to_dict(), result.describe(trace_rows=args.trace), result.figure)


def run_frame_template(args: argparse.Namespace) -> CommandResult:
    """Print a commented FRAME.toml (the paper's Example 4 frame).

    Examples
    --------
    stepframe structure frame-template > FRAME.toml     then edit FRAME.toml
    """
    from stepframe.structure.frame_file import frame_template

    text = frame_template()
    return CommandResult(data={"frame_toml": text}, text=text.rstrip("\n"))


def run_simulate(args: argparse.Namespace) -> SimulatedComponent:
    """Stepping response of a frame to one record (exact piecewise-analytic).

    Integrate the stepping portal frame of FRAME.toml (eqs. 4.11-4.12 with impact at
    touchdown) exactly under RECORD times --scale, then a free-vibration tail; report peaks,
    stepping episodes, impacts, residual displacement, overturning and the moving-resonance
    index (how much of the ground's work arrived while the record's energy lay near the frame's
    own frequency as it stepped down its band; docs/selection.md). --plot draws x(t) and, below,
    the frame's frequency ω_f(t) over the record's spectrum with the ground's work.

    Examples
    --------
    stepframe structure frame-template > FRAME.toml
    stepframe structure simulate --frame FRAME.toml RSN8883_14383980_13849360.AT2 --scale 6
    stepframe structure simulate --frame FRAME.toml --example fema-p695 --component MUL009 --scale 2
    stepframe structure simulate --frame FRAME.toml RSN8883_14383980_13849360.AT2 --scale 6 \\
        --tail-s 30 --json --plot response.png
    """
    source = options_from(args, RecordSource)
    return simulate_file(
        options_from(args, SimulateOptions), lambda: source.read(args.record),
        name=source.name(args.record), figure=args.plot is not None,
    )  # fmt: skip


def run_harmonic(args: argparse.Namespace) -> studies.HarmonicStudy:
    """Response to harmonic ground acceleration (closed form), periodic orbits.

    Integrate the frame under ground acceleration A cos(ωt) in closed form (no sampling error)
    from rest or a given state; with --orbit N, find the period-N orbit by Newton on the
    stroboscopic map from the final state and report its Floquet multipliers.

    Examples
    --------
    stepframe structure harmonic --frame FRAME.toml --amplitude-g 0.25 --omega-rad-s 7.854
    stepframe structure harmonic --block 0.25,1.0 --amplitude-g 0.3 --omega-rad-s 16 \\
        --periods 200 --orbit 1 --json --plot portrait.png
    """
    frame = options_from(args, FrameSource).portal_frame()
    return studies.harmonic_study(frame, options_from(args, HarmonicOptions))


def run_bifurcation(args: argparse.Namespace) -> studies.BifurcationSweep:
    """Brute-force bifurcation diagram over the forcing amplitude (all cores).

    For every amplitude and every initial state, iterate the stroboscopic map for --periods
    forcing periods and keep the last 20 points; report the fraction of initial states that
    overturn and the orbit periods found.

    Examples
    --------
    stepframe structure bifurcation --frame FRAME.toml --omega-rad-s 7.854 \\
        --amplitudes-g 0.05,0.5,200 --initial 50 --periods 100 --plot diagram.png
    stepframe structure bifurcation --block 0.25,1.0 --amplitude-g 0.3 --omegas-rad-s 5,40,100
    """
    frame = options_from(args, FrameSource).portal_frame()
    return studies.bifurcation_sweep(
        frame, options_from(args, BifurcationOptions), figure=args.plot is not None
    )


def run_ida(args: argparse.Namespace) -> studies.IdaStudy:
    """Incremental dynamic analysis by hunt-trace-fill, with resurrection detection.

    Raise each record's PGA until the frame overturns, trace every change of outcome to
    --resolution-g, probe up to --probe-factor times the first overturning (--probes evenly
    spaced; default 2 and 8) for resurrection, and report the overturning PGA per record with
    fractiles. With --pulse, the items are one-cycle pulses at each --omega-rad-s, intensities
    are in units of the static uplift acceleration γ₁/P₂, and the probes reach 10 times the
    first overturning (16 probes), where a pulse's survival band lies.

    Examples
    --------
    stepframe structure ida --frame FRAME.toml --fema-p695 100 --resolution-g 0.001 --plot ida.png
    stepframe structure ida --frame FRAME.toml RSN8883_14383980_13849360.AT2 --json
    stepframe structure ida --block 0.25,1.0 --pulse cosine --omega-rad-s 10.6,16
    """
    frame, source = options_from(args, FrameSource).portal_frame(), options_from(args, RecordSource)
    unread = source.given_flags() + ([f"--example {source.example}"] if source.example else [])
    if unread and not args.records:
        raise InputError(
            f"{', '.join(unread)} without RECORD files, expected record options only with "
            "RECORD files (the embedded catalogue: --fema-p695 N)"
        )
    records = [(path, source.read(path)) for path in args.records]
    return studies.ida_study(frame, options_from(args, IdaOptions), records)
