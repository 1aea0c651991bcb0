"""Output safety: text from files is escaped before it reaches a terminal or a spreadsheet.

Header text (station names, event names, comments) comes from files anyone can write. Printed raw,
an ANSI escape sequence in a station name recolours or rewrites the user's terminal; written raw
into a CSV, a cell starting with ``=``, ``+``, ``-`` or ``@`` is run as a formula by spreadsheet
programs (CSV injection). :func:`terminal_safe` escapes control characters; :func:`spreadsheet_safe`
prefixes such cells with a single quote, as the OWASP guidance on CSV injection recommends.
A number printed for people goes through :func:`number_text`, which never prints ``nan``.
"""

from __future__ import annotations

import re
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import pandas as pd

#: C0 and C1 control characters and DEL, except newline and tab (kept: they are layout).
_CONTROL = re.compile(r"[\x00-\x08\x0b-\x1f\x7f-\x9f]")

#: First characters a spreadsheet reads as the start of a formula (OWASP: = + - @, and the tab
#: and carriage return that some programs strip before looking).
_FORMULA_START = ("=", "+", "-", "@", "\t", "\r")


def number_text(value: Any, spec: str, missing: str = "—") -> str:
    """A number for people in the format ``spec``; ``missing`` for what is not a finite number
    (None, NaN, ±inf, text), where Python would print ``nan`` or ``None``."""
    import math

    if not isinstance(value, int | float):
        try:  # numpy scalars
            value = float(value)
        except (TypeError, ValueError):
            return missing
    if not math.isfinite(value):
        return missing
    return format(float(value), spec)


def terminal_safe(text: str) -> str:
    """``text`` with control characters (ESC, BEL, CR, ...) shown as ``\\x1b``-style escapes."""
    return _CONTROL.sub(lambda m: f"\\x{ord(m[0]):02x}", text)


def spreadsheet_cell(value: Any) -> Any:
    """A CSV cell that no spreadsheet runs as a formula: text starting with = + - @ gets a ``'``.

    Numbers are returned unchanged (a negative number is data, not a formula); so is text that
    reads as a number (``"-0.5"``).
    """
    if not isinstance(value, str) or not value.startswith(_FORMULA_START):
        return value
    try:
        float(value)
    except ValueError:
        return "'" + value
    return value


def spreadsheet_safe(frame: pd.DataFrame) -> pd.DataFrame:
    """A copy of ``frame`` whose text cells (and column names) pass :func:`spreadsheet_cell`."""
    from pandas.api.types import is_numeric_dtype

    safe = frame.copy()
    for column in safe.columns:
        if not is_numeric_dtype(safe[column]):
            safe[column] = safe[column].map(spreadsheet_cell)
    safe.columns = [spreadsheet_cell(str(c)) for c in safe.columns]
    safe.attrs = dict(frame.attrs)
    return safe
