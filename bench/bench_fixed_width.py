"""Reading the fixed-width record formats: the vectorised fields against the line-by-line path.

The CSMIP (DMG), COSMOS and GeoNet readers parse their data blocks as fixed-width Fortran fields
(``stepframe.records.formats._text.numbers`` with a width). Since 2026-11-28 a block is
converted a chunk of lines at a time (``_fixed_width``); anything it cannot convert exactly goes
to the line-by-line path, which was the only path before. This script reads each fixed-width
file of tests/data/formats both ways in the same run (the line-by-line path by turning the
vectorised one off), CPU time of this thread, median of ``--repeat`` reads, alternated, and checks
that both give the same samples to the bit.

Run: ``python bench/bench_fixed_width.py [--repeat 7]``. Prints a Markdown table for
docs/benchmarks.md.
"""

from __future__ import annotations

import argparse
import warnings
from pathlib import Path

import numpy as np

from stepframe.records import read
from stepframe.records.formats import _text
from timing import median_cpu_seconds

FORMATS = Path(__file__).parents[1] / "tests" / "data" / "formats"
FILES = (
    "dmg/CE58667.V2.gz",
    "dmg/CICLC.v1.gz",
    "cosmos/Cosmos12TimeSeriesTest.v1.gz",
    "cosmos/NP1795-n.305.v0c.gz",
    "cosmos/us1000hyfh_akbmrp_AKBMR--n.1000hyfh.BNZ.--.acc.V2c.gz",
    "geonet/20161113_110300_HSES_20.V1A.gz",
    "geonet/20180212_211557_WPWS_20.V2A.gz",
)


def _samples(path: Path) -> list[np.ndarray]:
    return [trace.data for trace in read(path)]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeat", type=int, default=7, help="reads per timing (median)")
    args = parser.parse_args()
    warnings.simplefilter("ignore")  # the readers' notes on the files (offsets, missing Vs30)
    vectorised = _text._fixed_width
    print("| file | samples | line by line | vectorised | ratio |")
    print("|---|---:|---:|---:|---:|")
    for name in FILES:
        path = FORMATS / name
        fast = _samples(path)
        _text._fixed_width = lambda *args: None  # type: ignore[assignment,misc]
        try:
            slow = _samples(path)
            assert all(a.tobytes() == b.tobytes() for a, b in zip(fast, slow, strict=True))
            slow_s = median_cpu_seconds(lambda: read(path), args.repeat)  # noqa: B023
        finally:
            _text._fixed_width = vectorised
        fast_s = median_cpu_seconds(lambda: read(path), args.repeat)  # noqa: B023
        samples = sum(data.size for data in fast)
        print(
            f"| {name} | {samples:,} | {1e3 * slow_s:.1f} ms | {1e3 * fast_s:.1f} ms "
            f"| {slow_s / fast_s:.2f} |"
        )


if __name__ == "__main__":
    main()
