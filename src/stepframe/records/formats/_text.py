"""Helpers shared by the text-format readers: decoding, number blocks, units, dates.

Every helper raises :class:`stepframe.errors.FormatError` naming the file and the 1-based line, so
each reader's errors have the same one-line shape.
"""

from __future__ import annotations

import re
import warnings
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import numpy as np

from stepframe.errors import FormatError
from stepframe.records.formats import ReadOptions
from stepframe.records.units import ACCELERATION_UNITS_TO_M_S2, normalize_units

#: Largest magnitude accepted for a number in a data block (any unit): far above any real
#: value in counts, g, cm/s² or header codes; a larger one is damage, and would overflow to
#: infinity on conversion to m/s².
MAX_VALUE = 1e100


class FormatWarning(UserWarning):
    """A file read cleanly whose header has a problem that does not touch the data."""


def read_lines(path: Path, what: str, *, allow_short: bool = False) -> list[str]:
    """The file's lines, refusing empty and binary files.

    DOS end-of-file characters (``\\x1a``) that old CDMG files end with are dropped.

    Parameters
    ----------
    path
        The file.
    what
        The format's name for messages (``"PEER AT2"``).
    allow_short
        The record may be read short (:class:`ReadOptions`): the last value of a file that does
        not end with a line break is dropped (:func:`drop_cut_value`).
    """
    raw = path.read_bytes().rstrip(b"\x1a")
    if not raw.strip():
        raise FormatError(f"empty file, expected {what} text", path)
    if b"\x00" in raw[:65536]:
        raise FormatError(f"binary content (NUL bytes), expected {what} text", path)
    if allow_short:
        raw = drop_cut_value(raw)
    try:
        text = raw.decode("utf-8")  # ASCII is UTF-8; a unit such as m/s² in a header often is
    except UnicodeDecodeError:
        # Latin-1 station names occur in real headers; numbers are ASCII in every text format.
        text = raw.decode("latin-1")
    # The bytes and the text of a long record each hold the file's size: never both with the
    # lines too (the reading peak of a 228 MB file was 1.7 GB with them, docs/benchmarks.md).
    del raw
    return text.splitlines()


def drop_cut_value(raw: bytes) -> bytes:
    """``raw`` without its last word when it ends inside one (not with a blank or line break).

    A file cut short was cut anywhere, often inside a number (``-12085`` cut to ``-12`` or
    ``-``): read short, its last value would be wrong or unreadable. Real record files end
    with a line break, so only a cut file loses a value here (and only when the record may be
    read short); a word followed by a blank was written whole.
    """
    if not raw.strip() or raw[-1:].isspace():
        return raw
    return raw[: len(raw) - len(raw.rsplit(None, 1)[-1])]


def numbers(
    lines: list[str],
    first: int,
    path: Path,
    *,
    count: int | None = None,
    width: int | None = None,
) -> tuple[np.ndarray, int]:
    """Parse numbers from ``lines[first:]``, separated by blanks or in fixed-width fields.

    Parameters
    ----------
    lines
        All lines of the file.
    first
        0-based index of the first data line.
    path
        The file, for messages.
    count
        Stop at the end of the line that completes this many values; None reads to the end.
    width
        Field width of a Fortran fixed format (``8F10.5`` → 10), so that fields that touch
        (``5.0000000-999.00000``) are split where the format puts them; None splits on blanks.

    Returns
    -------
    values
        The numbers as float64.
    next_line
        0-based index of the line after the last one consumed.

    Raises
    ------
    FormatError
        A field that is not a number, or values beyond ``count`` on the last line, naming the line.
    """
    if width is not None and width < 1:  # a data format such as (8F0.3)
        raise FormatError(
            f"data format with fields {width} characters wide, expected a positive width",
            path,
            first,  # the format's line, just before the data
        )
    fast = (
        _blank_separated(lines, first, count)
        if width is None
        else _fixed_width(lines, first, count, width)
    )
    if fast is not None:
        return fast
    # Line by line: fixed-width fields, Fortran D exponents, and the exact line of a bad value.
    values: list[float] = []
    index = first
    while index < len(lines) and (count is None or len(values) < count):
        line = lines[index]
        index += 1
        words = _words(line, width)
        try:
            row = [float(word) for word in words]
        except ValueError:
            # Fortran D exponents (1.0D-03) are numbers; the message shows the word as written.
            fixed = [w.replace("D", "E").replace("d", "e") for w in words]
            bad = next((w for w, f in zip(words, fixed, strict=True) if not _is_number(f)), None)
            if bad is not None:
                where = "" if count is None else f" after {len(values)} of {count} values"
                raise FormatError(
                    f"non-numeric value {bad[:30]!r}{where}, expected numbers", path, index
                ) from None
            row = [float(f) for f in fixed]
        if not all(abs(v) <= MAX_VALUE for v in row):  # also false for NaN
            bad = next(w for w, v in zip(words, row, strict=True) if not abs(v) <= MAX_VALUE)
            raise FormatError(
                f"value {bad[:30]!r} is not a finite number below {MAX_VALUE:g}, expected data",
                path,
                index,
            )
        values.extend(row)
    if count is not None and len(values) > count:
        raise FormatError(
            f"line holds values beyond the {count} stated, expected the block to end there",
            path,
            index,
        )
    return np.asarray(values, dtype=np.float64), index


