"""``read``: one entry point for every record format (found through the format registry)."""

from __future__ import annotations

from os import PathLike
from pathlib import Path
from typing import Any

from stepframe.errors import InputError
from stepframe.records.formats import FORMATS, SNIFF_BYTES, ReadOptions
from stepframe.records.units import normalize_units


def read(
    path: str | PathLike[str],
    format: str | None = None,
    units: str | None = None,
    dt: float | None = None,
    inventory: str | PathLike[str] | None = None,
    component: str | None = None,
) -> Any:
    """Read an accelerogram file into an ``obspy.Stream`` of records in m/s².

    Parameters
    ----------
    path
        The file.
    format
        A format name (``"at2"``, ``"fema"``, ...); None sniffs the file.
    units
        Units of the values when the file does not state them (``"g"``, ``"m/s2"``,
        ``"cm/s2"``/``"gal"``, ``"mm/s2"``).
    dt
        Sampling interval [s] when the file does not state it.
    inventory
        StationXML file for response removal (formats in counts).
    component
        Keep only this channel of a multi-channel file.

    Returns
    -------
    obspy.Stream
        One trace per acceleration channel, data in m/s², metadata in ``stats.stepframe``.

    Raises
    ------
    InputError
        Missing file, unknown format, or a file that does not follow its format (one line naming
        the file and line).
    """
    file = Path(path)
    if not file.exists():
        raise InputError("no such file, expected an existing record file", file)
    if file.is_dir():
        raise InputError("is a directory, expected a record file", file)
    options = ReadOptions(
        units=None if units is None else normalize_units(units),
        dt_s=dt,
        inventory=None if inventory is None else str(inventory),
        component=component,
    )
    if format is not None:
        name = format.lower()
        if name not in FORMATS:
            raise InputError(f"unknown format {format!r}, expected one of {', '.join(FORMATS)}")
        fmt = FORMATS[name]
    else:
        with file.open("rb") as handle:
            head = handle.read(SNIFF_BYTES)
        if not head:
            raise InputError("empty file, expected an accelerogram", file)
        matches = [f for f in FORMATS.values() if f.sniff(head, file)]
        if not matches:
            raise InputError(
                "format not recognised, expected one of "
                f"{', '.join(FORMATS)} (give it with --format)",
                file,
            )
        fmt = matches[0]
    stream = fmt.read(file, options)
    if component is not None:
        stream = stream.select(channel=component)
        if len(stream) == 0:
            raise InputError(
                f"no channel {component!r} in the file, expected an existing one", file
            )
    return stream
