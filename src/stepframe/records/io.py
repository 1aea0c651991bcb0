"""``read``: one entry point for every record format (found through the format registry).

A gzip-compressed file (``RSN1.AT2.gz``; data centres often ship them) is read as the file it
holds: it is decompressed to a temporary file with the inner name, and ``source_file`` names the
``.gz``. Units are never guessed: a reader that cannot tell them refuses with a message saying how
to give them.

Hostile input (docs/reliability.md): the file type is checked before anything is opened, so a
FIFO or a device never blocks; standard input (``-``), ``/dev/stdin`` and process substitution
(``<(zcat f.gz)``) are buffered once, then sniffed and read like a file; a file (or a gzip's
content) larger than :data:`MAX_RECORD_BYTES` is refused before it is read; every sample is
checked for plausibility (finite, not all zero, within :data:`MAX_ABS_G` g); and a reader that
fails in a way it did not foresee still gives a one-line error naming the file.
"""

from __future__ import annotations

import errno
import gzip
import os
import select
import stat
import sys
import tempfile
import warnings
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from stepframe.core.memory import check_memory
from stepframe.errors import FormatError, InputError, StepframeError
from stepframe.records.formats import (
    SNIFF_BYTES,
    ReadOptions,
    RecordFormat,
    format_labels,
    registered_formats,
)
from stepframe.records.formats._header import MAX_DT_S, MIN_DT_S
from stepframe.records.units import (
    ACCELERATION_UNITS_TO_M_S2,
    STANDARD_GRAVITY_M_S2,
    normalize_units,
)

if TYPE_CHECKING:
    from obspy import Stream

_GZIP_MAGIC = b"\x1f\x8b"

#: Largest record file read by default [bytes]: far above the largest real accelerogram files
#: (a multi-channel COSMOS V0 or a day of 200 Hz MiniSEED is tens of MB), far below what would
#: exhaust memory once parsed. ``read(..., max_bytes=...)`` overrides it.
MAX_RECORD_BYTES = 256 * 1024**2

#: Largest plausible acceleration [g]: the largest recorded peaks are about 4 g (Iwate-Miyagi
#: 2008); a sample beyond this is a damaged file or wrong units. ``read(..., max_abs_g=None)``
#: turns the check off.
MAX_ABS_G = 100.0

#: How a size refusal says to raise the limit (command line, then Python).
_RAISE_SIZE = "raise the limit with --max-file-mb MB, or max_bytes= in Python"


def _mib(size: int) -> str:
    """``size`` bytes in MiB, for messages (``--max-file-mb`` counts MiB)."""
    return f"{size / 1024**2:.4g} MiB"


#: Peak memory of reading a file in one of the project's text formats, per byte of the file:
#: its text, its lines and its values (2.9 measured on a 228 MB AT2, docs/benchmarks.md).
TEXT_READ_BYTES_PER_BYTE = 3.5
#: The same for a binary format read by obspy: compressed MiniSEED (Steim-2) packs up to 1.75
#: samples in a byte, each then held as an integer and as float64 twice.
BINARY_READ_BYTES_PER_BYTE = 24.0

#: Seconds to wait for the next bytes from a pipe or device before giving up.
STREAM_TIMEOUT_S = 10.0

#: The path that names standard input.
STDIN = "-"


