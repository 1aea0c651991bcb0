"""Options, declared once: dataclass fields that carry their help, and their argparse rendering.

A library function that takes many choices takes a frozen dataclass of them; each field is
declared with :func:`option`, which puts its help (with units), metavar and value kind in the
field's metadata. The command line derives its ``--field-name`` options from those fields
(:func:`add_fields`) and reads back what was given (:func:`fields_given`), so the name, default,
help and validation of an option are written once, next to the code that uses it. Options that
are not fields of a library input (``-o``, ``--plot``) are rows of :func:`add_options`.

Value kinds (``kind``) name how a command-line word becomes the value: ``float``, ``int``,
``text``, ``flag`` (a switch), ``positive`` (a number > 0), ``non_negative`` (≥ 0),
``non_negative_seconds``, ``positive_int``, ``floats`` (comma-separated numbers),
``positive_floats``, ``range`` (``LO,HI,N``), ``repeated`` (text, the option given once per
value: a list); ``choices`` lists the accepted names. The argparse
value types of the kinds (:func:`positive_float`, ...) live here too. Standard library only, so
``stepframe --help`` stays fast.
"""

from __future__ import annotations

import argparse
import functools
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import MISSING, dataclass, field
from typing import Any, TypeVar

T = TypeVar("T")

#: The value kinds :func:`option` accepts.
KINDS = (
    "float",
    "int",
    "text",
    "flag",
    "positive",
    "non_negative",
    "non_negative_seconds",
    "positive_int",
    "floats",
    "positive_floats",
    "range",
    "repeated",
)


@dataclass(frozen=True)
class Range:
    """The values a numeric option accepts: finite, between ``low`` and ``high`` (either end open
    or closed, or absent), or one of ``also``.

    ``Range(0, 1, low_open=True, high_open=True)`` is a damping fraction in (0, 1);
    ``Range(2, also=(0,))`` is "0, or at least 2".
    """

    low: float | None = None
    high: float | None = None
    low_open: bool = False
    high_open: bool = False
    also: tuple[float, ...] = ()

    def contains(self, value: float) -> bool:
        """Whether ``value`` is accepted (NaN and infinities never are, nor an integer past
        the float range)."""
        if value in self.also:
            return True
        try:
            if not math.isfinite(value):
                return False
        except OverflowError:  # an integer of hundreds of digits
            return False
        if self.low is not None and (value <= self.low if self.low_open else value < self.low):
            return False
        return not (
            self.high is not None and (value >= self.high if self.high_open else value > self.high)
        )

    def describe(self) -> str:
        """The accepted values in words: ``in (0, 1)``, ``≥ 100``, ``0 or ≥ 2``."""
        if self.low is not None and self.high is not None:
            text = (
                f"in {'(' if self.low_open else '['}{_number(self.low)}, {_number(self.high)}"
                f"{')' if self.high_open else ']'}"
            )
        elif self.low is not None:
            text = f"{'>' if self.low_open else '≥'} {_number(self.low)}"
        elif self.high is not None:
            text = f"{'<' if self.high_open else '≤'} {_number(self.high)}"
        else:
            text = "a finite number"
        return " or ".join([*(_number(value) for value in self.also), text])


def _number(value: float) -> str:
    """A bound in words: integers and whole numbers below 10⁸ in full (``1000000``, a seed's
    ``18446744073709551615``), others as ``%g``."""
    if isinstance(value, int):
        return str(value)
    if float(value).is_integer() and abs(value) < 1e8:
        return str(int(value))
    return f"{value:g}"


#: The seeds of random generators: numpy's take any integer ≥ 0; a seed is written into result
#: files and TOML, so it is kept within 64 bits (:data:`stepframe.core.validation.MAX_SEED`).
SEEDS = Range(0, 2**64 - 1)
#: Worker processes a run may start (far above any machine's cores).
JOBS = Range(1, 1024)

