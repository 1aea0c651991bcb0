"""The memory estimates of the commands against their measured peaks (issue 28, docs/benchmarks.md
"Memory of the commands").

Each row runs one command in a fresh process under tracemalloc (every Python and numpy
allocation; the interpreter's own libraries are not in it) and reads the estimate the command
asked ``core.memory.check_memory`` about: ``structure simulate`` with and without ``--plot``,
``structure ida`` and ``structure bifurcation`` (each after one run of the same command on a
short input, so that imports and the loading of the compiled kernels are not counted as the
work), and ``select`` on the example catalogue from a cold start (its fixed part holds them).

Run: ``nice python bench/bench_command_memory.py`` (about three minutes; long records are
written in a temporary folder and removed).
"""

from __future__ import annotations

import importlib.util
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).parents[1]
RECORD = ROOT / "tests" / "data" / "peer_nga_west2" / "RSN8883_14383980_13849090.AT2"
_SPEC = importlib.util.spec_from_file_location(
    "hostile_corpus", ROOT / "tests" / "hostile" / "corpus.py"
)
assert _SPEC is not None and _SPEC.loader is not None
corpus = importlib.util.module_from_spec(_SPEC)
sys.modules[_SPEC.name] = corpus  # dataclasses look their module up there
_SPEC.loader.exec_module(corpus)


def measure(argv: list[str], warm: list[str] | None, what: str, cwd: Path) -> tuple[float, float]:
    """(peak, estimate) [MiB] of one command."""
    env = dict(os.environ, WARM=json.dumps(warm) if warm else "")
    command = [sys.executable, "-c", corpus.MEASURE_CHILD, *argv]
    done = subprocess.run(command, capture_output=True, text=True, cwd=cwd, env=env)
    data = json.loads(done.stderr.strip().splitlines()[-1])
    assert data["status"] == 0, done.stderr[-500:]
    estimate = max(need for need, text in data["asked"] if text.startswith(what))
    return data["peak"] / 2**20, estimate / 2**20


def main() -> None:
    from stepframe.structure.frame_file import frame_template

    with tempfile.TemporaryDirectory() as name:
        folder = Path(name)
        frame = folder / "FRAME.toml"
        frame.write_text(frame_template())
        simulate = ["structure", "simulate", "--frame", str(frame), "--json"]
        ida = ["structure", "ida", "--frame", str(frame), "--json", "--resolution-g", "0.05"]
        bif = ["structure", "bifurcation", "--frame", str(frame), "--json", "--jobs", "1",
               "--omega-rad-s", "7.854", "--periods", "20", "--amplitudes-g"]  # fmt: skip
        rows: list[tuple[str, list[str], list[str] | None, str]] = []
        for npts in (400_000, 800_000):
            path = corpus.write_long_at2(folder / f"long{npts}.AT2", npts)
            warm = [*simulate, str(RECORD)]
            rows.append((f"simulate, {npts} samples", [*simulate, str(path)], warm, "simulating"))
            rows.append((
                f"simulate --plot, {npts} samples",
                [*simulate, "--plot", str(folder / "x.png"), str(path)],
                [*warm, "--plot", str(folder / "w.png")], "simulating",
            ))  # fmt: skip
            rows.append((
                f"ida, 4 records of {npts} samples", [*ida, *[str(path)] * 4],
                [*ida, str(RECORD)], "an IDA",
            ))  # fmt: skip
        for n_initial in (200, 800):
            rows.append((
                f"bifurcation, 100 × {n_initial} × 20 points",
                [*bif, "0.05,0.5,100", "--initial", str(n_initial)],
                [*bif, "0.05,0.5,2", "--initial", "2"], "a bifurcation",
            ))  # fmt: skip
        rows.append((
            "select, example catalogue (100 candidates), -n 3, --jobs 1",
            ["select", "--frame", str(frame), "--example", "fema-p695", "-n", "3", "-o",
             str(folder / "picks"), "--jobs", "1", "--json"], None, "selecting",
        ))  # fmt: skip
        print("| command | peak (tracemalloc) [MiB] | estimate [MiB] | estimate / peak |")
        print("|---|---:|---:|---:|")
        for label, argv, warm, what in rows:
            peak, estimate = measure(argv, warm, what, folder)
            print(f"| {label} | {peak:.1f} | {estimate:.1f} | {estimate / peak:.2f} |")
    print(f"\nload average at the end: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
