"""``stepframe run WORKFLOW``: run a workflow file incrementally (:mod:`stepframe.pipeline`).

Exit status: 0 every requested output produced (failed items listed), 1 an output could not be
produced, 2 a user error (nothing written), 3 another run holds the workspace.
"""

from __future__ import annotations

import argparse
import functools
from typing import Any

from stepframe.commands import CommandResult, add_command, workflow_result
from stepframe.core.options import add_fields, add_options, fields_given
from stepframe.errors import InputError
from stepframe.pipeline.run_options import RunOptions

EXAMPLES = """\
  stepframe run --template > my-scene.toml          a commented workflow to edit
  stepframe run site-amplification                  a shipped workflow: the paper's site
  stepframe run selection --dry-run                 what would be computed, and what is cached
  stepframe run inbox --copy my-inbox               copy a shipped workflow to edit or schedule
  stepframe run my-inbox/inbox.toml --wait --json   a scheduled run over the record files put in
                                                    my-inbox/inbox/ (waits for a running one)
  stepframe run selection --scheduler dask-local --jobs 2
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
    parser.add_argument(
        "workflow",
        nargs="?",
        metavar="WORKFLOW",
        help="a workflow file, or the name of a shipped one (selection, site-amplification, ...)",
    )
    add_options(
        parser,
        ("--copy", None, "DIR", "copy the shipped workflow into DIR (to edit) and exit"),
        ("--template", bool, None, "print a commented workflow file and exit"),
    )
    add_fields(parser, RunOptions)


def run(args: argparse.Namespace) -> CommandResult:
    """Run the workflow; exits 1 or 3 itself (after printing) when the run says so."""
    from stepframe.pipeline.run_options import run_with_options
    from stepframe.pipeline.runner import describe
    from stepframe.pipeline.workflow import workflow_template

    as_json = bool(getattr(args, "json", False))
    if args.template:
        text = workflow_template()
        return CommandResult(data={"template": text}, text=text.rstrip("\n"))
    if args.workflow is None:
        raise InputError("no workflow given, expected stepframe run WORKFLOW.toml or a name")
    if args.copy is not None:
        from stepframe.pipeline.shipped import copy_workflow

        copied = copy_workflow(args.workflow, args.copy)
        return CommandResult(data={"copied": copied}, text="\n".join(map(str, copied)))
    options = RunOptions(**fields_given(args, RunOptions))
    call = functools.partial(run_with_options, args.workflow, options, progress=not as_json)
    return workflow_result(call, describe, as_json)
