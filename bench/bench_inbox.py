"""The shipped inbox workflow under a trickle: 1,000 record files arriving one to ten per run.

Run: ``python bench/bench_inbox.py`` (about 15 minutes on 2 shared cores; ``--files N`` for a
shorter run). Every run is ``run_workflow`` on a copy of the shipped ``inbox`` workflow
(``[outputs] history = true``), in this process, ``--jobs 1``. The files are the 100 example
components at amplitude scales 1, 2, ... (distinct files of equal cost); every 97th arriving file
is damaged (not a record); every 25 runs the 10 oldest files still in the inbox are archived
(moved out). Measured, and printed as Markdown for docs/scheduling.md and docs/benchmarks.md:

- the outputs at the end: rows of ``features.csv`` (present and archived), rows of
  ``features.failures.csv`` and the runs whose log line counted each as new;
- the store's size per record against a batch run over the same files (one run, fresh
  workspace), with compaction (as shipped) and without (``COMPACT_AT`` set beyond reach: the
  store as it grew before issue 30);
- the run log's size per run, and the wall time of a run at the start and at the end;
- the cost of opening a checked store: a stage of 43,000 features-like rows (``--open-items``)
  opened with every segment read and its checksum checked, against reading only the segments'
  key columns (how the store was opened before issue 27).

Files go to bench/out/inbox/ (ignored by git).
"""

from __future__ import annotations

import argparse
import random
import shutil
import statistics
import time
from pathlib import Path

import pandas as pd

from stepframe.pipeline.catalogue.example_files import example_files
from stepframe.pipeline.engine import store as store_module
from stepframe.pipeline.engine.runner import run_workflow
from stepframe.pipeline.engine.shipped import copy_workflow
from stepframe.pipeline.stages import shipped_stages
from timing import median_seconds

OUT = Path(__file__).parent / "out" / "inbox"
SEED = 30
DAMAGED_EVERY = 97
ARCHIVE_EVERY_RUNS = 25
ARCHIVE_FILES = 10


def _files(count: int) -> list[tuple[str, bytes]]:
    """``count`` distinct record files: the example components at scales 1, 2, ..."""
    out: list[tuple[str, bytes]] = []
    scale = 1
    while len(out) < count:
        for name, data in example_files(scale=float(scale)):
            number = len(out) + 1
            if number % DAMAGED_EVERY == 0:
                damaged = f"PEER NGA STRONG MOTION DATABASE {number}\n".encode()  # distinct
                out.append((f"damaged_{number:04d}.AT2", damaged))
            else:
                out.append((f"s{scale}_{name}", data))
            if len(out) == count:
                break
        scale += 1
    return out


def _bytes(folder: Path) -> int:
    return sum(
        p.stat().st_size for p in folder.rglob("*") if p.is_file() and "quarantine" not in p.parts
    )


def trickle(root: Path, files: list[tuple[str, bytes]], compact: bool) -> dict[str, float]:
    """Run the inbox copy in ``root`` as the files arrive; what it measured."""
    shutil.rmtree(root, ignore_errors=True)
    copy_workflow("inbox", root)
    workflow, inbox, archive = root / "inbox.toml", root / "inbox", root / "archive"
    archive.mkdir()
    rng = random.Random(SEED)
    arrived: list[str] = []
    seconds: list[float] = []
    new_failures = 0
    saved = store_module.COMPACT_AT
    store_module.COMPACT_AT = store_module.COMPACT_AT if compact else 10**9
    try:
        while len(arrived) < len(files):
            for name, data in files[len(arrived) : len(arrived) + rng.randint(1, 10)]:
                (inbox / name).write_bytes(data)
                arrived.append(name)
            if len(seconds) % ARCHIVE_EVERY_RUNS == ARCHIVE_EVERY_RUNS - 1:
                present = sorted(p for p in inbox.iterdir() if not p.name.startswith("damaged"))
                for path in present[:ARCHIVE_FILES]:
                    shutil.move(path, archive / path.name)
            start = time.perf_counter()
            report = run_workflow(workflow, shipped_stages(), jobs=1)
            seconds.append(time.perf_counter() - start)
            assert report.exit_code == 0, report.missing
            new_failures += report.new_failures or 0
    finally:
        store_module.COMPACT_AT = saved
    work = root / "stepframe-work"
    features = pd.read_parquet(work / "outputs" / "features.parquet")
    failures = pd.read_csv(work / "outputs" / "features.failures.csv")
    log = work / "runs.jsonl"
    runs = len(seconds)
    return {
        "runs": runs,
        "rows": len(features),
        "present": int(features["present"].sum()),
        "archived": int((~features["present"]).sum()),
        "failures": len(failures),
        "new_failures": new_failures,
        "store_bytes": _bytes(work / "store"),
        "segments": len(list((work / "store").glob("*/seg-*.parquet"))),
        "log_bytes_per_run": log.stat().st_size / runs,
        "first_runs_s": statistics.median(seconds[1:11]),
        "last_runs_s": statistics.median(seconds[-10:]),
    }


