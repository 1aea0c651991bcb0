"""``stepframe demo`` on bad input, and the shipped workflows by name (``stepframe run NAME``).

The demo's results are checked in tests/test_cli.py (one full run); here every refusal is one
line with exit 2 (3 for a held lock), no traceback, and nothing written.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from stepframe.cli import main
from stepframe.pipeline.engine.lock import workspace_lock
from stepframe.pipeline.engine.shipped import (
    SHIPPED_DIR,
    copy_workflow,
    resolve_workflow,
    shipped_names,
)

SHIPPED = ["ida", "inbox", "selection", "site-amplification", "site-amplification-records"]


def _one_line(capsys: pytest.CaptureFixture[str]) -> str:
    captured = capsys.readouterr()
    assert captured.out == ""
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("stepframe: error: "), captured.err
    return lines[0]


def test_demo_refuses_a_file_as_its_folder(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("x")
    assert main(["demo", "-o", str(blocker)]) == 2
    line = _one_line(capsys)
    assert line == f"stepframe: error: {blocker}: exists and is not a folder, expected a folder"
    assert blocker.read_text() == "x" and sorted(tmp_path.iterdir()) == [blocker]


def test_demo_refuses_zero_jobs(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["demo", "-o", str(tmp_path / "demo"), "--jobs", "0"]) == 2
    assert _one_line(capsys) == "stepframe: error: --jobs 0, expected ≥ 1"
    assert list(tmp_path.iterdir()) == []


def test_demo_in_a_held_folder_exits_3_writing_nothing(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A second demo while one runs in the folder (the lock held here, as a running demo does)."""
    folder = tmp_path / "demo"
    with workspace_lock(folder):
        assert main(["demo", "-o", str(folder)]) == 3
        line = _one_line(capsys)
    assert line == f"stepframe: error: {folder}: already running (pid {os.getpid()})"
    assert [p.name for p in folder.iterdir()] == ["lock"]


