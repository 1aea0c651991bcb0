"""Engineering Strong Motion database (ESM) ASCII files (format name ``esm``).

One component a file: ``KEY: value`` header lines (``NETWORK``, ``STATION_CODE``, ``STREAM``,
``SAMPLING_INTERVAL_S``, ``NDATA``, ``DURATION_S``, ``UNITS``, ``DATA_TYPE``, ``PGA_CM/S^2``,
``EVENT_ID``, ``MAGNITUDE_W``/``MAGNITUDE_L``, ``EPICENTRAL_DISTANCE_KM``, ``VS30_M/S``,
``DATE_TIME_FIRST_SAMPLE_YYYYMMDD_HHMMSS``), then one value a line. Velocity and displacement files
(``DATA_TYPE: VELOCITY``...) are refused: not acceleration.

The same layout as national agencies redistribute it is read too:

- lines before the first ``KEY:`` line (processing notes) are kept, as written, in
  ``stats.stepframe.preamble``;
- an optional numeric field (magnitude, distance, Vs30, PGA) written empty, ``None``, ``NaN``,
  ``N/A``, ``-`` or anything else that is not a usable number is missing: the names of such
  fields are listed in ``stats.stepframe.header_missing`` (a value that is not a word for
  "missing" also gives a warning naming its line);
- the first-sample time may be written ``YYYYMMDD_HHMMSS[.f]`` (ESM), ``YYYY/MM/DD
  HH:MM:SS[.ffffff]`` or ``YYYY-MM-DD[T ]HH:MM:SS[.f]``, or day first, ``DD/MM/YYYY
  HH:MM:SS[.f]`` (as AFAD writes it); another spelling is a warning (start time left at 0);
- ``DATA_TYPE`` in any case (``Acceleration``).

The mandatory fields stay mandatory: the sampling interval, the sample count (``NDATA``, or
without it ``DURATION_S``, read as n·dt or (n - 1)·dt) and the units (``UNITS``, else
``--units``); the samples must number what the header declares.
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import TYPE_CHECKING

from stepframe.errors import FormatError
from stepframe.records.formats import ReadOptions, RecordFormat, _header, register
from stepframe.records.formats._text import (
    check_peak,
    check_samples,
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
#: Keys of the ESM header's first lines; a file naming four of them is ESM, wherever its
#: header starts in the first 4 KiB (after an agency's processing notes).
_SNIFF_KEYS = frozenset(
    {
        "EVENT_NAME",
        "EVENT_ID",
        "EVENT_DATE_YYYYMMDD",
        "EVENT_TIME_HHMMSS",
        "EVENT_LATITUDE_DEGREE",
        "EVENT_LONGITUDE_DEGREE",
        "EVENT_DEPTH_KM",
        "HYPOCENTER_REFERENCE",
        "MAGNITUDE_W",
        "MAGNITUDE_L",
        "NETWORK",
        "STATION_CODE",
        "STATION_NAME",
        "SAMPLING_INTERVAL_S",
        "NDATA",
    }
)
_SNIFF_MIN_KEYS = 4
#: Words agencies write for "no value" in an optional field.
_MISSING_WORDS = frozenset({"", "none", "nan", "null", "n/a", "na", "-", "--", "unknown"})
_START_KEY = "DATE_TIME_FIRST_SAMPLE_YYYYMMDD_HHMMSS"
_SECONDS = r"(\d{1,2}(?:\.\d*)?)"
#: First-sample time spellings: (pattern, order of year, month, day in its groups).
_DATE_SPELLINGS = (
    (re.compile(r"(\d{4})(\d{2})(\d{2})_(\d{2})(\d{2})(\d{2}(?:\.\d*)?)"), (1, 2, 3)),
    (
        re.compile(r"(\d{4})[/-](\d{1,2})[/-](\d{1,2})[ T_](\d{1,2}):(\d{1,2}):" + _SECONDS + "Z?"),
        (1, 2, 3),
    ),
    (
        re.compile(r"(\d{1,2})/(\d{1,2})/(\d{4})[ T_](\d{1,2}):(\d{1,2}):" + _SECONDS),
        (3, 2, 1),
    ),
)


def sniff(head: bytes, path: Path) -> bool:
    """True if the head holds ESM ``KEY: value`` lines (four of its first keys, at line starts),
    whether the header starts the file or follows processing notes."""
    try:
        text = head.decode("latin-1")
        keys = {m[1] for m in re.finditer(r"^([A-Z][A-Z0-9_/^.\-]*):", text, re.MULTILINE)}
        return len(keys & _SNIFF_KEYS) >= _SNIFF_MIN_KEYS
    except Exception:  # a sniffer never raises
        return False


class _Header:
    """The ``KEY: value`` lines of one file, with the optional fields found missing."""

    def __init__(self, fields: dict[str, tuple[str, int]], path: Path) -> None:
        self.fields = fields
        self.path = path
        self.missing: list[str] = []

    def text(self, key: str) -> str:
        """A text field ("" when absent or written as a word for missing)."""
        value = self.fields.get(key, ("", 0))[0]
        return "" if value.lower() in _MISSING_WORDS else value

    def line(self, key: str) -> int | None:
        return self.fields[key][1] if key in self.fields else None

    def optional(self, key: str, low: float, high: float) -> float | None:
        """An optional number in [low, high]; None (listed in ``missing``) when written empty,
        as a word for missing, or as something that is not a usable number (with a warning)."""
        if key not in self.fields:
            return None
        text, line = self.fields[key]
        if text.lower() in _MISSING_WORDS:
            self.missing.append(key)
            return None
        try:
            return _header.number(text, self.path, line, key, low=low, high=high)
        except FormatError as error:
            warn(f"{error.what}; {key} left missing", self.path, line)
            self.missing.append(key)
            return None

    def mandatory(self, key: str) -> tuple[str, int]:
        """A mandatory field's text and line; FormatError when absent or written as missing."""
        if key not in self.fields:
            raise FormatError(f"no {key} in the header, expected '{key}: <value>'", self.path)
        text, line = self.fields[key]
        if text.lower() in _MISSING_WORDS:
            raise FormatError(f"{key} is {text!r}, expected a value (mandatory)", self.path, line)
        return text, line


