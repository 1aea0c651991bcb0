"""A record's components described, and their response spectra with RotD.

What ``stepframe records info`` prints (:func:`record_info`: sampling, units and intensity
measures of each component), and what ``stepframe records spectrum`` prints and draws: PSA [g],
PSV [m/s] and SD [m] of each component (:func:`stepframe.records.spectra.response_spectrum`)
and, with exactly two horizontal components, their geometric mean, RotD50 and RotD100
(:mod:`stepframe.records.rotd`). Light at import (the command line reads
:class:`SpectrumOptions` for its help).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from os import PathLike
from typing import TYPE_CHECKING, Any

from stepframe.core.options import Range, check_fields, option
from stepframe.errors import InputError
from stepframe.records.channels import is_vertical

if TYPE_CHECKING:
    from matplotlib.figure import Figure
    from numpy.typing import ArrayLike
    from obspy import Trace


def record_info(traces: Sequence[Trace], file: str | PathLike[str] = "") -> list[dict[str, Any]]:
    """One row per component: file, station, component, npts, dt [s], duration [s], the units
    in the file, ``incomplete`` (None, or what a record read short lacks), and the intensity
    measures of
    :func:`stepframe.records.intensity.trace_intensity_measures` (PGA in g only; a record made
    from raw counts is measured after the stated standard processing, with a warning)."""
    from stepframe.records.intensity import trace_intensity_measures

    rows = []
    for trace in traces:
        dt = float(trace.stats.delta)
        measures = trace_intensity_measures(trace)
        rows.append(
            {
                "file": str(file),
                "station": trace.stats.station,
                "component": trace.stats.channel,
                "npts": int(trace.stats.npts),
                "dt_s": dt,
                "duration_s": dt * (int(trace.stats.npts) - 1),
                "units_in": trace.stats.stepframe.units_in,
                "incomplete": trace.stats.stepframe.get("incomplete"),
                **{key: value for key, value in measures.items() if key != "pga_m_s2"},
            }
        )
    return rows


def info_text(rows: Sequence[Mapping[str, Any]]) -> str:
    """:func:`record_info` rows as text, one line per component."""
    return "\n".join(
        # a plain-text record has no channel name: "acc.txt acc:", not "acc.txt acc :"
        " ".join(str(r[key]) for key in ("file", "station", "component") if r[key])
        + f": {r['npts']} samples at {r['dt_s']} s, "
        f"units {r['units_in']}, PGA {r['pga_g']:.4g} g, PGV {r['pgv_m_s']:.4g} m/s, "
        f"PGD {r['pgd_m']:.4g} m, Arias {r['arias_m_s']:.4g} m/s, D5-95 {r['d5_95_s']:.4g} s"
        + (f", INCOMPLETE ({r['incomplete']})" if r.get("incomplete") else "")
        for r in rows
    )


@dataclass(frozen=True)
class SpectrumOptions:
    """The oscillators of :func:`record_spectra` (its ``periods_s`` and ``damping``)."""

    periods_s: Sequence[float] | None = option(
        None,
        "oscillator periods [s]",
        kind="floats",
        metavar="T1,T2,...",
        valid=Range(1e-3, 1e4),  # records.spectra.PERIOD_RANGE_S
    )
    damping: float = option(
        0.05,
        "damping ratio as a fraction (default 0.05)",
        kind="float",
        metavar="ZETA",
        valid=Range(0, 1, high_open=True),
    )

    def __post_init__(self) -> None:
        check_fields(self)


def record_spectra(
    traces: Sequence[Trace], periods_s: ArrayLike | None = None, damping: float = 0.05
) -> dict[str, Any]:
    """Response spectra of every component; geometric mean and RotD of two horizontal ones.

    Parameters
    ----------
    traces
        Record components (``obspy.Trace`` in m/s²); two horizontal ones (vertical channels are
        recognised by name) also give ``geomean_g``, ``rotd50_g`` and ``rotd100_g``.
    periods_s
        Oscillator periods [s] (default :data:`stepframe.records.spectra.DEFAULT_PERIODS_S`).
    damping
        Damping ratio (fraction).

    Returns
    -------
    dict
        ``period_s``, ``damping``, ``components`` (each: ``component``, ``station``, ``psa_g``,
        ``psv_m_s``, ``sd_m``) and, for two horizontals, ``h1``, ``h2`` and the combined spectra.
    """
    import numpy as np

    from stepframe.records.spectra import DEFAULT_PERIODS_S, response_spectrum

    periods = np.asarray(DEFAULT_PERIODS_S if periods_s is None else periods_s, dtype=float)
    horizontal = [t for t in traces if not is_vertical(t.stats.channel)]
    if len(horizontal) == 2:
        check_one_record(*horizontal)  # before the work: refused, it would be wasted
    components = []
    for trace in traces:
        result = response_spectrum(trace.data, float(trace.stats.delta), periods, damping)
        components.append(
            {
                "component": trace.stats.channel,
                "station": trace.stats.station,
                "psa_g": result.psa_g,
                "psv_m_s": result.psv_m_s,
                "sd_m": result.sd_m,
                # a record read cut short (allow_short) says so in every output made from it
                **(
                    {"incomplete": str(trace.stats.stepframe.incomplete)}
                    if trace.stats.get("stepframe", {}).get("incomplete")
                    else {}
                ),
            }
        )
    data: dict[str, Any] = {
        "period_s": periods,
        "damping": damping,
        "components": components,
    }
    if len(horizontal) == 2:
        from stepframe.records.rotd import rotd_spectrum

        h1, h2 = horizontal
        rotd = rotd_spectrum(h1.data, h2.data, float(h1.stats.delta), periods, damping)
        data.update(
            h1=h1.stats.channel,
            h2=h2.stats.channel,
            geomean_g=rotd.in_g("geomean"),
            rotd50_g=rotd.in_g("rotd50"),
            rotd100_g=rotd.in_g("rotd100"),
        )
    return data


def check_one_record(h1: Trace, h2: Trace) -> None:
    """Refuse two components that are not of one record: combined into a geometric mean or
    RotD, they would describe no ground motion.

    A record is what the selection groups components by
    (:func:`stepframe.pipeline.selection.grouping.group_records`: PEER's RSN, a K-NET/KiK-net
    station and origin time, the header's station and event); components it names as different
    records are refused. Components it cannot name (plain text: each file is its own record)
    are taken as the user gives them, but they must still share the sampling interval, and two
    with a stated start time must overlap in time (two days of one station are two records).

    Raises
    ------
    InputError
        Different records, sampling intervals or time windows (naming both components).
    """
    import pandas as pd

    from stepframe.pipeline.selection.grouping import group_records

    def name(trace: Trace) -> str:
        file = trace.stats.stepframe.get("source_file") or ""
        return f"{file} {trace.stats.channel}".strip()

    pair = f"{name(h1)} and {name(h2)}"
    if float(h1.stats.delta) != float(h2.stats.delta):
        raise InputError(
            f"horizontal components {pair} sampled at {h1.stats.delta} s and "
            f"{h2.stats.delta} s, expected the same sampling interval (one record)"
        )
    table = pd.DataFrame(
        [
            {
                "file": trace.stats.stepframe.get("source_file") or "",
                "component": trace.stats.channel,
                "station": trace.stats.station,
                "event": trace.stats.stepframe.get("event"),
                "rsn": trace.stats.stepframe.get("rsn"),
                "format": trace.stats.stepframe.get("format"),
            }
            for trace in (h1, h2)
        ]
    )
    grouping = group_records(table)
    named = all(rule != "file" for rule in grouping.rule)
    if named and grouping.record[0] != grouping.record[1]:
        raise InputError(
            f"horizontal components {pair} are of two records ({grouping.record[0]} and "
            f"{grouping.record[1]}), expected two components of one record"
        )
    from obspy import UTCDateTime

    # Readers leave the start at epoch 0 where the format states none (AT2, FEMA text).
    starts = [trace.stats.starttime for trace in (h1, h2)]
    if all(start != UTCDateTime(0) for start in starts):
        ends = [trace.stats.endtime for trace in (h1, h2)]
        if starts[0] > ends[1] or starts[1] > ends[0]:
            raise InputError(
                f"horizontal components {pair} recorded {starts[0]} to {ends[0]} and "
                f"{starts[1]} to {ends[1]}, expected overlapping times (one record)"
            )


def spectra_figure(data: Mapping[str, Any], record: str | Sequence[str] | None = None) -> Figure:
    """The PSA of each component (and RotD50/RotD100) of :func:`record_spectra`'s result.

    ``record`` names the record in the title: one file name, or one per component.
    """
    from stepframe.records.plots import response_spectra_figure

    combined = {
        name: data[key]
        for key, name in (("rotd50_g", "RotD50"), ("rotd100_g", "RotD100"))
        if key in data
    }
    return response_spectra_figure(
        data["period_s"],
        {c["component"]: c["psa_g"] for c in data["components"]},
        damping=data["damping"],
        record=record,
        combined_g=combined,
    )


def spectra_text(data: Mapping[str, Any]) -> str:
    """:func:`record_spectra`'s result as a text table (PSA [g] per period)."""
    names = [c["component"] for c in data["components"]]
    header = ["period_s"] + [f"psa_g[{n}]" for n in names]
    columns = [data["period_s"]] + [c["psa_g"] for c in data["components"]]
    for key in ("geomean_g", "rotd50_g", "rotd100_g"):
        if key in data:
            header.append(key)
            columns.append(data[key])
    lines = [f"damping {data['damping']}", "  ".join(f"{h:>12}" for h in header)]
    for i in range(len(data["period_s"])):
        lines.append("  ".join(f"{float(col[i]):12.5g}" for col in columns))
    lines += [
        f"INCOMPLETE {c['component']}: {c['incomplete']} (read cut short: its spectrum lacks "
        "what is missing)"
        for c in data["components"]
        if c.get("incomplete")
    ]
    return "\n".join(lines)


__all__ = [
    "check_one_record",
    "info_text",
    "record_info",
    "record_spectra",
    "spectra_figure",
    "spectra_text",
]
