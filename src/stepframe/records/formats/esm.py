"""Engineering Strong Motion database (ESM) ASCII files (format name ``esm``).

One component a file: ``KEY: value`` header lines (``NETWORK``, ``STATION_CODE``, ``STREAM``,
``SAMPLING_INTERVAL_S``, ``NDATA``, ``UNITS``, ``DATA_TYPE``, ``PGA_CM/S^2``, ``EVENT_ID``,
``MAGNITUDE_W``/``MAGNITUDE_L``, ``EPICENTRAL_DISTANCE_KM``, ``VS30_M/S``,
``DATE_TIME_FIRST_SAMPLE_YYYYMMDD_HHMMSS``), then one value a line. Velocity and displacement files
(``DATA_TYPE: VELOCITY``...) are refused: not acceleration.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import TYPE_CHECKING

from stepframe.errors import FormatError
from stepframe.records.formats import ReadOptions, RecordFormat, _header, register
from stepframe.records.formats._text import (
    check_count,
    check_peak,
    numbers,
    read_lines,
    resolution_of,
    resolve_units,
    warn,
)
from stepframe.records.units import factor_to_m_s2

if TYPE_CHECKING:
    from obspy import Stream, UTCDateTime

_KEY = re.compile(r"^([A-Z][A-Z0-9_/^.\-]*):\s?(.*?)\s*$")
_REQUIRED = ("SAMPLING_INTERVAL_S", "NDATA")


def sniff(head: bytes, path: Path) -> bool:
    """True if the file starts with ESM ``KEY: value`` lines (``EVENT_NAME``, ``EVENT_ID``)."""
    try:
        text = head.decode("latin-1")
        return text.startswith("EVENT_NAME:") and "\nEVENT_ID:" in text and "\nNETWORK:" in text
    except Exception:  # a sniffer never raises
        return False


def _float(
    header: dict[str, tuple[str, int]],
    key: str,
    path: Path,
    low: float = -1e9,
    high: float = 1e9,
) -> float | None:
    """A numeric header value in [low, high]; None if empty; FormatError naming the line."""
    if key not in header or not header[key][0]:
        return None
    text, line = header[key]
    return _header.number(text, path, line, key, low=low, high=high)


def _start_time(header: dict[str, tuple[str, int]], path: Path) -> UTCDateTime:

    key = "DATE_TIME_FIRST_SAMPLE_YYYYMMDD_HHMMSS"
    if key not in header or not header[key][0]:
        return None
    text, line = header[key]
    match = re.fullmatch(r"(\d{4})(\d{2})(\d{2})_(\d{2})(\d{2})(\d{2}(?:\.\d*)?)", text)
    if match is None:
        warn(f"bad date {text!r}, expected YYYYMMDD_HHMMSS; start time left at 0", path, line)
        return None
    parts = tuple(int(match[k]) for k in range(1, 6))
    return _header.start_time(parts, match[6], path, line, repr(text), what="date")


def read(path: Path, options: ReadOptions) -> Stream:
    """Read an ESM ASCII file as a one-trace ``obspy.Stream`` in m/s².

    Raises
    ------
    FormatError
        Missing sampling interval or NDATA, a non-acceleration file, an unknown unit, non-numeric
        values or a count other than NDATA (each naming the line).
    """
    from obspy import Stream

    from stepframe.records.trace import make_trace

    lines = read_lines(path, "ESM ASCII")
    header: dict[str, tuple[str, int]] = {}
    first = 0
    for first, line in enumerate(lines):
        match = _KEY.match(line)
        if match is None:
            break
        header[match[1]] = (match[2], first + 1)
    else:
        first = len(lines)
    for key in _REQUIRED:
        if key not in header or not header[key][0]:
            raise FormatError(f"no {key} in the header, expected '{key}: <value>'", path)
    kind, kind_line = header.get("DATA_TYPE", ("ACCELERATION", None))
    if kind and kind.upper() != "ACCELERATION":
        raise FormatError(f"DATA_TYPE {kind!r}, expected ACCELERATION", path, kind_line)
    dt_text, dt_line = header["SAMPLING_INTERVAL_S"]
    dt_s = _header.interval(dt_text, path, dt_line, "SAMPLING_INTERVAL_S")
    npts_text, npts_line = header["NDATA"]
    npts = _header.sample_count(npts_text, path, npts_line, "NDATA")
    stated, units_line = header.get("UNITS", ("", None))
    units = resolve_units(stated or None, options.units, path, units_line)
    values, _ = numbers(lines, first, path)
    check_count(values, npts, path, header["NDATA"][1])
    data_m_s2 = values * factor_to_m_s2(units)
    if header.get("PGA_CM/S^2", ("", 0))[0]:
        pga_cm_s2 = _float(header, "PGA_CM/S^2", path, -1e6, 1e6)
        check_peak(
            data_m_s2,
            None if pga_cm_s2 is None else pga_cm_s2 * 0.01,
            path,
            "PGA_CM/S^2",
            resolution=resolution_of(header["PGA_CM/S^2"][0]) * 0.01,
            line=header["PGA_CM/S^2"][1],
        )
    magnitude = _float(header, "MAGNITUDE_W", path, -5.0, 11.0)
    if magnitude is None:
        magnitude = _float(header, "MAGNITUDE_L", path, -5.0, 11.0)
    trace = make_trace(
        data_m_s2,
        dt_s,
        network=header.get("NETWORK", ("", 0))[0],
        station=header.get("STATION_CODE", ("", 0))[0],
        location=header.get("LOCATION", ("", 0))[0],
        channel=header.get("STREAM", ("", 0))[0],
        starttime=_start_time(header, path),
        source_file=str(path),
        format="esm",
        units_in=units,
        event=header.get("EVENT_ID", ("", 0))[0] or None,
        magnitude=magnitude,
        repi_km=_float(header, "EPICENTRAL_DISTANCE_KM", path, 0.0, 20040.0),
        vs30_m_s=_float(header, "VS30_M/S", path, 0.0, 1e4),
    )
    return Stream([trace])


FORMAT = register(RecordFormat(name="esm", sniff=sniff, read=read, extensions=(".ASC",)))
