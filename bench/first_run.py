"""First run of commands that compile numba kernels, on a fresh non-editable install.

Builds a fresh venv (``--system-site-packages`` for the dependencies), installs this checkout
into it non-editably (``pip install --no-deps .``, build in isolation), then runs each command
three ways, each in a private mount namespace (``unshare -m``) with the installed package folder
bind-mounted read-only (a system install):

- ``user cache``: HOME read-only, ``XDG_CACHE_HOME`` a fresh writable folder: run 1 compiles and
  caches there, run 2 loads the cache;
- ``nothing writable``: HOME read-only, no cache folder: every run compiles in memory.

``--patch-exact`` applies, to the installed copy only, the one-line change
``structure/_exact.py`` needs to use :mod:`stepframe.core.jit` (``from numba import njit,
prange`` → ``from stepframe.core.jit import njit, prange``), to measure the simulator as it will
be once that file adopts it.

Prints a Markdown table of wall times [s] (whole command, interpreter start included), the exit
code and the compile line each run printed. Needs root (for ``unshare -m`` and ``mount``).

    python bench/first_run.py [--patch-exact] [--only "structure simulate"]
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
RECORD = ROOT / "tests" / "data" / "peer_nga_west2" / "RSN8883_14383980_13849360.AT2"


def install(venv: Path, source: Path = ROOT) -> Path:
    """A fresh venv with ``source`` (default: this checkout) installed non-editably; returns the
    package folder."""
    subprocess.run(["python3", "-m", "venv", "--system-site-packages", str(venv)], check=True)
    pip = [str(venv / "bin" / "python"), "-m", "pip", "install", "-q"]
    subprocess.run([*pip, "--no-deps", str(source)], check=True)
    code = "import stepframe, os; print(os.path.dirname(stepframe.__file__))"
    found = subprocess.run(
        [str(venv / "bin" / "python"), "-c", code], check=True, capture_output=True, text=True
    )
    return Path(found.stdout.strip())


def run(package: Path, home: Path, command: list[str], env: dict[str, str]) -> tuple[float, str]:
    """Wall time [s] of ``command`` with ``package`` and ``home`` read-only; and what it said."""
    mounts = f"mount --bind -o ro {package} {package} && mount --bind -o ro {home} {home}"
    script = f"{mounts} && exec {' '.join(command)}"
    full = {k: v for k, v in os.environ.items() if not k.startswith(("NUMBA_", "XDG_"))}
    full.update(HOME=str(home), **env)
    start = time.perf_counter()
    done = subprocess.run(
        ["unshare", "-m", "sh", "-c", script], capture_output=True, text=True, env=full
    )
    wall = time.perf_counter() - start
    said = [line for line in done.stderr.splitlines() if "compil" in line or "Error" in line]
    return wall, f"exit {done.returncode}; " + (said[-1].strip() if said else "no compile line")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--patch-exact", action="store_true")
    parser.add_argument("--only", default=None, help="run only this command")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="stepframe-first-run-") as tmp:
        base = Path(tmp)
        package = install(base / "venv")
        if args.patch_exact:
            exact = package / "structure" / "_exact.py"
            text = exact.read_text()
            old = "from numba import njit, prange"
            if old not in text:
                raise SystemExit(f"{exact}: no {old!r} line to patch")
            exact.write_text(text.replace(old, "from stepframe.core.jit import njit, prange"))
        exe = str(base / "venv" / "bin" / "stepframe")
        frame = base / "frame.toml"
        frame.write_text(
            subprocess.run([exe, "structure", "frame-template"], capture_output=True, text=True,
                           check=True).stdout
        )  # fmt: skip
        home = base / "home"
        home.mkdir()
        commands = {
            "records spectrum": [exe, "records", "spectrum", str(RECORD), "--json"],
            "structure simulate": [exe, "structure", "simulate", "--frame", str(frame),
                                   str(RECORD), "--scale", "6", "--json"],
        }  # fmt: skip
        print(f"package folder (read-only): {package}\n")
        print("| command | setting | run | wall [s] | outcome |")
        print("|---|---|---|---|---|")
        for name, command in commands.items():
            if args.only is not None and name != args.only:
                continue
            cache = base / f"cache-{name.replace(' ', '-')}"
            for setting, env in (
                ("user cache", {"XDG_CACHE_HOME": str(cache)}),
                ("nothing writable", {}),
            ):
                for number in (1, 2):
                    wall, said = run(package, home, command, env)
                    print(f"| {name} | {setting} | {number} | {wall:.1f} | {said} |")
        shutil.rmtree(base / "venv", ignore_errors=True)


if __name__ == "__main__":
    main()
