"""Helpers of the pipeline tests: example records written as files, workflows, the CLI."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import pandas as pd
import pytest

from stepframe.pipeline.catalogue.example_files import write_example_files

#: The first four example components: two records of two components each, 2,000-3,000 samples.
SMALL = 4


def write_workflow(folder: Path, text: str, name: str = "wf.toml") -> Path:
    """A workflow file in ``folder``."""
    path = folder / name
    path.write_text(text, encoding="utf-8")
    return path


FEATURES_WORKFLOW = """\
[records]
folder = "records"

[features]
frequency = "zero-crossing"

[outputs]
features = true
"""


@pytest.fixture
def scene(tmp_path: Path) -> Path:
    """A folder with records/ (the first four example components) and wf.toml (features)."""
    write_example_files(tmp_path / "records", count=SMALL)
    write_workflow(tmp_path, FEATURES_WORKFLOW)
    return tmp_path


def stepframe(
    *args: str, cwd: Path | None = None, timeout: float = 600
) -> subprocess.CompletedProcess[str]:
    """Run the ``stepframe`` command in a subprocess."""
    return subprocess.run(
        [sys.executable, "-m", "stepframe.cli", *args],
        capture_output=True,
        text=True,
        timeout=timeout,
        cwd=cwd,
        env={**os.environ, "PYTHONUNBUFFERED": "1"},
    )


def run_json(*args: str, cwd: Path | None = None) -> dict[str, Any]:
    """``stepframe --json run ...``: the report, checking exit 0."""
    done = stepframe("run", *args, "--json", cwd=cwd)
    assert done.returncode == 0, done.stderr
    report: dict[str, Any] = json.loads(done.stdout)
    return report


def stage(report: dict[str, Any], name: str) -> dict[str, Any]:
    """One stage's summary in a run report."""
    found: dict[str, Any] = next(s for s in report["stages"] if s["name"] == name)
    return found


def output_table(report: dict[str, Any], name: str) -> pd.DataFrame:
    """An output table (its Parquet file) of a run report."""
    parquet = next(p for p in report["outputs"][name] if p.endswith(".parquet"))
    return pd.read_parquet(parquet)


def tree(folder: Path) -> dict[str, bytes]:
    """Every file under ``folder`` (relative path → bytes)."""
    return {
        p.relative_to(folder).as_posix(): p.read_bytes()
        for p in sorted(folder.rglob("*"))
        if p.is_file()
    }
