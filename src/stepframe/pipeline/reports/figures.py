"""The report's figures: each returns a matplotlib Figure (drawn without pyplot, so no GUI state).

Titles name the site or record; the site's f_p, f_s, f_r are marked where a frequency axis shows
them; a value that is only a lower bound is drawn as an open marker with an upward arrow.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from stepframe.stochastic.model import GroundMotionModel

TWO_PI = 2 * math.pi


def new_figure(width_in: float = 8.0, height_in: float = 4.6) -> Figure:
    """A figure with constrained layout, not registered with pyplot."""
    from matplotlib.figure import Figure

    return Figure(figsize=(width_in, height_in), layout="constrained")


def mark_site_frequencies(ax: Axes, model: GroundMotionModel, *, axis: str = "x") -> None:
    """Dotted lines at f_p, f_s, f_r [Hz], labelled at the top of the axes."""
    names = (
        ("f_p", model.omega_p_rad_s),
        ("f_s", model.omega_s_rad_s),
        ("f_r", model.omega_r_rad_s),
    )
    for (name, omega), colour in zip(names, ("#8250df", "#bf3989", "#0969da"), strict=True):
        f = omega / TWO_PI
        if axis == "x":
            ax.axvline(f, color=colour, ls=":", lw=1.2)
            ax.annotate(
                f"{name} = {f:.3g} Hz",
                (f, 1.0),
                xycoords=("data", "axes fraction"),
                xytext=(2, -2),
                textcoords="offset points",
                rotation=90,
                va="top",
                fontsize=8,
                color=colour,
            )
        else:
            ax.axhline(f, color=colour, ls=":", lw=1.0)
            ax.annotate(
                f"{name} = {f:.3g} Hz",
                (1.0, f),
                xycoords=("axes fraction", "data"),
                xytext=(-2, 2),
                textcoords="offset points",
                ha="right",
                fontsize=8,
                color=colour,
            )


def evolutionary_spectrum_figure(
    spectrum: Any, features: Any, fitted: GroundMotionModel, *, name: str
) -> Figure:
    """ω_g(t) over a record's evolutionary spectrum.

    The STFT spectrum S(ω, t) is the background (dB relative to its peak, 40 dB range); the
    zero-crossing estimate of ω_g(t)/2π is drawn where it entered the fit (strong motion) and
    greyed outside, the fitted eq. 6.10 path over it, t_max and t_dur as vertical lines.
    """
    fig = new_figure(8.0, 4.4)
    ax = fig.add_subplot()
    time = np.asarray(spectrum["time"].values)
    freq = np.asarray(spectrum["omega"].values) / TWO_PI
    power = np.asarray(spectrum.values, dtype=np.float64).T
    db = 10 * np.log10(np.maximum(power / max(float(power.max()), 1e-300), 1e-4))
    top = min(float(freq[-1]), 25.0)
    keep = freq <= top
    image = ax.pcolormesh(time, freq[keep], db[keep], shading="nearest", cmap="magma", vmin=-40)
    fig.colorbar(image, ax=ax, label="S(ω, t) [dB re peak]", pad=0.01)
    strong = features.strong_motion()
    observed = features.omega_g_rad_s / TWO_PI
    ax.plot(features.time_s, np.where(strong, np.nan, observed), ".", color="0.75", ms=3)
    ax.plot(
        features.time_s,
        np.where(strong, observed, np.nan),
        ".",
        color="#7ee787",
        ms=4,
        label="ω_g(t)/2π, zero crossings (strong motion)",
    )
    t = np.linspace(features.t0_s, float(time[-1]), 400)
    ax.plot(t, fitted.omega_g(t) / TWO_PI, color="#58a6ff", lw=2.2, label="fitted path, eq. 6.10")
    for value, label, style in (
        (features.t0_s + fitted.t_max_s, "t_max", "--"),
        (features.t0_s + fitted.t_dur_s, "t_dur", ":"),
    ):
        ax.axvline(value, color="white", ls=style, lw=1.2, label=f"{label} = {value:.3g} s")
    ax.set_ylim(0, top)
    ax.set_xlim(float(time[0]), float(time[-1]))
    ax.set_xlabel("time from record start [s]")
    ax.set_ylabel("frequency [Hz]")
    ax.set_title(f"{name}: dominant frequency over the evolutionary spectrum")
    ax.legend(loc="upper right", fontsize=8, framealpha=0.85)
    return fig


def spectral_ratio_figure(model: GroundMotionModel, *, site: str) -> Figure:
    """Eq. 6.18's spectral ratio over 0.1-10 Hz with eq. 6.19's two approximations (the paper's)."""
    from stepframe.stochastic.amplification import (
        approx_eq_6_19_first,
        approx_eq_6_19_last,
        spectral_ratio_eq_6_18,
    )

    f = np.geomspace(0.1, 10.0, 300)
    ratio = spectral_ratio_eq_6_18(model, TWO_PI * f)
    fig = new_figure()
    ax = fig.add_subplot()
    ax.loglog(f, ratio, color="C0", lw=2, label="spectral ratio, eq. 6.18")
    first = approx_eq_6_19_first(model)
    last = approx_eq_6_19_last(model)
    ax.axhline(first, color="C2", ls="--", label=f"eq. 6.19, first approximation = {first:.3g}")
    ax.axhline(
        last, color="C1", ls="-.", label=f"eq. 6.19, last approximation (ω_p/ω_s)² = {last:.3g}"
    )
    mark_site_frequencies(ax, model)
    ax.set_xlabel("oscillator frequency f_0 [Hz]")
    ax.set_ylabel("ratio of spectral densities [-]")
    ax.set_title(f"{site}: spectral ratio at t_max (α reading: {model.alpha_reading})")
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=8, loc="lower left")
    return fig


