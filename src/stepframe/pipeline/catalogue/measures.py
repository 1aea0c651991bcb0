"""What a data centre's nightly job gives per record: intensity measures, PSA, RotD50, waveforms.

Per component (:func:`component_measures`): PGA, PGV, PGD, Arias intensity, D5-75 and D5-95,
CAV and PGV/PGA (:func:`stepframe.records.intensity.intensity_measures`, exact for a record read
as piecewise linear), and the 5 %-damped PSA at the 21 periods of the NGA-West2 ground-motion
models (:data:`STANDARD_PERIODS_S`, Bozorgnia et al. 2014, Earthquake Spectra 30(3); the exact
Nigam-Jennings recurrence of :func:`stepframe.records.spectra.response_spectrum`). Per pair of
horizontal components of one record (:func:`pair_measures`): RotD50 (Boore 2010) of PGA, PGV,
PGD and of the PSA at the same periods (:func:`stepframe.records.rotd.rotd_spectrum`).

Each is measured on the record after the processing :class:`MeasureOptions` names
(:func:`processed`): ``auto`` (default) applies
:func:`stepframe.records.processing.standard_processing` (offset and trend out, 5 % taper,
high-pass) only to data made from raw counts and not high-passed since, the rule of ``stepframe
records info``; ``standard`` applies it to every record; ``none`` measures the record as read.
The steps applied are a column of each row. The same processed record is what the
``waveforms`` stage writes (:func:`waveform_trace`).

Light at import (numpy and the records area are imported inside the functions), so that the
workflow reader can declare the ``[measures]`` table from :class:`MeasureOptions`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Literal

from stepframe.core.options import Range, check_fields, option

if TYPE_CHECKING:
    from obspy import Trace

#: The 21 oscillator periods [s] of the NGA-West2 ground-motion models (Bozorgnia et al. 2014).
STANDARD_PERIODS_S = (
    0.01,
    0.02,
    0.03,
    0.05,
    0.075,
    0.1,
    0.15,
    0.2,
    0.25,
    0.3,
    0.4,
    0.5,
    0.75,
    1.0,
    1.5,
    2.0,
    3.0,
    4.0,
    5.0,
    7.5,
    10.0,
)

#: Damping of the PSA columns (fraction of critical): the standard 5 %.
PSA_DAMPING = 0.05

#: Rotation-angle step of RotD50 [deg] (Boore 2010 uses 1°).
ROTD_ANGLE_STEP_DEG = 1.0

Processing = Literal["auto", "standard", "none"]


def psa_column(period_s: float) -> str:
    """The column of the PSA [g] at one period: ``psa_0.01s_g``, ``psa_10s_g``
    (:func:`stepframe.records.spectra.psa_column`, imported here when called: this module stays
    light at import)."""
    from stepframe.records.spectra import psa_column as column

    return column(period_s)


@dataclass(frozen=True)
class MeasureOptions:
    """How a record is processed before it is measured (the workflow's ``[measures]`` table,
    which the ``rotd50``, ``waveforms`` and ``arrivals_report`` stages follow too)."""

    processing: Processing = option(
        "auto",
        "before measuring: auto (default: the standard processing for data made from raw "
        "counts and not high-passed, none otherwise), standard (every record: offset and "
        "trend removed, 5 % taper, high-pass) or none (as read)",
        choices=("auto", "standard", "none"),
    )
    highpass_hz: float | None = option(
        None,
        "high-pass corner of the standard processing [Hz] (default 0.1)",
        kind="positive",
        metavar="F",
        valid=Range(0, low_open=True),
    )

    def __post_init__(self) -> None:
        check_fields(self)
        if self.highpass_hz is not None and self.processing == "none":
            from stepframe.errors import InputError

            raise InputError(
                f"highpass_hz = {self.highpass_hz} with processing = 'none', expected processing "
                "'auto' or 'standard' with it (nothing is filtered otherwise)",
                key="highpass_hz",
            )

    @property
    def corner_hz(self) -> float:
        """The high-pass corner [Hz] of the standard processing."""
        from stepframe.records.processing import STANDARD_HIGHPASS_HZ

        return STANDARD_HIGHPASS_HZ if self.highpass_hz is None else self.highpass_hz


def processed(trace: Trace, options: MeasureOptions) -> Trace:
    """A copy of the record after the processing ``options`` names (the steps are recorded in
    its ``stats.stepframe.processing``)."""
    from stepframe.records.processing import needs_standard_processing, standard_processing

    work = trace.copy()
    if options.processing == "standard" or (
        options.processing == "auto" and needs_standard_processing(trace)
    ):
        standard_processing(work, options.corner_hz)
    return work


def _steps_applied(before: Trace, after: Trace) -> tuple[str, float]:
    """The processing steps ``processed`` added, as text, and the high-pass corner [Hz] (NaN)."""
    done = list(after.stats.stepframe.processing)[len(before.stats.stepframe.processing) :]
    corner = next(
        (
            float(s["freqmin_hz"])
            for s in done
            if s.get("step") == "bandpass" and s.get("freqmin_hz")
        ),
        math.nan,
    )
    return ";".join(str(step["step"]) for step in done), corner


#: Column dictionary of the ``measures`` table beyond the context columns: name → (unit, meaning).
def measure_columns() -> dict[str, tuple[str, str]]:
    """The ``measures`` table's columns (unit, meaning), PSA columns included."""
    from stepframe.records.intensity import MEASURES

    columns: dict[str, tuple[str, str]] = {
        "file": ("", "record file, relative to the records folder"),
        "duplicates": ("", "other files with the same bytes (';'-separated), one item"),
        "station": ("", "station name"),
        "component": ("", "channel / component name"),
        "event": ("", "event name (empty if the file does not say)"),
        "dt_s": ("s", "sampling interval"),
        "npts": ("", "number of samples"),
        "processing": ("", "processing steps applied before measuring (empty: none)"),
        "highpass_hz": ("Hz", "high-pass corner applied (empty: none)"),
    }
    columns.update(MEASURES)
    for period in STANDARD_PERIODS_S:
        columns[psa_column(period)] = ("g", f"PSA at T = {period:g} s, 5 % damping")
    columns["processed_utc"] = ("", "start of the run that measured it (UTC)")
    return columns


