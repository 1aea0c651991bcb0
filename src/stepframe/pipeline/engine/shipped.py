"""The workflows shipped with the package (``stepframe/workflows/``), by name.

``stepframe run selection`` runs ``stepframe/workflows/selection.toml``: a workflow is named by
its file name without ``.toml``. The shipped files are inputs only (a system install may be
read-only): a run of one keeps its workspace in ``stepframe-work/`` of the current folder
instead of beside the file. To edit one, :func:`copy_workflow` (``stepframe run NAME --copy
DIR``) copies it with the frame file and records folder it names; the copy is an ordinary
workflow file whose paths are relative to itself.
"""

from __future__ import annotations

from pathlib import Path

from stepframe.core.io import read_toml, write_bytes
from stepframe.errors import InputError

#: The folder of the shipped workflow files (package data).
SHIPPED_DIR = Path(__file__).resolve().parents[2] / "workflows"


def shipped_names() -> list[str]:
    """The names of the shipped workflows, sorted (``selection``, ``inbox``, ...)."""
    return sorted(path.stem for path in SHIPPED_DIR.glob("*.toml"))


def is_shipped(path: Path) -> bool:
    """Whether ``path`` is one of the shipped files (its folder is the package's)."""
    return path.resolve().is_relative_to(SHIPPED_DIR)


def resolve_workflow(given: str | Path) -> Path:
    """The workflow file ``given`` names: an existing file, else a shipped workflow's name (a
    folder named ``selection`` in the current folder does not hide the shipped workflow).

    Raises
    ------
    InputError
        Neither a file nor a shipped name (the message lists the shipped names).
    """
    path = Path(given).expanduser()
    if path.is_file():
        return path
    name = str(given).removesuffix(".toml")
    if name in shipped_names():
        return SHIPPED_DIR / f"{name}.toml"
    raise InputError(
        "no such workflow file or shipped workflow, expected a WORKFLOW.toml or one of "
        + ", ".join(shipped_names()),
        given,
    )


def _named_paths(workflow: Path) -> tuple[list[Path], list[Path]]:
    """The frame file and records folder a shipped workflow names (relative paths only)."""
    data, _ = read_toml(workflow, "a workflow file")
    files, folders = [], []
    frame_file = data.get("frame", {}).get("file")
    if isinstance(frame_file, str) and not Path(frame_file).is_absolute():
        files.append(Path(frame_file))
    folder = data.get("records", {}).get("folder")
    if isinstance(folder, str) and not Path(folder).is_absolute():
        folders.append(Path(folder))
    return files, folders


def copy_workflow(name: str, target: str | Path) -> list[Path]:
    """Copy the shipped workflow ``name`` into the folder ``target``, to edit or schedule.

    The workflow file keeps its name; the frame file it names is copied beside it at the same
    relative path, and its records folder (``inbox/`` of ``inbox.toml``) is created empty.
    Nothing is overwritten: a file already there with other content is an error and nothing is
    written (one with the same content is left as it is, so copying twice is harmless).

    Returns
    -------
    list of pathlib.Path
        The workflow file, the frame file and the records folder of the copy.

    Raises
    ------
    InputError
        An unknown name, ``target`` an existing file, or a file already there.
    """
    names = shipped_names()
    if name.removesuffix(".toml") not in names:
        raise InputError(f"no shipped workflow {name!r}, expected one of {', '.join(names)}")
    source = SHIPPED_DIR / f"{name.removesuffix('.toml')}.toml"
    folder = Path(target).expanduser()
    if folder.exists() and not folder.is_dir():
        raise InputError("exists and is not a folder, expected a folder for the copy", folder)
    files, folders = _named_paths(source)
    relative = [Path(source.name), *files]
    todo = []
    for path in relative:
        there = folder / path
        if not there.exists():
            todo.append(path)
        elif not there.is_file() or there.read_bytes() != (SHIPPED_DIR / path).read_bytes():
            raise InputError("exists, expected a path the copy would not overwrite", there)
    try:
        for path in todo:
            (folder / path).parent.mkdir(parents=True, exist_ok=True)
            write_bytes(folder / path, (SHIPPED_DIR / path).read_bytes())
        for path in folders:
            (folder / path).mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise InputError(
            f"cannot write the copy ({error.strerror}), expected a writable folder", folder
        ) from None
    return [folder / path for path in relative] + [folder / path for path in folders]
