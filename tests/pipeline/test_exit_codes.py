"""Exit 1 when a requested output cannot be produced; failed items are listed either way."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from stepframe.cli import main

from .conftest import FEATURES_WORKFLOW, write_workflow


def test_no_readable_record_is_exit_1_with_the_failures_listed(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "records").mkdir()
    (tmp_path / "records" / "a.txt").write_text("not a record\n")
    (tmp_path / "records" / "b.txt").write_text("1 2 3 oops\n")
    write_workflow(tmp_path, FEATURES_WORKFLOW)
    assert main(["--json", "run", str(tmp_path / "wf.toml"), "--jobs", "1"]) == 1
    report = json.loads(capsys.readouterr().out)
    assert report["exit_code"] == 1
    assert [f["item"] for f in report["failures"]] == ["a.txt", "b.txt"]
    assert {f["stage"] for f in report["failures"]} == {"inventory"}
    stages = {s["name"]: s for s in report["stages"]}
    assert stages["inventory"]["failed"] == 2 and stages["inventory"]["status"] == "failed"
    assert stages["features"]["status"] == "skipped"
    assert "features" in report["missing"] and report["outputs"] == {}


def test_every_component_failing_is_exit_1(scene: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # 0.01 s sampling: Nyquist 314 rad/s, below the 1000 rad/s asked: every component fails
    text = FEATURES_WORKFLOW.replace("[features]", "[features]\nomega_max_rad_s = 1000.0")
    text = text.replace("[outputs]", '[site]\nfrom = "records"\n\n[outputs]\nsite = true')
    write_workflow(scene, text)
    assert main(["run", str(scene / "wf.toml"), "--jobs", "1"]) == 1
    out = capsys.readouterr().out
    assert out.count("features: RSN") == 4  # each failed component listed
    assert "output features NOT produced: no item computed (4 failed of 4)" in out
    assert "output site NOT produced: upstream stage features has no result" in out
