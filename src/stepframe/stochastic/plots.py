"""Figures of the stochastic area: a fitted record, the amplification curves and a record's
time-frequency picture.

Each function returns a :class:`matplotlib.figure.Figure` built without pyplot (no global state,
nothing shown or saved); the caller saves it, e.g. through
:func:`stepframe.core.figures.save_figure`. matplotlib is imported when a function is called.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure, SubFigure
    from obspy import Trace

    from stepframe.stochastic.features import RecordFeatures
    from stepframe.stochastic.fit import FitResult
    from stepframe.stochastic.model import GroundMotionModel


#: 2π, to draw angular frequencies [rad/s] in Hz.
TWO_PI = 2 * math.pi


#: Share of the evolutionary spectrum's energy below the top of the fit figure's spectrum panel.
ENERGY_SHARE = 0.99


def energy_band_hz(spectrum: xr.DataArray, share: float = ENERGY_SHARE) -> float:
    """The frequency [Hz] below which ``share`` of the evolutionary PSD's energy lies.

    The energy of each frequency is summed over time; the result is the first grid frequency at
    which the cumulative sum reaches ``share`` of the total (the grid's top when it is all zero).
    """
    omega = np.asarray(spectrum["omega"].values, dtype=np.float64)
    power = np.nan_to_num(np.asarray(spectrum.transpose("time", "omega").values, dtype=np.float64))
    energy = np.cumsum(np.maximum(power, 0.0).sum(axis=0))
    if energy[-1] <= 0.0:
        return float(omega[-1]) / TWO_PI
    index = int(np.searchsorted(energy, share * energy[-1]))
    return float(omega[min(index, omega.size - 1)]) / TWO_PI


def fit_figure(
    trace: Trace, spectrum: xr.DataArray, features: RecordFeatures, fitted: FitResult
) -> Figure:
    """Record, I_g(t), and the evolutionary PSD with the measured and fitted ω_g(t).

    The time origin t0 (the picked P onset, or the record start) and t0 + t_max are drawn on
    every panel and named in the legend. The spectrum panel shows frequencies [Hz] up to where
    99 % of the PSD's energy lies (and at least 1.25 f_p = 1.25 ω_p/2π, so the fitted path is
    seen whole), in dB relative to its peak over a 40 dB range.

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

    model = fitted.model
    time = np.arange(trace.stats.npts) * trace.stats.delta
    figure = Figure(figsize=(8, 9), layout="constrained")
    axes = figure.subplots(3, 1, sharex=True)
    axes[0].plot(time, trace.data, lw=0.5, color="k")
    axes[0].set_ylabel("acceleration [m/s²]")
    source = (trace.stats.get("stepframe") or {}).get("source_file")
    name = f"{trace.stats.station} {trace.stats.channel}".strip()
    if source:
        name = f"{Path(str(source)).name} [{trace.stats.channel}], {trace.stats.station}"
    axes[0].set_title(name)
    axes[1].plot(features.time_s, features.intensity, color="C0")
    axes[1].set_ylabel("I_g(t) [m/s²]")
    t0 = features.t0_s
    t0_label = (
        f"P onset t0 = {t0:.3g} s" if features.t0_source == "p-pick" else f"t0 = {t0:.3g} s (start)"
    )
    t_max = t0 + features.t_max_s
    t_max_label = f"t_max: t0 + {features.t_max_s:.3g} s"
    for ax in axes:
        # named once, in the top panel's legend; the same lines cross the panels below
        first = ax is axes[0]
        ax.axvline(t0, color="0.6", ls=":", lw=1.2, label=t0_label if first else None)
        ax.axvline(t_max, color="C3", ls="--", lw=1.2, label=t_max_label if first else None)
    for ax in axes[:2]:
        ax.grid(True, lw=0.3)
    axes[0].legend(loc="upper right", fontsize=8)
    frequency = np.asarray(spectrum["omega"].values, dtype=np.float64) / TWO_PI
    f_p = model.omega_p_rad_s / TWO_PI
    top = min(float(frequency[-1]), max(1.1 * energy_band_hz(spectrum), 1.25 * f_p))
    power = np.asarray(spectrum.transpose("time", "omega").values, dtype=np.float64).T
    db = 10 * np.log10(np.maximum(power / max(float(np.nanmax(power)), 1e-300), 1e-6))
    mesh = axes[2].pcolormesh(
        spectrum["time"].values, frequency, db, shading="auto", cmap="magma", vmin=-40, vmax=0
    )
    figure.colorbar(mesh, ax=axes[2], label="S(ω, t) [dB re peak]")
    strong = features.strong_motion()
    measured = features.omega_g_rad_s / TWO_PI
    axes[2].plot(features.time_s, np.where(strong, np.nan, measured), color="0.7", lw=0.8)
    axes[2].plot(
        features.time_s,
        np.where(strong, measured, np.nan),
        color="#7ee787",
        lw=1.2,
        label="ω_g/2π measured (strong motion; grey outside)",
    )
    axes[2].plot(
        features.time_s,
        model.omega_g(features.time_s) / TWO_PI,
        color="#58a6ff",
        lw=2,
        label=f"ω_g/2π fitted (eq. 6.10), f_p = {f_p:.3g} Hz",
    )
    axes[2].set_ylim(0.0, top)
    axes[2].set_ylabel("frequency [Hz]")
    axes[2].set_xlabel("time from record start [s]")
    axes[2].legend(loc="upper right", fontsize=8, framealpha=0.85)
    return figure