def read(
    path: str | PathLike[str],
    format: str | None = None,
    units: str | None = None,
    dt: float | None = None,
    inventory: str | PathLike[str] | None = None,
    component: str | None = None,
    *,
    max_bytes: int = MAX_RECORD_BYTES,
    max_abs_g: float | None = MAX_ABS_G,
    allow_short: bool = False,
) -> Stream:
    """Read an accelerogram file into an ``obspy.Stream`` of records in m/s².

    Parameters
    ----------
    path
        The file (optionally gzip-compressed); ``"-"`` reads standard input; a pipe such as
        ``/dev/stdin`` or a process substitution is buffered, then read like a file.
    format
        A format name (one of :func:`stepframe.records.formats.format_names`, or any obspy
        waveform format in lower case such as ``"mseed"``, ``"sac"``, ``"knet"``); None sniffs
        the file.
    units
        Units of the values when the file does not state them (``"g"``, ``"m/s2"``,
        ``"cm/s2"``/``"gal"``, ``"mm/s2"``). A file that states units different from these is
        refused.
    dt
        Sampling interval [s] when the file does not state it.
    inventory
        StationXML file for response removal (formats in counts).
    component
        Keep only this channel of a multi-channel file.
    max_bytes
        Largest file (or decompressed gzip content, or piped input) accepted [bytes]; the
        commands' ``--max-file-mb MB`` sets it in MiB.
    max_abs_g
        Largest plausible absolute acceleration [g]; None accepts any finite value; the
        commands' ``--max-abs-g G`` sets it.
    allow_short
        Accept a record with fewer samples than its header declares, or a multi-component file
        missing components (the commands' ``--allow-short``): it is read with a warning and
        flagged in ``stats.stepframe.incomplete`` (what is missing). Refused by default. More
        samples than declared are refused whatever this says.

    Returns
    -------
    obspy.Stream
        One trace per acceleration channel, data in m/s², metadata in ``stats.stepframe``
        (``units_in`` the file's units; ``processing`` any step the format's definition requires;
        ``incomplete`` None, or what a record read with ``allow_short`` lacks).

    Raises
    ------
    InputError
        Missing file, unknown format, units that cannot be determined, a file that does not
        follow its format (among them fewer or more samples than declared, a multi-component
        file missing a component), a file too large, a FIFO or device without data, a sampling
        interval outside [1 µs, 1 s], or samples that are not finite, all zero or beyond
        ``max_abs_g`` (one line naming the file and line).
    """
    from stepframe.core import validation

    display = Path(path)
    max_bytes = validation.integer("max_bytes", max_bytes, low=1)
    if max_abs_g is not None:
        validation.positive("max_abs_g", max_abs_g)
    if dt is not None and not (isinstance(dt, int | float) and dt > 0 and dt < float("inf")):
        raise InputError(f"dt = {dt} s, expected a positive sampling interval")
    if dt is not None:
        validation.in_range("dt", dt, MIN_DT_S, MAX_DT_S, unit="s")
    if not isinstance(allow_short, bool):
        raise InputError(f"allow_short = {allow_short!r}, expected True or False")
    options = ReadOptions(
        units=None if units is None else normalize_units(units),
        dt_s=dt,
        inventory=None if inventory is None else str(inventory),
        component=component,
        allow_short=allow_short,
    )
    if options.inventory is not None and not Path(options.inventory).is_file():
        raise InputError("no such inventory file, expected a StationXML file", options.inventory)
    if str(path) == STDIN:
        display = Path("<stdin>")
        stream = _read_bytes(
            _drain(sys.stdin.fileno(), display, max_bytes), display, format, options, max_bytes
        )
    else:
        kind = _file_kind(display, max_bytes)
        if kind == "stream":
            stream = _read_bytes(
                _read_stream(display, max_bytes), display, format, options, max_bytes
            )
        else:
            with display.open("rb") as handle:
                head = handle.read(SNIFF_BYTES)
            if head.startswith(_GZIP_MAGIC):
                stream = _read_gzip(display, format, options, max_bytes)
            else:
                stream = _read_plain(display, head, format, options)
    _check_agreement(stream, options, display)
    _check_plausible(stream, display, max_abs_g)
    if component is not None:
        stream = stream.select(channel=component)
        if len(stream) == 0:
            raise InputError(
                f"no channel {component!r} in the file, expected an existing one", display
            )
    return stream


def _file_kind(file: Path, max_bytes: int) -> str:
    """``"file"`` or ``"stream"`` (pipe, character device), checked before any ``open``."""
    try:
        info = file.stat()
    except FileNotFoundError:
        raise InputError("no such file, expected an existing record file", file) from None
    except OSError as exc:
        raise InputError(
            f"cannot access ({exc.strerror}), expected a readable file", file
        ) from None
    mode = info.st_mode
    if stat.S_ISDIR(mode):
        raise InputError("is a directory, expected a record file", file)
    if stat.S_ISFIFO(mode) or stat.S_ISCHR(mode):
        return "stream"
    if not stat.S_ISREG(mode):
        raise InputError(
            "not a regular file (socket or block device), expected a record file", file
        )
    from stepframe.core.paths import readable_file

    problem = readable_file(file)
    if problem is not None:
        raise InputError(f"{problem}, expected a record file", file)
    if info.st_size > max_bytes:
        raise InputError(
            f"{info.st_size} bytes ({_mib(info.st_size)}), expected a record file of at most "
            f"{max_bytes} bytes ({_mib(max_bytes)}; {_RAISE_SIZE} if this file is a real record)",
            file,
        )
    return "file"


