"""Which numba kernels a stepframe command compiles on its first run, and what each costs.

Runs the command in a fresh process (the interpreter ``--python``, default this one) with an empty
``NUMBA_CACHE_DIR``, with a listener on numba's compile events, and prints each compilation of the
command's own process: CPU seconds (process time; a nested compilation, indented, is listed before
the kernel that needed it and included in its time), the kernel and its signature, and totals;
with ``--passes S``, numba's passes of each top-level kernel that took over S seconds.
Worker processes of a command with ``--jobs`` > 1 are not seen: run those with ``--jobs 1``.

``--peer REV`` installs the commit REV (``git archive``, as bench/first_run.py does) into a fresh
venv and profiles it too, after this checkout, for a before/after table.

    python bench/compile_profile.py [--peer main] -- structure simulate --frame F.toml REC --json
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))
from first_run import ROOT, install  # a sibling script: bench/ is put on sys.path above

DRIVER = r"""
import json, sys, time
from numba.core import event

rows, stack = [], []

class Listener(event.Listener):
    def on_start(self, ev):
        stack.append(time.process_time())

    def on_end(self, ev):
        start = stack.pop()
        dispatcher = ev.data["dispatcher"]
        function = dispatcher.py_func
        # numba's own per-pass wall times of this compilation (nested ones included in the
        # pass that triggered them, usually type inference).
        cres = dispatcher.overloads.get(tuple(ev.data.get("args", ())))
        times = getattr(cres, "metadata", None) or {}
        passes = {name.split("_", 1)[1]: round(t.init + t.run + t.finalize, 3)
                  for pipeline in times.get("pipeline_times", {}).values()
                  for name, t in pipeline.items()}
        rows.append([len(stack), f"{function.__module__}.{function.__qualname__}",
                     str(ev.data.get("args", "")), time.process_time() - start, passes])

event.register("numba:compile", Listener())
from stepframe.cli import main
begin = time.process_time()
try:
    main(sys.argv[1:])
except SystemExit:
    pass
sys.stderr.write("\nCOMPILE-PROFILE " + json.dumps({"rows": rows,
                 "cpu": time.process_time() - begin}) + "\n")
"""


def profile(python: str, command: list[str], cwd: Path) -> dict[str, object]:
    """The compile rows and the process's CPU time of ``command`` run by ``python``."""
    with tempfile.TemporaryDirectory(prefix="stepframe-numba-cache-") as cache:
        env = {k: v for k, v in os.environ.items() if not k.startswith("NUMBA_")}
        env.update(NUMBA_CACHE_DIR=cache, STEPFRAME_COMPILE_NOTICE="0")
        done = subprocess.run(
            [python, "-c", DRIVER, *command], capture_output=True, text=True, env=env, cwd=cwd
        )
    line = [x for x in done.stderr.splitlines() if x.startswith("COMPILE-PROFILE ")]
    if not line:
        raise SystemExit(f"no profile from {python}: {done.stderr[-2000:]}")
    return dict(json.loads(line[-1].removeprefix("COMPILE-PROFILE ")))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--python", default=sys.executable)
    parser.add_argument("--peer", metavar="REV")
    parser.add_argument("--min-s", type=float, default=0.05, help="hide shorter compilations")
    parser.add_argument(
        "--passes", type=float, metavar="S", help="list numba's passes longer than S seconds"
    )
    parser.add_argument("command", nargs=argparse.REMAINDER)
    args = parser.parse_args()
    command = [c for c in args.command if c != "--"]
    with tempfile.TemporaryDirectory(prefix="stepframe-compile-profile-") as tmp:
        base = Path(tmp)
        pythons = {"this checkout": args.python}
        if args.peer:
            source = base / "peer-source"
            source.mkdir()
            archive = subprocess.run(
                ["git", "-C", str(ROOT), "archive", args.peer], check=True, capture_output=True
            ).stdout
            subprocess.run(["tar", "-x", "-C", str(source)], input=archive, check=True)
            install(base / "venv-peer", source)
            pythons[args.peer] = str(base / "venv-peer" / "bin" / "python")
        print(f"`stepframe {' '.join(command)}`, empty NUMBA_CACHE_DIR, CPU seconds\n")
        for build, python in pythons.items():
            work = base / build.replace(" ", "-")
            work.mkdir()
            result = profile(python, command, work)
            rows = [r for r in result["rows"] if isinstance(r, list)]  # type: ignore[attr-defined]
            top = sum(r[3] for r in rows if r[0] == 0)
            print(f"**{build}**: compilations {top:.2f} s of {result['cpu']:.2f} s CPU\n")
            print("| CPU [s] | kernel (indented: nested, counted in the next outer line) |")
            print("|---|---|")
            for depth, name, signature, seconds, _passes in rows:
                if seconds >= args.min_s and name.startswith("stepframe."):
                    indent = "&nbsp;&nbsp;" * depth
                    print(f"| {seconds:.2f} | {indent}`{name}` {signature[:60]} |")
            print()
            if args.passes is not None:
                print_passes(rows, args.passes)


def print_passes(rows: list[list[Any]], threshold: float) -> None:
    """numba's passes of each top-level stepframe kernel longer than ``threshold`` seconds (wall
    time, numba's ``pipeline_times``), longest first."""
    for depth, name, _, seconds, passes in rows:
        if depth or not name.startswith("stepframe.") or seconds < threshold:
            continue
        long = sorted(((t, p) for p, t in passes.items() if t >= threshold), reverse=True)
        listed = ", ".join(f"{p} {t:.2f}" for t, p in long)
        print(f"`{name}`: passes {sum(passes.values()):.2f} s wall: {listed}\n")


if __name__ == "__main__":
    main()
