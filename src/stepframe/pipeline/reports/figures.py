"""The selection report's own figures (ω_g paths against the band, spectra, confirmation).

General-purpose figures live with their area so the command line's ``--plot`` draws the same:
:mod:`stepframe.stochastic.plots` (ω_g over the evolutionary spectrum, eq. 6.18 with eq. 6.19's
approximations, the response amplification with Monte Carlo intervals and lower bounds) and
:mod:`stepframe.structure.plots` (the period-amplitude backbone and band). Each function returns a
matplotlib Figure drawn without pyplot.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from stepframe.stochastic.model import GroundMotionModel

TWO_PI = 2 * math.pi


def new_figure(width_in: float = 8.0, height_in: float = 4.6) -> Figure:
    """A figure with constrained layout, not registered with pyplot."""
    from matplotlib.figure import Figure

    return Figure(figsize=(width_in, height_in), layout="constrained")


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
    mean_g: NDArray[np.float64] | None = None,
    check: tuple[float, tuple[float, float]] | None = None,
) -> Figure:
    """Scaled spectra of the selected set: each record, the median and ±σ (log), the target;
    with ``mean_g`` the arithmetic mean (the codes' average), with ``check`` = (fraction,
    period range [s]) the share of the target the mean must reach over the range."""
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
    if mean_g is not None:
        ax.loglog(period_s, mean_g, color="C0", lw=1.5, label="mean (the codes' average)")
    if check is not None and target is not None:
        fraction, (low, high) = check
        inside = (target[0] >= low) & (target[0] <= high)
        ax.loglog(
            target[0][inside], fraction * target[1][inside], color="C3", ls=":", lw=1.5,
            label=f"{fraction:.0%} of the target over the code's range",
        )  # fmt: skip
    ax.plot([], [], color="0.7", lw=0.8, label="each record (scaled)")
    ax.set_xlabel("period T [s]")
    ax.set_ylabel(f"PSA [g], {damping:.0%} damping")
    ax.set_title("Response spectra of the selected set")
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=8, loc="lower left")
    return fig


def accelerograms_figure(
    records: Sequence[tuple[str, NDArray[np.float64], NDArray[np.float64]]],
) -> Figure:
    """Each record's acceleration [g] against time [s], one panel per record.

    ``records``: ``(name, time [s], acceleration [g])`` per record, already scaled.
    """
    from matplotlib.figure import Figure

    n = len(records)
    height = 1.9 * n + 0.7
    fig = Figure(figsize=(9.0, height))  # fixed margins: see omega_paths_figure
    fig.subplots_adjust(left=0.09, right=0.98, top=1 - 0.35 / height, bottom=0.5 / height,
                        hspace=0.6)  # fmt: skip
    axes = fig.subplots(n, 1, squeeze=False)[:, 0]
    for ax, (name, time_s, acceleration_g) in zip(axes, records, strict=True):
        ax.plot(time_s, acceleration_g, color="k", lw=0.5)
        ax.set_title(name, fontsize=8)
        ax.set_ylabel("a [g]")
        ax.grid(True, lw=0.3)
    axes[-1].set_xlabel("time [s]")
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
    shown = f"{rho:.2f}" if np.isfinite(rho) else "undefined (too few records or no spread)"
    ax.set_title(f"Confirmation by simulation: Spearman ρ = {shown}")
    ax.grid(True, lw=0.3)
    ax.legend(fontsize=8)
    return fig


def backbone_points_figure(details: dict[str, Any], band_rad_s: Sequence[float]) -> Figure:
    """The backbone at the selection's amplitude levels (when the run names no frame file)."""
    amplitude = np.asarray(details["level_amplitudes_m"], dtype=np.float64)
    frequency = np.asarray(details["level_omegas_rad_s"], dtype=np.float64) / TWO_PI
    fig = new_figure(8.0, 4.2)
    ax = fig.add_subplot()
    lo, hi = (band_rad_s[0] / TWO_PI, band_rad_s[1] / TWO_PI)
    ax.axhspan(lo, hi, color="#ddf4ff", label=f"band {lo:.3g}-{hi:.3g} Hz")
    ax.plot(amplitude, frequency, "o-", color="C0", lw=2, label="f(A) = 1/T(A) at the levels")
    for key, style, colour, name in (
        ("x_c_m", ":", "0.4", "uplift x_c"),
        ("x_star_m", "--", "C3", "overturning x*"),
        ("a_max_m", "-.", "C2", "amplitude limit A_max"),
    ):
        if isinstance(details.get(key), int | float):
            value = float(details[key])
            ax.axvline(value, color=colour, ls=style, label=f"{name} = {value:.3g} m")
    ax.set_yscale("log")
    ax.set_xlabel("amplitude A [m]")
    ax.set_ylabel("frequency [Hz]")
    ax.set_title("The frame's period elongation and the selection band")
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=8, loc="lower left")
    return fig
