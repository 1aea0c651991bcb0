"""The speed/accuracy trade of the ranking tiers (docs/selection.md, "Tiers").

Run: ``python bench/ranking_tiers.py [--jobs 2]`` (uses bench/ranking_study.py's cached inputs
and simulations; run bench/ranking_robustness.py first, or this runs them).

Two tables:

- cost: CPU time per candidate on one core (numba on one thread) of every tier and of the
  exact ranking, on 40 synthetic 6,000-sample records (60 s at 0.01 s) for Example 4's frame;
- agreement: for every frame and catalogue, each tier's Spearman ρ with the exact ranking (the
  library's ``simulated_response`` at the stated intensity, nominal frame) and the recall of the
  exact top N = 10 inside the tier's top K, K = N, 2N, 5N, 10N; then per tier the worst recall
  over frames and catalogues, which sets the automatic prefilter (the tier and the smallest K
  keeping ≥ 95 % everywhere).
"""

from __future__ import annotations

import argparse
import math
import time
from typing import Any

import numpy as np

from ranking_study import catalogues, frame_family, load_note, scores_and_peers, simulations, slug

N = 10


def _cpu_per_item(function: Any, items: list[Any], repeat: int = 3) -> float:
    """Median over ``repeat`` passes of the CPU time per item of ``function(item)`` [s]."""
    times = []
    for _ in range(repeat):
        start = time.process_time()
        for item in items:
            function(item)
        times.append((time.process_time() - start) / len(items))
    return float(np.median(times))


def cost_table(frame: Any) -> list[tuple[str, float, str]]:
    """(what, ms per candidate, note) on one core."""
    import numba

    from stepframe.pipeline.selection import scores as sc
    from stepframe.pipeline.selection.band import frame_band
    from stepframe.pipeline.selection.exact import simulated_response
    from stepframe.pipeline.selection.intensity import equal_intensity_scales
    from stepframe.pipeline.selection.path import strong_motion_paths
    from stepframe.pipeline.selection.peers import PeerPeriods, fiv3_m_s, record_peers
    from stepframe.pipeline.selection.substitute import substitute_levels
    from stepframe.records.integration import velocity_m_s
    from stepframe.records.spectra import peak_displacements_m
    from stepframe.stochastic.catalog_features import catalog_features
    from stepframe.stochastic.model import GroundMotionModel
    from stepframe.stochastic.synthetic import synthetic_motions

    numba.set_num_threads(1)
    band = frame_band(frame)
    t1 = band.period_1_s
    rng = np.random.default_rng(3)
    records = []
    for k in range(40):
        wp = float(np.exp(rng.uniform(np.log(15), np.log(60))))
        model = GroundMotionModel(wp, 0.5 * wp, 0.2 * wp, 0.3, 0.3, 8.0, 25.0)
        _, acc = synthetic_motions(model, duration_s=59.99, dt_s=0.01, seed=k, peak_intensity=1.0)
        records.append((acc[0], 0.01))
    assert all(a.size == 6000 for a, _ in records)
    periods = PeerPeriods(t1, 2 * math.pi / band.omega_low_rad_s)
    rows: list[tuple[str, float, str]] = []

    def spectrum(periods_s: np.ndarray, damping: float = 0.05) -> Any:
        return lambda r: peak_displacements_m(r[0], r[1], periods_s, damping)

    from obspy import Stream

    from stepframe.records.trace import make_trace

    stream = Stream([make_trace(a, dt, station=f"S{k}", channel="HNX", source_file=f"s{k}")
                     for k, (a, dt) in enumerate(records[:10])])  # fmt: skip
    start = time.process_time()
    features, _ = catalog_features(stream, n_jobs=1)
    fit_ms = (time.process_time() - start) / 10 * 1e3
    rows.append(("the features fit (what the fit-based tiers presuppose)", fit_ms, "per record"))
    table = features.loc[np.repeat(features.index, 100)].reset_index(drop=True)
    start = time.process_time()
    for _ in range(5):
        paths = strong_motion_paths(table, 0.3)
        sc.band_coverage(paths, band)
        sc.spectral_ratio_eq_6_18(table, band.omega_1_rad_s)
        sc.omega_p_over_s_sq(table)
    closed = (time.process_time() - start) / 5 / len(table) * 1e3
    rows.append(
        ("closed forms (band_coverage, eq. 6.18, (ω_p/ω_s)²), all three", closed, "given the fit")
    )
    xi_levels = sc.equivalent_damping(frame.xi_2, frame.c_r)
    feature_rows = features.to_dict(orient="records")
    fpaths = strong_motion_paths(features, 0.3)
    physics = _cpu_per_item(
        lambda i: sc.physics_scores(
            feature_rows[i], band, frame.xi_1, xi_levels, (fpaths.start_s[i], fpaths.end_s[i])
        ),
        list(range(len(feature_rows))),
        repeat=1,
    )
    rows.append(
        (
            "backbone_amplification + descent_amplification (one call)",
            physics * 1e3,
            "given the fit",
        )
    )
    levels = substitute_levels(band)
    groups = levels.spectrum_groups()
    substitute = _cpu_per_item(
        lambda r: [peak_displacements_m(r[0], r[1], p, z) for p, z in groups], records
    )
    rows.append(("substitute_demand_ratio", substitute * 1e3, f"{len(groups)} spectrum calls"))
    rows.append(("sa_t1_g", _cpu_per_item(spectrum(np.array([t1])), records) * 1e3, "1 period"))
    avg = np.concatenate([[t1], periods.average])
    rows.append(("sa_avg_g, sa_ratio", _cpu_per_item(spectrum(avg), records) * 1e3, "11 periods"))
    rows.append(("n_p_2t1", _cpu_per_item(spectrum(periods.twice), records) * 1e3, "10 periods"))
    rows.append(("n_p_band", _cpu_per_item(spectrum(periods.band), records) * 1e3, "10 periods"))
    rows.append(
        (
            "sa_1_5t1_ratio",
            _cpu_per_item(spectrum(np.array([t1, 1.5 * t1])), records) * 1e3,
            "2 periods",
        )
    )
    rows.append(("fiv3_m_s", _cpu_per_item(lambda r: fiv3_m_s(r[0], r[1], t1), records) * 1e3, ""))
    rows.append(
        (
            "pgv_pga_s",
            _cpu_per_item(lambda r: np.max(np.abs(velocity_m_s(r[0], r[1]))), records) * 1e3,
            "",
        )
    )
    rows.append(
        ("every peer (record_peers, as a run computes them)",
         _cpu_per_item(lambda r: record_peers(r[0], r[1], periods), records) * 1e3, "")
    )  # fmt: skip
    sd = np.array([peak_displacements_m(a, dt, [t1], frame.xi_1)[0] for a, dt in records])
    for ratio in (1.0, 2.0):
        base = equal_intensity_scales(sd, frame, ratio)
        simulated_response(frame, records[:2], base[:2])  # compiled
        start = time.process_time()
        result = simulated_response(frame, records, base)
        exact = (time.process_time() - start) / len(records) * 1e3
        over = int(np.isfinite(result.overturn_factor).sum())
        rows.append(
            (f"exact: simulated_response at onset ratio {ratio:g}", exact,
             f"5-level ladder, {over} of {len(records)} overturn in it (bisected)")
        )  # fmt: skip
    return rows


