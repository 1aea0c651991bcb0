"""The one way to write a user-visible file, and the one way to read a TOML file.

Every file the user sees is written through :func:`atomic_write`: to a temporary file in the same
folder, flushed and fsynced, then renamed over the target, so a reader sees the old file or the
new one, never a half-written one; on any exception the temporary is removed and the target is
left as it was. A folder of files published as one (a report's data folder, a pipeline result
set) is written into a staging folder and moved into place by :func:`publish_folder`
(:func:`staged_folder` does both). TOML (frame files, design cases, workflows) is read with
:func:`read_toml`, whose errors are one line naming the file and line.
"""

from __future__ import annotations

import contextlib
import os
import re
import shutil
import sys
import tempfile
import tomllib
from collections.abc import Iterator
from os import PathLike
from pathlib import Path
from typing import IO, Any, Literal

from stepframe.errors import InputError

#: Temporary names: ``.<target name>.<random>.tmp`` (hidden, same folder).
TEMPORARY_SUFFIX = ".tmp"


#: How tables print floats in CSV: 15 significant digits, so a value computed as
#: 81.97500000000001 is written 81.975 (beyond any measured quantity's precision; reading
#: back gives the value to 1e-15 relative).
CSV_FLOAT_FORMAT = "%.15g"


#: Bytes read at a time when hashing a file.
_HASH_BLOCK = 1 << 20


def file_sha256(path: str | PathLike[str]) -> str:
    """SHA-256 of a file's bytes (hex), read in 1 MiB blocks: the one file hash of the package
    (a store key, a copy found by content, a report's provenance, a selection's written files)."""
    import hashlib

    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        while block := handle.read(_HASH_BLOCK):
            digest.update(block)
    return digest.hexdigest()


def columns_path(path: str | PathLike[str]) -> Path:
    """``X.columns.csv`` beside ``X.csv``: where a table's column dictionary is written."""
    target = Path(path)
    return target.with_name(f"{target.stem}.columns.csv")


def _umask() -> int:
    # os.umask can only be read by setting it; set it back at once.
    mask = os.umask(0)
    os.umask(mask)
    return mask


@contextlib.contextmanager
def atomic_write(
    path: str | PathLike[str], mode: Literal["w", "wb"] = "w", *, encoding: str = "utf-8"
) -> Iterator[IO[Any]]:
    """Open a temporary file beside ``path``; on success it replaces ``path`` atomically.

    Parameters
    ----------
    path
        The file to (re)write. Its folder must exist.
    mode
        ``"w"`` (text, ``newline=""`` so CSV writers control line ends) or ``"wb"`` (bytes).
    encoding
        Text encoding for ``"w"``.

    Yields
    ------
    file object
        Write to it; when the ``with`` block ends without an exception the data is flushed,
        fsynced and renamed to ``path`` (created with the user's umask, like ``open``). On any
        exception (including KeyboardInterrupt) the temporary is removed and ``path`` is
        untouched.

    Raises
    ------
    InputError
        The folder does not exist or is not writable.

    Examples
    --------
    >>> with atomic_write("table.csv") as out:  # doctest: +SKIP
    ...     table.to_csv(out, index=False)
    """
    target = Path(path)
    folder = target.parent
    if not folder.is_dir():
        raise InputError("output folder does not exist, expected an existing folder", target)
    try:
        handle, temporary = tempfile.mkstemp(
            prefix=f".{target.name}.", suffix=TEMPORARY_SUFFIX, dir=folder
        )
    except PermissionError:
        raise InputError(
            "output folder is not writable, expected a writable folder", target
        ) from None
    try:
        # mkstemp creates 0600; a user file gets the mode open() would give it.
        os.chmod(temporary, 0o666 & ~_umask())
        if mode == "wb":
            stream: IO[Any] = os.fdopen(handle, "wb")
        else:
            stream = os.fdopen(handle, "w", encoding=encoding, newline="")
        with stream:
            yield stream
            stream.flush()
            os.fsync(stream.fileno())
        os.replace(temporary, target)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise


def publish_folder(staging: str | PathLike[str], target: str | PathLike[str]) -> Path:
    """Move the complete folder ``staging`` to ``target`` atomically, replacing any folder there.

    ``staging`` must be on the same filesystem (a sibling of ``target``). A reader sees the old
    folder or the new one, never a mix: the old one is renamed aside, the new one renamed into
    place (the old one is put back if that fails), then the old one is deleted. Both renames
    are made durable by syncing the folders.

    Returns
    -------
    pathlib.Path
        ``target``.
    """
    staging, target = Path(staging), Path(target)
    _fsync_folder(staging)
    old: Path | None = None
    if target.exists():
        old = target.with_name(f".{target.name}.{os.getpid()}.old")
        os.replace(target, old)
    try:
        os.replace(staging, target)
    except BaseException:
        if old is not None:
            os.replace(old, target)
        raise
    _fsync_folder(target.parent)
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)
    return target


