"""The selection workflow at NGA-West2 size: 43,000 components on this machine, then on Dask.

Run: ``python bench/bench_nga_scale.py`` (about an hour on 2 shared cores, after
``bench/nga_catalogue.py`` has written the catalogue; it is written here first if missing), or
``python bench/bench_nga_scale.py --records 500 --name small`` for a quick look.

The shipped selection workflow (``stepframe run selection``: features, the selection with
confirmation, the HTML report) with its records folder replaced by the synthetic catalogue of
:mod:`nga_catalogue` (hard links in a folder of the run's own). Every run is a real
``nice stepframe run WORKFLOW --json`` subprocess. Parts, in order:

1. first run with ``--jobs 2``: wall time per stage, peak memory of the process tree (summed
   PSS, sampled every 0.5 s: shared pages counted once), CPU time of the run's main process and
   of all its processes, store and output sizes, the report's size and its largest table;
2. the no-op re-run (twice);
3. the re-run after adding 1 % new records (the catalogue's ``extra`` records), and its no-op;
4. the run of part 1 on a Dask cluster on loopback (``dask scheduler`` and two ``dask worker``
   processes of one thread each, started here): outputs compared byte for byte with part 1, CPU
   of the main process against the workers' (the serial fraction), and the overhead.

Results are written after each part. ``--dask-only`` runs part 4 alone against the results of
an earlier run of the same ``--name`` (its part 1's output hashes).

The 1-minute load average is recorded beside every number (the 2 cores are shared). Results go
to ``bench/out/nga/<name>-results.json``; Markdown tables for docs/benchmarks.md and
docs/scaling.md are printed.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import shutil
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path
from typing import Any

import psutil

import nga_catalogue

OUT = nga_catalogue.OUT
SHIPPED = Path(__file__).resolve().parents[1] / "src" / "stepframe" / "workflows"
#: The output files compared between runs (the JSON summary carries a measured throughput).
COMPARED = (
    "features.parquet",
    "selection/selection.csv",
    "selection/candidates.csv",
    "selection/confirmation.csv",
    "selection/failures.csv",
)


class TreeMonitor(threading.Thread):
    """Samples the process trees of some roots: summed PSS (peak) and each process's CPU time."""

    def __init__(self, roots: list[int], interval_s: float = 0.5) -> None:
        super().__init__(daemon=True)
        self.roots = roots
        self.interval_s = interval_s
        self.peak_pss = 0
        self.peak_rss = 0
        self.cpu: dict[int, tuple[str, float]] = {}
        self._stop_event = threading.Event()

    def _sample(self) -> None:
        processes = []
        for root in self.roots:
            try:
                parent = psutil.Process(root)
                processes += [parent, *parent.children(recursive=True)]
            except psutil.NoSuchProcess:
                continue
        pss = rss = 0
        for process in processes:
            try:
                memory = process.memory_full_info()
                times = process.cpu_times()
                name = " ".join(process.cmdline()[:4])
            except (psutil.NoSuchProcess, psutil.AccessDenied, psutil.ZombieProcess):
                continue
            pss += memory.pss
            rss += memory.rss
            self.cpu[process.pid] = (name, times.user + times.system)
        self.peak_pss = max(self.peak_pss, pss)
        self.peak_rss = max(self.peak_rss, rss)

    def run(self) -> None:
        while not self._stop_event.is_set():
            self._sample()
            self._stop_event.wait(self.interval_s)

    def stop(self) -> None:
        self._stop_event.set()
        self.join()


