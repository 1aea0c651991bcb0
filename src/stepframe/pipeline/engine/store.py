"""The content-addressed store of a workspace: per-item rows in Parquet, whole-set results.

Layout (under ``<workspace>/store/<stage>/``)::

    index.json                       every object of the stage with its sha256 and size
                                     (:mod:`stepframe.pipeline.engine.integrity`)
    seg-<time_ns>-<pid>-<sha256>.parquet
                                     rows computed in one batch: column ``_key`` + the stage's
                                     columns (an item may have several rows, all with its key)
    fail-<time_ns>-<pid>-<sha256>.parquet
                                     the batch's failed items: ``_key``, item, stage,
                                     error_type, message
    sets/<key>/                      the files of one whole-set result (site model, curve, ...)

and ``<workspace>/store/quarantine/<stage>/`` holds the damaged objects a run moved aside.

A key is the sha256 of the item's input content (the file's bytes, never its path or mtime), the
stage's name, version and parameters, and the keys of what it was computed from
(:func:`make_key`); so renaming a folder keeps every key, a changed file or parameter changes the
keys downstream of it only.

Nothing is read unverified. Opening a stage reads each segment once, checks it against the
index (and its name), and keeps its bytes for the run; a whole-set result's files are checked
before it is used and its published copies after they are written. A damaged or missing object
is quarantined and recomputed, and named in the run's summary (:attr:`Store.events`). The key →
segment map is rebuilt from the segments' ``_key`` columns: a segment written later wins over
an earlier one with the same key (``--force``, ``--retry-failed``); segment names sort in write
order. Each object is written with :func:`stepframe.core.io.atomic_write` before the index names
it; a segment a killed run wrote but did not index is adopted (its name carries its checksum). A
whole-set result is written into a hidden temporary folder that is renamed into place. Small
segments (a scheduled run's few new items) are merged (:meth:`Store.compact`). Nothing is
pickled.
"""

from __future__ import annotations

import functools
import hashlib
import io
import json
import os
import re
import shutil
import time
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from stepframe.core.io import TEMPORARY_SUFFIX, atomic_write, publish_folder
from stepframe.core.results import FAILURE_COLUMNS, Failure
from stepframe.pipeline.engine.integrity import (
    INDEX_FILE,
    QUARANTINE,
    Checksum,
    Expected,
    StageIndex,
    StorageError,
    StoreEvent,
    check_folder,
    folder_manifest,
    make_folder,
    quarantine,
    read_index,
    read_verified,
    sha256_hex,
    write_object,
)

if TYPE_CHECKING:
    import pandas as pd

KEY_COLUMN = "_key"


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
    return KeyPrefix(stage, version, parameters).key(*inputs)


class KeyPrefix:
    """What the keys of one stage's items share (stage, version, parameters), hashed once.

    ``KeyPrefix(stage, version, parameters).key(*inputs)`` is :func:`make_key` with the same
    arguments, byte for byte: the prefix's sha256 state is copied and each input fed to it as
    :func:`make_key` does. A stage listing 43,000 tasks made the same parameters' JSON and
    hash 43,000 times (about 1.2 s of a no-op re-run's 12 s, docs/benchmarks.md).

    Parameters
    ----------
    stage, version, parameters
        As :func:`make_key`'s; the parameters are read once, here.
    """

    __slots__ = ("_digest", "_text")

    def __init__(self, stage: str, version: int, parameters: Mapping[str, Any]) -> None:
        self._text = canonical_json({"stage": stage, "version": version, "parameters": parameters})
        self._digest = hashlib.sha256(self._text.encode())

    def __reduce__(self) -> tuple[Any, tuple[str]]:
        # a sha256 state does not pickle; its text does (a prefix goes to the workers inside a
        # stage's expand arguments)
        return _key_prefix_of, (self._text,)

    def key(self, *inputs: str) -> str:
        """The key of one item computed from ``inputs`` (in :func:`make_key`'s order)."""
        digest = self._digest.copy()
        for item in inputs:
            digest.update(b"\0" + item.encode())
        return digest.hexdigest()