def _read_stream(file: Path, max_bytes: int) -> bytes:
    """All bytes of a FIFO or device, never blocking: a FIFO without a writer is an error."""
    try:
        fd = os.open(file, os.O_RDONLY | os.O_NONBLOCK)
    except OSError as exc:
        raise InputError(f"cannot open ({exc.strerror}), expected a readable file", file) from None
    try:
        return _drain(fd, file, max_bytes)
    finally:
        os.close(fd)


def _drain(fd: int, file: Path, max_bytes: int) -> bytes:
    """Read ``fd`` to its end (at most ``max_bytes``), waiting at most STREAM_TIMEOUT_S per chunk.

    A pipe whose writer has gone (or that never had one) reads as end of file at once, so a
    named FIFO nobody writes to gives "empty" instead of blocking for ever.
    """
    os.set_blocking(fd, False)
    chunks: list[bytes] = []
    size = 0
    poller = select.poll()
    poller.register(fd, select.POLLIN | select.POLLHUP | select.POLLERR)
    while True:
        try:
            chunk = os.read(fd, 1 << 16)
        except BlockingIOError:
            if not poller.poll(STREAM_TIMEOUT_S * 1000):
                raise InputError(
                    f"no data for {STREAM_TIMEOUT_S:g} s from a pipe or device, expected a "
                    "record file or a pipe that delivers one",
                    file,
                ) from None
            continue
        except OSError as exc:
            if exc.errno == errno.EINTR:
                continue
            raise InputError(
                f"cannot read ({exc.strerror}), expected a readable file", file
            ) from None
        if not chunk:
            break
        size += len(chunk)
        if size > max_bytes:
            raise InputError(
                f"more than {max_bytes} bytes ({_mib(max_bytes)}) from a pipe or device, "
                f"expected a record ({_RAISE_SIZE})",
                file,
            )
        chunks.append(chunk)
    return b"".join(chunks)


def _read_bytes(
    data: bytes, display: Path, format: str | None, options: ReadOptions, max_bytes: int
) -> Any:
    """Read buffered bytes (standard input, a pipe) through a temporary file."""
    if not data:
        raise InputError(
            "empty input (no data, or a FIFO with no writer), expected a record", display
        )
    name = display.name if display.name not in ("", "stdin", "<stdin>") else "stdin"
    if name.isdigit():  # /dev/fd/63 of a process substitution
        name = f"fd{name}"
    with tempfile.TemporaryDirectory(prefix="stepframe-") as folder:
        plain = Path(folder) / name
        plain.write_bytes(data)
        if data.startswith(_GZIP_MAGIC):
            stream = _read_gzip(plain, format, options, max_bytes, display=display)
        else:
            stream = _as_user_file(
                plain, display, lambda: _read_plain(plain, data[:SNIFF_BYTES], format, options)
            )
    for trace in stream:
        trace.stats.stepframe.source_file = str(display)
    return stream


#: Archives by their magic bytes (offset, bytes, name): their members' names and text could
#: pass a text format's check (a stored zip of an AT2 file read as "binary content, expected PEER
#: AT2 text"), so they are named before any format is tried.
ARCHIVES = (
    (0, b"PK\x03\x04", "a zip archive"),
    (0, b"PK\x05\x06", "an empty zip archive"),
    (257, b"ustar", "a tar archive"),
    (0, b"7z\xbc\xaf\x27\x1c", "a 7-Zip archive"),
    (0, b"Rar!\x1a\x07", "a RAR archive"),
    (0, b"BZh", "a bzip2 file"),
    (0, b"\xfd7zXZ\x00", "an xz file"),
)


def archive_kind(head: bytes) -> str | None:
    """What archive the first bytes of a file show, or None."""
    for offset, magic, name in ARCHIVES:
        if head[offset : offset + len(magic)] == magic:
            return name
    return None


