"""Where the workflow's ``responses`` stage spends its time per component (issue 29).

Run: ``python bench/bench_responses_pass.py [--records 200] [--skip-runs]``. Prints Markdown
tables for docs/benchmarks.md.

Components: the first ``2 × --records`` of :mod:`nga_catalogue`'s synthetic catalogue (20-80 s at
0.005-0.02 s), built if missing. Frame and options: the shipped selection workflow's (Example 4's
frame, ranking at equal PSA(T_1) at the onset of stepping, confirmation).

1. One core (numba on one thread, CPU time of this process): the pass of
   :func:`stepframe.pipeline.selection.record_pass.record_pass` taken apart, in the stage's
   groups of 31 components: reading the AT2 file, the spectra and peers, the ranking's
   simulations (``simulated_response``), the confirmation's equal-intensity run and its
   overturning scan, the scan both as it was (every record at every level) and as it is
   (:func:`stepframe.pipeline.selection.confirm.overturn_factors`, stopping each record at its
   first overturning level), checked equal. Beside them, in the same process, the standalone
   ranking of ``bench/bench_ranking.py`` (its 200 records of 6,000 samples, onset ratio 1).
   Then the same parts with the code as it was at :data:`bench_features.FORMER` (its modules
   read from git) and as it is, interleaved (median of three each), the results checked equal
   bit for bit: the spectra and peers, the ranking and the scan in rounds (issue 29).
2. The stage in the command: ``stepframe run WORKFLOW --force responses`` with ``--jobs 1`` and
   ``--jobs 2`` over the same components: the stage's wall time, the command's CPU time
   (its worker processes included) and the mean of the stored ``ranking_s`` column (each
   component's share of its group's ranking, wall time in the worker that ran it).
"""

from __future__ import annotations

import os

os.environ["NUMBA_NUM_THREADS"] = "1"  # per-core costs (before numba is imported)

import argparse
import glob
import json
import math
import shutil
import subprocess
import sys
import time
import tomllib
from pathlib import Path
from typing import Any

import numpy as np

import bench_features
import bench_ranking
import nga_catalogue

SHIPPED = Path(__file__).resolve().parents[1] / "src" / "stepframe" / "workflows"
OUT = nga_catalogue.OUT / "responses"
GROUP = 31


def _scene(files: list[Path]) -> Path:
    """A copy of the shipped selection workflow over ``files`` (hard links)."""
    root = OUT / "scene"
    shutil.rmtree(root, ignore_errors=True)
    (root / "records").mkdir(parents=True)
    for file in files:
        os.link(file, root / "records" / file.name)
    shutil.copytree(SHIPPED / "frames", root / "frames")
    text = (SHIPPED / "selection.toml").read_text(encoding="utf-8")
    text = text.replace('example = "fema-p695"', 'folder = "records"')
    (root / "selection.toml").write_text('workspace = "work"\n' + text, encoding="utf-8")
    return root / "selection.toml"


def _cpu(function: Any) -> tuple[Any, float]:
    start = time.process_time()
    value = function()
    return value, time.process_time() - start


