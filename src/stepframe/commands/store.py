"""``stepframe store verify`` and ``stepframe store compact``: upkeep of a workspace's store
(:mod:`stepframe.pipeline.engine.upkeep`)."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from stepframe.commands import add_command
from stepframe.core.options import add_fields
from stepframe.pipeline.engine.run_options import RunOptions

if TYPE_CHECKING:
    from stepframe.commands import Subparsers
    from stepframe.pipeline.engine.upkeep import StoreCheck


def register(subparsers: Subparsers) -> None:
    """Add ``verify`` and ``compact`` to the ``store`` group."""
    for name, run in (("verify", run_verify), ("compact", run_compact)):
        command = add_command(subparsers, name, run)
        command.add_argument(
            "workspace", metavar="WORKSPACE", help="a workspace folder, or a workflow file"
        )
        add_fields(command, RunOptions, ["wait"])


def _upkeep(args: argparse.Namespace, action: str) -> StoreCheck:
    from stepframe.pipeline.engine.upkeep import upkeep
    from stepframe.pipeline.stages import shipped_stages

    return upkeep(args.workspace, shipped_stages(), action, wait=args.wait)


def run_verify(args: argparse.Namespace) -> StoreCheck:
    """Check every object of a workspace's store against its checksum; remove unreachable ones.

    Every stored object (result segments, each file of a whole-set result, the index files) is
    read and checked against the checksum in its stage's index. A damaged or missing one is
    moved to store/quarantine/ and named; the next run recomputes what it held. Objects no key
    leads to (segments a later one fully replaces, result folders no index names) are removed.
    Exit 0: every object sound; 1: damaged objects found (quarantined); 2: user error; 3:
    another run holds the workspace.

    Examples
    --------
    stepframe store verify stepframe-work              a workspace folder
    stepframe store verify my-inbox/inbox.toml --json  the workspace of a workflow
    """
    return _upkeep(args, "verify")


def run_compact(args: argparse.Namespace) -> StoreCheck:
    """Merge the small result segments of a workspace's store into one per stage.

    A scheduled run that finds a few new files stores them as a small segment; a run merges a
    stage's small segments once it has 8 of them, this command merges them now (only the rows
    still in use are kept). Exit codes as store verify.

    Examples
    --------
    stepframe store compact my-inbox/stepframe-work
    """
    return _upkeep(args, "compact")
