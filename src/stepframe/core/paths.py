"""Which paths a run reads: the one rule for record folders, their globs and their files.

The records catalogue (``records catalog DIR``, ``stochastic features DIR``, ``report
amplification --records DIR``) and the workflow engine (``[records] folder`` and ``glob``) list
record files through :func:`walk_files`, so a folder is read the same way wherever it is given:

- **A records folder** is a folder on a real file system: a folder in ``/proc``, ``/sys`` or
  ``/dev`` (views of the kernel, of a process's memory, of devices) is refused
  (:func:`check_records_folder`).
- **Files**: only regular files are listed; devices, FIFOs and sockets (which block, never end
  or cannot be read) are skipped, and so are hidden files and folders (names starting with
  ``.``). A regular file of ``/proc`` or ``/sys`` given by name is refused
  (:func:`pseudo_file_system`): its size means nothing and reading it reads the kernel's memory.
  A file or folder whose name is not UTF-8 (Latin-1 bytes from an old archive) is skipped with
  one warning that counts them and names the first: no table can write its name.
- **Symbolic links** are followed (a linked sub-folder of records, a linked file), except into
  ``/proc``, ``/sys`` or ``/dev`` (a link to ``/proc/self/mem`` or ``/proc/kcore`` is skipped
  with one warning that counts them); each real folder is walked once (a link back up the tree,
  a loop, or a folder linked twice is not entered again). A dangling link, or a loop of links,
  is listed, so that reading it reports it.
- **A glob** (:func:`check_glob`) is a relative pattern of names, matched against each file's
  path inside the folder as :meth:`pathlib.Path.rglob` matches (``*.AT2``, ``sub/*.AT2``,
  ``**/RSN*``; ``**`` only as a whole part): an absolute glob, one with a ``..`` part, one with
  more than :data:`MAX_GLOB_WILDCARDS` wildcards or :data:`MAX_GLOB_CHARS` characters is
  refused with one line.

Standard library only; no science.
"""

from __future__ import annotations

import fnmatch
import os
import stat
import warnings
from collections.abc import Iterable, Iterator
from os import PathLike
from pathlib import Path

from stepframe.errors import InputError

#: Where the kernel's pseudo-file systems live: their files are views of memory and devices.
PSEUDO_ROOTS = ("/proc", "/sys", "/dev")
#: Longest glob accepted [characters] (a file name's limit on most file systems).
MAX_GLOB_CHARS = 255
#: Most wildcards (``*``, ``?``, ``[``) in a glob: a pattern of names needs a handful; thousands
#: only make matching slow.
MAX_GLOB_WILDCARDS = 32

_GLOB_EXAMPLES = "such as *.AT2, sub/*.AT2 or **/RSN*"


def check_glob(pattern: str) -> str:
    """``pattern`` if it is a glob of names inside a folder (module docstring), else an error.

    Raises
    ------
    InputError
        ``glob '/etc/*' is absolute, expected ...`` (and the same for ``..``, an empty pattern,
        ``**`` inside a name, too long or too many wildcards), without a file: the caller names
        where the glob came from.
    """
    expected = f"expected a pattern of names inside the records folder ({_GLOB_EXAMPLES})"
    shown = pattern if len(pattern) <= 40 else pattern[:37] + "..."
    problem = None
    if not pattern.strip():
        problem = "is empty"
    elif "\x00" in pattern:
        problem = "holds a NUL character"
    elif len(pattern) > MAX_GLOB_CHARS:
        problem = f"has {len(pattern)} characters (at most {MAX_GLOB_CHARS})"
    elif sum(pattern.count(c) for c in "*?[") > MAX_GLOB_WILDCARDS:
        problem = f"has more than {MAX_GLOB_WILDCARDS} wildcards"
    elif pattern.startswith(("/", "~", "\\")) or (len(pattern) > 1 and pattern[1] == ":"):
        problem = "is absolute"
    else:
        parts = pattern.replace("\\", "/").split("/")
        if ".." in parts:
            problem = "leaves the folder (a '..' part)"
        elif any("**" in part and part != "**" for part in parts):
            problem = "has '**' inside a name ('**' stands for any folders, as a whole part)"
    if problem is not None:
        raise InputError(f"glob {shown!r} {problem}, {expected}")
    return pattern