def _key_prefix_of(text: str) -> KeyPrefix:
    """A :class:`KeyPrefix` from its canonical JSON text (unpickling)."""
    prefix = KeyPrefix.__new__(KeyPrefix)
    prefix._text = text
    prefix._digest = hashlib.sha256(text.encode())
    return prefix


#: Segments smaller than this [bytes] are merged once a stage has :data:`COMPACT_AT` of them.
SMALL_SEGMENT_BYTES = 1 << 20
COMPACT_AT = 8
_SEGMENT_NAME = re.compile(r"^(seg|fail)-(\d+)-(\d+)(?:-([0-9a-f]{64}))?\.parquet$")


def _order(name: str) -> tuple[int, int, str]:
    """Write order of a segment name: its time, then its process id."""
    match = _SEGMENT_NAME.match(name)
    assert match is not None
    return int(match.group(2)), int(match.group(3)), name


@dataclass(frozen=True)
class Entry:
    """Where a key's latest result is: a results segment (``failed`` False) or a failure one."""

    segment: Path
    failed: bool


@dataclass
class _Segment:
    """A verified segment, its bytes kept for the run (read once, never re-read unchecked)."""

    name: str
    checksum: Checksum
    data: bytes
    keys: list[str]

    @property
    def failed(self) -> bool:
        return self.name.startswith("fail-")

    @functools.cached_property
    def distinct(self) -> int:
        """How many different keys the segment holds (fewer than its rows: a key has several)."""
        return len(set(self.keys))


@dataclass
class _Stage:
    """What the store knows of one stage: its verified segments, its sets, key → entry."""

    segments: dict[str, _Segment] = field(default_factory=dict)
    sets: dict[str, dict[str, Checksum]] = field(default_factory=dict)
    files: dict[str, Checksum] = field(default_factory=dict)
    entries: dict[str, Entry] = field(default_factory=dict)


