"""``read``: one entry point for every record format (found through the format registry).

A gzip-compressed file (``RSN1.AT2.gz``; data centres often ship them) is read as the file it
holds: it is decompressed to a temporary file with the inner name, and ``source_file`` names the
``.gz``. Units are never guessed: a reader that cannot tell them refuses with a message saying how
to give them.
"""

from __future__ import annotations

import gzip
import shutil
import tempfile
import warnings
from os import PathLike
from pathlib import Path
from typing import Any

from stepframe.errors import InputError
from stepframe.records.formats import FORMATS, SNIFF_BYTES, ReadOptions, RecordFormat
from stepframe.records.units import normalize_units

_GZIP_MAGIC = b"\x1f\x8b"


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
        The file (optionally gzip-compressed).
    format
        A format name (``"at2"``, ``"cosmos"``, ``"dmg"``, ``"geonet"``, ``"esm"``, ``"text"``,
        ``"fema"``, or any obspy waveform format in lower case such as ``"mseed"``, ``"sac"``,
        ``"knet"``); None sniffs the file.
    units
        Units of the values when the file does not state them (``"g"``, ``"m/s2"``,
        ``"cm/s2"``/``"gal"``, ``"mm/s2"``). A file that states units different from these is
        refused.
    dt
        Sampling interval [s] when the file does not state it.
    inventory
        StationXML file for response removal (formats in counts).
    component
        Keep only this channel of a multi-channel file.

    Returns
    -------
    obspy.Stream
        One trace per acceleration channel, data in m/s², metadata in ``stats.stepframe``
        (``units_in`` the file's units; ``processing`` any step the format's definition requires).

    Raises
    ------
    InputError
        Missing file, unknown format, units that cannot be determined, or a file that does not
        follow its format (one line naming the file and line).
    """
    file = Path(path)
    if not file.exists():
        raise InputError("no such file, expected an existing record file", file)
    if file.is_dir():
        raise InputError("is a directory, expected a record file", file)
    if dt is not None and not dt > 0:
        raise InputError(f"dt = {dt} s, expected a positive sampling interval")
    options = ReadOptions(
        units=None if units is None else normalize_units(units),
        dt_s=dt,
        inventory=None if inventory is None else str(inventory),
        component=component,
    )
    if options.inventory is not None and not Path(options.inventory).is_file():
        raise InputError("no such inventory file, expected a StationXML file", options.inventory)
    with file.open("rb") as handle:
        head = handle.read(SNIFF_BYTES)
    if head.startswith(_GZIP_MAGIC):
        stream = _read_gzip(file, format, options)
    else:
        stream = _read_plain(file, head, format, options)
    _check_agreement(stream, options, file)
    if component is not None:
        stream = stream.select(channel=component)
        if len(stream) == 0:
            raise InputError(
                f"no channel {component!r} in the file, expected an existing one", file
            )
    return stream


def _read_plain(file: Path, head: bytes, format: str | None, options: ReadOptions) -> Any:
    if not head:
        raise InputError("empty file, expected an accelerogram", file)
    fmt = _by_name(format, file) if format is not None else _sniff(head, file)
    return fmt.read(file, options)


def _read_gzip(file: Path, format: str | None, options: ReadOptions) -> Any:
    inner = file.name[:-3] if file.name.lower().endswith(".gz") else file.name + ".data"
    with tempfile.TemporaryDirectory(prefix="stepframe-") as folder:
        plain = Path(folder) / inner
        try:
            with gzip.open(file, "rb") as source, plain.open("wb") as target:
                shutil.copyfileobj(source, target)
        except (OSError, EOFError) as exc:
            raise InputError(f"corrupt gzip file ({exc}), expected a whole .gz", file) from None
        with plain.open("rb") as handle:
            head = handle.read(SNIFF_BYTES)
        # Messages must name the user's file, not the temporary one.
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                stream = _read_plain(plain, head, format, options)
            except InputError as exc:
                raise type(exc)(
                    exc.what, file if exc.path == str(plain) else exc.path, exc.line
                ) from None
        for warning in caught:
            message = str(warning.message).replace(str(plain), str(file))
            warnings.warn(message, warning.category, stacklevel=3)
    for trace in stream:
        trace.stats.stepframe.source_file = str(file)
    return stream


def _by_name(format: str, file: Path) -> RecordFormat:
    name = format.lower()
    if name in FORMATS:
        return FORMATS[name]
    from stepframe.records.formats.obspy_formats import obspy_format_names, read_with_obspy

    if name in obspy_format_names():
        return RecordFormat(
            name, lambda head, path: False, lambda p, o: read_with_obspy(p, o, name)
        )
    raise InputError(
        f"unknown format {format!r}, expected one of {', '.join(FORMATS)} "
        "or another obspy waveform format in lower case"
    )


def _sniff(head: bytes, file: Path) -> RecordFormat:
    for fmt in FORMATS.values():
        if fmt.sniff(head, file):
            return fmt
    raise InputError(
        "format not recognised, expected AT2, COSMOS, CSMIP/DMG, GeoNet, ESM, FEMA P695 text, "
        "plain text or an obspy waveform format (give it with --format)",
        file,
    )


def _check_agreement(stream: Any, options: ReadOptions, file: Path) -> None:
    """Refuse ``units``/``dt`` options that contradict what the file states.

    Readers use the options only where the file is silent; an option the file contradicts is a
    user error, never silently ignored.
    """
    for trace in stream:
        stated_units = trace.stats.stepframe.units_in
        if options.units is not None and stated_units != options.units:
            raise InputError(
                f"file states units {stated_units!r} but --units {options.units!r} was given, "
                "expected them to agree (omit --units)",
                file,
            )
        delta = float(trace.stats.delta)
        if options.dt_s is not None and abs(delta - options.dt_s) > 1e-9 * delta:
            raise InputError(
                f"file states dt = {delta:g} s but --dt-s {options.dt_s:g} was given, "
                "expected them to agree (omit --dt-s)",
                file,
            )
