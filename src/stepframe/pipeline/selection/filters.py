"""Filters of the candidate table, applied in order, each reporting what it dropped.

A row dropped by a filter keeps the filter's name in ``dropped_by`` (the first filter that
dropped it) and is never ranked. Metadata filters need their column in the table (the features
table joined with the catalogue's metadata): asking for one without its column is an error, not
a silent pass.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from stepframe.errors import InputError
from stepframe.pipeline.selection.band import FrameBand
from stepframe.pipeline.selection.options import SelectionOptions
from stepframe.pipeline.selection.path import MODEL_COLUMNS, Paths

Mask = NDArray[np.bool_]
LOWEST_USABLE_COLUMNS = ("lowest_usable_hz", "lowest_usable_frequency_hz")


@dataclass(frozen=True)
class FilterReport:
    """What one filter did: its name, the rule, how many rows it dropped and how many are left."""

    name: str
    rule: str
    dropped: int
    left: int

    def to_dict(self) -> dict[str, Any]:
        """Plain dictionary."""
        return {"name": self.name, "rule": self.rule, "dropped": self.dropped, "left": self.left}


def _column(table: Any, name: str, purpose: str) -> NDArray[Any]:
    if name not in table.columns:
        raise InputError(
            f"filter {purpose} needs column {name!r}, expected it in the features table (join "
            "the catalogue's metadata)"
        )
    return np.asarray(table[name])


def _between(values: NDArray[Any], low: float | None, high: float | None) -> Mask:
    v = np.asarray(values, dtype=np.float64)
    keep = np.isfinite(v)
    if low is not None:
        keep &= v >= low
    if high is not None:
        keep &= v <= high
    return np.asarray(keep)


def _range_text(name: str, low: float | None, high: float | None, unit: str) -> str:
    if low is not None and high is not None:
        return f"{low:g} ≤ {name} ≤ {high:g} {unit}".rstrip()
    if low is not None:
        return f"{name} ≥ {low:g} {unit}".rstrip()
    return f"{name} ≤ {high:g} {unit}".rstrip()


def apply_filters(
    table: Any, options: SelectionOptions, band: FrameBand, paths: Paths
) -> tuple[NDArray[np.object_], list[FilterReport]]:
    """The first filter that drops each row ('' when kept) and each filter's report.

    Parameters
    ----------
    table
        The candidate table: features (:data:`stepframe.stochastic.catalog_features.COLUMNS`)
        and, for the metadata filters, their columns (``magnitude``, ``rrup_km``/``rjb_km``/
        ``repi_km``, ``vs30_m_s``, ``d5_95_s``, ``pga_g``, ``rsn``, a lowest usable frequency).
    options, band, paths
        The run's options, the frame's band and the rows' strong-motion paths.
    """
    n = len(table)
    dropped_by = np.full(n, "", dtype=object)
    reports: list[FilterReport] = []
    rules: list[tuple[str, str, Callable[[], Mask]]] = []

    def finite_path() -> Mask:
        params = np.column_stack([np.asarray(table[c], dtype=np.float64) for c in MODEL_COLUMNS])
        return np.asarray(np.all(np.isfinite(params), axis=1) & np.isfinite(paths.end_s))

    rules.append(("path", "fitted parameters finite and t_max < t_dur", finite_path))
    if options.require_plausible:
        rules.append(
            (
                "fit_quality",
                "plausible fit (no parameter at a bound, floor or clip; omega in the usable band)",
                lambda: np.asarray(table["plausible"], dtype=bool),
            )
        )
    if options.exclude:
        excluded = set(options.exclude)

        def not_excluded() -> Mask:
            files = np.asarray(table["file"]).astype(str)
            names = np.array([f.rsplit("/", 1)[-1] for f in files])
            keep = ~(np.isin(files, list(excluded)) | np.isin(names, list(excluded)))
            if "rsn" in table.columns:
                rsn = np.asarray(table["rsn"]).astype(str)
                keep &= ~np.isin(rsn, list(excluded))
            return np.asarray(keep)

        rules.append(
            ("exclude", f"not in the exclusion list ({len(excluded)} entries)", not_excluded)
        )
    ranges: list[tuple[str, str, float | None, float | None, str, float]] = [
        ("magnitude", "magnitude", options.magnitude_min, options.magnitude_max, "", 1.0),
        (
            "distance",
            f"{options.distance_metric}_km",
            options.distance_min_km,
            options.distance_max_km,
            "km",
            1.0,
        ),
        ("vs30", "vs30_m_s", options.vs30_min_m_s, options.vs30_max_m_s, "m/s", 1.0),
        ("d5_95", "d5_95_s", options.d5_95_min_s, options.d5_95_max_s, "s", 1.0),
        ("pga", "pga_g", options.pga_min_g, options.pga_max_g, "g", 1.0),
    ]
    for name, column, low, high, unit, _ in ranges:
        if low is None and high is None:
            continue

        def in_range(
            column: str = column,
            low: float | None = low,
            high: float | None = high,
            name: str = name,
        ) -> Mask:
            return _between(_column(table, column, name), low, high)

        rules.append((name, _range_text(column, low, high, unit), in_range))
    if options.lowest_usable_below_band:
        limit_hz = band.omega_low_rad_s / (2 * math.pi)

        def usable() -> Mask:
            for column in LOWEST_USABLE_COLUMNS:
                if column in table.columns:
                    values = np.asarray(table[column], dtype=np.float64)
                    return np.asarray(np.isfinite(values) & (values <= limit_hz))
            raise InputError(
                "filter lowest_usable needs a column lowest_usable_hz, expected it in the "
                "features table"
            )

        rules.append(
            ("lowest_usable", f"lowest usable frequency ≤ {limit_hz:.4g} Hz (band bottom)", usable)
        )
    for name, rule, keep in rules:
        mask = keep()
        newly = (dropped_by == "") & ~mask
        dropped_by[newly] = name
        reports.append(FilterReport(name, rule, int(newly.sum()), int((dropped_by == "").sum())))
    return dropped_by, reports


def filter_summary(reports: list[FilterReport], n_rows: int) -> str:
    """One line: how many rows each filter left (``123 rows, path → 120, fit_quality → 90``)."""
    steps = ", ".join(f"{r.name} → {r.left}" for r in reports)
    return f"{n_rows} candidates" + (f", {steps}" if steps else "")