class Store:
    """The store folder of a workspace (see the module docstring).

    Parameters
    ----------
    root
        ``<workspace>/store``; created by :meth:`prepare`, not by the constructor (a dry run
        writes nothing).
    dry
        Write nothing: damaged objects are reported, not moved (a dry run).
    then
        What follows a damaged object's quarantine, in its event: a run recomputes it; ``store
        verify`` leaves that to the next run that needs it (its events said "recomputed").

    Attributes
    ----------
    events
        The damaged or missing objects found so far, and what was done.
    """

    def __init__(self, root: Path, *, dry: bool = False, then: str = "recomputed") -> None:
        self.root = root
        self.dry = dry
        self.then = then
        self.events: list[StoreEvent] = []
        self._stages: dict[str, _Stage] = {}

    def stage_dir(self, stage: str) -> Path:
        """The folder of one stage's results."""
        return self.root / stage

    def prepare(self) -> None:
        """Create the store and remove what killed runs left (temporary files and folders).

        Call only while holding the workspace lock: a temporary of a running writer would
        otherwise be removed under it.
        """
        make_folder(self.root)
        for temporary in list(self.root.rglob(f"*{TEMPORARY_SUFFIX}")):
            if temporary.is_dir():
                shutil.rmtree(temporary, ignore_errors=True)
            else:
                temporary.unlink(missing_ok=True)

    def stages(self) -> list[str]:
        """The stages with a folder in the store."""
        if not self.root.is_dir():
            return []
        return sorted(p.name for p in self.root.iterdir() if p.is_dir() and p.name != QUARANTINE)

    # -- opening a stage: every object verified ---------------------------------------------

    def _stage(self, stage: str) -> _Stage:
        if stage not in self._stages:
            self._stages[stage] = self._open(stage)
        return self._stages[stage]

    def _open(self, stage: str) -> _Stage:
        folder = self.stage_dir(stage)
        state = _Stage()
        if folder.exists() and not folder.is_dir():  # a file where the stage's folder belongs
            self.events.append(
                quarantine(self.root, stage, folder, "not a folder", dry=self.dry, then=self.then)
            )
        if not folder.is_dir():
            return state
        index, problem = read_index(folder / INDEX_FILE)
        if problem:
            self.events.append(
                quarantine(
                    self.root,
                    stage,
                    folder / INDEX_FILE,
                    problem,
                    dry=self.dry,
                    then="rebuilt from the segments",
                )
            )
        listed = index.segments if index is not None else {}
        state.sets = dict(index.sets) if index is not None else {}
        state.files = dict(index.files) if index is not None else {}
        on_disk = {p.name for p in folder.iterdir() if _SEGMENT_NAME.match(p.name)}
        changed = index is None and bool(on_disk)
        if changed and not problem:  # deleted, or a store written before checksums
            item = (folder / INDEX_FILE).relative_to(self.root).as_posix()
            self.events.append(StoreEvent(stage, item, "missing", "rebuilt from the segments"))
        for name in sorted(set(listed) | on_disk, key=_order):
            segment, problem = self._read_segment(folder / name, listed.get(name))
            if segment is None:
                self.events.append(quarantine(self.root, stage, folder / name, problem,
                                              dry=self.dry, then=self.then))  # fmt: skip
                changed = True
                continue
            changed = changed or name not in listed
            state.segments[name] = segment
        self._rebuild_entries(stage, state)
        if changed:
            self._save(stage, state)
        return state

    def _read_segment(self, path: Path, listed: Checksum | None) -> tuple[_Segment | None, str]:
        """A segment checked against the index, else against the sha256 in its name (a
        segment a killed run wrote before indexing it), else (a store written before checksums)
        parsed whole."""
        import pyarrow as pa
        import pyarrow.parquet as pq

        match = _SEGMENT_NAME.match(path.name)
        assert match is not None
        expected: Expected | None = listed
        if listed is None and match.group(4):
            expected = (match.group(4), None)
        data, problem = read_verified(path, expected)
        if data is None:
            return None, problem
        try:
            # checked bytes: the keys are enough; unchecked (a store written before checksums):
            # the whole table is parsed, which finds a cut or garbled file
            table = pq.read_table(pa.BufferReader(data), columns=[KEY_COLUMN] if expected else None)
            keys = [str(key) for key in table.column(KEY_COLUMN).to_pylist()]
        except Exception:  # pyarrow raises several types on damaged bytes
            return None, "not a readable Parquet segment"
        sha = expected[0] if expected is not None else sha256_hex(data)  # checked: it matches
        return _Segment(path.name, (sha, len(data)), data, keys), ""

    def _rebuild_entries(self, stage: str, state: _Stage) -> None:
        state.entries = {}
        folder = self.stage_dir(stage)
        for name in sorted(state.segments, key=_order):
            segment = state.segments[name]
            entry = Entry(folder / name, segment.failed)
            for key in segment.keys:
                state.entries[key] = entry

    def _save(self, stage: str, state: _Stage) -> None:
        """Write the stage's index (after the objects it names)."""
        if self.dry:
            return
        segments = {name: segment.checksum for name, segment in state.segments.items()}
        index = StageIndex(segments, state.sets, state.files)
        write_object(self.stage_dir(stage) / INDEX_FILE, index.to_json().encode())

    # -- per-item rows -------------------------------------------------------------------------

    def index(self, stage: str) -> dict[str, Entry]:
        """key → latest :class:`Entry` of a per-item stage (its segments verified)."""
        return self._stage(stage).entries

    def _segment_name(self, prefix: str, sha: str) -> str:
        # time_ns then pid: names sort in write order, and two processes never collide.
        return f"{prefix}-{time.time_ns():020d}-{os.getpid()}-{sha}.parquet"

    def _add_segment(self, stage: str, state: _Stage, prefix: str, table: pd.DataFrame) -> None:
        data = _parquet_bytes(table)
        name = self._segment_name(prefix, sha256_hex(data))
        path = self.stage_dir(stage) / name
        write_object(path, data)
        keys = [str(key) for key in table[KEY_COLUMN]]
        state.segments[name] = segment = _Segment(name, (sha256_hex(data), len(data)), data, keys)
        for key in keys:
            state.entries[key] = Entry(path, segment.failed)

    def add_rows(
        self, stage: str, rows: pd.DataFrame, failures: Iterable[tuple[str, Failure]]
    ) -> None:
        """Store one batch: ``rows`` (with a ``_key`` column) and ``(key, failure)`` pairs."""
        import pandas as pd

        make_folder(self.stage_dir(stage))
        state = self._stage(stage)
        failed = list(failures)
        if len(rows):
            self._add_segment(stage, state, "seg", rows)
        if failed:
            table = pd.DataFrame(
                [{KEY_COLUMN: key, **failure.to_dict()} for key, failure in failed],
                columns=[KEY_COLUMN, *FAILURE_COLUMNS],
            )
            self._add_segment(stage, state, "fail", table)
        if len(rows) or failed:
            self._save(stage, state)

    def _tables(self, stage: str, keys: Iterable[str], failed: bool) -> Iterable[pd.DataFrame]:
        """The rows of ``keys`` whose latest entry is (``failed``) a failure or not, read from
        the verified bytes, a table per segment."""
        import pandas as pd

        state = self._stage(stage)
        wanted: dict[str, set[str]] = {}
        for key in keys:
            entry = state.entries.get(key)
            if entry is not None and entry.failed == failed:
                wanted.setdefault(entry.segment.name, set()).add(key)
        for name, segment_keys in wanted.items():
            segment = state.segments[name]
            table = pd.read_parquet(io.BytesIO(segment.data))
            # Every key of the segment wanted (a no-op re-run's case): no filter, which on a
            # 43,000-row segment's Arrow strings cost about 0.2 s.
            if len(segment_keys) < segment.distinct:
                table = table[table[KEY_COLUMN].isin(segment_keys)]
            # A key's rows come from one computation: an exact repeat is a copy that a store
            # written before one-content-one-item (issue 27) holds; it is read once. Rows of
            # different keys differ in their key: only a segment with a repeated key can have one.
            if segment.distinct < len(segment.keys):
                table = table.drop_duplicates()
            yield table

    def rows(self, stage: str, keys: Iterable[str]) -> dict[str, pd.DataFrame]:
        """The stored rows of each successful key (keys whose latest entry is a failure or
        missing are left out), each with the ``_key`` column."""
        out: dict[str, pd.DataFrame] = {}
        for selected in self._tables(stage, keys, failed=False):
            for group_key, group in selected.groupby(KEY_COLUMN, sort=False):
                out[str(group_key)] = group.reset_index(drop=True)
        return out

    def table(self, stage: str, keys: Iterable[str]) -> pd.DataFrame:
        """The stored rows of every successful key among ``keys`` as one table (with ``_key``),
        each verified segment parsed once; rows of a key keep their stored order, keys come in
        no particular order (the runner orders them)."""
        import pandas as pd

        parts = list(self._tables(stage, keys, failed=False))
        if not parts:
            return pd.DataFrame(columns=[KEY_COLUMN])
        return pd.concat(parts, ignore_index=True) if len(parts) > 1 else parts[0]

    def failures(self, stage: str, keys: Iterable[str]) -> dict[str, Failure]:
        """The stored failure of each key whose latest entry is a failure."""
        out: dict[str, Failure] = {}
        for selected in self._tables(stage, keys, failed=True):
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

    def has_set(self, stage: str, key: str) -> bool:
        """Whether the whole-set result ``key`` is stored and sound: every file as the index
        says. A damaged one is quarantined (and so recomputed)."""
        state = self._stage(stage)
        manifest = state.sets.get(key)
        if manifest is None:
            return False
        target = self.set_dir(stage, key)
        problem = check_folder(target, manifest)
        if not problem:
            return True
        self.events.append(
            quarantine(self.root, stage, target, problem, dry=self.dry, then=self.then)
        )
        if not self.dry:
            del state.sets[key]
            self._save(stage, state)
        return False

    def new_set_dir(self, stage: str, key: str) -> Path:
        """A fresh hidden temporary folder to write a whole-set result into."""
        parent = self.stage_dir(stage) / "sets"
        make_folder(parent)
        temporary = parent / f".{key}.{os.getpid()}{TEMPORARY_SUFFIX}"
        if temporary.exists():
            shutil.rmtree(temporary)
        make_folder(temporary)
        return temporary

    def commit_set(self, stage: str, key: str, temporary: Path) -> Path:
        """Move a complete temporary folder into place (atomic on one filesystem) and index its
        files' checksums; with ``--force`` the new result replaces the old one."""
        state = self._stage(stage)
        manifest = folder_manifest(temporary)
        try:
            target = publish_folder(temporary, self.set_dir(stage, key))
        except OSError as error:
            raise StorageError(self.set_dir(stage, key), error) from None
        state.sets[key] = manifest
        self._save(stage, state)
        return target

    def drop_other_sets(self, stage: str, key: str) -> list[str]:
        """Remove every whole-set result of ``stage`` but ``key`` (the index first: a run killed
        between leaves only unreachable folders, which ``verify`` removes); returns them
        (relative to the store)."""
        state = self._stage(stage)
        others = [other for other in state.sets if other != key]
        if not others:
            return []
        for other in others:
            del state.sets[other]
        self._save(stage, state)
        for other in others:
            shutil.rmtree(self.set_dir(stage, other), ignore_errors=True)
        return [f"{stage}/sets/{other}" for other in others]

    def set_manifest(self, stage: str, key: str) -> dict[str, Checksum]:
        """The stored files of the whole-set result ``key`` and their checksums (empty: none)."""
        return dict(self._stage(stage).sets.get(key, {}))

    def check_published(self, stage: str, key: str, paths: Iterable[Path]) -> str:
        """The first published copy of a stored file that differs from it ("" if none).

        A published file is matched to the stored file whose path inside the result its own
        path ends with (the longest); files made from the result (tables) have no match.
        """
        manifest = self._stage(stage).sets.get(key, {})
        for path in paths:
            text = Path(path).as_posix()
            matches = [name for name in manifest if text.endswith("/" + name)]
            if matches:
                name = max(matches, key=len)
                _, problem = read_verified(Path(path), manifest[name])
                if problem:
                    return f"{path}: {problem}, expected a copy of the stored {name}"
        return ""

    # -- other files of a stage (its history) -----------------------------------------------

    def read_file(self, stage: str, name: str) -> bytes | None:
        """The stage's file ``name`` as last written (None: never written, or damaged, then
        quarantined and named in :attr:`events`)."""
        state = self._stage(stage)
        checksum = state.files.get(name)
        if checksum is None:
            return None
        path = self.stage_dir(stage) / name
        data, problem = read_verified(path, checksum)
        if data is None:
            self.events.append(
                quarantine(self.root, stage, path, problem, dry=self.dry, then="started again")
            )
            if not self.dry:
                del state.files[name]
                self._save(stage, state)
        return data

    def write_file(self, stage: str, name: str, data: bytes) -> None:
        """Write the stage's file ``name`` (atomically) and index its checksum."""
        make_folder(self.stage_dir(stage))
        state = self._stage(stage)
        write_object(self.stage_dir(stage) / name, data)
        state.files[name] = (sha256_hex(data), len(data))
        self._save(stage, state)

    # -- upkeep ----------------------------------------------------------------------------------

    def compact(self, stage: str, *, at: int | None = None) -> int:
        """Merge the stage's small segments once there are ``at`` (default
        :data:`COMPACT_AT`) of them (of rows; of failures), keeping only the rows still in use;
        returns the segments removed.

        A scheduled run that finds a few new files writes a segment of a few rows, and a
        Parquet file's own overhead (its schema and statistics, a few kB) is then most of the
        store: merged, the store grows as a batch run's would. The merged segment is written and
        indexed before the small ones are deleted, so a run killed in between keeps every row.
        """
        import pyarrow as pa
        import pyarrow.compute as pc
        import pyarrow.parquet as pq

        state = self._stage(stage)
        removed: list[_Segment] = []
        for failed in (False, True):
            small = [
                segment
                for name, segment in sorted(state.segments.items(), key=lambda i: _order(i[0]))
                if segment.failed == failed and segment.checksum[1] < SMALL_SEGMENT_BYTES
            ]
            if len(small) < max(COMPACT_AT if at is None else at, 2):
                continue
            # tables of one schema merge into one segment (a stage's new version may add columns)
            groups: dict[Any, list[Any]] = {}
            for segment in small:
                live = [k for k in segment.keys if state.entries[k].segment.name == segment.name]
                if not live:  # every key of it written again later: nothing to keep
                    continue
                table = pq.read_table(pa.BufferReader(segment.data))
                table = table.filter(pc.is_in(table.column(KEY_COLUMN), pa.array(live)))
                if table.num_rows:
                    groups.setdefault(table.schema.remove_metadata(), []).append(table)
            prefix = "fail" if failed else "seg"
            for tables in groups.values():
                self._add_merged(stage, state, prefix, pa.concat_tables(tables))
            for segment in small:
                del state.segments[segment.name]
            removed += small
        if removed:
            self._rebuild_entries(stage, state)
            self._save(stage, state)
            for segment in removed:
                (self.stage_dir(stage) / segment.name).unlink(missing_ok=True)
        return len(removed)

    def _add_merged(self, stage: str, state: _Stage, prefix: str, table: Any) -> None:
        import pyarrow.parquet as pq

        buffer = io.BytesIO()
        pq.write_table(table, buffer)
        data = buffer.getvalue()
        name = self._segment_name(prefix, sha256_hex(data))
        write_object(self.stage_dir(stage) / name, data)
        keys = [str(key) for key in table.column(KEY_COLUMN).to_pylist()]
        state.segments[name] = _Segment(name, (sha256_hex(data), len(data)), data, keys)

    def remove_unreachable(self, stage: str) -> list[str]:
        """Delete what no key leads to: segments whose every key a later segment holds, set
        folders the index does not name (a killed run's, a store written before checksums),
        and folders a replaced result left; returns them (relative to the store)."""
        state = self._stage(stage)
        live = {entry.segment.name for entry in state.entries.values()}
        dead = [name for name in state.segments if name not in live]
        for name in dead:
            del state.segments[name]
        if dead:
            self._save(stage, state)
        removed = []
        for name in dead:
            (self.stage_dir(stage) / name).unlink(missing_ok=True)
            removed.append(f"{stage}/{name}")
        sets = self.stage_dir(stage) / "sets"
        if sets.is_dir():
            for folder in sorted(sets.iterdir()):
                if folder.name not in state.sets:
                    if folder.is_dir():
                        shutil.rmtree(folder)
                    else:
                        folder.unlink()
                    removed.append(f"{stage}/sets/{folder.name}")
        return removed

    def verify(self) -> dict[str, Any]:
        """Check every object of every stage (damaged ones quarantined, :attr:`events`), and
        remove the unreachable ones; a summary per stage."""
        summary: dict[str, Any] = {}
        for stage in self.stages():
            state = self._stage(stage)
            for key in list(state.sets):
                self.has_set(stage, key)
            for name in list(state.files):
                self.read_file(stage, name)
            removed = self.remove_unreachable(stage)
            summary[stage] = {**self.describe(stage), "removed": removed}
        return summary

    def describe(self, stage: str) -> dict[str, int]:
        """A stage's segments, sets, items and bytes (segments and set files)."""
        state = self._stage(stage)
        return {
            "segments": len(state.segments),
            "sets": len(state.sets),
            "items": len(state.entries),
            "bytes": sum(s.checksum[1] for s in state.segments.values())
            + sum(size for files in state.sets.values() for _, size in files.values())
            + sum(size for _, size in state.files.values()),
        }


