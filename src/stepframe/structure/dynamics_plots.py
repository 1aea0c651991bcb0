"""Figures of harmonic dynamics and IDA: each function returns a matplotlib Figure.

The caller saves it (``stepframe.core.io.atomic_write(path, "wb")`` and ``fig.savefig(handle,
format="png")``) and closes it. matplotlib is imported inside each function: importing this
module costs nothing.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure

    from stepframe.structure.harmonic import HarmonicRun
    from stepframe.structure.ida import ItemIda


def bifurcation_figure(ds: xr.Dataset, *, g_m_s2: float = 9.81, title: str = "") -> Figure:
    """Stroboscopic x against amplitude [g] or frequency (the initial states whose runs survived)
    with the fraction of initial states that overturn.

    Parameters
    ----------
    ds
        A :func:`~stepframe.structure.bifurcation.bifurcation_diagram` or
        :func:`~stepframe.structure.bifurcation.frequency_diagram` result.
    g_m_s2
        Gravity used to express amplitudes in g.
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8, 5))
    ax = fig.add_subplot(1, 1, 1)
    by_amp = "amplitude" in ds.dims
    amps = ds["amplitude"].values / g_m_s2 if by_amp else ds["omega"].values
    x = ds["x_m"].values  # parameter, initial, sample
    a_grid = np.broadcast_to(amps[:, None, None], x.shape)
    # Only the runs that survived: an overturning run's last strobes are its escape (metres out,
    # which squeezed the attractors near 0 into a line), not an attractor.
    survived = (ds["outcome"].values == 0)[:, :, None]
    ok = np.isfinite(x) & survived
    ax.plot(a_grid[ok], x[ok], ".", ms=1.5, color="k", alpha=0.5)
    frac = (ds["outcome"].values == 1).mean(axis=1)
    ax2 = ax.twinx()
    ax2.plot(amps, frac, color="tab:red", lw=1.0)
    ax2.set_ylabel("fraction of initial states overturning", color="tab:red")
    ax2.set_ylim(0, 1.05)
    ax.set_xlabel("forcing amplitude [g]" if by_amp else "forcing frequency ω [rad/s]")
    ax.set_ylabel("x at t = kT [m]")
    fixed = (
        f"ω = {ds.attrs.get('omega_rad_s', 0):.4g} rad/s"
        if by_amp
        else f"A = {ds.attrs.get('amplitude_m_s2', 0) / g_m_s2:.4g} g"
    )
    ax.set_title(title or f"bifurcation diagram, {fixed}")
    fig.tight_layout()
    return fig


def ida_figure(
    items: Sequence[ItemIda],
    *,
    names: Sequence[str] | None = None,
    intensity_label: str = "PGA [g]",
) -> Figure:
    """IDA curves: intensity against peak |x| per item; overturning runs as crosses in a column
    of their own at the right (their peak is the frame's cap, metres beyond any standing peak,
    which would squeeze the curves into a sliver of the axis).

    Resurrected items are drawn in red, others in grey.
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7, 5))
    ax = fig.add_subplot(1, 1, 1)
    standing = [
        np.asarray(item.peak_abs_x_m)[~np.asarray(item.overturned, dtype=bool)] for item in items
    ]
    finite = np.concatenate([p[np.isfinite(p)] for p in standing]) if standing else np.empty(0)
    widest = float(finite.max()) if finite.size and finite.max() > 0 else 1.0
    column = 1.15 * widest  # where the overturned runs are drawn
    for k, item in enumerate(items):
        s = np.asarray(item.intensity)
        pk = np.asarray(item.peak_abs_x_m)
        ov = np.asarray(item.overturned, dtype=bool)
        color = "tab:red" if item.resurrections else "0.5"
        label = names[k] if names is not None and len(items) <= 8 else None
        ax.plot(pk[~ov], s[~ov], "-o", ms=2, lw=0.7, color=color, label=label)
        ax.plot(np.full(int(ov.sum()), column), s[ov], "x", ms=4, color=color)
    ax.axvline(1.075 * widest, color="0.7", lw=0.8, ls="--")
    ax.set_xlim(0.0, 1.23 * widest)
    ticks = [t for t in ax.get_xticks() if 0.0 <= t <= widest]
    ax.set_xticks([*ticks, column], [*(f"{t:g}" for t in ticks), "overturned"])
    ax.set_xlabel("peak |x| [m]")
    ax.set_ylabel(intensity_label)
    ax.set_title("IDA by hunt-trace-fill (red: resurrection found)")
    if names is not None and len(items) <= 8:
        ax.legend(fontsize="small")
    fig.tight_layout()
    return fig


def phase_portrait_figure(
    run: HarmonicRun,
    *,
    x_c_m: float,
    x_star_m: float,
    strobe_every: int | None = None,
    title: str = "",
) -> Figure:
    """Phase portrait (x, ẋ) of a harmonic run, with ±x_c, ±x* and stroboscopic points.

    Parameters
    ----------
    run
        A :class:`~stepframe.structure.harmonic.HarmonicRun`.
    x_c_m, x_star_m
        Switching and unstable-equilibrium displacements [m] to mark.
    strobe_every
        Samples per forcing period of ``run`` (its ``samples_per_period``): the stroboscopic
        points are drawn when given.
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6, 5))
    ax = fig.add_subplot(1, 1, 1)
    # Drop the first half as transient; an overturned run has samples only up to overturning
    # (NaN after), so all of it is drawn (its second half was empty).
    half = 0 if run.overturned else len(run.x_m) // 2
    ax.plot(run.x_m[half:], run.v_m_s[half:], lw=0.6, color="0.3")
    if strobe_every:
        ax.plot(
            run.x_m[half::strobe_every],
            run.v_m_s[half::strobe_every],
            "o",
            ms=3,
            color="tab:red",
            label="t = kT",
        )
    for level, style, name in ((x_c_m, ":", "±x_c"), (x_star_m, "--", "±x*")):
        ax.axvline(level, ls=style, color="tab:blue", lw=0.8, label=name)
        ax.axvline(-level, ls=style, color="tab:blue", lw=0.8)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("ẋ [m/s]")
    default = (
        f"phase portrait up to overturning at t = {run.t_end_s:.4g} s"
        if run.overturned
        else "phase portrait (second half of the run)"
    )
    ax.set_title(title or default)
    ax.legend(fontsize="small")
    fig.tight_layout()
    return fig
