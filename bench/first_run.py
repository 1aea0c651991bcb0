"""First run of commands that compile numba kernels, on a fresh non-editable install.

Builds a fresh venv, installs this checkout into it non-editably (``pip install --no-deps .``,
build in isolation; the dependencies are those of the interpreter running this script: its
site-packages are put on the venv's path), then runs each command two ways per setting:

- ``installed`` (default): the install as ``pip install`` leaves it, no ``NUMBA_CACHE_DIR``: the
  kernels the build compiled into the package (:mod:`stepframe.core.kernel_cache`) are what a
  new user's first run finds; the package's cache files are counted before and after each
  command (a kernel compiled on the way adds files);
- ``fresh``: ``NUMBA_CACHE_DIR`` a new, empty folder for each command, which numba prefers to the
  package's own cache: run 1 compiles every kernel the command needs, run 2 loads them (what
  every first run paid before the build compiled them);
- ``user cache`` and ``nothing writable`` (need root: ``unshare -m`` and ``mount``): the package
  folder and HOME bind-mounted read-only in a private mount namespace (a system install);
  ``XDG_CACHE_HOME`` a fresh writable folder (run 1 compiles and caches there, run 2 loads), or
  no cache folder at all (every run compiles in memory).

Commands (each the first stepframe command in its setting): ``records spectrum``, ``structure
simulate``, ``stochastic fit`` of RSN 8883, ``select --confirm`` of 10 from the example
catalogue (``--jobs 1`` and the default, all CPUs), and ``demo`` (default jobs).

Prints a Markdown table: wall time of the whole command (interpreter start included), CPU time
(user + sys of the command and its worker processes), the seconds of the compile lines
:mod:`stepframe.core.jit` printed (wall time of the compilations in the command's own process),
and the CPU time of run 1 minus run 2 (the compilation's cost, cache writing included, workers
included). ``--peer REV`` also installs the commit REV (``git archive``) into a second venv and
runs it interleaved with this checkout, so both see the same load.

    python bench/first_run.py [--peer main] [--setting installed] [--only "structure simulate"]
"""

from __future__ import annotations

import argparse
import os
import re
import resource
import shutil
import subprocess
import sys
import sysconfig
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
RECORD = ROOT / "tests" / "data" / "peer_nga_west2" / "RSN8883_14383980_13849360.AT2"
SETTINGS = ("installed", "fresh", "user cache", "nothing writable")


