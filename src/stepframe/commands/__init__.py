"""Shared machinery of the command groups: parser class, results, JSON, the record options.

Each command module (listed per group in :data:`GROUPS`) has ``register(subparsers)``, which adds
its commands with :func:`add_command`. A command parses its options, calls one library function
(mostly a :mod:`stepframe.pipeline` stage) and returns a :class:`CommandResult`;
:mod:`stepframe.cli` prints it. Command modules import only argparse and light name modules at
module level: the heavy imports happen inside ``run``.
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from types import ModuleType
from typing import TYPE_CHECKING, Any, NoReturn

from stepframe.errors import InputError
from stepframe.records.formats import format_names_help

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


def to_jsonable(value: Any) -> Any:
    """Convert numpy scalars/arrays, tuples and paths to JSON types; NaN and ±inf become None."""
    if isinstance(value, Mapping):
        return {str(k): to_jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [to_jsonable(v) for v in value]
    if hasattr(value, "tolist") and not isinstance(value, str):
        return to_jsonable(value.tolist())
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if value is None or isinstance(value, bool | int | str):
        return value
    return str(value)


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


FORMAT_NAMES_HELP = format_names_help()


def add_record_options(parser: argparse.ArgumentParser) -> None:
    """The record options every command that reads a record takes (DESIGN.md, Command line)."""
    group = parser.add_argument_group("record options")
    group.add_argument(
        "--format", metavar="NAME", help=f"file format ({FORMAT_NAMES_HELP}); default: sniffed"
    )
    group.add_argument(
        "--units",
        metavar="UNIT",
        help="units of the values if the file does not say: g, m/s2, cm/s2 (= gal), mm/s2",
    )
    group.add_argument(
        "--dt-s", type=float, metavar="DT", help="sampling interval [s] if the file does not say"
    )
    group.add_argument("--inventory", metavar="XML", help="StationXML file for response removal")
    group.add_argument("--component", metavar="NAME", help="which channel of a multi-channel file")


def add_t0_option(parser: argparse.ArgumentParser | argparse._ArgumentGroup, help: str) -> None:
    """``--t0 start|p-pick``: the time origin of eqs. 6.10-6.11 (default the record start)."""
    parser.add_argument("--t0", choices=("start", "p-pick"), default="start", help=help)


def read_record_file(path: str, args: argparse.Namespace) -> Stream:
    """Read ``path`` with the record options in ``args``; an ``obspy.Stream`` in m/s²."""
    from stepframe.records import read

    return read(path, **record_options(args))


def record_options(args: argparse.Namespace) -> dict[str, Any]:
    """The record options in ``args`` as keyword arguments of :func:`stepframe.records.read`."""
    return {
        "format": args.format,
        "units": args.units,
        "dt": args.dt_s,
        "inventory": args.inventory,
        "component": args.component,
    }


def _finite_float(text: str, accept: Callable[[float], bool], refused: str, expected: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number, expected {expected}") from None
    if not (math.isfinite(value) and accept(value)):
        raise argparse.ArgumentTypeError(f"{text!r}{refused}, expected {expected}")
    return value


def positive_float(text: str) -> float:
    """argparse type: a finite number > 0."""
    return _finite_float(text, lambda v: v > 0, " is not positive", "a positive number")


def non_negative_seconds(text: str) -> float:
    """argparse type: a finite duration ≥ 0 [s]."""
    return _finite_float(text, lambda v: v >= 0, "", "seconds ≥ 0")


def float_list(text: str) -> list[float]:
    """argparse type: comma-separated numbers (``0.01,0.2,1.0``)."""
    try:
        return [float(word) for word in text.split(",") if word.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}, expected comma-separated numbers") from None


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


__all__ = [
    "GROUPS",
    "CommandResult",
    "InputError",
    "Parser",
    "UserError",
    "add_command",
    "add_record_options",
    "add_t0_option",
    "float_list",
    "group_modules",
    "non_negative_seconds",
    "positive_float",
    "read_record_file",
    "record_options",
    "to_jsonable",
]
