"""Robustness of every ranking to the frame's uncertainty (docs/selection.md, "Robustness").

Run: ``python bench/ranking_robustness.py [--jobs 2] [--frames all|two]``. Inputs, frames and
perturbations: bench/ranking_study.py (cached under bench/out/ranking/; the first run simulates
about 240 runs per candidate and frame, a few minutes on 2 cores).

Each ranking is computed with the nominal frame at the stated intensity and judged by Spearman's
ρ against responses it did not see: the nominal frame's peak |x| at 1.5 times the stated
intensity and its overturning margin (the negated lowest onset ratio that overturns it), and
each perturbed frame's peak |x| at the stated intensity and overturning margin. Printed: per
frame and catalogue, ρ against each judge, the mean over the 8 perturbed frames with a 95 %
bootstrap interval over candidates (1,000 resamples, the same resamples for every ranking), and
the worst perturbation.
"""

from __future__ import annotations

import argparse
import math
from typing import Any

import numpy as np

from ranking_study import (
    GRID,
    LIBRARY_LADDERS,
    PERTURBATIONS,
    catalogues,
    frame_family,
    scores_and_peers,
    simulations,
    slug,
)

N_RESAMPLES = 1000
TIERS = (
    "substitute_demand_ratio",
    "backbone_amplification",
    "band_coverage",
    "spectral_ratio_eq_6_18",
    "omega_p_over_s_sq",
    "descent_amplification",
)


def grid_index(factor: float) -> int:
    return int(np.argmin(np.abs(np.log(np.asarray(GRID) / factor))))


#: Exact measures: the ladder's factors on the stated intensity.
LADDERS: dict[str, tuple[float, ...]] = {
    "exact: 1 run at the stated intensity": (1.0,),
    "exact: ladder 0.5-2 (5 levels)": (0.5, 0.707, 1.0, 1.414, 2.0),
    "exact: ladder 0.5-2 (3 levels)": (0.5, 1.0, 2.0),
    "exact: ladder 0.71-1.41 (3 levels)": (0.707, 1.0, 1.414),
    "exact: ladder 1-4 (5 levels)": (1.0, 1.414, 2.0, 2.83, 4.0),
    "exact: ladder 0.25-4 (9 levels)": (0.25, 0.354, 0.5, 0.707, 1.0, 1.414, 2.0, 2.83, 4.0),
}


def _order_value(order: np.ndarray) -> np.ndarray:
    value = np.empty(order.size)
    value[order] = -np.arange(order.size, dtype=float)
    return value


def rankings(
    frame: Any, ratio: float, sims: dict, scores: dict, base: np.ndarray
) -> dict[str, np.ndarray]:
    from stepframe.pipeline.selection.confirm import OVERTURN_RATIO_RANGE
    from stepframe.pipeline.selection.exact import ranking_order
    from stepframe.pipeline.selection.peers import PEERS, at_intensity

    nominal = sims["nominal"]
    peaks = nominal["peaks"]
    # the nominal scan's overturning ratio (onset units) on the stated intensity's scale
    factor = nominal["onset"] / ratio
    nowhere = np.full(factor.size, np.nan)
    out = {}
    for name, factors in LADDERS.items():
        idx = [grid_index(f) for f in factors]
        with np.errstate(divide="ignore"):
            response = np.exp(np.mean(np.log(peaks[:, idx]), axis=1))
        out[name] = _order_value(ranking_order(nowhere, response))
        if len(factors) > 1:
            within = np.where(factor <= max(factors) * (1 + 1e-9), factor, np.nan)
            out[f"{name}, overturning first"] = _order_value(ranking_order(within, response))
    for levels in LIBRARY_LADDERS:
        out[f"exact: library, ladder 0.5-2 ({levels} levels)"] = _order_value(
            ranking_order(
                nominal[f"library{levels}_overturn"], nominal[f"library{levels}_response"]
            )
        )
    onset = np.where(np.isnan(nominal["onset"]), 2 * OVERTURN_RATIO_RANGE[1], nominal["onset"])
    margin_order = np.lexsort((np.arange(onset.size), -peaks[:, grid_index(1.0)], onset))
    out["exact: overturn margin (24-run scan), then peak"] = _order_value(margin_order)
    for name in TIERS:
        out[name] = np.asarray(scores[name], dtype=float)
    for name in PEERS:
        out[name] = at_intensity(name, np.asarray(scores[name], dtype=float), base)
    return out