def test_demo_in_an_unwritable_folder(tmp_path: Path, read_only_bind: None) -> None:
    """Root ignores permission bits: the folder is a read-only bind mount (``unshare -m``)."""
    locked = tmp_path / "locked"
    locked.mkdir()
    command = f"{sys.executable} -m stepframe.cli demo -o {locked}/demo"
    run = subprocess.run(
        ["unshare", "-m", "sh", "-c", f"mount --bind -o ro {locked} {locked} && {command}"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert run.returncode == 2, run.stderr
    assert run.stdout == "" and "Traceback" not in run.stderr
    assert run.stderr.strip().splitlines() == [
        f"stepframe: error: {locked}: is not writable, expected a writable folder"
    ]
    assert list(locked.iterdir()) == []


def test_shipped_names_and_an_unknown_one(capsys: pytest.CaptureFixture[str]) -> None:
    assert shipped_names() == SHIPPED
    assert resolve_workflow("selection") == SHIPPED_DIR / "selection.toml"
    assert resolve_workflow("selection.toml") == SHIPPED_DIR / "selection.toml"
    assert main(["run", "selecton"]) == 2
    assert _one_line(capsys) == (
        "stepframe: error: selecton: no such workflow file or shipped workflow, expected a "
        "WORKFLOW.toml or one of " + ", ".join(SHIPPED)
    )


def test_a_file_wins_over_a_shipped_name(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    Path("ida").mkdir()  # a folder is not a workflow file: the shipped one is meant
    assert resolve_workflow("ida") == SHIPPED_DIR / "ida.toml"
    Path("selection").write_text("")
    assert resolve_workflow("selection") == Path("selection")


def test_copy_then_run_the_copy(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    target = tmp_path / "mine"
    assert main(["run", "selection", "--copy", str(target)]) == 0
    assert capsys.readouterr().out.splitlines() == [
        str(target / "selection.toml"),
        str(target / "frames" / "example-4.toml"),
    ]
    for name in ("selection.toml", "frames/example-4.toml"):
        assert (target / name).read_bytes() == (SHIPPED_DIR / name).read_bytes()
    # copying again is harmless; an edited copy is never overwritten
    assert copy_workflow("selection", target) == [
        target / "selection.toml",
        target / "frames" / "example-4.toml",
    ]
    edited = (target / "selection.toml").read_text().replace("n = 10", "n = 3")
    (target / "selection.toml").write_text(edited)
    assert main(["run", "selection", "--copy", str(target)]) == 2
    assert "selection.toml: exists, expected a path the copy would not overwrite" in _one_line(
        capsys
    )
    assert (target / "selection.toml").read_text() == edited
    # the copy is an ordinary workflow: its workspace beside it
    assert main(["--json", "run", str(target / "selection.toml"), "--dry-run"]) == 0
    assert f'"workspace": "{target / "stepframe-work"}"' in capsys.readouterr().out


def test_the_shipped_inbox_is_run_from_a_copy(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["run", "inbox"]) == 2
    assert _one_line(capsys) == (
        "stepframe: error: the shipped workflow inbox reads a records folder beside it, expected "
        "a copy: stepframe run inbox --copy DIR, then stepframe run DIR/inbox.toml"
    )


def test_copy_of_the_inbox_makes_its_folder(tmp_path: Path) -> None:
    copied = copy_workflow("inbox", tmp_path)
    assert copied == [tmp_path / "inbox.toml", tmp_path / "inbox"]
    assert (tmp_path / "inbox").is_dir() and not any((tmp_path / "inbox").iterdir())


def test_copy_into_a_file_is_refused(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("x")
    assert main(["run", "ida", "--copy", str(blocker)]) == 2
    assert _one_line(capsys) == (
        f"stepframe: error: {blocker}: exists and is not a folder, expected a folder for the copy"
    )
    assert main(["run", "nope", "--copy", str(tmp_path / "x")]) == 2
    assert "no shipped workflow 'nope', expected one of ida, inbox" in _one_line(capsys)
    assert sorted(tmp_path.iterdir()) == [blocker]


def test_copy_with_an_option_of_a_run_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--copy runs nothing: 'stepframe run site-amplification --copy DIR --dry-run' copied and
    dropped --dry-run (and any other option of a run) without a word."""
    target = tmp_path / "copy"
    assert main(["run", "site-amplification", "--copy", str(target), "--dry-run"]) == 2
    assert _one_line(capsys) == (
        "stepframe: error: --copy with --dry-run, expected --copy alone (it copies the workflow "
        "and runs nothing: run the copy with them)"
    )
    assert main(["run", "inbox", "--copy", str(target), "--jobs", "2", "--force", "features"]) == 2
    assert "--copy with --jobs, --force, expected --copy alone" in _one_line(capsys)
    assert not target.exists()


def test_a_shipped_run_writes_in_the_current_folder(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """The package is never written: the workspace of a shipped workflow is ./stepframe-work."""
    monkeypatch.chdir(tmp_path)
    before = sorted(p.relative_to(SHIPPED_DIR) for p in SHIPPED_DIR.rglob("*"))
    assert main(["--json", "run", "site-amplification", "--dry-run"]) == 0
    assert '"workspace": "stepframe-work"' in capsys.readouterr().out
    assert sorted(p.relative_to(SHIPPED_DIR) for p in SHIPPED_DIR.rglob("*")) == before


def test_every_shipped_file_is_package_data() -> None:
    """A ``pip install .`` (not editable) carries each file of stepframe/workflows/: the
    package-data globs of pyproject.toml match every one (bench/bench_demo.py runs the demo from
    such an install)."""
    import tomllib
    from pathlib import PurePosixPath

    # The source tree beside these tests, not SHIPPED_DIR: CI installs the package
    # non-editably, and the installed copy holds only what the globs already matched.
    root = Path(__file__).resolve().parents[2]
    source = root / "src" / "stepframe" / "workflows"
    config = tomllib.loads((root / "pyproject.toml").read_text())
    globs = config["tool"]["setuptools"]["package-data"]["stepframe"]
    files = [p.relative_to(source.parent).as_posix() for p in source.rglob("*")]
    files = [f for f in files if (source.parent / f).is_file() and "__pycache__" not in f]
    assert len(files) == 6
    for file in files:
        path = PurePosixPath(file)  # a setuptools glob's * does not cross a /
        assert any(
            path.match(glob) and len(path.parts) == len(PurePosixPath(glob).parts) for glob in globs
        ), file


@pytest.mark.parametrize("value", ["0", "two", "2000", "-1"])
def test_a_bad_jobs_variable_is_refused_before_anything_is_written(
    value: str, tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("STEPFRAME_JOBS", value)
    assert main(["demo", "-o", str(tmp_path / "demo")]) == 2
    assert _one_line(capsys) == (
        f"stepframe: error: STEPFRAME_JOBS = {value!r}, expected a number of worker processes "
        "in [1, 1024] (or unset: all CPUs)"
    )
    assert list(tmp_path.iterdir()) == []


def test_the_jobs_variable_is_the_default_and_jobs_overrides_it(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    from stepframe.core.execution import default_jobs
    from stepframe.pipeline.engine.scheduler import open_execution

    monkeypatch.setenv("STEPFRAME_JOBS", " 3 ")
    assert default_jobs() == 3
    with open_execution(None, None) as execution:
        assert execution.jobs == 3
    with open_execution(None, 1) as execution:
        assert execution.jobs == 1
    monkeypatch.delenv("STEPFRAME_JOBS")
    assert default_jobs() == len(os.sched_getaffinity(0))


def test_demo_names_a_damaged_stored_object(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A features segment overwritten on disk: the next demo quarantines it, recomputes the
    features and says so in its summary, as `stepframe run` does; the tables are unchanged."""
    folder = tmp_path / "demo"
    assert main(["demo", "-o", str(folder), "--jobs", "1"]) == 0
    before = (folder / "selection" / "selection.csv").read_bytes()
    segment = sorted((folder / "store" / "features").glob("seg-*.parquet"))[0]
    segment.write_bytes(b"garbage")
    capsys.readouterr()
    assert main(["demo", "-o", str(folder), "--jobs", "1"]) == 0
    store_lines = [
        line for line in capsys.readouterr().out.splitlines() if line.startswith("store:")
    ]
    assert len(store_lines) == 1 and segment.name in store_lines[0]
    assert (folder / "store" / "quarantine" / "features").is_dir()
    assert (folder / "selection" / "selection.csv").read_bytes() == before
