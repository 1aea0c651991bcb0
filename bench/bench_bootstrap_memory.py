"""Memory and time of the confirmation's bootstrap at catalogue size (issue 29).

Run: ``python bench/bench_bootstrap_memory.py [--n 43000] [--resamples 1000]``.

The paired Δρ interval (:func:`stepframe.pipeline.selection.confirm.paired_delta_rho`) over
``--n`` candidates, once with the resamples drawn and ranked in blocks (the default,
``BLOCK_INDICES`` indices a block) and once with every resample at once (``BLOCK_INDICES`` set
above n × resamples), each in a fresh process so that its peak resident memory is its own. The
two print the same interval: the blocks are drawn from the same stream in order.

Prints a Markdown table for docs/benchmarks.md (wall time and peak RSS of each process).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys

CHILD = """
import resource, sys, time
import numpy as np
from stepframe.pipeline.selection import confirm
n, resamples, block = int(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3])
if block:
    confirm.BLOCK_INDICES = block
rng = np.random.default_rng(1)
x = rng.normal(size=n)
y = x + rng.normal(size=n)
r = rng.normal(size=n)
start = time.perf_counter()
value, low, high, _ = confirm.paired_delta_rho(x, r, y, seed=0, n_resamples=resamples)
seconds = time.perf_counter() - start
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
print(f"{seconds:.1f} {peak:.0f} {value:.6f} {low:.6f} {high:.6f}")
"""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=43_000, help="candidates")
    parser.add_argument("--resamples", type=int, default=1_000, help="bootstrap resamples")
    args = parser.parse_args()
    print(f"load average before: {os.getloadavg()[0]:.1f}")
    print("| bootstrap | wall [s] | peak RSS [MiB] | Δρ [low, high] |")
    print("|---|---|---|---|")
    for label, block in (("in blocks (default)", 0), ("every resample at once", 1 << 62)):
        out = subprocess.run(
            [sys.executable, "-c", CHILD, str(args.n), str(args.resamples), str(block)],
            capture_output=True, text=True, check=True,
        ).stdout.split()  # fmt: skip
        seconds, peak, value, low, high = out
        print(f"| {label} | {seconds} | {peak} | {value} [{low}, {high}] |")


if __name__ == "__main__":
    main()