#: Most points of a ``LO,HI,N`` option (kind ``range``): each is a run or an oscillator.
MAX_RANGE_POINTS = 100_000
#: Most values of a list option (kinds ``floats``, ``positive_floats``).
MAX_LIST_VALUES = 10_000


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _shown(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def check_fields(instance: Any) -> None:
    """Check every field of a dataclass ``instance`` declared with a ``valid`` range, and the
    type of every other field whose plain type is ``bool``, ``int`` or ``float``
    (:func:`value_type`: a switch is true or false, never a string).

    A field whose value is None passes when None is its default (not given). A list field
    (kinds ``floats``, ``positive_floats``) is checked value by value, with at most
    :data:`MAX_LIST_VALUES` values; a ``LO,HI,N`` field (kind ``range``) has LO and HI in the
    range, LO ≤ HI, and 1 ≤ N ≤ :data:`MAX_RANGE_POINTS`.

    Raises
    ------
    InputError
        ``name = value, expected <range>`` (or ``true or false``, ``a number``, ``an
        integer``) with ``key`` = the field's name.
    """
    import dataclasses

    from stepframe.errors import InputError

    for f in dataclasses.fields(instance):
        value = getattr(instance, f.name)
        if value is None and f.default is None:
            continue
        valid = f.metadata.get("valid")
        if valid is None:
            problem = _type_problem(type(instance), f, value)
        else:
            problem = _field_problem(f.metadata.get("kind"), value, valid)
        if problem is not None:
            raise InputError(f"{f.name} = {_shown(value)}, expected {problem}", key=f.name)


def _type_problem(cls: type, f: Any, value: Any) -> str | None:
    """What a field of plain type ``bool``, ``int`` or ``float`` (its kind, else its annotation:
    :func:`value_type`) expects when ``value`` is not of it, or None: a field needs no ``valid``
    range to refuse a string where a switch belongs (``confirm = "false"`` is a true string)."""
    import numbers

    kind = _field_kind(cls, f)
    if kind is bool:
        return None if isinstance(value, bool) else "true or false"
    if isinstance(value, bool):  # a bool is an int to Python, never a number here
        ok = False
    elif kind in (int, positive_int):
        ok = isinstance(value, numbers.Integral)
    elif kind in (float, positive_float, non_negative_float, non_negative_seconds):
        ok = isinstance(value, numbers.Real)
    else:
        return None
    if ok:
        return None
    return "an integer" if kind in (int, positive_int) else "a number"


def accepted(kind: str | None, valid: Range) -> str:
    """The values a field of ``kind`` checked by ``valid`` accepts, in words (the end of the
    message of :func:`check_fields`, and the ranges table of docs/cli.md)."""
    if kind == "range":
        return f"LO,HI,N with LO ≤ HI each {valid.describe()} and N in [1, {MAX_RANGE_POINTS}]"
    if kind in ("floats", "positive_floats"):
        return f"1 to {MAX_LIST_VALUES} values, each {valid.describe()}"
    return valid.describe()


def _field_problem(kind: str | None, value: Any, valid: Range) -> str | None:
    """What is wrong with ``value`` of a field of ``kind`` checked by ``valid``, or None."""
    if kind == "range":
        ok = (
            isinstance(value, (list, tuple))
            and len(value) == 3
            and all(_is_number(v) and valid.contains(v) for v in value[:2])
            and value[0] <= value[1]
            and isinstance(value[2], int)
            and 1 <= value[2] <= MAX_RANGE_POINTS
        )
    elif kind in ("floats", "positive_floats"):
        ok = (
            isinstance(value, (list, tuple))
            and 0 < len(value) <= MAX_LIST_VALUES
            and all(_is_number(v) and valid.contains(v) for v in value)
        )
    else:
        ok = _is_number(value) and valid.contains(value)
    return None if ok else accepted(kind, valid)


def option(
    default: Any = MISSING,
    help: str | None = None,
    *,
    kind: str | None = None,
    metavar: str | None = None,
    choices: tuple[str, ...] | None = None,
    flag: str | None = None,
    valid: Range | None = None,
) -> Any:
    """A dataclass field with its option metadata (no default: a required option).

    Parameters
    ----------
    default
        The field's default.
    help
        What the option is, with its unit; ``%(default)s`` is replaced by the default.
    kind
        One of :data:`KINDS` (default: from the field's type).
    metavar
        The value's name in the help (``F``, ``FRAME.toml``).
    choices
        The accepted names.
    flag
        The option's flag when it is not ``--field-name``.
    valid
        The values accepted (:class:`Range`), checked by :func:`check_fields` (which the
        dataclass's ``__post_init__`` calls): one check for the command line, the library and
        the workflow.
    """
    if kind is not None and kind not in KINDS:
        raise ValueError(f"option kind {kind!r}, expected one of {KINDS}")
    metadata = {
        "help": help,
        "kind": kind,
        "metavar": metavar,
        "choices": choices,
        "flag": flag,
        "valid": valid,
    }
    if default is MISSING:
        return field(metadata=metadata)
    return field(default=default, metadata=metadata)


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
    """argparse type: comma-separated numbers (``0.01,0.2,1.0``); an empty item is refused."""
    words = text.split(",")
    for index, word in enumerate(words, start=1):
        if not word.strip():
            raise argparse.ArgumentTypeError(
                f"{text!r}: item {index} of {len(words)} is empty, expected comma-separated numbers"
            )
    try:
        return [float(word) for word in words]
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
            # argparse turns this into parser.error(message): one line, exit 2 on the CLI.
            message = f"{option_string} given twice, expected it once (one value per option)"
            raise argparse.ArgumentError(None, message)
        given.add(self.dest)
        setattr(namespace, self.dest, values)


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
    "repeated": list,
}


