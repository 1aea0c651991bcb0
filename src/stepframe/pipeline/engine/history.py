"""The outputs of a per-item stage: its table and its failures, and what earlier runs saw.

The failures table of an output lists the failures of the stage *and of every per-item stage it
is computed from*: a record file that cannot be read is a failure of the inventory, and it is
in ``features.failures.csv`` too (a component of it has no features).

With ``[outputs] history = true`` (the shipped ``inbox`` workflow) an output keeps what it saw:
each item and each failure gets ``first_seen_utc`` and ``last_seen_utc`` (the start of the runs
that first and last found it), ``present`` (among this run's inputs; false once its file has
left the folder, or once a failure is mended), and each failure ``new`` (first seen by this run).
The rows of absent items come from the store, which keeps every result. What was seen is the
stage's history in the store (``store/<stage>/history.parquet``, checksummed like every stored
object); ``stepframe run --prune`` drops the absent ones. These tables carry times, so unlike
every other output they differ from one run to the next.
"""

from __future__ import annotations

import io
import json
from dataclasses import dataclass
from typing import TYPE_CHECKING

from stepframe.core.results import FAILURE_COLUMNS, Failure, failures_table, set_column_dictionary
from stepframe.pipeline.engine.same_content import named_now
from stepframe.pipeline.engine.stage import Context, StageTable
from stepframe.pipeline.engine.store import KEY_COLUMN, Store

if TYPE_CHECKING:
    import pandas as pd

    from stepframe.pipeline.engine.workflow import Workflow

HISTORY_FILE = "history.parquet"
#: What the history holds per (stage, kind, key): kind ``row`` (an item with results) or
#: ``failure``; the item's name and context columns (JSON) or the failure's type and message.
HISTORY_COLUMNS = (KEY_COLUMN, "stage", "kind", "name", "context", "error_type", "message",
                   "first_seen_utc", "last_seen_utc")  # fmt: skip
SEEN_COLUMNS: dict[str, tuple[str, str]] = {
    "present": ("", "among this run's inputs (false: its file has left the folder)"),
    "first_seen_utc": ("", "start of the first run that found it (UTC)"),
    "last_seen_utc": ("", "start of the last run that found it (UTC)"),
}
NEW_COLUMN = ("new", "first found by this run")


@dataclass(frozen=True)
class ItemOutputs:
    """What a per-item stage publishes: its table, its failures table, and the failures this
    run found first, each as (stage, key) (None without a history)."""

    table: pd.DataFrame
    failures: pd.DataFrame
    new_failures: frozenset[tuple[str, str]] | None


def failures_first_seen(store: Store, names: list[str]) -> dict[tuple[str, str], str]:
    """When each failure, as (stage, key), was first seen by any of the outputs ``names``.

    A file that cannot be read is a failure of the inventory in the failures table of every
    output computed from it, and each output keeps its own history: a failure is new to a run
    only if no output saw it before (else one damaged file counted as 3 new failures with
    ``features``, ``measures`` and ``rotd50``, and an output turned on later marked every old
    failure new again)."""
    seen: dict[tuple[str, str], str] = {}
    for name in names:
        history = _read(store, name)
        failed = history[history["kind"] == "failure"]
        for key, stage, first in zip(
            failed[KEY_COLUMN], failed["stage"], failed["first_seen_utc"], strict=True
        ):
            identity = (str(stage), str(key))
            seen[identity] = min(seen.get(identity, str(first)), str(first))
    return seen


def item_stages(name: str, workflow: Workflow, stages: StageTable) -> list[str]:
    """The per-item stages ``name`` is computed from, upstream first, and ``name`` itself."""
    order: list[str] = []

    def visit(stage: str) -> None:
        for upstream in stages[stage].upstream(workflow):
            visit(upstream)
        if stages[stage].kind == "item" and stage not in order:
            order.append(stage)

    visit(name)
    return order


def _current_failures(
    name: str, workflow: Workflow, stages: StageTable, context: Context, store: Store
) -> list[tuple[str, str, Failure]]:
    """(stage, key, failure) of this run's failed items of ``name`` and its upstream stages."""
    found = []
    for stage in item_stages(name, workflow, stages):
        tasks = context.item_tasks.get(stage, [])
        stored = store.failures(stage, [task.key for task in tasks])
        found += [(stage, t.key, named_now(stored[t.key], t.name))
                  for t in tasks if t.key in stored]  # fmt: skip
    return found


