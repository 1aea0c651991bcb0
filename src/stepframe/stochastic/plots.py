"""Figures of the stochastic area: a fitted record and the amplification curves.

Each function returns a :class:`matplotlib.figure.Figure` built without pyplot (no global state,
nothing shown or saved); the caller saves it, e.g. through
:func:`stepframe.pipeline.figures.save_figure`. matplotlib is imported when a function is called.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure
    from obspy import Trace

    from stepframe.stochastic.features import RecordFeatures
    from stepframe.stochastic.fit import FitResult


def fit_figure(
    trace: Trace, spectrum: xr.DataArray, features: RecordFeatures, fitted: FitResult
) -> Figure:
    """Record, I_g(t), and the evolutionary PSD with the measured and fitted ω_g(t).

    Parameters
    ----------
    trace
        The record (``obspy.Trace`` in m/s²).
    spectrum
        Its evolutionary PSD (dims ``time`` [s], ``omega`` [rad/s]).
    features
        The measured I_g(t) [m/s²], ω_g(t) [rad/s], t0 and t_max [s].
    fitted
        The fitted model (its ω_g(t) of eq. 6.10 is drawn).
    """
    from matplotlib.figure import Figure

    time = np.arange(trace.stats.npts) * trace.stats.delta
    figure = Figure(figsize=(8, 9), layout="constrained")
    axes = figure.subplots(3, 1, sharex=True)
    axes[0].plot(time, trace.data, lw=0.5, color="k")
    axes[0].set_ylabel("acceleration [m/s²]")
    axes[0].set_title(f"{trace.stats.station} {trace.stats.channel}")
    axes[1].plot(features.time_s, features.intensity, color="C0")
    axes[1].set_ylabel("I_g(t) [m/s²]")
    for ax in axes[:2]:
        ax.axvline(features.t0_s, color="0.5", ls=":", lw=1)
        ax.axvline(features.t0_s + features.t_max_s, color="C3", ls="--", lw=1)
    omega = spectrum["omega"].values
    shown = omega <= min(float(omega.max()), 4 * fitted.model.omega_p_rad_s)
    values = np.log10(np.maximum(spectrum.values[:, shown].T, 1e-30))
    top = float(values.max())
    mesh = axes[2].pcolormesh(
        spectrum["time"].values, omega[shown], values, shading="auto", vmin=top - 4, vmax=top
    )
    figure.colorbar(mesh, ax=axes[2], label="log10 S [(m/s²)²·s/rad]")
    axes[2].plot(features.time_s, features.omega_g_rad_s, color="w", lw=1, label="ω_g measured")
    axes[2].plot(
        features.time_s,
        fitted.model.omega_g(features.time_s),
        color="C1",
        lw=2,
        label="ω_g fitted (eq. 6.10)",
    )
    axes[2].set_ylabel("ω [rad/s]")
    axes[2].set_xlabel("time from record start [s]")
    axes[2].legend(loc="upper right")
    return figure


def amplification_figure(
    curve: xr.Dataset, *, f0_hz: float | None = None, at_f0: float | None = None
) -> Figure:
    """The spectral ratio of eq. 6.18 and both response amplifications against f0.

    Parameters
    ----------
    curve
        An amplification curve (:func:`stepframe.pipeline.amplification.amplification_curve`):
        ``spectral_ratio_eq_6_18``, ``response_amplification_vs_fixed`` and
        ``response_amplification_vs_stationary`` on ``frequency`` [Hz], with attributes
        ``xi0``, ``alpha_reading``, ``approx_eq_6_19_last`` and ``omega_path``.
    f0_hz, at_f0
        A point to mark: the oscillator's f0 [Hz] and its amplification vs fixed.
    """
    from matplotlib.figure import Figure

    frequencies = curve["frequency"].values
    figure = Figure(figsize=(7, 4.5), layout="constrained")
    ax = figure.add_subplot()
    ax.loglog(
        frequencies, curve["spectral_ratio_eq_6_18"], color="C0", label="spectral ratio, eq. 6.18"
    )
    ax.loglog(
        frequencies,
        curve["response_amplification_vs_fixed"],
        color="C3",
        label="response amplification vs fixed",
    )
    ax.loglog(
        frequencies,
        curve["response_amplification_vs_stationary"],
        color="C3",
        ls="--",
        label="response amplification vs stationary",
    )
    ax.axhline(
        curve.attrs["approx_eq_6_19_last"], color="0.5", ls=":", label="(ω_p/ω_s)², eq. 6.19"
    )
    if f0_hz is not None and at_f0 is not None:
        ax.plot([f0_hz], [at_f0], "o", color="k", label=f"f0 = {f0_hz:.3g} Hz")
    ax.set_xlabel("small-amplitude oscillator frequency f0 [Hz]")
    ax.set_ylabel("amplification [-]")
    ax.set_title(
        f"tracking ω(t) = ω0·ω_g(t)/ω_p, ξ0 = {curve.attrs['xi0']:.3g}, "
        f"α reading {curve.attrs['alpha_reading']}"
    )
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=8)
    return figure


__all__ = ["amplification_figure", "fit_figure"]
