"""Run a workflow: check everything, take the lock, run the planned stages, publish the outputs.

Order of a run, so that a user error writes nothing and a killed run loses nothing but the items
it had not stored yet (fewer than a batch, and the groups under way):

1. read and check the workflow, its frame, the stage tables and the records folder (exit 2);
2. take the workspace lock (exit 3 if another run holds it, or wait with ``wait=True``);
3. remove temporaries of killed runs; open the store, checking every object it reads
   (:mod:`stepframe.pipeline.engine.store`: a damaged one is quarantined and recomputed);
4. per-item stages: one task per distinct key (inputs with the same bytes are one item,
   :mod:`stepframe.pipeline.engine.same_content`); compute the items whose key is not stored
   (or failed, with ``retry_failed``; or all, for a ``force``\\ d stage) in groups through
   :func:`stepframe.core.execution.iter_items`, storing a segment each time a batch of items
   has finished while the workers go on; then read
   every item's rows back from the store in input order (so a table is the same bytes whether
   its rows were computed now or earlier);
5. whole-set stages: compute the result unless its key is stored and sound;
6. publish the requested outputs (Parquet, CSV copies, failure tables, NetCDF) atomically,
   with what earlier runs saw when the workflow keeps a history
   (:mod:`stepframe.pipeline.engine.history`), each copy of a stored file checked against it
   (an output the last run published and left untouched is not written again:
   :func:`~stepframe.pipeline.engine.store.publish_output_table`,
   :func:`~stepframe.pipeline.engine.store.publish_set`);
7. merge a stage's small segments; append the run's line to the run log
   (:mod:`stepframe.pipeline.engine.run_log`).

Exit status (:attr:`RunReport.exit_code`): 0 every requested output produced (failed items are
listed), 1 an output could not be produced. A file that cannot be written (disk full) raises
:class:`~stepframe.pipeline.engine.integrity.StorageError` (exit 1 on the command line).
"""

from __future__ import annotations

import errno
import shutil
import time
from concurrent.futures import Executor
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from stepframe.core.execution import iter_items, probe_items
from stepframe.core.io import TEMPORARY_SUFFIX
from stepframe.core.results import Failure, failures_path, set_column_dictionary
from stepframe.errors import InputError
from stepframe.pipeline.engine.chain import (
    Computed,
    Follower,
    Group,
    compute_group,
    followers_of,
    group_name,
    groups,
)
from stepframe.pipeline.engine.history import (
    failures_first_seen,
    history_without_output,
    item_outputs,
)
from stepframe.pipeline.engine.integrity import StorageError, StoreEvent
from stepframe.pipeline.engine.lock import workspace_lock
from stepframe.pipeline.engine.plan import check_forced, plan_stages
from stepframe.pipeline.engine.run_log import append_run, run_line, utc_now
from stepframe.pipeline.engine.same_content import alias_lines, merge_same_key, named_now
from stepframe.pipeline.engine.scheduler import Execution, check_scheduler, open_execution
from stepframe.pipeline.engine.shipped import is_shipped, resolve_workflow
from stepframe.pipeline.engine.stage import Context, Stage, StageTable, Task
from stepframe.pipeline.engine.store import (
    KEY_COLUMN,
    Store,
    publish_output_table,
    publish_set,
    remember_published,
    withdraw_published,
)
from stepframe.pipeline.engine.workflow import DEFAULT_WORKSPACE, Workflow, load_workflow

if TYPE_CHECKING:
    import pandas as pd

#: Items stored per segment by default: a killed run loses at most one batch of finished items
#: (and the groups under way), and each segment is a file the store reads, so batches are not
#: small.
DEFAULT_BATCH_ITEMS = 1024
#: With many workers, at least this many items per worker in a batch.
BATCH_ITEMS_PER_WORKER = 32
#: Helper columns of the table assembly (task position, row position in the store).
_TASK = "_task"
_ROW = "_row"
#: Errors of a write that no retry of the item would mend: the run stops with one line, exit 1.
DISK_ERRORS = (errno.ENOSPC, errno.EDQUOT, errno.EROFS, errno.EIO)


