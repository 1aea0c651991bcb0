"""COSMOS strong-motion format v1.20 (format name ``cosmos``): V0, V1, V2 and their ``c`` variants.

A file holds one or more channels, each with: a text header (line 1 says ``Format v01.20 with 13
text lines``), an integer header and a real header (each announced with its count and Fortran
format), comment lines, then data blocks (``42000 acceleration pts, approx 210 secs,
units=cm/sec2(04),Format=(1E15.6)``) and an ``End-of-data`` line. Header values used (1-based, as
the specification numbers them; -999 means unknown):

- Int(40), Int(42..45): year, month, day, hour, minute of the first sample; Real(30): its seconds;
- Real(22): recorder least significant bit [µV/count]; Real(42): sensor sensitivity [V/g] (used
  only to convert V0 raw counts);
- Real(62): sampling interval of the data [ms]; Real(64): peak of the series, in data units.

Units come from the data block's units text, checked against its code (04 = cm/s², 50 = counts).
Blocks that are not acceleration (velocity, displacement, angles in degrees) are skipped; a
channel with no acceleration block is skipped with a warning.

Complete or refused: every block holds the points it declares and every channel ends with its
end-of-data line (``End-of-data for ...`` or CSMIP's ``/& ... End of data for channel 1``), so a
file cut anywhere inside a channel is refused (read with ``allow_short``, flagged). COSMOS
declares no count of the channels in a file (``(1 Chns of 12 at Sta)`` counts the recorder's
channels, and files of single channels are the rule), so a file cut exactly between two
channels cannot be told from a shorter file.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from stepframe.errors import FormatError
from stepframe.records.formats import ReadOptions, RecordFormat, _header, register
from stepframe.records.formats._text import (
    check_block_end,
    check_count,
    check_peak,
    check_samples,
    file_cut,
    fortran_width,
    mark_incomplete,
    numbers,
    read_lines,
    resolve_units,
    warn,
)
from stepframe.records.units import STANDARD_GRAVITY_M_S2, factor_to_m_s2

if TYPE_CHECKING:
    from obspy import Stream, UTCDateTime

_TEXT_COUNT = re.compile(r"Format\s+v?\s*\d+\.\d+\s+with\s+(\d+)\s+text\s+lines", re.I)
_INT_HEADER = re.compile(r"^\s*(\d+)\s+Integer-header\s+values\s+follow", re.I)
_REAL_HEADER = re.compile(r"^\s*(\d+)\s+Real-header\s+values\s+follow", re.I)
_COMMENTS = re.compile(r"^\s*(\d+)\s+Comment\s+line", re.I)
_DATA = re.compile(r"^\s*(\d+)\s+(.*?)\s+pts,.*?units\s*=\s*([^,(]*?)\s*\(\s*(\d+)\s*\)", re.I)
_END = re.compile(r"end.of.data", re.I)
_SCNL = re.compile(r"<SCNL>\s*([^.\s]*)\.([^.\s]*)\.([^.\s]*)\.(\S*)")
_CODE = re.compile(r"Code:\s*([A-Za-z0-9]+)-(\S+)")
_ORIENTATION = re.compile(r"Sta\s+Cha\w*\s+\S*:\s*(.*?)\s*\(Rcrdr", re.I)
_MAGNITUDE = re.compile(r"\bM([wWlLsSdD]?)\s*=\s*(\d+(?:\.\d+)?)")
#: Physical-units codes whose meaning the readers rely on (specification, table of units).
_UNIT_CODES = {4: "cm/s2", 50: "counts"}
_UNKNOWN = -999.0


@dataclass
class _Block:
    npts: int
    kind: str
    units_text: str
    units_code: int
    values: np.ndarray
    line: int


@dataclass
class _Channel:
    text: list[str]
    ints: np.ndarray
    reals: np.ndarray
    comments: list[str]
    first_line: int
    blocks: list[_Block] = field(default_factory=list)
    #: None, or what a channel cut short lacks (read with ``allow_short``).
    incomplete: str | None = None

    def real(self, number: int) -> float | None:
        """Real(number), 1-based; None when absent or unknown."""
        if number > self.reals.size or self.reals[number - 1] == _UNKNOWN:
            return None
        return float(self.reals[number - 1])

    def integer(self, number: int) -> int | None:
        """Int(number), 1-based; None when absent or unknown."""
        if number > self.ints.size or self.ints[number - 1] == _UNKNOWN:
            return None
        return int(self.ints[number - 1])


def sniff(head: bytes, path: Path) -> bool:
    """True if the first line announces a COSMOS text header and an integer header follows."""
    try:
        text = head.decode("latin-1")
        lines = text.splitlines()
        return bool(lines) and bool(_TEXT_COUNT.search(lines[0])) and "Integer-header" in text
    except Exception:  # a sniffer never raises
        return False


def _expect(pattern: re.Pattern[str], lines: list[str], index: int, what: str, path: Path) -> Any:
    line = lines[index] if index < len(lines) else ""
    match = pattern.search(line)
    if match is None:
        found = repr(line.strip()[:50]) if index < len(lines) else "end of file"
        raise FormatError(f"found {found}, expected {what}", path, index + 1)
    return match


def _parse(lines: list[str], path: Path, options: ReadOptions) -> tuple[list[_Channel], str | None]:
    """The channels of the file, and the note of a file cut inside a channel's header (read
    with ``allow_short``; that channel is lost)."""
    channels: list[_Channel] = []
    i = 0
    while i < len(lines):
        if not lines[i].strip():
            i += 1
            continue
        if channels and not any(_DATA.search(x) for x in lines[i:]):
            where = f"inside the header of channel {len(channels) + 1}"
            return channels, file_cut(where, path, len(lines), options, "whole channels")
        first = i
        n_text = int(_expect(_TEXT_COUNT, lines, i, "a COSMOS text header line 1", path)[1])
        text = lines[i : i + n_text]
        i += n_text
        n_int = int(_expect(_INT_HEADER, lines, i, "'... Integer-header values follow'", path)[1])
        ints, i = numbers(lines, i + 1, path, count=n_int, width=fortran_width(lines[i]))
        check_count(ints, n_int, path, i)
        for value in ints:
            _header.small_integer(value, path, i, "integer header value")
        n_real = int(_expect(_REAL_HEADER, lines, i, "'... Real-header values follow'", path)[1])
        reals, i = numbers(lines, i + 1, path, count=n_real, width=fortran_width(lines[i]))
        check_count(reals, n_real, path, i)
        if not np.all(np.isfinite(reals)):
            raise FormatError("real header value not finite, expected finite numbers", path, i)
        n_comments = int(_expect(_COMMENTS, lines, i, "'... Comment line(s) follow'", path)[1])
        comments = lines[i + 1 : i + 1 + n_comments]
        i += 1 + n_comments
        channel = _Channel(text, ints, reals, comments, first)
        channels.append(channel)
        _expect(_DATA, lines, i, "a data line '<n> acceleration pts, ... units=...'", path)
        while i < len(lines) and (match := _DATA.search(lines[i])):
            npts = _header.sample_count(match[1], path, i + 1, "number of points")
            width = fortran_width(lines[i])
            values, end = numbers(lines, i + 1, path, count=npts, width=width)
            channel.incomplete = check_samples(values.size, npts, path, i + 1, options)
            channel.blocks.append(
                _Block(npts, match[2].strip(), match[3].strip(), int(match[4]), values, i + 1)
            )
            if channel.incomplete is not None:
                return channels, None
            check_block_end(
                lines, end, npts, path, width=width, expected="'End-of-data' or the next block"
            )
            i = end
        if i >= len(lines):
            where = f"before the end-of-data line of channel {len(channels)}"
            channel.incomplete = file_cut(where, path, len(lines), options, "whole channels")
            return channels, None
        if not _END.search(lines[i]):
            raise FormatError(
                f"found {lines[i].strip()[:50]!r}, expected the end-of-data line of channel "
                f"{len(channels)}",
                path,
                i + 1,
            )
        i += 1
    return channels, None


def _identity(channel: _Channel, index: int) -> tuple[str, str, str, str]:
    """(network, station, location, channel) of a channel."""
    for comment in channel.comments:
        if match := _SCNL.search(comment):
            station, code, network, location = match[1], match[2], match[3], match[4]
            return network, station, "" if location == "--" else location, code
    header = "\n".join(channel.text)
    network = station = ""
    if match := _CODE.search(header):
        network, station = match[1], match[2]
    orientation = ""
    if match := _ORIENTATION.search(header):
        orientation = re.sub(r"\s*deg\b", "", match[1], flags=re.I).strip()
    return network, station, "", orientation or str(index + 1)


def _start_time(channel: _Channel, path: Path) -> UTCDateTime:
    parts = [channel.integer(n) for n in (40, 42, 43, 44, 45)]
    seconds = channel.real(30)
    if any(p is None for p in parts) or seconds is None:
        return None
    text = "{}-{}-{} {}:{}".format(*parts)
    return _header.start_time(tuple(parts), seconds, path, channel.first_line + 1, text)


def _units(block: _Block, options: ReadOptions, path: Path) -> str:
    """Canonical units of an acceleration block ("counts" for raw V0 data)."""
    text = block.units_text.lower()
    by_code = _UNIT_CODES.get(block.units_code)
    if text.startswith("count") or by_code == "counts":
        return "counts"
    stated = block.units_text or by_code
    units = resolve_units(stated, options.units, path, block.line)
    if by_code is not None and by_code != units:
        raise FormatError(
            f"units text {block.units_text!r} disagrees with units code {block.units_code:02d} "
            f"({by_code}), expected them to agree",
            path,
            block.line,
        )
    return units


def _is_acceleration(block: _Block) -> bool:
    return "acc" in block.kind.lower() and "deg" not in block.units_text.lower()


def read(path: Path, options: ReadOptions) -> Stream:
    """Read a COSMOS file: one trace per acceleration channel, in m/s².

    Raises
    ------
    FormatError
        A header or data block that does not follow the specification, NPTS disagreeing with the
        data, an unknown unit, or V0 counts without the LSB and sensitivity needed to convert them.
    """
    from obspy import Stream

    from stepframe.records.trace import make_trace

    lines = read_lines(path, "COSMOS", allow_short=options.allow_short)
    traces = []
    channels, cut = _parse(lines, path, options)
    for index, channel in enumerate(channels):
        network, station, location, code = _identity(channel, index)
        blocks = [b for b in channel.blocks if _is_acceleration(b)]
        if not blocks:
            kinds = ", ".join(f"{b.kind} ({b.units_text})" for b in channel.blocks)
            warn(
                f"channel {code} holds {kinds}, not acceleration: skipped",
                path,
                channel.first_line + 1,
            )
            continue
        block = blocks[0]
        dt_ms = channel.real(62)
        if dt_ms is None or not dt_ms > 0:
            if options.dt_s is None:
                raise FormatError(
                    "sampling interval Real(62) unknown, expected it in the real header "
                    "(or give --dt-s)",
                    path,
                    channel.first_line + 1,
                )
            dt_s = options.dt_s
        else:
            dt_s = _header.interval(dt_ms / 1000.0, path, channel.first_line + 1, "Real(62) / 1000")
        units = _units(block, options, path)
        if channel.incomplete is None:  # Real(64): the peak of the data, in the data's units
            check_peak(block.values, channel.real(64), path, f"channel {code}", units=units)
        processing: list[dict[str, Any]] = []
        if units == "counts":
            if options.units is not None:
                raise FormatError(
                    f"data are raw counts but --units {options.units!r} was given, "
                    "expected no --units for a V0 file",
                    path,
                    block.line,
                )
            lsb_uv, volts_per_g = channel.real(22), channel.real(42)
            if lsb_uv is None or volts_per_g is None or lsb_uv <= 0 or volts_per_g <= 0:
                raise FormatError(
                    "raw counts with no recorder LSB (Real(22), µV/count) and sensor sensitivity "
                    "(Real(42), V/g) in the header, expected a calibrated V1/V2 file",
                    path,
                    block.line,
                )
            factor = lsb_uv * 1e-6 / volts_per_g * STANDARD_GRAVITY_M_S2
            processing.append(
                {
                    "step": "counts_to_acceleration",
                    "lsb_uv": lsb_uv,
                    "sensitivity_v_per_g": volts_per_g,
                    "factor_m_s2_per_count": factor,
                }
            )
            mean_m_s2 = float(np.mean(block.values)) * factor
            warn(
                f"channel {code}: raw counts carry an offset of {mean_m_s2:.4g} m/s² "
                "(mean); the commands measure it after the standard processing",
                path,
                block.line,
            )
        else:
            factor = factor_to_m_s2(units)
        magnitude = None
        if len(channel.text) > 2 and (match := _MAGNITUDE.search(channel.text[2])):
            magnitude = _header.number(match[2], path, channel.first_line + 3, "magnitude")
        traces.append(
            make_trace(
                block.values * factor,
                dt_s,
                network=network,
                station=station,
                location=location,
                channel=code,
                starttime=_start_time(channel, path),
                source_file=str(path),
                format="cosmos",
                units_in=units,
                event=channel.text[1].strip() if len(channel.text) > 1 else None,
                magnitude=magnitude,
                processing=processing,
                incomplete=channel.incomplete,
            )
        )
    if not traces:
        raise FormatError("no acceleration channel in the file, expected at least one", path)
    mark_incomplete(traces, cut)
    return Stream(traces)


FORMAT = register(
    RecordFormat(
        name="cosmos",
        sniff=sniff,
        read=read,
        extensions=(".v0", ".v0c", ".v1", ".v1c", ".v2", ".v2c"),
    )
)
