"""How a workflow is run: the options of :func:`~stepframe.pipeline.engine.runner.run_workflow`
as one frozen dataclass (light: ``stepframe run --help`` derives its options from the fields)."""

from __future__ import annotations

from dataclasses import asdict, dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from stepframe.core.options import JOBS, Range, check_fields, option

if TYPE_CHECKING:
    from stepframe.pipeline.engine.runner import RunReport
    from stepframe.pipeline.engine.stage import StageTable


@dataclass(frozen=True)
class RunOptions:
    """The choices of one run of a workflow (the keyword arguments of
    :func:`~stepframe.pipeline.engine.runner.run_workflow`)."""

    dry_run: bool = option(False, "print the plan: items to compute and cached")
    jobs: int | None = option(
        None,
        "worker processes (default: all CPUs, or STEPFRAME_JOBS)",
        kind="int",
        metavar="N",
        valid=JOBS,
    )
    scheduler: str | None = option(
        None,
        "dask-local (a local Dask cluster) or tcp://HOST:PORT (an existing one); needs pip "
        "install 'stepframe[dask]'",
        metavar="WHERE",
    )
    force: list[str] | None = option(None, "recompute a stage", kind="repeated", metavar="STAGE")
    retry_failed: bool = option(False, "recompute items that failed before")
    prune: bool = option(
        False,
        "with [outputs] history: forget the items and failures no longer found (kept, with "
        "present = false, otherwise)",
    )
    wait: bool = option(False, "wait for a run holding the workspace (else exit 3)")
    batch_items: int | None = option(
        None,
        "items stored per batch (default 1024, or 32 per worker if more): a killed run loses "
        "at most one batch of finished items and the groups under way",
        kind="int",
        metavar="N",
        valid=Range(1, 10_000_000),
    )

    def __post_init__(self) -> None:
        check_fields(self)


def run_with_options(
    path: str | Path, stages: StageTable, options: RunOptions, *, progress: bool
) -> RunReport:
    """:func:`~stepframe.pipeline.engine.runner.run_workflow` of ``path`` with ``stages`` and
    ``options``; progress lines on stderr when ``progress``."""
    from stepframe.pipeline.engine.runner import run_workflow

    return run_workflow(path, stages, progress=progress, **asdict(options))
