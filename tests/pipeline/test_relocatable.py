"""Relocatable, repeatable results (issue 27): the same bytes wherever and whenever a workflow runs.

One scene (6 example records, the Example 4 frame, a confirmed selection of 2 and its report,
the features and the inventory) is run in two folders: every output is byte-identical, report
included (its time of writing and the confirmation's throughput are in the run log). A copy of
the first workspace, with its records, moved elsewhere gives the same outputs from its store
without computing anything. The selection report made again from another current folder finds
every record by its identity (every figure drawn, the same numbers); a record that changed or is
gone makes it fail loudly.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from stepframe.cli import main
from stepframe.pipeline.catalogue.example_files import write_example_files

from .conftest import tree

FRAMES = Path(__file__).resolve().parents[2] / "src" / "stepframe" / "workflows" / "frames"

WORKFLOW = """\
[records]
folder = "records"

[frame]
file = "frames/example-4.toml"

[selection]
n = 2
confirm = true

[outputs]
inventory = true
features = true
selection = true
selection_report = true
"""


def _scene(folder: Path) -> Path:
    write_example_files(folder / "records", count=6)
    shutil.copytree(FRAMES, folder / "frames")
    (folder / "wf.toml").write_text(WORKFLOW)
    return folder


def _run(scene: Path, capsys: pytest.CaptureFixture[str]) -> dict[str, object]:
    capsys.readouterr()
    assert main(["run", str(scene / "wf.toml"), "--jobs", "1", "--json"]) == 0
    report: dict[str, object] = json.loads(capsys.readouterr().out)
    return report


@pytest.fixture(scope="module")
def two_runs(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """The scene run in two folders (two uninterrupted runs, nothing shared)."""
    first = _scene(tmp_path_factory.mktemp("first") / "a")
    second = _scene(tmp_path_factory.mktemp("second") / "somewhere" / "else")
    for scene in (first, second):
        assert main(["run", str(scene / "wf.toml"), "--jobs", "1"]) == 0
    return first, second


def test_two_folders_give_the_same_bytes(two_runs: tuple[Path, Path]) -> None:
    first, second = two_runs
    outputs = tree(first / "stepframe-work" / "outputs")
    assert tree(second / "stepframe-work" / "outputs") == outputs
    assert {"selection_report.html", "selection/selection.csv", "features.csv"} <= set(outputs)
    for name, data in outputs.items():
        assert str(first).encode() not in data, name  # no absolute path of the workspace
    # the facts of each run are in its run log instead
    [line] = (first / "stepframe-work" / "runs.jsonl").read_text().splitlines()
    log = json.loads(line)
    assert log["facts"]["selection"]["confirmation_samples_per_s"] > 0
    assert log["exit_code"] == 0 and log["stages"]["features"] == [6, 6, 0, 0]


def test_the_selection_names_each_record_by_its_identity(two_runs: tuple[Path, Path]) -> None:
    from stepframe.core.io import file_sha256

    first, _ = two_runs
    selection = first / "stepframe-work" / "outputs" / "selection"
    summary = json.loads((selection / "selection.json").read_text())
    assert summary["records"] == {"folder": "records", "options": {}}
    rows = (selection / "selection.csv").read_text().splitlines()
    header = rows[0].split(",")
    assert header[1:3] == ["file", "content_sha256"]
    for row in rows[1:]:
        file, sha = row.split(",")[1:3]
        assert file_sha256(first / "records" / file) == sha


def test_a_copied_workspace_gives_the_same_bytes_computing_nothing(
    two_runs: tuple[Path, Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    first, _ = two_runs
    copy = tmp_path / "moved" / "scene"
    shutil.copytree(first, copy)
    shutil.rmtree(copy / "stepframe-work" / "outputs")
    report = _run(copy, capsys)
    assert all(stage["computed"] == 0 for stage in report["stages"])  # type: ignore[attr-defined,index]
    assert tree(copy / "stepframe-work" / "outputs") == tree(first / "stepframe-work" / "outputs")


def test_the_report_made_from_another_folder_draws_every_record(
    two_runs: tuple[Path, Path],
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:
    first, _ = two_runs
    outputs = first / "stepframe-work" / "outputs"
    monkeypatch.chdir(tmp_path)
    assert main(["report", "selection", str(outputs / "selection"), "-o", "again.html"]) == 0
    made = tree(tmp_path / "again_files")
    workflow_made = tree(outputs / "selection_report_files")
    del made["provenance.json"], workflow_made["provenance.json"]  # the command differs
    assert made == workflow_made
    numbers = json.loads(made["numbers.json"])
    assert len(numbers["accelerogram_records"]) == 2 and len(numbers["spectra_records"]) == 2
    assert "could be found" not in (tmp_path / "again.html").read_text()
    capsys.readouterr()


def test_a_changed_or_missing_record_fails_the_report_loudly(
    two_runs: tuple[Path, Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    first, _ = two_runs
    copy = tmp_path / "scene"
    shutil.copytree(first, copy)
    selection = copy / "stepframe-work" / "outputs" / "selection"
    file = (selection / "selection.csv").read_text().splitlines()[1].split(",")[1]
    record = copy / "records" / file
    record.write_bytes(record.read_bytes() + b"\n")
    capsys.readouterr()
    assert main(["report", "selection", str(selection)]) == 2
    err = capsys.readouterr().err.strip()
    assert err == (
        f"stepframe: error: {record}: changed since the selection (sha256 "
        f"{(selection / 'selection.csv').read_text().splitlines()[1].split(',')[2][:12]}…), "
        "expected the record it was made from (run the selection again)"
    )
    record.unlink()
    assert main(["report", "selection", str(selection)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"stepframe: error: {file} (sha256 ") and "not found in records/" in err