@contextlib.contextmanager
def staged_folder(target: str | PathLike[str]) -> Iterator[Path]:
    """A staging folder beside ``target``; on success it replaces ``target``.

    The replacement is :func:`publish_folder`.

    On any exception the staging folder is removed and ``target`` is left as it was. The staging
    folder gets the mode ``mkdir`` would give (the user's umask).
    """
    target = Path(target)
    if not target.parent.is_dir():
        raise InputError("output folder does not exist, expected an existing folder", target)
    staging = Path(
        tempfile.mkdtemp(prefix=f".{target.name}.", suffix=TEMPORARY_SUFFIX, dir=target.parent)
    )
    try:
        os.chmod(staging, 0o777 & ~_umask())  # mkdtemp creates 0700
        yield staging
        publish_folder(staging, target)
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise


def _fsync_folder(folder: Path) -> None:
    # A rename is durable only once the folder holding the entry is synced.
    descriptor = os.open(folder, os.O_RDONLY)
    try:
        os.fsync(descriptor)
    finally:
        os.close(descriptor)


def write_text(path: str | PathLike[str], text: str) -> Path:
    """Write ``text`` to ``path`` atomically (UTF-8); returns the path."""
    with atomic_write(path) as out:
        out.write(text)
    return Path(path)


def write_bytes(path: str | PathLike[str], data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically; returns the path."""
    with atomic_write(path, "wb") as out:
        out.write(data)
    return Path(path)


def copy_files(source: str | PathLike[str], target: str | PathLike[str]) -> list[Path]:
    """Copy every file under ``source`` to ``target`` (each atomically); the written paths."""
    origin, destination_root = Path(source), Path(target)
    destination_root.mkdir(parents=True, exist_ok=True)
    written = []
    for file in sorted(origin.rglob("*")):
        if file.is_file():
            destination = destination_root / file.relative_to(origin)
            destination.parent.mkdir(parents=True, exist_ok=True)
            written.append(write_bytes(destination, file.read_bytes()))
    return written


def replace_folder_copy(source: str | PathLike[str], target: str | PathLike[str]) -> list[Path]:
    """Copy every file under ``source`` into a folder that replaces ``target`` whole
    (:func:`staged_folder`): a file of an earlier ``target`` that ``source`` does not hold goes.

    Returns
    -------
    list of pathlib.Path
        The written paths, under ``target``.
    """
    origin, destination = Path(source), Path(target)
    destination.parent.mkdir(parents=True, exist_ok=True)
    with staged_folder(destination) as staging:
        written = copy_files(origin, staging)
    return [destination / path.relative_to(staging) for path in written]


def publish_copy(source: str | PathLike[str], target: str | PathLike[str]) -> list[Path]:
    """Copy a result folder ``source`` into the outputs folder ``target``: each folder of
    ``source`` replaces its namesake whole (:func:`replace_folder_copy`: a report's
    ``<name>_files/`` holds the numbers of this result only, none of an earlier one), then each
    of its files is written (atomically), so that a page is written after the folder it names.

    Returns
    -------
    list of pathlib.Path
        The written paths, under ``target``: the files of ``source`` first (the page), then
        those of its folders.
    """
    origin, destination = Path(source), Path(target)
    destination.mkdir(parents=True, exist_ok=True)
    entries = sorted(origin.iterdir())
    in_folders: list[Path] = []
    for entry in entries:
        if entry.is_dir():
            in_folders += replace_folder_copy(entry, destination / entry.name)
    files = [
        write_bytes(destination / entry.name, entry.read_bytes())
        for entry in entries
        if entry.is_file()
    ]
    return files + in_folders


#: The largest TOML file read (a workflow or a frame file is a few kB).
MAX_TOML_BYTES = 1 << 20


def read_toml(path: str | PathLike[str], what: str) -> tuple[dict[str, Any], str]:
    """Read a TOML file as UTF-8; errors are one line with the file and line.

    Parameters
    ----------
    path
        The file.
    what
        What the file should be, for messages (``"a FRAME.toml"``, ``"a workflow file"``).

    Returns
    -------
    data : dict
        The parsed document.
    text : str
        The file's text (for callers that map keys back to lines).

    Raises
    ------
    InputError
        Missing, unreadable, larger than :data:`MAX_TOML_BYTES`, not UTF-8, or not valid TOML
        (with the line of the error; nested too deeply; an integer of thousands of digits).
    """
    p = Path(path)
    try:
        raw = p.read_bytes()
    except FileNotFoundError:
        raise InputError(f"no such file, expected {what}", p) from None
    except IsADirectoryError:
        raise InputError(f"is a directory, expected {what}", p) from None
    except OSError as exc:
        raise InputError(f"cannot read ({exc.strerror}), expected {what}", p) from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        bad_line = raw[: exc.start].count(b"\n") + 1
        raise InputError(
            f"not UTF-8 text (byte {exc.start}), expected {what}", p, bad_line
        ) from None
    if len(raw) > MAX_TOML_BYTES:
        raise InputError(
            f"{len(raw):,} bytes, expected {what} of at most {MAX_TOML_BYTES:,} bytes", p
        )
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        match = re.search(r"line (\d+)", str(exc))
        line = int(match.group(1)) if match else None
        reason = re.sub(r"\s*\(at line \d+, column \d+\)", "", str(exc))
        raise InputError(f"not valid TOML ({reason}), expected {what}", p, line) from None
    except RecursionError:
        raise InputError(f"arrays or tables nested too deeply, expected {what}", p) from None
    except ValueError:  # tomllib's only ValueError: an integer past Python's digit limit
        raise InputError(
            f"an integer of more than {sys.get_int_max_str_digits():,} digits, expected {what}", p
        ) from None
    return data, text
