"""Options as dataclass fields that carry their own help: one declaration of each option.

A library function that takes many choices takes a frozen dataclass of them; each field is
declared with :func:`option`, which puts its help (with units), metavar and value kind in the
field's metadata. The command line derives its ``--field-name`` options from those fields
(:func:`stepframe.commands.add_fields`), so the name, default, help and validation of an option
are written once, next to the code that uses it.

Value kinds (``kind``) name how a command-line word becomes the value: ``float``, ``int``,
``text``, ``flag`` (a switch), ``positive`` (a number > 0), ``non_negative`` (≥ 0),
``non_negative_seconds``, ``positive_int``, ``floats`` (comma-separated numbers),
``positive_floats``, ``range`` (``LO,HI,N``); ``choices`` lists the accepted names.
"""

from __future__ import annotations

from dataclasses import MISSING, field
from typing import Any

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
)


def option(
    default: Any = MISSING,
    help: str | None = None,
    *,
    kind: str | None = None,
    metavar: str | None = None,
    choices: tuple[str, ...] | None = None,
    flag: str | None = None,
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
    """
    if kind is not None and kind not in KINDS:
        raise ValueError(f"option kind {kind!r}, expected one of {KINDS}")
    metadata = {"help": help, "kind": kind, "metavar": metavar, "choices": choices, "flag": flag}
    if default is MISSING:
        return field(metadata=metadata)
    return field(default=default, metadata=metadata)


__all__ = ["KINDS", "option"]
