"""The pipeline's incremental runs and executors, on the example catalogue written as AT2 files.

Run: ``python bench/bench_pipeline.py`` (incremental + executors, a few minutes on 2 cores), or
``python bench/bench_pipeline.py --scale 4000`` (the features stage on a synthetic catalogue of
4,000 components: the check of docs/scaling.md's estimate; about half an hour here).

Every run is a real ``stepframe run WORKFLOW --json`` subprocess (cold start included); counts
come from its JSON report. Parts:

1. incremental, on the 100 example components: first run, no-op re-run (ratio of wall times),
   2 new files (exactly 2 items computed per stage), the folder renamed (nothing computed), one
   changed features parameter (inventory cached, features recomputed);
2. executors, on 400 components (the 100 at 4 amplitude scales: distinct files of equal cost):
   the features stage serial (``--jobs 1``), process pool (``--jobs 2``) and ``--scheduler
   dask-local --jobs 2``, as ratios to serial;
3. ``--scale N``: N components through features with ``--jobs 2``, against the estimate from
   part 2's per-component cost, and the store's size per 1,000 components.

Files go to bench/out/pipeline/ (ignored by git). Prints Markdown tables for docs/benchmarks.md.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

from stepframe.pipeline.catalogue.example_files import write_example_files

OUT = Path(__file__).parent / "out" / "pipeline"

WORKFLOW = """\
workspace = "{workspace}"

[records]
folder = "{folder}"

[features]
window_s = {window_s}