#: Values converted at once by the vectorised path: the words of a block are Python strings
#: (about 60 bytes each), so a block holds a few MB whatever the record's length.
_BLOCK_VALUES = 1 << 16


def _blank_separated(
    lines: list[str], first: int, count: int | None
) -> tuple[np.ndarray, int] | None:
    """:func:`numbers` for blank-separated values, converted a block of
    :data:`_BLOCK_VALUES` at a time (vectorised, in bounded memory: the words of a whole long
    record would take eight times its values), or None when any value needs the line-by-line
    path (not a plain number, not finite and below ``MAX_VALUE``, or more values than
    ``count`` on the last line). A record's few thousand lines parse about three times faster
    this way."""
    blocks: list[np.ndarray] = []
    converted = 0
    words: list[str] = []
    index = first
    while index < len(lines) and (count is None or converted + len(words) < count):
        words += lines[index].split()
        index += 1
        if len(words) >= _BLOCK_VALUES or index == len(lines):
            block = _converted(words)
            if block is None:
                return None
            blocks.append(block)
            converted += block.size
            words = []
    if words:
        block = _converted(words)
        if block is None:
            return None
        blocks.append(block)
    return _joined(blocks, count, index)


def _fixed_width(
    lines: list[str], first: int, count: int | None, width: int
) -> tuple[np.ndarray, int] | None:
    """:func:`numbers` for fields of ``width`` characters, converted as fixed-width byte
    strings a chunk of lines at a time (numpy parses them as Python's ``float`` does), or None
    when any field needs the line-by-line path: a blank field (which that path skips), a field
    that is not a plain number (a Fortran D exponent, a word), a value not finite and below
    ``MAX_VALUE``, a character beyond ASCII, or more values than ``count`` on the last line.
    Lines are stripped, measured and joined by C loops; only a line that ends inside a field
    is padded in Python. A CSMIP or COSMOS file of 20,000-100,000 values reads two to five
    times faster (docs/benchmarks.md)."""
    blocks: list[np.ndarray] = []
    converted = 0
    index = first
    chunk_lines = max(1, _BLOCK_VALUES // 8)
    while index < len(lines) and (count is None or converted < count):
        stripped = list(map(str.rstrip, lines[index : index + chunk_lines]))
        lengths = np.fromiter(map(len, stripped), dtype=np.int64, count=len(stripped))
        fields = -(-lengths // width)
        if count is not None:  # up to the line that completes ``count`` values
            reached = np.flatnonzero(converted + np.cumsum(fields) >= count)
            if reached.size:
                del stripped[reached[0] + 1 :]
        index += len(stripped)
        # Pad a line that ends inside a field to whole fields, as the line-by-line path cuts it.
        for k in np.flatnonzero(lengths[: len(stripped)] % width):
            stripped[k] = stripped[k].ljust(int(fields[k]) * width)
        try:
            fields_text = np.frombuffer("".join(stripped).encode("ascii"), dtype=f"S{width}")
        except UnicodeEncodeError:
            return None
        block = _converted(fields_text)  # None for a blank field too: it is no number
        if block is None:
            return None
        blocks.append(block)
        converted += block.size
    return _joined(blocks, count, index)


def _joined(
    blocks: list[np.ndarray], count: int | None, index: int
) -> tuple[np.ndarray, int] | None:
    """The vectorised paths' blocks as one array with the next line, or None when they hold
    more values than ``count`` (the line-by-line path then names the line)."""
    converted = sum(block.size for block in blocks)
    if count is not None and converted > count:
        return None
    if len(blocks) == 1:
        return blocks[0], index
    return (np.concatenate(blocks) if blocks else np.empty(0, dtype=np.float64)), index


def _converted(words: list[str] | np.ndarray) -> np.ndarray | None:
    """``words`` (strings, or fixed-width byte strings) as float64 if each is a plain finite
    number below ``MAX_VALUE``, else None."""
    try:
        values = np.array(words, dtype=np.float64)
    except ValueError:
        return None
    if not np.all(np.abs(values) <= MAX_VALUE):  # also false for NaN
        return None
    return values


#: A Fortran data format such as ``(8F10.5)``, ``(1E15.6)``, ``(10I8)``.
_FORTRAN = re.compile(r"\(\s*(\d*)\s*[EFGDI]\s*(\d+)(?:\.\d+)?\s*\)", re.IGNORECASE)


def fortran_width(text: str) -> int | None:
    """Field width of the first Fortran format in ``text`` (``"Format=(8F10.5)"`` → 10)."""
    match = _FORTRAN.search(text)
    return int(match[2]) if match else None


def _is_number(word: str) -> bool:
    try:
        float(word)
    except ValueError:
        return False
    return True


#: A unit in brackets or parentheses: ``Accel[g]``, ``Acceleration (cm/s/s)``, ``{gal}``.
_BRACKETED = re.compile(r"[\[({]\s*([^\[\](){}]{1,16}?)\s*[\])}]")
#: A unit after the word "unit(s)": ``units: g``, ``IN UNITS OF G``, ``unit = cm/s^2``.
_AFTER_UNITS = re.compile(
    r"\bunits?\b\s*(?:of\b|in\b|[:=])?\s*([a-z][a-z/^*0-9'\u00b2]*)", re.IGNORECASE
)
#: A snake-case unit suffix of a column name: ``acc_g``, ``accel_gal``, ``a_cm_s2``.
_SUFFIX = re.compile(r"[a-z]\w*?_(g|gals?|cm_s2|m_s2|mm_s2)", re.IGNORECASE)
#: Unit words that name an acceleration on their own (``g`` alone is too ambiguous).
_BARE = re.compile(r"[a-z]+(?:/[a-z]+)+(?:\^?\*{0,2}[2\u00b2])?|gals?", re.IGNORECASE)


def _as_unit(word: str) -> str | None:
    """``word`` as a known acceleration unit's canonical name, or None."""
    text = word.strip().replace("\u00b2", "2").replace(" ", "").lower().replace("sec", "s")
    text = {"cm_s2": "cm/s2", "m_s2": "m/s2", "mm_s2": "mm/s2"}.get(text, text)
    try:
        return normalize_units(text)
    except Exception:  # not an acceleration unit: Time (s), cm/s, counts
        return None


def header_units(lines: list[str], first: int = 1) -> list[tuple[str, str, int]]:
    """The acceleration units a free-text header names, where it names them.

    Recognised: a unit in brackets or parentheses (``Accel[g]``, ``Acceleration (g)``,
    ``Acc (cm/s^2)``), after the word "units" (``units: gal``, ``IN UNITS OF G``), a snake-case
    column suffix (``acc_gal``, ``accel_g``) or a unit word standing alone (``cm/s/s``, ``gal``).
    Other units (``Time (s)``, ``Velocity (cm/s)``) are ignored.

    Parameters
    ----------
    lines
        The header lines.
    first
        The 1-based line number of ``lines[0]``.

    Returns
    -------
    list
        ``(unit as written, canonical unit, 1-based line)`` per mention, in file order.
    """
    found: list[tuple[str, str, int]] = []
    for number, line in enumerate(lines, start=first):
        candidates = [m[1] for m in _BRACKETED.finditer(line)]
        candidates += [m[1] for m in _AFTER_UNITS.finditer(line)]
        for word in re.split(r"[\s,;]+", line):
            word = word.strip("\"'#:=")
            suffix = _SUFFIX.fullmatch(word)
            if suffix:
                candidates.append(suffix[1])
            elif _BARE.fullmatch(word):
                candidates.append(word)
        for word in candidates:
            unit = _as_unit(word)
            if unit is not None:
                found.append((word, unit, number))
    return found


def same_units(a: str, b: str) -> bool:
    """Whether two unit names mean the same unit (``gal`` and ``cm/s2`` do)."""
    return (
        ACCELERATION_UNITS_TO_M_S2[normalize_units(a)]
        == ACCELERATION_UNITS_TO_M_S2[normalize_units(b)]
    )


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
    if given is not None and not same_units(given, units):
        raise FormatError(
            f"header states units {stated!r} but --units {given!r} was given, "
            "expected them to agree (omit --units)",
            path,
            line,
        )
    return units


def check_count(
    values: np.ndarray, npts: int, path: Path, line: int | None, what: str = "NPTS"
) -> None:
    """Refuse a header block (integer or real header) whose length differs from its count.

    Header blocks are never accepted short: a record whose header is cut is not a record.
    """
    if values.size != npts:
        raise FormatError(_count_message(values.size, npts, what), path, line)


def _count_message(found: int, declared: int, what: str) -> str:
    state = "truncated" if found < declared else "longer than stated"
    return f"{found} values follow ({state}), expected {what} = {declared}"


#: The smallest record :func:`check_samples` accepts short: one sample has no interval.
MIN_SHORT_SAMPLES = 2


def check_samples(
    found: int,
    declared: int,
    path: Path,
    line: int | None,
    options: ReadOptions,
    what: str = "NPTS",
) -> str | None:
    """Compare a data block's sample count with the count its header declares.

    Parameters
    ----------
    found, declared
        Samples in the file and samples the header declares.
    path, line
        The file and the 1-based line of the declaration, for the message.
    options
        The read options: ``allow_short`` accepts fewer samples than declared.
    what
        The declaration's name in the file (``"NPTS"``, ``"NDATA"``).

    Returns
    -------
    str or None
        None for a complete block; for a short block read with ``allow_short``, the note that
        flags the record (``"3849 of 28600 samples"``, for ``stats.stepframe.incomplete``),
        after a :class:`FormatWarning`.

    Raises
    ------
    FormatError
        More samples than declared (always), fewer without ``allow_short``, or fewer than
        :data:`MIN_SHORT_SAMPLES` (one line naming the file, the line, both counts).
    """
    if found == declared:
        return None
    message = _count_message(found, declared, what)
    if found > declared:
        raise FormatError(message, path, line)
    if not options.allow_short:
        raise FormatError(f"{message} (a short record is read only with --allow-short)", path, line)
    if found < MIN_SHORT_SAMPLES:
        raise FormatError(f"{message}, and a short record needs at least 2 samples", path, line)
    warn(f"{message}; read short (allow_short), flagged in stats.stepframe.incomplete", path, line)
    return f"{found} of {declared} samples"


def check_components(
    found: int,
    declared: int,
    path: Path,
    line: int | None,
    options: ReadOptions,
    *,
    what: str = "components",
    source: str = "as the header declares",
) -> str | None:
    """Compare the components of a multi-component file with the number it should hold.

    Parameters
    ----------
    found, declared
        Components read, components the file should hold.
    path, line
        The file and the 1-based line of the declaration (None: the format's definition).
    options
        The read options: ``allow_short`` accepts fewer components.
    what, source
        The components' name (``"channels"``) and where the number comes from, for messages.

    Returns
    -------
    str or None
        None when all are there; with ``allow_short``, the note flagging every trace of the
        file (``"1 of 3 components"``), after a :class:`FormatWarning`.

    Raises
    ------
    FormatError
        More components than declared, or fewer without ``allow_short``.
    """
    if found == declared:
        return None
    if found > declared:
        message = f"{found} {what} in the file, expected {declared} ({source})"
        raise FormatError(message, path, line)
    message = (
        f"{found} of {declared} {what} in the file (cut short?), expected {declared} ({source})"
    )
    if not options.allow_short:
        hint = f" (a file missing {what} is read only with --allow-short)"
        raise FormatError(message + hint, path, line)
    warn(f"{message}; read (allow_short), flagged in stats.stepframe.incomplete", path, line)
    return f"{found} of {declared} {what}"


def file_cut(where: str, path: Path, line: int | None, options: ReadOptions, expected: str) -> str:
    """Refuse a file that ends ``where`` a whole file goes on (after a block, before an end
    line, inside a heading), or with ``allow_short`` warn and return the note that flags its
    traces (``"file ends inside the header of channel 3"``).

    Parameters
    ----------
    where
        Where the file ends (``"before the '/&' line ending channel H2"``).
    path, line
        The file and the 1-based line, for the message.
    options
        The read options (``allow_short``).
    expected
        What a whole file holds there, for the message.
    """
    message = f"the file ends {where} (cut short?), expected {expected}"
    if not options.allow_short:
        raise FormatError(f"{message} (a cut file is read only with --allow-short)", path, line)
    warn(f"{message}; read (allow_short), flagged in stats.stepframe.incomplete", path, line)
    return f"file ends {where}"


def mark_incomplete(traces: Iterable[Any], note: str | None) -> None:
    """Add ``note`` to ``stats.stepframe.incomplete`` of each trace (``"; "``-joined)."""
    if note is None:
        return
    for trace in traces:
        previous = trace.stats.stepframe.get("incomplete")
        trace.stats.stepframe.incomplete = f"{previous}; {note}" if previous else note


def _is_numeric_line(line: str, width: int | None) -> bool:
    words = _words(line, width)
    return bool(words) and all(_is_number(w.replace("D", "E").replace("d", "e")) for w in words)


def check_block_end(
    lines: list[str],
    index: int,
    declared: int,
    path: Path,
    *,
    width: int | None = None,
    what: str = "NPTS",
    expected: str = "the next block",
) -> None:
    """Refuse numbers right after a data block that held its declared count.

    A block parsed up to its declared count stops there; values beyond it would otherwise be
    left unread silently (more samples than declared).

    Parameters
    ----------
    lines
        All lines of the file.
    index
        0-based index of the line after the block.
    declared
        The block's declared count, for the message.
    width
        Fixed field width of the block's Fortran format (None: blank-separated).
    what, expected
        The count's name and what must follow the block, for the message.
    """
    extra = 0
    first = index
    while index < len(lines) and _is_numeric_line(lines[index], width):
        extra += len(_words(lines[index], width))
        index += 1
    if extra:
        raise FormatError(
            f"{declared + extra} values follow (longer than stated), expected {what} = "
            f"{declared} and then {expected}",
            path,
            first + 1,
        )


def _words(line: str, width: int | None) -> list[str]:
    if width is None:
        return line.split()
    text = line.rstrip()
    return [w for w in (text[i : i + width].strip() for i in range(0, len(text), width)) if w]


def check_peak(
    data: np.ndarray,
    stated: float | None,
    path: Path,
    what: str,
    *,
    units: str,
    resolution: float | None = None,
    line: int | None = None,
) -> None:
    """Warn when a header's stated peak disagrees with the data's peak, both in ``units``.

    Every format words it the same way, units stated: ``PGA_CM/S^2: header peak 30.0022 cm/s2
    but the data peak is 0.300022 cm/s2``.

    Parameters
    ----------
    data
        The series, in ``units``.
    stated
        The header's peak (sign ignored), in ``units``; None skips the check.
    units
        The header value's unit (an acceleration unit of :mod:`stepframe.records.units`, or
        ``counts``), printed with both values.
    resolution
        The last printed digit of the header value (``".028"`` → 0.001): agreement is to half of
        it plus a relative 1e-6. None: agreement to a relative 5e-3.
    """
    if stated is None or data.size == 0:
        return
    peak = float(np.max(np.abs(data)))
    if resolution is None:
        tolerance = 5e-3 * abs(stated)
    else:
        tolerance = 0.5 * resolution + 1e-6 * abs(stated)
    if abs(peak - abs(stated)) > tolerance:
        warn(
            f"{what}: header peak {stated:g} {units} but the data peak is {peak:g} {units}",
            path,
            line,
        )


def resolution_of(text: str) -> float:
    """Value of the last printed digit of a decimal (``"27.114"`` → 0.001, ``"4"`` → 1).

    Call it on text already checked to be a finite number; the exponent is clamped so that no
    header can make it overflow.
    """
    parts = text.strip().lower().replace("d", "e").split("e")
    mantissa = parts[0]
    decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
    try:
        exponent = int(parts[1]) if len(parts) > 1 else 0
    except ValueError:
        exponent = 0
    power: float = 10.0 ** float(min(max(exponent - decimals, -300), 300))
    return power


def warn(message: str, path: Path, line: int | None = None) -> None:
    """Issue a :class:`FormatWarning` in the one-line ``file:line: message`` shape."""
    where = f"{path}:{line}" if line is not None else str(path)
    warnings.warn(f"{where}: {message}", FormatWarning, stacklevel=3)
