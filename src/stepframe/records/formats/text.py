"""Plain text accelerograms (format name ``text``): one column (dt given) or two (time, value).

Non-numeric lines before the first number are a header and are skipped; after it every line must
hold the same number of numbers (one or two). A text file states neither its units nor, with one
column, its sampling interval: both must be given (``--units``, ``--dt-s``), never guessed. With
two columns the interval is (t_last - t_first)/(n - 1), and the times must be uniform.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from stepframe.errors import FormatError
from stepframe.records.formats import ReadOptions, RecordFormat, _header, register
from stepframe.records.formats._text import MAX_VALUE, read_lines, resolve_units
from stepframe.records.units import factor_to_m_s2

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
        lines = head.decode("ascii").splitlines()[:-1]  # the last line may be cut short
        rows = [r for r in (_numeric_row(x) for x in lines) if r is not None]
        if not rows:
            return False
        first = next(i for i, x in enumerate(lines) if _numeric_row(x) is not None)
        body = [_numeric_row(x) for x in lines[first : first + _SNIFF_LINES] if x.strip()]
        widths = {len(r) for r in body if r is not None}
        return None not in body and len(widths) == 1 and widths <= {1, 2}
    except Exception:  # a sniffer never raises
        return False


def read(path: Path, options: ReadOptions) -> Any:
    """Read a plain text accelerogram as a one-trace ``obspy.Stream`` in m/s².

    Raises
    ------
    FormatError
        Units or (one column) the sampling interval not given, a line with another column
        count or a non-numeric value after the data started, non-uniform times, or a ``--dt-s``
        that disagrees with the times.
    """
    from obspy import Stream

    from stepframe.records.trace import make_trace

    lines = read_lines(path, "plain text")
    rows: list[list[float]] = []
    row_lines: list[int] = []
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
    units = resolve_units(None, options.units, path, None)
    trace = make_trace(
        values * factor_to_m_s2(units),
        dt_s,
        station=path.stem,
        source_file=str(path),
        format="text",
        units_in=units,
    )
    return Stream([trace])


FORMAT = register(
    RecordFormat(name="text", sniff=sniff, read=read, extensions=(".txt", ".dat", ".csv"))
)
