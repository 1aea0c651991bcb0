"""The plan of a run: only the stages the requested outputs need, in dependency order.

A site model from parameters needs no records (no inventory, no features); a features table
runs no site model or selection. The registry's order is a topological order (a stage is
registered after the stages it depends on), so the plan is the closure of the outputs over
``upstream``, listed in registry order.
"""

from __future__ import annotations

from stepframe.errors import InputError
from stepframe.pipeline.stages import registry
from stepframe.pipeline.workflow import Workflow, _suggest


def plan_stages(workflow: Workflow) -> list[str]:
    """The stages to run for ``workflow.outputs`` (dependencies first)."""
    stages = registry()
    needed: set[str] = set()
    pending = list(workflow.outputs)
    while pending:
        name = pending.pop()
        if name in needed:
            continue
        needed.add(name)
        for upstream in stages[name].upstream(workflow):
            if list(stages).index(upstream) >= list(stages).index(name):
                raise RuntimeError(f"stage {name!r} is registered before its upstream {upstream!r}")
            pending.append(upstream)
    return [name for name in stages if name in needed]


def check_forced(forced: list[str], planned: list[str]) -> None:
    """``--force`` names must be stages of this run's plan.

    Raises
    ------
    InputError
        An unknown stage (with the nearest name) or one the outputs do not need.
    """
    stages = registry()
    for name in forced:
        if name not in stages:
            raise InputError(f"--force {name}: unknown stage, {_suggest(name, list(stages))}")
        if name not in planned:
            raise InputError(
                f"--force {name}: not in this run's plan, expected one of {', '.join(planned)}"
            )
