"""What a Dask client spends per task, and idle, on a loopback cluster (issue 29).

The 43,000-component run on Dask spent more CPU in its client than the process pool's main
process did; this separates the client's cost per task from the rest. A scheduler and two
one-thread workers are started as processes of their own (``bench_nga_scale._dask_cluster``,
as the 43,000-component run has them); the client submits tasks shaped like a run's groups
(a 2 kB payload in, ``--rows`` rows of 40 floats back) through ``client.get_executor()``, as
the runner does, and its process's CPU time is read before and after; then it sits idle.

    python bench/bench_dask_tasks.py [--tasks 2000] [--rows 32] [--idle-s 30]
"""

from __future__ import annotations

import argparse
import json
import os
import time
from concurrent.futures import as_completed
from typing import Any

from bench_nga_scale import _dask_cluster


def group_rows(payload: tuple[int, str]) -> list[dict[str, float]]:
    """A group's result: ``payload[0]`` rows of 40 floats."""
    return [{f"c{k}": float(k) for k in range(40)} for _ in range(payload[0])]


def _cpu_s() -> float:
    times = os.times()
    return times.user + times.system


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tasks", type=int, default=2000)
    parser.add_argument("--rows", type=int, default=32)
    parser.add_argument("--idle-s", type=float, default=30.0)
    args = parser.parse_args()
    from dask.distributed import Client

    address, processes, _ = _dask_cluster(2)
    try:
        with Client(address) as client:
            executor = client.get_executor()
            executor.submit(int).result()  # connected, workers warm
            shapes = [(args.tasks, args.rows), (args.tasks // 4, 4 * args.rows)] * 2
            for tasks, rows in shapes:
                cpu, wall = _cpu_s(), time.perf_counter()
                futures = [executor.submit(group_rows, (rows, "x" * 2000)) for _ in range(tasks)]
                received = sum(len(f.result()) for f in as_completed(futures))
                cpu, wall = _cpu_s() - cpu, time.perf_counter() - wall
                row: dict[str, Any] = {"tasks": tasks, "rows_each": rows, "rows": received}
                row |= {"client_cpu_s": round(cpu, 3), "ms_per_task": round(1e3 * cpu / tasks, 3)}
                print(json.dumps(row | {"wall_s": round(wall, 3)}), flush=True)
            cpu = _cpu_s()
            time.sleep(args.idle_s)
            idle = (_cpu_s() - cpu) / args.idle_s
            print(json.dumps({"idle_client_cpu_ms_per_s": round(1e3 * idle, 3)}), flush=True)
    finally:
        for process in processes:
            process.kill()


if __name__ == "__main__":
    main()