def _split(lines: list[str], path: Path) -> tuple[list[str], dict[str, tuple[str, int]], int]:
    """(lines before the header, ``{key: (value, 1-based line)}``, 0-based first data line)."""
    first_key = next((i for i, line in enumerate(lines) if _KEY.match(line)), None)
    if first_key is None:
        raise FormatError("no 'KEY: value' header line, expected an ESM header", path)
    fields: dict[str, tuple[str, int]] = {}
    index = first_key
    while index < len(lines) and (not lines[index].strip() or _KEY.match(lines[index])):
        if match := _KEY.match(lines[index]):  # blank lines within the header are skipped
            fields[match[1]] = (match[2], index + 1)
        index += 1
    return lines[:first_key], fields, index


def _start_time(header: _Header, path: Path) -> UTCDateTime:
    key = next(
        (k for k in (_START_KEY, "DATE_TIME_FIRST_SAMPLE") if header.text(k)),
        None,
    )
    if key is None:
        return None
    text, line = header.text(key), header.line(key)
    for pattern, (y, m, d) in _DATE_SPELLINGS:
        if match := pattern.fullmatch(text):
            parts = (int(match[y]), int(match[m]), int(match[d]), int(match[4]), int(match[5]))
            return _header.start_time(parts, match[6], path, line, repr(text), what="date")
    warn(
        f"bad date {text!r}, expected YYYYMMDD_HHMMSS, YYYY/MM/DD HH:MM:SS.ffffff or "
        "DD/MM/YYYY HH:MM:SS; start time left at 0",
        path,
        line,
    )
    return None


