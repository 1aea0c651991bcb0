"""Shared machinery of the command groups: parser class, results, the leaf runner.

Each command module (listed per group in :data:`GROUPS`) has ``register(subparsers)``, which adds
its commands with :func:`add_command`. A command parses its options, calls one library function
(mostly a :mod:`stepframe.pipeline` stage) and returns what it got, a result with ``to_dict()``
and ``describe()`` (or a :class:`CommandResult`); :func:`execute` checks and draws ``--plot`` and
:mod:`stepframe.cli` prints. Command modules import only argparse and light name modules at
module level: the heavy imports happen inside their ``run`` functions.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from dataclasses import dataclass
from types import ModuleType
from typing import TYPE_CHECKING, Any, NoReturn, Protocol

from stepframe.core.memory import MemoryOptions
from stepframe.core.options import Once, add_fields, add_options, options_from

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    #: What ``ArgumentParser.add_subparsers()`` returns (argparse names the class privately; its
    #: parser type is :class:`Parser` or argparse's).
    Subparsers = argparse._SubParsersAction[Any]


class UserError(Exception):
    """A command-line usage error (unknown option, bad value), reported as one line."""


class Parser(argparse.ArgumentParser):
    """An argument parser that raises :class:`UserError` instead of printing usage and exiting.

    Sub-parsers inherit the class, so every level of the tree reports errors the same way.
    """

    def error(self, message: str) -> NoReturn:
        # the top-level parser's prog is the program itself, which the error line already names
        prefix = f"{self.prog}: " if " " in self.prog else ""
        raise UserError(f"{prefix}{message}")


@dataclass(frozen=True)
class CommandResult:
    """What a command produced: JSON-ready data for ``--json``, text for people, the figure that
    ``--plot`` draws, and the exit status (1: printed, but an output could not be produced)."""

    data: Any
    text: str = ""
    figure: Callable[[], Figure] | None = None
    exit_code: int = 0


class Reported(Protocol):
    """A library result a command can return as it is (its ``figure`` drawn by ``--plot``, its
    ``exit_code`` the command's)."""

    def to_dict(self) -> Any: ...

    def describe(self) -> str: ...


Run = Callable[[argparse.Namespace], CommandResult | Reported]


def add_command(
    subparsers: Subparsers, name: str, run: Run, *, plot: str | None = None
) -> argparse.ArgumentParser:
    """Add the leaf command ``name``, run by ``run``, with ``--json``, ``--debug``,
    ``--memory-mb MB`` (:class:`~stepframe.core.memory.MemoryOptions`) and, when ``plot`` (its
    help) is given, ``--plot OUT.png``.

    ``run``'s docstring is the command's help: its summary is the line in the group's command
    list (with a lowercase first letter and no full stop, as argparse writes its own), its
    other paragraphs the description, and its ``Examples`` section the worked examples (command
    lines, kept as written).
    """
    summary, description, examples = _help_text(run)
    parser: argparse.ArgumentParser = subparsers.add_parser(
        name,
        help=summary,
        description=description or summary,
        epilog="examples:\n" + examples,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    # SUPPRESS keeps a leaf's default from overwriting a --json given before the command name.
    add_options(
        parser,
        ("--json", bool, None, "print only JSON on stdout", argparse.SUPPRESS),
        ("--debug", bool, None, "show the traceback of an error", argparse.SUPPRESS),
    )
    add_fields(parser, MemoryOptions)
    if plot is not None:
        add_options(parser, ("--plot", None, "OUT.png", plot))
    parser.set_defaults(run=run, _leaf_parser=parser)
    return parser


def _help_text(run: Run) -> tuple[str, str, str]:
    """The summary, the description and the examples of ``run``'s docstring (see
    :func:`add_command`); each paragraph becomes one line, for the terminal to wrap."""
    import textwrap

    first, _, rest = (run.__doc__ or "").partition("\n")
    text, found, examples = f"{first}\n{textwrap.dedent(rest)}".partition("Examples\n--------\n")
    if not found:
        raise ValueError(f"{run.__qualname__}: no Examples section, expected worked examples")
    summary, *paragraphs = [" ".join(p.split()) for p in text.split("\n\n") if p.strip()]
    summary = summary[0].lower() + summary[1:].removesuffix(".")
    examples = textwrap.indent(examples.strip("\n"), "  ") + "\n"
    return summary, "\n\n".join(paragraphs), examples


def execute(args: argparse.Namespace) -> CommandResult:
    """Run the leaf command of ``args`` within its memory budget (``--memory-mb``,
    :mod:`stepframe.core.memory`): refuse a bad ``--plot`` path before any work, and draw the
    result's figure to it after (the result gains ``plot`` and the line ``plot written to``).
    """
    plot = getattr(args, "plot", None)
    if plot is not None:
        from stepframe.core.figures import check_figure_path

        check_figure_path(plot)
    with options_from(args, MemoryOptions).applied():
        done = args.run(args)
    if isinstance(done, CommandResult):
        result = done
    else:
        figure, exit_code = getattr(done, "figure", None), getattr(done, "exit_code", 0)
        result = CommandResult(done.to_dict(), done.describe(), figure, exit_code)
    result = finite_or_failed(result)
    if plot is None or result.figure is None:
        return result
    from stepframe.core.figures import save_figure

    save_figure(result.figure(), plot)
    data = {**result.data, "plot": plot} if isinstance(result.data, dict) else result.data
    return CommandResult(data, f"{result.text}\nplot written to {plot}", exit_code=result.exit_code)


#: Statuses (:data:`stepframe.core.results.STATUSES`) of a result that is not usable: the
#: command exits 1 (its output printed, for the record of what happened).
FAILED_STATUSES = ("nonfinite", "failed")


def finite_or_failed(result: CommandResult) -> CommandResult:
    """``result`` with an exit status that says whether its numbers are usable.

    A result with a ``status`` (an object at the top) is never ``ok`` with a number that left
    the finite range: such numbers are left out of the printed object (a key documented as a
    number is a number or absent, never null), the status becomes ``nonfinite`` with a message
    naming them, and the exit status 1; a result whose status is ``nonfinite`` or ``failed``
    exits 1 too.
    """
    import math

    data = result.data
    if not isinstance(data, dict) or "status" not in data:
        return result
    bad = [
        key for key, value in data.items() if isinstance(value, float) and not math.isfinite(value)
    ]
    status, exit_code = data["status"], result.exit_code
    if bad:
        data = {key: value for key, value in data.items() if key not in bad}
        status = data["status"] = "nonfinite" if status in ("ok", "success") else status
        note = f"not finite, left out: {', '.join(bad)}"
        data["message"] = "; ".join(filter(None, [str(data.get("message") or ""), note]))
    if status in FAILED_STATUSES:
        exit_code = max(exit_code, 1)
    if data is result.data and exit_code == result.exit_code:
        return result
    text = result.text + (f"\nstatus {status}: {data.get('message', '')}" if bad else "")
    return CommandResult(data, text, result.figure, exit_code)


def add_record_options(parser: argparse.ArgumentParser) -> None:
    """The record options every command that reads a record takes (DESIGN.md, Command line):
    the fields of :class:`~stepframe.records.read_options.RecordSource`, each refusing to be
    given twice (``--example`` only where the command has not declared its own)."""
    from stepframe.records.read_options import RecordReadOptions, RecordSource

    group = parser.add_argument_group("record options")
    if "--example" not in parser._option_string_actions:
        add_fields(group, RecordSource, ["example"], action=Once)
    add_fields(group, RecordReadOptions, action=Once)


#: The command groups: name → help. The commands of group ``name`` are added by
#: ``register(subparsers)`` of the module ``stepframe.commands.<name>``; modules are named, not
#: imported, so building the table needs none of them (they import this package).
GROUPS = {
    "report": "self-contained HTML reports: site amplification, record selection",
    "records": "read accelerograms, intensity measures, spectra, catalogues",
    "stochastic": "evolutionary spectra, ground-motion model, mean square, amplification",
    "structure": "frame parameters, quasi-dynamic design, stepping simulation",
    "store": "a workspace's store: verify every object's checksum, compact small segments",
}


def group_module(name: str) -> ModuleType:
    """The module of group ``name``, with ``register(subparsers)``."""
    import importlib

    return importlib.import_module(f"stepframe.commands.{name}")
