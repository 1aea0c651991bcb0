"""Registry of record formats: one small module per format, each with a sniffer and a reader.

A format module defines a :class:`RecordFormat` and registers it with :func:`register`. The
sniffer looks at the first bytes of a file and never raises; the reader raises
:class:`stepframe.errors.FormatError` naming the file and line. :func:`stepframe.records.read`
picks the reader by name or by sniffing, in registration order.
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
    """

    units: str | None = None
    dt_s: float | None = None
    inventory: str | None = None
    component: str | None = None


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


FORMATS: dict[str, RecordFormat] = {}


def register(fmt: RecordFormat) -> RecordFormat:
    """Add a format to the registry (later registrations of the same name replace earlier)."""
    FORMATS[fmt.name] = fmt
    return fmt


#: Built-in format modules in sniffing order: most specific sniffers first.
_BUILTIN_MODULES = (
    "fema",
    "cosmos",
    "geonet",
    "dmg",
    "esm",
    "at2",
    "obspy_formats",
    "text",
)


def _load_builtin_formats() -> None:
    # Imported for their registration side effect, in the order of _BUILTIN_MODULES.
    from importlib import import_module

    for name in _BUILTIN_MODULES:
        import_module(f"stepframe.records.formats.{name}")


_load_builtin_formats()
