"""A run's items streamed to the workers against batch by batch, and the record files hashed on
the workers against in the run's process (issue 29: the 2-core wall time and the serial part).

Run: ``python bench/bench_stream_batches.py --before /path/to/python-of-the-former-code``
(the python of a venv with the former code installed: ``python -m venv old && old/bin/pip
install 'git+file://$PWD@<commit>'`` or a worktree's ``pip install .``), after
``bench/nga_catalogue.py`` has written its catalogue.

Each run is the first run of a fresh workspace (``nice stepframe run WF --json --jobs 2``) of
the shipped selection workflow's items and selection (features and selection as outputs, no
report) over the first ``--components`` components of the catalogue, the two codes alternated
``--repeat`` times. Reported per run: the wall time of the item stages (inventory, features and
responses computed together), of the selection, the CPU of the run's main process and of all
its processes, and the workers' use of the two cores while the items ran ((all CPU - main CPU)
/ (2 x items' wall): the selection's share of the workers is small beside the items'). The
1-minute load average is recorded beside each run.
"""

from __future__ import annotations

import argparse
import os
import shutil
from pathlib import Path
from typing import Any

import bench_nga_scale
import nga_catalogue
from bench_nga_scale import SHIPPED

WORKFLOW = """workspace = "work"

[records]
folder = "records"

[frame]
file = "frames/example-4.toml"

[features]
frequency = "zero-crossing"

[selection]
n = 10
rank_onset_ratio = 1.0
confirm = true

[outputs]
features = true
selection = true
"""


def scene(root: Path, catalogue: Path, components: int) -> Path:
    """A folder with hard links to the first ``components`` files of the catalogue."""
    shutil.rmtree(root, ignore_errors=True)
    (root / "records").mkdir(parents=True)
    for file in sorted(catalogue.glob("*.AT2"))[:components]:
        os.link(file, root / "records" / file.name)
    shutil.copytree(SHIPPED / "frames", root / "frames")
    workflow = root / "wf.toml"
    workflow.write_text(WORKFLOW, encoding="utf-8")
    return workflow


def first_run(python: str, workflow: Path, *extra: str) -> dict[str, Any]:
    """One first run (workspace removed before) of ``workflow`` by ``python``."""
    shutil.rmtree(workflow.parent / "work", ignore_errors=True)
    run = bench_nga_scale._run(workflow, *extra, python=python)
    items_s = run["stages"]["inventory"]["seconds"]
    return {
        "wall_s": run["wall_s"],
        "items_s": items_s,
        "selection_s": run["stages"]["selection"]["seconds"],
        "main_cpu_s": run["main_cpu_s"],
        "tree_cpu_s": run["tree_cpu_s"],
        "workers_use": (run["tree_cpu_s"] - run["main_cpu_s"]) / (2 * items_s),
        "load": run["load"],
        "outputs": {
            name: (workflow.parent / "work" / "outputs" / name).read_bytes()
            for name in ("features.parquet", "selection/candidates.csv")
        },
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", required=True, help="the python of the former code's venv")
    parser.add_argument("--components", type=int, default=2048)
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument("--batch-items", type=int, default=None)
    parser.add_argument(
        "--catalogue", type=Path, default=nga_catalogue.OUT / "records", help="AT2 folder"
    )
    args = parser.parse_args()
    workflow = scene(nga_catalogue.OUT / "runs" / "stream", args.catalogue, args.components)
    extra = ["--jobs", "2"]
    if args.batch_items:
        extra += ["--batch-items", str(args.batch_items)]
    import sys

    codes = {"before": args.before, "after": sys.executable}
    runs: dict[str, list[dict[str, Any]]] = {name: [] for name in codes}
    for _ in range(args.repeat):
        for name, python in codes.items():
            runs[name].append(first_run(python, workflow, *extra))
            print(name, {k: v for k, v in runs[name][-1].items() if k != "outputs"}, flush=True)
    same = all(
        run["outputs"] == runs["before"][0]["outputs"] for name in codes for run in runs[name]
    )
    print(f"\n{args.components} components, --jobs 2, batch items {args.batch_items or 'default'}")
    print("| code | wall [s] | items [s] | selection [s] | main CPU [s] | all CPU [s] | "
          "workers' use of 2 cores | load |")  # fmt: skip
    print("|---|---:|---:|---:|---:|---:|---:|---|")
    for name in codes:
        for run in runs[name]:
            print(
                f"| {name} | {run['wall_s']:.1f} | {run['items_s']:.1f} | "
                f"{run['selection_s']:.1f} | {run['main_cpu_s']:.1f} | {run['tree_cpu_s']:.1f} "
                f"| {run['workers_use']:.3f} | {run['load'][0]:.1f}-{run['load'][1]:.1f} |"
            )
    print(f"\nfeatures.parquet and candidates.csv identical in every run: {same}")


if __name__ == "__main__":
    main()