def pseudo_file_system(path: str | PathLike[str]) -> str | None:
    """The pseudo-file system (``/proc``, ``/sys``, ``/dev``) ``path`` lies in once its links
    are resolved, or None."""
    real = os.path.realpath(path)
    for root in PSEUDO_ROOTS:
        if real == root or real.startswith(root + "/"):
            return root
    return None


def check_records_folder(folder: str | PathLike[str]) -> Path:
    """``folder`` as a :class:`~pathlib.Path` if it is a folder of a real file system.

    Raises
    ------
    InputError
        Not a folder, or a folder in ``/proc``, ``/sys`` or ``/dev`` (named with the folder).
    """
    path = Path(folder)
    root = pseudo_file_system(path)
    if root is not None:
        raise InputError(
            f"a folder in {root} (a view of the kernel, not files of data), expected a folder "
            "of record files",
            path,
        )
    if not path.is_dir():
        raise InputError("no such folder, expected a folder of record files", path)
    return path


def _glob_parts(pattern: str, recursive: bool) -> tuple[str, ...]:
    parts = tuple(p for p in pattern.replace("\\", "/").split("/") if p not in ("", "."))
    # Path.rglob(p) is Path.glob("**/" + p): a pattern matched at any depth.
    return ("**", *parts) if recursive else parts


def _matches(parts: tuple[str, ...], pattern: tuple[str, ...]) -> bool:
    """Whether the path ``parts`` matches the glob ``pattern`` (``**``: any folders, or none)."""
    if not pattern:
        return not parts
    if pattern[0] == "**" and "**" not in pattern[1:]:
        # each part after the only "**" matches one folder or name: the path's last parts
        # (a listing of 43,000 files tried every split: a second of a no-op re-run)
        tail = len(pattern) - 1
        return len(parts) >= tail and all(
            fnmatch.fnmatchcase(part, glob)
            for part, glob in zip(parts[len(parts) - tail :], pattern[1:], strict=True)
        )
    if pattern[0] == "**":
        return any(_matches(parts[k:], pattern[1:]) for k in range(len(parts) + 1))
    return (
        bool(parts)
        and fnmatch.fnmatchcase(parts[0], pattern[0])
        and (_matches(parts[1:], pattern[1:]))
    )


def walk_files(
    folder: str | PathLike[str],
    pattern: str = "*",
    *,
    recursive: bool = True,
    exclude: Iterable[str | PathLike[str]] = (),
) -> Iterator[tuple[str, Path]]:
    """The regular files under ``folder`` whose path inside it matches ``pattern``, as
    ``(relative path in POSIX form, path)``: each folder's files in name order, then its
    sub-folders in name order (the rule of the module docstring).

    Parameters
    ----------
    folder
        The records folder (checked by :func:`check_records_folder`).
    pattern
        A glob (:func:`check_glob`), matched at any depth when ``recursive``.
    recursive
        Look into sub-folders.
    exclude
        Folders never entered and files never listed (a workspace, an outputs folder or the
        workflow file inside the records folder: a run must not read its own files as records).

    Raises
    ------
    InputError
        A bad folder or glob.
    """
    root = check_records_folder(folder)
    glob = _glob_parts(check_glob(pattern), recursive)
    excluded = frozenset(os.path.realpath(path) for path in exclude)
    outside: list[str] = []
    seen: set[tuple[int, int]] = set()
    info = os.stat(root)
    seen.add((info.st_dev, info.st_ino))
    not_utf8: list[str] = []
    yield from _walk(root, (), glob, recursive, excluded, seen, outside, not_utf8)
    if not_utf8:
        warnings.warn(
            f"{root}: {len(not_utf8)} file(s) or folder(s) whose names are not UTF-8 skipped "
            f"(first: {not_utf8[0]}), expected UTF-8 names: rename them (no table can name them)",
            stacklevel=2,
        )
    if outside:
        warnings.warn(
            f"{root}: {len(outside)} symbolic link(s) into {', '.join(PSEUDO_ROOTS)} skipped "
            f"(first: {outside[0]}); their files are views of the kernel, not records",
            stacklevel=2,
        )


