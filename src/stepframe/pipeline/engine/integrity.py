"""The store's objects, verified: checksums, the stage index file, quarantine, write failures.

Every object the store writes (a Parquet segment, each file of a whole-set result) has its
sha256 and size in its stage's index file, ``<store>/<stage>/index.json``, and a segment also
carries its sha256 in its name. An object is read only through :func:`read_verified`: a file
missing, cut short, grown, altered or replaced by a folder is a *problem*, never a traceback.
The store then moves it aside (:func:`quarantine`, into ``<store>/quarantine/<stage>/``), drops
it from the index and recomputes what it held; the run's summary names it (:class:`StoreEvent`).

The index file holds its own checksum: an index that is cut short or altered is quarantined too
and rebuilt from the segments, whose names carry their checksums (so nothing computed is lost;
a whole-set result is recomputed, since its files' checksums were only in the index).

A write that fails (disk full, a read-only file system, an I/O error) raises
:class:`StorageError`: the command prints one line and exits 1. Objects are written with
:func:`stepframe.core.io.atomic_write` before the index names them, so the store stays
consistent and the next run resumes.
"""

from __future__ import annotations

import datetime
import hashlib
import json
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from stepframe.core.io import write_bytes
from stepframe.errors import StepframeError

INDEX_FILE = "index.json"
QUARANTINE = "quarantine"
INDEX_FORMAT = 1

#: sha256 and size [bytes] of an object.
Checksum = tuple[str, int]
#: What an object is checked against: sha256 and size, or sha256 alone (a segment found on disk
#: and not in the index: its name carries its sha256).
Expected = tuple[str, int | None]


class StorageError(StepframeError):
    """A file of the workspace could not be written (disk full, read-only, an I/O error).

    Nothing is half-written (every object is written to a temporary and renamed, and the index
    names only complete objects): free the space or fix the permissions and run again; the run
    resumes from what was stored. The command line prints the message as one line and exits 1.
    """

    def __init__(self, path: Path, error: OSError) -> None:
        reason = error.strerror or type(error).__name__
        super().__init__(
            f"{path}: cannot write ({reason}); the store is unchanged, the next run resumes"
        )


@dataclass(frozen=True)
class StoreEvent:
    """A damaged or missing object the store found, and what it did about it.

    Attributes
    ----------
    stage
        The stage whose object it is.
    item
        The object, relative to the store (``features/seg-...parquet``, ``selection/sets/KEY``).
    problem
        What was wrong (``checksum mismatch``, ``missing``, ``1,024 bytes, expected 9,000``).
    action
        What was done (``moved to quarantine/features/ (as ...); recomputed``).
    """

    stage: str
    item: str
    problem: str
    action: str

    def line(self) -> str:
        """One line for the run's summary."""
        return f"{self.item}: {self.problem}: {self.action}"

    def to_dict(self) -> dict[str, str]:
        """JSON-ready form."""
        return {"stage": self.stage, "object": self.item, "problem": self.problem,
                "action": self.action}  # fmt: skip


def sha256_hex(data: bytes) -> str:
    """sha256 of ``data`` (hex)."""
    return hashlib.sha256(data).hexdigest()


def read_verified(path: Path, expected: Expected | None) -> tuple[bytes | None, str]:
    """The bytes of ``path`` if they match ``expected`` (None: any bytes), else the problem.

    Returns
    -------
    (bytes, "") or (None, problem)
    """
    try:
        data = path.read_bytes()
    except FileNotFoundError:
        return None, "missing"
    except OSError as error:  # a folder in its place, no permission, an I/O error
        return None, f"unreadable ({error.strerror or type(error).__name__})"
    if expected is not None:
        sha, size = expected
        if size is not None and len(data) != size:
            cut = " (cut short)" if len(data) < size else ""
            return None, f"{len(data):,} bytes, expected {size:,}{cut}"
        if sha256_hex(data) != sha:
            return None, "checksum mismatch"
    return data, ""


def write_object(path: Path, data: bytes) -> None:
    """Write ``data`` to ``path`` atomically; a failure is a :class:`StorageError`."""
    try:
        write_bytes(path, data)
    except OSError as error:
        raise StorageError(path, error) from None


