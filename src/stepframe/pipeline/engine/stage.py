"""The stage types: what each stage is called, takes, needs and does.

A stage is either *per item* (one result per input item, cached per item: ``inventory`` per
file, ``features`` per component) or *whole set* (one result from everything upstream: ``site``,
``amplification``, ``selection``). Each declares

- its ``name`` (also the name of its workflow table, its ``[outputs]`` key and its store folder),
- its ``version`` (raise it when the computation changes: every cached result is recomputed),
- its parameters (:class:`Param`: the keys of its workflow table, with types and defaults),
- its upstream stages (a function of the workflow: ``site`` needs ``features`` only when the site
  comes from records),
- and the functions that do the work.

The engine knows no stage by name: it is handed a :class:`StageTable` (the shipped one is
:func:`stepframe.pipeline.engine.stage.shipped_stages`), and the workflow reader, the planner, the
runner and ``stepframe run --template`` read that table. A task carries its stage's ``compute``
(a module-level function, pickled by reference) to the worker, so a worker needs no table.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

if TYPE_CHECKING:
    import pandas as pd

    from stepframe.pipeline.engine.workflow import Workflow

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


def params_from_options(cls: type, names: Sequence[str]) -> dict[str, Param]:
    """The :class:`Param` of each field ``names`` of an options dataclass (declared with
    :func:`stepframe.core.options.option`): a workflow table with the same keys, types, defaults
    and help as the command line's options. The values are checked by building the dataclass."""
    import dataclasses

    from stepframe.core.options import value_type

    fields = {f.name: f for f in dataclasses.fields(cls)}
    params = {}
    for name in names:
        f = fields[name]
        help = str(f.metadata.get("help") or "").replace("%(default)s", str(f.default))
        choices = tuple(f.metadata.get("choices") or ())
        params[name] = Param(value_type(cls, name), f.default, help, choices)  # type: ignore[arg-type]
    return params