def add_fields(
    parser: argparse.ArgumentParser | argparse._ArgumentGroup,
    cls: type,
    names: Sequence[str | OptionRow] | None = None,
    *,
    action: type[argparse.Action] | None = None,
) -> None:
    """One option ``--field-name`` per field of the dataclass ``cls`` (those of ``names``, in
    their order, when given), stored by ``action`` when given (such as
    :class:`Once`); an :data:`OptionRow` among the names adds an option
    that is not a field at its place in the help.

    The help, metavar, flag and value kind come from the field's :func:`option` metadata (the
    kind, when not given, from its annotation: a ``Literal`` gives the choices, ``bool`` a
    flag); ``%(default)s`` in the help is the field's default. A field without a default is a
    required option; the others default to None (a flag to False), so that
    :func:`fields_given` returns only what the command line gave, to lay over a file's values
    or the dataclass's defaults.
    """
    import dataclasses

    fields = {f.name: f for f in dataclasses.fields(cls)}
    for name in fields if names is None else names:
        if not isinstance(name, str):
            add_options(parser, name)
            continue
        f = fields[name]
        meta = f.metadata
        help = meta.get("help")
        if help is not None:  # plain text: its % are literal
            help = help.replace("%(default)s", str(f.default)).replace("%", "%%")
        required = f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING
        flag = meta.get("flag") or "--" + name.replace("_", "-")
        default = REQUIRED if required else None
        kind = _field_kind(cls, f)
        metavar = meta.get("metavar")
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


def value_type(cls: type, name: str) -> str:
    """The plain type of field ``name`` of the dataclass ``cls`` as a file gives it: ``float``,
    ``int``, ``bool`` or ``str`` (a workflow table's key, say)."""
    import dataclasses

    f = next(f for f in dataclasses.fields(cls) if f.name == name)
    kind = _field_kind(cls, f)
    if kind is bool:
        return "bool"
    if kind in (int, positive_int):
        return "int"
    if kind in (float, positive_float, non_negative_float, non_negative_seconds):
        return "float"
    return "str"


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
    """The values of the :func:`add_fields` options ``names`` (a dataclass, or the ``names`` of
    :func:`add_fields`, whose option rows are skipped) that the command line gave (a flag:
    set)."""
    import dataclasses

    if dataclasses.is_dataclass(names):
        names = [f.name for f in dataclasses.fields(names)]
    values = {name: getattr(args, name, None) for name in names if isinstance(name, str)}
    return {
        name: value for name, value in values.items() if value is not None and value is not False
    }


def arguments_of(options: Any) -> dict[str, Any]:
    """The command-line options that give the dataclass ``options``: flag (without ``--``) →
    value, for each field that is not None; a switch appears (value True) only when set, a
    switch set by default not at all. For the command line that reproduces a result."""
    import dataclasses

    out: dict[str, Any] = {}
    for f in dataclasses.fields(options):
        value = getattr(options, f.name)
        if value is None or (isinstance(value, bool) and value == f.default):
            continue
        flag = f.metadata.get("flag") or "--" + f.name.replace("_", "-")
        out[flag.removeprefix("--").replace("-", "_")] = value
    return out


def options_from(args: argparse.Namespace, cls: type[T]) -> T:
    """The dataclass ``cls`` built from the :func:`add_fields` options the command line gave
    (its defaults for the others).

    Raises
    ------
    InputError
        A value its field's check refuses, named by its flag: ``--xi0 0.0, expected in (0, 1)``
        (the same check, and words, as a workflow file's ``xi0 = 0.0``).
    """
    import dataclasses

    from stepframe.errors import InputError

    try:
        return cls(**fields_given(args, cls))
    except InputError as error:
        fields = {f.name: f for f in dataclasses.fields(cls)}  # type: ignore[arg-type]
        if error.key not in fields or not error.what.startswith(f"{error.key} = "):
            raise
        flags = {
            name: f.metadata.get("flag") or "--" + name.replace("_", "-")
            for name, f in fields.items()
        }
        raise InputError(by_flags(error.what, flags)) from None


def by_flags(what: str, flags: Mapping[str, str]) -> str:
    """``what`` with every ``name = value`` of a key of ``flags`` written as ``--flag value``: a
    command-line error names each option it mentions by its flag ("--seed 5 with --monte-carlo
    0", not "--seed 5 with monte_carlo = 0")."""
    import re

    if not flags:
        return what
    names = "|".join(sorted(map(re.escape, flags), key=len, reverse=True))
    return re.sub(rf"\b({names}) = ", lambda match: flags[match.group(1)] + " ", what)


__all__ = [
    "JOBS",
    "KINDS",
    "KIND_TYPES",
    "MAX_LIST_VALUES",
    "MAX_RANGE_POINTS",
    "REQUIRED",
    "SEEDS",
    "Once",
    "OptionRow",
    "Range",
    "accepted",
    "add_fields",
    "add_options",
    "arguments_of",
    "by_flags",
    "check_fields",
    "fields_given",
    "float_list",
    "float_range",
    "non_negative_float",
    "non_negative_seconds",
    "option",
    "options_from",
    "positive_float",
    "positive_floats",
    "positive_int",
    "value_type",
]
