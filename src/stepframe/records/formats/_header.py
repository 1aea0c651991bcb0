"""Checked parsers for header numbers: one per kind (count, sampling interval, value, date).

Every reader turns header text into numbers through these, so a header value that parses as a
number but cannot be used (``NDATA: inf``, ``DT= 1e308``, ``PGA: 1e400``, year 99999999999) is
refused the same way in every format: one :class:`~stepframe.errors.FormatError` naming the file
and line, never a ``ValueError``/``OverflowError`` from deeper down.
"""

from __future__ import annotations

import math
from pathlib import Path

from stepframe.errors import FormatError

#: Sampling intervals accepted by default [s]: accelerographs sample at 1 Hz to 1 MHz.
MIN_DT_S = 1e-6
MAX_DT_S = 1.0

#: Years accepted in record dates: instrumental strong-motion records start in 1933.
MIN_YEAR = 1900
MAX_YEAR = 2200


def _text(value: str | float | int) -> str:
    return str(value).strip()[:40]


def number(
    text: str | float,
    path: Path,
    line: int | None,
    what: str,
    *,
    low: float = -math.inf,
    high: float = math.inf,
    kind: str = "number",
) -> float:
    """A finite physical value in [low, high], parsed from header text (Fortran ``D`` accepted).

    Parameters
    ----------
    text
        The header field (or an already parsed number).
    path, line
        Where it is, for the message (line 1-based).
    what
        The field's name in the file (``"PGA_CM/S^2"``).
    low, high
        Plausible bounds for the field.
    kind
        What the field must be, for the message (``"positive number"``).
    """
    if isinstance(text, str):
        try:
            value = float(text.strip().replace("D", "E").replace("d", "e"))
        except ValueError:
            raise FormatError(
                f"{what} = {_text(text)!r} is not a {kind}, expected one", path, line
            ) from None
    else:
        value = float(text)
    if not math.isfinite(value):
        raise FormatError(f"{what} = {_text(text)!r}, expected a finite number", path, line)
    if not low <= value <= high:
        raise FormatError(
            f"{what} = {value:g}, expected a value in [{low:g}, {high:g}]", path, line
        )
    return value


def sample_count(text: str | float, path: Path, line: int | None, what: str) -> int:
    """A positive whole number of samples (finite, below 10¹², as no record reaches).

    Readers never size an array from it: they parse the values present and compare counts, so a
    damaged count gives "n values follow (truncated)" rather than an allocation.
    """
    value = number(text, path, line, what, low=1, high=1e12)
    if value != int(value):
        raise FormatError(f"{what} = {_text(text)!r}, expected a whole number", path, line)
    return int(value)


def small_integer(text: str | float, path: Path, line: int | None, what: str) -> int:
    """An integer header code (a count of header lines, a unit code): finite, |n| < 10⁹."""
    value = number(text, path, line, what, low=-1e9, high=1e9)
    if value != int(value):
        raise FormatError(f"{what} = {_text(text)!r}, expected an integer", path, line)
    return int(value)


def interval(
    text: str | float,
    path: Path,
    line: int | None,
    what: str = "sampling interval",
    *,
    low_s: float = MIN_DT_S,
    high_s: float = MAX_DT_S,
) -> float:
    """A sampling interval [s] in [low_s, high_s] (default 1 µs to 1 s)."""
    value = number(text, path, line, what)
    if not low_s <= value <= high_s:
        raise FormatError(
            f"{what} = {value:g} s, expected an accelerogram's interval in "
            f"[{low_s:g}, {high_s:g}] s",
            path,
            line,
        )
    return value


def start_time(
    parts: tuple[float | int | None, ...],
    seconds: float | str | None,
    path: Path,
    line: int | None,
    text: str,
    what: str = "start time",
) -> object | None:
    """``obspy.UTCDateTime`` of (year, month, day, hour, minute) + seconds, or None with a warning.

    A bad date does not touch the data, so it is a warning (start time left at 0), never an
    error; an absurd year, a NaN or a 1e300 are bad dates like 31 February.

    Parameters
    ----------
    parts
        Year, month, day, hour, minute as read (None where absent).
    seconds
        Seconds of the minute (may carry a fraction).
    path, line
        Where, for the warning.
    text
        The date as written, for the warning.
    what
        The field's name for the warning.
    """
    from obspy import UTCDateTime

    from stepframe.records.formats._text import warn

    try:
        numbers = [float(p) for p in parts if p is not None]
        sec = 0.0 if seconds is None else float(seconds)
        if len(numbers) != 5 or not all(math.isfinite(v) and v == int(v) for v in numbers):
            raise ValueError(text)
        year_, month, day, hour, minute = (int(v) for v in numbers)
        if not (MIN_YEAR <= year_ <= MAX_YEAR and math.isfinite(sec) and 0 <= sec < 61):
            raise ValueError(text)
        start: object = UTCDateTime(year_, month, day, hour, minute) + sec
        return start
    except (ValueError, TypeError, OverflowError):
        warn(
            f"bad {what} {text[:40]}, expected a calendar date and time; start time left at 0",
            path,
            line,
        )
        return None
