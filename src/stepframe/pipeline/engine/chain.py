"""Per-item stages computed together: an upstream item, then the items it gives, in one call.

A per-item stage with :attr:`~stepframe.pipeline.engine.stage.Stage.expand` (``features``: one
item per component of an ``inventory`` file) is a *follower* of its upstream per-item stage. When
the runner computes an upstream item, the worker that computed it lists the follower's items for
it (``expand``) and computes them at once, while what the upstream item read is still at hand
(the record file: read once per run instead of once per stage). The follower's stage then finds
those items stored and computes only what is left (items of upstream items that were cached).

The worker entry :func:`compute_item` is the runner's for every per-item batch; a task without
followers is simply its stage's ``compute`` on its payload.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from stepframe.core.results import Failure
from stepframe.pipeline.engine.stage import Context, Stage, StageTable, Task

Rows = list[dict[str, Any]]


@dataclass(frozen=True)
class Follower:
    """A follower stage as a worker needs it (picklable: module-level functions, plain args).

    Attributes
    ----------
    name
        The follower's stage.
    compute, expand
        Its ``compute`` and ``expand``.
    args
        Its ``expand_args(context)``, evaluated in the main process.
    followers
        Its own followers.
    """

    name: str
    compute: Callable[[Any], Rows]
    expand: Callable[[Any, Task, Rows], list[Task]]
    args: Any
    followers: tuple[Follower, ...] = ()


#: What one chained item gave a follower: (stage, key, rows or the item's failure).
Followed = list[tuple[str, str, Rows | Failure]]


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
            and other.compute is not None
            and tuple(other.upstream(context.workflow)) == (stage.name,)
            and name not in forced
        ):
            out.append(
                Follower(
                    name,
                    other.compute,
                    other.expand,
                    other.expand_args(context),
                    followers_of(other, planned, stages, context, forced),
                )
            )
    return tuple(out)


def item_name(item: tuple[Callable[[Any], Rows], Task, tuple[Follower, ...]]) -> str:
    """How a failure names a batch item: its task's name."""
    return item[1].name


def compute_item(
    item: tuple[Callable[[Any], Rows], Task, tuple[Follower, ...]],
) -> tuple[Rows, Followed]:
    """Worker entry: the stage's compute function (carried with the task) on its payload, then
    the followers' items of that task (each failure recorded, never raised)."""
    compute, task, followers = item
    rows = compute(task.payload)
    return rows, _follow(task, rows, followers)


def _follow(task: Task, rows: Rows, followers: tuple[Follower, ...]) -> Followed:
    out: Followed = []
    for follower in followers:
        for sub in follower.expand(follower.args, task, rows):
            try:
                sub_rows = follower.compute(sub.payload)
            except Exception as error:  # one bad component never stops its file's others
                failure = Failure.from_exception(sub.name, follower.name, error)
                out.append((follower.name, sub.key, failure))
                continue
            out.append((follower.name, sub.key, sub_rows))
            out += _follow(sub, sub_rows, follower.followers)
    return out
