"""``stepframe run WORKFLOW`` (a workflow file, run incrementally: :mod:`stepframe.pipeline`) and
``stepframe demo`` (the shipped workflow ``selection``: :mod:`stepframe.pipeline.demo`)."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from stepframe.commands import CommandResult, add_command
from stepframe.core.options import add_fields, add_options, fields_given, options_from
from stepframe.errors import InputError
from stepframe.pipeline.engine.run_options import RunOptions, run_with_options

if TYPE_CHECKING:
    from stepframe.commands import Subparsers
    from stepframe.pipeline.demo import DemoRun
    from stepframe.pipeline.engine.runner import RunReport


def register(subparsers: Subparsers) -> None:
    """Add ``demo`` and ``run`` to the top-level commands."""
    demo = add_command(subparsers, "demo", run_demo)
    add_options(
        demo,
        (("-o", "--out-dir"), None, "DIR", "workspace and outputs; a second run reuses it "
         "(default: %(default)s)", "stepframe-demo"),
    )  # fmt: skip
    add_fields(demo, RunOptions, ["jobs"])
    run = add_command(subparsers, "run", run_workflow)
    run.add_argument(
        "workflow",
        nargs="?",
        metavar="WORKFLOW",
        help="a workflow file, or the name of a shipped one (selection, site-amplification, ...)",
    )
    add_options(
        run,
        ("--copy", None, "DIR", "copy the shipped workflow into DIR (to edit) and exit"),
        ("--template", bool, None, "print a commented workflow file and exit"),
    )
    add_fields(run, RunOptions)


def run_demo(args: argparse.Namespace) -> DemoRun:
    """Select records by moving resonance for the paper's Example 4 frame from the embedded FEMA
    P695 records, and confirm by simulation (stepframe run selection).

    Record selection by moving resonance (docs/selection.md) on the 100 FEMA P695 components
    for the paper's Example 4 frame, confirmed by simulation and ending in the selection report:
    the shipped workflow `stepframe run selection` with the folder as its workspace and outputs.
    Exit 0: done; 1: an output could not be produced; 2: user error; 3: another run holds the
    folder.

    Examples
    --------
    stepframe demo
    stepframe demo -o results --json
    """
    from stepframe.pipeline.demo import run_demo as run

    return run(args.out_dir, jobs=args.jobs, progress=not getattr(args, "json", False))


def run_workflow(args: argparse.Namespace) -> CommandResult | RunReport:
    """Run a workflow file: only the stages its outputs need, cached by content.

    Run the stages a workflow's [outputs] need. Results are cached in the workspace by the
    content of their inputs and their parameters: a re-run computes only new or changed items,
    and every stored object is checked against its checksum (a damaged one is quarantined and
    recomputed). Each run appends one JSON line to the workspace's run log (runs.jsonl). Exit 0:
    outputs produced (failed items listed); 1: an output could not be produced, or a file could
    not be written (disk full); 2: user error (nothing written); 3: another run holds the
    workspace.

    Examples
    --------
    stepframe run --template > my-scene.toml          a commented workflow to edit
    stepframe run site-amplification                  a shipped workflow: the paper's site
    stepframe run selection --dry-run                 what would be computed, and what is cached
    stepframe run inbox --copy my-inbox               copy a shipped workflow to edit or schedule
    stepframe run my-inbox/inbox.toml --wait --json   a scheduled run over the record files put in
                                                      my-inbox/inbox/ (waits for a running one)
    stepframe run selection --scheduler dask-local --jobs 2
    """
    from stepframe.pipeline.engine.shipped import copy_workflow
    from stepframe.pipeline.engine.workflow import workflow_template
    from stepframe.pipeline.stages import shipped_stages

    # the options of a run, given: with --template or --copy nothing runs, so they are errors
    run_flags = [
        "--" + name.replace("_", "-")
        for name, value in fields_given(args, RunOptions).items()
        if value != []  # --force's default: no stage named
    ]
    if args.template:
        # printed alone: a workflow or an option beside it would be ignored (nothing runs)
        given = [f"WORKFLOW {args.workflow}"] if args.workflow is not None else []
        given += ["--copy"] if args.copy is not None else []
        given += run_flags
        if given:
            raise InputError(
                f"--template with {', '.join(given)}, expected --template alone (it prints a "
                "commented workflow file and runs nothing)"
            )
        text = workflow_template(shipped_stages())
        return CommandResult(data={"template": text}, text=text.rstrip("\n"))
    if args.workflow is None:
        raise InputError("no workflow given, expected stepframe run WORKFLOW.toml or a name")
    if args.copy is not None:
        if run_flags:
            raise InputError(
                f"--copy with {', '.join(run_flags)}, expected --copy alone (it copies the "
                "workflow and runs nothing: run the copy with them)"
            )
        copied = copy_workflow(args.workflow, args.copy)
        return CommandResult(data={"copied": copied}, text="\n".join(map(str, copied)))
    progress = not getattr(args, "json", False)
    options = options_from(args, RunOptions)
    return run_with_options(args.workflow, shipped_stages(), options, progress=progress)
