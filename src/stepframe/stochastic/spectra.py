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
  not partition unity): within 8 % on a stationary eq. 6.12 process (tested).
- ``"parametric"``: eq. 6.12 of the model fitted to the record (:mod:`stepframe.stochastic.fit`)
  times the record's I_g(t)² (:func:`stepframe.stochastic.features.record_features`).
"""

from __future__ import annotations

import math
from contextlib import AbstractContextManager, nullcontext
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from stepframe.errors import InputError

if TYPE_CHECKING:
    import xarray as xr

SpectrumMethod = Literal["stft", "wavelet", "parametric"]
FftBackend = Literal["pyfftw", "scipy"]
StftEngine = Literal["batched", "shorttimefft"]
SPECTRUM_METHODS: tuple[SpectrumMethod, ...] = ("stft", "wavelet", "parametric")

#: Default STFT window length [s]: resolves 2π/2 s ≈ 3 rad/s, tracks changes over ~1 s.
DEFAULT_WINDOW_S = 2.0
#: Default spacing of frames [s].
DEFAULT_HOP_S = 0.1


def record_samples(record_or_array: Any, dt_s: float | None) -> tuple[NDArray[np.float64], float]:
    """Samples [m/s²] and dt [s] of an ``obspy.Trace`` or an array, validated.

    Raises
    ------
    InputError
        Not 1-D, fewer than 8 samples, NaN/inf values, all equal (constant or zero), missing or
        bad dt.
    """
    stats = getattr(record_or_array, "stats", None)
    if stats is not None:
        data = np.asarray(record_or_array.data, dtype=np.float64)
        dt = float(stats.delta) if dt_s is None else float(dt_s)
        # Name the record in error messages by its file (when a reader set one) and channel.
        source = (stats.get("stepframe") or {}).get("source_file")
        name = f"{source or ''} {stats.channel}".strip() or "record"
    else:
        if dt_s is None:
            raise InputError("dt_s missing, expected the sampling interval of the array [s]")
        data = np.asarray(record_or_array, dtype=np.float64)
        dt = float(dt_s)
        name = "record"
    if data.ndim != 1 or data.size < 8:
        raise InputError(f"{name}: {data.size} samples in shape {data.shape}, expected ≥ 8 in 1-D")
    if not (math.isfinite(dt) and dt > 0):
        raise InputError(f"{name}: dt = {dt} s, expected a positive number")
    bad = ~np.isfinite(data)
    if bad.any():
        first = int(np.argmax(bad))
        raise InputError(
            f"{name}: {int(bad.sum())} NaN/inf samples (first at sample {first}), "
            "expected finite values"
        )
    if np.ptp(data) == 0:
        raise InputError(f"{name}: all samples equal {data[0]}, expected a varying accelerogram")
    return data, dt


def fft_backend(fft: FftBackend) -> AbstractContextManager[Any]:
    """Context in which scipy.fft (and so ``ShortTimeFFT``) uses pyFFTW or its own FFT."""
    if fft == "scipy":
        return nullcontext()
    if fft != "pyfftw":
        raise InputError(f"fft = {fft!r}, expected 'pyfftw' or 'scipy'")
    import pyfftw.interfaces.cache
    import pyfftw.interfaces.scipy_fft
    import scipy.fft

    pyfftw.interfaces.cache.enable()  # keep FFTW plans between frames and records
    return scipy.fft.set_backend(pyfftw.interfaces.scipy_fft)  # type: ignore[no-any-return]


def window_samples(window_s: float, dt_s: float, npts: int) -> int:
    """Window length in samples (≥ 16), checked against the record length."""
    if not (math.isfinite(window_s) and window_s > 0):
        raise InputError(f"window_s = {window_s}, expected a positive number of seconds")
    m = round(window_s / dt_s)
    if m < 16:
        raise InputError(
            f"window_s = {window_s} s is {m} samples at dt = {dt_s} s, expected ≥ 16 samples"
        )
    if m > npts:
        raise InputError(
            f"record of {npts} samples ({npts * dt_s:.3g} s) is shorter than the "
            f"{window_s} s window, expected a record at least one window long"
        )
    return m


def stft_power(
    data: NDArray[np.float64],
    dt_s: float,
    *,
    window_s: float = DEFAULT_WINDOW_S,
    hop_s: float = DEFAULT_HOP_S,
    fft: FftBackend = "scipy",
    engine: StftEngine = "batched",
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """STFT evolutionary spectrum as arrays.

    Both engines use the window, frequencies and slice positions of one scipy ``ShortTimeFFT``
    (slice p centred on sample p·hop, zeros outside the record) and FFTs through ``scipy.fft``
    (so pyFFTW or scipy's own per ``fft``). ``"shorttimefft"`` calls ``ShortTimeFFT.stft``,
    which transforms one slice per Python call; ``"batched"`` (default) transforms all slices
    in one ``scipy.fft.rfft`` call on a strided view, 5-10x faster on records of a few thousand
    samples; the two agree to rounding (tests/stochastic/test_spectra.py).

    Returns
    -------
    time_s : numpy.ndarray
        Frame centres [s] from the record start (0, hop, ..., covering the record).
    omega_rad_s : numpy.ndarray
        Frequencies 0 ... π/dt [rad/s].
    psd : numpy.ndarray
        S, shape (time, omega) [(m/s²)²·s/rad].
    window : numpy.ndarray
        The Hann window used (for its known spectral spread).
    """
    import scipy.fft as sfft
    from scipy.signal import ShortTimeFFT
    from scipy.signal.windows import hann

    if engine not in ("batched", "shorttimefft"):
        raise InputError(f"engine = {engine!r}, expected 'batched' or 'shorttimefft'")
    npts = data.size
    m = window_samples(window_s, dt_s, npts)
    hop = max(1, round(hop_s / dt_s))
    win = hann(m, sym=False) if m % 2 == 0 else hann(m, sym=True)
    mfft = 1 << max(math.ceil(math.log2(m)), 4)
    stft = ShortTimeFFT(win, hop, 1.0 / dt_s, fft_mode="onesided", mfft=mfft)
    p1 = (npts - 1) // hop + 1
    with fft_backend(fft):
        if engine == "shorttimefft":
            spec = stft.stft(data, p0=0, p1=p1).T
        else:
            mid = stft.m_num_mid
            padded = np.zeros(npts + m + hop)
            padded[mid : mid + npts] = data
            frames = np.lib.stride_tricks.sliding_window_view(padded, m)[: p1 * hop : hop]
            spec = sfft.rfft(frames * win, n=mfft, axis=-1)
    psd = (dt_s / float(np.sum(win**2))) * (spec.real**2 + spec.imag**2)
    time_s = np.arange(p1, dtype=np.float64) * hop * dt_s
    omega = 2 * math.pi * np.asarray(stft.f, dtype=np.float64)
    return time_s, omega, np.ascontiguousarray(psd), np.asarray(win, dtype=np.float64)


def wavelet_power(
    data: NDArray[np.float64],
    dt_s: float,
    *,
    hop_s: float = DEFAULT_HOP_S,
    omega_rad_s: ArrayLike | None = None,
    morlet_q: float = 6.0,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Morlet-wavelet evolutionary spectrum (time, omega, S) on frames every ``hop_s``."""
    import scipy.fft as sfft

    npts = data.size
    nyquist = math.pi / dt_s
    if omega_rad_s is None:
        low = max(2 * math.pi / (npts * dt_s) * morlet_q, 0.2)
        omega = np.geomspace(low, 0.8 * nyquist, 96)
    else:
        omega = np.asarray(omega_rad_s, dtype=np.float64)
        if omega.ndim != 1 or np.any(omega <= 0) or np.any(omega >= nyquist):
            raise InputError(
                f"omega_rad_s must be positive frequencies below Nyquist {nyquist:.4g} rad/s"
            )
    if not (math.isfinite(morlet_q) and morlet_q >= 2):
        raise InputError(f"morlet_q = {morlet_q}, expected ≥ 2 (a band-pass wavelet)")
    nfft = sfft.next_fast_len(2 * npts)
    spectrum = sfft.rfft(data, nfft)
    freqs = 2 * math.pi * sfft.rfftfreq(nfft, dt_s)
    hop = max(1, round(hop_s / dt_s))
    frames = np.arange(0, npts, hop)
    psd = np.empty((frames.size, omega.size))
    full = np.zeros(nfft, dtype=np.complex128)
    for j, wj in enumerate(omega):
        sigma = wj / morlet_q
        gain = np.exp(-0.5 * ((freqs - wj) / sigma) ** 2)
        full[: freqs.size] = 2.0 * spectrum * gain  # analytic signal: positive frequencies only
        full[freqs.size :] = 0.0
        u = sfft.ifft(full)[:npts]
        psd[:, j] = math.sqrt(math.pi) * np.abs(u[frames]) ** 2 / (2.0 * sigma)
    return np.asarray(frames * dt_s, dtype=np.float64), omega, psd


def evolutionary_spectrum(
    record_or_array: Any,
    dt_s: float | None = None,
    method: SpectrumMethod = "stft",
    *,
    window_s: float = DEFAULT_WINDOW_S,
    hop_s: float = DEFAULT_HOP_S,
    fft: FftBackend = "scipy",
    omega_rad_s: ArrayLike | None = None,
    morlet_q: float = 6.0,
    t0: Literal["start", "p-pick"] = "start",
    frequency: Literal["zero-crossing", "ridge", "moment", "wavelet-ridge"] = "zero-crossing",
) -> xr.DataArray:
    """Evolutionary power spectral density S(ω, t) of a record.

    Parameters
    ----------
    record_or_array
        An ``obspy.Trace`` in m/s², or an array of accelerations (then ``dt_s`` is needed).
    dt_s
        Sampling interval [s] (overrides the trace's).
    method
        ``"stft"`` (default), ``"wavelet"`` (Morlet) or ``"parametric"`` (fitted eq. 6.12).
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
        values of the two-sided S [(m/s²)²·s/rad] with ``I_g² = (1/π)∫_0^∞ S dω``.

    Raises
    ------
    InputError
        Bad record (too short for the window, constant, NaNs), bad options.
    """
    import xarray as xr

    if method not in SPECTRUM_METHODS:
        raise InputError(f"method = {method!r}, expected one of {', '.join(SPECTRUM_METHODS)}")
    if not (math.isfinite(hop_s) and hop_s > 0):
        raise InputError(f"hop_s = {hop_s}, expected a positive number of seconds")
    data, dt = record_samples(record_or_array, dt_s)
    attrs: dict[str, Any] = {"method": method}
    if method == "stft":
        time_s, omega, psd, _ = stft_power(data, dt, window_s=window_s, hop_s=hop_s, fft=fft)
        attrs.update(window="hann", window_s=window_s, fft=fft)
    elif method == "wavelet":
        window_samples(window_s, dt, data.size)  # the same minimum length as the STFT
        time_s, omega, psd = wavelet_power(
            data, dt, hop_s=hop_s, omega_rad_s=omega_rad_s, morlet_q=morlet_q
        )
        attrs.update(wavelet="morlet", morlet_q=morlet_q)
    else:
        from stepframe.stochastic.features import record_features
        from stepframe.stochastic.fit import fit_model

        features = record_features(
            data, dt, window_s=window_s, hop_s=hop_s, fft=fft, t0=t0, frequency=frequency
        )
        fitted = fit_model(features)
        time_s = features.time_s
        omega = (
            np.linspace(0.0, math.pi / dt, 257)
            if omega_rad_s is None
            else np.asarray(omega_rad_s, dtype=np.float64)
        )
        if omega.ndim != 1 or not np.all(np.isfinite(omega)) or np.any(omega < 0):
            raise InputError("omega_rad_s must be finite frequencies ≥ 0 [rad/s] in a 1-D array")
        psd = fitted.model.psd(omega[None, :], time_s[:, None], features.intensity[:, None])
        attrs.update(fitted.model.to_dict())
        attrs["omega_c_rad_s"] = (
            "none" if fitted.model.omega_c_rad_s is None else attrs.get("omega_c_rad_s")
        )
    attrs.update(units="(m/s2)2 s/rad", long_name="two-sided evolutionary PSD of acceleration")
    return xr.DataArray(
        psd,
        dims=("time", "omega"),
        coords={
            "time": ("time", time_s, {"units": "s", "long_name": "time from record start"}),
            "omega": ("omega", omega, {"units": "rad/s", "long_name": "angular frequency"}),
        },
        name="psd",
        attrs=attrs,
    )


def mean_square(spectrum: xr.DataArray) -> NDArray[np.float64]:
    """(1/π)∫_0^∞ S dω by the trapezoid rule: the local mean square [(m/s²)²] at each time."""
    omega = np.asarray(spectrum["omega"].values, dtype=np.float64)
    values = np.asarray(spectrum.values, dtype=np.float64)
    return np.asarray(np.trapezoid(values, omega, axis=-1) / math.pi)