@dataclass
class StageSummary:
    """What one stage did in a run.

    Attributes
    ----------
    name, kind
        The stage and ``item``/``set``.
    items
        Items of the stage in this run (1 for a whole-set stage).
    computed, cached, failed
        Items computed now, taken from the store, and failed (now or stored failures).
    seconds
        Wall time [s].
    status
        ``ok``, ``failed`` (no result) or ``skipped`` (an upstream stage has no result).
    message
        Why, when not ``ok``.
    """

    name: str
    kind: str
    items: int = 0
    computed: int = 0
    cached: int = 0
    failed: int = 0
    seconds: float = 0.0
    status: str = "ok"
    message: str = ""


@dataclass
class RunReport:
    """The result of :func:`run_workflow`."""

    workflow: str
    workspace: str
    execution: str
    dry_run: bool
    stages: list[StageSummary] = field(default_factory=list)
    outputs: dict[str, list[str]] = field(default_factory=dict)
    missing: dict[str, str] = field(default_factory=dict)
    failures: list[Failure] = field(default_factory=list)
    #: ``(stage, name, same as)``: inputs with the same bytes as another, merged into its item.
    duplicates: list[tuple[str, str, str]] = field(default_factory=list)
    #: Damaged or missing objects the store found (quarantined and recomputed).
    store_events: list[StoreEvent] = field(default_factory=list)
    #: Failures this run found first (with ``[outputs] history``; else None).
    new_failures: int | None = None
    #: Per output the workflow no longer asks for, or that this run could not produce (then also
    #: in :attr:`missing`), what an earlier run published of it that this run removed from the
    #: outputs folder (names in it).
    removed: dict[str, list[str]] = field(default_factory=dict)

    @property
    def exit_code(self) -> int:
        """0 when every requested output was produced, else 1."""
        return 1 if self.missing else 0

    def describe(self) -> str:
        """The end-of-run summary for people: a line per stage, then the outputs."""
        lines = [f"workflow {self.workflow} ({self.execution}; workspace {self.workspace})"]
        header = (
            f"  {'stage':<22}{'items':>7}{'computed':>10}{'cached':>8}{'failed':>8}{'time s':>9}"
        )
        if self.dry_run:
            header = f"  {'stage':<22}{'items':>7}{'to compute':>12}{'cached':>8}"
        lines.append(header)
        for s in self.stages:
            if self.dry_run:
                line = f"  {s.name:<22}{s.items:>7}{s.computed:>12}{s.cached:>8}"
            else:
                line = (
                    f"  {s.name:<22}{s.items:>7}{s.computed:>10}{s.cached:>8}{s.failed:>8}"
                    f"{s.seconds:>9.2f}"
                )
            if s.status not in ("ok",):
                line += f"   {s.status}: {s.message}"
            lines.append(line)
        if self.duplicates:
            lines.append(f"same content as another input, one item ({len(self.duplicates)}):")
            lines += [f"  {stage}: {name} = {same}" for stage, name, same in self.duplicates[:20]]
            if len(self.duplicates) > 20:
                lines.append(f"  ... and {len(self.duplicates) - 20} more")
        lines += [f"store: {event.line()}" for event in self.store_events]
        if self.dry_run:
            lines.append("dry run: nothing computed or written")
            return "\n".join(lines)
        if self.failures:
            lines.append(f"failed items ({len(self.failures)}):")
            lines += [f"  {f.stage}: {f.item}: {f.message}" for f in self.failures[:20]]
            if len(self.failures) > 20:
                lines.append(f"  ... and {len(self.failures) - 20} more (see the failures tables)")
        for name, paths in self.outputs.items():
            more = f" (+{len(paths) - 1} files)" if len(paths) > 1 else ""
            lines.append(f"output {name}: {paths[0]}{more}")
        for name, reason in self.missing.items():
            lines.append(f"output {name} NOT produced: {reason}")
        for name, entries in self.removed.items():
            why = "no longer asked for"
            if name in self.missing:
                why = "an earlier run's, not produced by this one"
            lines.append(f"output {name} removed ({why}): {', '.join(entries)}")
        return "\n".join(lines)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form."""
        return {
            "workflow": self.workflow,
            "workspace": self.workspace,
            "execution": self.execution,
            "dry_run": self.dry_run,
            "stages": [vars(s) for s in self.stages],
            "outputs": self.outputs,
            "missing": self.missing,
            "failures": [f.to_dict() for f in self.failures],
            "duplicates": [
                {"stage": stage, "name": name, "same_as": same}
                for stage, name, same in self.duplicates
            ],
            "store": [event.to_dict() for event in self.store_events],
            "new_failures": self.new_failures,
            "removed": self.removed,
            "exit_code": self.exit_code,
        }


def _prepare(workflow: Workflow, forced: list[str], stages: StageTable) -> list[str]:
    """Plan and check everything that can be checked before writing anything."""
    planned = plan_stages(workflow, stages)
    check_forced(forced, planned, stages)
    for name in planned:
        check = stages[name].check
        if check is not None:
            check(workflow)
    if any(stages[name].needs_records for name in planned):
        records = workflow.records
        if records is None:
            raise InputError(
                "no [records] table, expected one for the outputs asked "
                f"({', '.join(workflow.outputs)})",
                workflow.path,
            )
        if records.folder is not None:
            # listed here for its errors (exit 2 before any work); the listing is kept for the
            # stages, whose first use gives its warnings (links skipped)
            workflow.record_files(quiet=True)
    _check_writable(workflow.workspace)
    _check_writable(workflow.outputs_folder)
    store = workflow.workspace / "store"
    for stage in store.iterdir() if store.is_dir() else ():
        # the folders a run renames objects in: a read-only one is found before any work
        for folder in (stage, stage / "sets"):
            if folder.is_dir():
                _check_writable(folder)
    return planned


def _check_writable(folder: Path) -> None:
    """The folder exists and is writable, or its nearest existing parent is (nothing created)."""
    import os

    probe = folder
    while not probe.exists():
        if probe.parent == probe:
            break
        probe = probe.parent
    if not probe.is_dir():
        raise InputError("exists and is not a folder, expected a folder", probe)
    if not os.access(probe, os.W_OK | os.X_OK):
        raise InputError("is not writable, expected a writable folder", probe)


def run_workflow(
    path: str | Path,
    stages: StageTable,
    *,
    jobs: int | None = None,
    scheduler: str | None = None,
    executor: Executor | None = None,
    force: list[str] | None = None,
    retry_failed: bool = False,
    prune: bool = False,
    dry_run: bool = False,
    wait: bool = False,
    progress: bool = False,
    batch_items: int | None = None,
    workspace: str | Path | None = None,
    outputs: str | Path | None = None,
) -> RunReport:
    """Run a workflow file (see the module docstring).

    Parameters
    ----------
    path
        The workflow file, or the name of a shipped workflow (``"selection"``,
        :func:`stepframe.pipeline.engine.shipped.resolve_workflow`).
    stages
        The stages the workflow may use and how its scene is read
        (:func:`stepframe.pipeline.engine.stage.shipped_stages`).
    jobs
        Worker processes (default: the CPUs available); with ``dask-local``, Dask workers.
    scheduler
        None (process pool), ``"dask-local"`` or ``"tcp://HOST:PORT"``.
    executor
        Any ``concurrent.futures.Executor`` to run the items on instead (a spawn-started
        process pool, a Dask client's executor); the caller owns it and shuts it down.
        Exclusive with ``scheduler``.
    force
        Stages whose items are all recomputed.
    retry_failed
        Recompute items whose stored result is a failure.
    prune
        With ``[outputs] history``: forget the items and failures this run does not find
        (:mod:`stepframe.pipeline.engine.history`).
    dry_run
        Only say what would be computed (nothing is written, no lock taken).
    wait
        Wait for another run holding the workspace instead of raising ``WorkspaceBusy``.
    progress
        Progress lines (count, rate, ETA) per stage on stderr.
    batch_items
        Items per stored segment (default: :data:`DEFAULT_BATCH_ITEMS`, or
        :data:`BATCH_ITEMS_PER_WORKER` per worker when that is more, so that a large cluster
        is not left idle at the end of each batch).
    workspace, outputs
        The workspace and the outputs folder instead of the workflow's
        (:func:`~stepframe.pipeline.engine.workflow.load_workflow`). A shipped workflow's workspace
        defaults to ``stepframe-work/`` in the current folder: the package is not written.

    Raises
    ------
    InputError
        Any user error (before anything is written).
    WorkspaceBusy
        Another run holds the workspace and ``wait`` is False.
    """
    if batch_items is not None and batch_items < 1:
        raise InputError(f"--batch-items {batch_items}, expected ≥ 1")
    check_scheduler(scheduler, jobs)  # before anything, a dry run too: a user error writes nothing
    if executor is not None and scheduler is not None:
        raise InputError(f"an executor and --scheduler {scheduler}, expected one of them")
    forced = list(force or [])
    file = resolve_workflow(path)
    if workspace is None and is_shipped(file):
        workspace = DEFAULT_WORKSPACE
    workflow = load_workflow(file, stages, workspace=workspace, outputs=outputs)
    if is_shipped(file) and workflow.records is not None and workflow.records.folder is not None:
        name = file.stem
        raise InputError(
            f"the shipped workflow {name} reads a records folder beside it, expected a copy: "
            f"stepframe run {name} --copy DIR, then stepframe run DIR/{name}.toml"
        )
    if prune and not workflow.history:
        raise InputError(
            "--prune without [outputs] history = true, expected a workflow that keeps what it saw"
        )
    planned = _prepare(workflow, forced, stages)
    store = Store(workflow.workspace / "store", dry=dry_run)
    if dry_run:
        return _dry_run(workflow, stages, planned, store, forced, retry_failed)
    # the lock before the executor: a busy workspace is reported before a cluster starts
    with (
        workspace_lock(workflow.workspace, wait=wait),
        open_execution(scheduler, jobs, executor) as execution,
    ):
        started, started_utc = time.perf_counter(), utc_now()
        report = RunReport(
            str(workflow.path), str(workflow.workspace), execution.description, False
        )
        store.prepare()
        _remove_temporaries(workflow.outputs_folder)
        context = Context(workflow, {}, {}, {}, {}, execution.jobs, execution.executor, progress,
                          started_utc=started_utc)  # fmt: skip
        batch = batch_items or max(DEFAULT_BATCH_ITEMS, BATCH_ITEMS_PER_WORKER * execution.jobs)
        try:
            _run_stages(stages, planned, context, store, execution, report, forced,
                        retry_failed, batch)  # fmt: skip
        except KeyboardInterrupt:
            # A scheduled run stopped by Ctrl-C (or its scheduler's SIGINT) left no line: the
            # log says it ran, which stages finished, and that nothing was published.
            seconds = time.perf_counter() - started
            line = run_line(report, started_utc, seconds, context.facts)
            append_run(workflow.workspace, {**line, "exit_code": 130, "interrupted": True})
            raise
        _finish(workflow, stages, planned, context, report, store, prune, started, started_utc)
    return report


def _run_stages(
    stages: StageTable,
    planned: list[str],
    context: Context,
    store: Store,
    execution: Execution,
    report: RunReport,
    forced: list[str],
    retry_failed: bool,
    batch: int,
) -> None:
    """Run the planned stages in order, each summarised in ``report`` (a stage whose upstream
    has no result is skipped, saying which)."""
    workflow = context.workflow
    for name in planned:
        stage = stages[name]
        summary = StageSummary(name, stage.kind)
        start = time.perf_counter()
        blocked = [u for u in stage.upstream(workflow) if not _available(context, u)]
        if blocked:
            summary.status = "skipped"
            summary.message = f"upstream stage {blocked[0]} has no result"
        elif stage.kind == "item":
            followers = followers_of(stage, planned, stages, context, forced)
            _run_items(stage, context, store, execution, summary, report, forced,
                       retry_failed, batch, followers)  # fmt: skip
        else:
            _run_set(stage, context, store, summary, name in forced)
        summary.seconds = round(time.perf_counter() - start, 3)
        report.stages.append(summary)


def _finish(
    workflow: Workflow,
    stages: StageTable,
    planned: list[str],
    context: Context,
    report: RunReport,
    store: Store,
    prune: bool,
    started: float,
    started_utc: str,
) -> None:
    """The end of a run: publish the outputs, merge small segments, write the run's log line."""
    _publish(workflow, stages, context, report, store, now=started_utc, prune=prune)
    for name in planned:
        if stages[name].kind == "item":
            store.compact(name)
    report.store_events = store.events
    seconds = time.perf_counter() - started
    append_run(workflow.workspace, run_line(report, started_utc, seconds, context.facts))


def _available(context: Context, name: str) -> bool:
    if name in context.tables:  # a stage with no item at all is not missing anything
        return len(context.tables[name]) > 0 or not context.item_keys.get(name)
    return name in context.set_dirs


def _remove_temporaries(folder: Path) -> None:
    # atomic_write's temporaries: hidden, ending in .tmp; left only by a killed run.
    if folder.is_dir():
        for temporary in folder.rglob(f".*{TEMPORARY_SUFFIX}"):
            if temporary.is_file():
                temporary.unlink(missing_ok=True)


def _run_items(
    stage: Stage,
    context: Context,
    store: Store,
    execution: Execution,
    summary: StageSummary,
    report: RunReport,
    forced: list[str],
    retry_failed: bool,
    batch_items: int,
    followers: tuple[Follower, ...] = (),
) -> None:
    assert stage.tasks is not None and (stage.compute or stage.compute_many) is not None
    if stage.prepare is not None:
        stage.prepare(context)
    tasks = merge_same_key(stage.tasks(context))
    report.duplicates += alias_lines(stage.name, tasks)
    context.item_tasks[stage.name] = tasks
    index = store.index(stage.name)
    force = stage.name in forced

    def wanted(task: Task) -> bool:
        entry = index.get(task.key)
        return force or entry is None or (entry.failed and retry_failed)

    todo = [task for task in tasks if wanted(task)]
    chained = context.chained.get(stage.name, set())
    summary.items = len(tasks)
    summary.computed = len(todo) + sum(1 for task in tasks if task.key in chained)
    summary.cached = len(tasks) - summary.computed
    # Every group goes to the workers at once and a segment is stored each time batch_items
    # items have finished, while the workers go on: no worker waits at a batch's end for the
    # slowest group or for this process to store (a killed run loses at most the finished
    # items not yet stored, fewer than batch_items, and the groups under way).
    single = probe_items(execution.executor, execution.jobs)
    work = groups(stage, todo, followers, execution.jobs, batch_items, single)
    finished: list[tuple[Group, bool, Any]] = []
    finished_items = 0
    for position, ok, value in iter_items(
        compute_group,
        work,
        jobs=execution.jobs,
        executor=execution.executor,
        chunk_size=1,
        stage=stage.name,
        name_of=group_name,
        progress="+".join([stage.name, *(f.work.name for f in followers)])
        if context.progress
        else False,
        # Count the stage's items, not the groups that carry them, and the failures inside.
        units_of=lambda group: len(group[1]),
        failures_in=lambda computed: sum(isinstance(v, Failure) for _, _, v in computed),
    ):
        finished.append((work[position], ok, value))
        finished_items += len(work[position][1])
        if finished_items >= batch_items:
            _store_batch(stage.name, finished, store, context)
            finished, finished_items = [], 0
    if finished:
        _store_batch(stage.name, finished, store, context)
    keys = [task.key for task in tasks]
    table = _stored_table(stage, tasks, store)
    context.tables[stage.name] = table
    failures = store.failures(stage.name, keys)
    stage_failures = [named_now(failures[t.key], t.name) for t in tasks if t.key in failures]
    summary.failed = len(stage_failures)
    report.failures += stage_failures
    context.item_keys[stage.name] = keys
    if table.empty and tasks:
        summary.status = "failed"
        summary.message = f"no item computed ({summary.failed} failed of {summary.items})"


def _store_batch(
    name: str, finished: list[tuple[Group, bool, Any]], store: Store, context: Context
) -> None:
    """Store finished groups as one segment per stage: their rows and failures, and those of
    the followers' items computed with them (remembered in ``context.chained``). A group whose
    worker failed as a whole (it died, say) fails each of its items."""
    import pandas as pd

    computed: Computed = []
    for group, ok, value in finished:
        if ok:
            computed += value
        else:
            computed += [
                (name, task.key, Failure(task.name, name, value.error_type, value.message))
                for task in group[1]
            ]
    rows: dict[str, list[dict[str, Any]]] = {name: []}
    row_keys: dict[str, list[str]] = {name: []}
    failed: dict[str, list[tuple[str, Failure]]] = {name: []}
    for stage, key, value in computed:
        rows.setdefault(stage, [])
        row_keys.setdefault(stage, [])
        failed.setdefault(stage, [])
        if isinstance(value, Failure):
            failed[stage].append((key, value))
        else:
            rows[stage] += value  # the workers' row dicts, not copied: the key is a column
            row_keys[stage] += [key] * len(value)
        if stage != name:
            context.chained.setdefault(stage, set()).add(key)
    for stage in rows:
        table = pd.DataFrame(rows[stage])
        if len(table):
            table.insert(0, KEY_COLUMN, row_keys[stage])
        store.add_rows(stage, table, failed[stage])


def _stored_table(stage: Stage, tasks: list[Task], store: Store) -> pd.DataFrame:
    """The stage's table: each task's stored rows in task order, with the task's context
    columns (the current file path) and ``_key``, and the stage's column dictionary.

    One pass over the store's segments and one join, whatever the number of items (a
    per-item loop of row assignments cost about 3 ms an item).
    """
    import numpy as np
    import pandas as pd

    stored = store.table(stage.name, [task.key for task in tasks])
    context_names = list(dict.fromkeys(name for task in tasks for name in task.context))
    order = pd.DataFrame(
        {
            KEY_COLUMN: [task.key for task in tasks],
            _TASK: np.arange(len(tasks)),
            **{name: [task.context.get(name) for task in tasks] for name in context_names},
        }
    )
    stored = stored.drop(columns=[c for c in context_names if c in stored.columns])
    stored[_ROW] = np.arange(len(stored))
    table = order.merge(stored, on=KEY_COLUMN, how="inner", sort=False)
    table = table.sort_values([_TASK, _ROW], kind="stable", ignore_index=True)
    columns = [*stage.columns(), KEY_COLUMN]
    table = table[[c for c in columns if c in table.columns]]
    if table.empty:
        table = pd.DataFrame(columns=columns)
    set_column_dictionary(
        table,
        pd.DataFrame(
            [(name, unit, meaning) for name, (unit, meaning) in stage.columns().items()],
            columns=["column", "unit", "meaning"],
        ),
    )
    return table


def _run_set(
    stage: Stage, context: Context, store: Store, summary: StageSummary, force: bool
) -> None:
    assert stage.set_key is not None and stage.run_set is not None
    summary.items = 1
    key = stage.set_key(context)
    target = store.set_dir(stage.name, key)
    if store.has_set(stage.name, key) and not force:
        summary.cached = 1
    else:
        summary.computed = 1
        temporary = store.new_set_dir(stage.name, key)
        try:
            stage.run_set(context, temporary)
        except Exception as error:  # the run goes on; this output is reported missing
            shutil.rmtree(temporary, ignore_errors=True)
            if isinstance(error, OSError) and error.errno in DISK_ERRORS:
                raise StorageError(Path(error.filename or temporary), error) from None
            summary.failed = 1
            summary.status = "failed"
            summary.message = Failure.from_exception(context.workflow.path.name, stage.name,
                                                     error).message  # fmt: skip
            return
        store.commit_set(stage.name, key, temporary)
        if stage.latest_set_only:
            store.drop_other_sets(stage.name, key)
    context.set_keys[stage.name] = key
    context.set_dirs[stage.name] = target


def _publish(
    workflow: Workflow,
    stages: StageTable,
    context: Context,
    report: RunReport,
    store: Store,
    *,
    now: str,
    prune: bool,
) -> None:
    try:
        _publish_outputs(workflow, stages, context, report, store, now=now, prune=prune)
    except OSError as error:
        raise StorageError(Path(error.filename or workflow.outputs_folder), error) from None


def _publish_outputs(
    workflow: Workflow,
    stages: StageTable,
    context: Context,
    report: RunReport,
    store: Store,
    *,
    now: str,
    prune: bool,
) -> None:
    folder = workflow.outputs_folder
    with_history = [n for n in workflow.outputs if workflow.history and stages[n].kind == "item"]
    failures_seen = failures_first_seen(store, with_history)
    new_failures: set[tuple[str, str]] = set()
    for name in stages:
        if name not in workflow.outputs:  # an output turned off leaves nothing behind
            removed = withdraw_published(store, name, folder, only_of=workflow.path)
            if removed:
                report.removed[name] = removed
    for name in workflow.outputs:
        stage = stages[name]
        summary = next(s for s in report.stages if s.name == name)
        if summary.status != "ok":
            report.missing[name] = summary.message or summary.status
            _withdraw_earlier(store, name, folder, report)
            if workflow.history and stage.kind == "item":  # its failures are seen now
                new_failures |= history_without_output(
                    name, workflow, stages, context, store,
                    now=now, prune=prune, failures_seen=failures_seen,
                )  # fmt: skip
                report.new_failures = len(new_failures)
            continue
        folder.mkdir(parents=True, exist_ok=True)
        if stage.kind == "item":
            made = item_outputs(
                name, workflow, stages, context, store,
                now=now, prune=prune, failures_seen=failures_seen,
            )  # fmt: skip
            paths = publish_output_table(made.table, folder / f"{name}.parquet", store, name)
            failures_file = failures_path(folder / f"{name}.csv")
            _write_csv(made.failures, failures_file)
            paths.append(failures_file)
            if made.new_failures is not None:  # each failure once, whatever outputs list it
                new_failures |= made.new_failures
                report.new_failures = len(new_failures)
        else:
            assert stage.publish is not None
            paths, problem = publish_set(stage.publish, folder, store, name, context.set_keys[name])
            if problem:  # never a damaged copy published as complete
                report.missing[name] = problem
                _withdraw_earlier(store, name, folder, report)
                continue
        remember_published(store, name, folder, paths, workflow.path)
        report.outputs[name] = [str(p) for p in paths]


def _withdraw_earlier(store: Store, name: str, folder: Path, report: RunReport) -> None:
    """An output this run could not produce: what an earlier run published of it is removed
    (a site model and report of 8 records stayed beside the features of the 3 left, which gave
    no site, as if they were this run's), and named in the summary."""
    removed = withdraw_published(store, name, folder)
    if removed:
        report.removed[name] = removed


def _write_csv(table: pd.DataFrame, path: Path) -> None:
    from stepframe.core.io import atomic_write

    with atomic_write(path) as out:
        table.to_csv(out, index=False, lineterminator="\n")


def _dry_run(
    workflow: Workflow,
    stages: StageTable,
    planned: list[str],
    store: Store,
    forced: list[str],
    retry_failed: bool,
) -> RunReport:
    """What a run would do: per stage, items to compute and cached (nothing written)."""
    report = RunReport(str(workflow.path), str(workflow.workspace), "dry run", True)
    context = Context(workflow, {}, {}, {}, {}, None, None, False, started_utc=utc_now())

    for name in planned:
        stage = stages[name]
        summary = StageSummary(name, stage.kind)
        blocked = [u for u in stage.upstream(workflow) if not _available(context, u)]
        if blocked:
            summary.status = "pending"
            summary.message = f"depends on {blocked[0]}, not yet complete"
        elif stage.kind == "item":
            assert stage.tasks is not None
            tasks = merge_same_key(stage.tasks(context))
            context.item_tasks[name] = tasks  # as a run's: a whole-set key may name them
            report.duplicates += alias_lines(name, tasks)
            index = store.index(name)
            todo = [
                t
                for t in tasks
                if name in forced or t.key not in index or (index[t.key].failed and retry_failed)
            ]
            summary.items, summary.computed = len(tasks), len(todo)
            summary.cached = len(tasks) - len(todo)
            if todo:
                summary.status = "pending"
                summary.message = f"{len(todo)} item(s) to compute"
            else:
                context.tables[name] = _stored_table(stage, tasks, store)
        else:
            assert stage.set_key is not None
            key = stage.set_key(context)
            summary.items = 1
            if store.has_set(name, key) and name not in forced:
                summary.cached = 1
                context.set_keys[name] = key
                context.set_dirs[name] = store.set_dir(name, key)
            else:
                summary.computed = 1
        report.stages.append(summary)
    report.store_events = store.events
    return report
