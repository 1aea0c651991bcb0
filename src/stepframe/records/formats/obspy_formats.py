"""Waveform formats read through ``obspy.read`` (MiniSEED, SAC, K-NET/KiK-net, Kinemetrics EVT...).

obspy is always called with an explicit format name, never left to guess: its guessing includes
the PICKLE format, and the project never unpickles a user's file. Sniffing calls obspy's own
format checks one by one, PICKLE excluded.

Units, in this order:

1. K-NET/KiK-net (``knet``, ``kiknet``): NIED's definition. Values are counts times the header's
   ``Scale Factor 3920(gal)/6182761``, minus the record mean (NIED's stated ``Max. Acc.`` is after
   that removal); both are recorded as processing steps.
2. An ``inventory`` (StationXML): the response is removed to acceleration. For accelerometers
   (response input in m/s²) by the overall sensitivity (``remove_sensitivity``, flat in the
   sensor's band); otherwise by the full response (``remove_response``, output ACC, water level
   60 dB). The step and its values are recorded.
3. ``units`` given by the user (data already calibrated).
4. What the format states: SAC ``idep`` = IACC (nm/s²); Kinemetrics EVT counts with the header's
   full scale [V], A/D bits and sensitivity [V/g].
5. Otherwise the record is refused with a message saying how to give the units.
"""

from __future__ import annotations

import io
import re
import warnings
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from stepframe.errors import FormatError, InputError
from stepframe.records.formats import OBSPY_PRIORITY, ReadOptions, RecordFormat, _header, register
from stepframe.records.formats._text import (
    check_peak,
    check_samples,
    drop_cut_value,
    file_cut,
    mark_incomplete,
)
from stepframe.records.units import STANDARD_GRAVITY_M_S2, factor_to_m_s2, normalize_units

if TYPE_CHECKING:
    from obspy import Stream, Trace

#: obspy waveform formats offered by name, in sniffing order (obspy's own order, PICKLE removed).
OBSPY_FORMATS = (
    "mseed",
    "sac",
    "gse2",
    "seisan",
    "q",
    "sh_asc",
    "slist",
    "tspair",
    "y",
    "seg2",
    "segy",
    "su",
    "sacxy",
    "gcf",
    "reftek130",
    "css",
    "nnsa_kb_core",
    "win",
    "kinemetrics_evt",
    "knet",
    "ah",
    "pdas",
    "rg16",
    "dmx",
    "wav",
)
_NEVER = {"PICKLE"}
_SCALE = re.compile(r"Scale\s+Factor\s+([\d.eE+-]+)\s*\(gal\)\s*/\s*([\d.eE+-]+)", re.I)
#: K-NET/KiK-net header lines declaring the sampling rate and the record length: the file
#: holds Sampling Freq × Duration Time samples (checked on every NIED file of gmprocess's and
#: obspy's test data: 48 files, 5900 to 28600 samples).
_KNET_FREQ = re.compile(r"^Sampling Freq\(Hz\)[ \t]+(\S*?)\s*Hz[ \t]*\r?$", re.M)
_KNET_DURATION = re.compile(r"^Duration Time\(s\)[ \t]+(\S+)[ \t]*\r?$", re.M)
#: obspy's warning when a MiniSEED file ends inside a record (a cut file).
_MSEED_CUT = re.compile(r"Unexpected end of file", re.I)
#: SAC ``idep`` codes (SAC manual, header variables): 8 = IACC in nm/s².
_SAC_IDEP = {5: "unknown", 6: "displacement (nm)", 7: "velocity (nm/s)", 50: "volts"}
#: KiK-net file names end in the component and 1 (borehole) or 2 (surface): ``.EW2``.
_KIKNET_SUFFIX = re.compile(r"\.(EW|NS|UD)[12](\.gz)?$", re.I)
_ACCELERATION_INPUT_UNITS = {"M/S**2", "M/S/S", "M/S2", "M/SEC**2", "M/S^2"}


class ObspyReadFailure(FormatError):
    """obspy raised while reading a file as ``name``, for ``reason`` (its message's first line).

    When the format was obspy's own guess, the guess may be what was wrong: its WIN check takes
    many binary files (bytes 0, 1, 2, ...) for WIN, and the reader then fails with ``[Errno 22]
    Invalid argument``.
    """

    def __init__(self, name: str, reason: str, path: str | PathLike[str]) -> None:
        self.format_name, self.reason = name, reason
        super().__init__(f"obspy could not read it as {name}: {reason}", path)


