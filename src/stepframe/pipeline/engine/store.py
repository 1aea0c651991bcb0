"""The content-addressed store of a workspace: per-item rows in Parquet, whole-set results.

Layout (under ``<workspace>/store/<stage>/``)::

    seg-<time_ns>-<pid>.parquet      rows computed in one batch: column ``_key`` + the stage's
                                     columns (an item may have several rows, all with its key)
    fail-<time_ns>-<pid>.parquet     the batch's failed items: ``_key``, item, stage,
                                     error_type, message
    sets/<key>/                      the files of one whole-set result (site model, curve, ...)

A key is the sha256 of the item's input content (the file's bytes, never its path or mtime), the
stage's name, version and parameters, and the keys of what it was computed from
(:func:`make_key`); so renaming a folder keeps every key, a changed file or parameter changes the
keys downstream of it only.

There is no index file to corrupt: the index (key → segment) is rebuilt from the segment files
every time a store is opened, reading only their ``_key`` column. A segment written later wins
over an earlier one with the same key (``--force``, ``--retry-failed``); segment names sort in
write order. Every file is written with :func:`stepframe.core.io.atomic_write`; a whole-set
result is written into a hidden temporary folder that is renamed into place, so a killed run
leaves either the whole result or a temporary that the next run removes. Nothing is pickled.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import time
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from stepframe.core.io import TEMPORARY_SUFFIX, atomic_write, publish_folder
from stepframe.core.results import FAILURE_COLUMNS, Failure

if TYPE_CHECKING:
    import pandas as pd

KEY_COLUMN = "_key"
_HASH_BLOCK = 1 << 20


def file_sha256(path: str | os.PathLike[str]) -> str:
    """sha256 of a file's bytes (hex)."""
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        while block := handle.read(_HASH_BLOCK):
            digest.update(block)
    return digest.hexdigest()


def canonical_json(value: Any) -> str:
    """JSON with sorted keys and no spaces: the same parameters always give the same text."""
    return json.dumps(value, sort_keys=True, separators=(",", ":"), allow_nan=True, default=str)


def make_key(stage: str, version: int, parameters: Mapping[str, Any], *inputs: str) -> str:
    """The store key of one result: sha256 of stage, version, parameters and input keys/hashes.

    Parameters
    ----------
    stage, version
        The stage's name and version (a new version invalidates its results).
    parameters
        The stage's parameters (plain JSON-able values).
    inputs
        Content hashes of the input files and keys of the upstream results, in a fixed order.
    """
    text = canonical_json({"stage": stage, "version": version, "parameters": parameters})
    digest = hashlib.sha256(text.encode())
    for item in inputs:
        digest.update(b"\0" + item.encode())
    return digest.hexdigest()


@dataclass(frozen=True)
class Entry:
    """Where a key's latest result is: a results segment (``failed`` False) or a failure one."""

    segment: Path
    failed: bool


