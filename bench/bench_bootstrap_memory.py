"""Memory and time of the confirmation's bootstrap at catalogue size (issue 29).

Run: ``python bench/bench_bootstrap_memory.py [--n 43000] [--resamples 1000]``.

The paired Δρ interval (:func:`stepframe.pipeline.selection.confirm.paired_delta_rho`) over
``--n`` candidates, each variant in a fresh process so that its peak resident memory is its own:

- ``counts``: as the function does it, each block of resamples (``BLOCK_INDICES`` indices) ranked
  from how often each candidate is drawn (no sort per resample);
- ``sorted``: the same blocks, each resample's drawn values ranked by sorting them
  (``confirm._rank_rho``, as the function did before);
- ``once``: ``sorted`` with every resample at once (``BLOCK_INDICES`` above n × resamples), as
  before the blocks (``--once``: it needs about 3 GB at 43,000).

All print the same interval up to rounding: the resamples are the same draws.

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
n, resamples, mode = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
if mode == "once":
    confirm.BLOCK_INDICES = 1 << 62
rng = np.random.default_rng(1)
x = rng.normal(size=n)
y = x + rng.normal(size=n)
r = rng.normal(size=n)
start = time.perf_counter()
if mode == "counts":
    value, low, high, _ = confirm.paired_delta_rho(x, r, y, seed=0, n_resamples=resamples)
else:  # each resample ranked by sorting its drawn values (before)
    value = float(confirm._rank_rho(x, y) - confirm._rank_rho(r, y))
    draws = confirm._resamples(np.random.default_rng(0), n, resamples)
    samples = np.concatenate(
        [confirm._rank_rho(x[p], y[p]) - confirm._rank_rho(r[p], y[p]) for p in draws]
    )
    low, high = np.percentile(samples[np.isfinite(samples)], [2.5, 97.5])
seconds = time.perf_counter() - start
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
print(f"{seconds:.1f} {peak:.0f} {value:.6f} {low:.6f} {high:.6f}")
"""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=43_000, help="candidates")
    parser.add_argument("--resamples", type=int, default=1_000, help="bootstrap resamples")
    parser.add_argument("--once", action="store_true", help="also every resample at once")
    args = parser.parse_args()
    print(f"load average before: {os.getloadavg()[0]:.1f}")
    print("| bootstrap | wall [s] | peak RSS [MiB] | Δρ [low, high] |")
    print("|---|---|---|---|")
    variants = [
        ("by counts, in blocks (default)", "counts"),
        ("sorting each resample, in blocks (before)", "sorted"),
    ]
    if args.once:
        variants.append(("sorting, every resample at once", "once"))
    for label, mode in variants:
        out = subprocess.run(
            [sys.executable, "-c", CHILD, str(args.n), str(args.resamples), mode],
            capture_output=True, text=True, check=True,
        ).stdout.split()  # fmt: skip
        seconds, peak, value, low, high = out
        print(f"| {label} | {seconds} | {peak} | {value} [{low}, {high}] |")


if __name__ == "__main__":
    main()
