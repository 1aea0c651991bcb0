"""Figures of records: response spectra.

Each function returns a :class:`matplotlib.figure.Figure` built without pyplot (no global state,
no backend chosen, nothing shown or saved); the caller saves it, e.g. through
:func:`stepframe.core.figures.save_figure`. matplotlib is imported when a function is called.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
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
    record: str | Sequence[str] | None = None,
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
    record
        The record named in the title: its file name, e.g. ``"RSN8883_14383980_13849360.AT2"``
        (the components drawn, the keys of ``psa_g``, follow it in brackets), or one file name
        per component of ``psa_g`` (components read from two files: one line each).
    """
    from matplotlib.figure import Figure

    figure = Figure(figsize=(6.4, 4.6), layout="constrained")
    axes = figure.add_subplot()
    for name, values in psa_g.items():
        axes.plot(period_s, values, label=name, lw=1)
    for name, values in (combined_g or {}).items():
        axes.plot(period_s, values, label=name, lw=2)
    axes.set(xscale="log", xlabel="period T [s]", ylabel="PSA [g]")
    axes.set_title(spectra_title(record, list(psa_g), damping), fontsize=10)
    axes.grid(True, which="both", alpha=0.3)
    axes.legend()
    return figure


def spectra_title(
    record: str | Sequence[str] | None, components: Sequence[str], damping: float
) -> str:
    """The record and its components over ``"pseudo-spectral acceleration, damping 5 %"``.

    ``"FILE [C1, C2]"`` for one file name; ``"FILE1 [C1]"`` and ``"FILE2 [C2]"`` on two lines for
    one file name per component (the same name repeated is written once); ``"components C1,
    C2"`` without a name.
    """
    tail = f"pseudo-spectral acceleration, damping {100 * damping:g} %"
    if isinstance(record, str) or (record is not None and len(set(record)) == 1):
        name = record if isinstance(record, str) else next(iter(record))
        head = f"{name} [{', '.join(components)}]" if components else name
    elif record:
        if len(record) != len(components):
            raise ValueError(
                f"{len(record)} record names for {len(components)} components, expected one each"
            )
        head = "\n".join(f"{n} [{c}]" for n, c in zip(record, components, strict=True))
    else:
        head = f"components {', '.join(components)}" if components else ""
    return f"{head}\n{tail}" if head else tail


__all__ = ["response_spectra_figure", "spectra_title"]
