"""Hostile input: time and peak memory of clean refusals (docs/reliability.md, benchmarks.md).

Each case runs ``stepframe records info`` in a fresh process (the user's cost, start-up included)
and reports wall time and the child's peak resident memory; the peer in the same run is
``records info`` on the real 249 kB AT2 file the 2 GB file starts with, so the refusal's cost can
be read against an ordinary read.

Run: ``python bench/bench_hostile.py`` (about half a minute; writes a 2 GiB sparse file, a few kB
on disk, in a temporary folder).
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

AT2 = (
    Path(__file__).parents[1]
    / "tests"
    / "data"
    / "peer_nga_west2"
    / "RSN8883_14383980_13849090.AT2"
)
#: The child reports VmHWM, the peak resident memory of its own address space (ru_maxrss would
#: count pages shared with the forking parent before exec).
CHILD = """
import sys
from pathlib import Path
from stepframe.cli import main
code = main(sys.argv[1:])
status = Path("/proc/self/status").read_text().splitlines()
peak_kib = next(int(x.split()[1]) for x in status if x.startswith("VmHWM:"))
print(f"peak_kib={peak_kib}", file=sys.stderr)
sys.exit(code)
"""
REPEATS = 3


def run(argv: list[str], repeats: int = REPEATS) -> tuple[float, float, int, str]:
    """(median wall time [s], peak memory [MiB], exit status, first error line) of
    ``repeats`` runs."""
    times, peaks = [], []
    status, message = 0, ""
    for _ in range(repeats):
        start = time.perf_counter()
        result = subprocess.run(
            [sys.executable, "-c", CHILD, *argv], capture_output=True, text=True, timeout=600
        )
        times.append(time.perf_counter() - start)
        lines = result.stderr.splitlines()
        peaks.append(int(lines[-1].split("=")[1]) / 1024)
        status = result.returncode
        message = next((x for x in lines if x.startswith("stepframe: error")), "")
    times.sort()
    return times[len(times) // 2], max(peaks), status, message


def main() -> None:
    with tempfile.TemporaryDirectory() as folder:
        huge = Path(folder) / "huge.AT2"
        with huge.open("wb") as handle:
            handle.write(AT2.read_bytes()[:2000])
            handle.truncate(2 * 1024**3)
        fifo = Path(folder) / "pipe.AT2"
        os.mkfifo(fifo)
        cases = {
            "real AT2, 249 kB (peer)": ["records", "info", str(AT2)],
            "2 GiB sparse file, sniffed": ["records", "info", str(huge)],
            "2 GiB sparse file, --format at2": ["records", "info", "--format", "at2", str(huge)],
            "FIFO with no writer": ["records", "info", str(fifo)],
        }
        print(f"| case | wall time [s] (median of {REPEATS}) | peak memory [MiB] | exit |")
        print("|---|---|---|---|")
        for name, argv in cases.items():
            seconds, peak, status, message = run(argv)
            print(f"| {name} | {seconds:.2f} | {peak:.0f} | {status} |")
            if message:
                print(f"|  | {message.replace(folder, '…')[:90]} | | |")


if __name__ == "__main__":
    main()
