"""One content, one item: the tasks of a stage that share a store key are one item.

Two record files with the same bytes (the same download saved twice, a file received under a
second name) hash to the same key. Computed as two tasks, each stored its rows under that key
and each read back every row stored under it: two copies of a one-component file gave a
features table of eight rows. The runner therefore merges a stage's tasks by key before
anything is computed: the first task (in the stage's order) is the item, and the names of the
others become its ``aliases``, listed in the run's summary. A stage whose table should name them
(the inventory's ``duplicates`` column) groups its inputs itself and sets ``aliases`` and its
context; the merge here is the guarantee for every stage, including a user's own. A stored
failure is listed under the name its item has now (:func:`named_now`).
"""

from __future__ import annotations

import dataclasses

from stepframe.core.results import Failure
from stepframe.pipeline.engine.stage import Task

#: How several names of one item are joined in a table cell and in the summary.
NAME_SEPARATOR = "; "


def merge_same_key(tasks: list[Task]) -> list[Task]:
    """``tasks`` with one task per key, in first-seen order; a dropped task's name (and its own
    aliases) are added to the kept task's ``aliases``."""
    kept: dict[str, Task] = {}
    for task in tasks:
        first = kept.get(task.key)
        if first is None:
            kept[task.key] = task
        else:
            aliases = (*first.aliases, task.name, *task.aliases)
            kept[task.key] = dataclasses.replace(first, aliases=aliases)
    return list(kept.values())


def alias_lines(stage: str, tasks: list[Task]) -> list[tuple[str, str, str]]:
    """``(stage, name, same as)`` for every alias of ``tasks``: what the summary lists."""
    return [(stage, alias, task.name) for task in tasks for alias in task.aliases]


def named_now(failure: Failure, name: str) -> Failure:
    """A stored failure under the name its item has in this run (a file renamed or moved since
    it failed keeps its failure, a key of content, but is listed under its new name)."""
    if failure.item == name:
        return failure
    message = failure.message.replace(failure.item, name)
    return dataclasses.replace(failure, item=name, message=message)
