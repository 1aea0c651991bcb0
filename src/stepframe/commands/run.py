"""``stepframe run WORKFLOW``: run a workflow file incrementally (:mod:`stepframe.pipeline`).

Exit status: 0 every requested output produced (failed items listed), 1 an output could not be
produced, 2 a user error (nothing written), 3 another run holds the workspace.
"""

from __future__ import annotations

import argparse
import json
import sys
from typing import Any

from stepframe.commands import CommandResult, add_command, to_jsonable
from stepframe.errors import InputError

EXIT_OUTPUT_MISSING = 1
EXIT_BUSY = 3

EXAMPLES = """\
  stepframe run --template > my-scene.toml          a commented workflow to edit
  stepframe run workflows/site-amplification.toml   the paper's site: model and amplification
  stepframe run workflows/selection.toml --dry-run  what would be computed, and what is cached
  stepframe run workflows/inbox.toml --wait --json  a scheduled run over the record files put in
                                                    workflows/inbox/ (waits for a running one)
  stepframe run workflows/selection.toml --scheduler dask-local --jobs 2
"""


def register(subparsers: Any) -> None:
    """Add ``run`` to the top-level commands."""
    parser = add_command(
        subparsers,
        "run",
        help="run a workflow file: only the stages its outputs need, cached by content",
        description=(
            "Run the stages a workflow's [outputs] need. Results are cached in the workspace "
            "by the content of their inputs and their parameters: a re-run computes only new "
            "or changed items. Exit 0: outputs produced; 1: an output could not be produced; "
            "2: user error; 3: another run holds the workspace."
        ),
        examples=EXAMPLES,
        run=run,
    )
    parser.add_argument("workflow", nargs="?", metavar="WORKFLOW.toml", help="the workflow file")
    parser.add_argument(
        "--template", action="store_true", help="print a commented workflow file and exit"
    )
    parser.add_argument(
        "--dry-run", action="store_true", help="print the plan: items to compute and cached"
    )
    parser.add_argument(
        "--jobs", type=int, default=None, metavar="N", help="worker processes (default: all CPUs)"
    )
    parser.add_argument(
        "--scheduler",
        default=None,
        metavar="WHERE",
        help="dask-local (a local Dask cluster) or tcp://HOST:PORT (an existing one); "
        "needs pip install 'stepframe[dask]'",
    )
    parser.add_argument(
        "--force", action="append", default=[], metavar="STAGE", help="recompute a stage"
    )
    parser.add_argument(
        "--retry-failed", action="store_true", help="recompute items that failed before"
    )
    parser.add_argument(
        "--wait", action="store_true", help="wait for a run holding the workspace (else exit 3)"
    )
    parser.add_argument(
        "--batch-items",
        type=int,
        default=None,
        metavar="N",
        help="items stored per batch (default 1024, or 32 per worker if more): a killed run "
        "loses at most one batch",
    )


def run(args: argparse.Namespace) -> CommandResult:
    """Run the workflow; exits 1 or 3 itself (after printing) when the run says so."""
    from stepframe.pipeline.lock import WorkspaceBusy
    from stepframe.pipeline.runner import describe, run_workflow
    from stepframe.pipeline.workflow import workflow_template

    as_json = bool(getattr(args, "json", False))
    if args.template:
        text = workflow_template()
        return CommandResult(data={"template": text}, text=text.rstrip("\n"))
    if args.workflow is None:
        raise InputError("no workflow file given, expected stepframe run WORKFLOW.toml")
    try:
        report = run_workflow(
            args.workflow,
            jobs=args.jobs,
            scheduler=args.scheduler,
            force=args.force,
            retry_failed=args.retry_failed,
            dry_run=args.dry_run,
            wait=args.wait,
            progress=not as_json,
            batch_items=args.batch_items,
        )
    except WorkspaceBusy as busy:
        print(f"stepframe: error: {busy}", file=sys.stderr)
        raise SystemExit(EXIT_BUSY) from None
    data = report.to_dict()
    if report.exit_code != 0:
        if as_json:
            print(json.dumps(to_jsonable(data), indent=2, allow_nan=False))
        else:
            print(describe(report))
        raise SystemExit(EXIT_OUTPUT_MISSING)
    return CommandResult(data=data, text=describe(report))
