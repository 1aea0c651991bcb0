"""``--jobs 2`` against ``--jobs 1`` on the commands users run (issue 29, "parallel that pays").

Each case is a real command in a subprocess, ``--jobs 1`` and ``--jobs 2`` interleaved, each
``--repeat`` times (median wall time; CPU time of the command and its workers, which other users
of the machine do not inflate; the 1-minute load average beside them):

1. ``stepframe select --example fema-p695 -n 10 --confirm`` (100 components);
2. ``stepframe run selection`` copied to a folder, first run (fresh workspace each time);
3. the features stage on 1,000 components (the 100 example components at 10 amplitude scales,
   AT2 files) through ``stepframe run``, fresh workspace each time;
4. the features stage on 4 components (a batch too small for workers: it must not be slower).

    python bench/bench_parallel_pays.py [--repeat 3] [--only 1,2,3,4]

Files go to bench/out/parallel/ (ignored by git).
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

from stepframe.pipeline.catalogue.example_files import write_example_files

OUT = Path(__file__).parent / "out" / "parallel"
FRAME = Path(__file__).parents[1] / "src" / "stepframe" / "workflows" / "frames" / "example-4.toml"
FEATURES = """\
workspace = "{workspace}"
[records]
folder = "{folder}"
[outputs]
features = true
"""


def _command(args: list[str], cwd: Path) -> tuple[float, float]:
    """Wall time and CPU time (the command and its waited-for children) of one command [s]."""
    before = os.times()
    start = time.perf_counter()
    done = subprocess.run(
        [sys.executable, "-m", "stepframe.cli", *args],
        cwd=cwd,
        capture_output=True,
        text=True,
        check=False,
    )
    wall = time.perf_counter() - start
    after = os.times()
    if done.returncode != 0:
        raise SystemExit(f"{' '.join(args)} failed: {done.stderr[-2000:]}")
    return wall, (after[2] + after[3]) - (before[2] + before[3])


def _case(name: str, runs: dict[int, list[str]], cwd: Path, repeat: int, fresh: Path | None) -> Any:
    walls: dict[int, list[float]] = {1: [], 2: []}
    cpus: dict[int, list[float]] = {1: [], 2: []}
    loads = []
    for _ in range(repeat):
        for jobs in (1, 2):
            if fresh is not None:
                shutil.rmtree(fresh, ignore_errors=True)
            wall, cpu = _command(runs[jobs], cwd)
            walls[jobs].append(wall)
            cpus[jobs].append(cpu)
            loads.append(os.getloadavg()[0])
    one, two = statistics.median(walls[1]), statistics.median(walls[2])
    row = {
        "case": name,
        "jobs1_s": one,
        "jobs2_s": two,
        "speed_up": one / two,
        "cpu1_s": statistics.median(cpus[1]),
        "cpu2_s": statistics.median(cpus[2]),
        "load": [min(loads), max(loads)],
    }
    print(json.dumps(row), flush=True)
    return row


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--only", default="1,2,3,4")
    args = parser.parse_args()
    only = {int(k) for k in args.only.split(",")}
    OUT.mkdir(parents=True, exist_ok=True)
    rows = []
    if 1 in only:
        select = ["select", "--example", "fema-p695", "--frame", str(FRAME), "-n", "10"]
        runs = {j: [*select, "--confirm", "-o", f"select{j}", "--jobs", str(j)] for j in (1, 2)}
        rows.append(_case("select --confirm, 100 components", runs, OUT, args.repeat, None))
    if 2 in only:
        subprocess.run(
            [sys.executable, "-m", "stepframe.cli", "run", "selection", "--copy", "shipped"],
            cwd=OUT,
            capture_output=True,
            check=False,
        )
        workflow = OUT / "shipped" / "selection.toml"
        runs = {j: ["run", str(workflow), "--jobs", str(j)] for j in (1, 2)}
        fresh = OUT / "shipped" / "stepframe-work"
        rows.append(_case("run selection, first run", runs, OUT, args.repeat, fresh))
    for number, count in ((3, 1000), (4, 4)):
        if number not in only:
            continue
        folder = OUT / f"records{count}"
        if not folder.is_dir():
            for k in range(max(1, count // 100)):
                write_example_files(
                    folder, count=min(count, 100), scale=1 - 0.04 * k, suffix=f"_s{k}" if k else ""
                )
        path = OUT / f"features{count}.toml"
        path.write_text(FEATURES.format(workspace=f"work{count}", folder=folder.name))
        runs = {j: ["run", str(path), "--jobs", str(j)] for j in (1, 2)}
        rows.append(
            _case(f"features, {count} components", runs, OUT, args.repeat, OUT / f"work{count}")
        )
    print("\n| case | --jobs 1 [s] | --jobs 2 [s] | speed-up | CPU 1 / 2 [s] | load |")
    print("|---|---:|---:|---:|---:|---|")
    for row in rows:
        print(
            f"| {row['case']} | {row['jobs1_s']:.1f} | {row['jobs2_s']:.1f} | "
            f"{row['speed_up']:.2f}× | {row['cpu1_s']:.1f} / {row['cpu2_s']:.1f} | "
            f"{row['load'][0]:.1f}-{row['load'][1]:.1f} |"
        )


if __name__ == "__main__":
    main()
