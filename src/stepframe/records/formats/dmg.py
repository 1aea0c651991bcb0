"""CSMIP/DMG strong-motion files (format name ``dmg``): V1 (uncorrected) and V2 (corrected).

A file holds one or more channels, each ending with a ``/&`` line. Each channel has a text header
(13 lines in V1, 25 in V2), an integer and a real header, then the data. The readers use the text
header only, whose wording CSMIP has kept stable:

- V1: ``31932 Accelerogram points at 100 pts/sec in units of g.  Format: (8f9.6)``, and
  ``Max = .344 g, at 234.360 sec.``;
- V2: ``7500 points of accel data equally spaced at .010 sec, in cm/sec2. (8f10.6)`` (older
  CDMG files: ``3251 POINTS OF ACCEL DATA EQUALLY SPACED AT .020 SEC. (UNITS: CM/SEC/SEC)``,
  upper case; the Fortran format may be missing), then the velocity and displacement blocks
  (counted, not read: acceleration only), and ``Peak acceleration = 27.114 cm/sec/sec``.

Station (``Station No. 58667`` / ``Station Id. CLC``), channel orientation (``Chan 1: 90 Deg``) and
start time (``Start time: 7/06/19, 03:16: 8.0 UTC``; older files ``TRIGGER TIME: 05/02/83,
16:42:48.2 PDT``, converted from Pacific time) come from the text header too.

Complete or refused: every channel ends with its ``/&`` line, every block holds the points it
declares (fewer only with ``allow_short``, flagged), and the file holds the channels its
header declares (``(3 Chns of 3 at Sta)``). Other CSMIP products are refused by name: V3
response spectra, and digitised film records (``.RAW``: time and acceleration pairs at
uneven times).
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

from stepframe.errors import FormatError
from stepframe.records.formats import ReadOptions, RecordFormat, _header, register
from stepframe.records.formats._text import (
    check_block_end,
    check_components,
    check_peak,
    check_samples,
    file_cut,
    fortran_width,
    mark_incomplete,
    numbers,
    read_lines,
    resolution_of,
    resolve_units,
    warn,
)
from stepframe.records.units import factor_to_m_s2, normalize_units

if TYPE_CHECKING:
    from obspy import Stream, UTCDateTime

_FIRST_LINE = re.compile(r"^\s*(Uncorrected|Corrected)\s+Accelerogram", re.I)
_V3_FIRST_LINE = re.compile(r"^\s*Response\s+and\s+Fourier\s+amplitude\s+spectra", re.I)
_FILM_PAIRS = re.compile(r"UNITS\s+OF\s+UNCOR\s+ACCEL\s+ARE\s+SEC\s+AND", re.I)
_UNIT_END = r"(\S+?)\.?(?=\s|$)"
_V1_DATA = re.compile(
    r"^\s*(\d+)\s+Accelerogram\s+points\s+at\s+(\S+)\s+pts/sec\s+in\s+units\s+of\s+" + _UNIT_END,
    re.I,
)
_V2_DATA = re.compile(
    r"^\s*(\d+)\s+points\s+of\s+(accel|veloc|displ)\w*\s+data\s+equally\s+spaced\s+at\s+(\S+)"
    r"\s+sec\b[,.]?\s*(?:in\s+" + _UNIT_END + r"|\(\s*units:\s*([^)\s]+)\s*\))",
    re.I,
)
_V1_PEAK = re.compile(r"\bMax\s*=\s*(-?[\d.]+)\s*([A-Za-z/0-9]+)")
_V2_PEAK = re.compile(r"Peak\s+acceleration\s*=\s*(-?[\d.]+)\s+(\S+)", re.I)
_STATION = re.compile(r"Station\s+(?:No\.|Id\.)\s*(\S+)", re.I)
_CHANNEL = re.compile(r"^\s*Chan\s+(\d+):\s*(.*?)\s*$", re.I)
_START = re.compile(
    r"(?:Start|Trigger)\s+time:\s*(\d+)[/-](\d+)[/-](\d+),\s*(\d+):\s*(\d+):\s*([\d.]+)\s*(\w*)",
    re.I,
)
#: Hours to add to a start time written in these zones to get UTC (US Pacific time).
_ZONE_TO_UTC_H = {"": 0, "UTC": 0, "GMT": 0, "PST": 8, "PDT": 7}
_END = re.compile(r"^/&")
#: Field widths of CSMIP data blocks when a file omits the Fortran format: V1 (8f9.6) and
#: V2 (8f10.6, 8f10.7), keyed by "is V1"; fields touch where values are long.
_DEFAULT_WIDTH = {True: 9, False: 10}
_N_CHANNELS = re.compile(r"\(\s*(\d+)\s+Chns\s+of\s+\d+\s+at\s+Sta\s*\)", re.I)


def sniff(head: bytes, path: Path) -> bool:
    """True for a CSMIP accelerogram header: first line, ``Station No./Id.`` and ``Chan n:``."""
    try:
        text = head.decode("latin-1")
        lines = text.splitlines()
        return (
            bool(lines)
            and bool(_FIRST_LINE.search(lines[0]) or _V3_FIRST_LINE.search(lines[0]))
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
            zone = match[7].upper()
            if zone not in _ZONE_TO_UTC_H:
                warn(
                    f"start time {text!r} in zone {zone!r}, expected UTC; start time left at 0",
                    path,
                    first + offset + 1,
                )
                return None
            parts = (year, month, day, hour, minute)
            start = _header.start_time(parts, match[6], path, first + offset + 1, text)
            if start is None:
                return None
            return cast("UTCDateTime", start) + 3600.0 * _ZONE_TO_UTC_H[zone]
    return None


def _channel(
    lines: list[str],
    start: int,
    stop: int,
    index: int,
    options: ReadOptions,
    path: Path,
) -> Any:
    """One trace from the channel in ``lines[start:stop]`` (0-based; ``stop`` at its ``/&``, or
    the end of a file cut inside the channel), or None when the file ends before its data."""
    from stepframe.records.trace import make_trace

    terminated = stop < len(lines)
    data_line = None
    for i in range(start, stop):
        match = _V1_DATA.search(lines[i]) or _V2_DATA.search(lines[i])
        if match is not None and (match.re is _V1_DATA or match[2].lower() == "accel"):
            data_line, data_match = i, match
            break
    if data_line is None:
        if not terminated:
            return None
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
        stated_units = data_match[4] or data_match[5]
    units = resolve_units(stated_units, options.units, path, data_line + 1)
    width = fortran_width(lines[data_line]) or _DEFAULT_WIDTH[data_match.re is _V1_DATA]
    values, end = numbers(lines, data_line + 1, path, count=npts, width=width)
    incomplete = check_samples(values.size, npts, path, number, options)
    orientation = next(
        (
            re.sub(r"\s*deg\b", "", match[2], flags=re.I).strip()
            for line in header
            if (match := _CHANNEL.match(line))
        ),
        "",
    )
    name = orientation or str(index + 1)
    if incomplete is None:
        incomplete = _later_blocks(lines, end, stop, npts, width, name, options, path)
    data_m_s2 = values * factor_to_m_s2(units)
    station = ""
    for offset, line in enumerate(header):
        if not station and (match := _STATION.search(line)):
            station = match[1]
        peak = _V1_PEAK.search(line) if data_match.re is _V1_DATA else _V2_PEAK.search(line)
        if peak is not None and values.size == npts:
            try:
                peak_units = normalize_units(peak[2].rstrip(",."))
            except Exception:
                warn(
                    f"peak units {peak[2]!r} not known, peak not checked", path, start + offset + 1
                )
            else:
                stated_peak = _header.number(peak[1], path, start + offset + 1, "peak")
                check_peak(
                    data_m_s2 / factor_to_m_s2(peak_units),
                    stated_peak,
                    path,
                    f"channel {name}",
                    units=peak_units,
                    resolution=resolution_of(peak[1]),
                    line=start + offset + 1,
                )
    return make_trace(
        data_m_s2,
        dt_s,
        station=station,
        channel=name,
        starttime=_start_time(header, start, path),
        source_file=str(path),
        format="dmg",
        units_in=units,
        incomplete=incomplete,
    )


def _later_blocks(
    lines: list[str],
    index: int,
    stop: int,
    declared: int,
    width: int | None,
    channel: str,
    options: ReadOptions,
    path: Path,
) -> str | None:
    """Check what follows a channel's acceleration up to its ``/&``: V2 velocity and
    displacement blocks each holding the points they declare, no values beyond a block, and
    the ``/&`` itself (a file cut after the acceleration lacks it).

    Returns the incomplete note of a file cut there (read with ``allow_short``), else None.
    """
    while True:
        check_block_end(
            lines,
            index,
            declared,
            path,
            width=width,
            what="the points of its block",
            expected="'/&' or the next block",
        )
        found = next(((k, m) for k in range(index, stop) if (m := _V2_DATA.search(lines[k]))), None)
        if found is None:
            break
        index, match = found
        declared = _header.sample_count(match[1], path, index + 1, "number of points")
        width = fortran_width(lines[index]) or _DEFAULT_WIDTH[False]
        block, index = numbers(lines, index + 1, path, count=declared, width=width)
        if block.size < declared:
            where = f"in the {match[2].lower()} block of channel {channel}"
            return file_cut(where, path, index, options, "the whole channel")
    if stop >= len(lines):
        where = f"before the '/&' line ending channel {channel}"
        return file_cut(where, path, len(lines), options, "the whole channel")
    return None


def _refuse_other_products(lines: list[str], path: Path) -> None:
    """Refuse, by name, the CSMIP products that are not equally spaced accelerograms."""
    if lines and _V3_FIRST_LINE.search(lines[0]):
        raise FormatError(
            "CSMIP V3 response and Fourier spectra, expected a V1 or V2 accelerogram", path, 1
        )
    for number, line in enumerate(lines[:40], start=1):
        if _FILM_PAIRS.search(line):
            raise FormatError(
                "digitised film record ((time, acceleration) pairs at uneven times), expected "
                "an equally spaced V1 or V2 accelerogram (the V2 of the same record)",
                path,
                number,
            )


def read(path: Path, options: ReadOptions) -> Stream:
    """Read a CSMIP/DMG V1 or V2 file: one trace per channel (acceleration), in m/s².

    Raises
    ------
    FormatError
        A channel without an acceleration data line, a count disagreeing with the data (fewer
        points or channels only with ``allow_short``), a channel without its ``/&`` line,
        non-numeric values, an unknown unit, or a V3 or digitised film file (each naming the
        line).
    """
    from obspy import Stream

    lines = read_lines(path, "CSMIP/DMG", allow_short=options.allow_short)
    _refuse_other_products(lines, path)
    traces: list[Any] = []
    start = 0
    while start < len(lines):
        if not lines[start].strip():
            start += 1
            continue
        stop = start
        while stop < len(lines) and not _END.match(lines[stop]):
            stop += 1
        trace = _channel(lines, start, stop, len(traces), options, path)
        if trace is None:  # the file ends inside this channel's header
            if not traces:
                raise FormatError(
                    "the file ends inside the first channel's header, expected its data",
                    path,
                    len(lines),
                )
            break
        traces.append(trace)
        start = stop + 1
    if not traces:
        raise FormatError("no channel in the file, expected CSMIP/DMG V1 or V2 text", path)
    _check_channel_count(lines, traces, path, options)
    return Stream(traces)


def _check_channel_count(
    lines: list[str], traces: list[Any], path: Path, options: ReadOptions
) -> None:
    """Refuse (or, with ``allow_short``, flag) a file holding fewer channels than its header
    declares (a file cut at a channel's end)."""
    for number, line in enumerate(lines[:40], start=1):
        if match := _N_CHANNELS.search(line):
            declared = int(match[1])
            if len(traces) < declared:
                note = check_components(
                    len(traces), declared, path, number, options, what="channels"
                )
                mark_incomplete(traces, note)
            return


FORMAT = register(
    RecordFormat(name="dmg", sniff=sniff, read=read, extensions=(".v1", ".v2", ".V1", ".V2"))
)