def _is_format(obspy_name: str, path: Path) -> bool:
    """obspy's own check of ``path`` for one format; False on any failure."""
    try:
        from obspy.core.util.base import ENTRY_POINTS
        from obspy.core.util.misc import buffered_load_entry_point

        entry = ENTRY_POINTS["waveform"][obspy_name.upper()]
        check = buffered_load_entry_point(
            entry.dist.name, f"obspy.plugin.waveform.{entry.name}", "isFormat"
        )
        return bool(check(str(path)))
    except Exception:  # a sniffer never raises
        return False


def _sniffer(name: str) -> Any:
    def sniff(head: bytes, path: Path) -> bool:
        return _is_format(name, path)

    sniff.__doc__ = f"obspy's check for {name.upper()} (never raises)."
    return sniff


def obspy_format_names() -> list[str]:
    """Lower-case names of every waveform format the installed obspy reads, PICKLE excluded."""
    from obspy.core.util.base import ENTRY_POINTS

    return [n.lower() for n in ENTRY_POINTS["waveform"] if n.upper() not in _NEVER]


def _obspy_read(path: Path, name: str, options: ReadOptions) -> tuple[Any, str | None]:
    """The stream obspy reads, and a note when the file was cut short (read with
    ``allow_short``: a MiniSEED file ending inside a record, which obspy only warns about)."""
    import obspy

    if name.upper() in _NEVER:
        raise InputError(f"format {name!r} is never read (it unpickles), expected another", path)
    obspy_name = "knet" if name == "kiknet" else name
    source: Any = str(path)
    if options.allow_short and obspy_name == "knet":
        # A cut K-NET file may end inside a number (``-12085`` cut to ``-``): drop that value.
        source = io.BytesIO(drop_cut_value(path.read_bytes()))
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            stream = obspy.read(source, format=obspy_name.upper())
    except Exception as exc:
        reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise ObspyReadFailure(name, reason, path) from None
    note = None
    for warning in caught:
        text = " ".join(str(warning.message).split())
        if not _MSEED_CUT.search(text):
            warnings.warn(text, warning.category, stacklevel=2)
            continue
        note = file_cut("inside a MiniSEED record", path, None, options, "whole records")
    return stream, note


def _knet_sampling(path: Path, head: str, trace: Trace, options: ReadOptions) -> str | None:
    """Check a K-NET/KiK-net record's sampling rate and sample count against its header.

    Returns the incomplete note of a short record read with ``allow_short`` (else None).

    Raises
    ------
    FormatError
        A rate outside the accelerograph range (1 Hz to 1 MHz: an interval in [1 µs, 1 s]),
        one obspy read differently, or fewer (without ``allow_short``) or more samples than
        Sampling Freq × Duration Time.
    """
    freq = _KNET_FREQ.search(head)
    duration = _KNET_DURATION.search(head)
    if freq is None or duration is None:
        raise FormatError(
            "no 'Sampling Freq(Hz) <n>Hz' and 'Duration Time(s) <s>' header lines, expected both",
            path,
        )
    freq_line = head[: freq.start()].count("\n") + 1
    rate_hz = _header.number(
        freq[1],
        path,
        freq_line,
        "Sampling Freq(Hz)",
        low=1.0 / _header.MAX_DT_S,
        high=1.0 / _header.MIN_DT_S,
        kind="positive number",
    )
    if abs(float(trace.stats.sampling_rate) - rate_hz) > 1e-9 * rate_hz:
        raise FormatError(
            f"Sampling Freq(Hz) {freq[1]!r} read as {trace.stats.sampling_rate:g} Hz, "
            "expected a whole number of Hz",
            path,
            freq_line,
        )
    duration_line = head[: duration.start()].count("\n") + 1
    duration_s = _header.number(
        duration[1], path, duration_line, "Duration Time(s)", low=0.0, high=1e7
    )
    declared = round(rate_hz * duration_s)
    what = f"Sampling Freq × Duration Time ({rate_hz:g} Hz × {duration_s:g} s)"
    return check_samples(int(trace.stats.npts), declared, path, duration_line, options, what)


