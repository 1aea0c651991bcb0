"""``--jobs 2`` against ``--jobs 1`` on the commands users run (issue 29, "parallel that pays").

Each case is a real command in a subprocess, ``--jobs 1`` and ``--jobs 2`` interleaved, each
``--repeat`` times (median wall time; CPU time of the command and its workers, which other users
of the machine do not inflate; the 1-minute load average beside them):

1. ``stepframe select --example fema-p695 -n 10 --confirm`` (100 components);
2. ``stepframe run selection`` copied to a folder, first run (fresh workspace each time);
3. the features stage on 1,000 components (the 100 example components at 10 amplitude scales,
   AT2 files) through ``stepframe run``, fresh workspace each time;
4. the features stage on 4 components (a batch too small for workers: it must not be slower);
5. the shipped selection workflow (features, the responses stage's exact ranking and
   confirmation, the selection, the report) over 1,000 components of :mod:`nga_catalogue`'s
   catalogue (500 records), fresh workspace each time; the stages' own seconds too.

On shared cores the wall time measures the load as much as the command, so each run also has
its processes sampled (psutil, every 0.2 s): the CPU time of the main process and of each
worker. ``--jobs 2`` on two free cores would take about main CPU + the busiest worker's CPU (the
main process waits while the workers compute), which gives the CPU-based speed-up printed
beside the wall-time one: ``--jobs 1``'s CPU over that.

    python bench/bench_parallel_pays.py [--repeat 3] [--only 1,2,3,4,5]

The host's speed drifts by a quarter within minutes, more than the change a comparison looks
for, so ``--before PYTHON`` (case 5 only) compares two installations on the same drift: each
repeat runs ``--jobs 1`` then ``--jobs 2`` with PYTHON (another venv's interpreter, the former
code installed in it), then with this interpreter, and prints each pair's speed-up of the item
stages (the inventory stage, with the features and the responses stage's exact ranking chained
to it) and their median:

    python bench/bench_parallel_pays.py --before /path/to/venv/bin/python --repeat 5

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
import threading
import time
from pathlib import Path
from typing import Any

import psutil

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


def _command(
    args: list[str], cwd: Path, python: str = sys.executable
) -> tuple[float, float, float, float, Any]:
    """One command run by ``python``: wall time, CPU time of it and its children, of its main
    process, of its busiest worker [s], and its JSON output (None unless ``--json`` was given)."""
    before = os.times()
    start = time.perf_counter()
    process = subprocess.Popen(
        [python, "-m", "stepframe.cli", *args],
        cwd=cwd,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    cpu: dict[int, float] = {}
    done = threading.Event()

    def sample() -> None:
        while not done.is_set():
            try:
                tree = [psutil.Process(process.pid)]
                tree += tree[0].children(recursive=True)
            except psutil.NoSuchProcess:
                return
            for member in tree:
                try:
                    times = member.cpu_times()
                except psutil.Error:
                    continue
                cpu[member.pid] = times.user + times.system
            done.wait(0.2)

    watcher = threading.Thread(target=sample, daemon=True)
    watcher.start()
    stdout, stderr = process.communicate()
    done.set()
    watcher.join()
    wall = time.perf_counter() - start
    after = os.times()
    if process.returncode != 0:
        raise SystemExit(f"{' '.join(args)} failed: {stderr[-2000:]}")
    total = (after[2] + after[3]) - (before[2] + before[3])
    # the main process's last sample misses its final fraction of a second: the rest of the
    # total is charged to it
    workers = [value for pid, value in cpu.items() if pid != process.pid]
    main_cpu = total - sum(workers)
    report = json.loads(stdout) if "--json" in args else None
    return wall, total, main_cpu, max(workers, default=0.0), report


def _case(name: str, runs: dict[int, list[str]], cwd: Path, repeat: int, fresh: Path | None) -> Any:
    walls: dict[int, list[float]] = {1: [], 2: []}
    cpus: dict[int, list[float]] = {1: [], 2: []}
    paths: dict[int, list[float]] = {1: [], 2: []}
    mains: dict[int, list[float]] = {1: [], 2: []}
    stages: dict[int, list[dict[str, float]]] = {1: [], 2: []}
    loads = []
    for _ in range(repeat):
        for jobs in (1, 2):
            if fresh is not None:
                shutil.rmtree(fresh, ignore_errors=True)
            loads.append(os.getloadavg()[0])
            wall, cpu, main_cpu, busiest, report = _command(runs[jobs], cwd)
            walls[jobs].append(wall)
            cpus[jobs].append(cpu)
            paths[jobs].append(main_cpu + busiest)
            mains[jobs].append(main_cpu)
            if report is not None:
                stages[jobs].append({s["name"]: s["seconds"] for s in report["stages"]})
            loads.append(os.getloadavg()[0])
    one, two = statistics.median(walls[1]), statistics.median(walls[2])
    row = {
        "case": name,
        "jobs1_s": one,
        "jobs2_s": two,
        "speed_up": one / two,
        "cpu1_s": statistics.median(cpus[1]),
        "cpu2_s": statistics.median(cpus[2]),
        "critical_path2_s": statistics.median(paths[2]),
        "main1_s": statistics.median(mains[1]),
        "main2_s": statistics.median(mains[2]),
        # the share of the work that stays in the main process with workers to hand it to
        "serial_fraction2": statistics.median(mains[2]) / statistics.median(cpus[2]),
        "cpu_speed_up": statistics.median(cpus[1]) / statistics.median(paths[2]),
        "stages": stages,
        "load": [min(loads), max(loads)],
    }
    print(json.dumps(row), flush=True)
    return row


def _item_stages_s(report: Any) -> float:
    """The item stages' seconds of a run's ``--json`` report: the inventory stage, with the
    stages chained to it, and any item stage run apart."""
    return float(
        sum(
            s["seconds"]
            for s in report["stages"]
            if s["name"] in ("inventory", "features", "responses")
        )
    )


def _before_after(scene: Path, before: str, repeat: int) -> None:
    """Case 5 with two installations alternated (module docstring, ``--before``)."""
    pythons = {"before": before, "after": sys.executable}
    ratios: dict[str, list[float]] = {name: [] for name in pythons}
    for _ in range(repeat):
        for name, python in pythons.items():
            seconds = {}
            for jobs in (1, 2):
                shutil.rmtree(scene / "work", ignore_errors=True)
                load = os.getloadavg()[0]
                args = ["run", str(scene / "selection.toml"), "--json", "--jobs", str(jobs)]
                wall, cpu, main_cpu, busiest, report = _command(args, OUT, python)
                seconds[jobs] = _item_stages_s(report)
                row = {"code": name, "jobs": jobs, "item_stages_s": seconds[jobs], "wall_s": wall}
                row |= {"cpu_s": cpu, "main_cpu_s": main_cpu, "busiest_worker_cpu_s": busiest}
                print(json.dumps(row | {"load": load}), flush=True)
            ratios[name].append(seconds[1] / seconds[2])
    print("\n| code | item stages --jobs 1 / --jobs 2, each pair | median |")
    print("|---|---|---:|")
    for name, values in ratios.items():
        cells = ", ".join(f"{value:.2f}×" for value in values)
        print(f"| {name} | {cells} | {statistics.median(values):.2f}× |")


def _nga1000() -> Path:
    """Case 5's scene: 1,000 components of :mod:`nga_catalogue` and the shipped workflow."""
    sys.path.insert(0, str(Path(__file__).parent))
    import nga_catalogue

    folder = nga_catalogue.build(nga_catalogue.OUT / "records-500", range(500))
    scene = OUT / "nga1000"
    if not (scene / "records").is_dir():
        (scene / "records").mkdir(parents=True)
        for file in sorted(folder.glob("*.AT2")):
            os.link(file, scene / "records" / file.name)
        shipped = Path(__file__).parents[1] / "src" / "stepframe" / "workflows"
        shutil.copytree(shipped / "frames", scene / "frames")
        text = (shipped / "selection.toml").read_text(encoding="utf-8")
        text = text.replace('example = "fema-p695"', 'folder = "records"')
        (scene / "selection.toml").write_text('workspace = "work"\n' + text, encoding="utf-8")
    return scene


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--only", default="1,2,3,4,5")
    parser.add_argument(
        "--before", metavar="PYTHON", help="alternate case 5 with this interpreter's stepframe"
    )
    args = parser.parse_args()
    only = {int(k) for k in args.only.split(",")}
    OUT.mkdir(parents=True, exist_ok=True)
    if args.before:
        _before_after(_nga1000(), args.before, args.repeat)
        return
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
    if 5 in only:
        scene = _nga1000()
        runs = {
            j: ["run", str(scene / "selection.toml"), "--json", "--jobs", str(j)] for j in (1, 2)
        }
        rows.append(
            _case("run selection, 1,000 components", runs, OUT, args.repeat, scene / "work")
        )
    print(
        "\n| case | --jobs 1 [s] | --jobs 2 [s] | speed-up (wall) | CPU --jobs 1 / 2 [s] |"
        " --jobs 2: main + busiest worker CPU [s] | speed-up (CPU) | load |"
    )
    print("|---|---:|---:|---:|---:|---:|---:|---|")
    for row in rows:
        print(
            f"| {row['case']} | {row['jobs1_s']:.1f} | {row['jobs2_s']:.1f} | "
            f"{row['speed_up']:.2f}× | {row['cpu1_s']:.1f} / {row['cpu2_s']:.1f} | "
            f"{row['critical_path2_s']:.1f} | {row['cpu_speed_up']:.2f}× | "
            f"{row['load'][0]:.1f}-{row['load'][1]:.1f} |"
        )
    print(
        "\n| case | main-process CPU --jobs 1 / 2 [s] | all CPU --jobs 1 / 2 [s] |"
        " serial fraction (--jobs 2) |"
    )
    print("|---|---:|---:|---:|")
    for row in rows:
        print(
            f"| {row['case']} | {row['main1_s']:.1f} / {row['main2_s']:.1f} | "
            f"{row['cpu1_s']:.1f} / {row['cpu2_s']:.1f} | {row['serial_fraction2']:.1%} |"
        )
    for row in rows:
        for jobs, runs_stages in row["stages"].items():
            for stages in runs_stages:
                cells = ", ".join(f"{name} {seconds:.1f}" for name, seconds in stages.items())
                print(f"{row['case']}, --jobs {jobs}: {cells}")


if __name__ == "__main__":
    main()
