"""The selection report's moving-resonance section: each best record's band spectrum with the
frame's ω_f(t) of its simulation over it, and the ground's work (issue 26, item 5).

One exact simulation with history per drawn record, at the ranking intensity (the record's
``ranking_scale``: where the ranking saw it respond; its scale factor when the run has none),
measured by :func:`stepframe.pipeline.dynamics.resonance.moving_resonance` over the
report's band (docs/selection.md, "Moving resonance, measured").
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from functools import partial
from typing import Any

import pandas as pd

from stepframe.pipeline.reports.document import Figure, Note, Section, Table, figure_from_matplotlib

TITLE = "Moving resonance in the best records' simulations"

#: The measures shown per record: (column, the measure's field, its column dictionary entry);
#: short column names so that the table fits the page.
SHOWN = (
    ("R_m", "moving_resonance_index", "R_m: share of the work while stepped down the band that "
     "arrived while the record's energy lay near ω_f [0-1]"),
    ("M", "moving_resonance_share", "M: share of all the ground's positive work that arrived by "
     "moving resonance [0-1]"),
    ("depth", "work_depth", "how far down its band the frame was when the ground pumped it [0-1]"),
    ("stepped_half_cycles", "n_stepping_half_cycles", "half-cycles in which the frame stepped"),
    ("lowest_omega_f_rad_s", "lowest_omega_f_rad_s", "lowest ω_f before overturning [rad/s]"),
    ("work_m2_s2", "input_energy_m2_s2", "net work of the ground on the frame [m²/s²]"),
)  # fmt: skip
COLUMNS = {
    "record": "record",
    "scale": "the record's factor at the ranking intensity (ranking_scale) [-]",
    **{column: meaning for column, _, meaning in SHOWN},
    "overturned": "the frame overturned",
}


#: One record's row of the table and its figure, or the note that replaces them.
Measured = tuple[dict[str, Any] | None, Figure | Note]


def resonance_runs(
    rows: Sequence[dict[str, Any]],
    names: Sequence[str],
    scales: Sequence[float],
    frame: Any,
    band_rad_s: tuple[float, float],
    load: Callable[[dict[str, Any]], Any],
) -> tuple[list[Callable[[], Measured]], list[str]]:
    """The section's simulations for the records ``rows`` (best first), as calls to make where
    the report's figures are drawn (:func:`~stepframe.pipeline.reports.document.draw_figures`:
    each one a simulation with history and its figure), and the names of the rows whose record
    was not found. The records are read here.

    Parameters
    ----------
    rows, scales
        The selection's rows and the factors they are simulated at [-] (the ranking's).
    names
        Display names of the selection's rows, in order (at least as many as ``rows``).
    frame
        The stepping frame (None: the folder has none, nothing is simulated).
    band_rad_s
        The report's band (low, high) [rad/s].
    load
        The row's record as a Trace in m/s², or None when its file is not found.
    """
    if frame is None:
        return [], []
    calls: list[Callable[[], Measured]] = []
    missing = []
    for k, (row, name, scale) in enumerate(zip(rows, names, scales, strict=False)):
        trace = load(row)
        if trace is None:
            missing.append(name)
            continue
        record = (trace.data, float(trace.stats.delta))
        calls.append(partial(measured, frame, record, scale, band_rad_s, (name, k)))
    return calls, missing


def measured(
    frame: Any,
    record: tuple[Any, float],
    scale: float,
    band_rad_s: tuple[float, float],
    name_position: tuple[str, int],
) -> Measured:
    """One record at ``scale`` simulated exactly with the index measured
    (:func:`~stepframe.pipeline.dynamics.resonance.moving_resonance`), its row of the table
    and its figure (None and a note when the band spectrum could not be had)."""
    from stepframe.pipeline.dynamics.resonance import moving_resonance

    name, k = name_position
    run = moving_resonance(
        frame, record[0], record[1], scale=scale, band_rad_s=band_rad_s,
        title=f"{name} × {scale:.3g}",
    )  # fmt: skip
    data = run.measures.to_dict()
    if run.spectrum is None:
        return None, Note(f"{name}: {run.measures.message}", "warning")
    row = (
        {"record": name, "scale": scale}
        | {column: data[key] for column, key, _ in SHOWN}
        | {"overturned": bool(run.result.summary.overturned)}
    )
    figure = figure_from_matplotlib(
        run.figure(),
        key=f"moving_resonance_{k + 1}",
        title=f"{name}: the record's spectrum over the band, and the frame's ω_f(t)",
        alt=(
            "heat map of the record's spectrum, frequency in Hz (log) against time in s, "
            "the band shaded, the frame's frequency drawn over it; below, the ground's "
            "accumulated work on the frame"
        ),
        how_to_read=(
            "The record at the ranking intensity, simulated exactly: where the green line "
            "(the frame's own frequency, from its half-cycles) runs through bright "
            "colour, the record's energy is where the frame is. It leaves ω_1 only while "
            "the frame steps. R_m and M in the title (docs/selection.md, 'Moving "
            "resonance, measured')."
        ),
    )
    return row, figure


def resonance_section(
    frame: Any, results: Sequence[Measured], missing: Sequence[str], numbers: dict[str, Any]
) -> Section:
    """The section from the results of :func:`resonance_runs`' calls (in order) and the
    records not found; ``numbers["moving_resonance"]`` is set (a list of rows, or "not
    run")."""
    if frame is None:
        numbers["moving_resonance"] = "not run"
        return Section(TITLE, [Note("Not run: this selection folder names no frame file.")])
    items: list[Figure | Table | Note] = [item for _, item in results]
    measured_rows = [row for row, _ in results if row is not None]
    if not measured_rows:
        numbers["moving_resonance"] = "not run"
        return Section(TITLE, [Note("None of the best records' files could be found.")])
    numbers["moving_resonance"] = measured_rows
    items.append(
        Table(
            "moving_resonance",
            "Moving-resonance measures of each drawn record",
            pd.DataFrame(measured_rows),
            "The exact simulator on each record at the ranking intensity, with the index",
            COLUMNS,
        )
    )
    if missing:
        items.append(Note(f"Not found, not drawn: {', '.join(missing)}.", "warning"))
    return Section(TITLE, items)


__all__ = ["measured", "resonance_runs", "resonance_section"]
