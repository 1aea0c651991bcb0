"""Median timings shared by the bench scripts (run them from the repository root, as
``python bench/<script>.py``, so that this module is importable beside them).

Medians, not means: the 2-core machine is shared, and a median of repeated runs is robust to the
occasional run slowed by other work. ``time.thread_time`` measures what one core spends on this
thread (less sensitive to load than wall time); ``time.perf_counter`` is wall time.
"""

from __future__ import annotations

import statistics
import time
from collections.abc import Callable


def median_seconds(
    function: Callable[[], object], repeat: int = 5, clock: Callable[[], float] = time.perf_counter
) -> float:
    """Median over ``repeat`` calls of ``function()`` of the time ``clock`` measures [s]."""
    times = []
    for _ in range(repeat):
        start = clock()
        function()
        times.append(clock() - start)
    return statistics.median(times)


def median_cpu_seconds(function: Callable[[], object], repeat: int = 5) -> float:
    """Median CPU time of this thread over ``repeat`` calls of ``function()`` [s]."""
    return median_seconds(function, repeat, time.thread_time)
