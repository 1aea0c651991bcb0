"""PEER NGA AT2 files (format name ``at2``), both header styles.

Four header lines, then the values, usually five to a line::

    PEER NGA STRONG MOTION DATABASE RECORD
    14383980, 7/29/2008, Anaheim - Lakeview & Riverdale, 90
    ACCELERATION TIME SERIES IN UNITS OF G
    NPTS=  16396, DT=   0.005 SEC

The older NGA style writes line 2 as ``IMPERIAL VALLEY 10/15/79 2316, EL CENTRO ARRAY #6, 230``
and line 4 as ``  3930    0.0100    NPTS, DT``. Line 2 is event (NGA-West2: the event id, then the
date), station and component, comma separated; line 3 names the quantity and its units (g when
unstated). Velocity (VT2) and displacement (DT2) files are refused: they are not acceleration.
"""

from __future__ import annotations

import datetime as dt
import re
from pathlib import Path
from typing import TYPE_CHECKING

from stepframe.errors import FormatError
from stepframe.records.formats import ReadOptions, RecordFormat, _header, register
from stepframe.records.formats._text import check_samples, numbers, read_lines, resolve_units, warn
from stepframe.records.units import factor_to_m_s2

if TYPE_CHECKING:
    from obspy import Stream

_NEW_STYLE = re.compile(r"NPTS\s*=\s*([^,\s]*)\s*,?\s*DT\s*=\s*([^\s,]*?)\s*(?:SEC\b|,|\s|$)", re.I)
_OLD_STYLE = re.compile(r"^\s*(\S+)\s+(\S+)\s+NPTS\s*,\s*DT\b", re.I)
_QUANTITY = re.compile(
    r"^\s*(ACCELERATION|VELOCITY|DISPLACEMENT)\b.*?(?:UNITS\s+OF\s+(.+?))?\s*$", re.I
)
_DATE = re.compile(r"(\d{1,2})/(\d{1,2})/(\d{2,4})")
_DATE_LIKE = re.compile(r"[^\s,]+/[^\s,]+/[^\s,]+")
_RSN_IN_NAME = re.compile(r"RSN(\d+)", re.I)
#: The header is at most this many lines; the NPTS/DT line ends it.
_MAX_HEADER = 6


def sniff(head: bytes, path: Path) -> bool:
    """True if one of the first lines is an AT2 ``NPTS, DT`` line (either style), or if the
    header is PEER's (line 3 ``ACCELERATION TIME SERIES ...``, line 4 naming NPTS) with an
    NPTS line the reader refuses by line and cause (no DT, say) rather than leaving the file
    unrecognised."""
    try:
        lines = head.decode("latin-1").splitlines()[:_MAX_HEADER]
        if not lines or lines[0].lstrip().startswith("#"):
            return False
        if any(_NEW_STYLE.search(x) or _OLD_STYLE.search(x) for x in lines):
            return True
        return (
            len(lines) > 3
            and _QUANTITY.match(lines[2]) is not None
            and "TIME SERIES" in lines[2].upper()
            and "NPTS" in lines[3].upper()
        )
    except Exception:  # a sniffer never raises
        return False


def _npts_dt(lines: list[str], path: Path) -> tuple[int, float, int]:
    """(NPTS, DT [s], 0-based index of the NPTS/DT line)."""
    for index, line in enumerate(lines[:_MAX_HEADER]):
        if "NPTS" not in line.upper():
            continue
        match = _NEW_STYLE.search(line) or _OLD_STYLE.search(line)
        if match is None or not match[2]:
            raise FormatError(
                f"NPTS line {line.strip()!r} has no DT, expected 'NPTS= n, DT= dt SEC'",
                path,
                index + 1,
            )
        try:
            float(match[1]), float(match[2])
        except ValueError:
            raise FormatError(
                f"NPTS/DT {match[1]!r}/{match[2]!r} are not numbers, "
                "expected an integer count and an interval in seconds",
                path,
                index + 1,
            ) from None
        npts = _header.sample_count(match[1], path, index + 1, "NPTS")
        dt_s = _header.interval(match[2], path, index + 1, "DT")
        return npts, dt_s, index
    raise FormatError(
        f"no NPTS/DT line in the first {_MAX_HEADER} lines, expected 'NPTS= n, DT= dt SEC' "
        "or 'n dt NPTS, DT'",
        path,
    )


def _identity(line: str) -> tuple[str, str, str, str | None]:
    """(event, station, component, date text) from header line 2."""
    fields = [f.strip() for f in line.split(",")]
    if len(fields) < 3:
        return line.strip(), "", "", None
    component, station = fields[-1], fields[-2]
    event_fields = fields[:-2]
    date: str | None = None
    for field in event_fields:
        if match := _DATE_LIKE.search(field):
            date = match[0]
            break
    # NGA-West2 puts the date in a field of its own; drop it from the event name.
    event = ", ".join(f for f in event_fields if f != date)
    return event, station, component, date


def _event_date(date: str | None, path: Path) -> str | None:
    """The event date as ISO ``YYYY-MM-DD``, or None with a warning if it is not a real date."""
    if date is None:
        return None
    match = _DATE.fullmatch(date)
    try:
        if match is None:
            raise ValueError(date)
        month, day, year = int(match[1]), int(match[2]), int(match[3])
        if year < 100:
            # NGA-era two-digit years: strong-motion records start in 1933, so 33-99 are 19xx.
            year += 1900 if year >= 33 else 2000
        return dt.date(year, month, day).isoformat()
    except ValueError:
        warn(f"bad date {date!r} in the header, expected month/day/year; date left out", path, 2)
        return None


def read(path: Path, options: ReadOptions) -> Stream:
    """Read an AT2 file as a one-trace ``obspy.Stream`` in m/s².

    Raises
    ------
    FormatError
        Missing or non-numeric NPTS/DT, non-numeric values, a value count other than NPTS
        (fewer only with ``allow_short``, flagged), a velocity or displacement file, or an
        unknown unit (each naming the line).
    """
    from obspy import Stream

    from stepframe.records.trace import make_trace

    lines = read_lines(path, "PEER AT2", allow_short=options.allow_short)
    npts, dt_s, npts_line = _npts_dt(lines, path)
    stated_units: str | None = None
    units_line: int | None = None
    for index, line in enumerate(lines[:npts_line]):
        if match := _QUANTITY.match(line):
            if match[1].upper() != "ACCELERATION":
                raise FormatError(
                    f"{match[1].lower()} time series, expected acceleration (AT2)",
                    path,
                    index + 1,
                )
            stated_units, units_line = match[2], index + 1
            break
    if stated_units is None and units_line is None:
        stated_units = "g"  # PEER's AT2 definition: acceleration in g.
    units = resolve_units(stated_units, options.units, path, units_line)
    event, station, component, date = _identity(lines[1]) if npts_line >= 2 else ("", "", "", None)
    values, _ = numbers(lines, npts_line + 1, path)
    incomplete = check_samples(values.size, npts, path, npts_line + 1, options)
    rsn_match = _RSN_IN_NAME.search(path.name)
    trace = make_trace(
        values * factor_to_m_s2(units),
        dt_s,
        station=station,
        channel=component,
        source_file=str(path),
        format="at2",
        units_in=units,
        event=event,
        event_date=_event_date(date, path),
        rsn=int(rsn_match[1]) if rsn_match else None,
        incomplete=incomplete,
    )
    return Stream([trace])


FORMAT = register(RecordFormat(name="at2", sniff=sniff, read=read, extensions=(".at2", ".AT2")))
