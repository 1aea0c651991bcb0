"""The copy command, the cron line and the systemd service of docs/scheduling.md, run as written.

The root ``/srv/stepframe`` of the page is replaced by a temporary folder, and
``/srv/stepframe/.venv/bin/stepframe`` by this environment's command.
"""

from __future__ import annotations

import json
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from stepframe.pipeline.catalogue.example_files import write_example_files

ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / "docs" / "scheduling.md"
PROJECT = "/srv/stepframe"


def _commands() -> dict[str, str]:
    text = PAGE.read_text(encoding="utf-8")
    copy = re.search(r"^(\S+/stepframe run inbox --copy \S+)$", text, re.M)
    cron = re.search(r"^\*/15 \* \* \* \* (.+)$", text, re.M)
    service = re.search(r"^ExecStart=(.+)$", text, re.M)
    assert copy and cron and service, "the page lost its copy command, cron line or ExecStart"
    assert re.search(r"^Persistent=true$", text, re.M)
    return {"copy": copy.group(1), "cron": cron.group(1), "systemd": service.group(1)}


def _as_here(command: str, project: Path) -> str:
    executable = shlex.quote(str(Path(sys.executable).parent / "stepframe"))
    command = command.replace(f"{PROJECT}/.venv/bin/stepframe", executable)
    return command.replace(PROJECT, str(project))


@pytest.mark.parametrize("scheduler", ["cron", "systemd"])
def test_the_documented_command_runs_the_inbox(tmp_path: Path, scheduler: str) -> None:
    command = _commands()[scheduler]
    assert "workflows/inbox.toml" in command
    project = tmp_path / "srv"
    copied = subprocess.run(_as_here(_commands()["copy"], project), shell=True, text=True,
                            capture_output=True)  # fmt: skip
    assert copied.returncode == 0, copied.stderr
    inbox = project / "workflows" / "inbox"
    assert inbox.is_dir() and not any(inbox.iterdir())
    write_example_files(inbox, count=2)
    first = subprocess.run(_as_here(command, project), shell=True, capture_output=True, text=True)
    assert first.returncode == 0, first.stderr
    errors = project / "inbox-errors.log"
    if scheduler == "cron":
        assert "--wait" in command and first.stdout == "" and errors.read_text() == ""
    run_log = project / "workflows" / "stepframe-work" / "runs.jsonl"
    report = json.loads(run_log.read_text().splitlines()[-1])  # one line per run
    assert report["stages"] == {"inventory": [2, 2, 0, 0], "features": [2, 2, 0, 0]}
    outputs = project / "workflows" / "stepframe-work" / "outputs"
    assert (outputs / "features.csv").read_text().count("\n") == 3  # header + 2 components
    # two files arrive in a sub-folder: a copy of a file already seen (the same bytes: one item
    # with two names) and a new one, which the next scheduled run computes alone
    write_example_files(inbox / "later", count=3)
    first_name, copied_name = sorted(p.name for p in inbox.glob("*.AT2"))
    (inbox / "later" / first_name).unlink()
    second = subprocess.run(_as_here(command, project), shell=True, capture_output=True, text=True)
    assert second.returncode == 0, second.stderr
    lines = run_log.read_text().splitlines()
    assert len(lines) == 2
    report = json.loads(lines[-1])
    assert report["stages"] == {"inventory": [3, 1, 2, 0], "features": [3, 1, 2, 0]}
    assert report["duplicates"] == 1  # later/<copied_name>: the same bytes as <copied_name>
    features = (outputs / "features.csv").read_text()
    assert f"{copied_name},later/{copied_name}," in features