class Store:
    """The store folder of a workspace (see the module docstring).

    Parameters
    ----------
    root
        ``<workspace>/store``; created by :meth:`prepare`, not by the constructor (a dry run
        writes nothing).
    """

    def __init__(self, root: Path) -> None:
        self.root = root
        self._index: dict[str, dict[str, Entry]] = {}

    def stage_dir(self, stage: str) -> Path:
        """The folder of one stage's results."""
        return self.root / stage

    def prepare(self) -> None:
        """Create the store and remove what killed runs left (temporary files and folders).

        Call only while holding the workspace lock: a temporary of a running writer would
        otherwise be removed under it.
        """
        self.root.mkdir(parents=True, exist_ok=True)
        for temporary in list(self.root.rglob(f"*{TEMPORARY_SUFFIX}")):
            if temporary.is_dir():
                shutil.rmtree(temporary, ignore_errors=True)
            else:
                temporary.unlink(missing_ok=True)

    # -- per-item rows -------------------------------------------------------------------------

    def index(self, stage: str) -> dict[str, Entry]:
        """key → latest :class:`Entry` of a per-item stage, rebuilt from the segment files."""
        if stage not in self._index:
            self._index[stage] = self._scan(stage)
        return self._index[stage]

    def _scan(self, stage: str) -> dict[str, Entry]:
        import pyarrow.parquet as pq

        folder = self.stage_dir(stage)
        entries: dict[str, Entry] = {}
        if not folder.is_dir():
            return entries
        segments = sorted(
            (p for p in folder.glob("*.parquet") if p.name.startswith(("seg-", "fail-"))),
            key=lambda p: p.name.split("-", 1)[1],
        )
        for segment in segments:
            keys = pq.read_table(segment, columns=[KEY_COLUMN]).column(KEY_COLUMN).to_pylist()
            failed = segment.name.startswith("fail-")
            for key in keys:
                entries[str(key)] = Entry(segment, failed)
        return entries

    def _segment_name(self, prefix: str) -> str:
        # time_ns then pid: names sort in write order, and two processes never collide.
        return f"{prefix}-{time.time_ns():020d}-{os.getpid()}.parquet"

    def add_rows(
        self, stage: str, rows: pd.DataFrame, failures: Iterable[tuple[str, Failure]]
    ) -> None:
        """Store one batch: ``rows`` (with a ``_key`` column) and ``(key, failure)`` pairs."""
        import pandas as pd

        folder = self.stage_dir(stage)
        folder.mkdir(parents=True, exist_ok=True)
        index = self.index(stage)
        failed = list(failures)
        if len(rows):
            path = folder / self._segment_name("seg")
            _write_parquet(rows, path)
            for key in rows[KEY_COLUMN].unique():
                index[str(key)] = Entry(path, False)
        if failed:
            table = pd.DataFrame(
                [{KEY_COLUMN: key, **failure.to_dict()} for key, failure in failed],
                columns=[KEY_COLUMN, *FAILURE_COLUMNS],
            )
            path = folder / self._segment_name("fail")
            _write_parquet(table, path)
            for key, _ in failed:
                index[key] = Entry(path, True)

    def rows(self, stage: str, keys: Iterable[str]) -> dict[str, pd.DataFrame]:
        """The stored rows of each successful key (keys whose latest entry is a failure or
        missing are left out), each with the ``_key`` column."""
        import pandas as pd

        wanted: dict[Path, set[str]] = {}
        index = self.index(stage)
        for key in keys:
            entry = index.get(key)
            if entry is not None and not entry.failed:
                wanted.setdefault(entry.segment, set()).add(key)
        out: dict[str, pd.DataFrame] = {}
        for segment, segment_keys in wanted.items():
            table = pd.read_parquet(segment)
            selected = table[table[KEY_COLUMN].isin(segment_keys)]
            for group_key, group in selected.groupby(KEY_COLUMN, sort=False):
                out[str(group_key)] = group.reset_index(drop=True)
        return out

    def table(self, stage: str, keys: Iterable[str]) -> pd.DataFrame:
        """The stored rows of every successful key among ``keys`` as one table (with ``_key``),
        each segment read once; rows of a key keep their stored order, keys come in no
        particular order (the runner orders them)."""
        import pandas as pd

        wanted: dict[Path, set[str]] = {}
        index = self.index(stage)
        for key in keys:
            entry = index.get(key)
            if entry is not None and not entry.failed:
                wanted.setdefault(entry.segment, set()).add(key)
        parts = []
        for segment, segment_keys in wanted.items():
            table = pd.read_parquet(segment)
            parts.append(table[table[KEY_COLUMN].isin(segment_keys)])
        if not parts:
            return pd.DataFrame(columns=[KEY_COLUMN])
        return pd.concat(parts, ignore_index=True) if len(parts) > 1 else parts[0]

    def failures(self, stage: str, keys: Iterable[str]) -> dict[str, Failure]:
        """The stored failure of each key whose latest entry is a failure."""
        import pandas as pd

        wanted: dict[Path, set[str]] = {}
        index = self.index(stage)
        for key in keys:
            entry = index.get(key)
            if entry is not None and entry.failed:
                wanted.setdefault(entry.segment, set()).add(key)
        out: dict[str, Failure] = {}
        for segment, segment_keys in wanted.items():
            table = pd.read_parquet(segment)
            selected = table[table[KEY_COLUMN].isin(segment_keys)]
            for record in selected.to_dict(orient="records"):
                out[str(record[KEY_COLUMN])] = Failure(
                    str(record["item"]),
                    str(record["stage"]),
                    str(record["error_type"]),
                    str(record["message"]),
                )
        return out

    # -- whole-set results -----------------------------------------------------------------------

    def set_dir(self, stage: str, key: str) -> Path:
        """The folder of one whole-set result (it exists only once complete)."""
        return self.stage_dir(stage) / "sets" / key

    def new_set_dir(self, stage: str, key: str) -> Path:
        """A fresh hidden temporary folder to write a whole-set result into."""
        parent = self.stage_dir(stage) / "sets"
        parent.mkdir(parents=True, exist_ok=True)
        temporary = parent / f".{key}.{os.getpid()}{TEMPORARY_SUFFIX}"
        if temporary.exists():
            shutil.rmtree(temporary)
        temporary.mkdir()
        return temporary

    def commit_set(self, stage: str, key: str, temporary: Path) -> Path:
        """Move a complete temporary folder into place (atomic on one filesystem); with
        ``--force`` the new result replaces the old one."""
        return publish_folder(temporary, self.set_dir(stage, key))


def _write_parquet(table: pd.DataFrame, path: Path) -> None:
    """A DataFrame as Parquet through :func:`atomic_write` (attrs left out: not tabular)."""
    plain = table.copy()
    plain.attrs = {}
    with atomic_write(path, "wb") as out:
        plain.to_parquet(out, index=False, engine="pyarrow")


def write_output_table(table: pd.DataFrame, path: Path) -> list[Path]:
    """Write a final table as Parquet, with a CSV copy for people and its column dictionary
    (:func:`stepframe.core.tables.write_table`: ``X.csv`` and ``X.columns.csv``), atomically.

    Returns the paths written (Parquet first).
    """
    from stepframe.core.tables import write_table

    _write_parquet(table, path)
    return [path, *write_table(table, path.with_suffix(".csv"))]
