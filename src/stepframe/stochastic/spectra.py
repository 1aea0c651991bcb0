"""Evolutionary power spectra of a record: short-time Fourier, Morlet wavelet, parametric eq. 6.12.

Convention (DESIGN.md): ``S(ω, t)`` is two-sided in ω [rad/s], returned for ω ≥ 0 only, so the
local mean square is ``(1/π) ∫_0^∞ S dω``.

- ``"stft"``: scipy ``ShortTimeFFT`` with a Hann window of ``window_s``; FFTs by scipy's own
  (default) or pyFFTW (``fft="pyfftw"``, through ``scipy.fft.set_backend``).
  ``S_k = dt |X_k|² / Σ w_n²`` makes the identity exact: the trapezoid rule of
  ``(1/π)∫_0^∞ S dω`` equals the window-weighted mean square ``Σ w_n² x_n² / Σ w_n²`` of the
  record around each frame centre (zeros outside it).
- ``"wavelet"``: analytic Morlet (Gaussian band-pass, constant relative bandwidth
  ``1/morlet_q``) computed by FFT; ``S(ω_j, t) = √π |u_j(t)|² / (2 σ_j)`` with σ_j = ω_j/q,
  the density of a spectrum flat across the band. The identity holds approximately (the bands do
  not partition unity): within 8 % on a stationary eq. 6.12 process (tested). Constant Q: the
  default bands reach down to 2√2·q/T on a record of T s (0.38 rad/s on 45 s with q = 6), the
  bottom of a frame's band where the record is long enough.

Every result has the coordinate ``omega_floor`` (dim ``time``): the lowest frequency resolved
at each frame [rad/s]: 2π/``window_s`` for the STFT (one cycle in the window), the cone of
influence √2·q/d for the wavelet (d the time to the nearer record end,
:func:`stepframe.stochastic.transforms.cone_of_influence`), 0 for the parametric model.
- ``"parametric"``: eq. 6.12 of the model fitted to the record (:mod:`stepframe.stochastic.fit`)
  times the record's I_g(t)² (:func:`stepframe.stochastic.features.record_features`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

from stepframe.errors import InputError
from stepframe.stochastic.features import (
    FrequencyEstimator,
    TimeOrigin,
    fixed_window_floor,
    record_features,
)
from stepframe.stochastic.fit import fit_model
from stepframe.stochastic.methods import DEFAULT_FREQUENCY_METHOD, FrequencyMethod, SpectrumMethod
from stepframe.stochastic.transforms import (
    DEFAULT_HOP_S,
    DEFAULT_WINDOW_S,
    FftBackend,
    cone_of_influence,
    record_samples,
    stft_power,
    wavelet_power,
    window_samples,
)

if TYPE_CHECKING:
    import xarray as xr
    from obspy import Trace


@dataclass(frozen=True)
class SpectrumOptions:
    """The options of :func:`evolutionary_spectrum` a spectrum method may use (see there)."""

    window_s: float = DEFAULT_WINDOW_S
    hop_s: float = DEFAULT_HOP_S
    fft: FftBackend = "scipy"
    omega_rad_s: ArrayLike | None = None
    morlet_q: float = 6.0
    t0: TimeOrigin = "start"
    frequency: FrequencyMethod | FrequencyEstimator = DEFAULT_FREQUENCY_METHOD


#: The attribute a spectrum method may set to state its per-frame floor (see SpectrumFunction).
FLOOR = "omega_floor_rad_s"
#: What a spectrum method returns: frame times [s], ω ≥ 0 [rad/s], S (time × ω) and attributes.
SpectrumParts = tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], dict[str, Any]]


class SpectrumFunction(Protocol):
    """An evolutionary-spectrum method: validated samples [m/s²], dt [s] and options in.

    Its attributes may hold ``omega_floor_rad_s``, the lowest frequency it resolves at each
    frame (an array over time [rad/s]), which becomes the result's ``omega_floor`` coordinate
    (absent: 0, nothing stated).
    """

    __name__: str

    def __call__(
        self, data: NDArray[np.float64], dt_s: float, options: SpectrumOptions, /
    ) -> SpectrumParts: ...


def stft_spectrum(
    data: NDArray[np.float64], dt_s: float, options: SpectrumOptions
) -> SpectrumParts:
    """Hann-window STFT (module docstring)."""
    time_s, omega, psd, _ = stft_power(
        data, dt_s, window_s=options.window_s, hop_s=options.hop_s, fft=options.fft
    )
    floor = np.full(time_s.shape, fixed_window_floor(options.window_s))
    attrs = {"window": "hann", "window_s": options.window_s, "fft": options.fft}
    return time_s, omega, psd, {**attrs, FLOOR: floor}


def wavelet_spectrum(
    data: NDArray[np.float64], dt_s: float, options: SpectrumOptions
) -> SpectrumParts:
    """Analytic Morlet wavelet (module docstring)."""
    window_samples(options.window_s, dt_s, data.size)  # the same minimum length as the STFT
    time_s, omega, psd = wavelet_power(
        data, dt_s, hop_s=options.hop_s, omega_rad_s=options.omega_rad_s, morlet_q=options.morlet_q
    )
    floor = cone_of_influence(time_s, (data.size - 1) * dt_s, options.morlet_q)
    return time_s, omega, psd, {"wavelet": "morlet", "morlet_q": options.morlet_q, FLOOR: floor}


def parametric_spectrum(
    data: NDArray[np.float64], dt_s: float, options: SpectrumOptions
) -> SpectrumParts:
    """Eq. 6.12 of the model fitted to the record, times its I_g(t)² (module docstring)."""
    features = record_features(
        data, dt_s, window_s=options.window_s, hop_s=options.hop_s, fft=options.fft,
        t0=options.t0, frequency=options.frequency,
    )  # fmt: skip
    fitted = fit_model(features)
    time_s = features.time_s
    omega = (
        np.linspace(0.0, math.pi / dt_s, 257)
        if options.omega_rad_s is None
        else np.asarray(options.omega_rad_s, dtype=np.float64)
    )
    if omega.ndim != 1 or not np.all(np.isfinite(omega)) or np.any(omega < 0):
        raise InputError("omega_rad_s must be finite frequencies ≥ 0 [rad/s] in a 1-D array")
    psd = fitted.model.psd(omega[None, :], time_s[:, None], features.intensity[:, None])
    attrs: dict[str, Any] = fitted.model.to_dict()
    attrs["omega_c_rad_s"] = (
        "none" if fitted.model.omega_c_rad_s is None else attrs.get("omega_c_rad_s")
    )
    return time_s, omega, np.asarray(psd, dtype=np.float64), attrs


#: The evolutionary-spectrum methods by name (:data:`stepframe.stochastic.methods.SpectrumMethod`).
SPECTRUM_METHODS: dict[str, SpectrumFunction] = {
    "stft": stft_spectrum,
    "wavelet": wavelet_spectrum,
    "parametric": parametric_spectrum,
}


def _spectrum_method(method: str | SpectrumFunction) -> SpectrumFunction:
    if callable(method):
        return method
    try:
        return SPECTRUM_METHODS[method]
    except (KeyError, TypeError):
        raise InputError(
            f"method = {method!r}, expected one of {', '.join(SPECTRUM_METHODS)} or a function"
        ) from None


def evolutionary_spectrum(
    record_or_array: Trace | ArrayLike,
    dt_s: float | None = None,
    method: SpectrumMethod | SpectrumFunction = "stft",
    *,
    window_s: float = DEFAULT_WINDOW_S,
    hop_s: float = DEFAULT_HOP_S,
    fft: FftBackend = "scipy",
    omega_rad_s: ArrayLike | None = None,
    morlet_q: float = 6.0,
    t0: TimeOrigin = "start",
    frequency: FrequencyMethod | FrequencyEstimator = DEFAULT_FREQUENCY_METHOD,
) -> xr.DataArray:
    """Evolutionary power spectral density S(ω, t) of a record.

    Parameters
    ----------
    record_or_array
        An ``obspy.Trace`` in m/s², or an array of accelerations (then ``dt_s`` is needed).
    dt_s
        Sampling interval [s] (overrides the trace's).
    method
        A name of :data:`SPECTRUM_METHODS`: ``"stft"`` (default), ``"wavelet"`` (Morlet) or
        ``"parametric"`` (fitted eq. 6.12); or a :class:`SpectrumFunction`.
    window_s, hop_s
        STFT window length and frame spacing [s] (wavelet and parametric use ``hop_s``).
    fft
        ``"scipy"`` (default) or ``"pyfftw"``: FFT used by the STFT (pyFFTW through
        ``scipy.fft.set_backend``). Measured on the example catalogue (docs/benchmarks.md,
        Features), pyFFTW is not faster here: each record has its own number of frames, so FFTW
        plans a new transform per record, and 512-point transforms are cheap for pocketfft.
    omega_rad_s
        Wavelet centre frequencies [rad/s] (default: 96 log-spaced up to 0.8 Nyquist).
    morlet_q
        Wavelet relative bandwidth ω/σ (larger: finer in frequency, coarser in time).
    t0
        Time origin of the fitted model for ``"parametric"`` (``"start"`` or ``"p-pick"``).
    frequency
        ω_g(t) estimator of the fit for ``"parametric"`` (as
        :func:`stepframe.stochastic.features.record_features`).

    Returns
    -------
    xarray.DataArray
        Dims (``time``, ``omega``): ``time`` [s] from the record start, ``omega`` ≥ 0 [rad/s];
        values of the two-sided S [(m/s²)²·s/rad] with ``I_g² = (1/π)∫_0^∞ S dω``; the
        coordinate ``omega_floor`` (dim ``time``) is the lowest frequency resolved at each frame
        [rad/s] (module docstring).

    Raises
    ------
    InputError
        Bad record (too short for the window, constant, NaNs), bad options.
    """
    import xarray as xr

    _spectrum_method(method)  # a bad name fails before any work
    if not (math.isfinite(hop_s) and hop_s > 0):
        raise InputError(f"hop_s = {hop_s}, expected a positive number of seconds")
    data, dt = record_samples(record_or_array, dt_s)
    options = SpectrumOptions(window_s, hop_s, fft, omega_rad_s, morlet_q, t0, frequency)
    time_s, omega, psd, found = _spectrum_method(method)(data, dt, options)
    name = method if isinstance(method, str) else getattr(method, "__name__", "custom")
    found = dict(found)
    floor = np.asarray(found.pop(FLOOR, np.zeros(time_s.shape)), dtype=np.float64)
    attrs: dict[str, Any] = {"method": name, **found}
    attrs.update(units="(m/s2)2 s/rad", long_name="two-sided evolutionary PSD of acceleration")
    floor_attrs = {"units": "rad/s", "long_name": "lowest frequency resolved"}
    return xr.DataArray(
        psd,
        dims=("time", "omega"),
        coords={
            "time": ("time", time_s, {"units": "s", "long_name": "time from record start"}),
            "omega": ("omega", omega, {"units": "rad/s", "long_name": "angular frequency"}),
            "omega_floor": ("time", np.broadcast_to(floor, time_s.shape).copy(), floor_attrs),
        },
        name="psd",
        attrs=attrs,
    )


def mean_square(spectrum: xr.DataArray) -> NDArray[np.float64]:
    """(1/π)∫_0^∞ S dω by the trapezoid rule: the local mean square [(m/s²)²] at each time."""
    omega = np.asarray(spectrum["omega"].values, dtype=np.float64)
    values = np.asarray(spectrum.values, dtype=np.float64)
    return np.asarray(np.trapezoid(values, omega, axis=-1) / math.pi)