def make_folder(path: Path) -> None:
    """``mkdir -p``; a failure is a :class:`StorageError`."""
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise StorageError(path, error) from None


def quarantine(
    root: Path, stage: str, path: Path, problem: str, *, dry: bool, then: str = "recomputed"
) -> StoreEvent:
    """Move the damaged object ``path`` to ``<root>/quarantine/<stage>/`` (a missing one is only
    reported; with ``dry`` nothing is moved) and say so, with what follows (``then``)."""
    item = path.relative_to(root).as_posix()
    if problem == "missing":
        return StoreEvent(stage, item, problem, then)
    if dry:
        return StoreEvent(stage, item, problem, f"would be quarantined and {then}")
    stamp = datetime.datetime.now(datetime.UTC).strftime("%Y%m%dT%H%M%S%fZ")
    folder = root / QUARANTINE / stage
    target = folder / f"{stamp}-{path.name}"
    make_folder(folder)
    try:
        os.replace(path, target)
    except FileNotFoundError:  # gone since it was read: nothing to move
        return StoreEvent(stage, item, problem, then)
    except OSError as error:
        raise StorageError(path, error) from None
    where = target.parent.relative_to(root).as_posix()
    return StoreEvent(stage, item, problem, f"moved to {where}/ (as {target.name}); {then}")


def _checksum_of(body: dict[str, Any]) -> str:
    text = json.dumps(body, sort_keys=True, separators=(",", ":"))
    return sha256_hex(text.encode())


@dataclass
class StageIndex:
    """The content of a stage's index file.

    Attributes
    ----------
    segments
        Segment file name → checksum.
    sets
        Whole-set result key → (file path inside its folder → checksum).
    files
        Other files of the stage (its history) → checksum.
    """

    segments: dict[str, Checksum]
    sets: dict[str, dict[str, Checksum]]
    files: dict[str, Checksum]

    def to_json(self) -> str:
        """The file's text: the index and its own checksum."""
        body = {
            "format": INDEX_FORMAT,
            "segments": {name: list(checksum) for name, checksum in sorted(self.segments.items())},
            "sets": {
                key: {name: list(checksum) for name, checksum in sorted(files.items())}
                for key, files in sorted(self.sets.items())
            },
            "files": {name: list(checksum) for name, checksum in sorted(self.files.items())},
        }
        return json.dumps({**body, "checksum": _checksum_of(body)}, indent=1, sort_keys=True)


def read_index(path: Path) -> tuple[StageIndex | None, str]:
    """A stage's index file: (index, "") when it is sound, (None, "") when there is none, and
    (None, problem) when it is damaged."""
    data, problem = read_verified(path, None)
    if data is None:
        return None, "" if problem == "missing" else problem
    try:
        document = json.loads(data.decode("utf-8"))
        body = {k: document[k] for k in ("format", "segments", "sets", "files")}
        if document["checksum"] != _checksum_of(body) or body["format"] != INDEX_FORMAT:
            return None, "checksum mismatch"
        segments = _checksums(body["segments"])
        sets = {str(key): _checksums(files) for key, files in body["sets"].items()}
        files = _checksums(body["files"])
    except (ValueError, KeyError, TypeError, IndexError, AttributeError):
        return None, "not a readable index"
    return StageIndex(segments, sets, files), ""


def _checksums(given: dict[str, Any]) -> dict[str, Checksum]:
    return {str(name): (str(value[0]), int(value[1])) for name, value in given.items()}


def folder_manifest(folder: Path) -> dict[str, Checksum]:
    """Checksum of every file under ``folder`` (path relative to it → checksum)."""
    manifest = {}
    for path in sorted(folder.rglob("*")):
        if path.is_file():
            data = path.read_bytes()
            manifest[path.relative_to(folder).as_posix()] = (sha256_hex(data), len(data))
    return manifest


def check_folder(folder: Path, manifest: dict[str, Checksum]) -> str:
    """The first problem of a whole-set result's folder against its manifest ("" if none)."""
    if not folder.is_dir():
        return "missing" if not folder.exists() else "not a folder"
    for name, checksum in manifest.items():
        _, problem = read_verified(folder / name, checksum)
        if problem:
            return f"{name}: {problem}"
    return ""
