"""The memory a selection run needs, estimated from its features table before the record pass.

The run's peak is a fixed part (the features' block of STFT frames, the ranking's and the
report's tables at small catalogues), each worker's pass over the largest record (read,
spectra, the ranking's ladder of simulations), the samples this process holds (the records
given in memory; else the chosen set and its controls), the candidates' rows (features,
scores, spectra, ladders) and the confirmation's bootstrap, drawn in blocks of
:data:`~stepframe.pipeline.selection.confirm.BLOCK_INDICES` indices. Each term was measured with
tracemalloc on ``stepframe select`` (docs/benchmarks.md, "Memory of the commands").
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from typing import Any

import numpy as np

from stepframe.core.memory import check_memory
from stepframe.pipeline.selection.confirm import BLOCK_INDICES, N_RESAMPLES

#: Fixed part [bytes]: measured 113-120 MiB with 20 to 60 candidates of 16,000-64,000 samples.
FIXED_BYTES = 128.0 * 1024**2
#: Per sample of the largest record, per worker [bytes]: its read, features, spectra and
#: ladder (measured about 130-190: 20 records of 64,000 samples, 6 of 400,000).
LARGEST_BYTES_PER_SAMPLE = 200.0
#: Per sample held in this process [bytes] (float64).
HELD_BYTES_PER_SAMPLE = 8.0
#: Per candidate [bytes]: its rows in the features, candidates and spectra tables, its peers
#: and ladder outcomes (the 43,000-candidate run of docs/benchmarks.md: about 3 KiB).
CANDIDATE_BYTES = 4096.0
#: Per bootstrap index drawn at once [bytes]: the index, the two values drawn and their ranks.
BOOTSTRAP_BYTES_PER_INDEX = 48.0


def selection_memory_bytes(
    samples: Iterable[int], held_samples: int, workers: int, n_chosen: int
) -> float:
    """The estimated peak memory of a selection run [bytes].

    Parameters
    ----------
    samples
        Samples of each candidate (its duration over its sampling interval).
    held_samples
        Samples this process holds throughout (the records given in memory).
    workers
        Worker processes that each pass over a record at once.
    n_chosen
        Components chosen: their samples and as many controls' are read into this process
        (counted at the largest record's length).
    """
    sizes = np.fromiter(samples, dtype=np.float64)
    n = int(sizes.size)
    largest = float(sizes.max()) if n else 0.0
    held = float(held_samples) + 2.0 * min(n_chosen, n) * largest
    bootstrap = min(float(n) * N_RESAMPLES, float(max(BLOCK_INDICES, n)))
    return (
        FIXED_BYTES
        + max(workers, 1) * LARGEST_BYTES_PER_SAMPLE * largest
        + HELD_BYTES_PER_SAMPLE * held
        + CANDIDATE_BYTES * n
        + BOOTSTRAP_BYTES_PER_INDEX * bootstrap
    )


def check_selection_memory(
    features: Any, records: Mapping[Any, tuple[Any, float]] | None, workers: int, n_chosen: int
) -> None:
    """Refuse a selection whose estimate (:func:`selection_memory_bytes`) passes the budget.

    Parameters
    ----------
    features
        The features table (``duration_s`` and ``dt_s`` per candidate).
    records
        The samples given in memory, or None.
    workers
        Worker processes.
    n_chosen
        Components (or records) chosen.
    """
    duration = np.asarray(features["duration_s"], dtype=np.float64)
    dt = np.asarray(features["dt_s"], dtype=np.float64)
    with np.errstate(divide="ignore", invalid="ignore"):
        counts = np.where(dt > 0, duration / dt + 1.0, 0.0)
    counts = np.nan_to_num(counts, nan=0.0, posinf=0.0)
    held = sum(int(np.size(acc)) for acc, _ in (records or {}).values())
    need = selection_memory_bytes((math.ceil(c) for c in counts), held, workers, n_chosen)
    check_memory(
        need,
        f"selecting from {counts.size} candidates (the longest {int(counts.max(initial=0))} "
        f"samples) on {max(workers, 1)} worker(s)",
        "fewer or shorter records, or fewer --jobs",
    )


__all__ = ["check_selection_memory", "selection_memory_bytes"]