def _nied(
    trace: Trace, path: Path, options: ReadOptions
) -> tuple[np.ndarray, str, list[Any], str | None]:
    if options.units is not None or options.inventory is not None:
        raise FormatError(
            "K-NET/KiK-net values are defined by the header's scale factor, "
            "expected no --units or --inventory",
            path,
        )
    head = path.read_bytes()[:2048].decode("latin-1")
    incomplete = _knet_sampling(path, head, trace, options)
    match = _SCALE.search(head)
    if match is None:
        raise FormatError("no 'Scale Factor <gal>(gal)/<counts>' line, expected one", path)
    gal_per_count = float(match[1]) / float(match[2])
    data_gal = np.asarray(trace.data, dtype=np.float64) * gal_per_count
    mean_gal = float(np.mean(data_gal))
    data_gal = data_gal - mean_gal
    accmax = trace.stats.knet.get("accmax") if hasattr(trace.stats, "knet") else None
    if accmax is not None and incomplete is None:
        check_peak(data_gal, float(accmax), path, "Max. Acc. (gal)", units="gal", resolution=0.001)
    m_s2_per_gal = factor_to_m_s2("gal")
    steps = [
        {"step": "nied_scale_factor", "gal_per_count": gal_per_count},
        {"step": "remove_mean", "mean_m_s2": mean_gal * m_s2_per_gal, "reason": "NIED definition"},
    ]
    return data_gal * m_s2_per_gal, "gal", steps, incomplete


def _inventory(trace: Trace, inventory: Any, inventory_path: str) -> tuple[np.ndarray, list[Any]]:
    try:
        response = inventory.get_response(trace.id, trace.stats.starttime)
    except Exception:
        raise InputError(
            f"no response for {trace.id} at {trace.stats.starttime} in the inventory, "
            "expected a StationXML with that channel",
            inventory_path,
        ) from None
    sensitivity = response.instrument_sensitivity
    input_units = str(getattr(sensitivity, "input_units", "") or "").upper()
    work = trace.copy()
    work.data = np.asarray(work.data, dtype=np.float64)
    if input_units in _ACCELERATION_INPUT_UNITS:
        work.remove_sensitivity(inventory)
        step = {
            "step": "remove_sensitivity",
            "inventory": inventory_path,
            "sensitivity_counts_per_m_s2": float(sensitivity.value),
            "frequency_hz": float(sensitivity.frequency),
        }
    else:
        work.remove_response(inventory=inventory, output="ACC", water_level=60.0)
        step = {
            "step": "remove_response",
            "inventory": inventory_path,
            "output": "ACC",
            "water_level_db": 60.0,
            "input_units": input_units,
        }
    return np.asarray(work.data, dtype=np.float64), [step]


def _stated(trace: Trace, path: Path) -> tuple[np.ndarray, str, list[Any]] | None:
    """Data in m/s² from the units the format itself states, or None if it states none."""
    data = np.asarray(trace.data, dtype=np.float64)
    if hasattr(trace.stats, "sac"):
        idep = trace.stats.sac.get("idep")
        if idep == 8:
            return data * factor_to_m_s2("nm/s2"), "nm/s2", []
        if idep in (6, 7, 50):
            raise FormatError(
                f"SAC idep says {_SAC_IDEP[idep]}, expected acceleration "
                "(for counts or volts give --inventory)",
                path,
            )
        return None
    if hasattr(trace.stats, "kinemetrics_evt"):
        header = trace.stats.kinemetrics_evt
        fullscale_v = float(header.get("chan_fullscale", 0) or 0)
        volts_per_g = float(header.get("chan_sensitivity", 0) or 0)
        bits = int(header.get("a2dbits", 24) or 24)
        if fullscale_v <= 0 or volts_per_g <= 0:
            return None
        factor = fullscale_v / 2.0 ** (bits - 1) / volts_per_g * STANDARD_GRAVITY_M_S2
        step = {
            "step": "counts_to_acceleration",
            "fullscale_v": fullscale_v,
            "a2d_bits": bits,
            "sensitivity_v_per_g": volts_per_g,
            "factor_m_s2_per_count": factor,
        }
        return data * factor, "counts", [step]
    return None


