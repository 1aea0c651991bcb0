"""Inputs of a selection run: the features table joined with catalogue metadata, record samples."""

from __future__ import annotations

from typing import Any

import numpy as np

#: Metadata columns of the embedded example catalogue that the filters and caps use.
EXAMPLE_METADATA = (
    "rsn",
    "event",
    "year",
    "magnitude",
    "rrup_km",
    "rjb_km",
    "repi_km",
    "vs30_m_s",
    "pga_g",
    "lowest_usable_frequency_hz",
)


def join_metadata(features: Any, metadata: Any, on: str = "file") -> Any:
    """``features`` with the columns of ``metadata`` it lacks, matched on ``on`` (left join).

    The column dictionaries in ``attrs`` are dropped before joining (pandas compares attrs when
    it combines frames) and the features table's dictionary is kept.
    """
    left = features.copy()
    left.attrs = {}
    right = metadata.copy()
    right.attrs = {}
    extra = [c for c in right.columns if c not in left.columns or c == on]
    joined = left.merge(right[extra], on=on, how="left")
    joined.attrs = dict(features.attrs)
    return joined


def example_catalogue(jobs: int | None = None) -> tuple[Any, dict[tuple[str, str], Any], Any]:
    """The embedded FEMA P695 catalogue as selection inputs.

    Returns
    -------
    table : pandas.DataFrame
        Features of the 100 components joined with their metadata (``event`` is event and year).
    records : dict
        (file, component) → (ground acceleration [m/s²], dt [s]).
    failures : pandas.DataFrame
        Components whose features failed (item, stage, error_type, message).
    """
    from stepframe.records.examples import fema_p695
    from stepframe.stochastic.catalog_features import catalog_features

    stream, metadata = fema_p695()
    features, failures = catalog_features(stream, n_jobs=jobs)
    meta = metadata.assign(
        file="fema_p695/" + metadata["file"].astype(str),
        event=metadata["event"].astype(str) + " " + metadata["year"].astype(str),
    )[["file", *EXAMPLE_METADATA]]
    records = {
        (str(trace.stats.stepframe.source_file), str(trace.stats.channel)): (
            np.asarray(trace.data, dtype=np.float64),
            float(trace.stats.delta),
        )
        for trace in stream
    }
    return join_metadata(features, meta), records, failures
