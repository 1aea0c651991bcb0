"""Processing steps on a record, each recorded in ``stats.stepframe.processing`` once it succeeds.

Every step works in place on an ``obspy.Trace`` in m/s² and returns it; the new samples are
computed first and assigned only when the step has succeeded, then ``{"step": name, **params}``
is appended to the history (gmprocess-style provenance). Nothing is applied unless asked for.
:func:`process` runs an ordered list of named steps, as a workflow file gives them.

Steps: ``demean``, ``detrend`` (least-squares line), ``baseline`` (polynomial fit to the
displacement, its second derivative removed from the acceleration), ``bandpass`` (Butterworth,
acausal by default; either corner may be omitted for a high- or low-pass), ``taper`` (Hann ends),
``resample`` (FFT, band-limited) and ``trim`` (seconds from the first sample).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from numpy.typing import NDArray

from stepframe.errors import InputError

if TYPE_CHECKING:
    from obspy import Stream, Trace
from stepframe.records.integration import displacement_m

StepName = Literal["demean", "detrend", "baseline", "bandpass", "taper", "resample", "trim"]


def _record(trace: Trace, step: str, new_data: NDArray[np.float64], **params: Any) -> Trace:
    if not np.all(np.isfinite(new_data)):
        raise InputError(f"step {step!r} produced non-finite samples, expected a finite record")
    trace.data = np.ascontiguousarray(new_data, dtype=np.float64)
    trace.stats.stepframe.processing.append({"step": step, **params})
    return trace


def demean(trace: Trace) -> Trace:
    """Remove the mean of the record."""
    data = np.asarray(trace.data, dtype=np.float64)
    return _record(trace, "demean", data - data.mean())


def detrend(trace: Trace) -> Trace:
    """Remove the least-squares straight line of the record."""
    data = np.asarray(trace.data, dtype=np.float64)
    t = np.arange(data.size, dtype=np.float64)
    slope, intercept = np.polyfit(t, data, 1)
    return _record(trace, "detrend", data - (slope * t + intercept))


def baseline(trace: Trace, order: int = 6) -> Trace:
    """Polynomial baseline correction: fit u(t) ≈ Σ_{k=2}^{order} c_k t^k to the displacement.

    The fitted polynomial has no constant or linear term (the record starts from rest), and its
    second derivative is removed from the acceleration (Boore et al. practice, as in gmprocess).

    Parameters
    ----------
    order
        Degree of the polynomial, 2 to 10.
    """
    if not 2 <= order <= 10:
        raise InputError(f"baseline polynomial order {order}, expected 2 to 10")
    data = np.asarray(trace.data, dtype=np.float64)
    dt = float(trace.stats.delta)
    duration = dt * (data.size - 1)
    # Scaled time keeps the normal equations well conditioned for high orders.
    x = np.arange(data.size) * dt / duration
    powers = np.arange(2, order + 1)
    design = x[:, None] ** powers[None, :]
    coeffs, *_ = np.linalg.lstsq(design, displacement_m(data, dt), rcond=None)
    second = (powers * (powers - 1) * coeffs)[None, :] * x[:, None] ** (powers - 2)[None, :]
    correction = second.sum(axis=1) / duration**2
    return _record(trace, "baseline", data - correction, order=order)


def bandpass(
    trace: Trace,
    freqmin_hz: float | None,
    freqmax_hz: float | None,
    order: int = 4,
    zero_phase: bool = True,
) -> Trace:
    """Butterworth filter (second-order sections); acausal (forward-backward) by default.

    Parameters
    ----------
    freqmin_hz, freqmax_hz
        Corner frequencies [Hz]; None for a low-pass or high-pass only. The upper corner must be
        below the Nyquist frequency.
    order
        Order of the Butterworth design (the acausal filter applies it twice).
    zero_phase
        Forward-backward filtering (no phase shift) when True; causal when False.
    """
    from scipy import signal

    nyquist = 0.5 / float(trace.stats.delta)
    if freqmin_hz is None and freqmax_hz is None:
        raise InputError("bandpass without corners, expected freqmin_hz and/or freqmax_hz")
    for name, value in (("freqmin_hz", freqmin_hz), ("freqmax_hz", freqmax_hz)):
        if value is not None and not (math.isfinite(value) and 0 < value < nyquist):
            raise InputError(f"{name} = {value}, expected 0 < f < Nyquist ({nyquist:g} Hz)")
    if freqmin_hz is not None and freqmax_hz is not None and freqmin_hz >= freqmax_hz:
        raise InputError(f"corners {freqmin_hz} >= {freqmax_hz} Hz, expected freqmin < freqmax")
    if freqmin_hz is not None and freqmax_hz is not None:
        sos = signal.butter(
            order, [freqmin_hz, freqmax_hz], "bandpass", fs=2 * nyquist, output="sos"
        )
    elif freqmin_hz is not None:
        sos = signal.butter(order, freqmin_hz, "highpass", fs=2 * nyquist, output="sos")
    else:
        sos = signal.butter(order, freqmax_hz, "lowpass", fs=2 * nyquist, output="sos")
    data = np.asarray(trace.data, dtype=np.float64)
    filtered = signal.sosfiltfilt(sos, data) if zero_phase else signal.sosfilt(sos, data)
    return _record(
        trace,
        "bandpass",
        filtered,
        freqmin_hz=freqmin_hz,
        freqmax_hz=freqmax_hz,
        order=order,
        zero_phase=zero_phase,
    )


def taper(trace: Trace, fraction: float = 0.05) -> Trace:
    """Hann taper over ``fraction`` of the record at each end (0 < fraction <= 0.5)."""
    if not 0 < fraction <= 0.5:
        raise InputError(f"taper fraction {fraction}, expected 0 < fraction <= 0.5")
    data = np.asarray(trace.data, dtype=np.float64)
    width = max(int(fraction * data.size), 1)
    ramp = 0.5 * (1 - np.cos(np.pi * np.arange(width) / width))
    window = np.ones(data.size)
    window[:width] = ramp
    window[data.size - width :] = np.minimum(window[data.size - width :], ramp[::-1])
    return _record(trace, "taper", data * window, fraction=fraction)


def resample(trace: Trace, dt_s: float) -> Trace:
    """Resample to interval ``dt_s`` [s] by FFT; when downsampling, content above the new
    Nyquist frequency is removed (an ideal anti-alias filter)."""
    from scipy import signal

    if not (math.isfinite(dt_s) and dt_s > 0):
        raise InputError(f"dt = {dt_s} s, expected a positive sampling interval")
    data = np.asarray(trace.data, dtype=np.float64)
    old_dt = float(trace.stats.delta)
    npts = max(round(data.size * old_dt / dt_s), 2)
    new = signal.resample(data, npts)
    _record(trace, "resample", new, dt_s=dt_s, dt_in_s=old_dt)
    trace.stats.delta = data.size * old_dt / npts
    return trace


def trim(trace: Trace, start_s: float = 0.0, end_s: float | None = None) -> Trace:
    """Keep samples from ``start_s`` to ``end_s`` [s] after the first sample (inclusive)."""
    data = np.asarray(trace.data, dtype=np.float64)
    dt = float(trace.stats.delta)
    first = math.ceil(start_s / dt - 1e-9)
    last = data.size - 1 if end_s is None else math.floor(end_s / dt + 1e-9)
    if not (0 <= first < last <= data.size - 1):
        duration = dt * (data.size - 1)
        raise InputError(
            f"trim window {start_s}..{end_s} s, expected 0 <= start < end <= {duration:g} s"
        )
    starttime = trace.stats.starttime + first * dt
    _record(trace, "trim", data[first : last + 1], start_s=start_s, end_s=end_s)
    trace.stats.starttime = starttime
    return trace


STEPS: dict[str, Callable[..., Any]] = {
    "demean": demean,
    "detrend": detrend,
    "baseline": baseline,
    "bandpass": bandpass,
    "taper": taper,
    "resample": resample,
    "trim": trim,
}


def process(trace: Trace, steps: Sequence[Mapping[str, Any]]) -> Trace:
    """Apply named steps in order: ``[{"step": "bandpass", "freqmin_hz": 0.1, ...}, ...]``.

    A failing step raises :class:`InputError` naming it; the steps before it stay applied and
    recorded, the failing one leaves the record unchanged.
    """
    for number, spec in enumerate(steps, start=1):
        params = dict(spec)
        name = params.pop("step", None)
        if name not in STEPS:
            raise InputError(
                f"processing step {number}: {name!r}, expected one of {', '.join(STEPS)}"
            )
        try:
            STEPS[name](trace, **params)
        except TypeError as exc:
            raise InputError(f"processing step {number} ({name}): {exc}") from None
    return trace


#: Steps that make acceleration out of raw counts (the readers' names: an inventory's
#: sensitivity or response, a header's calibration of COSMOS V0 or Kinemetrics EVT counts): data
#: after them keep the sensor's and digitiser's offset and drift, which integrate into
#: metres-per-second PGV and kilometre PGD.
FROM_COUNTS_STEPS = ("remove_sensitivity", "remove_response", "counts_to_acceleration")
#: High-pass corner [Hz] of :func:`standard_processing`: the usual fixed corner of strong-motion
#: processing for records with no measured noise spectrum (periods up to 10 s kept).
STANDARD_HIGHPASS_HZ = 0.1
#: Taper fraction at each end of :func:`standard_processing`.
STANDARD_TAPER = 0.05


def needs_standard_processing(trace: Trace) -> bool:
    """Whether the record was made from raw counts (:data:`FROM_COUNTS_STEPS`) and has not been
    high-passed since: its intensity measures need :func:`standard_processing` first."""
    history = list(trace.stats.get("stepframe", {}).get("processing", []))
    converted = [i for i, step in enumerate(history) if step.get("step") in FROM_COUNTS_STEPS]
    if not converted:
        return False
    later = history[converted[-1] + 1 :]
    return not any(s.get("step") == "bandpass" and s.get("freqmin_hz") for s in later)


def standard_processing(trace: Trace, highpass_hz: float = STANDARD_HIGHPASS_HZ) -> Trace:
    """The stated processing of data converted from raw counts, in place: ``demean`` (offset),
    ``detrend`` (linear baseline), ``taper`` (5 % Hann at each end) and ``bandpass`` as a
    high-pass at ``highpass_hz`` [Hz] (4th-order Butterworth, acausal), each recorded.

    It is the chain obspy's documentation and strong-motion practice apply around response
    removal (offset and trend out, ends tapered, long periods the sensor does not resolve
    filtered out), so that PGV, PGD and durations describe ground motion, not sensor drift.
    """
    demean(trace)
    detrend(trace)
    taper(trace, STANDARD_TAPER)
    return bandpass(trace, highpass_hz, None, order=4, zero_phase=True)


def measured(trace: Trace) -> Trace:
    """The record every output is made from: a copy after :func:`standard_processing` if it
    :func:`needs_standard_processing`, with a :class:`ProcessingWarning` naming the steps, else
    ``trace`` itself.

    The one decision of the processing policy: intensity measures, spectra, fits, catalogue rows
    and simulations of a record read from raw counts are all made from the same processed copy
    (a catalogue row mixed a processed PGA with PSA of the unprocessed record, whose offset
    dominates long periods: CE.68150 HNN PSA(10 s) 0.059 g as read, 0.0077 g processed).
    """
    if not needs_standard_processing(trace):
        return trace
    import warnings

    work = standard_processing(trace.copy())
    steps = [step["step"] for step in work.stats.stepframe.processing[-4:]]
    corner_hz = work.stats.stepframe.processing[-1]["freqmin_hz"]
    warnings.warn(
        f"{trace.id}: made from raw counts and not high-passed: measured after the standard "
        f"processing ({', '.join(steps)}: offset and linear trend removed, "
        f"{STANDARD_TAPER:.0%} taper, high-pass at {corner_hz:g} Hz)",
        ProcessingWarning,
        stacklevel=3,
    )
    return work


def measured_stream(stream: Stream) -> Stream:
    """:func:`measured` of every trace of ``stream`` (a new Stream; traces that need no
    processing are the same objects)."""
    from obspy import Stream

    return Stream([measured(trace) for trace in stream])


class ProcessingWarning(UserWarning):
    """Outputs computed after a processing step the user did not ask for."""
