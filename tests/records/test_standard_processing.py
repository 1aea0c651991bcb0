"""Intensity measures of raw counts: the stated standard processing, checked against obspy's own
detrend/taper/filter chain computed independently (CE.68150 MiniSEED + StationXML)."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import cumulative_trapezoid

from stepframe.records import read
from stepframe.records.intensity import ProcessingWarning, trace_intensity_measures
from stepframe.records.processing import bandpass, needs_standard_processing

DATA = Path(__file__).resolve().parents[1] / "data" / "formats" / "miniseed"
MSEED = DATA / "CE.68150.unprocessed_counts.mseed"
XML = DATA / "CE.68150.stationxml.xml"


def _obspy_chain() -> dict[str, dict[str, float]]:
    """PGA, PGV, PGD by obspy alone: sensitivity removed, demean, linear detrend, 5 % Hann
    taper, 4-corner zero-phase Butterworth high-pass at 0.1 Hz; trapezoidal integration."""
    import obspy

    stream = obspy.read(str(MSEED))
    stream.remove_sensitivity(obspy.read_inventory(str(XML)))
    out = {}
    for trace in stream:
        trace.data = trace.data.astype(np.float64)
        trace.detrend("demean")
        trace.detrend("linear")
        trace.taper(max_percentage=0.05, type="hann")
        trace.filter("highpass", freq=0.1, corners=4, zerophase=True)
        dt = trace.stats.delta
        vel = cumulative_trapezoid(trace.data, dx=dt, initial=0.0)
        disp = cumulative_trapezoid(vel, dx=dt, initial=0.0)
        out[trace.id] = {
            "pga_m_s2": float(np.abs(trace.data).max()),
            "pgv_m_s": float(np.abs(vel).max()),
            "pgd_m": float(np.abs(disp).max()),
        }
    return out


def test_raw_counts_are_processed_before_intensity_measures_as_obspy_does() -> None:
    stream = read(MSEED, inventory=XML)
    reference = _obspy_chain()
    assert len(stream) == 3
    for trace in stream:
        assert needs_standard_processing(trace)
        with pytest.warns(ProcessingWarning, match="high-pass at 0.1 Hz"):
            measures = trace_intensity_measures(trace)
        ref = reference[trace.id]
        # obspy's zero-phase filter runs forward-backward without padding, scipy's sosfiltfilt
        # pads: the two differ at the tapered ends only.
        assert measures["pga_m_s2"] == pytest.approx(ref["pga_m_s2"], rel=0.01)
        assert measures["pgv_m_s"] == pytest.approx(ref["pgv_m_s"], rel=0.02)
        assert measures["pgd_m"] == pytest.approx(ref["pgd_m"], rel=0.05)
        assert measures["pgv_m_s"] < 1.0 and measures["pgd_m"] < 0.5  # not the raw 37 m/s, 2 km
        assert len(trace.stats.stepframe.processing) == 1  # the caller's record is untouched


def test_high_passed_or_calibrated_records_are_measured_as_they_are() -> None:
    trace = read(MSEED, inventory=XML)[0]
    bandpass(trace, 0.05, None)
    assert not needs_standard_processing(trace)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ProcessingWarning)
        trace_intensity_measures(trace)
