"""Cost and size of the two HTML reports.

Run: ``python bench/bench_reports.py [--selection DIR]``. Times, in one process:

- the amplification report of the paper's site (f_p, f_s, f_r = 7.43, 3.12, 1.11 Hz, ξ_p = 0.096,
  ξ_r = 0.655, t_max = 5 s, t_dur = 20 s, the paper's α reading) with Example 4's frame and
  δ* = 0.25 m, at the command's defaults (50 Monte Carlo motions at 4 frequencies, 2,000 steps);
- the selection report of a demo-sized selection folder: ``--selection DIR`` (the output of
  ``stepframe select``, or ``selection/`` in ``stepframe demo``'s folder), else the test
  fixture's folder built from all 100 example-catalogue components with 10 selected (not timed).

For each: the first call in the process (imports, numba cache loads, font cache), then the median
of 3 warm calls, split into the figures (matplotlib to PNG), the rest (computation, template,
writing), and the page and data-folder sizes. The peer measured in the same run is the
computation alone: what the report adds on top of the numbers it shows. Prints a Markdown table
for docs/benchmarks.md.
"""

from __future__ import annotations

import argparse
import importlib.util
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import stepframe.pipeline.reports.document as document
from stepframe.pipeline.amplification.report import (
    AmplificationOptions,
    write_amplification_report,
)
from stepframe.pipeline.reports import collect_provenance
from stepframe.pipeline.reports.document import data_folder_of
from stepframe.pipeline.selection.report import write_selection_report
from stepframe.stochastic.model import GroundMotionModel
from stepframe.structure.frame_file import frame_template, read_frame_file

ROOT = Path(__file__).resolve().parents[1]


class FigureClock:
    """Accumulates the time spent turning matplotlib figures into PNG."""

    def __init__(self) -> None:
        self.seconds = 0.0
        self._inner = document.figure_from_matplotlib

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        start = time.perf_counter()
        try:
            return self._inner(*args, **kwargs)
        finally:
            self.seconds += time.perf_counter() - start


def _timed(make: Callable[[], Path], clock: FigureClock) -> tuple[float, float, float, Path]:
    """Wall time, time in figures, CPU time of this process [s], and the report."""
    clock.seconds = 0.0
    start, cpu = time.perf_counter(), time.process_time()
    out = make()
    return time.perf_counter() - start, clock.seconds, time.process_time() - cpu, out


def _size(out: Path) -> tuple[int, int]:
    folder = data_folder_of(out)
    return out.stat().st_size, sum(p.stat().st_size for p in folder.iterdir())


def _selection_folder(given: str | None, work: Path) -> tuple[Path, str]:
    if given:
        return Path(given), f"`{given}`"
    path = ROOT / "tests" / "pipeline" / "reports" / "selection_fixture.py"
    spec = importlib.util.spec_from_file_location("selection_fixture", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    folder = module.make_selection_folder(work / "selection", n_selected=10, rows=range(100))
    return Path(folder), "test fixture, 100 candidates, 10 selected"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--selection", help="a selection output folder (default: built)")
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    clock = FigureClock()
    # the report modules call figure_from_matplotlib through their own imported name
    import stepframe.pipeline.amplification.report as amplification
    import stepframe.pipeline.selection.report as selection

    amplification.figure_from_matplotlib = clock  # type: ignore[assignment]
    selection.figure_from_matplotlib = clock  # type: ignore[assignment]
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        (work / "frame.toml").write_text(frame_template(), encoding="utf-8")
        frame = read_frame_file(work / "frame.toml")
        model = GroundMotionModel.from_hz(
            7.43, 3.12, 1.11, 0.096, 0.655, t_max_s=5.0, t_dur_s=20.0, alpha_reading="paper"
        )
        options = AmplificationOptions(site_name="paper's site", delta_star_m=0.25)
        provenance = collect_provenance("bench", inputs=[work / "frame.toml"])

        def amplification_report() -> Path:
            return write_amplification_report(
                model, work / "paper.html", frame=frame, options=options, provenance=provenance
            )

        folder, source = _selection_folder(args.selection, work)

        def selection_report() -> Path:
            return write_selection_report(
                folder, work / "selection.html", provenance=collect_provenance("bench")
            )

        rows = []
        for name, make in (
            ("amplification, paper's site + Example 4 frame", amplification_report),
            (f"selection ({source})", selection_report),
        ):
            first = _timed(make, clock)[0]
            runs = [_timed(make, clock) for _ in range(args.repeat)]
            total = statistics.median(r[0] for r in runs)
            figures = statistics.median(r[1] for r in runs)
            cpu = statistics.median(r[2] for r in runs)
            page, data = _size(runs[-1][3])
            rows.append((name, first, total, cpu, figures, total - figures, page, data))
    print(
        "| report | first call [s] | warm wall [s] | warm CPU [s] | of which figures [s] "
        "| computation + page [s] | HTML [kB] | numbers folder [kB] |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for name, first, total, cpu, figures, rest, page, data in rows:
        print(
            f"| {name} | {first:.2f} | {total:.2f} | {cpu:.2f} | {figures:.2f} | {rest:.2f} "
            f"| {page / 1e3:.0f} | {data / 1e3:.0f} |"
        )


if __name__ == "__main__":
    main()
