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

from stepframe.commands import CommandResult, add_command, float_list, positive_float
from stepframe.pipeline.design import PIER_KEYS

if TYPE_CHECKING:
    from stepframe.commands import Subparsers

EXAMPLES = """\
  # Example 2 of the paper (two-column steel frame), β = 0.8, W_col = 0 (the paper leaves it out):
  stepframe structure design --weight-super-n 1.472e6 --weight-col-n 0 \\
      --weight-total-n 2.807e6 --footing-length-m 8.839 --block-width-m 1.166 \\
      --height-m 29.944 --sds-g 1.038 --sd1-g 0.456 --beta 0.8 --delta0-m 0.00254,0.3048
  # The paper's Table 1 (Example 2, caption constants, long-branch formula forced), full trace:
  stepframe structure design --w-per-m 0.136737 --lambda-2-sqrt-m 0.381964 --sds-g 1.038 \
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
    parser.add_argument("--input", metavar="TOML", help="design input file (see --template)")
    parser.add_argument(
        "--template", action="store_true", help="print a commented input file and exit"
    )
    pier = parser.add_argument_group("pier (override [pier] of --input)")
    for key, text in PIER_KEYS.items():
        pier.add_argument("--" + key.replace("_", "-"), dest=key, type=float, help=text)
    spectrum = parser.add_argument_group("two-period spectrum (override [spectrum])")
    for key, (flag, text) in _SPECTRUM_OPTIONS.items():
        spectrum.add_argument(flag, dest=key, type=positive_float, help=text)
    damping = parser.add_argument_group("damping (override [damping]; one of --beta/--xi/--c-r)")
    damping.add_argument("--beta", type=positive_float, help="spectral reduction factor β")
    damping.add_argument("--xi", type=float, help="equivalent viscous damping ratio (fraction)")
    damping.add_argument(
        "--c-r", dest="c_r", type=float, help="velocity ratio at impact; ξ = 0.48(1 - C_r²)"
    )
    damping.add_argument(
        "--damping-method",
        choices=("ec8", "ec8-1998", "aashto-isolation"),
        help="damping-reduction formula with --xi/--c-r (default ec8)",
    )
    given_map = parser.add_argument_group("map constants instead of a pier (override [map])")
    given_map.add_argument("--w-per-m", type=positive_float, help="w of eq. 2.3 [1/m]")
    given_map.add_argument(
        "--lambda-2-sqrt-m", type=positive_float, help="λ_2 of eq. 2.5 [m^½] (needs S_D1)"
    )
    parser.add_argument(
        "--branch",
        choices=("auto", "short", "long", "very-long"),
        default="auto",
        help="spectrum branch used by the iteration: auto (S_a at each T_i, the procedure) or "
        "one branch's formula whatever T_i is (as the paper's Table 1 does)",
    )
    parser.add_argument("--trace", action="store_true", help="print every iterate (i, δ, K, T)")
    parser.add_argument(
        "--delta0-m", type=float_list, metavar="D,...", help="starts of the iteration [m]"
    )
    parser.add_argument(
        "--method",
        choices=("closed-form", "search"),
        default=None,
        help="how the design answer is chosen (default: closed-form for a two-period "
        "spectrum, search for a tabulated one)",
    )
    parser.add_argument(
        "--max-iterations", type=int, default=200, help="iteration limit (default 200)"
    )
    parser.add_argument("--plot", metavar="OUT.png", help="draw the cobweb of the iteration")


def run(args: argparse.Namespace) -> CommandResult:
    """Compute and report the design displacement."""
    if args.template:
        from stepframe.pipeline.design import DESIGN_TEMPLATE

        return CommandResult({"template": DESIGN_TEMPLATE}, DESIGN_TEMPLATE.rstrip("\n"))

    from stepframe.pipeline.design import DAMPING_KEYS, MAP_KEYS, design_case, run_design

    if args.plot:
        from stepframe.pipeline.figures import check_figure_path

        check_figure_path(args.plot)
    names = (*PIER_KEYS, *MAP_KEYS, *_SPECTRUM_OPTIONS, *DAMPING_KEYS)
    case = design_case(
        args.input,
        {name: getattr(args, name) for name in names},
        damping_method=args.damping_method,
        delta0_m=args.delta0_m,
    )
    result = run_design(
        case, method=args.method, branch=args.branch, max_iterations=args.max_iterations
    )
    data = result.to_dict()
    if args.plot:
        from stepframe.pipeline.figures import save_figure
        from stepframe.structure.plots import cobweb_figure

        figure = cobweb_figure(
            case.stepping_map, case.spectrum, result.traces, [*result.closed, *result.found]
        )
        save_figure(figure, args.plot)
        data["plot"] = args.plot
    text = result.describe(trace_rows=args.trace)
    if args.plot:
        text += f"\ncobweb written to {args.plot}"
    return CommandResult(data, text)