def install(venv: Path, source: Path = ROOT) -> Path:
    """A fresh venv with ``source`` (default: this checkout) installed non-editably; returns the
    package folder, and prints the install's wall time (the build compiles the kernels). The
    dependencies come from this interpreter's site-packages (a path line in the venv, after its
    own site-packages: the fresh stepframe is found first)."""
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    python = venv / "bin" / "python"
    purelib = subprocess.run(
        [str(python), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
        check=True, capture_output=True, text=True,
    ).stdout.strip()  # fmt: skip
    Path(purelib, "stepframe-bench-dependencies.pth").write_text(
        sysconfig.get_paths()["purelib"] + "\n", encoding="utf-8"
    )
    pip = [str(python), "-m", "pip", "install", "-q"]
    start = time.perf_counter()
    subprocess.run([*pip, "--no-deps", str(source)], check=True)
    print(f"pip install --no-deps {source}: {time.perf_counter() - start:.1f} s wall")
    code = "import stepframe, os; print(os.path.dirname(stepframe.__file__))"
    found = subprocess.run([str(python), "-c", code], check=True, capture_output=True, text=True)
    return Path(found.stdout.strip())


def _cpu_children() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run(
    command: list[str], env: dict[str, str], cwd: Path, read_only: tuple[Path, Path] | None
) -> tuple[float, float, float, str]:
    """Wall [s], CPU [s] (children included), compile seconds printed, and the outcome of
    ``command``; with ``read_only`` = (package, home), those two are mounted read-only."""
    if read_only is not None:
        package, home = read_only
        mounts = f"mount --bind -o ro {package} {package} && mount --bind -o ro {home} {home}"
        command = ["unshare", "-m", "sh", "-c", f"{mounts} && exec {' '.join(command)}"]
    cpu = _cpu_children()
    start = time.perf_counter()
    done = subprocess.run(command, capture_output=True, text=True, env=env, cwd=cwd)
    wall = time.perf_counter() - start
    cpu = _cpu_children() - cpu
    lines = [line for line in done.stderr.splitlines() if "compiling" in line]
    compiled = sum(float(m) for m in re.findall(r"\.\.\. ([0-9.]+) s", "\n".join(lines)))
    errors = [line for line in done.stderr.splitlines() if "Error" in line or "error:" in line]
    outcome = f"exit {done.returncode}" + (f"; {errors[-1].strip()}" if errors else "")
    return wall, cpu, compiled, outcome


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--peer", metavar="REV", help="also run the commit REV, interleaved")
    parser.add_argument("--setting", choices=SETTINGS, action="append")
    parser.add_argument("--only", action="append", help="run only this command (repeatable)")
    args = parser.parse_args()
    settings = args.setting or ["installed"]
    with tempfile.TemporaryDirectory(prefix="stepframe-first-run-") as tmp:
        base = Path(tmp)
        builds = {"this checkout": (base / "venv", install(base / "venv"))}
        if args.peer:
            source = base / "peer-source"
            source.mkdir()
            archive = subprocess.run(
                ["git", "-C", str(ROOT), "archive", args.peer], check=True, capture_output=True
            ).stdout
            subprocess.run(["tar", "-x", "-C", str(source)], input=archive, check=True)
            builds[f"{args.peer}"] = (base / "venv-peer", install(base / "venv-peer", source))
        frame = base / "frame.toml"
        exe = str(base / "venv" / "bin" / "stepframe")
        frame.write_text(
            subprocess.run([exe, "structure", "frame-template"], capture_output=True, text=True,
                           check=True).stdout
        )  # fmt: skip
        home = base / "home"
        home.mkdir()
        commands = {
            "records spectrum": ["records", "spectrum", str(RECORD), "--json"],
            "structure simulate": ["structure", "simulate", "--frame", str(frame), str(RECORD),
                                   "--scale", "6", "--json"],
            "stochastic fit": ["stochastic", "fit", str(RECORD), "--json"],
            "select --confirm --jobs 1": ["select", "--frame", str(frame), "--example",
                                          "fema-p695", "-n", "10", "--confirm", "-o", "OUT",
                                          "--jobs", "1", "--json"],
            "select --confirm": ["select", "--frame", str(frame), "--example", "fema-p695",
                                 "-n", "10", "--confirm", "-o", "OUT", "--json"],
            "demo": ["demo", "-o", "OUT", "--json"],
        }  # fmt: skip
        clean = {k: v for k, v in os.environ.items() if not k.startswith(("NUMBA_", "XDG_"))}
        load = [os.getloadavg()[0]]
        print("| command | setting | build | run | wall [s] | CPU [s] | compile lines [s] | "
              "CPU run 1 - run 2 [s] | outcome |")  # fmt: skip
        print("|---|---|---|---|---|---|---|---|---|")
        for name, tail in commands.items():
            if args.only and name not in args.only:
                continue
            for setting in settings:
                cpu_first: dict[str, float] = {}
                for number in (1, 2):
                    for build, (venv, package) in builds.items():  # interleaved
                        tag = f"{build}-{name}-{setting}".replace(" ", "-")
                        work = base / "work" / f"{tag}-{number}"
                        work.mkdir(parents=True)
                        env = {**clean, "HOME": str(home)}
                        read_only = None
                        shipped = sum(1 for _ in package.rglob("*.nb[ic]"))
                        if setting == "fresh":
                            cache = base / f"numba-{tag}"
                            cache.mkdir(exist_ok=True)
                            env["NUMBA_CACHE_DIR"] = str(cache)
                        elif setting != "installed":
                            read_only = (package, home)
                            if setting == "user cache":
                                env["XDG_CACHE_HOME"] = str(base / f"xdg-{tag}")
                        command = [str(venv / "bin" / "stepframe"), *tail]
                        command = [str(work / "out") if c == "OUT" else c for c in command]
                        wall, cpu, compiled, outcome = run(command, env, work, read_only)
                        load.append(os.getloadavg()[0])
                        added = sum(1 for _ in package.rglob("*.nb[ic]")) - shipped
                        if setting == "installed" and added:
                            outcome += f"; {added} cache files added to the package"
                        if number == 1:
                            cpu_first[build] = cpu
                        delta = f"{cpu_first[build] - cpu:.1f}" if number == 2 else ""
                        cells = f"{wall:.1f} | {cpu:.1f} | {compiled:.1f} | {delta} | {outcome}"
                        print(f"| {name} | {setting} | {build} | {number} | {cells} |", flush=True)
        print(f"\nload average (1 min) before and after each run: "
              f"{', '.join(f'{v:.1f}' for v in load)} on {os.cpu_count()} CPUs")  # fmt: skip
        for venv, _ in builds.values():
            shutil.rmtree(venv, ignore_errors=True)


if __name__ == "__main__":
    main()
