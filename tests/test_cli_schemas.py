"""docs/cli.md states one JSON shape per command: the top-level keys of each command's output,
run as written there on the shipped files, are exactly the documented ones."""

from __future__ import annotations

import contextlib
import io
import json
import re
import shlex
import shutil
from pathlib import Path

import pytest

from stepframe.cli import main

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data"


def _sections() -> list[tuple[str, str, list[str]]]:
    text = (ROOT / "docs" / "cli.md").read_text()
    found = []
    for name, command, block in re.findall(
        r"## `stepframe ([^`]+)`\n\n`([^`]+)` prints .*?```text\n(.*?)```", text, re.S
    ):
        keys = [line.split(":")[0] for line in block.splitlines() if not line.startswith(" ")]
        found.append((name, command, keys))
    return found


SECTIONS = _sections()


def test_every_command_is_documented() -> None:
    names = {name for name, _, _ in SECTIONS}
    assert names == {
        "demo", "records info", "records spectrum", "records catalog", "stochastic fit",
        "stochastic features", "stochastic amplify", "structure design", "structure simulate",
        "select", "report amplification", "report selection", "run", "store verify",
        "store compact", "structure harmonic", "structure bifurcation", "structure ida",
    }  # fmt: skip


@pytest.fixture(scope="module")
def workspace(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("schemas")
    (folder / "records").mkdir()
    for path in (DATA / "peer_nga_west2").glob("*.AT2"):
        shutil.copy(path, folder)
        shutil.copy(path, folder / "records")
    # the selection folder `report selection` reads, whichever order the commands run in
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(["structure", "frame-template"]) == 0
    (folder / "FRAME.toml").write_text(out.getvalue())
    words = ["select", "--frame", str(folder / "FRAME.toml"), "--example", "fema-p695", "-n", "3"]
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        assert main([*words, "-o", str(folder / "picks")]) == 0
    return folder


def _json(words: list[str]) -> object:
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
        assert main(words) == 0, words
    return json.loads(out.getvalue())


@pytest.mark.parametrize(("name", "command", "keys"), SECTIONS)
def test_documented_top_level_keys(
    name: str, command: str, keys: list[str], workspace: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(workspace)
    for setup, target in (
        (["structure", "frame-template"], "FRAME.toml"),
        (["structure", "design", "--template"], "pier.toml"),
    ):
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            assert main(setup) == 0
        Path(target).write_text(out.getvalue())
    data = _json(shlex.split(command)[1:])
    if isinstance(data, list):  # one object per component
        assert data and all(isinstance(item, dict) for item in data)
        data = data[0]
    assert isinstance(data, dict)
    assert list(data) == keys, name
