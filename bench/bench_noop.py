"""A no-op re-run of a cached workspace, two installations interleaved (issue 29: ≤ 10 s at
43,000 components).

Runs ``python -m stepframe.cli run WORKFLOW --json`` in the workflow's folder with each given
interpreter in turn (before, after, before, after, ...), each a fresh process, and prints per run
its wall time, the CPU time of the process and its children (user + system, from ``wait4``), the
stages' items computed (all 0 in a no-op), and the 1-minute load average before it; then the
medians per interpreter and their ratio. The first round is a warm-up, not counted: a changed
code may legitimately write its stamps and outputs again once. With ``--settle`` each counted
run follows an uncounted one of the same interpreter: a code that leaves published files alone
when untouched publishes them again after a run of a code that copies them each time, once.
With ``--pycache DIR`` the runs may cache their bytecode in DIR (``PYTHONPYCACHEPREFIX``) where
the environment forbids writing it (``PYTHONDONTWRITEBYTECODE``): without it every run compiles
the package's sources again, which an ordinary installation does not.

Usage (the workspace of ``bench/bench_nga_scale.py --name nga43k``)::

    python bench/bench_noop.py RUNS/nga43k/selection.toml \\
        --python before=/work/venv/bin/python --python after=/work/venvs/noop/bin/python
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import time
from dataclasses import dataclass
from pathlib import Path


@dataclass
class Run:
    """One run: wall and CPU (user + system, with children) time [s], the 1-minute load
    average before it, and each stage's computed items."""

    wall_s: float
    cpu_s: float
    load: float
    computed: list[int]


def _one_run(python: str, workflow: Path, env: dict[str, str]) -> Run:
    """Wall and CPU time [s] of one run, its stages' computed items, the load before it."""
    load = os.getloadavg()[0]
    start = time.perf_counter()
    process = subprocess.Popen(
        [python, "-m", "stepframe.cli", "run", workflow.name, "--json"],
        cwd=workflow.parent,
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        env=env,
    )
    assert process.stdout is not None
    out = process.stdout.read()
    _, status, usage = os.wait4(process.pid, 0)
    wall = time.perf_counter() - start
    if os.waitstatus_to_exitcode(status) != 0:
        raise SystemExit(f"{python}: exit {os.waitstatus_to_exitcode(status)}")
    report = json.loads(out)
    computed = [int(stage["computed"]) for stage in report["stages"]]
    return Run(wall, usage.ru_utime + usage.ru_stime, load, computed)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("workflow", type=Path, help="the workflow file of a cached workspace")
    parser.add_argument(
        "--python", action="append", required=True, help="NAME=interpreter, in run order"
    )
    parser.add_argument("--rounds", type=int, default=4, help="counted runs per interpreter")
    parser.add_argument("--settle", action="store_true", help="an uncounted run before each")
    parser.add_argument("--pycache", type=Path, help="a folder for the runs' bytecode")
    args = parser.parse_args()
    env = dict(os.environ)
    if args.pycache is not None:
        env.pop("PYTHONDONTWRITEBYTECODE", None)
        env["PYTHONPYCACHEPREFIX"] = str(args.pycache.absolute())
    pythons = dict(item.split("=", 1) for item in args.python)
    results: dict[str, list[Run]] = {name: [] for name in pythons}
    for round_ in range(args.rounds + 1):
        for name, python in pythons.items():
            if args.settle and round_ > 0:
                _one_run(python, args.workflow.absolute(), env)
            run = _one_run(python, args.workflow.absolute(), env)
            counted = round_ > 0
            print(
                f"{name:>8} {'run' if counted else 'warm-up'}: wall {run.wall_s:.2f} s, "
                f"CPU {run.cpu_s:.2f} s, load {run.load:.2f}, computed {run.computed}",
                flush=True,
            )
            if counted:
                results[name].append(run)
    medians = {}
    for name, runs in results.items():
        wall = statistics.median(r.wall_s for r in runs)
        cpu = statistics.median(r.cpu_s for r in runs)
        medians[name] = (wall, cpu)
        walls = ", ".join(f"{r.wall_s:.1f}" for r in runs)
        print(f"{name:>8}: median wall {wall:.2f} s ({walls}), median CPU {cpu:.2f} s")
    names = list(medians)
    for name in names[1:]:
        print(
            f"{name} / {names[0]}: wall {medians[name][0] / medians[names[0]][0]:.2f}, "
            f"CPU {medians[name][1] / medians[names[0]][1]:.2f}"
        )


if __name__ == "__main__":
    main()