def _parquet_bytes(table: pd.DataFrame) -> bytes:
    """A DataFrame as Parquet bytes (attrs left out: not tabular)."""
    plain = table.copy()
    plain.attrs = {}
    buffer = io.BytesIO()
    plain.to_parquet(buffer, index=False, engine="pyarrow")
    return buffer.getvalue()


def _write_parquet(table: pd.DataFrame, path: Path) -> None:
    """A DataFrame as Parquet through :func:`atomic_write` (attrs left out: not tabular)."""
    with atomic_write(path, "wb") as out:
        out.write(_parquet_bytes(table))


def write_output_table(table: pd.DataFrame, path: Path) -> list[Path]:
    """Write a final table as Parquet, with a CSV copy for people and its column dictionary
    (:func:`stepframe.core.tables.write_table`: ``X.csv`` and ``X.columns.csv``), atomically.

    Returns the paths written (Parquet first).
    """
    from stepframe.core.tables import write_table

    _write_parquet(table, path)
    return [path, *write_table(table, path.with_suffix(".csv"))]


#: The stage's store file that remembers what :func:`publish_output_table` last wrote.
OUTPUT_STAMP = "output-stamp.json"


def _file_stats(paths: list[Path]) -> list[list[Any] | None]:
    """Each file's path, size and modification time [ns] (None when missing)."""
    stats: list[list[Any] | None] = []
    for path in paths:
        try:
            stat = path.stat()
        except OSError:
            stats.append(None)
            continue
        stats.append([str(path.absolute()), stat.st_size, stat.st_mtime_ns])
    return stats