def agreement_rows(jobs: int | None) -> list[dict[str, Any]]:
    from stepframe.pipeline.selection.exact import ranking_order
    from stepframe.pipeline.selection.intensity import equal_intensity_scales
    from stepframe.pipeline.selection.names import TIERS
    from stepframe.pipeline.selection.tiers import agreement, tier_values

    rows = []
    cats = catalogues(jobs)
    for frame_name, (frame, ratio) in frame_family().items():
        for cat_name, (table, _, records) in cats.items():
            tag = slug(f"{frame_name}_{cat_name}")
            scores = scores_and_peers(frame, table, records, tag)
            base = equal_intensity_scales(scores["sd_t1_xi1_m"], frame, ratio)
            nominal = simulations(frame, ratio, records, scores["sd_t1_xi1_m"], tag)["nominal"]
            order = ranking_order(nominal["library5_overturn"], nominal["library5_response"])
            exact = np.empty(order.size)
            exact[order] = 1.0 - np.arange(order.size) / (order.size - 1.0)
            frame_table = {name: np.asarray(scores[name], dtype=float) for name in TIERS}
            values = {name: tier_values(frame_table, name, base) for name in TIERS}
            for entry in agreement(exact, values, N):
                rows.append({"frame": frame_name, "catalogue": cat_name, **entry})
    return rows


def main() -> None:
    import pandas as pd

    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--jobs", type=int, default=None)
    parser.add_argument("--skip-cost", action="store_true")
    args = parser.parse_args()
    family = frame_family()
    if not args.skip_cost:
        frame = family["Example 4 (T1 0.97 s, x_c/x* 0.57)"][0]
        print(f"cost per candidate, one core ({load_note()}):\n")
        print("| ranking | ms per candidate | note |")
        print("|---|---|---|")
        for what, ms, note in cost_table(frame):
            print(f"| {what} | {ms:.3g} | {note} |")
        print(f"\n({load_note()} after)\n")
    rows = pd.DataFrame(agreement_rows(args.jobs))
    keys = [f"recall_at_{m}n" for m in (1, 2, 5, 10)]
    print("| frame | catalogue | tier | ρ with exact | recall K=N | 2N | 5N | 10N |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows.itertuples():
        rho = "—" if not np.isfinite(r.spearman) else f"{r.spearman:.2f}"
        recalls = " | ".join(f"{getattr(r, k):.1f}" for k in keys)
        print(f"| {r.frame} | {r.catalogue} | {r.tier} | {rho} | {recalls} |")
    worst = rows.groupby("tier", sort=False)[[*keys, "spearman"]].agg(
        {**dict.fromkeys(keys, "min"), "spearman": "mean"}
    )
    print("\nworst recall over every frame and catalogue, mean ρ:\n")
    print("| tier | mean ρ with exact | worst recall K=N | 2N | 5N | 10N |")
    print("|---|---|---|---|---|---|")
    for tier, r in worst.iterrows():
        print(f"| {tier} | {r['spearman']:.2f} | " + " | ".join(f"{r[k]:.2f}" for k in keys) + " |")


if __name__ == "__main__":
    main()
