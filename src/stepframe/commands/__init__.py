"""Shared machinery of the command groups: parser class, results, JSON, the record options.

Each command module (listed per group in :data:`GROUPS`) has ``register(subparsers)``, which adds
its commands with :func:`add_command`. A command parses its options, calls one library function
(mostly a :mod:`stepframe.pipeline` stage) and returns a :class:`CommandResult`;
:mod:`stepframe.cli` prints it. Command modules import only argparse and light name modules at
module level: the heavy imports happen inside ``run``.
"""

from __future__ import annotations

import argparse
import functools
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from types import ModuleType
from typing import TYPE_CHECKING, Any, NoReturn

# Re-exported: commands print results through it (stepframe.core.jsonable is its home).
from stepframe.core.jsonable import to_jsonable as to_jsonable
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
    """The record options every command that reads a record takes (DESIGN.md, Command line);
    each refuses to be given twice (:class:`Once`)."""
    group = parser.add_argument_group("record options")
    if "--example" not in parser._option_string_actions:
        add_options(
            group,
            ("--example", EXAMPLE_NAMES, None, "read the embedded example catalogue instead of a "
             "file (100 FEMA P695 components; --component picks one, such as MUL009)"),
            action=Once,
        )  # fmt: skip
    add_options(
        group,
        ("--format", None, "NAME", f"file format ({FORMAT_NAMES_HELP}); default: sniffed"),
        ("--units", None, "UNIT", "units of the values if the file does not say: g, m/s2, "
         "cm/s2 (= gal), mm/s2"),
        ("--dt-s", float, "DT", "sampling interval [s] if the file does not say"),
        ("--inventory", None, "XML", "StationXML file for response removal"),
        ("--component", None, "NAME", "which channel of a multi-channel file"),
        ("--max-abs-g", positive_float, "G", "refuse a record whose peak exceeds G [g] "
         "(default 100: wrong units or damage)"),
        ("--max-file-mb", positive_float, "MB", "refuse a record file larger than MB [MiB] "
         "(default 256)"),
        action=Once,
    )  # fmt: skip


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
    options: dict[str, Any] = {
        "format": args.format,
        "units": args.units,
        "dt": args.dt_s,
        "inventory": args.inventory,
        "component": args.component,
    }
    # The read limits only when given: read(max_abs_g=None) would turn the peak check off.
    max_abs_g = getattr(args, "max_abs_g", None)
    if max_abs_g is not None:
        options["max_abs_g"] = float(max_abs_g)
    max_file_mb = getattr(args, "max_file_mb", None)
    if max_file_mb is not None:
        options["max_bytes"] = max(1, int(max_file_mb * 1024**2))
    return options


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


def non_negative_float(text: str) -> float:
    """argparse type: a finite number ≥ 0."""
    return _finite_float(text, lambda v: v >= 0, "", "a finite number ≥ 0")