def response_amplification_figure(
    frequencies_hz: NDArray[np.float64],
    vs_fixed: NDArray[np.float64],
    vs_stationary: NDArray[np.float64],
    model: GroundMotionModel,
    *,
    site: str,
    xi0: float,
    monte_carlo: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], int]
    | None = None,
    band_hz: tuple[float, float] | None = None,
    frame_point: tuple[float, float, bool] | None = None,
) -> Figure:
    """Response amplification against small-amplitude frequency, with Monte Carlo intervals.

    Parameters
    ----------
    monte_carlo
        ``(frequencies [Hz], median ratio, (n, 2) interval, N)`` of the Monte Carlo check.
    band_hz
        The frame's band [f(A_max), f_1] [Hz], shaded.
    frame_point
        ``(f_1 [Hz], amplification, lower_bound)`` of the frame-driven run; a lower bound is an
        open marker with an upward arrow.
    """
    fig = new_figure(9.5, 4.6)
    ax = fig.add_subplot()
    if band_hz is not None:
        ax.axvspan(*band_hz, color="#ddf4ff", label="frame's band [f(A_max), f_1]")
    ax.semilogx(
        frequencies_hz, vs_fixed, color="C3", lw=2, label="vs fixed oscillator (covariance)"
    )
    ax.semilogx(
        frequencies_hz, vs_stationary, color="C3", ls="--", label="vs stationary RMS (covariance)"
    )
    if monte_carlo is not None:
        f_mc, median, interval, count = monte_carlo
        ax.errorbar(
            f_mc,
            median,
            yerr=np.abs(np.vstack([median - interval[:, 0], interval[:, 1] - median])),
            fmt="s",
            color="k",
            ms=4,
            capsize=3,
            label=f"Monte Carlo vs fixed, N = {count} (95 % interval)",
        )
    if frame_point is not None:
        f1, value, lower = frame_point
        if lower:
            ax.plot(
                [f1], [value], "o", mfc="white", mec="C4", ms=8, label="frame-driven: lower bound"
            )
            # an arrow up from the marker: the true value is higher (the run overturned)
            ax.annotate(
                "",
                xy=(f1, value),
                xytext=(0, 32),
                textcoords="offset points",
                ha="center",
                color="C4",
                arrowprops={"arrowstyle": "<|-", "color": "C4", "lw": 1.5},
            )
        else:
            ax.plot([f1], [value], "o", color="C4", ms=8, label="frame-driven ω(t) = 2π/T(A)")
    mark_site_frequencies(ax, model)
    ax.axhline(1.0, color="0.4", lw=0.8)
    ax.set_xlabel("small-amplitude oscillator frequency f_0 [Hz]")
    ax.set_ylabel("peak-RMS ratio [-]")
    ax.set_title(f"{site}: response amplification, tracking ω(t) = ω_0·ω_g(t)/ω_p, ξ_0 = {xi0:.3g}")
    ax.grid(True, which="both", lw=0.3)
    # outside the axes: the curves rise at both ends, where a legend inside would hide them
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    return fig


def band_lines(ax: Axes, band_hz: Sequence[float], *, label: str = "frame's band") -> None:
    """Shade a frequency band on the y axis."""
    ax.axhspan(band_hz[0], band_hz[1], color="#ddf4ff", label=label, zorder=0)


def backbone_figure(
    frame: Any, band_rad_s: Sequence[float], *, a_max_m: float | None, frame_name: str
) -> Figure:
    """The frame's period-amplitude backbone f(A) = 1/T(A) with its selection band shaded."""
    from stepframe.structure.period_amplitude import period_amplitude

    x_star = float(frame.x_star_m)
    amplitude = np.linspace(0.0, 0.995 * x_star, 400)
    frequency = 1.0 / np.asarray(period_amplitude(frame, amplitude, beyond_x_star="inf"))
    fig = new_figure(8.0, 4.2)
    ax = fig.add_subplot()
    lo, hi = (band_rad_s[0] / TWO_PI, band_rad_s[1] / TWO_PI)
    ax.axhspan(lo, hi, color="#ddf4ff", label=f"band {lo:.3g}-{hi:.3g} Hz")
    ax.plot(amplitude, frequency, color="C0", lw=2, label="backbone f(A) = 1/T(A)")
    ax.axvline(frame.x_c_m, color="0.4", ls=":", label=f"uplift x_c = {frame.x_c_m:.3g} m")
    ax.axvline(x_star, color="C3", ls="--", label=f"overturning x* = {x_star:.3g} m")
    if a_max_m is not None:
        ax.axvline(a_max_m, color="C2", ls="-.", label=f"amplitude limit A_max = {a_max_m:.3g} m")
    ax.set_yscale("log")
    ax.set_xlabel("amplitude A [m]")
    ax.set_ylabel("frequency [Hz]")
    ax.set_title(f"{frame_name}: period elongation and the selection band")
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=8, loc="lower left")
    return fig