def item_outputs(
    name: str,
    workflow: Workflow,
    stages: StageTable,
    context: Context,
    store: Store,
    *,
    now: str,
    prune: bool,
    failures_seen: dict[tuple[str, str], str] | None = None,
) -> ItemOutputs:
    """The table and failures table of the per-item stage ``name`` (see the module docstring).

    Parameters
    ----------
    now
        The run's start (UTC, ISO 8601): its seen time.
    prune
        Drop from the history the items and failures this run did not find.
    failures_seen
        When the outputs published with this one first saw each failure
        (:func:`failures_first_seen`): a failure one of them saw is not new to this one.
    """
    table = context.tables[name]
    if not workflow.history:
        failed = _current_failures(name, workflow, stages, context, store)
        plain = table.drop(columns=[KEY_COLUMN])
        plain.attrs = dict(table.attrs)
        return ItemOutputs(plain, failures_table([f for _, _, f in failed]), None)
    history = _seen_now(name, workflow, stages, context, store, table, now, prune, failures_seen)
    return ItemOutputs(
        _table_with_history(table, history, name, store),
        _failures_with_history(history, now),
        _new_failures(history, now),
    )


def history_without_output(
    name: str,
    workflow: Workflow,
    stages: StageTable,
    context: Context,
    store: Store,
    *,
    now: str,
    prune: bool,
    failures_seen: dict[tuple[str, str], str] | None = None,
) -> frozenset[tuple[str, str]]:
    """The history of a per-item output this run could not produce (every file failed),
    brought up to date with this run's failures, which it returns as :attr:`ItemOutputs.
    new_failures`: they are new in this run, the one that found them (they were new in the
    next run that produced the output, or never if the file left before it)."""
    import pandas as pd

    empty = pd.DataFrame(columns=[KEY_COLUMN])
    history = _seen_now(name, workflow, stages, context, store, empty, now, prune, failures_seen)
    return _new_failures(history, now)


def _seen_now(
    name: str,
    workflow: Workflow,
    stages: StageTable,
    context: Context,
    store: Store,
    table: pd.DataFrame,
    now: str,
    prune: bool,
    failures_seen: dict[tuple[str, str], str] | None,
) -> pd.DataFrame:
    """The output's history with this run's items (``table``) and failures, written."""
    failed = _current_failures(name, workflow, stages, context, store)
    history = _updated(
        _read(store, name), name, context, table, failed, now, prune, failures_seen or {}
    )
    store.write_file(name, HISTORY_FILE, _parquet(history))
    return history


def _new_failures(history: pd.DataFrame, now: str) -> frozenset[tuple[str, str]]:
    new = history[(history["kind"] == "failure") & (history["first_seen_utc"] == now)]
    return frozenset(zip(map(str, new["stage"]), map(str, new[KEY_COLUMN]), strict=True))


def _read(store: Store, name: str) -> pd.DataFrame:
    import pandas as pd

    data = store.read_file(name, HISTORY_FILE)
    if data is None:
        return pd.DataFrame({column: pd.Series(dtype=str) for column in HISTORY_COLUMNS})
    return pd.read_parquet(io.BytesIO(data))


def _parquet(table: pd.DataFrame) -> bytes:
    buffer = io.BytesIO()
    table.to_parquet(buffer, index=False, engine="pyarrow")
    return buffer.getvalue()


def _updated(
    history: pd.DataFrame,
    name: str,
    context: Context,
    table: pd.DataFrame,
    failed: list[tuple[str, str, Failure]],
    now: str,
    prune: bool,
    failures_seen: dict[tuple[str, str], str],
) -> pd.DataFrame:
    """The history with this run's items and failures seen ``now`` (a failure another output
    saw first keeps its first time)."""
    import pandas as pd

    with_rows = set(table[KEY_COLUMN])
    current = [
        (
            t.key,
            name,
            "row",
            t.name,
            json.dumps(dict(t.context), sort_keys=True, default=str),
            "",
            "",
        )
        for t in context.item_tasks.get(name, [])
        if t.key in with_rows
    ]
    current += [
        (key, stage, "failure", failure.item, "", failure.error_type, failure.message)
        for stage, key, failure in failed
    ]
    now_table = pd.DataFrame(current, columns=list(HISTORY_COLUMNS[:-2]))
    identity = [KEY_COLUMN, "stage", "kind"]
    first_seen = history.set_index(identity)["first_seen_utc"].to_dict()
    now_table["first_seen_utc"] = [
        first_seen.get(
            (key, stage, kind),
            failures_seen.get((stage, key), now) if kind == "failure" else now,
        )
        for key, stage, kind in now_table[identity].itertuples(index=False)
    ]
    now_table["last_seen_utc"] = now
    if prune or history.empty:
        return now_table.reset_index(drop=True)
    seen = set(map(tuple, now_table[identity].itertuples(index=False)))
    earlier = history[[tuple(row) not in seen for row in history[identity].itertuples(index=False)]]
    return pd.concat([now_table, earlier], ignore_index=True)


