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
    log = project / "inbox.log"
    report = json.loads(log.read_text()) if scheduler == "cron" else json.loads(first.stdout)
    assert [(s["name"], s["computed"]) for s in report["stages"]] == [
        ("inventory", 2),
        ("features", 2),
    ]
    outputs = project / "workflows" / "stepframe-work" / "outputs"
    assert (outputs / "features.csv").read_text().count("\n") == 3  # header + 2 components
    # two files arrive in a sub-folder: a copy of a file already seen (the same bytes: one item
    # with two names) and a new one, which the next scheduled run computes alone
    write_example_files(inbox / "later", count=3)
    first_name, copied_name = sorted(p.name for p in inbox.glob("*.AT2"))
    (inbox / "later" / first_name).unlink()
    log.unlink(missing_ok=True)
    second = subprocess.run(_as_here(command, project), shell=True, capture_output=True, text=True)
    assert second.returncode == 0, second.stderr
    report = json.loads(log.read_text()) if scheduler == "cron" else json.loads(second.stdout)
    assert [(s["name"], s["computed"], s["cached"]) for s in report["stages"]] == [
        ("inventory", 1, 2),
        ("features", 1, 2),
    ]
    assert [d["name"] for d in report["duplicates"]] == [f"later/{copied_name}"]