def one_core(files: list[Path], workflow: Path) -> dict[str, float]:
    """CPU seconds per component of each part of the pass (module docstring, part 1)."""
    from stepframe.pipeline.selection import confirm, exact, record_pass
    from stepframe.pipeline.selection.intensity import equal_intensity_scales
    from stepframe.pipeline.selection.options import SelectionOptions
    from stepframe.pipeline.selection.peers import spectra_and_peers
    from stepframe.records import read
    from stepframe.structure.frame_file import read_frame_file

    options = SelectionOptions.from_dict(tomllib.loads(workflow.read_text())["selection"])
    frame = read_frame_file(workflow.parent / "frames" / "example-4.toml")
    spec = record_pass.selection_inputs(frame, options, {})[3]
    assert spec is not None and spec.onset_ratio is not None

    def read_all() -> list[tuple[np.ndarray, float]]:
        out = []
        for file in files:
            trace = read(file)[0]
            out.append((np.asarray(trace.data, dtype=np.float64), float(trace.stats.delta)))
        return out

    records, read_s = _cpu(read_all)
    groups = [range(i, min(i + GROUP, len(records))) for i in range(0, len(records), GROUP)]
    spectra_and_peers((*records[0], spec.groups, spec.peer_periods))  # kernels loaded
    passes, spectra_s = _cpu(
        lambda: [spectra_and_peers((a, dt, spec.groups, spec.peer_periods)) for a, dt in records]
    )
    sd_t1 = np.array([float(spectra[1][0]) for spectra, _ in passes])
    psa_t1 = np.array([(2 * math.pi / spec.groups[0][0][0]) ** 2 * s[0][0] / 9.80665 for s in [
        p[0] for p in passes]])  # fmt: skip
    base = np.array([spec.base_scale(p, s) for p, s in zip(psa_t1, sd_t1, strict=True)])

    def ranking() -> None:
        for g in groups:
            exact.simulated_response(frame, [records[i] for i in g], base[g], spec.ladder)

    def equal() -> None:
        for g in groups:
            scales = equal_intensity_scales(sd_t1[g], frame, spec.onset_ratio)
            confirm.run_batch(frame, [records[i] for i in g], scales)

    def scan(rounds: bool) -> np.ndarray:
        out = []
        for g in groups:
            subset = [records[i] for i in g]
            onset = equal_intensity_scales(sd_t1[g], frame, 1.0)
            if rounds:
                out.append(confirm.overturn_factors(frame, subset, onset, confirm.SCAN_LEVELS))
            else:  # as it was: every record at every level, then the bisection
                every = exact.ladder_runs(frame, subset, onset, confirm.SCAN_LEVELS.tolist())
                out.append(exact.first_overturn(frame, subset, onset, confirm.SCAN_LEVELS,
                                                every.overturned))  # fmt: skip
        return np.concatenate(out)

    exact.simulated_response(frame, records[:2], base[:2], spec.ladder)  # kernels loaded
    former = before_after(frame, spec, records, groups, sd_t1, base)
    _, ranking_s = _cpu(ranking)
    _, equal_s = _cpu(equal)
    before, scan_before_s = _cpu(lambda: scan(False))
    after, scan_after_s = _cpu(lambda: scan(True))
    assert np.array_equal(before, after, equal_nan=True), "the scan in rounds differs"
    motions = bench_ranking.motions(200, seed=1)
    _, standalone_s = _cpu(lambda: bench_ranking.rank(frame, motions, True))
    n = len(records)
    return {
        "components": n,
        "mean_samples": float(np.mean([a.size for a, _ in records])),
        "read_ms": read_s / n * 1e3,
        "spectra_peers_ms": spectra_s / n * 1e3,
        "ranking_ms": ranking_s / n * 1e3,
        "equal_run_ms": equal_s / n * 1e3,
        "scan_every_level_ms": scan_before_s / n * 1e3,
        "scan_in_rounds_ms": scan_after_s / n * 1e3,
        "standalone_ranking_ms": standalone_s / len(motions) * 1e3,
        "load": os.getloadavg()[0],
        **former,
    }


def before_after(
    frame: Any,
    spec: Any,
    records: list[tuple[np.ndarray, float]],
    groups: list[range],
    sd_t1: np.ndarray,
    base: np.ndarray,
    repeat: int = 3,
) -> dict[str, float]:
    """CPU ms per component of the spectra and peers, the ranking and the scan in rounds, at
    :data:`bench_features.FORMER` and now, interleaved; their results checked equal bit for
    bit (module docstring, part 1)."""
    from stepframe.pipeline.selection import confirm, exact, peers
    from stepframe.pipeline.selection.intensity import equal_intensity_scales

    former_exact = bench_features.former_module("former_exact", "pipeline/selection/exact.py")
    former_peers = bench_features.former_module("former_peers", "pipeline/selection/peers.py")
    modules = {"former": (former_exact, former_peers), "now": (exact, peers)}
    current = exact.ladder_runs, exact.first_overturn

    def parts(version: str) -> dict[str, Any]:
        ranking_module, peers_module = modules[version]
        return {
            "spectra": lambda: [peers_module.spectra_and_peers(
                (a, dt, spec.groups, spec.peer_periods)) for a, dt in records],
            "ranking": lambda: [ranking_module.simulated_response(
                frame, [records[i] for i in g], base[g], spec.ladder) for g in groups],
            "scan": lambda: [confirm.overturn_factors(
                frame, [records[i] for i in g],
                equal_intensity_scales(sd_t1[g], frame, 1.0), confirm.SCAN_LEVELS)
                for g in groups],
        }  # fmt: skip

    cpu: dict[str, dict[str, list[float]]] = {v: {} for v in modules}
    results: dict[str, dict[str, Any]] = {v: {} for v in modules}
    for _ in range(repeat):
        for version in modules:
            for part, function in parts(version).items():
                ranking_module = modules[version][0]
                # the scan imports these from the exact module when it runs
                exact.ladder_runs, exact.first_overturn = (
                    ranking_module.ladder_runs, ranking_module.first_overturn
                )  # fmt: skip
                try:
                    results[version][part], seconds = _cpu(function)
                finally:
                    exact.ladder_runs, exact.first_overturn = current
                cpu[version].setdefault(part, []).append(seconds)
    for part in results["now"]:
        difference = bench_features._largest_difference(
            results["former"][part], results["now"][part]
        )
        assert difference == 0.0, f"{part} differs from {bench_features.FORMER}"
    return {
        f"{part}_{version}_ms": float(np.median(cpu[version][part])) / len(records) * 1e3
        for version in modules
        for part in cpu[version]
    }


