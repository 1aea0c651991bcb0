"""Cold start of ``stepframe --help``: this checkout against a peer checkout, same interpreter.

Usage: ``python bench/bench_cli_start.py [PEER_SRC]`` from the repository root. Each command runs
in fresh processes, interleaved with the peer and with a bare ``python -c pass`` so that machine
load affects all three alike; the table gives medians [s] and the import time of the stepframe
modules alone (``python -X importtime``, best of the runs).
"""

from __future__ import annotations

import os
import re
import statistics
import subprocess
import sys
import time
from pathlib import Path

RUNS = 15


def _wall(command: list[str], env: dict[str, str]) -> float:
    start = time.perf_counter()
    subprocess.run(command, check=True, capture_output=True, env=env)
    return time.perf_counter() - start


def _stepframe_import_s(env: dict[str, str]) -> float:
    done = subprocess.run(
        [sys.executable, "-X", "importtime", "-m", "stepframe.cli", "--help"],
        check=True, capture_output=True, text=True, env=env,
    )  # fmt: skip
    total = 0
    for line in done.stderr.splitlines():
        match = re.match(r"import time:\s+(\d+) \|\s+\d+ \|(\s*)(stepframe\S*)", line)
        if match:
            total += int(match.group(1))  # self times: each module counted once
    return total / 1e6


def main() -> None:
    here = str(Path(__file__).resolve().parents[1] / "src")
    peer = sys.argv[1] if len(sys.argv) > 1 else None
    variants = {"this checkout": here, **({"peer": peer} if peer else {})}
    envs = {name: {**os.environ, "PYTHONPATH": src} for name, src in variants.items()}
    walls: dict[str, list[float]] = {name: [] for name in [*variants, "python -c pass"]}
    imports: dict[str, list[float]] = {name: [] for name in variants}
    for _ in range(RUNS):
        walls["python -c pass"].append(_wall([sys.executable, "-c", "pass"], dict(os.environ)))
        for name, env in envs.items():
            walls[name].append(_wall([sys.executable, "-m", "stepframe.cli", "--help"], env))
            imports[name].append(_stepframe_import_s(env))
    print(f"{'':16s} {'median wall [s]':>16s} {'stepframe imports [s]':>22s}")
    for name, values in walls.items():
        own = f"{min(imports[name]):22.4f}" if name in imports else f"{'':22s}"
        print(f"{name:16s} {statistics.median(values):16.3f} {own}")


if __name__ == "__main__":
    main()
