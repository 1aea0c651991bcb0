"""Filters of the candidate table, applied in order, each reporting what it dropped.

A row dropped by a filter keeps the filter's name in ``dropped_by`` (the first filter that
dropped it) and is never ranked. Metadata filters need their column in the table (the features
table joined with the catalogue's metadata): asking for one without its column is an error, not
a silent pass. The amplitude filters (PGA, PGV, PSA(T_1), D5-95, Arias) take the metadata's value
where it gives one and compute the rest from the records (:mod:`stepframe.records.intensity`,
:mod:`stepframe.records.spectra`).

Before the filters, the rows are grouped into records (:mod:`.grouping`): columns ``record``,
``record_rule``, ``vertical`` and the ``event_key``/``station_key`` the caps count (a record
without an event is its own event; without a station, its own station). Vertical components
are left out unless asked for; an exclusion entry matches a record's RSN (``RSN174``, ``174``),
its name, or a file by name, stem or path (as either catalogue names it), and an entry that
matches nothing is an error (or a warning); a cap on events or stations that no row can
honour is an error saying how to give them.
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
from stepframe.pipeline.selection.grouping import group_records
from stepframe.pipeline.selection.options import SelectionOptions
from stepframe.pipeline.selection.path import MODEL_COLUMNS, Paths
from stepframe.pipeline.selection.samples import Sources, read_samples

Mask = NDArray[np.bool_]
LOWEST_USABLE_COLUMNS = ("lowest_usable_hz", "lowest_usable_frequency_hz")


@dataclass(frozen=True)
class FilterReport:
    """What one filter did: its name, the rule, how many rows it dropped and how many are left."""

    name: str
    rule: str
    dropped: int
    left: int
    #: A warning about the rule (an exclusion entry that matched nothing, with the option
    #: that makes it a warning); '' when none.
    warning: str = ""

    def to_dict(self) -> dict[str, Any]:
        """Plain dictionary (``warning`` only when there is one)."""
        out: dict[str, Any] = {
            "name": self.name, "rule": self.rule, "dropped": self.dropped, "left": self.left
        }  # fmt: skip
        if self.warning:
            out["warning"] = self.warning
        return out


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


#: Amplitude filters: (name, column, unit, measure of the records that gives it).
AMPLITUDE_FILTERS = (
    ("pga", "pga_g", "g"),
    ("pgv", "pgv_m_s", "m/s"),
    ("psa_t1", "psa_t1_g", "g"),
    ("d5_95", "d5_95_s", "s"),
    ("arias", "arias_m_s", "m/s"),
)


def add_grouping(table: Any) -> None:
    """The table's records (:func:`.grouping.group_records`) as columns: ``record``,
    ``record_rule``, ``vertical``, and the ``event_key``/``station_key`` the caps count (the
    record's own name where the row has no event or station)."""
    grouping = group_records(table)
    table["record"] = grouping.record
    table["record_rule"] = grouping.rule
    table["vertical"] = grouping.vertical
    table["event_key"] = np.where(grouping.event == "", grouping.record, grouping.event)
    table["station_key"] = np.where(grouping.station == "", grouping.record, grouping.station)
    table["has_event"] = grouping.event != ""
    table["has_station"] = grouping.station != ""


def _check_caps(table: Any, options: SelectionOptions) -> None:
    """A cap on events or stations that no row can honour is an error saying how to give them."""
    for cap, column, what, how in (
        (
            options.max_per_event, "has_event", "event",
            "--metadata CSV with columns file,event, or records whose headers name their event "
            "(PEER RSN with metadata, K-NET/KiK-net, COSMOS, ESM, GeoNet, AT2 event field)",
        ),
        (
            options.max_per_station, "has_station", "station",
            "--metadata CSV with columns file,station, or records whose headers name their "
            "station (every format but plain text)",
        ),
    ):  # fmt: skip
        if cap is not None and not table[column].to_numpy(dtype=bool).any():
            raise InputError(
                f"max_per_{what} = {cap} needs each record's {what}, but none of the "
                f"{len(table)} components has one, expected {how}"
            )


def _exclusion_keys(table: Any) -> list[set[str]]:
    """Each row's names an exclusion entry may use (lower case): its record (``rsn174``), the
    RSN alone (``174``), the file as given, its name, its stem and every trailing part of its
    path (``fema-p695/rsn174_impvall_h-e11230.at2``)."""
    keys = []
    for file, record, rule in zip(
        table["file"].astype(str), table["record"].astype(str), table["record_rule"], strict=True
    ):
        path = file.replace("\\", "/")
        parts = [p for p in path.split("/") if p]
        names = {path, record, *("/".join(parts[k:]) for k in range(len(parts)))}
        if parts:
            names.add(parts[-1].split(".", 1)[0])
        if rule == "rsn":
            names.add(record[3:])
        keys.append({n.lower() for n in names})
    return keys


def _normalised(entry: str) -> str:
    text = entry.strip().replace("\\", "/").lower()
    while text.startswith("./"):
        text = text[2:]
    return text


def _exclusion(
    table: Any, options: SelectionOptions
) -> tuple[str, str, Callable[[], Mask], list[str]]:
    """The exclusion rule, and the entries that match no row (an error unless
    ``exclude_unmatched = "warn"``)."""
    entries = {_normalised(e): e for e in options.exclude}
    keys = _exclusion_keys(table)
    hit = np.array([bool(entries.keys() & k) for k in keys], dtype=bool)
    matched = set().union(*keys) & entries.keys() if keys else set()
    unmatched = [entries[e] for e in entries if e not in matched]
    if unmatched and options.exclude_unmatched == "error":
        example = next(iter(sorted(keys[0]))) if keys else ""
        raise InputError(
            f"exclude: {', '.join(unmatched)} matches no candidate, expected a record's RSN "
            f"(RSN174 or 174), record name, file name or path as the catalogue names it (such "
            f"as {table['record'].iat[0]!s} or {example}); exclude_unmatched = 'warn' "
            "(--exclude-unmatched warn) to go on"
        )
    rule = f"not in the exclusion list ({len(entries)} entries, matching {int(hit.sum())} rows)"
    return "exclude", rule, lambda: np.asarray(~hit), unmatched


def _measures(
    table: Any, wanted: list[tuple[str, str]], period_1_s: float, sources: Sources
) -> dict[str, str]:
    """Fill the amplitude columns of ``wanted`` (name, column) where the metadata gives no
    value, from the records; returns, per column, where its values came from."""
    from stepframe.records.intensity import intensity_measures
    from stepframe.records.spectra import response_spectrum

    origin: dict[str, str] = {}
    missing_any = np.zeros(len(table), dtype=bool)
    for _, column in wanted:
        if column not in table.columns:
            table[column] = np.nan
        missing_any |= ~np.isfinite(np.asarray(table[column], dtype=np.float64))
    rows = np.flatnonzero(missing_any)
    samples, _ = read_samples(table, rows, *sources) if rows.size else ({}, [])
    computed = {column: 0 for _, column in wanted}
    for i, (acc, dt) in samples.items():
        measures = intensity_measures(acc, dt)
        for _, column in wanted:
            if np.isfinite(table[column].iat[i]):
                continue
            if column == "psa_t1_g":
                value = float(response_spectrum(acc, dt, [period_1_s], 0.05).psa_g[0])
            else:
                value = measures[column]
            table.loc[i, column] = value
            computed[column] += 1
    for _, column in wanted:
        given = int(np.isfinite(np.asarray(table[column], dtype=np.float64)).sum())
        origin[column] = (
            f"{given - computed[column]} from metadata, {computed[column]} from the records"
        )
    return origin


Rule = tuple[str, str, Callable[[], Mask]]


def _metadata_rules(table: Any, options: SelectionOptions) -> list[Rule]:
    """The magnitude, distance and Vs30 filters asked for (each needs its column)."""
    ranges: list[tuple[str, str, float | None, float | None, str]] = [
        ("magnitude", "magnitude", options.magnitude_min, options.magnitude_max, ""),
        (
            "distance",
            f"{options.distance_metric}_km",
            options.distance_min_km,
            options.distance_max_km,
            "km",
        ),
        ("vs30", "vs30_m_s", options.vs30_min_m_s, options.vs30_max_m_s, "m/s"),
    ]
    rules: list[Rule] = []
    for name, column, low, high, unit in ranges:
        if low is None and high is None:
            continue
        missing = _missing_values(table, column, name)

        def in_range(
            column: str = column,
            low: float | None = low,
            high: float | None = high,
            name: str = name,
        ) -> Mask:
            return _between(_column(table, column, name), low, high)

        text = _range_text(column, low, high, unit)
        rules.append((name, text + (f" ({missing} without a value)" if missing else ""), in_range))
    return rules


def _missing_values(table: Any, column: str, name: str) -> int:
    """How many candidates have no value in ``column`` (they fail its filter, and the filter's
    text says how many); none with a value at all is an error, like a missing column (a filter
    on an empty column dropped every candidate as out of range: "vs30 → 0")."""
    if column not in table.columns:
        return 0  # the rule itself names the missing column
    values = np.asarray(table[column], dtype=np.float64)
    missing = int((~np.isfinite(values)).sum())
    if values.size and missing == values.size:
        raise InputError(
            f"filter {name} needs values in column {column!r}, expected the metadata to give "
            f"them (none of the {values.size} candidates has one: a --metadata CSV names it "
            f"{column})"
        )
    return missing


def _amplitude_rules(
    table: Any, options: SelectionOptions, band: FrameBand, sources: Sources
) -> list[Rule]:
    """The amplitude filters asked for, their values from the metadata or the records."""
    amplitude = [
        (name, column, unit, *options.amplitude_range(name))
        for name, column, unit in AMPLITUDE_FILTERS
        if options.amplitude_range(name) != (None, None)
    ]
    if not amplitude:
        return []
    origin = _measures(table, [(a[0], a[1]) for a in amplitude], band.period_1_s, sources)
    rules: list[Rule] = []
    for name, column, unit, low, high in amplitude:

        def measured(
            column: str = column, low: float | None = low, high: float | None = high
        ) -> Mask:
            return _between(np.asarray(table[column]), low, high)

        text = f"{_range_text(column, low, high, unit)} ({origin[column]})"
        rules.append((name, text, measured))
    return rules


def _lowest_usable_rule(table: Any, band: FrameBand) -> Rule:
    """The lowest usable frequency at or below the band's bottom."""
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

    return "lowest_usable", f"lowest usable frequency ≤ {limit_hz:.4g} Hz (band bottom)", usable


def apply_filters(
    table: Any,
    options: SelectionOptions,
    band: FrameBand,
    paths: Paths,
    sources: Sources = (None, None),
) -> tuple[NDArray[np.object_], list[FilterReport]]:
    """The first filter that drops each row ('' when kept) and each filter's report.

    Parameters
    ----------
    table
        The candidate table: features (:data:`stepframe.stochastic.catalog_features.COLUMNS`)
        and, for the metadata filters, their columns (``magnitude``, ``rrup_km``/``rjb_km``/
        ``repi_km``, ``vs30_m_s``, ``rsn``, a lowest usable frequency). The grouping's columns
        (:func:`add_grouping`) and the amplitude measures a filter asks for are added to it.
    options, band, paths
        The run's options, the frame's band and the rows' strong-motion paths.
    sources
        Where the records' samples are (amplitude measures the metadata does not give).

    Raises
    ------
    InputError
        An exclusion entry that matches nothing (unless a warning is asked for), a cap on
        events or stations that no row has, a metadata filter without its column.
    """
    add_grouping(table)
    _check_caps(table, options)
    n = len(table)
    dropped_by = np.full(n, "", dtype=object)
    reports: list[FilterReport] = []
    rules: list[Rule] = []
    warnings: dict[str, str] = {}

    def finite_path() -> Mask:
        params = np.column_stack([np.asarray(table[c], dtype=np.float64) for c in MODEL_COLUMNS])
        return np.asarray(np.all(np.isfinite(params), axis=1) & np.isfinite(paths.end_s))

    rules.append(("path", "fitted parameters finite and t_max < t_dur", finite_path))
    if not options.verticals:
        rules.append(
            (
                "vertical",
                "horizontal components only (verticals = true to keep the verticals)",
                lambda: ~table["vertical"].to_numpy(dtype=bool),
            )
        )
    if options.require_plausible:
        rules.append(
            (
                "fit_quality",
                "plausible fit (no parameter at a bound, floor or clip; omega in the usable band)",
                lambda: np.asarray(table["plausible"], dtype=bool),
            )
        )
    if options.exclude:
        name, rule, keep, unmatched = _exclusion(table, options)
        rules.append((name, rule, keep))
        if unmatched:
            warnings[name] = f"exclude: {', '.join(unmatched)} matched no candidate"
    rules += _metadata_rules(table, options)
    rules += _amplitude_rules(table, options, band, sources)
    if options.lowest_usable_below_band:
        rules.append(_lowest_usable_rule(table, band))
    for name, rule, keep in rules:
        mask = keep()
        newly = (dropped_by == "") & ~mask
        dropped_by[newly] = name
        reports.append(
            FilterReport(
                name, rule, int(newly.sum()), int((dropped_by == "").sum()),
                warnings.get(name, ""),
            )
        )  # fmt: skip
    return dropped_by, reports


def filter_summary(reports: list[FilterReport], n_rows: int) -> str:
    """One line: how many rows each filter left (``123 rows, path → 120, fit_quality → 90``)."""
    steps = ", ".join(f"{r.name} → {r.left}" for r in reports)
    return f"{n_rows} candidates" + (f", {steps}" if steps else "")
