"""Provenance of a report: what produced it, from which inputs, on which machine.

A reviewer must be able to tell which code and which files gave the numbers: every report carries
the stepframe and dependency versions, the command (or workflow and its text), each input file's
name and SHA-256, the parameters, the date and the machine's core count.
"""

from __future__ import annotations

import dataclasses
import datetime as _dt
import os
import platform
import sys
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from importlib import metadata
from os import PathLike
from pathlib import Path
from typing import Any

from stepframe.core.io import file_sha256

#: Distributions whose versions change the numbers or the figures of a report.
DEPENDENCIES = ("numpy", "scipy", "pandas", "xarray", "matplotlib", "obspy", "numba", "jinja2")


def _version(name: str) -> str:
    try:
        return metadata.version(name)
    except metadata.PackageNotFoundError:
        return "not installed"


@dataclass(frozen=True)
class Provenance:
    """Everything a report states about how it was made.

    Attributes
    ----------
    command
        The command line (``stepframe report ...``) or the stage that wrote the report.
    inputs
        ``(name, sha256)`` of each input file, in the order given.
    parameters
        The options that change the numbers (JSON-ready values).
    workflow
        ``(name, text)`` of the workflow file when a workflow ran the report, else None.
    created_utc
        ISO 8601 time of writing (UTC, seconds).
    versions
        ``python``, ``stepframe`` and :data:`DEPENDENCIES` → version.
    cpu_count
        Cores of the machine (``os.cpu_count()``).
    platform
        Operating system and machine (``platform.platform()``).
    """

    command: str
    inputs: tuple[tuple[str, str], ...] = ()
    parameters: Mapping[str, Any] = field(default_factory=dict)
    workflow: tuple[str, str] | None = None
    created_utc: str = ""
    versions: Mapping[str, str] = field(default_factory=dict)
    cpu_count: int = 0
    platform: str = ""

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary (written beside the report as provenance.json)."""
        return {
            "command": self.command,
            "inputs": [{"name": name, "sha256": digest} for name, digest in self.inputs],
            "parameters": dict(self.parameters),
            "workflow": None
            if self.workflow is None
            else {"name": self.workflow[0], "text": self.workflow[1]},
            "created_utc": self.created_utc,
            "versions": dict(self.versions),
            "cpu_count": self.cpu_count,
            "platform": self.platform,
        }


def collect_provenance(
    command: str | Iterable[str] | None = None,
    *,
    inputs: Iterable[str | PathLike[str]] = (),
    parameters: Mapping[str, Any] | None = None,
    workflow: str | PathLike[str] | None = None,
) -> Provenance:
    """Provenance of a report being made now.

    Parameters
    ----------
    command
        The command line as a string or argument list (default: ``sys.argv``).
    inputs
        Input files; each is hashed (SHA-256). Folders are expanded to their files, sorted.
    parameters
        Options that change the numbers.
    workflow
        The workflow file that ran the report (its text is embedded), if any.
    """
    from stepframe import __version__

    if command is None:
        command = ["stepframe", *sys.argv[1:]]
    if not isinstance(command, str):
        command = " ".join(str(word) for word in command)
    files: list[Path] = []
    for item in inputs:
        path = Path(item)
        files.extend(sorted(p for p in path.rglob("*") if p.is_file()) if path.is_dir() else [path])
    versions = {"python": platform.python_version(), "stepframe": __version__}
    versions |= {name: _version(name) for name in DEPENDENCIES}
    text = None
    if workflow is not None:
        text = (str(workflow), Path(workflow).read_text(encoding="utf-8"))
    return Provenance(
        command=command,
        inputs=tuple((str(p), file_sha256(p)) for p in files),
        parameters=dict(parameters or {}),
        workflow=text,
        created_utc=_dt.datetime.now(_dt.UTC).replace(microsecond=0).isoformat(),
        versions=versions,
        cpu_count=os.cpu_count() or 0,
        platform=platform.platform(),
    )


#: What a workflow's report says for its time of writing: the run log has it (a report made
#: by a workflow is the same bytes whenever and wherever the workflow runs, docs/workflows.md).
IN_THE_RUN_LOG = "see the workspace's run log (runs.jsonl)"


def workflow_provenance(workflow: str | PathLike[str], parameters: Mapping[str, Any]) -> Provenance:
    """Provenance of a report made by a workflow's stage: ``stepframe run WORKFLOW`` (by the
    file's name: not where it happens to be; a shipped workflow by the name it is run by,
    ``stepframe run site-amplification``, there being no such file to give), the workflow's
    text and the stage's parameters; the time of writing is in the run log."""
    from stepframe.pipeline.engine.shipped import is_shipped

    name = Path(workflow).name
    command = Path(workflow).stem if is_shipped(Path(workflow)) else name
    made = collect_provenance(
        ["stepframe", "run", command], parameters=parameters, workflow=workflow
    )
    text = made.workflow[1] if made.workflow is not None else ""
    return dataclasses.replace(made, workflow=(name, text), created_utc=IN_THE_RUN_LOG)


def command_line(words: list[str], parameters: Mapping[str, Any]) -> str:
    """The command line ``words --name value ...`` that reproduces a report (shell-quoted; a
    value True is a switch, ``--name`` alone)."""
    import shlex

    for name, value in parameters.items():
        flag = f"--{name.replace('_', '-')}"
        words = [*words, flag] if value is True else [*words, flag, str(value)]
    return shlex.join(words)
