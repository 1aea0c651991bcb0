"""Size and load time of the embedded example catalogue; cold start of ``stepframe --help``.

Run: ``python bench/bench_examples.py``. Prints a Markdown table for docs/benchmarks.md.
"""

from __future__ import annotations

import shutil
import sys
import time
from importlib import resources

from fresh_process import fresh_process_walls


def main() -> None:
    data = resources.files("stepframe.records.data")
    archive = data.joinpath("fema_p695.npz")
    size_mb = len(archive.read_bytes()) / 1e6
    load_code = "from stepframe.records.examples import fema_p695; fema_p695()"
    _, load = fresh_process_walls([sys.executable, "-c", load_code])
    _, python_only = fresh_process_walls([sys.executable, "-c", "pass"])
    start = time.perf_counter()
    from stepframe.records.examples import fema_p695

    stream, _ = fema_p695()
    in_process = time.perf_counter() - start
    n_samples = sum(trace.stats.npts for trace in stream)
    exe = shutil.which("stepframe") or "stepframe"
    _, cold = fresh_process_walls([exe, "--help"])
    print("| quantity | value |")
    print("|---|---|")
    print(f"| archive size (100 components, {n_samples:,} samples) | {size_mb:.2f} MB |")
    print(f"| load in a fresh process, import included (median of 5) | {load:.3f} s |")
    print(f"| same, bare `python -c pass` for comparison | {python_only:.3f} s |")
    print(f"| load in process (obspy already imported by the call) | {in_process:.3f} s |")
    print(f"| `stepframe --help` cold start, 2nd run after install, median of 5 | {cold:.3f} s |")


if __name__ == "__main__":
    main()
