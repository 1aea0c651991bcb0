"""``stepframe demo`` wall time: first run after install, warm, and a re-run into the same folder.

The demo is the shipped selection workflow (``stepframe run selection``) run by the pipeline's
runner with its workspace in the demo's folder. This installs the checkout non-editably into a
fresh venv (``bench/first_run.py``'s :func:`install`: ``--system-site-packages`` for the
dependencies, ``pip install --no-deps .``), so the shipped workflow comes from the package data
exactly as a user's ``pip install .`` gets it, then runs in a fresh temporary folder:

1. first run after install: ``NUMBA_CACHE_DIR`` an empty folder, so every kernel compiles;
2. warm: a second demo into a fresh folder (kernels cached, every stage computed);
3. re-run: the same command into the folder of run 2 (every stage taken from the store).

Prints a Markdown table (wall and CPU seconds, children included, and the per-stage seconds the
run reports) and the load average, which matters: the 2 cores are shared with other work.

    python bench/bench_demo.py
"""

from __future__ import annotations

import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from first_run import install  # a sibling script: bench/ is put on sys.path above


def _cpu_children() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def demo(exe: str, folder: Path, cwd: Path, env: dict[str, str]) -> tuple[float, float, dict]:
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
    with tempfile.TemporaryDirectory(prefix="stepframe-bench-demo-") as tmp:
        base = Path(tmp)
        package = install(base / "venv")
        exe = str(base / "venv" / "bin" / "stepframe")
        cache = base / "numba-cache"
        cache.mkdir()
        env = {k: v for k, v in os.environ.items() if not k.startswith("NUMBA_")}
        env.update(NUMBA_CACHE_DIR=str(cache), STEPFRAME_COMPILE_NOTICE="0")
        work = base / "work"
        work.mkdir()
        load = [os.getloadavg()[0]]
        runs = [
            ("first run after install (empty numba cache)", work / "first"),
            ("warm, fresh folder (every stage computed)", work / "warm"),
            ("re-run into the same folder (store: nothing computed)", work / "warm"),
        ]
        rows = []
        outputs = []
        for label, folder in runs:
            wall, cpu, data = demo(exe, folder, work, env)
            load.append(os.getloadavg()[0])
            stages = ", ".join(
                f"{s['name']} {s['seconds']:.1f}" + (" cached" if s["computed"] == 0 else "")
                for s in data["stages"]
            )
            rows.append(f"| {label} | {wall:.1f} | {cpu:.1f} | {stages} |")
            outputs.append(data)
        # the records are files in each demo's folder: compare names, not absolute paths
        chosen = [[(Path(s["file"]).name, s["component"]) for s in d["selected"]] for d in outputs]
        same = all(c == chosen[0] for c in chosen)
        print(f"installed (non-editable): {package}")
        print(f"shipped workflow run: {outputs[0]['workflow']}")
        print(f"report: {outputs[0]['report']} (exists: {Path(outputs[0]['report']).is_file()})")
        print(f"same selection in every run: {same}\n")
        print("| `stepframe demo` | wall [s] | CPU [s] | stages [s] |")
        print("|---|---|---|---|")
        print("\n".join(rows))
        print(
            f"\nload average (1 min) before and after each run: "
            f"{', '.join(f'{v:.1f}' for v in load)} on {os.cpu_count()} CPUs"
        )


if __name__ == "__main__":
    main()