def component_measures(trace: Trace, options: MeasureOptions) -> dict[str, Any]:
    """One component's row: sampling, processing, intensity measures and PSA [g].

    Parameters
    ----------
    trace
        The record component, in m/s².
    options
        The processing before measuring.
    """
    import numpy as np

    from stepframe.records.intensity import intensity_measures
    from stepframe.records.spectra import response_spectrum

    work = processed(trace, options)
    steps, corner = _steps_applied(trace, work)
    data = np.asarray(work.data, dtype=np.float64)
    dt = float(work.stats.delta)
    spectrum = response_spectrum(data, dt, np.asarray(STANDARD_PERIODS_S), PSA_DAMPING)
    row: dict[str, Any] = {
        "dt_s": dt,
        "npts": int(work.stats.npts),
        "processing": steps,
        "highpass_hz": corner,
        **intensity_measures(data, dt),
    }
    for period, value in zip(STANDARD_PERIODS_S, spectrum.psa_g, strict=True):
        row[psa_column(period)] = float(value)
    return row


def rotd50_columns() -> dict[str, tuple[str, str]]:
    """The ``rotd50`` table's columns (unit, meaning)."""
    columns: dict[str, tuple[str, str]] = {
        "record": ("", "the record, named as the selection names it (RSN8883, station / event)"),
        "files": ("", "the pair's record file(s), relative to the records folder, ';'-separated"),
        "station": ("", "station name"),
        "event": ("", "event name (empty if the files do not say)"),
        "components": ("", "the two horizontal components, h1;h2 (θ = 0 is h1)"),
        "dt_s": ("s", "sampling interval"),
        "npts": ("", "samples compared (the shorter component's)"),
        "processing": ("", "processing steps applied to both before measuring"),
        "pga_rotd50_g": ("g", "RotD50 of the peak ground acceleration"),
        "pgv_rotd50_m_s": ("m/s", "RotD50 of the peak ground velocity"),
        "pgd_rotd50_m": ("m", "RotD50 of the peak ground displacement"),
    }
    for period in STANDARD_PERIODS_S:
        columns[psa_column(period).replace("psa_", "psa_rotd50_")] = (
            "g",
            f"RotD50 PSA at T = {period:g} s, 5 % damping",
        )
    columns["processed_utc"] = ("", "start of the run that measured it (UTC)")
    return columns


def pair_measures(h1: Trace, h2: Trace, options: MeasureOptions) -> dict[str, Any]:
    """RotD50 of PGA, PGV, PGD and of the PSA of two horizontal components of one record.

    RotD50 is the median over rotation angles θ ∈ [0°, 180°) (step
    :data:`ROTD_ANGLE_STEP_DEG`) of the peak of the motion rotated to θ; the rotated velocity
    and displacement are the rotated integrals (integration is linear), so one pair of
    histories serves every angle (:func:`stepframe.records.rotd.rotated_peaks`).

    Raises
    ------
    InputError
        The components are sampled differently.
    """
    import numpy as np

    from stepframe.errors import InputError
    from stepframe.records.integration import displacement_m, velocity_m_s
    from stepframe.records.rotd import rotated_peaks, rotd_spectrum
    from stepframe.records.units import STANDARD_GRAVITY_M_S2

    one, two = processed(h1, options), processed(h2, options)
    dt = float(one.stats.delta)
    if dt != float(two.stats.delta):
        raise InputError(
            f"horizontal components sampled at {one.stats.delta} s and {two.stats.delta} s, "
            "expected the same sampling interval"
        )
    n = min(one.stats.npts, two.stats.npts)
    a1 = np.asarray(one.data[:n], dtype=np.float64)
    a2 = np.asarray(two.data[:n], dtype=np.float64)
    angles = np.deg2rad(np.arange(0.0, 180.0 - 1e-9, ROTD_ANGLE_STEP_DEG))
    spectrum = rotd_spectrum(
        a1, a2, dt, np.asarray(STANDARD_PERIODS_S), PSA_DAMPING, angle_step_deg=ROTD_ANGLE_STEP_DEG
    )
    steps, _ = _steps_applied(h1, one)
    row: dict[str, Any] = {
        "dt_s": dt,
        "npts": int(n),
        "processing": steps,
        "pga_rotd50_g": float(np.median(rotated_peaks(a1, a2, angles))) / STANDARD_GRAVITY_M_S2,
        "pgv_rotd50_m_s": float(
            np.median(rotated_peaks(velocity_m_s(a1, dt), velocity_m_s(a2, dt), angles))
        ),
        "pgd_rotd50_m": float(
            np.median(rotated_peaks(displacement_m(a1, dt), displacement_m(a2, dt), angles))
        ),
    }
    for period, value in zip(STANDARD_PERIODS_S, spectrum.in_g("rotd50"), strict=True):
        row[psa_column(period).replace("psa_", "psa_rotd50_")] = float(value)
    return row


__all__ = [
    "PSA_DAMPING",
    "STANDARD_PERIODS_S",
    "MeasureOptions",
    "component_measures",
    "measure_columns",
    "pair_measures",
    "processed",
    "psa_column",
    "rotd50_columns",
]