def _declared_count(header: _Header, dt_s: float, found: int) -> tuple[int, int, str]:
    """(declared sample count, its line, its name): NDATA, else DURATION_S / dt.

    A duration is read as either convention, n·dt or (n - 1)·dt, so it declares two counts;
    the one nearer the samples found is compared with them.
    """
    path = header.path
    if header.text("NDATA"):
        text, line = header.mandatory("NDATA")
        return _header.sample_count(text, path, line, "NDATA"), line, "NDATA"
    if not header.text("DURATION_S"):
        raise FormatError(
            "no NDATA or DURATION_S in the header, expected the sample count or the duration",
            path,
            header.line("NDATA") or header.line("DURATION_S"),
        )
    text, line = header.mandatory("DURATION_S")
    duration_s = _header.number(text, path, line, "DURATION_S", low=0.0, high=1e7)
    intervals = round(duration_s / dt_s)
    if not math.isclose(intervals * dt_s, duration_s, rel_tol=1e-6, abs_tol=0.5 * dt_s):
        raise FormatError(
            f"DURATION_S = {duration_s:g} s is not a whole number of intervals of {dt_s:g} s, "
            "expected n·SAMPLING_INTERVAL_S",
            path,
            line,
        )
    declared = intervals + 1 if found == intervals + 1 else intervals
    return declared, line, f"DURATION_S / SAMPLING_INTERVAL_S ({duration_s:g} s / {dt_s:g} s)"


def read(path: Path, options: ReadOptions) -> Stream:
    """Read an ESM ASCII file as a one-trace ``obspy.Stream`` in m/s².

    Raises
    ------
    FormatError
        A missing sampling interval, sample count (NDATA or DURATION_S) or units, a
        non-acceleration file, an unknown unit, non-numeric values or a count other than
        declared (each naming the line).
    """
    from obspy import Stream

    from stepframe.records.trace import make_trace

    lines = read_lines(path, "ESM ASCII", allow_short=options.allow_short)
    preamble, fields, first = _split(lines, path)
    header = _Header(fields, path)
    kind = header.text("DATA_TYPE") or "ACCELERATION"
    if kind.upper() != "ACCELERATION":
        raise FormatError(
            f"DATA_TYPE {kind!r}, expected ACCELERATION", path, header.line("DATA_TYPE")
        )
    dt_text, dt_line = header.mandatory("SAMPLING_INTERVAL_S")
    dt_s = _header.interval(dt_text, path, dt_line, "SAMPLING_INTERVAL_S")
    units = resolve_units(header.text("UNITS") or None, options.units, path, header.line("UNITS"))
    values, _ = numbers(lines, first, path)
    declared, count_line, what = _declared_count(header, dt_s, values.size)
    incomplete = check_samples(values.size, declared, path, count_line, options, what)
    data_m_s2 = values * factor_to_m_s2(units)
    pga_cm_s2 = header.optional("PGA_CM/S^2", -1e6, 1e6)
    if pga_cm_s2 is not None and incomplete is None:
        check_peak(
            data_m_s2 / factor_to_m_s2("cm/s2"),
            pga_cm_s2,
            path,
            "PGA_CM/S^2",
            units="cm/s2",
            resolution=resolution_of(header.text("PGA_CM/S^2")),
            line=header.line("PGA_CM/S^2"),
        )
    magnitude_w = header.optional("MAGNITUDE_W", -5.0, 11.0)
    magnitude_l = header.optional("MAGNITUDE_L", -5.0, 11.0)
    trace = make_trace(
        data_m_s2,
        dt_s,
        network=header.text("NETWORK"),
        station=header.text("STATION_CODE"),
        location=header.text("LOCATION"),
        channel=header.text("STREAM"),
        starttime=_start_time(header, path),
        source_file=str(path),
        format="esm",
        units_in=units,
        event=header.text("EVENT_ID") or None,
        magnitude=magnitude_w if magnitude_w is not None else magnitude_l,
        repi_km=header.optional("EPICENTRAL_DISTANCE_KM", 0.0, 20040.0),
        vs30_m_s=header.optional("VS30_M/S", 0.0, 1e4),
        incomplete=incomplete,
        preamble=[line.rstrip() for line in preamble],
        header_missing=header.missing,
    )
    return Stream([trace])


FORMAT = register(RecordFormat(name="esm", sniff=sniff, read=read, extensions=(".ASC",)))