def _read_plain(file: Path, head: bytes, format: str | None, options: ReadOptions) -> Stream:
    if not head:
        raise InputError("empty file, expected an accelerogram", file)
    archive = archive_kind(head)
    if archive is not None:
        raise InputError(
            f"{archive}, expected a record file (unpack it: records are read one file each, "
            "plain or .gz)",
            file,
        )
    fmt = format_by_name(format) if format is not None else _sniff(head, file)
    size = file.stat().st_size
    text = fmt.name in registered_formats()
    check_memory(
        size * (TEXT_READ_BYTES_PER_BYTE if text else BINARY_READ_BYTES_PER_BYTE),
        f"reading {size} bytes ({_mib(size)}) as {fmt.name}",
        "a smaller file",
    )
    try:
        return fmt.read(file, options)
    except FormatError as exc:
        _raise_unless_guessed(exc, fmt, format, file)
        raise
    except StepframeError:
        raise
    except MemoryError:
        raise InputError(
            f"out of memory reading it as {fmt.name}, expected a record that fits in memory", file
        ) from None
    except Exception as exc:  # a reader (or obspy's) failing in a way it did not foresee
        detail = " ".join(str(exc).split())[:120]
        raise FormatError(
            f"not readable as {fmt.name} ({type(exc).__name__}: {detail}), expected a valid "
            f"{fmt.name} file",
            file,
        ) from exc


def _as_user_file(plain: Path, file: Path, read_it: Any) -> Stream:
    """Run ``read_it()`` on a temporary copy, naming the user's file in errors and warnings."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            stream = read_it()
        except InputError as exc:
            path = file if exc.path == str(plain) else exc.path
            raise type(exc)(exc.what.replace(str(plain), str(file)), path, exc.line) from None
    for warning in caught:
        message = str(warning.message).replace(str(plain), str(file))
        warnings.warn(message, warning.category, stacklevel=4)
    return stream


def _read_gzip(
    file: Path,
    format: str | None,
    options: ReadOptions,
    max_bytes: int,
    display: Path | None = None,
) -> Any:
    shown = file if display is None else display
    name = shown.name
    inner = name[:-3] if name.lower().endswith(".gz") else name + ".data"
    with tempfile.TemporaryDirectory(prefix="stepframe-") as folder:
        plain = Path(folder) / (inner or "record")
        try:
            with gzip.open(file, "rb") as source, plain.open("wb") as target:
                size = 0
                while chunk := source.read(1 << 20):
                    size += len(chunk)
                    if size > max_bytes:
                        raise InputError(
                            f"decompresses to more than {max_bytes} bytes ({_mib(max_bytes)}), "
                            f"expected a record ({_RAISE_SIZE})",
                            shown,
                        )
                    target.write(chunk)
        except (OSError, EOFError, gzip.BadGzipFile) as exc:
            detail = " ".join(str(exc).split())[:80]
            raise InputError(f"corrupt gzip file ({detail}), expected a whole .gz", shown) from None
        with plain.open("rb") as handle:
            head = handle.read(SNIFF_BYTES)
        stream = _as_user_file(plain, shown, lambda: _read_plain(plain, head, format, options))
    for trace in stream:
        trace.stats.stepframe.source_file = str(shown)
    return stream


def format_by_name(format: str) -> RecordFormat:
    """The reader named ``format`` (a stepframe format, or an obspy format in lower case).

    Raises
    ------
    InputError
        An unknown name, naming the accepted ones (with ``key`` ``format``).
    """
    name = format.lower()
    formats = registered_formats()
    if name in formats:
        return formats[name]
    from stepframe.records.formats.obspy_formats import obspy_format_names, read_with_obspy

    if name in obspy_format_names():
        return RecordFormat(
            name, lambda head, path: False, lambda p, o: read_with_obspy(p, o, name)
        )
    raise InputError(
        f"unknown format {format!r}, expected one of {', '.join(formats)} "
        "or another obspy waveform format in lower case",
        key="format",
    )


def _raise_unless_guessed(
    error: FormatError, fmt: RecordFormat, given: str | None, file: Path
) -> None:
    """Say that the format was a guess when obspy fails on a format only its own check chose:
    its checks take some files that are no record at all for one of its formats (a binary file
    of bytes 0, 1, 2, ... for WIN), and "could not read it as win" alone blamed a WIN file that
    never was. A format the user named keeps the reader's message."""
    from stepframe.records.formats.obspy_formats import ObspyReadFailure

    if given is None and isinstance(error, ObspyReadFailure):
        name = fmt.name.upper()
        raise FormatError(
            f"obspy's check took it for {name} but its reader failed ({error.reason}): a damaged "
            f"{name} file, or no record, expected {format_labels()} or an obspy waveform format "
            "(give it with --format)",
            file,
        ) from None


def _sniff(head: bytes, file: Path) -> RecordFormat:
    for fmt in registered_formats().values():
        if fmt.sniff(head, file):
            return fmt
    raise InputError(
        f"format not recognised, expected {format_labels()} or an obspy waveform format "
        "(give it with --format)",
        file,
    )


