"""The samples of candidate rows: from the ``records`` mapping, or each file re-read by path."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

from stepframe.core.results import Failure
from stepframe.errors import InputError

Floats = NDArray[np.float64]
Samples = tuple[Floats, float]
RecordKey = tuple[str, str]
#: Where samples come from: the (file, component) → samples mapping, or the read options of
#: :func:`stepframe.records.read` for reading each file by its path.
Sources = tuple[Mapping[RecordKey, Samples] | None, Mapping[str, Any] | None]


def read_samples(
    table: Any,
    rows: NDArray[np.int64],
    records: Mapping[RecordKey, Samples] | None,
    record_options: Mapping[str, Any] | None,
) -> tuple[dict[int, Samples], list[Failure]]:
    """Row → (ground acceleration [m/s²], dt [s]) of ``rows`` of ``table`` (from ``records``,
    else the file read by its path), and the rows whose samples could not be had (a batch goes
    on: they land in failures.csv)."""
    out: dict[int, Samples] = {}
    failures: list[Failure] = []
    cache: dict[str, Any] = {}
    for i in rows:
        file, component = str(table["file"].iat[i]), str(table["component"].iat[i])
        name = f"{file} [{component}]"
        try:
            if records is not None and (file, component) in records:
                acc, dt = records[(file, component)]
            else:  # a file beside the mapping's records (a folder beside the example)
                from stepframe.records.io import read_measured

                if file not in cache:  # raw counts after the standard processing, as measured
                    cache[file] = read_measured(file, **dict(record_options or {}))
                traces = [t for t in cache[file] if str(t.stats.channel) == component]
                if not traces:
                    raise InputError(f"no channel {component!r} in the file", file)
                acc, dt = np.asarray(traces[0].data, float), float(traces[0].stats.delta)
            out[int(i)] = (np.asarray(acc, dtype=np.float64), float(dt))
        except Exception as error:  # a batch goes on: the record lands in failures.csv
            failures.append(Failure.from_exception(name, "samples", error))
    return out, failures