def publish_output_table(table: pd.DataFrame, path: Path, store: Store, stage: str) -> list[Path]:
    """:func:`write_output_table`, skipped when ``table`` is the one the last publication of
    ``stage`` wrote and its three files are as that run left them.

    The stamp (in the stage's store, :data:`OUTPUT_STAMP`) holds the digest of the table's
    Parquet bytes and column dictionary, and each file's path, size and modification time in
    nanoseconds: a file edited, replaced, moved or deleted since, or an outputs folder moved, is
    written again. A no-op re-run of 43,000 components spent about 3 s writing the same 17 MB
    CSV again (docs/scaling.md).

    Returns the paths (Parquet first), written or not.
    """
    from stepframe.core.tables import column_dictionary, columns_path, write_table

    data = _parquet_bytes(table)
    dictionary = column_dictionary(table).to_csv(index=False).encode()
    digest = sha256_hex(data + b"\0" + dictionary)
    csv_path = path.with_suffix(".csv")
    files = [path, csv_path, columns_path(csv_path)]
    stamp = store.read_file(stage, OUTPUT_STAMP)
    if stamp is not None:
        last = json.loads(stamp)
        if last.get("digest") == digest and last.get("files") == _file_stats(files):
            return files
    with atomic_write(path, "wb") as out:
        out.write(data)
    written = [path, *write_table(table, csv_path)]
    record = {"digest": digest, "files": _file_stats(written)}
    store.write_file(stage, OUTPUT_STAMP, json.dumps(record).encode())
    return written


