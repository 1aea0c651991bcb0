"""Confirmation of the selection scores by simulation, on the example and a synthetic catalogue.

Writes docs/selection_confirmation.png and prints the Spearman table quoted in docs/selection.md.
Run: ``python bench/selection_confirmation.py [--n-synthetic 300] [--jobs 2]``.

Example catalogue: the 100 embedded FEMA P695 components. Synthetic catalogue: Beck-Papadimitriou
motions (:func:`stepframe.stochastic.synthetic.synthetic_motions`, 40 s at 0.01 s) with
parameters drawn log-uniformly (seeded): ω_p in [15, 90] rad/s, ω_r in [3.5, 40] rad/s below
it, ω_s between, ξ_p, ξ_r in [0.1, 0.6], t_max in [3, 10] s, t_dur = t_max + [8, 20] s. Both go
through the same features, selection and confirmation as ``stepframe select --confirm``, with the
paper's Example 4 frame.
"""

from __future__ import annotations

import argparse
import math
import tomllib
from typing import Any

import numpy as np


def synthetic_catalogue(n: int, seed: int) -> tuple[Any, dict[tuple[str, str], Any]]:
    """Features table and samples of ``n`` synthetic motions (one component each)."""
    from obspy import Stream

    from stepframe.records.trace import make_trace
    from stepframe.stochastic.catalog_features import catalog_features
    from stepframe.stochastic.model import GroundMotionModel
    from stepframe.stochastic.synthetic import synthetic_motions

    rng = np.random.default_rng(seed)
    traces = []
    records = {}
    for k in range(n):
        wp = math.exp(rng.uniform(math.log(15), math.log(90)))
        wr = math.exp(rng.uniform(math.log(3.5), math.log(min(40.0, 0.8 * wp))))
        ws = wr + (wp - wr) * rng.uniform(0.05, 0.6)
        t_max = rng.uniform(3, 10)
        model = GroundMotionModel(
            wp,
            ws,
            wr,
            rng.uniform(0.1, 0.6),
            rng.uniform(0.1, 0.6),
            t_max,
            t_max + rng.uniform(8, 20),
        )
        _, acc = synthetic_motions(
            model, duration_s=40.0, dt_s=0.01, seed=seed * 100_000 + k, peak_intensity=1.0
        )
        name = f"synthetic/{k:04d}"
        traces.append(
            make_trace(acc[0], 0.01, station=f"S{k:04d}", channel="HNX", source_file=name)
        )
        records[(name, "HNX")] = (acc[0], 0.01)
    features, _ = catalog_features(Stream(traces))
    return features, records


def main() -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from stepframe.core.io import atomic_write
    from stepframe.pipeline.selection import SelectionOptions, select_records
    from stepframe.pipeline.selection.inputs import example_catalogue
    from stepframe.structure.frame_file import FRAME_TEMPLATE, frame_from_mapping

    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--n-synthetic", type=int, default=300)
    parser.add_argument("--jobs", type=int, default=None)
    parser.add_argument("--out", default="docs/selection_confirmation.png")
    args = parser.parse_args()
    frame = frame_from_mapping(tomllib.loads(FRAME_TEMPLATE))
    options = SelectionOptions(n=10, confirm=True, n_bootstrap=0)
    runs = {}
    table, records, _ = example_catalogue(args.jobs)
    runs["FEMA P695 (100 components)"] = select_records(
        table, frame, options, records=records, jobs=args.jobs
    )
    table, records = synthetic_catalogue(args.n_synthetic, seed=7)
    runs[f"synthetic B-P ({args.n_synthetic} motions)"] = select_records(
        table, frame, options, records=records, jobs=args.jobs
    )
    shown = (
        "backbone_amplification",
        "descent_amplification",
        "spectral_ratio_eq_6_18",
        "psa_t1_g",
    )
    fig, axes = plt.subplots(len(runs), len(shown), figsize=(4 * len(shown), 3.6 * len(runs)))
    print("| catalogue | score | response | Spearman | 95 % interval | n |")
    print("|---|---|---|---|---|---|")
    for row, (label, result) in enumerate(runs.items()):
        conf = result.confirmation
        equal = conf[conf["case"] == "equal-psa-t1"].set_index(["file", "component"])
        cands = result.candidates.set_index(["file", "component"]).loc[equal.index]
        for entry in result.summary["correlations"]:
            print(
                f"| {label} | {entry['score']} | {entry['response']} | "
                f"{entry['spearman']:.2f} | [{entry['low']:.2f}, {entry['high']:.2f}] | "
                f"{entry['n']} |"
            )
        for col, name in enumerate(shown):
            ax = axes[row, col]
            over = equal["overturned"].to_numpy(dtype=bool)
            x = cands[name].to_numpy(dtype=float)
            y = equal["peak_abs_x_m"].to_numpy(dtype=float)
            ax.scatter(x[~over], y[~over], s=10, c="k", label="stays up")
            ax.scatter(x[over], y[over], s=14, c="r", marker="^", label="overturns")
            ax.set_yscale("log")
            ax.set_xlabel(name)
            entry = next(
                e
                for e in result.summary["correlations"]
                if e["score"] == name and e["response"] == "peak_drift"
            )
            ax.set_title(
                f"{label}\nρ = {entry['spearman']:.2f} [{entry['low']:.2f}, {entry['high']:.2f}]",
                fontsize=9,
            )
            if col == 0:
                ax.set_ylabel("peak |x| at equal PSA(T1) [m]")
        medians = result.summary["medians"]
        print(f"\n{label}: medians {medians}\n")
    axes[0, 0].legend(fontsize=8)
    fig.tight_layout()
    with atomic_write(args.out, "wb") as handle:
        fig.savefig(handle, dpi=100, format="png")
    print(f"figure: {args.out}")


if __name__ == "__main__":
    main()
