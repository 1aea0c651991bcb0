"""``stepframe demo``: the shipped selection workflow, run into one folder, and its summary.

The demo is ``stepframe run selection`` (``stepframe/workflows/selection.toml``: the 100 FEMA
P695 components, the paper's Example 4 frame, 10 components, confirmation by simulation, the
selection report) through the same runner, stages and store, with the workspace and the outputs
both in the demo's folder. A second demo into the same folder takes every result from the store.
The folder then holds:

- ``selection_report.html`` and ``selection_report_files/`` (the report and its numbers);
- ``selection/`` (``selection.csv``, ``candidates.csv``, ``confirmation.csv``,
  ``failures.csv``, ``columns.csv``, ``selection.json``: what ``stepframe select`` writes);
- ``features.parquet``, ``features.csv``, ``features.columns.csv``, ``features.failures.csv``;
- the workspace: ``store/`` (the cache), ``examples/`` (the records as files) and ``lock``.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from stepframe.pipeline.engine.runner import RunReport, run_workflow
from stepframe.pipeline.selection.result import SELECTION_REPORT_HTML, written_lines
from stepframe.pipeline.stages import shipped_stages

if TYPE_CHECKING:
    from stepframe.pipeline.selection.result import SelectionResult

#: The shipped workflow the demo runs.
DEMO_WORKFLOW = "selection"
#: The demo's folder when none is given.
DEFAULT_FOLDER = "stepframe-demo"


@dataclass(frozen=True)
class DemoRun:
    """What :func:`run_demo` did.

    Attributes
    ----------
    folder
        The demo's folder (workspace and outputs).
    run
        The runner's report (stages computed and cached, outputs, failed items).
    selection
        The selection read back from ``folder/selection``; None when the run produced none.
    """

    folder: Path
    run: RunReport
    selection: SelectionResult | None

    @property
    def report_html(self) -> Path:
        """The selection report."""
        return self.folder / SELECTION_REPORT_HTML

    @property
    def exit_code(self) -> int:
        """0 when every output was produced, else 1 (as ``stepframe run``)."""
        return self.run.exit_code

    def to_dict(self) -> dict[str, Any]:
        """The ``--json`` output: the selection's keys (``stepframe select --json``), then
        ``report``, ``outputs`` (output → paths), ``stages`` and ``workflow`` of the run."""
        data = {} if self.selection is None else self.selection.to_dict()
        data["report"] = str(self.report_html) if self.exit_code == 0 else None
        data["outputs"] = self.run.outputs
        data["stages"] = [vars(stage) for stage in self.run.stages]
        data["workflow"] = self.run.workflow
        data["missing"] = self.run.missing
        return data

    def describe(self) -> str:
        """The summary for people: band, chosen records, the ranking (its intensity, the chosen
        set against the rest, the standard intensity measures and the tiers' recall), the
        confirmation, where the outputs are."""
        from stepframe.pipeline.selection.ranking import ranking_lines

        if self.selection is None:
            return self.run.describe()
        stages = ", ".join(f"{s.name} {s.computed}/{s.cached}" for s in self.run.stages)
        return "\n".join(
            [
                *self.selection.summary_lines(),
                *ranking_lines(self.selection.summary),
                # a damaged stored object was quarantined and recomputed: say so, as `run` does
                *(f"store: {event.line()}" for event in self.run.store_events),
                f"report: {self.report_html}",
                *written_lines(self.folder / "selection", "tables"),
                f"features: {self.folder / 'features.csv'}",
                f"workflow: {self.run.workflow} (computed/cached: {stages})",
            ]
        )


def run_demo(
    folder: str | Path = DEFAULT_FOLDER, *, jobs: int | None = None, progress: bool = False
) -> DemoRun:
    """Run the shipped selection workflow with its workspace and outputs in ``folder``.

    Parameters
    ----------
    folder
        The demo's folder (made if missing; an existing one is reused incrementally).
    jobs
        Worker processes (default: the CPUs available).
    progress
        Progress lines on stderr.

    Raises
    ------
    InputError
        ``folder`` is a file or not writable, or ``jobs`` < 1 (nothing written).
    WorkspaceBusy
        Another run holds the folder's lock.
    """
    from stepframe.pipeline.selection.result import read_selection

    path = Path(folder)
    report = run_workflow(
        DEMO_WORKFLOW, shipped_stages(), jobs=jobs, progress=progress, workspace=path, outputs=path
    )
    selection = read_selection(path / "selection") if "selection" in report.outputs else None
    return DemoRun(path, report, selection)
