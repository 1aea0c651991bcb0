"""Figures of the structure area: the design iteration's cobweb and a stepping response.

Each function returns a :class:`matplotlib.figure.Figure` built without pyplot (no global state,
nothing shown or saved); the caller saves it, e.g. through
:func:`stepframe.core.figures.save_figure`. matplotlib is imported when a function is called.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

if TYPE_CHECKING:
    from matplotlib.figure import Figure, SubFigure

    from stepframe.structure.design_spectrum import Spectrum
    from stepframe.structure.frame import PortalFrame
    from stepframe.structure.quasi_dynamic import FixedPoint, Iteration, SteppingMap
    from stepframe.structure.simulator import SimulationResult


def cobweb_figure(
    smap: SteppingMap,
    spectrum: Spectrum,
    traces: Sequence[Iteration],
    points: Sequence[FixedPoint],
) -> Figure:
    """The map f(δ), the diagonal, each iteration as a cobweb and the fixed points.

    Parameters
    ----------
    smap, spectrum
        The stepping map (eq. 2.3) and the design spectrum it is evaluated with.
    traces
        Iterations of the AASHTO/Priestley procedure (their δ_i [m]).
    points
        Fixed points: filled markers when stable, open when unstable.
    """
    from matplotlib.figure import Figure

    # Frame the iterates and the stable fixed points; an unstable δ_4* near 1/w would squash them.
    finite = [p.delta_m for p in points if p.delta_m is not None and p.stable]
    finite += [r.delta_m for t in traces for r in t.rows]
    top = min(0.999 * smap.delta_limit_m, 1.5 * max([*finite, 1e-3 * smap.delta_limit_m]))
    grid = np.linspace(0.0, top, 600)
    values = np.array([smap(float(d), spectrum) for d in grid])
    figure = Figure(figsize=(6.4, 5.2), layout="tight")
    ax = figure.add_subplot()
    ax.plot(grid, np.where(values <= 1.2 * top, values, np.nan), color="k", label="f(δ)")
    ax.plot([0, top], [0, top], color="0.6", lw=0.8, label="δ = f(δ)")
    for trace in traces:
        xs, ys = [trace.rows[0].delta_m], [0.0]
        for a, b in zip(trace.rows[:-1], trace.rows[1:], strict=True):
            xs += [a.delta_m, b.delta_m]
            ys += [b.delta_m, b.delta_m]
        ax.plot(xs, ys, lw=0.8, label=f"iteration from {trace.rows[0].delta_m:.3g} m")
    for p in points:
        if p.delta_m is not None and p.on_branch and p.delta_m <= top:
            ax.plot(p.delta_m, p.delta_m, "o", mfc="k" if p.stable else "w", mec="k")
    ax.set_xlim(0, top)
    ax.set_ylim(0, 1.2 * top)
    ax.set_xlabel(r"$\delta_i$ [m]")
    ax.set_ylabel(r"$\delta_{i+1}$ [m]")
    ax.set_title("Design iteration (filled: stable fixed point, open: unstable)")
    ax.legend(loc="upper left", fontsize=8)
    return figure


def response_figure(
    result: SimulationResult,
    frame: PortalFrame,
    *,
    title: str,
    ground_acc_m_s2: ArrayLike | None = None,
    dt_s: float | None = None,
    scale: float = 1.0,
) -> Figure:
    """x(t) with the stepped samples highlighted, ±x_c and ±x* marked, and any overturning.

    With the ground motion, a top panel draws the scaled ground acceleration [g] on the same time
    axis, with the frame's static uplift acceleration ±ω₁² x_c / P₁ marked. The legend sits below
    the axes, where it hides no line.

    Parameters
    ----------
    result
        A simulation run with ``record_history=True``.
    frame
        The frame simulated (for x_c [m], x* [m] and the uplift acceleration [m/s²]).
    title
        The figure title (the record and its scale).
    ground_acc_m_s2
        The record as given to the simulator [m/s²], unscaled; None: no ground-motion panel.
    dt_s
        Its sampling interval [s] (default the simulation's, ``result.dt_s``).
    scale
        The factor the simulation applied to the record [-]; the panel draws
        ``scale · ground_acc_m_s2`` in g.
    """
    from matplotlib.figure import Figure

    height = 4.6 if ground_acc_m_s2 is None else 6.2
    figure = Figure(figsize=(9, height), layout="constrained")
    draw_response(figure, result, frame, title=title, ground_acc_m_s2=ground_acc_m_s2, dt_s=dt_s,
                  scale=scale)  # fmt: skip
    return figure


def draw_response(
    target: Figure | SubFigure,
    result: SimulationResult,
    frame: PortalFrame,
    *,
    title: str,
    ground_acc_m_s2: ArrayLike | None = None,
    dt_s: float | None = None,
    scale: float = 1.0,
) -> None:
    """:func:`response_figure` drawn into ``target`` (a figure, or a subfigure of a job's
    composite figure)."""
    from stepframe.records.units import STANDARD_GRAVITY_M_S2

    history = result.history
    if history is None:
        raise ValueError("the simulation kept no history, expected record_history=True")
    time_s = history["time"].to_numpy()
    x_m = history["x"].to_numpy()
    stepped = history["phase"].to_numpy() != 0
    if ground_acc_m_s2 is None:
        ax = target.add_subplot()
        axes = [ax]
    else:
        ground_ax, ax = target.subplots(2, 1, sharex=True, height_ratios=(1, 2))
        axes = [ground_ax, ax]
        step = result.dt_s if dt_s is None else float(dt_s)
        acc_g = float(scale) * np.asarray(ground_acc_m_s2, dtype=float) / STANDARD_GRAVITY_M_S2
        ground_ax.plot(
            np.arange(acc_g.size) * step,
            acc_g,
            lw=0.6,
            color="0.2",
            label=f"ground acceleration × {scale:g}",
        )
        uplift_g = frame.uplift_acceleration_m_s2 / STANDARD_GRAVITY_M_S2
        ground_ax.axhline(
            uplift_g, ls=":", color="tab:orange", lw=0.9, label=f"±uplift {uplift_g:.3g} g"
        )
        ground_ax.axhline(-uplift_g, ls=":", color="tab:orange", lw=0.9)
        ground_ax.set_ylabel("ground acc. [g]")
        ground_ax.set_title(title)
        ground_ax.grid(True, lw=0.3)
    ax.plot(time_s, x_m, lw=0.7, color="0.3", label="x (unstepped)")
    ax.plot(time_s, np.where(stepped, x_m, np.nan), lw=1.4, color="tab:red", label="x (stepped)")
    for level, style, name in ((frame.x_c_m, ":", "±x_c (uplift)"), (frame.x_star_m, "--", "±x*")):
        ax.axhline(level, ls=style, color="tab:blue", lw=0.8, label=f"{name} = {level:.3g} m")
        ax.axhline(-level, ls=style, color="tab:blue", lw=0.8)
    if result.summary.overturned and result.summary.overturn_time_s is not None:
        for each in axes:
            each.axvline(result.summary.overturn_time_s, color="k", lw=0.8)
        ax.lines[-1].set_label(f"overturned at {result.summary.overturn_time_s:.3g} s")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("x [m]")
    ax.grid(True, lw=0.3)
    if ground_acc_m_s2 is None:
        ax.set_title(title)
    # Below the axes: inside, the legend would hide a ±x_c or ±x* line (they span the full width).
    handles, labels = [], []
    for each in axes:
        for handle, label in zip(*each.get_legend_handles_labels(), strict=True):
            if label not in labels:
                handles.append(handle)
                labels.append(label)
    target.legend(handles, labels, loc="outside lower center", ncol=4, fontsize="small")


#: 2π, to draw angular frequencies [rad/s] in Hz.
TWO_PI = 2 * math.pi


def backbone_figure(
    frame: PortalFrame, band_rad_s: Sequence[float], *, a_max_m: float | None, frame_name: str
) -> Figure:
    """The frame's period-amplitude backbone f(A) = 1/T(A) with its selection band shaded."""
    from stepframe.structure.period_amplitude import period_amplitude

    x_star = float(frame.x_star_m)
    amplitude = np.linspace(0.0, 0.995 * x_star, 400)
    frequency = 1.0 / np.asarray(period_amplitude(frame, amplitude, beyond_x_star="inf"))
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8.0, 4.2), layout="constrained")
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


__all__ = ["backbone_figure", "cobweb_figure", "draw_response", "response_figure"]