def _table_with_history(
    table: pd.DataFrame, history: pd.DataFrame, name: str, store: Store
) -> pd.DataFrame:
    """The items of this run (present) and those of earlier runs (absent), with seen times."""
    import pandas as pd

    from stepframe.core.results import get_column_dictionary

    rows = history[history["kind"] == "row"]
    seen: dict[str, dict[str, str]] = {
        str(key): {"context": context, "first": first, "last": last}
        for key, context, first, last in zip(
            rows[KEY_COLUMN], rows["context"], rows["first_seen_utc"], rows["last_seen_utc"],
            strict=True,
        )
    }  # fmt: skip
    present = table.copy()
    present["present"] = True
    present["first_seen_utc"] = [seen[str(k)]["first"] for k in present[KEY_COLUMN]]
    present["last_seen_utc"] = [seen[str(k)]["last"] for k in present[KEY_COLUMN]]
    now = set(map(str, table[KEY_COLUMN]))
    absent = [key for key in seen if key not in now]
    # one read of the store for every absent item (a key no longer stored is left out)
    gone = store.table(name, absent)
    order = {key: position for position, key in enumerate(absent)}
    gone = gone.iloc[sorted(range(len(gone)), key=lambda i: order[str(gone[KEY_COLUMN].iat[i])])]
    contexts = {key: json.loads(seen[key]["context"]) for key in absent}
    keys = [str(key) for key in gone[KEY_COLUMN]]
    for column in dict.fromkeys(c for context in contexts.values() for c in context):
        gone[column] = [contexts[key].get(column) for key in keys]
    gone["present"] = False
    gone["first_seen_utc"] = [seen[key]["first"] for key in keys]
    gone["last_seen_utc"] = [seen[key]["last"] for key in keys]
    parts = [present, gone] if len(gone) else [present]  # an empty part would change dtypes
    out = pd.concat(parts, ignore_index=True)[list(present.columns)].drop(columns=[KEY_COLUMN])
    dictionary = get_column_dictionary(table)
    if dictionary is not None:
        extra = pd.DataFrame(
            [(column, unit, meaning) for column, (unit, meaning) in SEEN_COLUMNS.items()],
            columns=["column", "unit", "meaning"],
        )
        set_column_dictionary(out, pd.concat([dictionary, extra], ignore_index=True))
    return out


def _failures_with_history(history: pd.DataFrame, now: str) -> pd.DataFrame:
    """Every failure seen: this run's (present), and earlier ones (absent or mended)."""
    import pandas as pd

    failed = history[history["kind"] == "failure"]
    out = pd.DataFrame(
        {
            "item": failed["name"],
            "stage": failed["stage"],
            "error_type": failed["error_type"],
            "message": failed["message"],
            "first_seen_utc": failed["first_seen_utc"],
            "last_seen_utc": failed["last_seen_utc"],
            "present": failed["last_seen_utc"] == now,
            "new": failed["first_seen_utc"] == now,
        }
    ).reset_index(drop=True)
    meanings = [
        *FAILURE_COLUMNS.items(),
        *((column, meaning) for column, (_, meaning) in SEEN_COLUMNS.items()),
        NEW_COLUMN,
    ]
    order = ["item", "stage", "error_type", "message", "first_seen_utc", "last_seen_utc",
             "present", "new"]  # fmt: skip
    meaning_of = dict(meanings)
    return set_column_dictionary(
        out[order],
        pd.DataFrame(
            [(column, "", meaning_of[column]) for column in order],
            columns=["column", "unit", "meaning"],
        ),
    )
