"""Plain text accelerograms (format name ``text``): one column (dt given) or two (time, value).

Non-numeric lines before the first number are a header; after it every line must hold the same
number of numbers (one or two). Units are never guessed: a header that names them (``Time[s]
Accel[g]``, ``Acceleration (g)``, ``units: cm/s/s``, ``acc_gal``, as PEER-style and exported text
files do; :func:`stepframe.records.formats._text.header_units`) gives them, and a ``--units`` that
contradicts it is an error naming the header line; otherwise they must be given (``--units``).
With one column the sampling interval must be given (``--dt-s``); with two the interval is
(t_last - t_first)/(n - 1), and the times must be uniform.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from stepframe.errors import FormatError
from stepframe.records.formats import ReadOptions, RecordFormat, _header, register
from stepframe.records.formats._text import (
    MAX_VALUE,
    header_units,
    read_lines,
    resolve_units,
    same_units,
)
from stepframe.records.units import factor_to_m_s2, normalize_units

if TYPE_CHECKING:
    from obspy import Stream

#: Largest relative deviation of a time step from the mean step (printed times are rounded).
_UNIFORM_REL = 1e-3
_SNIFF_LINES = 20


def _numeric_row(line: str) -> list[float] | None:
    """The numbers of a line split on blanks, commas, semicolons or tabs; None if not numeric."""
    words = line.replace(",", " ").replace(";", " ").split()
    try:
        return [float(w) for w in words] if words else None
    except ValueError:
        return None


def sniff(head: bytes, path: Path) -> bool:
    """True if, after any header lines, the first lines are numbers in one or two columns."""
    try:
        if b"\x00" in head:
            return False
        # The header may hold non-ASCII text (m/s², a station name); the numbers may not.
        text = head.decode("latin-1")
        lines = text.splitlines()
        if not text.endswith(("\n", "\r")):
            lines = lines[:-1]  # cut short by the head's size (a whole line ends in a break)
        rows = [r for r in (_numeric_row(x) for x in lines) if r is not None]
        if not rows:
            return False
        first = next(i for i, x in enumerate(lines) if _numeric_row(x) is not None)
        body = [_numeric_row(x) for x in lines[first : first + _SNIFF_LINES] if x.strip()]
        widths = {len(r) for r in body if r is not None}
        return None not in body and len(widths) == 1 and widths <= {1, 2}
    except Exception:  # a sniffer never raises
        return False


def read(path: Path, options: ReadOptions) -> Stream:
    """Read a plain text accelerogram as a one-trace ``obspy.Stream`` in m/s².

    Raises
    ------
    FormatError
        Units neither named by the header nor given (or given against the header's), a
        header naming two units and none given, one column and no sampling interval, a line
        with another column count or a non-numeric value after the data started, non-uniform
        times, or a ``--dt-s``
        that disagrees with the times.
    """
    from obspy import Stream

    from stepframe.records.trace import make_trace

    lines = read_lines(path, "plain text")
    rows: list[list[float]] = []
    row_lines: list[int] = []
    header: list[tuple[int, str]] = []  # (1-based line, text) before the data
    width = 0
    first_line = 0
    for number, line in enumerate(lines, start=1):
        if not line.strip():
            continue
        row = _numeric_row(line)
        if row is None:
            if rows:
                raise FormatError(
                    f"non-numeric line {line.strip()[:40]!r} after the data started, "
                    "expected numbers",
                    path,
                    number,
                )
            header.append((number, line))
            continue
        if not rows:
            width, first_line = len(row), number
            if width not in (1, 2):
                raise FormatError(
                    f"{width} columns, expected one (acceleration) or two (time, acceleration)",
                    path,
                    number,
                )
        elif len(row) != width:
            raise FormatError(f"{len(row)} columns, expected {width} as above", path, number)
        rows.append(row)
        row_lines.append(number)
    if not rows:
        raise FormatError("no numeric lines, expected a column of accelerations", path)
    table = np.asarray(rows, dtype=np.float64)
    # False for NaN too: a NaN time would also switch the uniformity check off.
    fine = np.all(np.abs(table) <= MAX_VALUE, axis=1)
    if not np.all(fine):
        bad = int(np.argmin(fine))
        first_bad = next(v for v in table[bad] if not abs(v) <= MAX_VALUE)
        raise FormatError(
            f"value {first_bad} is not a finite number below {MAX_VALUE:g}, expected data",
            path,
            row_lines[bad],
        )
    if width == 2:
        time_s = table[:, 0]
        if time_s.size < 2:
            raise FormatError("one sample, expected at least two to know the interval", path)
        steps = np.diff(time_s)
        dt_s = float((time_s[-1] - time_s[0]) / (time_s.size - 1))
        if dt_s > 0:
            dt_s = _header.interval(dt_s, path, first_line, "time step")
        if not dt_s > 0 or np.max(np.abs(steps - dt_s)) > _UNIFORM_REL * dt_s:
            worst = int(np.argmax(np.abs(steps - dt_s)))
            raise FormatError(
                f"time step {steps[worst]:g} s differs from the mean {dt_s:g} s, "
                "expected uniformly increasing times",
                path,
                first_line + worst + 1,
            )
        if options.dt_s is not None and abs(options.dt_s - dt_s) > _UNIFORM_REL * dt_s:
            raise FormatError(
                f"times give dt = {dt_s:g} s but --dt-s {options.dt_s:g} was given, "
                "expected them to agree (omit --dt-s)",
                path,
                first_line,
            )
        values = table[:, 1]
    else:
        if options.dt_s is None:
            raise FormatError(
                "one column and no sampling interval, expected it given with --dt-s "
                "(or dt= in Python), or a time column",
                path,
            )
        dt_s = options.dt_s
        values = table[:, 0]
    units = _units(header, options.units, path)
    trace = make_trace(
        values * factor_to_m_s2(units),
        dt_s,
        station=path.stem,
        source_file=str(path),
        format="text",
        units_in=units,
    )
    return Stream([trace])


def _units(header: list[tuple[int, str]], given: str | None, path: Path) -> str:
    """The units the header names (checked against ``--units``), else ``--units``.

    ``header`` holds the (1-based line, text) of the lines before the data.
    """
    mentions: list[tuple[str, str, int]] = []
    for number, text in header:
        mentions += header_units([text], number)
    if not mentions:
        return resolve_units(None, given, path, None)
    word, unit, where = mentions[0]
    other = next((m for m in mentions if not same_units(m[1], unit)), None)
    if other is not None:
        if given is None:
            raise FormatError(
                f"header names units {word!r} (line {where}) and {other[0]!r} (line "
                f"{other[2]}), expected one (give the record's units with --units)",
                path,
                other[2],
            )
        return normalize_units(given)  # the user decides between the header's two
    if given is not None and not same_units(given, unit):
        shown = " ".join(dict(header)[where].split())[:60]
        raise FormatError(
            f"header line {where} {shown!r} states units {word!r} but --units {given!r} was "
            "given, expected them to agree (omit --units)",
            path,
            where,
        )
    return unit


FORMAT = register(
    RecordFormat(name="text", sniff=sniff, read=read, extensions=(".txt", ".dat", ".csv"))
)
