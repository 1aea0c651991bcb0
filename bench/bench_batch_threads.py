"""The batch simulator on threads against a former revision's numba ``prange`` kernel.

``simulate_batch`` runs its in-process block on a thread per core, each thread running the
GIL-free serial kernel on pieces of the pairs; before, one numba ``prange`` loop ran them, whose
parfor lowering cost about 3 s of compilation on a first run (docs/benchmarks.md, issue 29 item
3). This script loads ``src/stepframe/structure/_exact.py`` of the revision ``--peer`` (default
the commit before the change) as a module of its own, runs its ``integrate_batch`` through the
same blocks, and times both in the same process, interleaved (wall time, median of ``--repeat``),
on the 100 FEMA P695 components at 4 scales (bench/bench_simulator.py's frame). Both must give
identical tables. An empty ``NUMBA_CACHE_DIR`` is used, so the first calls time the
compilations (process CPU time; each module compiles its own ``integrate``, the second with
numba's typing caches warm, so the order is swapped by ``--threads-first``).

    python bench/bench_batch_threads.py [--peer d5d7c2b] [--repeat 9] [--threads-first]
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

os.environ["NUMBA_CACHE_DIR"] = tempfile.mkdtemp(prefix="stepframe-numba-cache-")
os.environ["STEPFRAME_COMPILE_NOTICE"] = "0"

import numpy as np

from bench_simulator import FRAME  # a sibling script: run from the repository root
from stepframe.records.examples import fema_p695
from stepframe.records.units import STANDARD_GRAVITY_M_S2
from stepframe.structure import simulator

ROOT = Path(__file__).resolve().parents[1]
SCALES = [0.05, 0.1, 0.2, 0.4]


def _peer_kernel(rev: str, folder: Path) -> Any:
    """``integrate_batch`` of ``_exact.py`` at ``rev``, imported as a module of its own."""
    source = subprocess.run(
        ["git", "-C", str(ROOT), "show", f"{rev}:src/stepframe/structure/_exact.py"],
        check=True, capture_output=True, text=True,
    ).stdout  # fmt: skip
    path = folder / "peer_exact.py"
    path.write_text(source, encoding="utf-8")
    spec = importlib.util.spec_from_file_location("peer_exact", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.integrate_batch


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--peer", default="d5d7c2b", help="revision with the prange kernel")
    parser.add_argument("--repeat", type=int, default=9)
    parser.add_argument("--threads-first", action="store_true", help="compile this checkout first")
    args = parser.parse_args()
    stream, _ = fema_p695()
    series = [(tr.data.astype(float) * STANDARD_GRAVITY_M_S2, tr.stats.delta) for tr in stream]
    threaded = simulator._run_block
    with tempfile.TemporaryDirectory() as tmp:
        kernel = _peer_kernel(args.peer, Path(tmp))

        def prange_block(block: Any) -> np.ndarray:
            offsets = np.zeros(len(block.series) + 1, dtype=np.int64)
            offsets[1:] = np.cumsum([a.size for a in block.series])
            out = np.empty((block.scales.size, 10))
            kernel(np.concatenate(block.series), offsets, block.rec_local, block.scales,
                   block.dts, block.tails, block.params, out)  # fmt: skip
            return out

        runs = {f"prange ({args.peer})": prange_block, "threads (this checkout)": threaded}
        if args.threads_first:
            runs = dict(reversed(runs.items()))
        tables, first = {}, {}
        times: dict[str, list[float]] = {name: [] for name in runs}
        for _ in range(args.repeat + 1):
            for name, block_runner in runs.items():  # interleaved: both see the same load
                simulator._run_block = block_runner
                start, cpu = time.perf_counter(), time.process_time()
                tables[name] = simulator.simulate_batch(FRAME, series, SCALES, tail_s=0.0)
                if name in first:
                    times[name].append(time.perf_counter() - start)
                else:  # the compilation: CPU of this process, less sensitive to load than wall
                    first[name] = time.process_time() - cpu
        simulator._run_block = threaded
    old, new = tables.values()
    same = old.equals(new)
    print(f"100 FEMA P695 components x {len(SCALES)} scales, simulate_batch(..., tail_s=0), "
          f"{os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.1f}; identical tables: "
          f"{same}\n")  # fmt: skip
    print("| batch kernel | first call (compiles), CPU [s] | median wall [s] | time / prange |")
    print("|---|---|---|---|")
    base = statistics.median(times[f"prange ({args.peer})"])
    for name, values in times.items():
        median = statistics.median(values)
        print(f"| {name} | {first[name]:.2f} | {median:.4f} | {median / base:.2f} |")
    if not same:
        sys.exit("the two kernels' tables differ")


if __name__ == "__main__":
    main()
