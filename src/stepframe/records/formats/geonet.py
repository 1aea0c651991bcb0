"""GeoNet (GNS Science, New Zealand) V1A and V2A files (format name ``geonet``).

A file holds one block per component: 16 text lines, 40 integers (``10I8``, 4 lines), 60 reals
(``10F8``, 6 lines), then the acceleration values in ``10F8`` fields and, in V2A files, the velocity
and displacement blocks (not read: acceleration only). Integers 34-36 (1-based) give the numbers
of acceleration, velocity and displacement values; integers 1-6 the start date and time (the
seconds times ten) of the unprocessed record; real 22 the seconds of padding V2A processing adds
before it (the header's peak times agree with the data only with that pad). Text lines used::

    Site WPWS      39 56 38S  176 35 04E ...
    Epicentre  40 03 27S 176 32 45E  Bearing S15W  Dist   13km  Depth    9km M  4.17
    Raw readings in units of 1.00 mm/s/s  at intervals of 0.005 s          (V1A)
    Instrument corrected data at 0.020 sec intervals                        (V2A)
    Component S16W  Longitudinal Accelerometer Axis
    Acceleration:  peak    -41.6 mm/s/s at  43.68 sec ...
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from stepframe.errors import FormatError
from stepframe.records.formats import ReadOptions, RecordFormat, _header, register
from stepframe.records.formats._text import (
    check_block_end,
    check_components,
    check_count,
    check_peak,
    check_samples,
    file_cut,
    mark_incomplete,
    numbers,
    read_lines,
    resolution_of,
    resolve_units,
)
from stepframe.records.units import factor_to_m_s2

if TYPE_CHECKING:
    from obspy import Stream, UTCDateTime

_FIRST_LINE = re.compile(r"^\s*(Uncorrected|Corrected)\s+accelerogram", re.I)
_SITE = re.compile(r"^\s*Site\s+(\S+)")
_INTERVAL = re.compile(r"(?:intervals\s+of\s+|data\s+at\s+)(\S+)\s*s", re.I)
_RAW_UNITS = re.compile(r"units\s+of\s+(\S+)\s+(\S+)", re.I)
_COMPONENT = re.compile(r"^\s*Component\s+(\S+)", re.I)
_PEAK = re.compile(r"^\s*Acceleration:\s*peak\s+(-?[\d.]+)\s+(\S+)", re.I)
_EPICENTRE = re.compile(r"Dist\s+(\d+(?:\.\d+)?)\s*km.*?\bM\w?\s+(\d+(?:\.\d+)?)", re.I)
_N_TEXT, _N_INT, _N_REAL, _WIDTH = 16, 40, 60, 8
#: Lines of a component's heading: text, 40 integers (4 lines of 10), 60 reals (6 lines).
_N_HEADING_LINES = _N_TEXT + 4 + 6
#: "Each accelerogram data file contains heading data and accelerations for three orthogonal
#: component directions" (GeoNet, Strong Motion File Formats).
N_COMPONENTS = 3


def sniff(head: bytes, path: Path) -> bool:
    """True for a GeoNet text header: accelerogram line, ``Site`` line, ``Component`` line."""
    try:
        lines = head.decode("latin-1").splitlines()
        return (
            len(lines) >= 13
            and bool(_FIRST_LINE.search(lines[0]))
            and bool(_SITE.match(lines[1]))
            and any(_COMPONENT.match(x) for x in lines[:16])
        )
    except Exception:  # a sniffer never raises
        return False


def _start_time(ints: list[int], path: Path, line: int) -> UTCDateTime:
    year, month, day, hour, minute, tenths = ints[:6]
    text = f"{year}-{month}-{day} {hour}:{minute}"
    return _header.start_time((year, month, day, hour, minute), tenths / 10.0, path, line, text)


def _component(
    lines: list[str], start: int, options: ReadOptions, path: Path
) -> tuple[Any, int] | None:
    """The trace of the block starting at ``lines[start]`` and the index after the block;
    None when the file ends inside the block's heading (a component lost to a cut)."""
    from stepframe.records.trace import make_trace

    if len(lines) - start < _N_HEADING_LINES:
        return None
    text = lines[start : start + _N_TEXT]
    if len(text) < _N_TEXT or not _FIRST_LINE.search(text[0]):
        raise FormatError(
            "component block does not start with a 16-line GeoNet text header, "
            "expected '... accelerogram ...'",
            path,
            start + 1,
        )
    ints_f, i = numbers(lines, start + _N_TEXT, path, count=_N_INT, width=_WIDTH)
    check_count(ints_f, _N_INT, path, start + _N_TEXT + 1)
    reals_line = i + 1
    reals, i = numbers(lines, i, path, count=_N_REAL, width=_WIDTH)
    check_count(reals, _N_REAL, path, reals_line)
    int_line = start + _N_TEXT + 1
    ints = [_header.small_integer(v, path, int_line, "integer header value") for v in ints_f]
    if not np.all(np.isfinite(reals)):
        raise FormatError("real header value not finite, expected finite numbers", path, i)
    n_acc, n_vel, n_dis = ints[33:36]
    if n_vel < 0 or n_dis < 0:
        raise FormatError(
            f"velocity/displacement counts {n_vel}/{n_dis}, expected counts ≥ 0", path, int_line
        )
    dt_s: float | None = None
    stated: str | None = None
    scale = 1.0
    channel = station = ""
    peak_match = None
    epicentre = None
    for offset, line in enumerate(text):
        number = start + offset + 1
        if (match := _INTERVAL.search(line)) and dt_s is None:
            dt_s = _header.interval(match[1], path, number)
            if raw := _RAW_UNITS.search(line):
                scale = _header.number(raw[1], path, number, "unit scale", low=1e-12, high=1e12)
                stated = raw[2]
        if match := _COMPONENT.match(line):
            channel = match[1]
        if match := _SITE.match(line):
            station = match[1]
        if match := _PEAK.match(line):
            peak_match, peak_line = match, number
            stated = stated or match[2]
        if match := _EPICENTRE.search(line):
            epicentre = match
    if dt_s is None:
        raise FormatError(
            "no sampling interval in the text header, expected 'at intervals of <dt> s' or "
            "'data at <dt> sec intervals'",
            path,
            start + 11,
        )
    units = resolve_units(stated, options.units, path, start + 11)
    count_line = int_line + 3  # integers 31-40
    what = "integer 34 (acceleration samples)"
    n_acc = _header.sample_count(n_acc, path, count_line, what)
    values, end = numbers(lines, i, path, count=n_acc, width=_WIDTH)
    incomplete = check_samples(values.size, n_acc, path, count_line, options, what)
    data_m_s2 = values * scale * factor_to_m_s2(units)
    if peak_match is not None and incomplete is None:
        check_peak(
            values * scale,
            _header.number(peak_match[1], path, peak_line, "peak acceleration") * scale,
            path,
            f"component {channel}",
            units=units,
            resolution=resolution_of(peak_match[1]) * scale,
            line=peak_line,
        )
    # Velocity and displacement blocks of V2A files follow (10F8 too): not read, but counted,
    # so that a file cut inside them or holding more values than declared is known.
    declared, last = n_acc, what
    for name, number, count in (("velocity", 35, n_vel), ("displacement", 36, n_dis)):
        if incomplete is not None or count == 0:
            continue
        block, end = numbers(lines, end, path, count=count, width=_WIDTH)
        declared, last = count, f"integer {number} ({name} samples)"
        if block.size < count:
            where = f"in the {name} block of component {channel} ({block.size} of {count} values)"
            incomplete = file_cut(where, path, count_line, options, "the whole component")
    if incomplete is None:
        check_block_end(
            lines,
            end,
            declared,
            path,
            width=_WIDTH,
            what=last,
            expected="the next component's heading",
        )
    start_time = _start_time(ints, path, start + _N_TEXT + 1)
    if start_time is not None and reals.size > 21 and reals[21] > 0:
        # V2A processing pads the front; real 22 is the pad [s]: the header's peak times (from
        # the V1A origin) match the data only once it is subtracted (checked on real files).
        start_time -= _header.number(reals[21], path, i, "front pad [s]", high=1e6)
    trace = make_trace(
        data_m_s2,
        dt_s,
        network="NZ",
        station=station,
        channel=channel,
        starttime=start_time,
        source_file=str(path),
        format="geonet",
        units_in=units,
        event=text[6].strip(),
        magnitude=_header.number(epicentre[2], path, None, "magnitude") if epicentre else None,
        repi_km=_header.number(epicentre[1], path, None, "distance") if epicentre else None,
        incomplete=incomplete,
    )
    return trace, end


