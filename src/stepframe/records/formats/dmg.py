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
from typing import Any

from stepframe.errors import FormatError
from stepframe.records.formats import ReadOptions, RecordFormat, register
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


def _start_time(header: list[str], first: int, path: Path) -> Any:
    from obspy import UTCDateTime

    for offset, line in enumerate(header):
        if match := _START.search(line):
            month, day, year, hour, minute = (int(match[k]) for k in range(1, 6))
            if year < 100:
                # CSMIP two-digit years: digital records start in the 1970s.
                year += 1900 if year >= 70 else 2000
            try:
                return UTCDateTime(year, month, day, hour, minute) + float(match[6])
            except (ValueError, TypeError):
                warn(
                    f"bad start time {match[0].split(':', 1)[1].strip()!r}, expected "
                    "month/day/year, hh:mm:ss; start time left at 0",
                    path,
                    first + offset + 1,
                )
                return None
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
    npts = int(data_match[1])
    try:
        if data_match.re is _V1_DATA:
            dt_s = 1.0 / float(data_match[2])
            stated_units = data_match[3]
        else:
            dt_s = float(data_match[3])
            stated_units = data_match[4]
    except (ValueError, ZeroDivisionError):
        raise FormatError(
            f"sampling {data_match[0].strip()!r} not a positive number, expected one",
            path,
            data_line + 1,
        ) from None
    if not dt_s > 0:
        raise FormatError(
            f"sampling interval {dt_s} s, expected a positive one", path, data_line + 1
        )
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
                check_peak(
                    data_m_s2,
                    float(peak[1]) * factor,
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


def read(path: Path, options: ReadOptions) -> Any:
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
    return Stream(traces)


FORMAT = register(
    RecordFormat(name="dmg", sniff=sniff, read=read, extensions=(".v1", ".v2", ".V1", ".V2"))
)