[outputs]
features = true
"""


def _workflow(root: Path, folder: str, workspace: str, window_s: float = 2.0) -> Path:
    path = root / f"{workspace}.toml"
    path.write_text(WORKFLOW.format(folder=folder, workspace=workspace, window_s=window_s))
    return path


def _cpu_s() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def _run(workflow: Path, *extra: str) -> tuple[float, dict[str, Any]]:
    """Wall time [s] of ``stepframe run`` and its JSON report (with ``cpu_s``: CPU time of the
    run and its workers, which the other users of the machine do not inflate)."""
    cpu = _cpu_s()
    start = time.perf_counter()
    done = subprocess.run(
        [sys.executable, "-m", "stepframe.cli", "run", str(workflow), "--json", *extra],
        capture_output=True,
        text=True,
        check=False,
    )
    seconds = time.perf_counter() - start
    if done.returncode != 0:
        raise SystemExit(f"stepframe run failed ({done.returncode}): {done.stderr}")
    report = json.loads(done.stdout)
    report["cpu_s"] = _cpu_s() - cpu
    report["load"] = os.getloadavg()[0]
    return seconds, report


def _counts(report: dict[str, Any]) -> str:
    return ", ".join(f"{s['name']} {s['computed']}/{s['cached']}" for s in report["stages"])


def _stage_seconds(report: dict[str, Any], name: str) -> float:
    return float(next(s["seconds"] for s in report["stages"] if s["name"] == name))


def _catalogue(folder: Path, scales: list[float]) -> int:
    count = 0
    for number, scale in enumerate(scales):
        count += len(
            write_example_files(folder, scale=scale, suffix=f"_s{number}" if number else "")
        )
    return count


def incremental(root: Path) -> None:
    shutil.rmtree(root, ignore_errors=True)
    root.mkdir(parents=True)
    _catalogue(root / "records", [1.0])
    workflow = _workflow(root, "records", "work")
    rows = []
    first, report = _run(workflow)
    rows.append(("first run, 100 components", first, report))
    noop, report = _run(workflow)
    rows.append(("no-op re-run", noop, report))
    # 2 new files: two components at another scale (new content, same cost)
    for path in write_example_files(root / "new", count=2, scale=0.9, suffix="_new"):
        shutil.move(path, root / "records" / path.name)
    added, report = _run(workflow)
    rows.append(("2 new files", added, report))
    (root / "records").rename(root / "renamed")
    workflow = _workflow(root, "renamed", "work")
    renamed, report = _run(workflow)
    rows.append(("folder renamed", renamed, report))
    workflow = _workflow(root, "renamed", "work", window_s=3.0)
    changed, report = _run(workflow)
    rows.append(("features window_s 2 → 3", changed, report))
    first_cpu = rows[0][2]["cpu_s"]
    print(
        "\n| run | wall [s] | wall vs first | CPU [s] | CPU vs first | stage time [s] "
        "| computed/cached per stage |"
    )
    print("|---|---:|---:|---:|---:|---:|---|")
    for name, seconds, run in rows:
        stage_time = sum(s["seconds"] for s in run["stages"])
        print(
            f"| {name} | {seconds:.1f} | {seconds / first:.3f} | {run['cpu_s']:.1f} | "
            f"{run['cpu_s'] / first_cpu:.3f} | {stage_time:.2f} | {_counts(run)} |"
        )
    size = sum(p.stat().st_size for p in (root / "work" / "store").rglob("*") if p.is_file())
    print(f"\nstore after these runs: {size / 1e6:.2f} MB")
    print(
        "1-minute load average after each run (2 cores): "
        + ", ".join(f"{r[2]['load']:.1f}" for r in rows)
    )


def executors(root: Path) -> float:
    """Serial, process pool, dask-local on 400 components; returns the serial run's CPU time
    per component [s] (all stages, start-up included)."""
    shutil.rmtree(root, ignore_errors=True)
    root.mkdir(parents=True)
    n = _catalogue(root / "records", [1.0, 0.9, 0.8, 0.7])
    runs = [
        ("serial (--jobs 1)", "serial", ["--jobs", "1"]),
        ("process pool (--jobs 2)", "pool", ["--jobs", "2"]),
        ("dask-local (--jobs 2)", "dask", ["--scheduler", "dask-local", "--jobs", "2"]),
    ]
    results = []
    for name, workspace, extra in runs:
        seconds, report = _run(_workflow(root, "records", workspace), *extra)
        results.append((name, seconds, _stage_seconds(report, "features"), report))
    serial_features = results[0][2]
    print(f"\n{n} components, features stage (and the whole run, cold start included):\n")
    print(
        "| executor | features [s] | per component [ms] | speed-up vs serial | whole run [s] "
        "| CPU, all processes [s] |"
    )
    print("|---|---:|---:|---:|---:|---:|")
    for name, seconds, features, report in results:
        print(
            f"| {name} | {features:.1f} | {1000 * features / n:.0f} | "
            f"{serial_features / features:.2f}× | {seconds:.1f} | {report['cpu_s']:.0f} |"
        )
    tables = [(root / w / "outputs" / "features.parquet").read_bytes() for _, w, _ in runs]
    print(f"\nfeatures tables identical across executors: {len(set(tables)) == 1}")
    loads = ", ".join(f"{r[3]['load']:.1f}" for r in results)
    print(f"1-minute load average after each run (2 cores): {loads}")
    serial_cpu = results[0][3]["cpu_s"] / n
    print(f"serial run: {1000 * serial_cpu:.0f} ms CPU per component, all stages and start-up")
    return serial_cpu


def scale(root: Path, n_components: int, per_item_s: float | None) -> None:
    copies = -(-n_components // 100)
    scales = [1.0 - 0.5 * k / copies for k in range(copies)]
    shutil.rmtree(root / "work", ignore_errors=True)
    records = root / "records"
    if records.is_dir() and len(list(records.iterdir())) == 100 * copies:
        n = 100 * copies  # written by an earlier run (writing 4,000 files takes minutes)
    else:
        shutil.rmtree(root, ignore_errors=True)
        root.mkdir(parents=True)
        n = _catalogue(records, scales)
    seconds, report = _run(_workflow(root, "records", "work"), "--jobs", "2")
    features = _stage_seconds(report, "features")
    inventory = _stage_seconds(report, "inventory")
    store = root / "work" / "store"
    size = {
        stage: sum(p.stat().st_size for p in (store / stage).rglob("*") if p.is_file())
        for stage in ("inventory", "features")
    }
    records = sum(p.stat().st_size for p in (root / "records").iterdir())
    print(
        f"\n{n} components with --jobs 2: whole run {seconds:.0f} s, inventory {inventory:.0f} s,"
    )
    print(f"features {features:.0f} s ({1000 * features / n:.0f} ms per component, 2 workers)")
    cpu = report["cpu_s"]
    print(f"CPU time, all processes: {cpu:.0f} s ({1000 * cpu / n:.0f} ms per component)")
    print(f"wall time on 2 dedicated cores would be ≥ CPU / 2 = {cpu / 2:.0f} s")
    if per_item_s is not None:
        print(f"estimate from the serial run's CPU per component × {n}: {per_item_s * n:.0f} s CPU")
    for stage, bytes_ in size.items():
        print(f"store {stage}: {bytes_ / 1e6:.2f} MB, {bytes_ / n * 1000 / 1e6:.3f} MB per 1,000")
    print(f"record files: {records / 1e6:.0f} MB")
    _, noop = _run(_workflow(root, "records", "work"), "--jobs", "2")
    print(f"no-op re-run of {n}: {_counts(noop)}")
    print(f"1-minute load average after the run (2 cores): {report['load']:.1f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scale", type=int, default=0, metavar="N", help="also run N components")
    parser.add_argument("--per-item-s", type=float, default=None, help="serial cost for --scale")
    parser.add_argument("--only-scale", action="store_true", help="skip parts 1 and 2")
    args = parser.parse_args()
    per_item = args.per_item_s
    if not args.only_scale:
        incremental(OUT / "incremental")
        per_item = executors(OUT / "executors")
    if args.scale:
        scale(OUT / "scale", args.scale, per_item)


if __name__ == "__main__":
    main()