def read(path: Path, options: ReadOptions) -> Stream:
    """Read a GeoNet V1A/V2A file: one trace per component, in m/s².

    Raises
    ------
    FormatError
        A block that does not follow the layout, a count disagreeing with the data (fewer
        samples without ``allow_short``, or more), a file without its three components (without
        ``allow_short``), non-numeric values or an unknown unit (each naming the line).
    """
    from obspy import Stream

    lines = read_lines(path, "GeoNet V1A/V2A", allow_short=options.allow_short)
    traces = []
    i = 0
    while i < len(lines):
        if not lines[i].strip():
            i += 1
            continue
        block = _component(lines, i, options, path)
        if block is None:  # the file ends inside this component's heading
            break
        trace, i = block
        traces.append(trace)
        if trace.stats.stepframe.incomplete is not None:
            break  # the file was cut inside this component
    if not traces:
        raise FormatError(
            "the file ends inside the first component's heading, expected "
            f"{_N_HEADING_LINES} heading lines and data",
            path,
            len(lines),
        )
    note = check_components(
        len(traces), N_COMPONENTS, path, None, options, source="a GeoNet file holds three"
    )
    mark_incomplete(traces, note)
    return Stream(traces)


FORMAT = register(RecordFormat(name="geonet", sniff=sniff, read=read, extensions=(".V1A", ".V2A")))
