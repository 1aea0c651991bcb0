"""docs/cli.md states one JSON shape per command: the top-level keys of each command's output,
run as written there on the shipped files, are exactly the documented ones; and in the outputs
of ``demo``, ``select`` and the ``structure`` commands (what they print and the JSON files they
write), no key the page documents as a number (or integer) is null, at any depth: an undefined
number is absent (core/jsonable.py)."""

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


def _documented_types(block: str) -> dict[tuple[str, ...], str]:
    """Path of keys (arrays transparent) → documented type, from a block of docs/cli.md
    (two spaces of indent per level; ``a, b: numbers`` documents both keys)."""
    types: dict[tuple[str, ...], str] = {}
    stack: list[str] = []
    for line in block.splitlines():
        depth = (len(line) - len(line.lstrip(" "))) // 2
        names, _, kind = line.strip().partition(": ")
        del stack[depth:]
        for name in names.split(", "):
            types[(*stack, name)] = kind
        stack.append(names.split(", ")[0])
    return types


def _numbers_documented(kind: str) -> bool:
    return kind.startswith(("number", "integer", "array of numbers", "array of integers"))


def nulls_where_numbers(value: object, types: dict[tuple[str, ...], str]) -> list[str]:
    """The paths of ``value`` whose documented type is a number and whose value is null."""
    found: list[str] = []

    def walk(item: object, path: tuple[str, ...]) -> None:
        if isinstance(item, dict):
            for key, sub in item.items():
                walk(sub, (*path, str(key)))
        elif isinstance(item, list):
            for sub in item:
                walk(sub, path)
        elif item is None and _numbers_documented(types.get(path, "")):
            found.append(".".join(path))

    walk(value, ())
    return found


def test_nulls_where_numbers_finds_them() -> None:
    """The walker of the test below finds a null at depth and in an array of numbers."""
    types = _documented_types("a: number\nb: array of objects\n  c: number, or null\n"
                              "  d: string\ne: array of numbers\n")  # fmt: skip
    data = {"a": 1.0, "b": [{"c": 2.0, "d": None}, {"c": None}], "e": [1.0, None]}
    assert nulls_where_numbers(data, types) == ["b.c", "e"]


def _sections() -> list[tuple[str, str, list[str]]]:
    text = (ROOT / "docs" / "cli.md").read_text()
    found = []
    for name, command, block in re.findall(
        r"## `stepframe ([^`]+)`\n\n`([^`]+)` prints .*?```text\n(.*?)```", text, re.S
    ):
        keys = [line.split(":")[0] for line in block.splitlines() if not line.startswith(" ")]
        found.append((name, command, keys))
        TYPES[name] = _documented_types(block)
    return found


#: Command → its documented key paths and types.
TYPES: dict[str, dict[tuple[str, ...], str]] = {}
SECTIONS = _sections()
#: The commands whose outputs are held to "a number or absent, never null" at every depth.
NO_NULL_NUMBERS = ("demo", "select", "structure ", "stochastic amplify")


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
    before = {path: path.stat().st_mtime_ns for path in workspace.rglob("*.json")}
    data = _json(shlex.split(command)[1:])
    if name.startswith(NO_NULL_NUMBERS):
        assert nulls_where_numbers(data, TYPES[name]) == [], name
        # the JSON files it wrote: a selection's summary has the shape of `select --json`
        written = [
            path for path in workspace.rglob("selection.json")
            if before.get(path) != path.stat().st_mtime_ns
        ]  # fmt: skip
        for path in written:
            found = nulls_where_numbers(json.loads(path.read_text()), TYPES["select"])
            assert found == [], (name, path)
    if isinstance(data, list):  # one object per component
        assert data and all(isinstance(item, dict) for item in data)
        data = data[0]
    assert isinstance(data, dict)
    # a key documented "absent when ..." may be left out (an undefined number), in its place
    optional = {key for key in keys if "absent" in TYPES[name].get((key,), "")}
    assert list(data) == [key for key in keys if key in data or key not in optional], name
