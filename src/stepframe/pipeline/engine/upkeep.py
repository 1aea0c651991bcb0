"""Upkeep of a workspace's store: ``stepframe store verify`` and ``stepframe store compact``.

A run already checks every object it reads and merges a stage's small segments when it has
:data:`~stepframe.pipeline.engine.store.COMPACT_AT` of them. ``verify`` checks *every* object,
also those no run of the current workflow reads (results of other parameters, whole-set results
not asked for lately), quarantines the damaged ones and removes the unreachable ones (segments
whose every key a later segment holds, result folders no index names); ``compact`` merges every
stage's small segments now. Both hold the workspace lock.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from stepframe.errors import InputError
from stepframe.pipeline.engine.integrity import QUARANTINE, StoreEvent
from stepframe.pipeline.engine.lock import workspace_lock
from stepframe.pipeline.engine.stage import StageTable
from stepframe.pipeline.engine.store import Store


@dataclass
class StoreCheck:
    """What ``stepframe store verify`` or ``compact`` found and did.

    Attributes
    ----------
    workspace
        The workspace.
    action
        ``verify`` or ``compact``.
    stages
        Per stage: segments, sets, items, bytes, and the objects removed (verify) or the
        segments merged (compact).
    events
        Damaged or missing objects (quarantined; the next run recomputes them).
    quarantined
        Files in ``store/quarantine/`` (from this and earlier runs), to inspect and delete.
    """

    workspace: str
    action: str
    stages: dict[str, Any] = field(default_factory=dict)
    events: list[StoreEvent] = field(default_factory=list)
    quarantined: int = 0

    @property
    def exit_code(self) -> int:
        """1 when a damaged or missing object was found, else 0."""
        return 1 if self.events else 0

    def describe(self) -> str:
        """For people: a line per stage, then each damaged object."""
        lines = [f"store of {self.workspace}: {self.action}"]
        for name, info in self.stages.items():
            done = info.get("removed", info.get("merged"))
            what = "removed" if "removed" in info else "merged"
            count = len(done) if isinstance(done, list) else done
            lines.append(
                f"  {name:<22}{info['items']:>7} items {info['segments']:>4} segments "
                f"{info['sets']:>3} sets {info['bytes'] / 1e6:>9.3f} MB   {what} {count}"
            )
        lines += [f"damaged: {event.line()}" for event in self.events]
        if not self.events:
            lines.append("every object matches its checksum")
        if self.quarantined:
            lines.append(
                f"{self.quarantined} file(s) in store/{QUARANTINE}/: inspect, then delete them"
            )
        return "\n".join(lines)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form."""
        return {
            "workspace": self.workspace,
            "action": self.action,
            "stages": self.stages,
            "damaged": [event.to_dict() for event in self.events],
            "quarantined": self.quarantined,
            "exit_code": self.exit_code,
        }


def workspace_of(path: str | Path, stages: StageTable) -> Path:
    """The workspace named by ``path``: a workspace folder (it holds ``store/``) or a workflow
    file (its workspace).

    Raises
    ------
    InputError
        Neither.
    """
    from stepframe.pipeline.engine.workflow import load_workflow

    given = Path(path)
    if given.is_file():
        return load_workflow(given, stages).workspace
    if (given / "store").is_dir():
        return given
    if not given.exists():
        raise InputError(
            "no such file or folder, expected a workspace (the folder holding store/ and lock) "
            "or a workflow file",
            given,
        )
    raise InputError(
        "no store/ in it, expected a workspace (the folder holding store/ and lock) or a "
        "workflow file",
        given,
    )


def upkeep(path: str | Path, stages: StageTable, action: str, *, wait: bool = False) -> StoreCheck:
    """Verify (``action="verify"``) or compact (``"compact"``) the store of a workspace.

    Parameters
    ----------
    path
        A workspace folder or a workflow file (:func:`workspace_of`).
    stages
        The stages, to read a workflow file.
    action
        ``verify`` or ``compact``.
    wait
        Wait for a run holding the workspace instead of raising ``WorkspaceBusy``.
    """
    workspace = workspace_of(path, stages)
    check = StoreCheck(str(workspace), action)
    with workspace_lock(workspace, wait=wait):
        store = Store(workspace / "store", then="the next run that needs it recomputes it")
        store.prepare()
        if action == "verify":
            check.stages = store.verify()
        else:
            for stage in store.stages():
                merged = store.compact(stage, at=2)
                check.stages[stage] = {**store.describe(stage), "merged": merged}
        check.events = store.events
        quarantine = workspace / "store" / QUARANTINE
        if quarantine.is_dir():
            check.quarantined = sum(1 for stage in quarantine.iterdir() for _ in stage.iterdir())
    return check