def _check_plausible(stream: Stream, file: Path, max_abs_g: float | None) -> None:
    """Refuse samples that no accelerogram has: not finite, all zero, or beyond ``max_abs_g``,
    and a sampling interval outside [MIN_DT_S, MAX_DT_S] (every reader checks it where the
    file states it, naming the line; this is the net under all of them)."""
    for trace in stream:
        data = np.asarray(trace.data, dtype=np.float64)
        name = trace.stats.channel or trace.stats.station or "record"
        channel = f" (channel {name})" if len(stream) > 1 else ""
        if data.size < 2:  # nothing can be measured of one sample (no step, no duration)
            raise FormatError(
                f"{data.size} sample{channel}, expected an accelerogram of at least 2 samples",
                file,
            )
        delta = float(trace.stats.delta)
        if not MIN_DT_S <= delta <= MAX_DT_S:
            raise FormatError(
                f"sampling interval {delta:g} s{channel}, expected an accelerogram's interval "
                f"in [{MIN_DT_S:g}, {MAX_DT_S:g}] s",
                file,
            )
        bad = ~np.isfinite(data)
        if bad.any():
            first = int(np.argmax(bad))
            time_s = first * float(trace.stats.delta)
            raise FormatError(
                f"{int(bad.sum())} NaN/inf samples (first at sample {first}){channel}: sample "
                f"{first} (t = {time_s:g} s) is {data[first]}, expected finite accelerations",
                file,
            )
        if data.size and not np.any(data):
            raise FormatError(
                f"all samples equal 0.0{channel}, expected a varying accelerogram", file
            )
        if max_abs_g is not None and data.size:
            peak_g = float(np.max(np.abs(data))) / STANDARD_GRAVITY_M_S2
            if peak_g > max_abs_g:
                raise FormatError(
                    f"peak {peak_g:.3g} g{channel}, expected at most {max_abs_g:g} g "
                    "(wrong units or a damaged file; --max-abs-g G, or max_abs_g= in Python, "
                    "overrides)",
                    file,
                )


def _same_units(stated: str, given: str) -> bool:
    """Whether two unit names mean the same unit (``gal`` and ``cm/s2`` do)."""
    if stated == given:
        return True
    factors = ACCELERATION_UNITS_TO_M_S2
    return stated in factors and given in factors and factors[stated] == factors[given]


def _check_agreement(stream: Stream, options: ReadOptions, file: Path) -> None:
    """Refuse ``units``/``dt`` options that contradict what the file states.

    Readers use the options only where the file is silent; an option the file contradicts is a
    user error, never silently ignored. So is an inventory no reader used: only a reader that
    converts counts with it records a step naming it (``remove_sensitivity``,
    ``remove_response``); the formats that state their units (AT2, COSMOS, DMG, GeoNet, ESM,
    FEMA text) and plain text never look at it. One rule here, after the reader, rather than
    one refusal per reader.
    """
    if options.inventory is not None and not any(
        "inventory" in step for trace in stream for step in trace.stats.stepframe.processing
    ):
        formats = sorted({str(trace.stats.stepframe.format) for trace in stream})
        raise InputError(
            f"--inventory {options.inventory} given but the {'/'.join(formats)} reader does not "
            "use one (the file states its units, or --units gives them), expected no "
            "--inventory (a StationXML converts raw counts: MiniSEED, SAC, ...)",
            file,
        )
    for trace in stream:
        stated_units = trace.stats.stepframe.units_in
        if options.units is not None and not _same_units(stated_units, options.units):
            raise InputError(
                f"file states units {stated_units!r} but --units {options.units!r} was given, "
                "expected them to agree (omit --units)",
                file,
            )
        delta = float(trace.stats.delta)
        if options.dt_s is not None and abs(delta - options.dt_s) > 1e-9 * delta:
            raise InputError(
                f"file states dt = {delta:g} s but --dt-s {options.dt_s:g} was given, "
                "expected them to agree (omit --dt-s)",
                file,
            )


def read_measured(path: str | PathLike[str], **options: Any) -> Stream:
    """:func:`read`, then each trace as every output measures it: a record made from raw counts
    after the standard processing (:func:`stepframe.records.processing.measured`, with its
    warning). What a selection ranks, simulates and writes out, and what the workflow's stages
    measure, come from here (a COSMOS V0 record, a constant -0.89 g of sensor offset as read,
    was ranked first and written out as a chosen motion)."""
    from stepframe.records.processing import measured_stream

    return measured_stream(read(path, **options))
