"""Cost of the nightly job's outputs: ``measures``, ``rotd50``, ``waveforms``, ``arrivals_report``.

Run: ``python bench/bench_measures.py [--jobs 1]``.

A workflow over an inbox holding the embedded example catalogue's files (100 FEMA P695
components, 50 records with two horizontals each) asks for the four outputs and ``features``
(the fits, which the summary shows beside the measures). Three runs in one process, each
timed per stage from the run's own summary (wall seconds; the machine's cores are shared):

1. the first run, everything computed;
2. a run with nothing new (what a scheduled run costs most nights);
3. a run after two files (one record) arrive.

Prints a Markdown table for docs/benchmarks.md ("Issue 30") with seconds per stage and per item,
the size of each output, and the store's size per stage at the end (kB per 1,000 items: what
the nightly lines of the shipped ``inbox`` add to its store, docs/scheduling.md).
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

from stepframe.pipeline.catalogue.example_files import example_files
from stepframe.pipeline.engine.runner import RunReport, run_workflow
from stepframe.pipeline.stages import shipped_stages

WORKFLOW = """name = "nightly"
[records]
folder = "inbox"
[outputs]
features = true
measures = true
rotd50 = true
waveforms = true
arrivals_report = true
"""
STAGES = ("features", "measures", "rotd50", "waveforms", "arrivals_report")


def _size(path: Path) -> int:
    if path.is_file():
        return path.stat().st_size
    return sum(p.stat().st_size for p in path.rglob("*") if p.is_file())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--jobs", type=int, default=1)
    args = parser.parse_args()
    files = list(example_files())
    kept, late = files[:-2], files[-2:]
    rows: list[tuple[str, RunReport]] = []
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        inbox = folder / "inbox"
        inbox.mkdir()
        for name, data in kept:
            (inbox / name).write_bytes(data)
        (folder / "wf.toml").write_text(WORKFLOW, encoding="utf-8")

        def run(label: str) -> None:
            report = run_workflow(folder / "wf.toml", shipped_stages(), jobs=args.jobs)
            assert report.exit_code == 0, report.missing
            rows.append((label, report))

        run(f"first run, {len(kept)} files")
        run("nothing new")
        for name, data in late:
            (inbox / name).write_bytes(data)
        run("two files arrive")
        outputs = folder / "stepframe-work" / "outputs"
        sizes = {
            "measures.parquet": _size(outputs / "measures.parquet"),
            "rotd50.parquet": _size(outputs / "rotd50.parquet"),
            "waveforms/": _size(outputs / "waveforms"),
            "arrivals_report (html + files)": _size(outputs / "arrivals_report.html")
            + _size(outputs / "arrivals_report_files"),
        }
        store = folder / "stepframe-work" / "store"
        stored = {
            stage: (_size(store / stage), next(s for s in rows[-1][1].stages if s.name == stage))
            for stage in ("inventory", *STAGES)
        }
    print("| run | " + " | ".join(f"{s} [s] (computed/items)" for s in STAGES) + " |")
    print("|---|" + "---|" * len(STAGES))
    for label, report in rows:
        cells = []
        for stage in STAGES:
            summary = next(s for s in report.stages if s.name == stage)
            cells.append(f"{summary.seconds:.2f} ({summary.computed}/{summary.items})")
        print(f"| {label} | " + " | ".join(cells) + " |")
    print()
    print("| output | size [kB] |")
    print("|---|---|")
    for name, size in sizes.items():
        print(f"| {name} | {size / 1e3:.0f} |")
    print()
    print("| store folder | size [kB] | items | kB per 1,000 items |")
    print("|---|---|---|---|")
    for stage, (size, summary) in stored.items():
        # a whole-set result is one item: per item is no figure to scale by
        per = f"{size / summary.items:.0f}" if summary.kind == "item" else "(one result)"
        print(f"| store/{stage} | {size / 1e3:.0f} | {summary.items} | {per} |")


if __name__ == "__main__":
    main()
