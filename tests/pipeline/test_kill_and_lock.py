"""Crash safety and the workspace lock, through real `stepframe run` subprocesses.

Kill test: a run is killed with SIGKILL while reading records, while computing features and
while writing outputs; re-running gives byte-identical final tables to an uninterrupted run,
and no partial file remains. Lock test: a second run on the same workspace exits 3 naming the
holder's pid, or waits with --wait.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import pandas as pd
import pytest

from stepframe.pipeline.catalogue.example_files import write_example_files

from .conftest import FEATURES_WORKFLOW, stepframe, tree, write_workflow

N_FILES = 6


def _start(workflow: Path, *extra: str) -> subprocess.Popen[str]:
    return subprocess.Popen(
        [sys.executable, "-m", "stepframe.cli", "run", str(workflow), "--json", *extra],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )


def _wait_for(
    condition: Callable[[], bool], process: subprocess.Popen[str], timeout: float
) -> bool:
    """Poll ``condition`` until true (True) or the process ends first (False)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if condition():
            return True
        if process.poll() is not None:
            return False
        time.sleep(0.002)
    raise AssertionError("condition not reached in time")


def _segments(workspace: Path, stage: str) -> int:
    folder = workspace / "store" / stage
    return len(list(folder.glob("seg-*.parquet"))) if folder.is_dir() else 0


@pytest.fixture
def two_workspaces(tmp_path: Path) -> tuple[Path, Path]:
    write_example_files(tmp_path / "records", count=N_FILES)
    reference = write_workflow(tmp_path, 'workspace = "reference"\n' + FEATURES_WORKFLOW, "a.toml")
    killed = write_workflow(tmp_path, 'workspace = "killed"\n' + FEATURES_WORKFLOW, "b.toml")
    return reference, killed


@pytest.mark.slow
def test_sigkill_at_several_points_then_rerun_gives_identical_tables(
    two_workspaces: tuple[Path, Path],
) -> None:
    reference, killed = two_workspaces
    done = stepframe("run", str(reference), "--jobs", "1")
    assert done.returncode == 0, done.stderr
    work = killed.parent / "killed"
    points: list[tuple[str, Callable[[], bool]]] = [
        ("reading", lambda: _segments(work, "inventory") >= 1),
        ("features", lambda: _segments(work, "features") >= 2),
        ("writing", lambda: (work / "outputs").is_dir()),
    ]
    killed_at = []
    for name, condition in points:
        process = _start(killed, "--jobs", "1", "--batch-items", "1", "--force", "features")
        if _wait_for(condition, process, timeout=300):
            process.send_signal(signal.SIGKILL)
            killed_at.append(name)
        process.wait(timeout=60)
        process.communicate()
    assert "reading" in killed_at and "features" in killed_at  # at least the two long phases
    final = stepframe("run", str(killed), "--jobs", "1", "--json")
    assert final.returncode == 0, final.stderr
    expected = tree(killed.parent / "reference" / "outputs")
    assert tree(work / "outputs") == expected
    assert set(expected) >= {"features.parquet", "features.csv", "features.failures.csv"}
    leftovers = [p for p in work.rglob("*") if p.name.endswith(".tmp")]
    assert leftovers == []
    for segment in (work / "store").rglob("*.parquet"):
        pd.read_parquet(segment)  # every stored segment is complete


def test_killed_mid_features_resumes_without_recomputing_stored_items(
    two_workspaces: tuple[Path, Path],
) -> None:
    _, killed = two_workspaces
    work = killed.parent / "killed"
    process = _start(killed, "--jobs", "1", "--batch-items", "1")
    assert _wait_for(lambda: _segments(work, "features") >= 2, process, timeout=300)
    process.send_signal(signal.SIGKILL)
    process.wait(timeout=60)
    process.communicate()
    stored = _segments(work, "features")
    done = stepframe("run", str(killed), "--jobs", "1", "--json")
    assert done.returncode == 0, done.stderr
    features = next(s for s in json.loads(done.stdout)["stages"] if s["name"] == "features")
    assert features["cached"] == stored and features["computed"] == N_FILES - stored


def test_second_run_exits_3_naming_the_holder_or_waits(two_workspaces: tuple[Path, Path]) -> None:
    reference, _ = two_workspaces
    lock = reference.parent / "reference" / "lock"
    first = _start(reference, "--jobs", "1")
    assert _wait_for(lambda: lock.is_file() and lock.read_text().strip() != "", first, timeout=300)
    second = stepframe("run", str(reference), "--jobs", "1")
    assert second.returncode == 3
    assert second.stdout == ""
    assert second.stderr.strip() == (
        f"stepframe: error: {reference.parent / 'reference'}: already running (pid {first.pid})"
    )
    waiting = _start(reference, "--jobs", "1", "--wait")
    out, err = first.communicate(timeout=600)
    assert first.returncode == 0, err
    out_wait, err_wait = waiting.communicate(timeout=600)
    assert waiting.returncode == 0, err_wait
    first_report, waited_report = json.loads(out), json.loads(out_wait)
    # the waiting run found everything stored by the first: the store is intact
    assert [s["computed"] for s in waited_report["stages"]] == [0, 0]
    assert [s["cached"] for s in waited_report["stages"]] == [N_FILES, N_FILES]
    assert waited_report["outputs"] == first_report["outputs"]
    assert lock.read_text() == ""  # released and emptied
    assert os.path.exists(lock)


def test_an_interrupted_run_leaves_its_line_in_the_run_log(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Ctrl-C in the middle of a run (here in the features stage, after the inventory) left no
    line in runs.jsonl: the log of a scheduled run did not say it had run at all."""
    from stepframe.pipeline.engine import runner
    from stepframe.pipeline.stages import shipped_stages

    write_example_files(tmp_path / "records", count=2)
    workflow = write_workflow(tmp_path, FEATURES_WORKFLOW)
    finished = runner._run_items

    def interrupted(stage: object, *args: object) -> None:
        if getattr(stage, "name", "") == "features":
            raise KeyboardInterrupt
        finished(stage, *args)  # type: ignore[arg-type]

    monkeypatch.setattr(runner, "_run_items", interrupted)
    with pytest.raises(KeyboardInterrupt):
        runner.run_workflow(workflow, shipped_stages(), jobs=1)
    (line,) = [
        json.loads(text)
        for text in (tmp_path / "stepframe-work" / "runs.jsonl").read_text().splitlines()
    ]
    assert line["interrupted"] is True and line["exit_code"] == 130
    assert list(line["stages"]) == ["inventory"] and line["outputs"] == []
