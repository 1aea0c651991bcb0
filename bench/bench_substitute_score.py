"""Cost of the substitute-structure score per candidate, against the covariance physics score.

Run: ``python bench/bench_substitute_score.py``. One numba thread, one process. For each usable
FEMA P695 component (the example catalogue's plausible fits) with Example 4's frame:

- substitute score: the SD at the substitute structure's 16 levels
  (:meth:`SubstituteLevels.spectrum_groups`, one kernel call per distinct damping) through the
  spectra worker :func:`record_spectra`, then :func:`substitute_demand_ratio`; this is the extra
  work the score adds to the one spectra pass a run already makes;
- peer, in the same run: ``scores.physics_scores`` (``backbone_amplification`` and
  ``descent_amplification``, the exact covariance method on the fitted model).

Prints the median over 3 repeats of the mean time per candidate [ms], and the samples per record.
"""

from __future__ import annotations

import os

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import statistics
import time
import tomllib

import numpy as np


def main() -> None:
    from stepframe.pipeline.selection import scores as sc
    from stepframe.pipeline.selection.band import frame_band
    from stepframe.pipeline.selection.inputs import example_catalogue
    from stepframe.pipeline.selection.path import MODEL_COLUMNS, strong_motion_paths
    from stepframe.pipeline.selection.spectral import record_spectra
    from stepframe.pipeline.selection.substitute import substitute_demand_ratio, substitute_levels
    from stepframe.structure.frame_file import FRAME_TEMPLATE, frame_from_mapping

    frame = frame_from_mapping(tomllib.loads(FRAME_TEMPLATE))
    band = frame_band(frame)
    levels = substitute_levels(band)
    groups = tuple(levels.spectrum_groups())
    table, records, _ = example_catalogue(1)
    table = table[table["plausible"].astype(bool)].reset_index(drop=True)
    samples = [records[(f, c)] for f, c in zip(table["file"], table["component"], strict=True)]
    paths = strong_motion_paths(table, 0.3)
    rows = table.to_dict(orient="records")
    xi_levels = sc.equivalent_damping(frame.xi_2, frame.c_r)

    def substitute() -> None:
        sd = np.array([levels.gather(record_spectra((a, dt, groups))) for a, dt in samples])
        substitute_demand_ratio(sd, levels)

    def physics() -> None:
        for i, row in enumerate(rows):
            model_row = {c: float(row[c]) for c in MODEL_COLUMNS}
            window = (float(paths.start_s[i]), float(paths.end_s[i]))
            sc.physics_scores(model_row, band, frame.xi_1, xi_levels, window)

    substitute()  # compile and warm
    physics()
    results = {}
    for name, function in (("substitute_demand_ratio", substitute), ("physics_scores", physics)):
        times = []
        for _ in range(3):
            start = time.perf_counter()
            function()
            times.append(time.perf_counter() - start)
        results[name] = statistics.median(times) / len(samples) * 1e3
    n_samples = [a.size for a, _ in samples]
    print(
        f"{len(samples)} candidates, {len(groups)} spectrum calls per record, samples per record "
        f"median {int(np.median(n_samples))} (max {max(n_samples)})"
    )
    print("| score | ms per candidate (one core) |")
    print("|---|---|")
    for name, ms in results.items():
        print(f"| `{name}` | {ms:.2f} |")
    ratio = results["physics_scores"] / results["substitute_demand_ratio"]
    print(f"ratio physics/substitute: {ratio:.1f}")


if __name__ == "__main__":
    main()
