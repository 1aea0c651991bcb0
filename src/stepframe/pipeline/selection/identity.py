"""A selected record found again by its identity, from anywhere.

A selection made by a workflow (or ``stepframe select`` on a folder) names each record by its
``file`` relative to the records folder and its ``content_sha256``, and its ``selection.json``
says where that folder is (``records.folder``: relative to the selection's folder or to one of
the folders above it, as the workflow gives it; or ``records.example``) and with which options
the files were read (:meth:`~stepframe.pipeline.selection.result.SelectionResult.
with_record_identity`). :func:`find_record` looks for ``<folder>/<file>`` beside the selection's
folder and each folder above it (then the current folder), and takes only a file with the same
bytes: a record that is gone or changed is an error naming it, never a report drawn without it.
"""

from __future__ import annotations

import dataclasses
import json
import os
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING, Any

from stepframe.core.io import file_sha256
from stepframe.errors import InputError

if TYPE_CHECKING:
    from stepframe.pipeline.selection.result import SelectionResult
    from stepframe.records.read_options import RecordSource

SUMMARY_FILE = "selection.json"


def identified(
    result: SelectionResult, catalogue: Path, out_dir: Path, source: RecordSource
) -> SelectionResult:
    """The result of ``stepframe select CATALOGUE -o OUT_DIR`` naming its records by identity:
    files relative to the catalogue folder, their sha256, the folder relative to ``out_dir``
    and the record options (:meth:`~stepframe.pipeline.selection.result.SelectionResult.
    with_record_identity`)."""
    prefix = f"{catalogue.as_posix().rstrip('/')}/"  # the files as catalog_features names them
    names = {str(file) for table in (result.selection, result.candidates) for file in table["file"]}
    hashes = {
        name.removeprefix(prefix): file_sha256(name)
        for name in names
        if name.startswith(prefix) and Path(name).is_file()
    }
    options = {
        key: value
        for key, value in dataclasses.asdict(source).items()
        if value is not None and key != "example"
    }
    folder = Path(os.path.relpath(catalogue.absolute(), out_dir.absolute())).as_posix()
    return result.with_record_identity(catalogue, hashes, {"folder": folder, "options": options})


def records_identity(folder: Path) -> dict[str, Any] | None:
    """``records`` of the selection in ``folder`` (None: a selection written without it)."""
    try:
        summary = json.loads((folder / SUMMARY_FILE).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    records = summary.get("records") if isinstance(summary, dict) else None
    return records if isinstance(records, dict) else None


def find_record(row: dict[str, Any], folder: Path, records: dict[str, Any]) -> Any:
    """The selected component ``row`` as a Trace, read from the file with its identity.

    Parameters
    ----------
    row
        A row of ``selection.csv`` (``file``, ``content_sha256``, ``component``).
    folder
        The selection's folder.
    records
        Its ``records`` identity (:func:`records_identity`).

    Raises
    ------
    InputError
        No file with those bytes where the selection says (gone, or changed since).
    """
    from stepframe.pipeline.catalogue.stage import read_kwargs
    from stepframe.records import read

    file, sha = str(row["file"]), str(row["content_sha256"])
    component = row.get("component")
    options = read_kwargs(dict(records.get("options") or {}))
    if isinstance(component, str) and component:
        options["component"] = component
    if "example" in records:
        place = Path("examples") / str(records["example"])
    else:
        place = Path(str(records.get("folder", ".")))
    bases = [] if place.is_absolute() else [folder, *folder.resolve().parents, Path.cwd()]
    changed = []
    for path in [place / file] if place.is_absolute() else [b / place / file for b in bases]:
        if path.is_file():
            if file_sha256(path) == sha:
                return read(path, **options)[0]
            changed.append(path)
    if "example" in records:
        trace = _example_record(file, sha, options)
        if trace is not None:
            return trace
    if changed:
        raise InputError(
            f"changed since the selection (sha256 {sha[:12]}…), expected the record it was made "
            "from (run the selection again)",
            changed[0],
        )
    raise InputError(
        f"{file} (sha256 {sha[:12]}…) not found in {place.as_posix()}/ beside {folder} or a folder "
        "above it, expected the record the selection was made from",
    )


def _example_record(name: str, sha: str, options: dict[str, Any]) -> Any:
    """The example file ``name`` made again from the embedded catalogue, if its bytes match."""
    import hashlib

    from stepframe.pipeline.catalogue.example_files import example_files
    from stepframe.records import read

    for file, data in example_files():
        if file == name and hashlib.sha256(data).hexdigest() == sha:
            with tempfile.TemporaryDirectory() as folder:
                path = Path(folder) / name
                path.write_bytes(data)
                return read(path, **options)[0]
    return None
