"""Every example in README.md, docs/*.md and every ``--help`` text runs as written.

The examples name files that ship with the project (tests/data: the RSN 8883 pair, the format
files with their .gz names, ``acc.txt``, the CE.68150 MiniSEED and StationXML); the test runs
them in a folder holding those files under their names, ``records/`` (the RSN 8883 pair), a copy
of the shipped workflows in ``workflows/`` (as ``stepframe run NAME --copy workflows`` makes it),
and what the docs tell a user to make first: the parameter files (``stepframe structure
frame-template > FRAME.toml``, ``structure design --template > pier.toml``), ``meta.csv`` (written
as docs/selection.md shows), the inbox copy ``my-inbox/`` with record files in ``my-inbox/inbox/``
(docs/workflows.md) and ``stepframe-demo/``, the folder of ``stepframe demo`` (docs/reports.md).
Each must exit 0.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import re
import shlex
import shutil
from pathlib import Path

import pytest

from stepframe.cli import build_parser, main
from stepframe.pipeline.engine.shipped import copy_workflow, shipped_names

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data"
_PROSE = re.compile(r"\s{2,}\S.*$")  # "stepframe demo    what it does": the text after 2 spaces


def _join(text: str) -> str:
    """Continuation lines (a trailing backslash) joined with one space."""
    return re.sub(r" *\\\n\s*", " ", text)


def _help_examples() -> list[tuple[str, str]]:
    found = []

    def walk(parser: argparse.ArgumentParser, path: list[str]) -> None:
        for action in parser._actions:
            if isinstance(action, argparse._SubParsersAction):
                for name, sub in action.choices.items():
                    walk(sub, [*path, name])
        epilog = _join(parser.epilog or "")
        for line in epilog.splitlines():
            if line.strip().startswith("stepframe "):
                found.append((f"--help of {' '.join(path) or 'stepframe'}", line.strip()))

    walk(build_parser(), [])
    return found


def _docs_examples() -> list[tuple[str, str]]:
    """Command lines of the fenced blocks; one followed by ``stepframe: error:`` output is an
    example of an error (expected exit 2), marked with a leading ``!``."""
    found = []
    for path in [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]:
        for block in re.findall(r"```[a-z]*\n(.*?)```", path.read_text(), re.S):
            lines = [line.strip().removeprefix("$ ") for line in _join(block).splitlines()]
            for number, line in enumerate(lines):
                if line.startswith("stepframe ") and not line.startswith("stepframe: "):
                    following = lines[number + 1] if number + 1 < len(lines) else ""
                    failing = following.startswith("stepframe: error:")
                    found.append((path.name, ("!" if failing else "") + line))
    return found


def _runnable(line: str) -> bool:
    """Listings of commands (``info | spectrum``) and placeholders (``<group>``) are not runs."""
    return " | " not in line and "<" not in line.split(">")[0]


EXAMPLES = sorted(
    {(where, _PROSE.sub("", line)) for where, line in _help_examples() + _docs_examples()
     if _runnable(line)}
)  # fmt: skip


@pytest.fixture(scope="module")
def workspace(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("examples")
    for path in DATA.rglob("*"):
        if path.is_file():
            shutil.copy(path, folder / path.name)
    (folder / "records").mkdir()
    for path in (DATA / "peer_nga_west2").glob("*.AT2"):
        shutil.copy(path, folder / "records" / path.name)
    for name in shipped_names():
        copy_workflow(name, folder / "workflows")
    copy_workflow("inbox", folder / "my-inbox")  # stepframe run inbox --copy my-inbox
    for path in (folder / "records").glob("*.AT2"):  # record files arrive in the inboxes
        shutil.copy(path, folder / "workflows" / "inbox" / path.name)
        shutil.copy(path, folder / "my-inbox" / "inbox" / path.name)
    selection_md = (ROOT / "docs" / "selection.md").read_text()
    meta = re.search(r"cat > meta\.csv <<'EOF'\n(.*?)^EOF$", selection_md, re.S | re.M)
    assert meta, "docs/selection.md writes meta.csv"
    (folder / "meta.csv").write_text(meta.group(1))
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        assert main(["demo", "-o", str(folder / "stepframe-demo")]) == 0  # stepframe demo
    return folder


def _run(line: str) -> tuple[int, str]:
    words = shlex.split(line)[1:]
    target = None
    if ">" in words:
        at = words.index(">")
        words, target = words[:at], words[at + 1]
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(words)
    if target is not None:
        Path(target).write_text(out.getvalue())
    return code, err.getvalue()


def test_examples_are_found() -> None:
    lines = [line.removeprefix("!") for _, line in EXAMPLES]
    assert len(lines) >= 25
    assert any("records info RSN8883_14383980_13849090.AT2" in line for line in lines)
    assert any(line.startswith("stepframe structure design") for line in lines)


@pytest.mark.parametrize(("where", "line"), EXAMPLES)
def test_example_runs_as_written(
    where: str, line: str, workspace: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(workspace)
    for setup in (
        "stepframe structure frame-template > FRAME.toml",
        "stepframe structure frame-template > frame.toml",
        "stepframe structure frame-template > f.toml",
        "stepframe structure design --template > pier.toml",
    ):
        if not Path(setup.split("> ")[1]).exists():
            assert _run(setup)[0] == 0, setup
    expected = 2 if line.startswith("!") else 0  # an example of an error message
    code, err = _run(line.removeprefix("!"))
    assert code == expected, f"{where}: {line}\n{err}"
    if expected:
        assert err.startswith("stepframe: error:") and "Traceback" not in err