def judges(sims: dict) -> dict[str, np.ndarray]:
    from stepframe.pipeline.selection.confirm import OVERTURN_RATIO_RANGE

    top = 2 * OVERTURN_RATIO_RANGE[1]
    nominal = sims["nominal"]
    out = {
        "nominal: peak at the stated intensity": nominal["peaks"][:, grid_index(1.0)],
        "nominal: peak at 1.5x": nominal["judge_peak"],
        "nominal: margin": -np.where(np.isnan(nominal["onset"]), top, nominal["onset"]),
    }
    for name, run in sims["perturbed"].items():
        out[f"{name}: peak"] = run["peak"]
        out[f"{name}: margin"] = -np.where(np.isnan(run["onset"]), top, run["onset"])
    return out


def _ranks(values: np.ndarray) -> np.ndarray:
    from scipy.stats import rankdata

    return np.asarray(rankdata(values, axis=-1), dtype=float)


def rho_samples(x: np.ndarray, y: np.ndarray, seed: int) -> tuple[float, np.ndarray]:
    """Spearman ρ of the finite pairs, and over :data:`N_RESAMPLES` bootstrap resamples of them
    (the same resamples, by seed, for every ranking with the same finite pairs: paired)."""

    def rho(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        ra, rb = _ranks(a), _ranks(b)
        ra -= ra.mean(axis=-1, keepdims=True)
        rb -= rb.mean(axis=-1, keepdims=True)
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.asarray(
                (ra * rb).sum(axis=-1) / np.sqrt((ra**2).sum(axis=-1) * (rb**2).sum(axis=-1))
            )

    keep = np.isfinite(x) & np.isfinite(y)
    if keep.sum() < 4 or np.ptp(x[keep]) == 0:
        return math.nan, np.full(N_RESAMPLES, np.nan)
    xs, ys = x[keep], y[keep]
    picks = np.random.default_rng(seed).integers(0, xs.size, size=(N_RESAMPLES, xs.size))
    return float(rho(xs, ys)), rho(xs[picks], ys[picks])


def study(frame_names: list[str], jobs: int | None) -> list[dict[str, Any]]:
    from stepframe.pipeline.selection.intensity import equal_intensity_scales

    family = frame_family()
    cats = catalogues(jobs)
    rows = []
    for frame_name in frame_names:
        frame, ratio = family[frame_name]
        for cat_name, (table, _, records) in cats.items():
            tag = slug(f"{frame_name}_{cat_name}")
            scores = scores_and_peers(frame, table, records, tag)
            sd_t1 = scores["sd_t1_xi1_m"]
            base = equal_intensity_scales(sd_t1, frame, ratio)
            sims = simulations(frame, ratio, records, sd_t1, tag)
            ranked = rankings(frame, ratio, sims, scores, base)
            judged = judges(sims)
            for name, x in ranked.items():
                row: dict[str, Any] = {"frame": frame_name, "catalogue": cat_name, "ranking": name}
                per: dict[str, tuple[float, np.ndarray]] = {
                    j: rho_samples(x, y, seed=0) for j, y in judged.items()
                }
                row.update({j: v for j, (v, _) in per.items()})
                for kind in ("peak", "margin"):
                    keys = [f"{p}: {kind}" for p in PERTURBATIONS]
                    values = np.array([per[k][0] for k in keys])
                    samples = np.nanmean(np.array([per[k][1] for k in keys]), axis=0)
                    low, high = (
                        np.nanpercentile(samples, [2.5, 97.5])
                        if np.isfinite(samples).any()
                        else (math.nan, math.nan)
                    )
                    row[f"perturbed {kind}: mean"] = (
                        float(np.nanmean(values)) if np.isfinite(values).any() else math.nan
                    )
                    row[f"perturbed {kind}: low"] = float(low)
                    row[f"perturbed {kind}: high"] = float(high)
                    worst = int(np.nanargmin(values)) if np.isfinite(values).any() else 0
                    row[f"perturbed {kind}: worst"] = (
                        f"{values[worst]:.2f} ({list(PERTURBATIONS)[worst]})"
                        if np.isfinite(values).any()
                        else "—"
                    )
                rows.append(row)
    return rows


def main() -> None:
    import pandas as pd

    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--jobs", type=int, default=None)
    parser.add_argument("--frames", choices=("all", "two"), default="all")
    parser.add_argument("--csv", default=None, help="also write every number to this CSV")
    parser.add_argument(
        "--from-csv", default=None, help="print the summary tables of a CSV this script wrote"
    )
    args = parser.parse_args()
    if args.from_csv:
        summary_tables(pd.read_csv(args.from_csv))
        return
    names = list(frame_family())
    if args.frames == "two":
        names = [n for n in names if n.startswith(("Example 4", "wide"))]
    rows = study(names, args.jobs)
    table = pd.DataFrame(rows)
    if args.csv:
        table.to_csv(args.csv, index=False)

    def f(v: float) -> str:
        return "—" if not np.isfinite(v) else f"{v:.2f}"

    print(
        "| frame | catalogue | ranking | nominal peak 1.5x | nominal margin | perturbed peak: "
        "mean [95 %] | worst | perturbed margin: mean [95 %] | worst |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(
            f"| {r['frame']} | {r['catalogue']} | {r['ranking']} | "
            f"{f(r['nominal: peak at 1.5x'])} | {f(r['nominal: margin'])} | "
            f"{f(r['perturbed peak: mean'])} [{f(r['perturbed peak: low'])}, "
            f"{f(r['perturbed peak: high'])}] | {r['perturbed peak: worst']} | "
            f"{f(r['perturbed margin: mean'])} [{f(r['perturbed margin: low'])}, "
            f"{f(r['perturbed margin: high'])}] | {r['perturbed margin: worst']} |"
        )
    summary_tables(table)


#: The rankings of the summary tables (docs/selection.md, "Robustness").
SUMMARY = {
    "exact: library, ladder 0.5-2 (5 levels)": "default (ladder ×0.5-2, 5)",
    "exact: 1 run at the stated intensity": "1 run",
    "exact: overturn margin (24-run scan), then peak": "24-run scan",
    "substitute_demand_ratio": "substitute",
}
PEER_COLUMNS = ("n_p_band", "fiv3_m_s", "sa_avg_g", "pgv_pga_s")


def summary_tables(table: Any) -> None:
    """Per judge (perturbed peak, perturbed margin, nominal peak at 1.5x): a frame × catalogue
    row with the mean ρ [95 %] of the default, the other exact measures, the substitute score,
    and the best peer (named); then the means over the 12 rows."""
    from stepframe.pipeline.selection.names import PEER_NAMES

    def f(v: float) -> str:
        return "—" if not np.isfinite(v) else f"{v:.2f}"

    for judge, label in (
        ("perturbed peak", "peak |x| of the 8 perturbed frames at the stated intensity"),
        ("perturbed margin", "overturning margin of the 8 perturbed frames"),
    ):
        print(f"\nmean ρ with the {label} [95 % bootstrap interval]:\n")
        heads = [*SUMMARY.values(), *PEER_COLUMNS, "best peer"]
        print("| frame | catalogue | " + " | ".join(heads) + " |")
        print("|---" * (len(heads) + 2) + "|")
        means: dict[str, list[float]] = {h: [] for h in heads}
        for (frame, catalogue), rows in table.groupby(["frame", "catalogue"], sort=False):
            by = rows.set_index("ranking")
            cells = []
            for name, head in [*SUMMARY.items(), *((p, p) for p in PEER_COLUMNS)]:
                value = by.at[name, f"{judge}: mean"]
                means[head].append(value)
                if name in SUMMARY and name != "substitute_demand_ratio":
                    low, high = by.at[name, f"{judge}: low"], by.at[name, f"{judge}: high"]
                    cells.append(f"{f(value)} [{f(low)}, {f(high)}]")
                else:
                    cells.append(f(value))
            peers = by.loc[[p for p in PEER_NAMES if p in by.index], f"{judge}: mean"]
            best = peers.idxmax()
            means["best peer"].append(peers.max())
            cells.append(f"{f(peers.max())} ({best})")
            print(f"| {frame} | {catalogue} | " + " | ".join(cells) + " |")
        print("| mean | | " + " | ".join(f(float(np.nanmean(means[h]))) for h in heads) + " |")


if __name__ == "__main__":
    main()
