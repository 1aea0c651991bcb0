"""The stage registry: what each stage is called, takes, needs and does.

A stage is either *per item* (one result per input item, cached per item: ``inventory`` per
file, ``features`` per component) or *whole set* (one result from everything upstream: ``site``,
``amplification``, ``selection``). Each declares

- its ``name`` (also the name of its workflow table, its ``[outputs]`` key and its store folder),
- its ``version`` (raise it when the computation changes: every cached result is recomputed),
- its parameters (:class:`Param`: the keys of its workflow table, with types and defaults),
- its upstream stages (a function of the workflow: ``site`` needs ``features`` only when the site
  comes from records),
- and the functions that do the work.

New stages (reports, confirmation) plug in with :func:`register_stage`; the workflow reader, the
planner and ``stepframe run --template`` read the registry, so nothing else changes.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

if TYPE_CHECKING:
    import pandas as pd

    from stepframe.pipeline.workflow import Workflow

ParamType = Literal["float", "int", "bool", "str", "table"]


@dataclass(frozen=True)
class Param:
    """One parameter of a stage (a key of its workflow table).

    Attributes
    ----------
    type
        ``float`` (an int is accepted), ``int``, ``bool``, ``str`` or ``table`` (a TOML table
        checked by the stage itself).
    default
        The value when the key is absent (None: no default; the stage says when it is needed).
    help
        One line, with the unit, for the template and error messages.
    choices
        The allowed values of a ``str`` parameter (empty: any).
    """

    type: ParamType
    default: Any
    help: str
    choices: tuple[str, ...] = ()


@dataclass(frozen=True)
class Task:
    """One item of a per-item stage.

    Attributes
    ----------
    key
        Its store key (:func:`stepframe.pipeline.store.make_key`).
    name
        How failures and tables name it (the file, ``file [channel]``).
    payload
        What the worker needs (plain, picklable data: paths and options, never records).
    context
        Columns the output table gets from the current run (the file's path now), not stored.
    """

    key: str
    name: str
    payload: Any
    context: Mapping[str, Any] = field(default_factory=dict)


@dataclass
class Context:
    """What a stage sees when it runs: the workflow, upstream outputs and the executor."""

    workflow: Workflow
    tables: dict[str, pd.DataFrame]
    set_keys: dict[str, str]
    set_dirs: dict[str, Path]
    item_keys: dict[str, list[str]]
    jobs: int | None
    executor: Any
    progress: bool


@dataclass(frozen=True)
class Stage:
    """A registered stage (see the module docstring).

    Per-item stages give ``tasks`` (the items and their keys, from the context) and ``compute``
    (module-level, run on workers: payload → list of row dicts; raises to fail the item).
    ``columns`` gives the column dictionary of a per-item stage's table (name → unit, meaning).
    ``check`` validates the stage's table beyond types (errors with file:line) before anything
    runs; with ``free_params`` the stage's table is passed through unchecked by the reader and
    ``check`` must do it. Whole-set stages give ``set_key`` (the key of the result from the
    context) and ``run_set`` (context, temporary folder → writes its files there with
    ``atomic_write``). ``publish``
    copies a result to the outputs folder and returns the written paths.
    """

    name: str
    version: int
    description: str
    kind: Literal["item", "set"]
    params: Mapping[str, Param]
    upstream: Callable[[Workflow], Sequence[str]]
    columns: Callable[[], Mapping[str, tuple[str, str]]] = dict
    tasks: Callable[[Context], list[Task]] | None = None
    compute: Callable[[Any], list[dict[str, Any]]] | None = None
    set_key: Callable[[Context], str] | None = None
    run_set: Callable[[Context, Path], None] | None = None
    publish: Callable[[Path, Path], list[Path]] | None = None
    needs_records: bool = False
    needs_frame: bool = False
    check: Callable[[Workflow], None] | None = None
    free_params: bool = False

    def parameters(self, workflow: Workflow) -> dict[str, Any]:
        """The stage's parameters in ``workflow`` (defaults filled in)."""
        given = workflow.tables.get(self.name, {})
        if self.free_params:
            return dict(given)
        return {name: given.get(name, param.default) for name, param in self.params.items()}


REGISTRY: dict[str, Stage] = {}


def register_stage(stage: Stage) -> Stage:
    """Add a stage to the registry (its name must be new)."""
    if stage.name in REGISTRY:
        raise ValueError(f"stage {stage.name!r} is already registered")
    REGISTRY[stage.name] = stage
    return stage


def registry() -> dict[str, Stage]:
    """Every registered stage, built-in ones loaded, in registration (= pipeline) order."""
    from stepframe.pipeline import stage_ida, stage_items, stage_reports, stage_sets  # noqa: F401

    return REGISTRY
