"""How a worker computes a group of items: a stage's items, then the items they give, in one call.

The runner hands a per-item stage's items to the workers in groups (a few per worker and batch).
A worker computes a group's items with the stage's ``compute`` (one item at a time) or
``compute_many`` (the whole group at once: the selection's responses simulate a group's records
in one batch of the simulator).

A per-item stage with :attr:`~stepframe.pipeline.engine.stage.Stage.expand` (``features``: one
item per component of an ``inventory`` file) is a *follower* of its upstream per-item stage. When
the runner computes an upstream item, the worker that computed it lists the follower's items for
it (``expand``) and computes them in the same call, while what the upstream item read is still at
hand (the record file: read once per run instead of once per stage); a follower with
``compute_many`` computes the group's items together at the end of the group. The follower's
stage then finds those items stored and computes only what is left (the items of upstream items
that were cached).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from stepframe.core.results import Failure
from stepframe.pipeline.engine.stage import Context, Stage, StageTable, Task

Rows = list[dict[str, Any]]
#: What a group gave: (stage, key, rows or the item's failure) per item, followers' included.
Computed = list[tuple[str, str, Rows | Failure]]
#: Items of one group at most (a group is one task of the executor).
MAX_GROUP = 32


@dataclass(frozen=True)
class Work:
    """How a worker computes one stage's items (picklable: module-level functions)."""

    name: str
    compute: Callable[[Any], Rows] | None
    compute_many: Callable[[list[Any]], list[Rows | Exception]] | None

    @classmethod
    def of(cls, stage: Stage) -> Work:
        """The stage's ``compute`` and ``compute_many``."""
        return cls(stage.name, stage.compute, stage.compute_many)


@dataclass(frozen=True)
class Follower:
    """A follower stage as a worker needs it.

    Attributes
    ----------
    work
        How its items are computed.
    expand
        Its ``expand``.
    args
        Its ``expand_args(context)``, evaluated in the main process.
    followers
        Its own followers.
    """

    work: Work
    expand: Callable[[Any, Task, Rows], list[Task]]
    args: Any
    followers: tuple[Follower, ...] = ()


#: One executor task: the stage's work, its items, and their followers.
Group = tuple[Work, tuple[Task, ...], tuple[Follower, ...]]


def followers_of(
    stage: Stage,
    planned: Sequence[str],
    stages: StageTable,
    context: Context,
    forced: Sequence[str],
) -> tuple[Follower, ...]:
    """The planned, not forced, per-item stages that follow ``stage`` (and theirs, in turn).

    A forced stage is computed by itself (all its items, once); so are the followers of a
    forced stage, whose items mostly exist already.
    """
    if stage.name in forced:
        return ()
    out = []
    for name in planned:
        other = stages[name]
        if (
            other.kind == "item"
            and other.expand is not None
            and other.expand_args is not None
            and (other.compute is not None or other.compute_many is not None)
            and tuple(other.upstream(context.workflow)) == (stage.name,)
            and name not in forced
        ):
            out.append(
                Follower(
                    Work.of(other),
                    other.expand,
                    other.expand_args(context),
                    followers_of(other, planned, stages, context, forced),
                )
            )
    return tuple(out)


def groups(
    stage: Stage,
    tasks: Sequence[Task],
    followers: tuple[Follower, ...],
    workers: int,
    most: int = MAX_GROUP,
    single: int = 0,
) -> list[Group]:
    """``tasks`` in groups of about a quarter of an equal share per worker (at most
    :data:`MAX_GROUP`, and at most ``most``: a run's batch, which a group must not outgrow), in
    order; the first ``single`` tasks each a group of its own (the executor's probe, run in this
    process while the workers are not started: :func:`~stepframe.core.execution.probe_items`).
    """
    size = max(1, min(MAX_GROUP, most, math.ceil(len(tasks) / (4 * max(1, workers)))))
    work = Work.of(stage)
    alone = [(work, (task,), followers) for task in tasks[:single]]
    rest = tasks[single:]
    return alone + [(work, tuple(rest[i : i + size]), followers) for i in range(0, len(rest), size)]


def group_name(group: Group) -> str:
    """How a failure of a whole group names it: its first item."""
    return group[1][0].name if group[1] else ""


def compute_group(group: Group) -> Computed:
    """Worker entry: the group's items, then their followers' (each failure recorded)."""
    work, tasks, followers = group
    out: Computed = []
    pending: dict[str, tuple[Follower, list[Task]]] = {}
    # One item and its followers at a time (what the item read is at hand), or all at once.
    batches = [list(tasks)] if work.compute_many is not None else [[task] for task in tasks]
    for batch in batches:
        for task, value in _compute(work, batch):
            out.append((work.name, task.key, value))
            if not isinstance(value, Failure):
                _follow(task, value, followers, out, pending)
    while pending:  # the followers computed many at a time, once the group has given them all
        follower, subs = pending.pop(next(iter(pending)))
        for sub, value in _compute(follower.work, subs):
            out.append((follower.work.name, sub.key, value))
            if not isinstance(value, Failure):
                _follow(sub, value, follower.followers, out, pending)
    return out


def _compute(work: Work, tasks: list[Task]) -> list[tuple[Task, Rows | Failure]]:
    """Each task's rows, or its failure (one bad item never stops the others)."""
    if work.compute_many is not None:
        try:
            values: list[Rows | Exception] = work.compute_many([t.payload for t in tasks])
        except Exception as error:  # the whole call failed: each of its items did
            values = [error] * len(tasks)
        return [
            (task, Failure.from_exception(task.name, work.name, value))
            if isinstance(value, Exception)
            else (task, value)
            for task, value in zip(tasks, values, strict=True)
        ]
    assert work.compute is not None
    out: list[tuple[Task, Rows | Failure]] = []
    for task in tasks:
        try:
            out.append((task, work.compute(task.payload)))
        except Exception as error:
            out.append((task, Failure.from_exception(task.name, work.name, error)))
    return out


def _follow(
    task: Task,
    rows: Rows,
    followers: tuple[Follower, ...],
    out: Computed,
    pending: dict[str, tuple[Follower, list[Task]]],
) -> None:
    for follower in followers:
        subs = follower.expand(follower.args, task, rows)
        if follower.work.compute_many is not None:
            pending.setdefault(follower.work.name, (follower, []))[1].extend(subs)
            continue
        for sub, value in _compute(follower.work, subs):
            out.append((follower.work.name, sub.key, value))
            if not isinstance(value, Failure):
                _follow(sub, value, follower.followers, out, pending)