def _walk(
    folder: Path,
    prefix: tuple[str, ...],
    glob: tuple[str, ...],
    recursive: bool,
    excluded: frozenset[str],
    seen: set[tuple[int, int]],
    outside: list[str],
    not_utf8: list[str],
) -> Iterator[tuple[str, Path]]:
    excluded_names = {os.path.basename(path) for path in excluded}
    try:
        with os.scandir(folder) as found:
            entries = sorted(found, key=lambda entry: entry.name)
    except OSError as exc:
        raise InputError(
            f"cannot list ({exc.strerror}), expected a readable folder", folder
        ) from None
    folders: list[tuple[str, Path]] = []
    for entry in entries:
        if entry.name.startswith("."):
            continue
        if not _utf8(entry.name):
            shown = os.fsencode(entry.name).decode("utf-8", "backslashreplace")
            not_utf8.append("/".join((*prefix, shown)))
            continue
        path = folder / entry.name
        kind = _kind(entry, outside)
        parts = (*prefix, entry.name)
        if kind == "folder":
            folders.append((entry.name, path))
        elif kind == "file" and _matches(parts, glob):
            # by name first: resolving every file of a large folder would cost a system call each
            if entry.name in excluded_names and os.path.realpath(path) in excluded:
                continue
            yield "/".join(parts), path
    if not (recursive or "**" in glob):
        # A pattern with folders in it ("sub/*.AT2") still descends as far as it names them.
        folders = [f for f in folders if len(prefix) + 1 < len(glob)]
    for name, path in folders:
        if name in excluded_names and os.path.realpath(path) in excluded:
            continue
        info = os.stat(path)
        if (info.st_dev, info.st_ino) in seen:
            continue  # a loop, or a folder linked twice
        seen.add((info.st_dev, info.st_ino))
        yield from _walk(path, (*prefix, name), glob, recursive, excluded, seen, outside, not_utf8)


def _utf8(name: str) -> bool:
    """Whether a file name as the file system gave it is UTF-8: a name of other bytes (from a
    Latin-1 archive) holds surrogates that no table can write, a traceback in every batch."""
    try:
        name.encode("utf-8")
    except UnicodeEncodeError:
        return False
    return True


def _kind(entry: os.DirEntry[str], outside: list[str]) -> str | None:
    """``"file"`` (regular, or a dangling link for the reader to report), ``"folder"`` or None
    (anything else, to skip: a device, a FIFO, a socket, a link into a pseudo-file system); a
    link is its target's kind. The directory entry's own type answers without a system call
    per file."""
    try:
        if entry.is_symlink():
            target = os.path.realpath(entry.path)
            if pseudo_file_system(target) is not None:
                outside.append(f"{entry.path} -> {target}")
                return None
            try:
                mode = os.stat(target).st_mode
            except OSError:  # dangling, or a loop of links: read() names it as a failure
                return "file"
            return "folder" if stat.S_ISDIR(mode) else "file" if stat.S_ISREG(mode) else None
        if entry.is_dir(follow_symlinks=False):
            return "folder"
        return "file" if entry.is_file(follow_symlinks=False) else None
    except OSError:
        return None


def readable_file(path: str | PathLike[str]) -> str | None:
    """Why ``path`` is not a file of data to read (a regular file of ``/proc`` or ``/sys``),
    or None."""
    root = pseudo_file_system(path)
    if root in ("/proc", "/sys"):
        return f"a file of {root} (a view of the kernel's memory, not a file of data)"
    return None


__all__ = [
    "MAX_GLOB_CHARS",
    "MAX_GLOB_WILDCARDS",
    "PSEUDO_ROOTS",
    "check_glob",
    "check_records_folder",
    "pseudo_file_system",
    "readable_file",
    "walk_files",
]


def absolute_name(path: str | PathLike[str]) -> str:
    """``str(Path(path).absolute())`` without building a ``Path`` (the cwd joined to a relative
    path, nothing normalised): at 43,000 files per run, ``pathlib`` took seconds of a no-op
    re-run (docs/scaling.md)."""
    name = os.fspath(path)
    return name if os.path.isabs(name) else os.path.join(os.getcwd(), name)


def relative_name(path: str | PathLike[str], folder: str | PathLike[str]) -> str:
    """``Path(path).relative_to(folder).as_posix()`` by the strings when ``path`` lies under
    ``folder`` as written (the folder's own listing), by ``pathlib`` otherwise."""
    name, base = os.fspath(path), os.fspath(folder)
    prefix = base if base.endswith(os.sep) else base + os.sep
    if name.startswith(prefix) and base not in ("", "."):
        relative = name[len(prefix) :]
        return relative if os.sep == "/" else relative.replace(os.sep, "/")
    return Path(name).relative_to(base).as_posix()
