"""Processing steps: exact effects on analytic records, recorded history, failures leave none."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import signal

from stepframe.errors import InputError
from stepframe.records.intensity import displacement_m
from stepframe.records.processing import (
    bandpass,
    baseline,
    demean,
    detrend,
    process,
    resample,
    taper,
    trim,
)
from stepframe.records.trace import make_trace


def _trace(data: np.ndarray, dt: float = 0.01):  # type: ignore[no-untyped-def]
    return make_trace(data, dt, station="TEST", channel="HNE")


def test_nothing_applied_unless_asked() -> None:
    trace = _trace(np.arange(10.0))
    assert trace.stats.stepframe.processing == []
    np.testing.assert_array_equal(trace.data, np.arange(10.0))


def test_demean_and_detrend_exact() -> None:
    t = np.arange(1000) * 0.01
    trace = demean(_trace(3.0 + np.sin(2 * np.pi * t)))
    assert abs(trace.data.mean()) < 1e-14
    trace = detrend(_trace(0.5 + 2.0 * t + np.sin(2 * np.pi * t)))
    # A whole number of sine periods is orthogonal to constants; the fitted line removes 0.5 + 2t
    # up to the sine's small projection on t.
    line = np.polyfit(t, np.sin(2 * np.pi * t), 1)
    np.testing.assert_allclose(trace.data, np.sin(2 * np.pi * t) - np.polyval(line, t), atol=1e-10)
    assert [step["step"] for step in trace.stats.stepframe.processing] == ["detrend"]


def test_baseline_removes_a_polynomial_drift_exactly() -> None:
    """Acceleration = signal + second derivative of a quadratic-cubic displacement drift."""
    dt = 0.01
    t = np.arange(2001) * dt
    drift_acc = 2 * 0.003 + 6 * 0.0004 * t  # u = 0.003 t² + 0.0004 t³
    trace = baseline(_trace(drift_acc), order=3)
    np.testing.assert_allclose(trace.data, 0.0, atol=1e-9)
    assert trace.stats.stepframe.processing == [{"step": "baseline", "order": 3}]
    # Drift added to a record: the corrected displacement has no quadratic-cubic trend left.
    clean = np.sin(2 * np.pi * 1.0 * t) * np.hanning(t.size)
    corrected = baseline(_trace(clean + drift_acc), order=3)
    disp = displacement_m(corrected.data, dt)
    design = np.stack([t**2, t**3], axis=1)
    residual_fit, *_ = np.linalg.lstsq(design, disp, rcond=None)
    np.testing.assert_allclose(residual_fit, 0.0, atol=1e-10)


def test_bandpass_against_transfer_function() -> None:
    """Sines through the acausal 4th-order Butterworth: gain |H(f)|², no phase shift."""
    dt = 0.005
    t = np.arange(8000) * dt
    sos = signal.butter(4, [0.5, 1.5], "bandpass", fs=1 / dt, output="sos")
    for freq_hz in (0.8, 2.0):
        x = np.sin(2 * np.pi * freq_hz * t)
        trace = bandpass(_trace(x, dt), 0.5, 1.5)
        _, h = signal.sosfreqz(sos, worN=[freq_hz], fs=1 / dt)
        gain = abs(h[0]) ** 2
        middle = slice(2000, 6000)
        # Transients of the ends have decayed to a few percent of the gain in the middle.
        np.testing.assert_allclose(trace.data[middle], gain * x[middle], atol=0.03 * gain)
    assert trace.stats.stepframe.processing[-1] == {
        "step": "bandpass",
        "freqmin_hz": 0.5,
        "freqmax_hz": 1.5,
        "order": 4,
        "zero_phase": True,
    }


def test_taper_and_trim() -> None:
    trace = taper(_trace(np.ones(100)), 0.1)
    assert trace.data[0] == 0.0 and trace.data[50] == 1.0 and trace.data[-1] == 0.0
    np.testing.assert_array_equal(trace.data, trace.data[::-1])
    assert trace.data[5] == pytest.approx(0.5 * (1 - np.cos(np.pi * 5 / 10)))
    trace = trim(_trace(np.arange(100.0)), 0.2, 0.5)
    np.testing.assert_array_equal(trace.data, np.arange(20.0, 51.0))
    assert float(trace.stats.starttime.timestamp) == pytest.approx(0.2)


def test_resample_band_limited_sine() -> None:
    dt = 0.01
    t = np.arange(1000) * dt
    trace = resample(_trace(np.sin(2 * np.pi * 1.0 * t)), 0.005)
    assert trace.stats.delta == pytest.approx(0.005) and trace.stats.npts == 2000
    t_new = np.arange(2000) * 0.005
    np.testing.assert_allclose(trace.data, np.sin(2 * np.pi * 1.0 * t_new), atol=1e-9)


def test_process_list_and_failure_leaves_record_unchanged() -> None:
    trace = _trace(np.sin(np.arange(500) * 0.1) + 1.0)
    process(trace, [{"step": "demean"}, {"step": "taper", "fraction": 0.05}])
    assert [s["step"] for s in trace.stats.stepframe.processing] == ["demean", "taper"]
    before = trace.data.copy()
    with pytest.raises(InputError, match="freqmax_hz = 80"):
        process(trace, [{"step": "bandpass", "freqmin_hz": 0.1, "freqmax_hz": 80.0}])
    np.testing.assert_array_equal(trace.data, before)
    assert len(trace.stats.stepframe.processing) == 2
    with pytest.raises(InputError, match="expected one of"):
        process(trace, [{"step": "smooth"}])
    with pytest.raises(InputError, match="unexpected keyword"):
        process(trace, [{"step": "taper", "width": 3}])
    with pytest.raises(InputError, match="trim window"):
        trim(trace, 3.0, 1.0)
