"""The run log of a workspace: one JSON line per run, ``<workspace>/runs.jsonl``.

What is true of a run and not of its results lives here, so that the outputs are the same
bytes whenever and wherever a workflow runs: when it started, how long it took, what each stage
computed or took from the store, new failures, damaged store objects, and the facts a stage
reports about its own run (the confirmation's simulation throughput). A scheduled run's log is
this file (docs/scheduling.md): about half a kilobyte a run, appended once at the end of the run
(opened, written, closed), so that log rotation by renaming is safe between runs.
"""

from __future__ import annotations

import datetime
import json
import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

from stepframe.core.jsonable import to_jsonable
from stepframe.pipeline.engine.integrity import StorageError

if TYPE_CHECKING:
    from stepframe.pipeline.engine.runner import RunReport

RUN_LOG = "runs.jsonl"


def utc_now() -> str:
    """The current time, UTC, to the microsecond (ISO 8601 with ``Z``): the identity of a run
    in the history (two runs never start in the same microsecond: one holds the lock)."""
    now = datetime.datetime.now(datetime.UTC)
    return now.isoformat(timespec="microseconds").replace("+00:00", "Z")


def run_line(
    report: RunReport, started_utc: str, seconds: float, facts: dict[str, Any]
) -> dict[str, Any]:
    """The log line of a finished run."""
    stages = {
        s.name: [s.items, s.computed, s.cached, s.failed] + ([s.status] if s.status != "ok" else [])
        for s in report.stages
    }
    line: dict[str, Any] = {
        "started_utc": started_utc,
        "seconds": round(seconds, 3),
        "workflow": report.workflow,
        "exit_code": report.exit_code,
        "stages": stages,
        "failed": len(report.failures),
        "new_failures": report.new_failures,
        "duplicates": len(report.duplicates),
        "outputs": sorted(report.outputs),
    }
    if report.missing:
        line["missing"] = report.missing
    if report.removed:
        line["removed"] = report.removed
    if report.store_events:
        line["store"] = [event.to_dict() for event in report.store_events]
    if facts:
        line["facts"] = facts
    return line


def append_run(workspace: Path, line: dict[str, Any]) -> Path:
    """Append ``line`` to the workspace's run log as one JSON line (flushed and synced).

    Raises
    ------
    StorageError
        The log cannot be written (disk full, read-only).
    """
    path = workspace / RUN_LOG
    text = json.dumps(to_jsonable(line), separators=(",", ":"), allow_nan=False) + "\n"
    try:
        with open(path, "a", encoding="utf-8") as log:
            log.write(text)
            log.flush()
            os.fsync(log.fileno())
    except OSError as error:
        raise StorageError(path, error) from None
    return path
