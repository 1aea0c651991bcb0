"""The FEMA P695 text layout of the project's reference data (format name ``fema``).

Lines starting with ``#`` form the header; one of them reads ``NPTS= 4096 DT= 0.01 SEC
PGA_g= 0.509338``. Others give the source, ``RSN 1111, component KOBE/NIS000`` and
``Event: Kobe, Japan 1995 M6.9; Station: Nishi-Akashi (CUE)``. Values follow, in g, five to a line.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from stepframe.errors import FormatError
from stepframe.records.formats import SNIFF_BYTES, ReadOptions, RecordFormat, _header, register
from stepframe.records.formats._text import check_peak, check_samples, resolution_of
from stepframe.records.units import factor_to_m_s2

if TYPE_CHECKING:
    from obspy import Stream

_NPTS_DT = re.compile(r"NPTS\s*=\s*(\S+)\s+DT\s*=\s*(\S+)\s*SEC", re.IGNORECASE)
_PGA = re.compile(r"PGA_g\s*=\s*(\S+)")
_RSN = re.compile(r"RSN\s+(\d+),\s*component\s+(\S+)")
_EVENT = re.compile(r"Event:\s*(.*?);\s*Station:\s*(.*)$")
_MAGNITUDE = re.compile(r"\bM(\d+(?:\.\d+)?)\s*$")


@dataclass(frozen=True)
class FemaText:
    """The parsed content of one FEMA P695 text file (values as written, in g)."""

    values_g: np.ndarray
    dt_s: float
    rsn: int | None
    component: str
    event: str
    station: str
    magnitude: float | None
    header_lines: int
    incomplete: str | None = None


def sniff(head: bytes, path: Path) -> bool:
    """True if the file starts with ``#`` lines containing ``NPTS= ... DT= ... SEC``."""
    try:
        text = head[:SNIFF_BYTES].decode("ascii", errors="replace")
        header = [line for line in text.splitlines() if line.startswith("#")]
        return bool(header) and text.startswith("#") and any(_NPTS_DT.search(h) for h in header)
    except Exception:  # a sniffer never raises
        return False


def parse(path: Path, options: ReadOptions | None = None) -> FemaText:
    """Parse a FEMA P695 text file, checking NPTS (and PGA_g, a warning) against the values.

    Parameters
    ----------
    path
        The file.
    options
        Read options (``allow_short`` accepts fewer values than NPTS, flagged); None: defaults.

    Raises
    ------
    FormatError
        Missing NPTS/DT line, non-numeric value (with its line), or a count other than NPTS.
    """
    try:
        lines = path.read_text(encoding="ascii").splitlines()
    except UnicodeDecodeError as exc:
        raise FormatError("binary or non-ASCII content, expected FEMA P695 text", path) from exc
    npts: int | None = None
    npts_line = 0
    dt_s: float | None = None
    rsn: int | None = None
    component = event = station = ""
    magnitude: float | None = None
    n_header = 0
    pga: tuple[str, int] | None = None
    for number, line in enumerate(lines, start=1):
        if not line.startswith("#"):
            break
        n_header = number
        if match := _NPTS_DT.search(line):
            npts = _header.sample_count(match[1], path, number, "NPTS")
            npts_line = number
            dt_s = _header.interval(match[2], path, number, "DT")
        if match := _PGA.search(line):
            pga = (match[1], number)
        if match := _RSN.search(line):
            rsn, component = int(match[1]), match[2]
        if match := _EVENT.search(line):
            event, station = match[1].strip(), match[2].strip()
            if mag := _MAGNITUDE.search(event):
                magnitude = _header.number(mag[1], path, number, "magnitude")
    if npts is None or dt_s is None:
        raise FormatError("no 'NPTS= n DT= dt SEC' header line, expected one", path)
    values: list[float] = []
    for number, line in enumerate(lines[n_header:], start=n_header + 1):
        try:
            values.extend(float(word) for word in line.split())
        except ValueError as exc:
            raise FormatError(
                f"non-numeric value in {line.strip()[:40]!r}, expected numbers", path, number
            ) from exc
    incomplete = check_samples(len(values), npts, path, npts_line, options or ReadOptions())
    if pga is not None and incomplete is None:
        pga_text, pga_line = pga
        check_peak(
            np.asarray(values, dtype=np.float64),
            _header.number(pga_text, path, pga_line, "PGA_g"),
            path,
            "PGA_g",
            units="g",
            resolution=resolution_of(pga_text),
            line=pga_line,
        )
    return FemaText(
        values_g=np.asarray(values, dtype=np.float64),
        dt_s=dt_s,
        rsn=rsn,
        component=component,
        event=event,
        station=station,
        magnitude=magnitude,
        header_lines=n_header,
        incomplete=incomplete,
    )


def read(path: Path, options: ReadOptions) -> Stream:
    """Read a FEMA P695 text file as a one-trace ``obspy.Stream`` in m/s² (values are in g)."""
    from obspy import Stream

    from stepframe.records.trace import make_trace

    parsed = parse(path, options)
    trace = make_trace(
        parsed.values_g * factor_to_m_s2("g"),
        parsed.dt_s,
        station=parsed.station,
        channel=parsed.component.rsplit("/", 1)[-1],
        source_file=str(path),
        format="fema",
        units_in="g",
        event=parsed.event,
        rsn=parsed.rsn,
        magnitude=parsed.magnitude,
        incomplete=parsed.incomplete,
    )
    return Stream([trace])


FORMAT = register(RecordFormat(name="fema", sniff=sniff, read=read, extensions=(".txt",)))