def command(workflow: Path, jobs: int) -> dict[str, float]:
    """``stepframe run --force responses --jobs N``: stage wall, command CPU, mean ranking_s."""
    import pandas as pd

    env = {k: v for k, v in os.environ.items() if k != "NUMBA_NUM_THREADS"}
    load = os.getloadavg()[0]
    before = os.times()
    done = subprocess.run(
        [sys.executable, "-m", "stepframe.cli", "run", str(workflow), "--json",
         "--force", "responses", "--jobs", str(jobs)],
        capture_output=True, text=True, check=True, env=env,
    )  # fmt: skip
    after = os.times()
    stages = {s["name"]: s for s in json.loads(done.stdout)["stages"]}
    segments = glob.glob(str(workflow.parent / "work" / "store" / "responses" / "**" / "*.parquet"),
                         recursive=True)  # fmt: skip
    table = pd.read_parquet(max(segments, key=os.path.getmtime))
    return {
        "jobs": jobs,
        "stage_s": stages["responses"]["seconds"],
        "cpu_s": (after[2] + after[3]) - (before[2] + before[3]),
        "ranking_s_mean_ms": float(table["ranking_s"].mean() * 1e3),
        "components": len(table),
        "load": [load, os.getloadavg()[0]],
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--records", type=int, default=200, help="records (two files each)")
    parser.add_argument("--skip-runs", action="store_true", help="part 1 only")
    args = parser.parse_args()
    folder = nga_catalogue.build(nga_catalogue.OUT / "records-500", range(500))
    files = sorted(folder.glob("*.AT2"))[: 2 * args.records]
    workflow = _scene(files)
    print(f"load average before: {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs", flush=True)
    part1 = one_core(files, workflow)
    print(json.dumps(part1), flush=True)
    runs = []
    if not args.skip_runs:
        env = {k: v for k, v in os.environ.items() if k != "NUMBA_NUM_THREADS"}
        subprocess.run([sys.executable, "-m", "stepframe.cli", "run", str(workflow), "--jobs",
                        "1"], capture_output=True, check=True, env=env)  # fmt: skip
        for _ in range(2):
            for jobs in (1, 2):
                runs.append(command(workflow, jobs))
                print(json.dumps(runs[-1]), flush=True)
    print(f"\n{part1['components']} components, {part1['mean_samples']:.0f} samples on average;"
          f" CPU ms per component, one core (load {part1['load']:.1f}):\n")  # fmt: skip
    print("| part of the pass | CPU [ms per component] |\n|---|---:|")
    for key, label in (
        ("read_ms", "read the AT2 file"),
        ("spectra_peers_ms", "spectra and peers"),
        ("ranking_ms", "ranking (`simulated_response`, groups of 31)"),
        ("equal_run_ms", "confirmation: the equal-intensity run"),
        ("scan_every_level_ms", "confirmation: overturning scan, every level (before)"),
        ("scan_in_rounds_ms", "confirmation: overturning scan in rounds (after)"),
        ("standalone_ranking_ms", "standalone `bench_ranking.rank`, 200 × 6,000 samples"),
    ):
        print(f"| {label} | {part1[key]:.2f} |")
    print(f"\nAt {bench_features.FORMER} and now, interleaved (median of 3), results equal bit "
          "for bit:\n\n| part | before [ms per component] | now | now / before |\n"
          "|---|---:|---:|---:|")  # fmt: skip
    for part, label in (("spectra", "spectra and peers"), ("ranking", "ranking"),
                        ("scan", "confirmation: overturning scan in rounds")):  # fmt: skip
        before, now = part1[f"{part}_former_ms"], part1[f"{part}_now_ms"]
        print(f"| {label} | {before:.2f} | {now:.2f} | {now / before:.2f} |")
    if runs:
        print("\n| command | stage wall [s] | command CPU [s] | mean ranking_s [ms] | load |")
        print("|---|---:|---:|---:|---|")
        for run in runs:
            print(f"| `run --force responses --jobs {run['jobs']}` ({run['components']}) | "
                  f"{run['stage_s']:.1f} | {run['cpu_s']:.1f} | {run['ranking_s_mean_ms']:.1f} | "
                  f"{run['load'][0]:.1f}-{run['load'][1]:.1f} |")  # fmt: skip


if __name__ == "__main__":
    main()
