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
from stepframe.core.options import add_fields, fields_given
from stepframe.pipeline.design import (
    DAMPING_KEYS,
    DESIGN_TEMPLATE,
    MAP_KEYS,
    PIER_KEYS,
    SPECTRUM_KEYS,
    DesignOptions,
    design_run,
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


#: The DesignOptions fields per help group (after --input and --template).
GROUPS = {
    "pier (override [pier] of --input)": PIER_KEYS,
    "two-period spectrum (override [spectrum])": SPECTRUM_KEYS,
    "damping (override [damping]; one of --beta/--xi/--c-r)": (*DAMPING_KEYS, "damping_method"),
    "map constants instead of a pier (override [map])": MAP_KEYS,
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
    add_fields(parser, DesignOptions, [
        "input", ("--template", bool, None, "print a commented input file and exit"),
    ])  # fmt: skip
    for title, names in GROUPS.items():
        add_fields(parser.add_argument_group(title), DesignOptions, names)
    add_fields(parser, DesignOptions, [
        "branch", ("--trace", bool, None, "print every iterate (i, δ, K, T)"),
        "delta0_m", "method", "max_iterations",
        ("--plot", None, "OUT.png", "draw the cobweb of the iteration"),
    ])  # fmt: skip


def run(args: argparse.Namespace) -> CommandResult:
    """Compute and report the design displacement."""
    if args.template:
        return CommandResult({"template": DESIGN_TEMPLATE}, DESIGN_TEMPLATE.rstrip("\n"))
    check_plot(args.plot)
    result = design_run(DesignOptions(**fields_given(args, DesignOptions)))
    text = result.describe(trace_rows=args.trace)
    return save_plot(CommandResult(result.to_dict(), text), args.plot, result.figure, "cobweb")
