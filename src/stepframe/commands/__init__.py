"""Shared machinery of the command groups: parser class, results, JSON, the record options.

Each command module (listed per group in :data:`GROUPS`) has ``register(subparsers)``, which adds
its commands with :func:`add_command`. A command parses its options, calls one library function
(mostly a :mod:`stepframe.pipeline` stage) and returns a :class:`CommandResult`;
:mod:`stepframe.cli` prints it. Command modules import only argparse and light name modules at
module level: the heavy imports happen inside ``run``.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Callable
from dataclasses import dataclass
from types import ModuleType
from typing import TYPE_CHECKING, Any, NoReturn

from stepframe.core.jsonable import to_jsonable
from stepframe.core.options import add_fields, add_options, fields_given
from stepframe.errors import InputError
from stepframe.records.read_options import RecordReadOptions

if TYPE_CHECKING:
    from obspy import Stream

    #: What ``ArgumentParser.add_subparsers()`` returns (argparse names the class privately).
    Subparsers = argparse._SubParsersAction[argparse.ArgumentParser]


class UserError(Exception):
    """A command-line usage error (unknown option, bad value), reported as one line."""


class Parser(argparse.ArgumentParser):
    """An argument parser that raises :class:`UserError` instead of printing usage and exiting.

    Sub-parsers inherit the class, so every level of the tree reports errors the same way.
    """

    def error(self, message: str) -> NoReturn:
        raise UserError(f"{self.prog}: {message}")


@dataclass(frozen=True)
class CommandResult:
    """What a command produced: JSON-ready data for ``--json`` and text for people."""

    data: Any
    text: str = ""


def add_command(
    subparsers: Subparsers,
    name: str,
    *,
    help: str,
    examples: str,
    run: Callable[[argparse.Namespace], CommandResult],
    description: str | None = None,
) -> argparse.ArgumentParser:
    """Add a leaf command with ``--json``, ``--debug`` and a worked example in its ``--help``."""
    parser: argparse.ArgumentParser = subparsers.add_parser(
        name,
        help=help,
        description=description or help,
        epilog="examples:\n" + examples,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    # SUPPRESS keeps a leaf's default from overwriting a --json given before the command name.
    parser.add_argument(
        "--json", action="store_true", default=argparse.SUPPRESS, help="print only JSON on stdout"
    )
    parser.add_argument(
        "--debug",
        action="store_true",
        default=argparse.SUPPRESS,
        help="show the traceback of an error",
    )
    parser.set_defaults(run=run)
    return parser


class Once(argparse.Action):
    """Store an option's value, and refuse it given twice (argparse keeps the last silently:
    ``--record a --record b`` would drop ``a`` without a word)."""

    def __call__(
        self,
        parser: argparse.ArgumentParser,
        namespace: argparse.Namespace,
        values: Any,
        option_string: str | None = None,
    ) -> None:
        given: set[str] = namespace.__dict__.setdefault("_given_once", set())
        if self.dest in given:
            raise UserError(
                f"{parser.prog}: {option_string} given twice, expected it once "
                "(one value per option)"
            )
        given.add(self.dest)
        setattr(namespace, self.dest, values)


def add_record_options(parser: argparse.ArgumentParser) -> None:
    """The record options every command that reads a record takes (DESIGN.md, Command line):
    ``--example`` and the fields of :class:`RecordReadOptions`; each refuses to be given twice
    (:class:`Once`)."""
    group = parser.add_argument_group("record options")
    if "--example" not in parser._option_string_actions:
        add_options(
            group,
            ("--example", EXAMPLE_NAMES, None, "read the embedded example catalogue instead of a "
             "file (100 FEMA P695 components; --component picks one, such as MUL009)"),
            action=Once,
        )  # fmt: skip
    add_fields(group, RecordReadOptions, action=Once)


#: Embedded example catalogues that ``--example`` names.
EXAMPLE_NAMES = ("fema-p695",)


def read_record_file(path: str | None, args: argparse.Namespace) -> Stream:
    """Read ``path`` with the record options in ``args``, or the embedded example catalogue
    (``--example fema-p695``; ``--component`` picks one of its components, such as MUL009);
    an ``obspy.Stream`` in m/s²."""
    example = getattr(args, "example", None)
    if example is not None:
        if path is not None:
            raise InputError(f"a record file and --example {example}, expected one of them")
        from stepframe.records.examples import example_stream

        return example_stream(example, args.component)
    if path is None:
        raise InputError("no record file, expected a record file or --example fema-p695")
    from stepframe.records import read

    return read(path, **record_options(args))


def record_paths(paths: list[str], args: argparse.Namespace) -> list[str | None]:
    """The files of a command that takes several, or ``[None]`` (the example) with --example."""
    if getattr(args, "example", None) is not None and not paths:
        return [None]
    if not paths:
        raise InputError("no record file, expected record files or --example fema-p695")
    return list(paths)


def record_options(args: argparse.Namespace) -> dict[str, Any]:
    """The record options in ``args`` as keyword arguments of :func:`stepframe.records.read`."""
    return RecordReadOptions(**fields_given(args, RecordReadOptions)).read_kwargs()


def check_plot(path: str | None) -> None:
    """Refuse a ``--plot`` path before any work: a figure suffix, an existing folder."""
    if path is not None:
        from stepframe.pipeline.figures import check_figure_path

        check_figure_path(path)


def save_plot(
    result: CommandResult, path: str | None, figure: Callable[[], Any], line: str | None = "plot"
) -> CommandResult:
    """Draw ``figure()`` to ``path`` (when given); the result gains ``plot`` and, unless ``line``
    is None, the text line ``<line> written to <path>``."""
    if path is None:
        return result
    from stepframe.pipeline.figures import save_figure

    save_figure(figure(), path)
    data = {**result.data, "plot": path}
    text = result.text if line is None else f"{result.text}\n{line} written to {path}"
    return CommandResult(data, text)


def workflow_result(
    run: Callable[[], Any], text: Callable[[Any], str], as_json: bool
) -> CommandResult:
    """The result of a workflow run, ``run()`` (with ``exit_code`` and ``to_dict()``), and its
    ``text``; exit 3 after one error line when another run holds the workspace, and when an
    output could not be produced print the result and exit with the run's code (1)."""
    from stepframe.pipeline.lock import WorkspaceBusy

    try:
        done = run()
    except WorkspaceBusy as busy:
        print(f"stepframe: error: {busy}", file=sys.stderr)
        raise SystemExit(3) from None
    result = CommandResult(done.to_dict(), text(done))
    if done.exit_code != 0:
        data = json.dumps(to_jsonable(result.data), indent=2, allow_nan=False)
        print(data if as_json else result.text)
        raise SystemExit(done.exit_code)
    return result


#: The command groups: name → (help, the modules whose ``register(subparsers)`` add its
#: commands). Modules are named, not imported, so building the table needs none of them (they
#: import this package for :func:`add_command`); :func:`group_modules` imports them.
GROUPS: dict[str, tuple[str, tuple[str, ...]]] = {
    "records": (
        "read accelerograms, intensity measures, spectra, catalogues",
        ("stepframe.commands.records",),
    ),
    "stochastic": (
        "evolutionary spectra, ground-motion model, mean square, amplification",
        ("stepframe.commands.stochastic_fit", "stepframe.commands.stochastic_amplify"),
    ),
    "structure": (
        "frame parameters, quasi-dynamic design, stepping simulation",
        (
            "stepframe.commands.structure_design",
            "stepframe.commands.structure_simulate",
            "stepframe.commands.structure_dynamics",
        ),
    ),
}


def group_modules(name: str) -> list[ModuleType]:
    """The modules of group ``name``, each with ``register(subparsers)``."""
    import importlib

    return [importlib.import_module(module) for module in GROUPS[name][1]]
