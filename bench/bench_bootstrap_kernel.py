"""The confirmation's bootstrap intervals: the compiled kernel against the numpy blocks before it.

Run: ``python bench/bench_bootstrap_kernel.py [--n 43000] [--repeat 3]`` from the repository
(the former implementation is read from git: ``confirm.py`` at commit ``FORMER``, loaded as a
module of its own).

Per interval (:func:`~stepframe.pipeline.selection.confirm.spearman_interval`, 1,000 resamples,
and :func:`~stepframe.pipeline.selection.confirm.paired_delta_rho`), CPU time of this process,
median of ``--repeat``, the two implementations interleaved, on the same normal variables with
ties and infinities; and whether the two give the same numbers (bit for bit). The kernel's
first compilation is left out of the timing (it is paid once per install).
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

import numpy as np

from stepframe.pipeline.selection import confirm

#: The commit whose ``confirm.py`` ranked the resamples with numpy blocks.
FORMER = "0cc7163"
ROOT = Path(__file__).resolve().parents[1]


def former_module() -> Any:
    source = subprocess.run(
        ["git", "show", f"{FORMER}:src/stepframe/pipeline/selection/confirm.py"],
        cwd=ROOT, capture_output=True, text=True, check=True,
    ).stdout  # fmt: skip
    folder = Path(tempfile.mkdtemp())
    path = folder / "confirm_former.py"
    path.write_text(source, encoding="utf-8")
    spec = importlib.util.spec_from_file_location("confirm_former", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules["confirm_former"] = module  # its dataclasses look their module up
    spec.loader.exec_module(module)
    return module


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, nargs="+", default=[1_000, 43_000])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    former = former_module()
    confirm.spearman_interval(np.arange(5.0), np.arange(5.0), seed=0)  # compile or load
    print(f"load average: {os.getloadavg()[0]:.1f}")
    print("| interval | candidates | numpy blocks (before) [s] | kernel (now) [s] | before / now "
          "| same numbers |")  # fmt: skip
    print("|---|---|---|---|---|---|")
    for n in args.n:
        rng = np.random.default_rng(n)
        x, r = rng.normal(size=n), rng.normal(size=n)
        y = x + 0.5 * r + rng.normal(size=n)
        x[::7] = np.round(x[::7], 1)  # ties
        y[:3] = np.inf  # overturned runs rank last
        cases = {
            "Spearman ρ": lambda m, x=x, y=y: m.spearman_interval(x, y, seed=4),
            "paired Δρ": lambda m, x=x, r=r, y=y: m.paired_delta_rho(x, r, y, seed=5),
        }
        for label, call in cases.items():
            times: dict[str, list[float]] = {"former": [], "now": []}
            out: dict[str, Any] = {}
            for _ in range(args.repeat):
                for name, module in (("former", former), ("now", confirm)):
                    start = time.process_time()
                    out[name] = call(module)
                    times[name].append(time.process_time() - start)
            before, now = (statistics.median(times[k]) for k in ("former", "now"))
            print(
                f"| {label} | {n:,} | {before:.3f} | {now:.3f} | {before / now:.1f} "
                f"| {out['former'] == out['now']} |"
            )
    sys.stdout.flush()


if __name__ == "__main__":
    main()
