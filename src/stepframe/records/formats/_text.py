"""Helpers shared by the text-format readers: decoding, number blocks, units, dates.

Every helper raises :class:`stepframe.errors.FormatError` naming the file and the 1-based line, so
each reader's errors have the same one-line shape.
"""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import numpy as np

from stepframe.errors import FormatError
from stepframe.records.units import normalize_units

#: A decimal number in Fortran E/F notation; used only where values run into each other.
_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eEdD][-+]?\d+)?"
_RUN_TOGETHER = re.compile(rf"(?:\s*{_NUMBER})+\s*")
_ONE_NUMBER = re.compile(_NUMBER)


class FormatWarning(UserWarning):
    """A file read cleanly whose header has a problem that does not touch the data."""


def read_lines(path: Path, what: str) -> list[str]:
    """The file's lines, refusing empty and binary files.

    Parameters
    ----------
    path
        The file.
    what
        The format's name for messages (``"PEER AT2"``).
    """
    raw = path.read_bytes()
    if not raw.strip():
        raise FormatError(f"empty file, expected {what} text", path)
    if b"\x00" in raw[:65536]:
        raise FormatError(f"binary content (NUL bytes), expected {what} text", path)
    try:
        text = raw.decode("ascii")
    except UnicodeDecodeError:
        # Latin-1 station names occur in real headers; numbers are ASCII in every text format.
        text = raw.decode("latin-1")
    return text.splitlines()


def numbers(
    lines: list[str], first: int, path: Path, *, count: int | None = None
) -> tuple[np.ndarray, int]:
    """Parse whitespace-separated numbers from ``lines[first:]``.

    Parameters
    ----------
    lines
        All lines of the file.
    first
        0-based index of the first data line.
    path
        The file, for messages.
    count
        Stop after this many values (the rest of the file is left unread); None reads to the end.

    Returns
    -------
    values
        The numbers as float64.
    next_line
        0-based index of the line after the last one consumed.

    Raises
    ------
    FormatError
        A word that is not a number, naming its line.
    """
    values: list[float] = []
    index = first
    while index < len(lines) and (count is None or len(values) < count):
        line = lines[index]
        index += 1
        words = line.split()
        try:
            values.extend(float(word) for word in words)
        except ValueError:
            # Fixed-width Fortran fields can touch ("-1.234E-02-5.678E-03"); accept only that.
            fixed = line.replace("D", "E").replace("d", "e")
            if not _RUN_TOGETHER.fullmatch(fixed):
                bad = next(w for w in words if not _is_number(w))
                raise FormatError(
                    f"non-numeric value {bad[:30]!r} in the data, expected numbers", path, index
                ) from None
            values.extend(float(m[0]) for m in _ONE_NUMBER.finditer(fixed))
    if count is not None and len(values) > count:
        raise FormatError(
            f"line holds values beyond the {count} stated, expected the block to end there",
            path,
            index,
        )
    return np.asarray(values, dtype=np.float64), index


def _is_number(word: str) -> bool:
    try:
        float(word)
    except ValueError:
        return False
    return True


def resolve_units(stated: str | None, given: str | None, path: Path, line: int | None) -> str:
    """The units to use: the file's stated units, checked against the user's ``--units``.

    Raises
    ------
    FormatError
        If neither is known (message says how to give them), the stated unit is not an
        acceleration unit, or the two disagree.
    """
    if stated is None:
        if given is None:
            raise FormatError(
                "units not stated in the file, expected them given with --units "
                "(g, m/s2, cm/s2 = gal, mm/s2) or units= in Python",
                path,
            )
        return normalize_units(given)
    try:
        units = normalize_units(stated)
    except Exception:
        raise FormatError(
            f"unknown unit {stated!r} in the header, expected g, m/s2, cm/s2 (gal) or mm/s2",
            path,
            line,
        ) from None
    if given is not None and normalize_units(given) != units:
        raise FormatError(
            f"header states units {stated!r} but --units {given!r} was given, "
            "expected them to agree (omit --units)",
            path,
            line,
        )
    return units


def check_count(values: np.ndarray, npts: int, path: Path, line: int | None) -> None:
    """Refuse a data block whose length differs from the header's sample count."""
    if values.size != npts:
        state = "truncated" if values.size < npts else "longer than stated"
        raise FormatError(
            f"{values.size} values follow ({state}), expected NPTS = {npts}", path, line
        )


def check_peak(
    data: np.ndarray, stated: float | None, path: Path, what: str, *, rel: float = 5e-3
) -> None:
    """Warn when a header's stated peak disagrees with the data's peak (both in file units).

    A header's peak is printed to a few digits, so agreement is to ``rel`` (relative).
    """
    if stated is None or data.size == 0:
        return
    peak = float(np.max(np.abs(data)))
    if abs(peak - abs(stated)) > rel * max(abs(stated), 1e-30):
        warnings.warn(
            f"{path}: {what}: header peak {stated:g} but the data peak is {peak:g}",
            FormatWarning,
            stacklevel=3,
        )


def warn(message: str, path: Path, line: int | None = None) -> None:
    """Issue a :class:`FormatWarning` in the one-line ``file:line: message`` shape."""
    where = f"{path}:{line}" if line is not None else str(path)
    warnings.warn(f"{where}: {message}", FormatWarning, stacklevel=3)