def batch(root: Path, files: list[tuple[str, bytes]]) -> int:
    """The store's size after one run over every file (the same workflow, fresh workspace)."""
    shutil.rmtree(root, ignore_errors=True)
    copy_workflow("inbox", root)
    for name, data in files:
        (root / "inbox" / name).write_bytes(data)
    report = run_workflow(root / "inbox.toml", shipped_stages(), jobs=1)
    assert report.exit_code == 0, report.missing
    return _bytes(root / "stepframe-work" / "store")


def open_cost(root: Path, items: int, per_segment: int = 1024) -> tuple[float, float, float]:
    """Opening a stage of ``items`` features-like rows (31 numbers and 4 texts per row) in
    segments of ``per_segment``: the store's checked open (every segment read and its sha256
    checked) against reading only each segment's key column (the open before issue 27), median
    of 5 [s]; and the store's size [MB]."""
    import numpy as np
    import pyarrow.parquet as pq

    from stepframe.pipeline.engine.store import KEY_COLUMN, Store

    shutil.rmtree(root, ignore_errors=True)
    store = Store(root)
    store.prepare()
    rng = np.random.default_rng(SEED)
    for start in range(0, items, per_segment):
        count = min(per_segment, items - start)
        table = pd.DataFrame(rng.normal(size=(count, 31)), columns=[f"x{i}" for i in range(31)])
        for column in ("file", "station", "component", "flags"):
            table[column] = [f"{column}_{start + i:06d}" for i in range(count)]
        table[KEY_COLUMN] = [f"{start + i:064x}" for i in range(count)]
        store.add_rows("features", table, [])
    segments = sorted((root / "features").glob("seg-*.parquet"))

    def checked() -> None:
        assert len(Store(root).index("features")) == items

    def keys_only() -> None:
        assert sum(pq.read_table(p, columns=[KEY_COLUMN]).num_rows for p in segments) == items

    size_mb = sum(p.stat().st_size for p in segments) / 1e6
    return median_seconds(checked), median_seconds(keys_only), size_mb


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--files", type=int, default=1000)
    parser.add_argument("--open-items", type=int, default=43000)
    args = parser.parse_args()
    checked_s, keys_s, size_mb = open_cost(OUT / "open", args.open_items)
    print(f"opening a stage of {args.open_items:,} rows ({size_mb:.1f} MB in 1,024-row "
          f"segments): checked {checked_s:.3f} s, key columns only {keys_s:.3f} s "
          f"(x{checked_s / keys_s:.2f})\n")  # fmt: skip
    files = _files(args.files)
    damaged = sum(1 for name, _ in files if name.startswith("damaged"))
    records = len(files) - damaged
    batch_bytes = batch(OUT / "batch", files)
    with_compaction = trickle(OUT / "trickle", files, compact=True)
    without = trickle(OUT / "no-compaction", files, compact=False)
    per_record = 1000 / records / 1e6  # bytes → MB per 1,000 records
    print(f"{len(files)} files ({damaged} damaged) over {with_compaction['runs']:.0f} runs, "
          f"1-10 per run; {ARCHIVE_FILES} archived every {ARCHIVE_EVERY_RUNS} runs\n")  # fmt: skip
    print("| | batch (one run) | trickle, compaction | trickle, no compaction |")
    print("|---|---|---|---|")
    print(f"| store, MB per 1,000 records | {batch_bytes * per_record:.3f} | "
          f"{with_compaction['store_bytes'] * per_record:.3f} | "
          f"{without['store_bytes'] * per_record:.3f} |")  # fmt: skip
    print(f"| ratio to batch | 1 | {with_compaction['store_bytes'] / batch_bytes:.2f} | "
          f"{without['store_bytes'] / batch_bytes:.1f} |")  # fmt: skip
    print(f"| segments | | {with_compaction['segments']:.0f} | {without['segments']:.0f} |")
    for key, label in (
        ("rows", "features.csv rows"),
        ("present", "of which present"),
        ("archived", "of which archived (present = false)"),
        ("failures", "features.failures.csv rows"),
        ("new_failures", "failures marked new (sum over runs)"),
        ("log_bytes_per_run", "run log, bytes per run"),
        ("first_runs_s", "run wall time, runs 2-11 (median) [s]"),
        ("last_runs_s", "run wall time, last 10 runs (median) [s]"),
    ):
        print(f"| {label} | | {with_compaction[key]:.4g} | {without[key]:.4g} |")


if __name__ == "__main__":
    main()