#: The stage's store file that remembers what :func:`publish_set` last published.
SET_STAMP = "published-stamp.json"


def publish_set(
    publish: Callable[[Path, Path], list[Path]],
    outputs: Path,
    store: Store,
    stage: str,
    key: str,
) -> tuple[list[Path], str]:
    """Publish the whole-set result ``key`` of ``stage`` into ``outputs`` with the stage's
    ``publish``, each copy of a stored file checked against it (:meth:`Store.check_published`);
    skipped when the last publication of the stage was of this result (its key and its files'
    checksums) into this folder and the files it wrote are as that run left them.

    The stamp (in the stage's store, :data:`SET_STAMP`) holds the key, a digest of the result's
    manifest, the paths ``publish`` returned and each file's path, size and modification time in
    nanoseconds: a file edited, replaced or deleted since, the outputs folder moved, or the run
    started from another folder, and the result is published again. A no-op re-run of 43,000
    components copied the selection's and its report's 100 MB again, and read them back to check
    them (docs/benchmarks.md).

    Returns
    -------
    paths : list of Path
        What the publication wrote (now or in the run the stamp names).
    problem : str
        The first published copy that differs from the stored file ("" if none).
    """
    manifest = canonical_json(store.set_manifest(stage, key))
    digest = sha256_hex(manifest.encode())
    place = str(outputs.absolute())
    stamp = store.read_file(stage, SET_STAMP)
    if stamp is not None:
        last = json.loads(stamp)
        paths = [Path(name) for name in last.get("paths", [])]
        same = (last.get("key"), last.get("manifest"), last.get("outputs")) == (key, digest, place)
        if same and paths and last.get("files") == _file_stats(paths):
            return paths, ""
    paths = publish(store.set_dir(stage, key), outputs)
    problem = store.check_published(stage, key, paths)
    if not problem:
        record = {"key": key, "manifest": digest, "outputs": place,
                  "paths": [str(path) for path in paths], "files": _file_stats(paths)}  # fmt: skip
        store.write_file(stage, SET_STAMP, json.dumps(record).encode())
    return paths, problem


