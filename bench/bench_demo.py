"""``stepframe demo`` wall time: first run after install, warm, and a re-run into the same folder.

The demo is the shipped selection workflow (``stepframe run selection``) run by the pipeline's
runner with its workspace in the demo's folder. This installs the checkout non-editably into a
fresh venv (``bench/first_run.py``'s :func:`install`: the dependencies from the interpreter running
the script, ``pip install --no-deps .``), so the shipped workflow comes from the package data
exactly as a user's ``pip install .`` gets it, then runs in a fresh temporary folder:

1. first run after install: ``NUMBA_CACHE_DIR`` an empty folder, so every kernel compiles;
2. warm: a second demo into a fresh folder (kernels cached, every stage computed);
3. re-run: the same command into the folder of run 2 (every stage taken from the store).

Prints a Markdown table (wall and CPU seconds, children included, and the per-stage seconds the
run reports) and the load average, which matters: the 2 cores are shared with other work.

``--peer REV`` also installs the commit REV (``git archive``) into a second venv and runs its demo
the same three ways in the same run, interleaved with this checkout's (before this change the demo
called the selection library directly, without the runner's store): the peer of the comparison.

    python bench/bench_demo.py [--peer c3b0bb3]
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))
from first_run import ROOT, install  # a sibling script: bench/ is put on sys.path above


def _cpu_children() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def demo(exe: str, folder: Path, cwd: Path, env: dict[str, str]) -> tuple[float, float, Any]:
    """Wall [s], CPU [s] (user + sys of the process and its workers) and the --json output."""
    cpu = _cpu_children()
    start = time.perf_counter()
    done = subprocess.run(
        [exe, "demo", "-o", str(folder), "--json"], capture_output=True, text=True, cwd=cwd, env=env
    )
    wall = time.perf_counter() - start
    if done.returncode != 0:
        raise SystemExit(f"demo failed ({done.returncode}): {done.stderr.strip()[-2000:]}")
    return wall, _cpu_children() - cpu, json.loads(done.stdout)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--peer", metavar="REV", help="also run the demo of this commit")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="stepframe-bench-demo-") as tmp:
        base = Path(tmp)
        builds = {"this checkout": install(base / "venv")}
        if args.peer:
            source = base / "peer-source"
            source.mkdir()
            archive = subprocess.run(
                ["git", "-C", str(ROOT), "archive", args.peer], check=True, capture_output=True
            ).stdout
            subprocess.run(["tar", "-x", "-C", str(source)], input=archive, check=True)
            builds[f"peer {args.peer}"] = install(base / "venv-peer", source)
        venvs = {"this checkout": base / "venv", f"peer {args.peer}": base / "venv-peer"}
        env = {k: v for k, v in os.environ.items() if not k.startswith("NUMBA_")}
        env["STEPFRAME_COMPILE_NOTICE"] = "0"
        steps = [
            ("first run after install (empty numba cache)", "first"),
            ("warm, fresh folder", "warm"),
            ("re-run into the same folder", "warm"),
        ]
        rows = []
        load = [os.getloadavg()[0]]
        chosen: list[list[tuple[str, float]]] = []
        for k, (label, name) in enumerate(steps):
            for build in builds:  # interleaved: both see the same load
                tag = build.replace(" ", "-")
                work = base / "work" / tag
                work.mkdir(parents=True, exist_ok=True)
                cache = base / f"numba-cache-{tag}"
                cache.mkdir(exist_ok=True)
                exe = str(venvs[build] / "bin" / "stepframe")
                wall, cpu, data = demo(
                    exe, work / name, work, {**env, "NUMBA_CACHE_DIR": str(cache)}
                )
                load.append(os.getloadavg()[0])
                stages = ", ".join(
                    f"{s['name']} {s['seconds']:.1f}" + (" cached" if s["computed"] == 0 else "")
                    for s in data.get("stages", [])
                )
                rows.append(f"| {label} | {build} | {wall:.1f} | {cpu:.1f} | {stages or '-'} |")
                # file names differ (the peer names the catalogue's files, the workflow writes
                # them as AT2 files in its folder): compare components and scores
                chosen.append([(s["component"], round(s["score"], 9)) for s in data["selected"]])
                if k == 0 and build == "this checkout":
                    print(f"installed (non-editable): {builds[build]}")
                    print(f"shipped workflow run: {data['workflow']}")
                    print(f"report: {data['report']} (exists: {Path(data['report']).is_file()})")
        print(f"same selection in every run: {all(c == chosen[0] for c in chosen)}\n")
        print("| `stepframe demo` | build | wall [s] | CPU [s] | stages [s] |")
        print("|---|---|---|---|---|")
        print("\n".join(rows))
        print(
            f"\nload average (1 min) before and after each run: "
            f"{', '.join(f'{v:.1f}' for v in load)} on {os.cpu_count()} CPUs"
        )


if __name__ == "__main__":
    main()
