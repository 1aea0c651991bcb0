"""``stepframe demo``: the main job, as the shipped workflow ``stepframe run selection``.

Record selection by moving resonance (docs/selection.md) on the 100 FEMA P695 components with the
paper's Example 4 frame, confirmed by simulation, ending in the selection report; the workspace
and the outputs are the demo's folder (:mod:`stepframe.pipeline.demo`). Exit status as
``stepframe run``: 0 done, 1 an output could not be produced, 2 a user error, 3 another run holds
the folder.
"""

from __future__ import annotations

import argparse
import json
import sys
from typing import Any

from stepframe.commands import CommandResult, add_command, to_jsonable
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
    from stepframe.pipeline.demo import run_demo
    from stepframe.pipeline.lock import WorkspaceBusy

    as_json = bool(getattr(args, "json", False))
    try:
        demo = run_demo(args.out_dir, jobs=args.jobs, progress=not as_json)
    except WorkspaceBusy as busy:
        print(f"stepframe: error: {busy}", file=sys.stderr)
        raise SystemExit(3) from None
    if demo.exit_code != 0:
        data = demo.to_dict()
        print(json.dumps(to_jsonable(data), indent=2) if as_json else demo.text())
        raise SystemExit(demo.exit_code)
    return CommandResult(data=demo.to_dict(), text=demo.text())
