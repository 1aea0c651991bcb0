"""Figures of the structure area: the design iteration's cobweb and a stepping response.

Each function returns a :class:`matplotlib.figure.Figure` built without pyplot (no global state,
nothing shown or saved); the caller saves it, e.g. through
:func:`stepframe.pipeline.figures.save_figure`. matplotlib is imported when a function is called.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from matplotlib.figure import Figure

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


def response_figure(result: SimulationResult, frame: PortalFrame, *, title: str) -> Figure:
    """x(t) with the stepped samples highlighted, ±x_c and ±x* marked, and any overturning.

    Parameters
    ----------
    result
        A simulation run with ``record_history=True``.
    frame
        The frame simulated (for x_c [m] and x* [m]).
    title
        The figure title (the record and its scale).
    """
    from matplotlib.figure import Figure

    history = result.history
    if history is None:
        raise ValueError("the simulation kept no history, expected record_history=True")
    time_s = history["time"].to_numpy()
    x_m = history["x"].to_numpy()
    stepped = history["phase"].to_numpy() != 0
    figure = Figure(figsize=(9, 4), layout="tight")
    ax = figure.add_subplot()
    ax.plot(time_s, x_m, lw=0.7, color="0.3", label="x (unstepped)")
    ax.plot(time_s, np.where(stepped, x_m, np.nan), lw=1.4, color="tab:red", label="stepped")
    for level, style, name in ((frame.x_c_m, ":", "±x_c"), (frame.x_star_m, "--", "±x*")):
        ax.axhline(level, ls=style, color="tab:blue", lw=0.8, label=name)
        ax.axhline(-level, ls=style, color="tab:blue", lw=0.8)
    if result.summary.overturned and result.summary.overturn_time_s is not None:
        ax.axvline(result.summary.overturn_time_s, color="k", lw=0.8, label="overturned")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("x [m]")
    ax.set_title(title)
    ax.legend(loc="upper right", fontsize="small")
    return figure


__all__ = ["cobweb_figure", "response_figure"]
