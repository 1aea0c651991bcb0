"""CSMIP/DMG strong-motion files (format name ``dmg``): V1 (uncorrected) and V2 (corrected).

A file holds one or more channels, each ending with a ``/&`` line. Each channel has a text header
(13 lines in V1, 25 in V2), an integer and a real header, then the data. The readers use the text
header only, whose wording CSMIP has kept stable:

- V1: ``31932 Accelerogram points at 100 pts/sec in units of g.  Format: (8f9.6)``, and
  ``Max = .344 g, at 234.360 sec.``;
- V2: ``7500 points of accel data equally spaced at .010 sec, in cm/sec2. (8f10.6)``, then the
  velocity and displacement blocks (not read: acceleration only), and
  ``Peak acceleration = 27.114 cm/sec/sec``.

Station (``Station No. 58667`` / ``Station Id. CLC``), channel orientation (``Chan 1: 90 Deg``) and
start time (``Start time: 7/06/19, 03:16: 8.0 UTC``) come from the text header too.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import TYPE_CHECKING, Any

from stepframe.errors import FormatError
from stepframe.records.formats import ReadOptions, RecordFormat, _header, register
from stepframe.records.formats._text import (
    check_count,
    check_peak,
    fortran_width,
    numbers,
    read_lines,
    resolution_of,
    resolve_units,
    warn,
)
from stepframe.records.units import factor_to_m_s2

if TYPE_CHECKING:
    from obspy import Stream, UTCDateTime

_FIRST_LINE = re.compile(r"^\s*(Uncorrected|Corrected)\s+Accelerogram", re.I)
_V1_DATA = re.compile(
    r"^\s*(\d+)\s+Accelerogram\s+points\s+at\s+(\S+)\s+pts/sec\s+in\s+units\s+of\s+(\S+?)\.?\s",
    re.I,
)
_V2_DATA = re.compile(
    r"^\s*(\d+)\s+points\s+of\s+(accel|veloc|displ)\w*\s+data\s+equally\s+spaced\s+at\s+(\S+)"
    r"\s+sec,\s+in\s+(\S+?)\.?\s",
    re.I,
)
_V1_PEAK = re.compile(r"\bMax\s*=\s*(-?[\d.]+)\s*([A-Za-z/0-9]+)")
_V2_PEAK = re.compile(r"Peak\s+acceleration\s*=\s*(-?[\d.]+)\s+(\S+)", re.I)
_STATION = re.compile(r"Station\s+(?:No\.|Id\.)\s*(\S+)", re.I)
_CHANNEL = re.compile(r"^\s*Chan\s+(\d+):\s*(.*?)\s*$", re.I)
_START = re.compile(
    r"Start\s+time:\s*(\d+)/(\d+)/(\d+),\s*(\d+):\s*(\d+):\s*([\d.]+)\s*(\w*)", re.I
)
_END = re.compile(r"^/&")
_N_CHANNELS = re.compile(r"\(\s*(\d+)\s+Chns\s+of\s+\d+\s+at\s+Sta\s*\)", re.I)


def sniff(head: bytes, path: Path) -> bool:
    """True for a CSMIP accelerogram header: first line, ``Station No./Id.`` and ``Chan n:``."""
    try:
        text = head.decode("latin-1")
        lines = text.splitlines()
        return (
            bool(lines)
            and bool(_FIRST_LINE.search(lines[0]))
            and bool(_STATION.search(text))
            and any(_CHANNEL.match(x) for x in lines)
        )
    except Exception:  # a sniffer never raises
        return False


def _start_time(header: list[str], first: int, path: Path) -> UTCDateTime:
    for offset, line in enumerate(header):
        if match := _START.search(line):
            month, day, year, hour, minute = (int(match[k]) for k in range(1, 6))
            if year < 100:
                # CSMIP two-digit years: digital records start in the 1970s.
                year += 1900 if year >= 70 else 2000
            text = match[0].split(":", 1)[-1].strip()
            parts = (year, month, day, hour, minute)
            return _header.start_time(parts, match[6], path, first + offset + 1, text)
    return None


def _channel(
    lines: list[str], start: int, stop: int, index: int, options: ReadOptions, path: Path
) -> Any:
    """One trace from the channel in ``lines[start:stop]`` (0-based, ``stop`` at its ``/&``)."""
    from stepframe.records.trace import make_trace

    data_line = None
    for i in range(start, stop):
        match = _V1_DATA.search(lines[i]) or _V2_DATA.search(lines[i])
        if match is not None:
            data_line, data_match = i, match
            break
    if data_line is None:
        raise FormatError(
            "channel has no acceleration data line, expected '<n> Accelerogram points at ...' "
            "(V1) or '<n> points of accel data ...' (V2)",
            path,
            start + 1,
        )
    header = lines[start:data_line]
    number = data_line + 1
    npts = _header.sample_count(data_match[1], path, number, "number of points")
    if data_match.re is _V1_DATA:
        rate_hz = _header.number(
            data_match[2], path, number, "sampling rate", low=1.0, kind="positive number"
        )
        dt_s = _header.interval(1.0 / rate_hz, path, number)
        stated_units = data_match[3]
    else:
        dt_s = _header.interval(data_match[3], path, number)
        stated_units = data_match[4]
    units = resolve_units(stated_units, options.units, path, data_line + 1)
    values, _ = numbers(
        lines, data_line + 1, path, count=npts, width=fortran_width(lines[data_line])
    )
    check_count(values, npts, path, data_line + 1)
    data_m_s2 = values * factor_to_m_s2(units)
    station = orientation = ""
    for offset, line in enumerate(header):
        if not station and (match := _STATION.search(line)):
            station = match[1]
        if not orientation and (match := _CHANNEL.match(line)):
            orientation = re.sub(r"\s*deg\b", "", match[2], flags=re.I).strip()
        peak = _V1_PEAK.search(line) if data_match.re is _V1_DATA else _V2_PEAK.search(line)
        if peak is not None:
            try:
                factor = factor_to_m_s2(peak[2].rstrip(",."))
            except Exception:
                warn(
                    f"peak units {peak[2]!r} not known, peak not checked", path, start + offset + 1
                )
            else:
                stated_peak = _header.number(peak[1], path, start + offset + 1, "peak")
                check_peak(
                    data_m_s2,
                    stated_peak * factor,
                    path,
                    f"channel {orientation or index + 1}",
                    resolution=resolution_of(peak[1]) * factor,
                    line=start + offset + 1,
                )
    return make_trace(
        data_m_s2,
        dt_s,
        station=station,
        channel=orientation or str(index + 1),
        starttime=_start_time(header, start, path),
        source_file=str(path),
        format="dmg",
        units_in=units,
    )


def read(path: Path, options: ReadOptions) -> Stream:
    """Read a CSMIP/DMG V1 or V2 file: one trace per channel (acceleration), in m/s².

    Raises
    ------
    FormatError
        A channel without an acceleration data line, a count disagreeing with the data,
        non-numeric values or an unknown unit (each naming the line).
    """
    from obspy import Stream

    lines = read_lines(path, "CSMIP/DMG")
    traces: list[Any] = []
    start = 0
    while start < len(lines):
        if not lines[start].strip():
            start += 1
            continue
        stop = start
        while stop < len(lines) and not _END.match(lines[stop]):
            stop += 1
        traces.append(_channel(lines, start, stop, len(traces), options, path))
        start = stop + 1
    if not traces:
        raise FormatError("no channel in the file, expected CSMIP/DMG V1 or V2 text", path)
    _check_channel_count(lines, len(traces), path)
    return Stream(traces)


def _check_channel_count(lines: list[str], found: int, path: Path) -> None:
    """Refuse a file holding fewer channels than its header declares (cut at a channel end)."""
    for number, line in enumerate(lines[:40], start=1):
        if match := _N_CHANNELS.search(line):
            declared = int(match[1])
            if found < declared:
                raise FormatError(
                    f"{found} channel(s) in the file but the header declares {declared} "
                    "(truncated file?), expected all of them",
                    path,
                    number,
                )
            return


FORMAT = register(
    RecordFormat(name="dmg", sniff=sniff, read=read, extensions=(".v1", ".v2", ".V1", ".V2"))
)