def positive_int(text: str) -> int:
    """argparse type: an integer ≥ 1."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not an integer, expected ≥ 1") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"{text!r}, expected an integer ≥ 1")
    return value


def float_list(text: str) -> list[float]:
    """argparse type: comma-separated numbers (``0.01,0.2,1.0``)."""
    try:
        return [float(word) for word in text.split(",") if word.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}, expected comma-separated numbers") from None


def positive_floats(text: str) -> list[float]:
    """argparse type: comma-separated positive numbers, at least one (``10.6,16``)."""
    values = float_list(text)
    if not values or not all(math.isfinite(v) and v > 0 for v in values):
        raise argparse.ArgumentTypeError(f"{text!r}, expected positive numbers")
    return values


def float_range(text: str) -> tuple[float, float, int]:
    """argparse type: ``LO,HI,N``, N values from LO to HI with 0 ≤ LO ≤ HI and N ≥ 1."""
    parts = text.split(",")
    try:
        lo, hi, n = float(parts[0]), float(parts[1]), int(parts[2])
    except (ValueError, IndexError):
        raise argparse.ArgumentTypeError(
            f"{text!r}, expected LO,HI,N (e.g. 0.05,0.5,200)"
        ) from None
    if len(parts) != 3 or not (0 <= lo <= hi and math.isfinite(hi) and n >= 1):
        raise argparse.ArgumentTypeError(f"{text!r}, expected 0 ≤ LO ≤ HI and N ≥ 1")
    return lo, hi, n


def check_plot(path: str | None) -> None:
    """Refuse a ``--plot`` path before any work: a figure suffix, an existing folder."""
    if path is not None:
        from stepframe.pipeline.figures import check_figure_path

        check_figure_path(path)


#: The default of an option row that is required.
REQUIRED = object()

#: An option row: (flag, type, metavar, help) or (flag, type, metavar, help, default). The flag
#: is one string or a tuple (``("-o", "--out")``); the type is an argparse type function, a
#: tuple of choices, ``bool`` (a flag: store_true), ``list`` (repeatable: append) or None
#: (text); the default :data:`REQUIRED` makes the option required.
OptionRow = tuple[Any, ...]


def add_options(
    parser: argparse.ArgumentParser | argparse._ArgumentGroup,
    *rows: OptionRow,
    action: type[argparse.Action] | None = None,
) -> None:
    """Add one option per row (see :data:`OptionRow`): a compact table of a command's options.

    ``action`` (such as :class:`Once`) stores the values of the rows that take one.
    """
    for flag, kind, metavar, help, *rest in rows:
        _add_option(parser, flag, kind, metavar, help, rest[0] if rest else None, action=action)


def _add_option(
    parser: argparse.ArgumentParser | argparse._ArgumentGroup,
    flag: str | tuple[str, ...],
    kind: Any,
    metavar: str | None,
    help: str | None,
    default: Any,
    *,
    action: type[argparse.Action] | None = None,
    dest: str | None = None,
) -> None:
    options: dict[str, Any] = {"help": help}
    if action is not None and kind not in (bool, list):
        options["action"] = action
    if default is REQUIRED:
        options["required"] = True
    elif default is not None:
        options["default"] = default
    if kind is bool:
        options["action"] = "store_true"
    elif kind is list:
        options.update(action="append", default=[])
    elif isinstance(kind, tuple):
        options["choices"] = kind
    elif kind is not None:
        options["type"] = kind
    if metavar is not None:
        options["metavar"] = metavar
    if dest is not None:
        options["dest"] = dest
    parser.add_argument(*((flag,) if isinstance(flag, str) else flag), **options)


#: argparse types of the value kinds of :func:`stepframe.core.options.option`.
KIND_TYPES: dict[str, Any] = {
    "float": float,
    "int": int,
    "text": None,
    "flag": bool,
    "positive": positive_float,
    "non_negative": non_negative_float,
    "non_negative_seconds": non_negative_seconds,
    "positive_int": positive_int,
    "floats": float_list,
    "positive_floats": positive_floats,
    "range": float_range,
}

#: A row of :func:`add_fields`: (type, metavar, help), each None to take the field's
#: (:func:`stepframe.core.options.option` metadata, else its annotation: a ``Literal`` gives
#: the choices, ``bool`` a flag). A key that starts with ``-`` is an option that is not a field
#: (an :data:`OptionRow` without the flag).
FieldRow = tuple[Any, str | None, str | None]


def add_fields(
    parser: argparse.ArgumentParser | argparse._ArgumentGroup,
    cls: type,
    rows: Mapping[str, FieldRow] | Sequence[str] | None = None,
    *,
    action: type[argparse.Action] | None = None,
) -> None:
    """One option ``--field-name`` per field of the dataclass ``cls`` (those of ``rows``, in
    their order, when given: field names, or a :data:`FieldRow` per name), stored by
    ``action`` when given (such as :class:`Once`).

    A field without a default is a required option; the others default to None (a flag to
    False), so that :func:`fields_given` returns only what the command line gave, to lay over
    a file's values or the dataclass's defaults.
    """
    import dataclasses

    fields = {f.name: f for f in dataclasses.fields(cls)}
    if rows is None or not isinstance(rows, Mapping):
        rows = dict.fromkeys(rows or fields, (None, None, None))
    for name, (kind, metavar, help) in rows.items():
        if name.startswith("-"):
            _add_option(parser, name, kind, metavar, help, None)
            continue
        f = fields[name]
        meta = f.metadata
        plain = help is None  # the metadata's help is plain text: its % are literal
        help = help or meta.get("help")
        required = f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING
        if help is not None:
            help = help.replace("%(default)s", str(f.default))
            help = help.replace("%", "%%") if plain else help
        flag = meta.get("flag") or "--" + name.replace("_", "-")
        kind = kind or _field_kind(cls, f)
        metavar = metavar or meta.get("metavar")
        default = REQUIRED if required else None
        _add_option(parser, flag, kind, metavar, help, default, dest=name, action=action)


def _field_kind(cls: type, f: Any) -> Any:
    """The argparse type (or choices, or bool) of a field: its metadata, else its annotation."""
    import types
    import typing

    meta = f.metadata
    if meta.get("choices") is not None:
        return tuple(meta["choices"])
    if meta.get("kind") is not None:
        return KIND_TYPES[meta["kind"]]
    hint = _type_hints(cls).get(f.name)
    if hint is None:  # names imported for type checking only: read the annotation's text
        text = str(f.type).removesuffix(" | None")
        return {"float": float, "int": int, "bool": bool}.get(text)
    if isinstance(hint, types.UnionType):  # X | None: the option gives an X
        hint = next(arg for arg in typing.get_args(hint) if arg is not type(None))
    if typing.get_origin(hint) is typing.Literal:
        return typing.get_args(hint)
    return hint if hint in (bool, int, float) else None


@functools.cache
def _type_hints(cls: type) -> dict[str, Any]:
    """The resolved annotations of ``cls`` (once per class: resolving costs), or {} when one
    names a type imported for type checking only."""
    import typing

    try:
        return typing.get_type_hints(cls)
    except NameError:
        return {}


def fields_given(args: argparse.Namespace, names: Any) -> dict[str, Any]:
    """The values of the :func:`add_fields` options ``names`` (a dataclass, or field names) that
    the command line gave (a flag: set)."""
    import dataclasses

    if dataclasses.is_dataclass(names):
        names = [f.name for f in dataclasses.fields(names)]
    values = {name: getattr(args, name, None) for name in names if not name.startswith("-")}
    return {
        name: value for name, value in values.items() if value is not None and value is not False
    }


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
