"""Records, not files: the components of a candidate table grouped into records.

A *record* is what one station recorded of one event: its horizontal components (and a
vertical, which the selection leaves out unless asked). Catalogues split records across files
(PEER: one AT2 file per component; K-NET/KiK-net: one file per direction) or put several in one
(COSMOS, MiniSEED), so the rows of the features table are grouped by the first rule that names
their record, in this order:

1. ``rsn``: PEER's record sequence number, from an ``rsn`` column (metadata, the AT2 reader) or
   the file name (``RSN8883_14383980_13849090.AT2``, ``RSN174_IMPVALL_H-E11230.AT2``);
2. ``nied``: a K-NET/KiK-net file name, station code and origin time
   (``AOM0011801241951.EW``: station AOM001, origin 2018-01-24 19:51 JST; KiK-net's
   ``NGNH311106302345.EW2``, station NGNH31; KiK-net's borehole
   ``EW1`` and surface ``EW2`` sensors are two records);
3. ``header``: the station and event the file's header (or the metadata) gives;
4. ``file``: otherwise the file alone is the record (its own components, if several).

Each row also gets the event and station that the caps count (:func:`group_records`): those
given, else none (an empty string), and the selection counts a record without an event as its
own event (and without a station as its own station).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import PurePath
from typing import Any

import numpy as np
from numpy.typing import NDArray

from stepframe.records.channels import is_vertical

#: The columns the grouping adds to the candidate table (:func:`.filters.add_grouping`).
COLUMNS: dict[str, tuple[str, str]] = {
    "record": ("", "the record the component belongs to (RSN174, a station and event, a file)"),
    "record_rule": ("", "how its files were grouped: rsn, nied, header or file"),
    "vertical": ("", "a vertical component"),
    "event_key": ("", "the event the caps count (the record's own name when it has none)"),
    "station_key": ("", "the station the caps count (the record's own name when it has none)"),
    "has_event": ("", "the catalogue gives the record's event"),
    "has_station": ("", "the catalogue gives the record's station"),
}

#: The grouping rules, in the order they are tried, and what each says in the output.
RULES: dict[str, str] = {
    "rsn": "PEER record number (RSN)",
    "nied": "K-NET/KiK-net station and origin time",
    "header": "the header's station and event",
    "file": "one file",
}

_RSN_NAME = re.compile(r"(?:^|_)RSN(\d+)(?=[_.\-]|$)", re.IGNORECASE)
_NIED_NAME = re.compile(
    r"^([A-Z]{3,4}\d{2,3})(\d{10})\.(?:EW|NS|UD)([12]?)(?:\.gz)?$", re.IGNORECASE
)
_KIKNET_CHANNEL = re.compile(r"^(?:EW|NS|UD)([12])$", re.IGNORECASE)


def _text(value: Any) -> str:
    """A metadata cell as text, '' for missing (None, NaN, empty)."""
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return ""
    text = str(value).strip()
    return "" if text.lower() in {"nan", "none"} else text


def _rsn(value: Any, file: str) -> int | None:
    text = _text(value)
    if text:
        try:
            return int(float(text))
        except ValueError:
            pass
    match = _RSN_NAME.search(PurePath(file).name)
    return int(match[1]) if match else None


@dataclass(frozen=True)
class Grouping:
    """The records of a candidate table, row by row.

    Attributes
    ----------
    record
        The record's name (``RSN174``, ``AOM001 2018-01-24T10:51:00``, a file).
    rule
        The rule that named it (a key of :data:`RULES`).
    event, station
        The event and station the caps count ('' when the row has none).
    vertical
        Whether the row is a vertical component.
    """

    record: NDArray[np.object_]
    rule: NDArray[np.object_]
    event: NDArray[np.object_]
    station: NDArray[np.object_]
    vertical: NDArray[np.bool_]


def group_records(table: Any) -> Grouping:
    """Group the rows of ``table`` (columns ``file``, ``component``; optional ``station``,
    ``event``, ``rsn``, ``format``) into records by the rules of this module."""
    n = len(table)
    columns = set(table.columns)

    def column(name: str) -> list[Any]:
        return list(table[name]) if name in columns else [None] * n

    files = [str(f) for f in table["file"]]
    channels = [str(c) for c in table["component"]]
    formats = column("format")
    out = {key: np.empty(n, dtype=object) for key in ("record", "rule", "event", "station")}
    rows = zip(
        files, channels, column("rsn"), column("station"), column("event"), formats, strict=True
    )
    for i, (file, channel, rsn_value, station_value, event_value, fmt) in enumerate(rows):
        # the plain-text reader names the station after the file: that is no station
        station = "" if _text(fmt) == "text" else _text(station_value)
        event = _text(event_value)
        sensor = _KIKNET_CHANNEL.match(channel)
        suffix = f" sensor {sensor[1]}" if sensor else ""
        rsn = _rsn(rsn_value, file)
        nied = _NIED_NAME.match(PurePath(file).name)
        if rsn is not None:
            record, rule = f"RSN{rsn}", "rsn"
        elif nied is not None:
            station = station or nied[1].upper()
            event = event or f"{nied[2]} JST"
            record, rule = f"{nied[1].upper()} {nied[2]}{suffix}", "nied"
        elif station and event:
            record, rule = f"{station} / {event}{suffix}", "header"
        else:
            record, rule = file, "file"
        out["record"][i], out["rule"][i] = record, rule
        out["event"][i], out["station"][i] = event, station
    vertical = np.array([is_vertical(c) for c in channels], dtype=bool)
    return Grouping(out["record"], out["rule"], out["event"], out["station"], vertical)


def grouping_summary(table: Any, alive: NDArray[np.bool_] | None = None) -> dict[str, Any]:
    """How the files were grouped (from the table's ``record``, ``record_rule``, ``vertical``
    columns): files, records by rule, the records left with one horizontal component (among
    ``alive`` rows when given), the vertical components."""
    files = table["file"].astype(str)
    record = table["record"].astype(str)
    rules = table["record_rule"].astype(str)
    vertical = table["vertical"].to_numpy(dtype=bool)
    by_rule = {
        rule: int(record[rules == rule].nunique()) for rule in RULES if (rules == rule).any()
    }
    horizontal = ~vertical if alive is None else (~vertical & alive)
    counts = record[horizontal].value_counts()
    single = sorted(str(r) for r in counts.index[counts == 1])
    return {
        "files": int(files.nunique()),
        "components": len(table),
        "records": int(record.nunique()),
        "by_rule": by_rule,
        "single": single,
        "vertical": int(vertical.sum()),
    }


def grouping_line(summary: dict[str, Any]) -> str:
    """The grouping in one line for people."""
    parts = ", ".join(f"{count} by {RULES[rule]}" for rule, count in summary["by_rule"].items())
    single = summary["single"]
    shown = ", ".join(single[:4]) + (" ..." if len(single) > 4 else "")
    line = (
        f"records: {summary['files']} files, {summary['components']} components → "
        f"{summary['records']} records ({parts})"
    )
    if summary["vertical"]:
        line += f"; {summary['vertical']} vertical components"
    return line + (f"; single (one horizontal component): {len(single)}: {shown}" if single else "")
