"""Registry of record formats: one small module per format, each with a sniffer and a reader.

A format module defines a :class:`RecordFormat` and registers it with :func:`register`. The
sniffer looks at the first bytes of a file and never raises; the reader raises
:class:`stepframe.errors.FormatError` naming the file and line. :func:`stepframe.records.read`
picks the reader by name or by sniffing, in order of :attr:`RecordFormat.priority` (then
registration): specific formats first, obspy's, then the generic plain-text sniffer last, so a
format registered later (default priority :data:`DEFAULT_PRIORITY`) is tried before the text one.

This module is light (no numpy, no obspy): :data:`BUILTIN_FORMATS` names the built-in formats and
their modules, so the command line's ``--format`` help and the messages list the names without
importing a reader; the reader modules are imported on the first :func:`registered_formats`.

Adding a format: write ``stepframe/records/formats/NAME.py`` with ``sniff`` and ``read`` ending in
``register(RecordFormat(...))``, and add one line to :data:`BUILTIN_FORMATS` (or, outside the
package, import your module and call :func:`register`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

#: How many bytes a sniffer is shown.
SNIFF_BYTES = 4096


@dataclass(frozen=True)
class ReadOptions:
    """The record options of DESIGN.md (Command line), passed to every reader.

    Attributes
    ----------
    units
        Units of the values in the file when the file does not say (``"g"``, ``"m/s2"``,
        ``"cm/s2"``/``"gal"``, ``"mm/s2"``); a reader refuses a file whose units it cannot tell.
    dt_s
        Sampling interval [s] when the file does not say.
    inventory
        Path of a StationXML file for response removal (obspy formats).
    component
        Which channel of a multi-channel file to return (None: all acceleration channels).
    allow_short
        Accept a record cut short (fewer samples than its header declares, or a multi-component
        file missing components) instead of refusing it; each such record is flagged in
        ``stats.stepframe.incomplete`` and a warning says so. More samples than declared are
        refused whatever this says.
    """

    units: str | None = None
    dt_s: float | None = None
    inventory: str | None = None
    component: str | None = None
    allow_short: bool = False


@dataclass(frozen=True)
class RecordFormat:
    """A record format: its name, a sniffer that never raises, and a reader.

    Attributes
    ----------
    name
        The ``--format`` name (lower case).
    sniff
        ``sniff(head: bytes, path: Path) -> bool``: does the file look like this format? Must not
        raise.
    read
        ``read(path: Path, options: ReadOptions) -> obspy.Stream`` in m/s².
    extensions
        Usual file-name endings, for documentation and for ordering candidates.
    """

    name: str
    sniff: Callable[[bytes, Path], bool]
    read: Callable[[Path, ReadOptions], Any]
    extensions: tuple[str, ...] = field(default=())


#: Sniffing priority of specific formats (lower is tried first).
SPECIFIC_PRIORITY = 10
#: Priority of a format registered without one: after the built-in specific formats, before
#: obspy's formats and the generic text sniffer.
DEFAULT_PRIORITY = 50
#: Priority of obspy's formats (their checks read more than the head, so they come late).
OBSPY_PRIORITY = 80
#: Priority of the generic plain-text format (accepts any column of numbers: tried last).
GENERIC_PRIORITY = 100


@dataclass(frozen=True)
class BuiltinFormat:
    """A built-in format named without importing its reader.

    Attributes
    ----------
    module
        The module that registers it (imported on first use).
    label
        Its name for people (messages, help).
    priority
        Sniffing priority (lower first).
    """

    module: str
    label: str
    priority: int


#: The built-in formats, ``{name: reader module}``, in sniffing order. ``obspy`` stands for the
#: obspy waveform formats (mseed, sac, knet, ...), registered by one module.
BUILTIN_FORMATS: dict[str, BuiltinFormat] = {
    "fema": BuiltinFormat("stepframe.records.formats.fema", "FEMA P695 text", SPECIFIC_PRIORITY),
    "cosmos": BuiltinFormat("stepframe.records.formats.cosmos", "COSMOS", SPECIFIC_PRIORITY),
    "geonet": BuiltinFormat("stepframe.records.formats.geonet", "GeoNet", SPECIFIC_PRIORITY),
    "dmg": BuiltinFormat("stepframe.records.formats.dmg", "CSMIP/DMG", SPECIFIC_PRIORITY),
    "esm": BuiltinFormat("stepframe.records.formats.esm", "ESM", SPECIFIC_PRIORITY),
    "at2": BuiltinFormat("stepframe.records.formats.at2", "PEER AT2", SPECIFIC_PRIORITY),
    "obspy": BuiltinFormat(
        "stepframe.records.formats.obspy_formats", "obspy waveform formats", OBSPY_PRIORITY
    ),
    "text": BuiltinFormat("stepframe.records.formats.text", "plain text", GENERIC_PRIORITY),
}


def format_names() -> tuple[str, ...]:
    """The ``--format`` names of the stepframe readers, without importing them (light)."""
    return tuple(name for name in BUILTIN_FORMATS if name != "obspy")


def format_names_help() -> str:
    """The ``--format`` choices as help text (light: for ``stepframe --help``)."""
    return ", ".join(format_names()) + ", or an obspy format name in lower case"


def format_labels() -> str:
    """The formats' names for people, for "format not recognised" messages."""
    return ", ".join(entry.label for name, entry in BUILTIN_FORMATS.items() if name != "obspy")


_REGISTERED: dict[str, tuple[int, int, RecordFormat]] = {}
_loaded = False


def register(fmt: RecordFormat, *, priority: int | None = None) -> RecordFormat:
    """Add a format to the registry (a later registration of the same name replaces it).

    Parameters
    ----------
    fmt
        The format.
    priority
        Sniffing priority: lower is tried first. Built-in specific formats use
        :data:`SPECIFIC_PRIORITY`, obspy's :data:`OBSPY_PRIORITY`, plain text
        :data:`GENERIC_PRIORITY`. None: the built-in table's priority for a built-in name, else
        :data:`DEFAULT_PRIORITY` (before obspy's formats and plain text).
    """
    if priority is None:
        entry = BUILTIN_FORMATS.get(fmt.name)
        priority = DEFAULT_PRIORITY if entry is None else entry.priority
    _REGISTERED[fmt.name] = (priority, len(_REGISTERED), fmt)
    return fmt


def registered_formats() -> dict[str, RecordFormat]:
    """Every registered format, ``{name: format}``, in sniffing order (imports the readers)."""
    _load_builtin_formats()
    ordered = sorted(_REGISTERED.values(), key=lambda item: (item[0], item[1]))
    return {fmt.name: fmt for _, _, fmt in ordered}


def _load_builtin_formats() -> None:
    # Imported for their registration side effect; each module registers with its priority.
    global _loaded
    if _loaded:
        return
    _loaded = True
    from importlib import import_module

    for entry in BUILTIN_FORMATS.values():
        import_module(entry.module)


def __getattr__(name: str) -> Any:
    # ``FORMATS`` (the registry in sniffing order) is computed on access, keeping import light.
    if name == "FORMATS":
        return registered_formats()
    raise AttributeError(name)