def read_with_obspy(path: Path, options: ReadOptions, name: str) -> Stream:
    """Read ``path`` with obspy as format ``name`` and convert every trace to m/s².

    Raises
    ------
    FormatError
        obspy cannot read the file, or a trace's units cannot be determined (the message says how
        to give them: ``--inventory`` for counts, ``--units`` for calibrated data).
    InputError
        An unreadable inventory, or one without the trace's channel.
    """
    from obspy import Stream

    from stepframe.records.trace import make_trace

    stream, cut = _obspy_read(path, name, options)
    inventory = None
    if options.inventory is not None:
        import obspy

        try:
            inventory = obspy.read_inventory(options.inventory)
        except Exception as exc:
            reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            raise InputError(
                f"not a readable StationXML inventory ({reason}), expected one",
                options.inventory,
            ) from None
    traces = []
    for trace in stream:
        kind = str(trace.stats.get("_format", name)).upper()
        incomplete = None
        if kind == "KNET":
            data_m_s2, units_in, steps, incomplete = _nied(trace, path, options)
        elif inventory is not None and options.inventory is not None:
            if options.units is not None:
                raise InputError(
                    "both --inventory and --units given, expected one: --inventory for counts, "
                    "--units for calibrated values",
                    path,
                )
            data_m_s2, steps = _inventory(trace, inventory, options.inventory)
            units_in = "counts"
        elif options.units is not None:
            stated = _stated(trace, path)
            units_in = normalize_units(options.units)
            if stated is not None and stated[1] != units_in:
                raise FormatError(
                    f"file states {stated[1]} but --units {options.units!r} was given, "
                    "expected them to agree (omit --units)",
                    path,
                )
            data_m_s2 = np.asarray(trace.data, dtype=np.float64) * factor_to_m_s2(units_in)
            steps = []
        else:
            stated = _stated(trace, path)
            if stated is None:
                raise FormatError(
                    f"units of {trace.id} unknown (raw counts?), expected --inventory "
                    "STATIONXML to remove the response, or --units (g, m/s2, cm/s2, mm/s2) "
                    "if the values are already acceleration",
                    path,
                )
            data_m_s2, units_in, steps = stated
        trace_format = name
        if kind == "KNET" and (name == "kiknet" or _KIKNET_SUFFIX.search(path.name)):
            trace_format = "kiknet"
        traces.append(
            make_trace(
                data_m_s2,
                float(trace.stats.delta),
                network=trace.stats.network,
                station=trace.stats.station,
                location=trace.stats.location,
                channel=trace.stats.channel,
                starttime=trace.stats.starttime,
                source_file=str(path),
                format=trace_format,
                units_in=units_in,
                magnitude=_magnitude(trace),
                processing=steps,
                incomplete=incomplete,
                **_nied_event(trace),
            )
        )
    mark_incomplete(traces, cut)
    return Stream(traces)


def _nied_event(trace: Trace) -> dict[str, Any]:
    """K-NET/KiK-net headers: the event as its origin time (UTC, ISO 8601: the one event key
    of NIED's files) and the epicentral distance [km] from the event's and station's
    coordinates (WGS84 geodesic)."""
    header = trace.stats.get("knet")
    if header is None or header.get("evot") is None:
        return {}
    out: dict[str, Any] = {"event": header["evot"].isoformat()}
    coordinates = [header.get(k) for k in ("evla", "evlo", "stla", "stlo")]
    if all(isinstance(v, int | float) for v in coordinates):
        from obspy.geodetics import gps2dist_azimuth

        distance_m = gps2dist_azimuth(*coordinates)[0]
        out["repi_km"] = float(distance_m) / 1000.0
    return out


def _magnitude(trace: Trace) -> float | None:
    if hasattr(trace.stats, "knet"):
        value = trace.stats.knet.get("mag")
        return None if value is None else float(value)
    return None


def _reader(name: str) -> Any:
    def read(path: Path, options: ReadOptions) -> Stream:
        return read_with_obspy(path, options, name)

    read.__doc__ = f"Read a {name.upper()} file through obspy, in m/s²."
    return read


def _register_all() -> None:
    for name in OBSPY_FORMATS:
        register(
            RecordFormat(name=name, sniff=_sniffer(name), read=_reader(name)),
            priority=OBSPY_PRIORITY,
        )
    # KiK-net files are K-NET's layout; the name is offered so users can say what they have.
    register(
        RecordFormat(name="kiknet", sniff=lambda head, path: False, read=_reader("kiknet")),
        priority=OBSPY_PRIORITY,
    )


_register_all()
