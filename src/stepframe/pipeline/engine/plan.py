"""The plan of a run: only the stages the requested outputs need, in dependency order.

A site model from parameters needs no records (no inventory, no features); a features table
runs no site model or selection. The plan is the closure of the outputs over each stage's
declared ``upstream``, ordered by :class:`graphlib.TopologicalSorter`: among the stages whose
upstreams are done, the one first in the stage table runs first, so the order is the table's
wherever the dependencies allow and never depends on which module was imported first.
"""

from __future__ import annotations

import graphlib

from stepframe.errors import InputError
from stepframe.pipeline.engine.stage import StageTable
from stepframe.pipeline.engine.workflow import Workflow, _suggest


def plan_stages(workflow: Workflow, stages: StageTable) -> list[str]:
    """The stages to run for ``workflow.outputs`` (dependencies first).

    Raises
    ------
    ValueError
        A stage names an upstream that is not in ``stages``, or the upstreams form a cycle
        (an error in the stage table, not in the workflow).
    """
    graph: dict[str, tuple[str, ...]] = {}
    pending = list(workflow.outputs)
    while pending:
        name = pending.pop()
        if name in graph:
            continue
        upstream = tuple(stages[name].upstream(workflow))
        unknown = [u for u in upstream if u not in stages]
        if unknown:
            raise ValueError(f"stage {name!r} names an upstream {unknown[0]!r} not in the table")
        graph[name] = upstream
        pending += upstream
    position = {name: index for index, name in enumerate(stages.names)}
    sorter = graphlib.TopologicalSorter(graph)
    try:
        sorter.prepare()
    except graphlib.CycleError as error:
        raise ValueError(f"the stages' upstreams form a cycle: {error.args[1]}") from None
    order: list[str] = []
    ready: list[str] = []
    while sorter.is_active():
        ready = sorted({*ready, *sorter.get_ready()}, key=position.__getitem__)
        first = ready.pop(0)
        order.append(first)
        sorter.done(first)
    return order


def check_forced(forced: list[str], planned: list[str], stages: StageTable) -> None:
    """``--force`` names must be stages of this run's plan.

    Raises
    ------
    InputError
        An unknown stage (with the nearest name) or one the outputs do not need.
    """
    for name in forced:
        if name not in stages:
            raise InputError(f"--force {name}: unknown stage, {_suggest(name, stages.names)}")
        if name not in planned:
            raise InputError(
                f"--force {name}: not in this run's plan, expected one of {', '.join(planned)}"
            )