#: The stage's store file naming the entries of the outputs folder its last publication made
#: (:func:`remember_published`), so that a run that no longer asks for the output removes them.
PUBLISHED_NAMES = "published-names.json"


def remember_published(
    store: Store, stage: str, outputs: Path, paths: Iterable[Path], workflow: Path
) -> None:
    """Remember the entries of ``outputs`` (its files and folders, one level down) that the
    publication of ``stage`` by the workflow file ``workflow`` wrote as ``paths`` (the store
    file is written only when that changes: a no-op re-run writes nothing)."""
    root = outputs.absolute()
    names = sorted(
        {
            path.absolute().relative_to(root).parts[0]
            for path in paths
            if path.absolute().is_relative_to(root) and path.absolute() != root
        }
    )
    publisher = str(workflow.absolute())
    record = canonical_json({"outputs": str(root), "names": names, "workflow": publisher})
    if store.read_file(stage, PUBLISHED_NAMES) != record.encode():
        store.write_file(stage, PUBLISHED_NAMES, record.encode())


def withdraw_published(
    store: Store, stage: str, outputs: Path, *, only_of: Path | None = None
) -> list[str]:
    """Remove from ``outputs`` what the last publication of ``stage`` put there (an output the
    workflow no longer asks for, or one this run could not produce: its files, and its folders
    whole), and forget it.

    Only the entries :func:`remember_published` recorded for this outputs folder are touched:
    a file of the user's beside the outputs is never removed. With ``only_of`` (a workflow
    file), only what that workflow published: the shipped workflows share one workspace, and a
    run of ``selection`` removed the site and amplification outputs ``site-amplification`` had
    published there, which it never asks for ("no longer asked for" is one workflow's word).

    Returns
    -------
    list of str
        The entries removed (names in ``outputs``).
    """
    data = store.read_file(stage, PUBLISHED_NAMES)
    if data is None:
        return []
    record = json.loads(data)
    root = outputs.absolute()
    if record.get("outputs") != str(root) or not record.get("names"):
        return []
    if only_of is not None and record.get("workflow") != str(only_of.absolute()):
        return []
    removed = []
    for name in record["names"]:
        entry = root / name
        if entry.is_dir() and not entry.is_symlink():
            shutil.rmtree(entry)
        elif entry.exists() or entry.is_symlink():
            entry.unlink()
        else:
            continue
        removed.append(name)
    forgotten = canonical_json(
        {"outputs": str(root), "names": [], "workflow": record.get("workflow")}
    )
    store.write_file(stage, PUBLISHED_NAMES, forgotten.encode())
    return removed
