"""Peak memory of the long-record paths against the file's size (issue 28, docs/benchmarks.md).

Writes an AT2 file of ``--npts`` samples (default 1.5·10⁷, 228 MB: the real 16,396-sample
record of tests/data repeated, in the PEER layout of five values a line) and runs, each in a
fresh process, ``records info``, ``stochastic fit`` and ``records info`` under a memory budget
too small for it (``--memory-mb 200``: refused before reading). Each row gives the child's peak
resident memory (VmHWM, read by the child itself) and its ratio to the file's size.

Run: ``nice python bench/bench_memory.py [--npts N]`` (about two minutes at the default size;
the file is written in a temporary folder and removed).
"""

from __future__ import annotations

import argparse
import importlib.util
import sys
import tempfile
from pathlib import Path

from bench_hostile import run  # a fresh child that reports its own peak memory

#: The corpus of the hostile tests writes the long record (one writer for both).
_SPEC = importlib.util.spec_from_file_location(
    "hostile_corpus", Path(__file__).parents[1] / "tests" / "hostile" / "corpus.py"
)
assert _SPEC is not None and _SPEC.loader is not None
corpus = importlib.util.module_from_spec(_SPEC)
sys.modules[_SPEC.name] = corpus  # dataclasses look their module up there
_SPEC.loader.exec_module(corpus)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--npts", type=int, default=15_000_000)
    npts = parser.parse_args().npts
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "long.AT2"
        corpus.write_long_at2(path, npts)
        size_mib = path.stat().st_size / 1024**2
        print(f"file: {npts} samples, {size_mib:.0f} MiB")
        cases = {
            "records info": ["records", "info", "--json", str(path)],
            "stochastic fit": ["stochastic", "fit", "--json", str(path)],
            "records info --memory-mb 200": [
                "records", "info", "--memory-mb", "200", str(path)
            ],
        }  # fmt: skip
        print("| command | wall time [s] | peak memory [MiB] | peak / file size | exit |")
        print("|---|---|---|---|---|")
        for name, argv in cases.items():
            seconds, peak, status, message = run(argv, repeats=1)
            print(f"| {name} | {seconds:.1f} | {peak:.0f} | {peak / size_mib:.2f} | {status} |")
            if message:
                print(f"|  | {message.replace(folder, '…')[:160]} | | | |")


if __name__ == "__main__":
    main()
