"""The short human summary of a selection run (``stepframe select`` and ``stepframe demo``)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from stepframe.pipeline.selection.result import SelectionResult


def summary_text(result: SelectionResult, out_dir: Path) -> str:
    """Band, chosen records, the confirmation's correlation and medians, the output folder.

    Parameters
    ----------
    result
        A selection run (:func:`~stepframe.pipeline.selection.select_records`, or one read back
        with :func:`~stepframe.pipeline.selection.read_selection`).
    out_dir
        The folder its tables were written to.
    """
    low, high = result.band_rad_s
    lines = [
        f"band: {low:.3g} to {high:.3g} rad/s (T {6.2832 / high:.3g} to {6.2832 / low:.3g} s); "
        f"{result.summary['filter_summary']}",
        f"chosen by {result.summary['rank_by']} ({result.status}: {result.message}):",
    ]
    for row in result.selection.itertuples():
        name = str(row.file).rsplit("/", 1)[-1]
        lines.append(
            f"  {row.rank:2d}. {name} [{row.component}]  score {row.score:.4g}  "
            f"scale {row.scale_factor:.3g}  P(in set) {row.selection_probability:.2f}"
        )
    for entry in result.summary.get("correlations", []):
        if entry["score"] == result.summary["rank_by"]:
            lines.append(
                f"confirmation: Spearman({entry['score']}, {entry['response']}) = "
                f"{entry['spearman']:.2f} [{entry['low']:.2f}, {entry['high']:.2f}], "
                f"n = {entry['n']}"
            )
    medians = result.summary.get("medians") or {}
    if medians:
        lines.append(
            "median peak |x| at equal PSA(T_1): selected "
            f"{medians['equal_psa_t1_peak_x_m_selected']:.3g} m, controls "
            f"{medians['equal_psa_t1_peak_x_m_control']:.3g} m"
        )
    lines.append(
        f"outputs: {out_dir}/ (selection.csv, candidates.csv, confirmation.csv, "
        "failures.csv, columns.csv, selection.json)"
    )
    return "\n".join(lines)


__all__ = ["summary_text"]
