"""Wall time of a command in fresh processes, as a user meets it (imports and caches included).

Shared by the bench scripts; run them from the repository root (``python bench/<script>.py``)
so that this module is importable beside them.
"""

from __future__ import annotations

import statistics
import subprocess
import time


def fresh_process_walls(command: list[str], runs: int = 6) -> tuple[float, float]:
    """Run ``command`` ``runs`` times, each in a new process.

    Returns
    -------
    first, median_rest
        Wall time of the first run and the median of the others [s]. The first run after an
        install also compiles bytecode (and numba kernels), so targets are judged on the rest.
    """
    walls = []
    for _ in range(runs):
        start = time.perf_counter()
        subprocess.run(command, check=True, capture_output=True)
        walls.append(time.perf_counter() - start)
    return walls[0], statistics.median(walls[1:])
