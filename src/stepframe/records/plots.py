"""Figures of records: response spectra.

Each function returns a :class:`matplotlib.figure.Figure` built without pyplot (no global state,
no backend chosen, nothing shown or saved); the caller saves it, e.g. through
:func:`stepframe.pipeline.figures.save_figure`. matplotlib is imported when a function is called.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

from numpy.typing import ArrayLike

if TYPE_CHECKING:
    from matplotlib.figure import Figure


def response_spectra_figure(
    period_s: ArrayLike,
    psa_g: Mapping[str, ArrayLike],
    *,
    damping: float,
    combined_g: Mapping[str, ArrayLike] | None = None,
) -> Figure:
    """Pseudo-spectral acceleration of each component against period (log axis).

    Parameters
    ----------
    period_s
        Oscillator periods [s].
    psa_g
        Component name → PSA [g] at ``period_s`` (thin lines).
    damping
        Damping ratio of the spectra (fraction), for the title.
    combined_g
        Name → a combined spectrum [g] (``"RotD50"``, ``"RotD100"``; thick lines).
    """
    from matplotlib.figure import Figure

    figure = Figure(figsize=(6.4, 4.2), layout="constrained")
    axes = figure.add_subplot()
    for name, values in psa_g.items():
        axes.plot(period_s, values, label=name, lw=1)
    for name, values in (combined_g or {}).items():
        axes.plot(period_s, values, label=name, lw=2)
    axes.set(
        xscale="log",
        xlabel="period T [s]",
        ylabel="PSA [g]",
        title=f"pseudo-spectral acceleration, damping {damping:g}",
    )
    axes.grid(True, which="both", alpha=0.3)
    axes.legend()
    return figure


__all__ = ["response_spectra_figure"]