def amplification_figure(
    curve: xr.Dataset,
    *,
    f0_hz: float | None = None,
    at_f0: float | None = None,
    lower_bound: bool = False,
    site: str | None = None,
    point_name: str = "f0",
    monte_carlo: tuple[float, tuple[float, float], int] | None = None,
) -> Figure:
    """The spectral ratio of eq. 6.18 and both response amplifications against f0.

    Parameters
    ----------
    curve
        An amplification curve
        (:func:`stepframe.pipeline.amplification.amplify.amplification_curve`):
        ``spectral_ratio_eq_6_18``, ``response_amplification_vs_fixed`` and
        ``response_amplification_vs_stationary`` on ``frequency`` [Hz], with attributes
        ``xi0``, ``alpha_reading``, ``approx_eq_6_19_last`` and ``omega_path``.
    f0_hz, at_f0
        A point to mark: the oscillator's f0 [Hz] and its amplification vs fixed.
    lower_bound
        The point is only a lower bound (a frame-driven run that overturned): drawn open, with
        an arrow up.
    site
        Named in the title.
    point_name
        What the point is, in its legend entry (``"f0"``; a frame's run is not a tracking
        oscillator of the curves: "frame-driven, f_1").
    monte_carlo
        ``(amplification vs fixed, (low, high) 95 % interval, N)`` of the Monte Carlo check at
        ``f0_hz`` (synthetic motions), drawn beside the point with its interval.
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
        if lower_bound:
            label = f"{point_name} = {f0_hz:.3g} Hz: ≥ {at_f0:.3g} (overturned)"
            ax.plot([f0_hz], [at_f0], "o", mfc="white", mec="k", label=label)
            ax.annotate(
                "",
                xy=(f0_hz, at_f0),
                xytext=(0, 32),
                textcoords="offset points",
                arrowprops={"arrowstyle": "<|-", "color": "k", "lw": 1.2},
            )
        else:
            label = f"{point_name} = {f0_hz:.3g} Hz: {at_f0:.3g}"
            ax.plot([f0_hz], [at_f0], "o", color="k", label=label)
    if monte_carlo is not None and f0_hz is not None:
        value, (low, high), count = monte_carlo
        ax.errorbar(
            # a hollow square around the covariance's point at the same f0: both stay visible
            [f0_hz], [value], yerr=[[max(value - low, 0.0)], [max(high - value, 0.0)]], fmt="s",
            color="0.3", ms=7, mfc="none", capsize=5, zorder=3,
            label=f"Monte Carlo check, N = {count} motions: {value:.3g} (95 % interval)",
        )  # fmt: skip
    keys = ("model_omega_p_rad_s", "model_omega_s_rad_s", "model_omega_r_rad_s")
    if all(key in curve.attrs for key in keys):
        from stepframe.stochastic.model import GroundMotionModel

        known = set(GroundMotionModel.__dataclass_fields__)
        fields = {
            k[6:]: v for k, v in curve.attrs.items() if k.startswith("model_") and k[6:] in known
        }
        mark_site_frequencies(ax, GroundMotionModel(**fields))
    ax.set_xlabel("small-amplitude oscillator frequency f0 [Hz]")
    ax.set_ylabel("amplification [-]")
    ax.set_title(
        (f"{site}\n" if site else "")
        + f"tracking ω(t) = ω0·ω_g(t)/ω_p, ξ0 = {curve.attrs['xi0']:.3g}, "
        f"α reading {curve.attrs['alpha_reading']}",
        fontsize=10,
    )
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=8)
    return figure


#: Least distance [in] between two labels of the site-frequency scale: a label, turned upright,
#: is about 0.12 in wide at 8 pt; closer frequencies share one label.
LABEL_ROOM_IN = 0.2


def mark_site_frequencies(ax: Axes, model: GroundMotionModel) -> None:
    """Dotted lines at f_p, f_s, f_r [Hz], labelled on a scale above the axes.

    The labels sit outside the plotting area, upright, where no curve, legend or marker can
    cover them (frequencies closer than :data:`LABEL_ROOM_IN` share one label), and the x range
    is widened to include all three (a site's f_p of 15-20 Hz lies beyond a 0.1-10 Hz grid; it
    is shown, not dropped).
    """
    names = (
        ("f_r", model.omega_r_rad_s, "#0969da"),
        ("f_s", model.omega_s_rad_s, "#bf3989"),
        ("f_p", model.omega_p_rad_s, "#8250df"),
    )
    frequencies = [omega / TWO_PI for _, omega, _ in names]
    low, high = ax.get_xlim()
    low, high = min(low, min(frequencies) / 1.25), max(high, max(frequencies) * 1.25)
    ax.set_xlim(low, high)
    for (_, _, colour), f in zip(names, frequencies, strict=True):
        ax.axvline(f, color=colour, ls=":", lw=1.2)
    figure = ax.get_figure(root=True)
    assert figure is not None  # the axes were made by a figure's add_subplot
    # the axes' width before the layout engine runs, less what an outside legend may take
    width_in = 0.5 * ax.get_position().width * figure.get_figwidth()
    decades = math.log10(high / low)
    ticks: list[float] = []
    texts: list[str] = []
    colours: list[str] = []
    for (name, _, colour), f in zip(names, frequencies, strict=True):
        if ticks and math.log10(f / ticks[-1]) / decades * width_in < LABEL_ROOM_IN:
            texts[-1] = texts[-1].removesuffix(" Hz") + f", {name} {f:.3g} Hz"
            continue
        ticks.append(f)
        texts.append(f"{name} {f:.3g} Hz")
        colours.append(colour)
    top = ax.secondary_xaxis("top")
    top.set_xticks(ticks, texts)
    top.minorticks_off()
    top.tick_params(labelsize=8, length=3, labelrotation=90)
    for label, colour in zip(top.get_xticklabels(), colours, strict=True):
        label.set_color(colour)


def omega_path_figure(
    spectrum: Any, features: Any, fitted: GroundMotionModel, *, name: str
) -> Figure:
    """ω_g(t) over a record's evolutionary spectrum.

    The STFT spectrum S(ω, t) is the background (dB relative to its peak, 40 dB range); the
    zero-crossing estimate of ω_g(t)/2π is drawn where it entered the fit (strong motion) and
    greyed outside, the fitted eq. 6.10 path over it, t_0 + t_max and t_0 + t_dur as vertical
    lines (the axis is record time; the legend gives t_max and t_dur after t_0, as the fit's
    table does).
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8.0, 4.4), layout="constrained")
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
    # drawn in record time, labelled as the parameter table states them (after t_0)
    for value, label, style in (
        (fitted.t_max_s, "t_max", "--"),
        (fitted.t_dur_s, "t_dur", ":"),
    ):
        ax.axvline(
            features.t0_s + value,
            color="white",
            ls=style,
            lw=1.2,
            label=f"t_0 + {label}, {label} = {value:.3g} s",
        )
    ax.set_ylim(0, top)
    ax.set_xlim(float(time[0]), float(time[-1]))
    ax.set_xlabel("time from record start [s]")
    ax.set_ylabel("frequency [Hz]")
    ax.set_title(f"{name}: dominant frequency over the evolutionary spectrum", fontsize=10)
    ax.legend(loc="upper right", fontsize=8, framealpha=0.85)
    return fig