@dataclass(frozen=True)
class Task:
    """One item of a per-item stage.

    Attributes
    ----------
    key
        Its store key (:func:`stepframe.pipeline.engine.store.make_key`).
    name
        How failures and tables name it (the file, ``file [channel]``).
    payload
        What the worker needs (plain, picklable data: paths and options, never records).
    context
        Columns the output table gets from the current run (the file's path now), not stored.
    aliases
        Names of other inputs with the same key (the same bytes under other names): one item,
        computed once, its other names listed in the run's summary
        (:mod:`stepframe.pipeline.engine.same_content`).
    """

    key: str
    name: str
    payload: Any
    context: Mapping[str, Any] = field(default_factory=dict)
    aliases: tuple[str, ...] = ()


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
    #: Per stage, the keys of items computed earlier in this run, in the same worker call as
    #: their upstream item (:attr:`Stage.expand`).
    chained: dict[str, set[str]] = field(default_factory=dict)
    #: Facts of this run a stage reports (timings): kept in the run log, not in the outputs.
    facts: dict[str, Any] = field(default_factory=dict)
    #: The tasks of each per-item stage in this run (one per key).
    item_tasks: dict[str, list[Task]] = field(default_factory=dict)
    #: The run's start (UTC, ISO 8601, :func:`~stepframe.pipeline.engine.run_log.utc_now`): the
    #: seen time of the history and the stamp of the rows a stage dates by their run.
    started_utc: str = ""
    #: Values a stage's ``prepare`` computed for its ``tasks`` in this run (by a key of the
    #: stage's own), so that the two do not do the same work twice.
    memo: dict[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class Stage:
    """A registered stage (see the module docstring).

    Per-item stages give ``tasks`` (the items and their keys, from the context) and ``compute``
    (module-level, run on workers: payload → list of row dicts; raises to fail the item), or
    ``compute_many`` (payloads → per payload its rows or the exception that failed it: for work
    that costs less done together, such as simulations in one batch of the simulator).
    ``columns`` gives the column dictionary of a per-item stage's table (name → unit, meaning).
    ``check`` validates the stage's table beyond types (errors with file:line) before anything
    runs; with ``free_params`` the stage's table is passed through unchecked by the reader and
    ``check`` must do it. Whole-set stages give ``set_key`` (the key of the result from the
    context) and ``run_set`` (context, temporary folder → writes its files there with
    ``atomic_write``). ``publish`` copies a result to the outputs folder and returns the written
    paths. ``prepare`` (optional) makes a stage's inputs exist before its tasks are listed in a
    real run (the inventory writes the embedded example's files); ``tasks`` itself writes
    nothing, so a dry run lists the same tasks with no special case. With ``latest_set_only``
    a whole-set stage keeps only its latest result in the store (a result made for the records
    folder as it is now, such as the folder's processed waveforms, which a scheduled run over a
    trickle would otherwise store again, whole, each time a file arrives).

    A per-item stage whose items each come from one item of its only upstream per-item stage
    (``features``: one per component of an ``inventory`` file) may give ``expand`` (module-level:
    ``expand(expand_args(context), upstream task, the upstream item's rows)`` → its tasks for
    that item). Then an upstream item computed in a run has its own items computed in the same
    worker call, right after it: each record file is read once (the stages share what the file
    gave, :mod:`stepframe.pipeline.catalogue.stage`). ``tasks`` should build its tasks with the
    same function, so that both give the same keys.
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
    prepare: Callable[[Context], None] | None = None
    latest_set_only: bool = False
    expand: Callable[[Any, Task, list[dict[str, Any]]], list[Task]] | None = None
    expand_args: Callable[[Context], Any] | None = None
    compute_many: Callable[[list[Any]], list[list[dict[str, Any]] | Exception]] | None = None

    def parameters(self, workflow: Workflow) -> dict[str, Any]:
        """The stage's parameters in ``workflow`` (defaults filled in)."""
        given = workflow.tables.get(self.name, {})
        if self.free_params:
            return dict(given)
        return {name: given.get(name, param.default) for name, param in self.params.items()}


@dataclass(frozen=True)
class Scene:
    """How the engine reads a scene's frame and checks its record options.

    Handed in with the stages, so that the engine imports no science: the composition root
    (:mod:`stepframe.pipeline.engine.stage`) gives the structure's frame readers and the records'
    unit check.

    Attributes
    ----------
    read_frame_file
        A FRAME.toml path → the frame (raises ``InputError`` with file:line).
    frame_from_mapping
        The ``[frame]`` tables of a workflow as a FRAME.toml mapping, and the workflow's path →
        the frame.
    check_units
        A ``[records] units`` value → None, or raises ``InputError`` naming what is accepted.
    check_record_options
        The record options of ``[records]`` (key → value) → None, or raises ``InputError``
        naming the key (``key``) and what it accepts: the command line's one check of them.
    """

    read_frame_file: Callable[[Path], Any]
    frame_from_mapping: Callable[[dict[str, Any], Path], Any]
    check_units: Callable[[str], object]
    check_record_options: Callable[[dict[str, Any]], object]


@dataclass(frozen=True)
class StageTable:
    """The stages a workflow may use, in a stated order, and how its scene is read.

    The order is the order of tables in ``stepframe run --template``, of ``[outputs]`` keys and
    of a run's summary when the dependencies allow it; the run order itself comes from the
    declared upstreams (:func:`stepframe.pipeline.engine.plan.plan_stages`).
    """

    stages: tuple[Stage, ...]
    scene: Scene

    def __post_init__(self) -> None:
        names = [stage.name for stage in self.stages]
        repeated = sorted({name for name in names if names.count(name) > 1})
        if repeated:
            raise ValueError(f"stage {repeated[0]!r} is in the table twice")

    @property
    def names(self) -> list[str]:
        """The stages' names, in table order."""
        return [stage.name for stage in self.stages]

    def __getitem__(self, name: str) -> Stage:
        for stage in self.stages:
            if stage.name == name:
                return stage
        raise KeyError(name)

    def __contains__(self, name: object) -> bool:
        return any(stage.name == name for stage in self.stages)

    def __iter__(self) -> Iterator[str]:
        return iter(self.names)

    def items(self) -> list[tuple[str, Stage]]:
        """(name, stage) pairs in table order."""
        return [(stage.name, stage) for stage in self.stages]

    def with_stages(self, *stages: Stage) -> StageTable:
        """This table with ``stages`` added at the end (a plug-in's stages, say)."""
        return StageTable((*self.stages, *stages), self.scene)
