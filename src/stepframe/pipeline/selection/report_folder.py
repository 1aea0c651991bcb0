"""Reading a selection run's output folder (the one place that knows its layout).

``stepframe select -o OUTDIR`` writes ``selection.json`` (the run's summary: band, rank_by, counts,
and the frame and target spectrum when known), ``selection.csv`` (the chosen records),
``candidates.csv`` (every candidate, its scores and the filter that dropped it),
``confirmation.csv`` (simulated response, only with confirmation), ``failures.csv``, and a column
dictionary beside each table. A workflow's selection stage writes the same folder as
``selection/`` in its outputs (``stepframe demo``'s folder holds one): such a folder is read
through its ``selection/``. The report reads them through :func:`read_selection_folder` only, so a
change of layout is one change here.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from os import PathLike
from pathlib import Path
from typing import Any

import pandas as pd

from stepframe.errors import InputError

#: Files without which there is no selection to report.
REQUIRED = ("selection.json", "selection.csv", "candidates.csv")

#: The selection's folder inside a workflow's outputs folder (the selection stage's).
WORKFLOW_FOLDER = "selection"

#: Files a run may lack (no confirmation asked, no failures, a folder from before the set's
#: spectra were written).
OPTIONAL = ("confirmation.csv", "failures.csv", "spectra.csv")


@dataclass(frozen=True)
class SelectionOutputs:
    """A selection folder, read.

    Attributes
    ----------
    folder
        Where it was read from.
    summary
        ``selection.json``.
    tables
        ``selection``, ``candidates`` and, when present, ``confirmation`` and ``failures``.
    columns
        Per table, column → meaning (from its column dictionary; empty when there is none).
    files
        Every file read (for the provenance).
    """

    folder: Path
    summary: dict[str, Any]
    tables: dict[str, pd.DataFrame]
    columns: dict[str, dict[str, str]] = field(default_factory=dict)
    files: tuple[Path, ...] = ()


def _shared_dictionary(folder: Path, stem: str) -> tuple[dict[str, str], Path | None]:
    """``columns.csv`` (table, column, unit, meaning) as the selection stage writes it."""
    path = folder / "columns.csv"
    if not path.is_file():
        return {}, None
    table = _read_csv(path).fillna("")
    if not {"table", "column", "meaning"} <= set(table.columns):
        return {}, None
    rows = table[table["table"] == stem]
    units = rows["unit"] if "unit" in rows.columns else [""] * len(rows)
    return {
        str(column): f"{meaning} [{unit}]" if unit else str(meaning)
        for column, meaning, unit in zip(rows["column"], rows["meaning"], units, strict=True)
    }, path


def _dictionary(folder: Path, stem: str) -> tuple[dict[str, str], Path | None]:
    shared, path = _shared_dictionary(folder, stem)
    if shared:
        return shared, path
    for name in (f"{stem}.columns.csv", f"{stem}_columns.csv", f"{stem}.columns.json"):
        path = folder / name
        if not path.is_file():
            continue
        if path.suffix == ".json":
            entries = json.loads(path.read_text(encoding="utf-8"))
            if isinstance(entries, dict):
                return {str(k): str(v) for k, v in entries.items()}, path
            return {str(e["column"]): str(e.get("meaning", "")) for e in entries}, path
        table = pd.read_csv(path, dtype=str, keep_default_na=False)
        if table.shape[1] >= 2:
            return dict(zip(table.iloc[:, 0], table.iloc[:, 1], strict=True)), path
    return {}, None


#: Columns read as text whatever they look like: a component named "000" stays "000".
TEXT_COLUMNS = {"file": str, "component": str, "station": str, "event": str}


def _read_csv(path: Path) -> pd.DataFrame:
    try:
        return pd.read_csv(path, dtype=TEXT_COLUMNS)
    except pd.errors.EmptyDataError:
        raise InputError("empty file, expected a CSV table with a header line", path) from None
    except (pd.errors.ParserError, UnicodeDecodeError) as error:
        message = str(error).splitlines()[0] if str(error) else type(error).__name__
        raise InputError(f"not a readable CSV table ({message}), expected CSV", path) from None


def read_selection_folder(folder: str | PathLike[str]) -> SelectionOutputs:
    """Read a selection output folder, or the ``selection/`` of a workflow's outputs folder.

    Raises
    ------
    InputError
        Not a folder, or a required file missing or unreadable (a half-written run), or a table
        without its ``file`` column.
    """
    root = Path(folder)
    if not root.is_dir():
        raise InputError("not a folder, expected the output folder of `stepframe select`", root)
    if not (root / REQUIRED[0]).exists() and (root / WORKFLOW_FOLDER / REQUIRED[0]).is_file():
        root = root / WORKFLOW_FOLDER
    missing = [name for name in REQUIRED if not (root / name).is_file()]
    if missing:
        raise InputError(
            f"incomplete selection folder: {', '.join(missing)} missing, expected "
            f"{', '.join(REQUIRED)} (the output of a finished `stepframe select -o DIR`)",
            root,
        )
    summary_path = root / "selection.json"
    try:
        summary = json.loads(summary_path.read_text(encoding="utf-8"))
    except (json.JSONDecodeError, UnicodeDecodeError) as error:
        line = getattr(error, "lineno", None)
        raise InputError("not valid JSON, expected the run's summary", summary_path, line) from None
    if not isinstance(summary, dict):
        raise InputError("not a JSON object, expected the run's summary", summary_path)
    _check_unchanged(root, summary, summary_path)
    tables: dict[str, pd.DataFrame] = {}
    columns: dict[str, dict[str, str]] = {}
    files = [summary_path]
    for name in (*REQUIRED[1:], *OPTIONAL):
        path = root / name
        if not path.is_file():
            continue
        stem = path.stem
        tables[stem] = _read_csv(path)
        files.append(path)
        columns[stem], dictionary = _dictionary(root, stem)
        if dictionary is not None and dictionary not in files:
            files.append(dictionary)
    for stem in ("selection", "candidates"):
        if "file" not in tables[stem].columns:
            raise InputError(
                "no 'file' column, expected one row per record with its file",
                root / f"{stem}.csv",
                1,
            )
    return SelectionOutputs(root, summary, tables, columns, tuple(files))


def _check_unchanged(root: Path, summary: dict[str, Any], summary_path: Path) -> None:
    """Every file the run recorded in ``selection.json`` is there with the bytes it wrote: a
    report of an edited ``selection.csv`` said "Selected 2" above "of 3 components" (the
    summary's); a folder written before the run recorded them is read as it is."""
    from stepframe.core.io import file_sha256
    from stepframe.pipeline.selection.result import FILES_KEY

    recorded = summary.get(FILES_KEY)
    if recorded is None:
        return
    if not isinstance(recorded, dict):
        raise InputError(f"{FILES_KEY} is not an object, expected file → sha256", summary_path)
    for name, digest in recorded.items():
        path = root / name
        if not path.is_file():
            raise InputError(
                f"{name} is missing, expected every file the selection run wrote (run the "
                "selection again)",
                root,
            )
        if file_sha256(path) != digest:
            raise InputError(
                f"{name} was changed after the selection run wrote it (its sha256 is not the "
                "one selection.json records), expected the run's own files: run the selection "
                "again rather than editing its tables",
                root,
            )