def frequency_range_hz(
    model: GroundMotionModel, low_hz: float = 0.1, high_hz: float = 10.0
) -> tuple[float, float]:
    """[low, high] widened to hold the site's f_r and f_p with a margin (a factor 1.25) [Hz]."""
    f_r, f_p = model.omega_r_rad_s / TWO_PI, model.omega_p_rad_s / TWO_PI
    return min(low_hz, f_r / 1.25), max(high_hz, f_p * 1.25)


def spectral_ratio_figure(
    model: GroundMotionModel, *, site: str, range_hz: tuple[float, float] = (0.1, 10.0)
) -> Figure:
    """Eq. 6.18's spectral ratio with eq. 6.19's two approximations (the paper's figure).

    Drawn over ``range_hz`` widened to hold the site's f_r and f_p
    (:func:`frequency_range_hz`): eq. 6.18 is closed-form, so it is drawn wherever the site's
    frequencies are.
    """
    from matplotlib.figure import Figure

    from stepframe.stochastic.amplification import (
        approx_eq_6_19_first,
        approx_eq_6_19_last,
        spectral_ratio_eq_6_18,
    )

    low, high = frequency_range_hz(model, *range_hz)
    f = np.geomspace(low, high, 400)
    ratio = spectral_ratio_eq_6_18(model, TWO_PI * f)
    fig = Figure(figsize=(9.5, 4.6), layout="constrained")
    ax = fig.add_subplot()
    ax.loglog(f, ratio, color="C0", lw=2, label="spectral ratio, eq. 6.18")
    first = approx_eq_6_19_first(model)
    last = approx_eq_6_19_last(model)
    ax.axhline(first, color="C2", ls="--", label=f"eq. 6.19, first approximation = {first:.3g}")
    ax.axhline(
        last, color="C1", ls="-.", label=f"eq. 6.19, last approximation (ω_p/ω_s)² = {last:.3g}"
    )
    ax.set_xlim(low, high)
    mark_site_frequencies(ax, model)
    ax.set_xlabel("oscillator frequency f_0 [Hz]")
    ax.set_ylabel("ratio of spectral densities [-]")
    ax.set_title(f"{site}: spectral ratio at t_max (α reading: {model.alpha_reading})", fontsize=10)
    ax.grid(True, which="both", lw=0.3)
    # outside the axes: the ratio spans decades, and a legend inside would cover some of them
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
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
    parameter_band: tuple[NDArray[np.float64], NDArray[np.float64], str] | None = None,
    on_grid: NDArray[np.bool_] | None = None,
) -> Figure:
    """Response amplification against small-amplitude frequency, with its uncertainty.

    Parameters
    ----------
    monte_carlo
        ``(frequencies [Hz], median ratio, (n, 2) interval, N)`` of the Monte Carlo check of
        the covariance method (synthetic motions).
    band_hz
        The frame's band [f(A_max), f_1] [Hz], shaded.
    frame_point
        ``(f_1 [Hz], amplification, lower_bound)`` of the frame-driven run; a lower bound is an
        open marker with an upward arrow.
    parameter_band
        ``(low, high, label)`` at ``frequencies_hz``: the band from the site parameters'
        standard errors, shaded along the whole curve.
    on_grid
        Which points are on the f0 grid asked for; the others (added past an edge to find a
        maximum) are drawn thinner and the grid's edges marked.
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(9.5, 4.6), layout="constrained")
    ax = fig.add_subplot()
    if band_hz is not None:
        ax.axvspan(*band_hz, color="#ddf4ff", label="frame's band [f(A_max), f_1]")
    if parameter_band is not None:
        low, high, label = parameter_band
        ax.fill_between(frequencies_hz, low, high, color="C3", alpha=0.18, lw=0, label=label)
    ax.semilogx(
        frequencies_hz, vs_fixed, color="C3", lw=2, label="vs fixed oscillator (covariance)"
    )
    ax.semilogx(
        frequencies_hz, vs_stationary, color="C3", ls="--", label="vs stationary RMS (covariance)"
    )
    if on_grid is not None and not np.all(on_grid):
        grid = frequencies_hz[on_grid]
        for edge in (grid[0], grid[-1]):
            ax.axvline(edge, color="0.35", lw=0.8, ls=(0, (6, 3)))
        ax.plot([], [], color="0.35", lw=0.8, ls=(0, (6, 3)),
                label="edges of the f0 grid asked (extended to find the maxima)")  # fmt: skip
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
            label=f"Monte Carlo check, N = {count} motions (95 % interval)",
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
    ax.set_title(
        f"{site}: response amplification, tracking ω(t) = ω_0·ω_g(t)/ω_p, ξ_0 = {xi0:.3g}",
        fontsize=10,
    )
    ax.grid(True, which="both", lw=0.3)
    # outside the axes: the curves rise at both ends, where a legend inside would hide them
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    return fig


#: Dynamic range of the time-frequency heat map [dB below its peak].
HEAT_MAP_RANGE_DB = 30.0


def time_frequency_figure(
    spectrum: xr.DataArray,
    *,
    band_rad_s: tuple[float, float] | None = None,
    path: tuple[ArrayLike, ArrayLike] | None = None,
    path_label: str = "",
    cumulative: tuple[ArrayLike, ArrayLike] | None = None,
    cumulative_label: str = "",
    marker_s: float | None = None,
    marker_label: str = "",
    title: str = "",
) -> Figure:
    """A record's evolutionary spectrum as a heat map on log frequency, optionally with a band
    shaded, a frequency path drawn over it and an accumulated quantity in a panel below.

    Data in, figure out: every argument is an array or a number, so a report or a job can draw
    the same picture from what it holds (the moving-resonance picture passes the frame's ω_f(t)
    as ``path`` and the ground's work as ``cumulative``; a site report passes neither).

    Parameters
    ----------
    spectrum
        S(ω, t) with dims (``time`` [s], ``omega`` [rad/s]) (:mod:`stepframe.stochastic.spectra`),
        drawn in dB below its peak over :data:`HEAT_MAP_RANGE_DB`, frequency in Hz on a log axis.
    band_rad_s
        (low, high) [rad/s] to shade (hatched, edges dashed), or None.
    path
        (time [s], ω [rad/s]) drawn over the heat map; values ≤ 0 or NaN are not drawn.
    path_label
        Its legend label.
    cumulative
        (time [s], value) drawn in a panel below on the same time axis, or None.
    cumulative_label
        Its y-axis label (with the unit).
    marker_s, marker_label
        A time [s] marked by a vertical line on both panels (an overturning), or None.
    title
        The title.
    """
    from matplotlib.figure import Figure

    figure = Figure(figsize=(9.0, 5.6 if cumulative is not None else 4.0), layout="constrained")
    draw_time_frequency(
        figure, spectrum, band_rad_s=band_rad_s, path=path, path_label=path_label,
        cumulative=cumulative, cumulative_label=cumulative_label, marker_s=marker_s,
        marker_label=marker_label, title=title,
    )  # fmt: skip
    return figure


def draw_time_frequency(
    target: Figure | SubFigure,
    spectrum: xr.DataArray,
    *,
    band_rad_s: tuple[float, float] | None = None,
    path: tuple[ArrayLike, ArrayLike] | None = None,
    path_label: str = "",
    cumulative: tuple[ArrayLike, ArrayLike] | None = None,
    cumulative_label: str = "",
    marker_s: float | None = None,
    marker_label: str = "",
    title: str = "",
) -> None:
    """:func:`time_frequency_figure` drawn into ``target`` (a figure, or a subfigure of a job's
    composite figure)."""
    if cumulative is not None:
        ax, below = target.subplots(2, 1, sharex=True, height_ratios=(2.2, 1))
    else:
        ax, below = target.subplots(), None
    time = np.asarray(spectrum["time"].values, dtype=np.float64)
    freq = np.asarray(spectrum["omega"].values, dtype=np.float64) / TWO_PI
    power = np.asarray(spectrum.transpose("time", "omega").values, dtype=np.float64).T
    peak = max(float(power.max()), 1e-300)
    floor = 10.0 ** (-HEAT_MAP_RANGE_DB / 10.0)
    db = 10 * np.log10(np.maximum(power / peak, floor))
    image = ax.pcolormesh(time, freq, db, shading="nearest", cmap="magma",
                          vmin=-HEAT_MAP_RANGE_DB, vmax=0.0, rasterized=True)  # fmt: skip
    target.colorbar(image, ax=ax, label="S(ω, t) [dB re peak]", pad=0.01)
    ax.set_yscale("log")
    if band_rad_s is not None:
        low, high = band_rad_s[0] / TWO_PI, band_rad_s[1] / TWO_PI
        ax.axhspan(low, high, facecolor="none", edgecolor="#58a6ff", hatch="//", lw=0.0,
                   alpha=0.35)  # fmt: skip
        for edge in (low, high):
            ax.axhline(edge, color="#58a6ff", lw=1.0, ls="--")
        ax.plot([], [], color="#58a6ff", ls="--", label=f"band {low:.3g}-{high:.3g} Hz")
    if "omega_floor" in spectrum.coords:
        # Edge effects: below the lowest frequency resolved at each time (a wavelet's cone of
        # influence, a window's floor) the estimate leans on the record's ends; grey it out.
        resolved = np.asarray(spectrum["omega_floor"].values, dtype=np.float64) / TWO_PI
        top = np.clip(np.nan_to_num(resolved, nan=freq[-1], posinf=freq[-1]), freq[0], freq[-1])
        if np.any(top > freq[0]):
            ax.fill_between(time, freq[0], top, step="mid", facecolor="#8b949e", alpha=0.45,
                            edgecolor="none", label="edge effects (not resolved)")  # fmt: skip
    if path is not None:
        path_w = np.asarray(path[1], dtype=np.float64)
        shown = np.where(np.isfinite(path_w) & (path_w > 0), path_w / TWO_PI, np.nan)
        ax.plot(np.asarray(path[0]), shown, color="#7ee787", lw=1.6, label=path_label or None)
    ax.set_ylim(float(freq[0]), float(freq[-1]))
    ax.set_xlim(float(time[0]), float(time[-1]))
    ax.set_ylabel("frequency [Hz]")
    if title:
        ax.set_title(title)
    axes = [ax] if below is None else [ax, below]
    if marker_s is not None:
        for each in axes:
            each.axvline(marker_s, color="white" if each is ax else "k", lw=1.0, ls=":")
        ax.plot([], [], color="k", lw=1.0, ls=":", label=f"{marker_label} {marker_s:.3g} s")
    if ax.get_legend_handles_labels()[0]:
        ax.legend(loc="upper right", fontsize=8, framealpha=0.85)
    if below is not None and cumulative is not None:
        below.plot(np.asarray(cumulative[0]), np.asarray(cumulative[1]), color="k", lw=1.2)
        below.set_ylabel(cumulative_label)
        below.grid(True, lw=0.3)
    axes[-1].set_xlabel("time [s]")


__all__ = [
    "ENERGY_SHARE",
    "HEAT_MAP_RANGE_DB",
    "LABEL_ROOM_IN",
    "amplification_figure",
    "draw_time_frequency",
    "energy_band_hz",
    "fit_figure",
    "frequency_range_hz",
    "mark_site_frequencies",
    "omega_path_figure",
    "response_amplification_figure",
    "spectral_ratio_figure",
    "time_frequency_figure",
]