def omega_paths_figure(
    paths: Sequence[tuple[str, GroundMotionModel, tuple[float, float]]],
    band_rad_s: Sequence[float],
) -> Figure:
    """Each record's fitted ω_g(t)/2π against the band, its strong-motion window shaded.

    ``paths``: ``(name, model, (window start, window end) [s])`` per record.
    """
    n = len(paths)
    columns = 2 if n > 1 else 1
    rows = math.ceil(n / columns)
    from matplotlib.figure import Figure

    height = 2.3 * rows + 0.6
    # fixed margins instead of constrained layout: with ten log axes the layout solver took
    # most of the report's time (docs/benchmarks.md, Reports)
    fig = Figure(figsize=(9.0, height))
    fig.subplots_adjust(
        left=0.08, right=0.98, top=1 - 0.65 / height, bottom=0.5 / height, hspace=0.5, wspace=0.08
    )
    axes = fig.subplots(rows, columns, squeeze=False, sharey=True)
    lo, hi = (band_rad_s[0] / TWO_PI, band_rad_s[1] / TWO_PI)
    for ax, (name, model, (start, end)) in zip(axes.flat, paths, strict=False):
        t = np.linspace(0.0, max(end, model.t0_s + model.t_dur_s) * 1.2, 300)
        ax.axhspan(lo, hi, color="#ddf4ff")
        ax.axvspan(start, end, color="#fff8c5")
        ax.plot(t, model.omega_g(t) / TWO_PI, color="C0", lw=1.8)
        ax.set_yscale("log")
        ax.set_title(name, fontsize=8)
        ax.grid(True, which="major", lw=0.3)
    for ax in axes.flat[n:]:
        ax.set_visible(False)
    for ax in axes[-1]:
        ax.set_xlabel("time [s]")
    for ax in axes[:, 0]:
        ax.set_ylabel("ω_g/2π [Hz]")
    fig.suptitle(
        "Fitted ω_g(t) (blue) against the frame's band (light blue), strong motion (yellow)",
        fontsize=10,
    )
    return fig


def spectra_figure(
    period_s: NDArray[np.float64],
    psa_g: NDArray[np.float64],
    names: Sequence[str],
    *,
    target: tuple[NDArray[np.float64], NDArray[np.float64]] | None,
    band_period_s: tuple[float, float] | None,
    damping: float,
) -> Figure:
    """Scaled spectra of the selected set: each record, the median and ±σ (log), the target."""
    fig = new_figure(8.0, 4.6)
    ax = fig.add_subplot()
    if band_period_s is not None:
        ax.axvspan(*band_period_s, color="#ddf4ff", label="frame's band (periods)")
    for row in psa_g:
        ax.loglog(period_s, row, color="0.7", lw=0.8)
    logs = np.log(psa_g)
    median = np.exp(np.median(logs, axis=0))
    sigma = np.std(logs, axis=0, ddof=1) if len(names) > 1 else np.zeros(period_s.size)
    ax.loglog(period_s, median, color="k", lw=2, label=f"median of {len(names)} scaled records")
    ax.loglog(period_s, median * np.exp(sigma), color="k", ls="--", lw=1, label="median · e^±σ")
    ax.loglog(period_s, median * np.exp(-sigma), color="k", ls="--", lw=1)
    if target is not None:
        ax.loglog(target[0], target[1], color="C3", lw=2, label="target spectrum")
    ax.plot([], [], color="0.7", lw=0.8, label="each record (scaled)")
    ax.set_xlabel("period T [s]")
    ax.set_ylabel(f"PSA [g], {damping:.0%} damping")
    ax.set_title("Response spectra of the selected set")
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=8, loc="lower left")
    return fig


def confirmation_figure(
    score: NDArray[np.float64],
    response: NDArray[np.float64],
    selected: NDArray[np.bool_],
    *,
    score_name: str,
    response_name: str,
    rho: float,
) -> Figure:
    """Score against simulated peak response at equal intensity; selected and controls apart."""
    fig = new_figure(7.0, 4.4)
    ax = fig.add_subplot()
    ax.plot(score[~selected], response[~selected], "o", color="0.55", label="controls / others")
    ax.plot(score[selected], response[selected], "o", color="C3", label="selected")
    ax.set_xlabel(score_name)
    ax.set_ylabel(response_name)
    ax.set_title(f"Confirmation by simulation: Spearman ρ = {rho:.2f}")
    ax.grid(True, lw=0.3)
    ax.legend(fontsize=8)
    return fig
