"""``stepframe structure design``: quasi-dynamic design displacement of a stepping pier (Part 1).

Inputs come from a TOML file (``--input``, see ``--template``) or from options; options given on
the command line override the file's values. The command prints the map constants (w, λ_1, λ_2),
the closed-form fixed points δ_1*..δ_4* (eqs. 2.9, 2.14) with their multipliers, stability and
branch check, the fixed points of the full map found numerically, the traced AASHTO/Priestley
iteration from each start, and the design answer δ*, T* and stepping effectiveness SE.
"""

# The work is done by stepframe.pipeline.design; this module parses and prints.

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from stepframe.commands import CommandResult, add_command, check_plot, save_plot
from stepframe.core.options import add_options, float_list, positive_float
from stepframe.pipeline.design import (
    DAMPING_KEYS,
    DESIGN_TEMPLATE,
    MAP_KEYS,
    PIER_KEYS,
    design_case,
    run_design,
)

if TYPE_CHECKING:
    from stepframe.commands import Subparsers

EXAMPLES = """\
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


_SPECTRUM_OPTIONS = {
    "s_ds_g": ("--sds-g", "S_DS [g]"),
    "s_ds_m_s2": ("--sds-m-s2", "S_DS [m/s²]"),
    "s_d1_g": ("--sd1-g", "S_D1 [g]"),
    "s_d1_m_s": ("--sd1-m-s", "S_D1 [m/s]"),
    "t_l_s": ("--tl-s", "long-period transition T_L [s]"),
}


def register(subparsers: Subparsers) -> None:
    """Add ``design`` to the ``structure`` group."""
    parser = add_command(
        subparsers,
        "design",
        help="quasi-dynamic design displacement: fixed points, stability, iteration, SE",
        description=__doc__.split("\n\n", 1)[1].strip() if __doc__ else None,
        examples=EXAMPLES,
        run=run,
    )
    add_options(
        parser,
        ("--input", None, "TOML", "design input file (see --template)"),
        ("--template", bool, None, "print a commented input file and exit"),
    )
    pier = parser.add_argument_group("pier (override [pier] of --input)")
    for key, text in PIER_KEYS.items():
        pier.add_argument("--" + key.replace("_", "-"), dest=key, type=float, help=text)
    spectrum = parser.add_argument_group("two-period spectrum (override [spectrum])")
    for key, (flag, text) in _SPECTRUM_OPTIONS.items():
        spectrum.add_argument(flag, dest=key, type=positive_float, help=text)
    add_options(
        parser.add_argument_group("damping (override [damping]; one of --beta/--xi/--c-r)"),
        ("--beta", positive_float, None, "spectral reduction factor β"),
        ("--xi", float, None, "equivalent viscous damping ratio (fraction)"),
        ("--c-r", float, None, "velocity ratio at impact; ξ = 0.48(1 - C_r²)"),
        ("--damping-method", ("ec8", "ec8-1998", "aashto-isolation"), None,
         "damping-reduction formula with --xi/--c-r (default ec8)"),
    )  # fmt: skip
    add_options(
        parser.add_argument_group("map constants instead of a pier (override [map])"),
        ("--w-per-m", positive_float, None, "w of eq. 2.3 [1/m]"),
        ("--lambda-2-sqrt-m", positive_float, None, "λ_2 of eq. 2.5 [m^½] (needs S_D1)"),
    )
    add_options(
        parser,
        ("--branch", ("auto", "short", "long", "very-long"), None, "spectrum branch used by the "
         "iteration: auto (S_a at each T_i, the procedure) or one branch's formula whatever T_i "
         "is (as the paper's Table 1 does)", "auto"),
        ("--trace", bool, None, "print every iterate (i, δ, K, T)"),
        ("--delta0-m", float_list, "D,...", "starts of the iteration [m]"),
        ("--method", ("closed-form", "search"), None, "how the design answer is chosen (default: "
         "closed-form for a two-period spectrum, search for a tabulated one)"),
        ("--max-iterations", int, None, "iteration limit (default 200)", 200),
        ("--plot", None, "OUT.png", "draw the cobweb of the iteration"),
    )  # fmt: skip


def run(args: argparse.Namespace) -> CommandResult:
    """Compute and report the design displacement."""
    if args.template:
        return CommandResult({"template": DESIGN_TEMPLATE}, DESIGN_TEMPLATE.rstrip("\n"))
    check_plot(args.plot)
    names = (*PIER_KEYS, *MAP_KEYS, *_SPECTRUM_OPTIONS, *DAMPING_KEYS)
    case = design_case(
        args.input, {name: getattr(args, name) for name in names},
        damping_method=args.damping_method, delta0_m=args.delta0_m,
    )  # fmt: skip
    result = run_design(
        case, method=args.method, branch=args.branch, max_iterations=args.max_iterations
    )
    text = result.describe(trace_rows=args.trace)
    return save_plot(CommandResult(result.to_dict(), text), args.plot, result.figure, "cobweb")
