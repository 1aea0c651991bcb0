"""``stepframe demo``: the main job, as the shipped workflow ``stepframe run selection``.

Record selection by moving resonance (docs/selection.md) on the 100 FEMA P695 components with the
paper's Example 4 frame, confirmed by simulation, ending in the selection report; the workspace
and the outputs are the demo's folder (:mod:`stepframe.pipeline.demo`). Exit status as
``stepframe run``: 0 done, 1 an output could not be produced, 2 a user error, 3 another run holds
the folder.
"""

from __future__ import annotations

import argparse
import functools
from typing import Any

from stepframe.commands import CommandResult, add_command, workflow_result
from stepframe.core.options import add_fields, add_options
from stepframe.pipeline.run_options import RunOptions


def register(subparsers: Any) -> None:
    """Add ``demo`` to the top-level commands."""
    parser = add_command(
        subparsers,
        "demo",
        help="select records by moving resonance for the paper's Example 4 frame from the "
        "embedded FEMA P695 records, and confirm by simulation (stepframe run selection)",
        examples="  stepframe demo\n  stepframe demo -o results --json\n",
        run=run,
    )
    add_options(
        parser,
        (("-o", "--out-dir"), None, "DIR", "workspace and outputs; a second run reuses it "
         "(default: %(default)s)", "stepframe-demo"),
    )  # fmt: skip
    add_fields(parser, RunOptions, ["jobs"])


def run(args: argparse.Namespace) -> CommandResult:
    """Run the shipped selection workflow into the folder; print its summary."""
    from stepframe.pipeline.demo import DemoRun, run_demo

    as_json = bool(getattr(args, "json", False))
    call = functools.partial(run_demo, args.out_dir, jobs=args.jobs, progress=not as_json)
    return workflow_result(call, DemoRun.text, as_json)