def _run(
    workflow: Path, *extra: str, watch: list[int] | None = None, python: str = sys.executable
) -> dict[str, Any]:
    """One ``nice stepframe run WORKFLOW --json`` (by ``python``: another installation's, to
    compare) with its wall time, memory and CPU."""
    command = ["nice", python, "-m", "stepframe.cli", "run", str(workflow), "--json"]
    load_before = os.getloadavg()[0]
    start = time.perf_counter()
    process = subprocess.Popen(
        [*command, *extra], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    monitor = TreeMonitor([process.pid, *(watch or [])])
    monitor.start()
    stdout, stderr = process.communicate()
    wall = time.perf_counter() - start
    monitor.stop()
    if process.returncode != 0:
        raise SystemExit(f"stepframe run failed ({process.returncode}): {stderr[-3000:]}")
    report = json.loads(stdout)
    main_cpu = monitor.cpu.get(process.pid, ("", 0.0))[1]
    return {
        "wall_s": wall,
        "stages": {s["name"]: s for s in report["stages"]},
        "failed_items": len(report["failures"]),
        "peak_pss_mb": monitor.peak_pss / 2**20,
        "peak_rss_sum_mb": monitor.peak_rss / 2**20,
        "main_cpu_s": main_cpu,
        "tree_cpu_s": sum(cpu for pid, (_, cpu) in monitor.cpu.items() if pid not in (watch or [])),
        "watched_cpu_s": {str(pid): monitor.cpu.get(pid, ("", 0.0))[1] for pid in watch or []},
        "load": [load_before, os.getloadavg()[0]],
    }


def _size_mb(folder: Path) -> float:
    return sum(p.stat().st_size for p in folder.rglob("*") if p.is_file()) / 1e6


def _hashes(root: Path) -> dict[str, str]:
    """sha256 of each compared output of the run in ``root``, with ``root`` written ``ROOT``
    (the selection's tables hold the records' absolute paths)."""
    outputs = root / "work" / "outputs"
    prefix = str(root.absolute()).encode()
    return {
        name: hashlib.sha256((outputs / name).read_bytes().replace(prefix, b"ROOT")).hexdigest()
        for name in COMPARED
    }


def _report_page(outputs: Path) -> dict[str, Any]:
    html = (outputs / "selection_report.html").read_text(encoding="utf-8")
    tables = html.split("<table")[1:]
    return {
        "html_mb": len(html.encode()) / 1e6,
        "largest_table_rows": max((t.split("</table>")[0].count("<tr") for t in tables), default=0),
        "data_folder_mb": _size_mb(outputs / "selection_report_files"),
    }


def _scene(root: Path, records: Path) -> Path:
    """The run's folder: hard links to the catalogue's files, the frame, the shipped workflow
    with ``folder = "records"`` for its example."""
    shutil.rmtree(root, ignore_errors=True)
    (root / "records").mkdir(parents=True)
    for file in sorted(records.glob("*.AT2")):
        os.link(file, root / "records" / file.name)
    shutil.copytree(SHIPPED / "frames", root / "frames")
    text = (SHIPPED / "selection.toml").read_text(encoding="utf-8")
    text = text.replace('example = "fema-p695"', 'folder = "records"')
    workflow = root / "selection.toml"
    workflow.write_text('workspace = "work"\n' + text, encoding="utf-8")
    return workflow


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


def _dask_cluster(workers: int) -> tuple[str, list[subprocess.Popen[bytes]], list[int]]:
    """A scheduler and ``workers`` one-thread workers on loopback; (address, processes, worker
    pids)."""
    from dask.distributed import Client

    port = _free_port()
    address = f"tcp://127.0.0.1:{port}"
    bin_dir = Path(sys.executable).parent
    quiet = {"stdout": subprocess.DEVNULL, "stderr": subprocess.DEVNULL}
    processes = [
        subprocess.Popen(
            [
                "nice",
                str(bin_dir / "dask"),
                "scheduler",
                "--host",
                "127.0.0.1",
                "--port",
                str(port),
                "--no-dashboard",
            ],
            **quiet,
        )
    ]
    for k in range(workers):
        processes.append(
            subprocess.Popen(
                [
                    "nice",
                    str(bin_dir / "dask"),
                    "worker",
                    address,
                    "--nthreads",
                    "1",
                    "--no-nanny",
                    "--no-dashboard",
                    "--memory-limit",
                    "0",
                    "--name",
                    f"w{k}",
                ],
                **quiet,
            )
        )
    with Client(address, timeout=60) as client:
        client.wait_for_workers(workers, timeout=120)
        pids = list(client.run(os.getpid).values())
    return address, processes, pids


def _folder(name: str, count: int, default: int) -> str:
    """The catalogue's folder (``records``, ``extra``), or one named by its count."""
    return name if count == default else f"{name}-{count}"


def _local_parts(
    root: Path, records: Path, extra: Path, jobs: list[str], save: Any
) -> dict[str, str]:
    """Parts 1-3 (first run, no-op re-runs, 1 % new records and its no-op); the first run's
    output hashes."""
    workflow = _scene(root, records)
    first = _run(workflow, *jobs)
    outputs = root / "work" / "outputs"
    first["store_mb"] = _size_mb(root / "work" / "store")
    first["outputs_mb"] = _size_mb(outputs)
    first["records_mb"] = _size_mb(root / "records")
    first["report"] = _report_page(outputs)
    first["hashes"] = reference = _hashes(root)
    save("first", first)
    save("noop", [_run(workflow, *jobs) for _ in range(2)])

    for file in sorted(extra.glob("*.AT2")):
        os.link(file, root / "records" / file.name)
    incremental = _run(workflow, *jobs)
    incremental["store_mb"] = _size_mb(root / "work" / "store")
    save("incremental", incremental)
    save("incremental_noop", _run(workflow, *jobs))
    return reference


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--records", type=int, default=21_500, help="records (two files each)")
    parser.add_argument("--extra", type=int, default=215, help="records added for part 3")
    parser.add_argument("--name", default="nga", help="name of the run's folders")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--skip-dask", action="store_true")
    parser.add_argument(
        "--dask-only",
        action="store_true",
        help="only part 4, compared with part 1 of an earlier run of the same --name",
    )
    args = parser.parse_args()
    records = nga_catalogue.build(
        OUT / _folder("records", args.records, 21_500), range(args.records)
    )
    extra = nga_catalogue.build(
        OUT / _folder("extra", args.extra, 215), range(21_500, 21_500 + args.extra)
    )
    path = OUT / f"{args.name}-results.json"
    results: dict[str, Any] = {"components": 2 * args.records, "jobs": args.jobs}
    if args.dask_only:
        results = json.loads(path.read_text(encoding="utf-8"))
        reference = results["first"]["hashes"]
    root = OUT / "runs" / args.name
    jobs = ["--jobs", str(args.jobs)]

    def save(part: str, value: Any) -> None:
        results[part] = value
        path.write_text(json.dumps(results, indent=1), encoding="utf-8")
        print(part, json.dumps(value, indent=1), flush=True)

    if not args.dask_only:
        reference = _local_parts(root, records, extra, jobs, save)
    if not args.skip_dask:
        dask_root = OUT / "runs" / f"{args.name}-dask"
        dask_workflow = _scene(dask_root, records)
        address, processes, pids = _dask_cluster(args.jobs)
        try:
            dask = _run(dask_workflow, "--scheduler", address, watch=pids)
        finally:
            for process in reversed(processes):
                process.terminate()
            for process in processes:
                try:  # a worker still closing its connections: its numbers are taken already
                    process.wait(timeout=60)
                except subprocess.TimeoutExpired:
                    process.kill()
                    process.wait()
        dask_hashes = _hashes(dask_root)
        dask["identical"] = {n: dask_hashes[n] == reference[n] for n in COMPARED}
        save("dask", dask)
        shutil.rmtree(dask_root / "work" / "store", ignore_errors=True)
    print(f"results: {path}")


if __name__ == "__main__":
    main()
