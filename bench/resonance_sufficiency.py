"""Does the moving-resonance share explain the response beyond N_p? (issue 26, item 4)

Writes docs/resonance_sufficiency.png and prints the table quoted in docs/selection.md, "Moving
resonance, measured". Run: ``python bench/resonance_sufficiency.py [--n-synthetic 150]``.

Frames: the family of issue 24's ranking study (bench/ranking_study.py :func:`frame_family`):
Example 4 and the wide frame, and both with K_b changed so that T_1 = 0.5 s and 2 s (x_c/x* =
0.57 and 0.03), each with its stated onset ratio (1 and 2). Catalogues: the 100 FEMA P695
components, and Beck-Papadimitriou motions (60 s at 0.02 s, seeded) whose ω_g(t) falls into the
frames' band: ω_p in [8, 40] rad/s, ω_r in [0.5, 4] rad/s, ω_s between, ξ_p, ξ_r in [0.1, 0.6],
t_max in [3, 10] s, t_dur = t_max + [10, 30] s, all log-uniform or uniform as written.

Each record is scaled to equal PSA(T_1) at ``factor`` × the frame's stated ratio × the onset of
stepping (x_c / (P_1 SD(T_1))) for the factors of :data:`FACTORS`, and simulated exactly with the
index (:func:`stepframe.pipeline.dynamics.resonance.moving_resonance`). The response is
ln(peak |x| / x_c) of the runs that stepped and stood; runs that overturned are counted apart.
The standard measures are issue 24's peers (:func:`stepframe.pipeline.selection.peers.
record_peers`): N_p over [T_1, 2 T_1] and over [T_1, T(A_max)] (Bojórquez and Iervolino 2011)
and FIV3 of the scaled record (Dávalos and Miranda 2019), the best peers of docs/selection.md,
section 9. For each frame, catalogue and measure:

    ln(peak/x_c) = a + b ln IM + c ln factor + residual,

then the residual regressed on the moving-resonance share M (and on R_m where it is defined):
slope, its two-sided p-value (t test), the effect of one standard deviation of the index on the
response (exp(slope · sd) - 1), and the share of the residual variance it explains, beside the
share that the work depth alone explains (M = R_m × depth, and the depth is itself a response:
how far down its band the frame's amplitude took its frequency). The same on the subset of runs
with at least :data:`MANY_HALF_CYCLES` stepping half-cycles, the only ones in which a moving
resonance can build up.
"""

from __future__ import annotations

import argparse
import math
from typing import Any

import numpy as np

from ranking_study import frame_family

#: Intensities: multiples of the frame's stated onset ratio at equal PSA(T_1).
FACTORS = (0.75, 1.0, 1.5)
#: Stepping half-cycles of a run "that steps for many cycles".
MANY_HALF_CYCLES = 6


def synthetic_records(n: int, seed: int) -> list[tuple[np.ndarray, float]]:
    """``n`` Beck-Papadimitriou motions (m/s², peak intensity 1) with ω_r in the band."""
    from stepframe.stochastic.model import GroundMotionModel
    from stepframe.stochastic.synthetic import synthetic_motions

    rng = np.random.default_rng(seed)
    out = []
    for k in range(n):
        wp = math.exp(rng.uniform(math.log(8), math.log(40)))
        wr = math.exp(rng.uniform(math.log(0.5), math.log(4)))
        ws = wr + (wp - wr) * rng.uniform(0.05, 0.6)
        t_max = rng.uniform(3, 10)
        model = GroundMotionModel(
            wp, ws, wr, rng.uniform(0.1, 0.6), rng.uniform(0.1, 0.6), t_max,
            t_max + rng.uniform(10, 30),
        )  # fmt: skip
        _, acc = synthetic_motions(model, duration_s=60.0, dt_s=0.02, seed=seed * 100_000 + k)
        out.append((acc[0], 0.02))
    return out


def runs(
    frame: Any, ratio: float, records: list[tuple[np.ndarray, float]]
) -> dict[str, np.ndarray]:
    """Every record at every factor × ``ratio``: ln N_p over [T_1, 2 T_1] and over [T_1,
    T(A_max)], ln FIV3 of the scaled record, ln factor, peak/x_c, overturned, M, R_m, stepping
    half-cycles, work depth."""
    from stepframe.pipeline.dynamics.resonance import default_band, moving_resonance
    from stepframe.pipeline.selection.peers import PeerPeriods, record_peers
    from stepframe.records.spectra import peak_displacements_m

    t1 = 2 * math.pi / frame.omega_1_rad_s
    band = default_band(frame)
    periods = PeerPeriods(t1, 2 * math.pi / band[0])
    rows = []
    for acc, dt_s in records:
        peers = record_peers(acc, dt_s, periods)
        onset = frame.x_c_m / (frame.p_1 * peak_displacements_m(acc, dt_s, [t1], 0.05)[0])
        for factor in FACTORS:
            scale = factor * ratio * onset
            run = moving_resonance(frame, acc, dt_s, scale=scale, band_rad_s=band)
            m, s = run.measures, run.result.summary
            rows.append((
                math.log(peers["n_p_2t1"]), math.log(peers["n_p_band"]),
                math.log(peers["fiv3_m_s"] * scale), math.log(factor),
                s.peak_abs_x_m / frame.x_c_m, float(s.overturned), m.moving_resonance_share,
                m.moving_resonance_index, m.n_stepping_half_cycles, m.work_depth,
            ))  # fmt: skip
    table = np.array(rows)
    names = ("ln_np", "ln_np_band", "ln_fiv3", "ln_ratio", "peak_ratio", "overturned", "M",
             "R_m", "n_step", "depth")  # fmt: skip
    return {name: table[:, k] for k, name in enumerate(names)}


def residual_test(
    data: dict[str, np.ndarray], keep: np.ndarray, index: str, measure: str = "ln_np"
) -> dict[str, float]:
    """ln(peak/x_c) on ``measure`` and ln factor over ``keep``; the residual on ``index``."""
    from scipy.stats import linregress

    ok = keep & np.isfinite(data[index])
    nan = math.nan
    if ok.sum() < 5:
        return dict.fromkeys(("slope", "p", "effect", "r2", "b_np", "resid_sd"), nan) | {
            "n": float(ok.sum())
        }
    y = np.log(data["peak_ratio"][ok])
    design = np.column_stack([np.ones(ok.sum()), data[measure][ok], data["ln_ratio"][ok]])
    coef, *_ = np.linalg.lstsq(design, y, rcond=None)
    residual = y - design @ coef
    x = data[index][ok]
    if np.ptp(x) == 0:
        return {"n": float(ok.sum()), "slope": nan, "p": nan, "effect": nan, "r2": nan,
                "b_np": float(coef[1]), "resid_sd": float(np.std(residual))}  # fmt: skip
    fit = linregress(x, residual)
    return {
        "n": float(ok.sum()), "slope": float(fit.slope), "p": float(fit.pvalue),
        "effect": math.expm1(float(fit.slope) * float(np.std(x))), "r2": float(fit.rvalue) ** 2,
        "b_np": float(coef[1]), "resid_sd": float(np.std(residual)),
    }  # fmt: skip


def _panel(ax: Any, data: dict[str, np.ndarray], stood: np.ndarray, index: str, name: str) -> None:
    """The residual of ln(peak/x_c) on ln N_p and ln factor against ``index``, the runs that
    stepped for many half-cycles in colour."""
    keep = stood & np.isfinite(data[index])
    y = np.log(data["peak_ratio"][keep])
    design = np.column_stack([np.ones(keep.sum()), data["ln_np"][keep], data["ln_ratio"][keep]])
    coef, *_ = np.linalg.lstsq(design, y, rcond=None)
    many = data["n_step"][keep] >= MANY_HALF_CYCLES
    x, residual = data[index][keep], y - design @ coef
    ax.scatter(x[~many], residual[~many], s=9, color="0.6", label="fewer stepping half-cycles")
    ax.scatter(x[many], residual[many], s=11, color="C3",
               label=f"≥ {MANY_HALF_CYCLES} stepping half-cycles")  # fmt: skip
    ax.axhline(0.0, color="k", lw=0.6)
    ax.set_xlabel(name)
    ax.set_ylabel("residual of ln(peak/x_c)")
    ax.legend(fontsize="small")


def main() -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from stepframe.core.io import atomic_write
    from stepframe.records.examples import fema_p695

    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--n-synthetic", type=int, default=150)
    parser.add_argument("--out", default="docs/resonance_sufficiency.png")
    args = parser.parse_args()
    stream, _ = fema_p695()
    catalogues = {
        "FEMA P695 (100)": [(tr.data.astype(float), tr.stats.delta) for tr in stream],
        f"synthetic, ω_r in band ({args.n_synthetic})": synthetic_records(args.n_synthetic, 11),
    }
    figure, axes = plt.subplots(2, 2, figsize=(10, 7.5), layout="constrained", squeeze=False)
    figure.suptitle("Residual of ln(peak/x_c) on ln N_p [T_1, 2T_1] and ln factor against the "
                    "index (runs that stepped and stood)")  # fmt: skip
    print("| frame | catalogue | stood / stepped / overturned | subset | measure | n | b | "
          "residual sd | slope on M | p | 1 sd of M | R² (M) | R² (depth) | slope on R_m "
          "| p (R_m) | 1 sd of R_m |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    measures = {"ln_np": "N_p [T_1, 2T_1]", "ln_np_band": "N_p [T_1, T(A_max)]",
                "ln_fiv3": "FIV3"}  # fmt: skip
    for frame_name, (frame, ratio) in frame_family().items():
        for col, (label, records) in enumerate(catalogues.items()):
            data = runs(frame, ratio, records)
            stood = (data["overturned"] == 0) & (data["peak_ratio"] > 1)
            counts = (f"{int(stood.sum())} / {int((data['n_step'] > 0).sum())} / "
                      f"{int(data['overturned'].sum())} of {data['M'].size}")  # fmt: skip
            many = stood & (data["n_step"] >= MANY_HALF_CYCLES)
            for subset, keep in (("stood", stood), (f"≥ {MANY_HALF_CYCLES} half-cycles", many)):
                for measure, measure_name in measures.items():
                    on = {key: residual_test(data, keep, key, measure) for key in
                          ("M", "R_m", "depth")}  # fmt: skip
                    m, r = on["M"], on["R_m"]
                    if m["n"] < 5:  # too few runs to regress on
                        continue
                    print(
                        f"| {frame_name} | {label} | {counts} | {subset} | {measure_name} | "
                        f"{m['n']:.0f} | {m['b_np']:.2f} | {m['resid_sd']:.2f} | "
                        f"{m['slope']:.2f} | {m['p']:.2g} | {100 * m['effect']:+.0f} % | "
                        f"{m['r2']:.2f} | {on['depth']['r2']:.2f} | {r['slope']:.2f} | "
                        f"{r['p']:.2g} | {100 * r['effect']:+.0f} % |"
                    )
            if frame_name.startswith("wide ("):  # Example 4's frame stands too rarely to show
                shown = (("M", "moving-resonance share M"), ("R_m", "moving-resonance index R_m"))
                for panel, (index, name) in enumerate(shown):
                    _panel(axes[panel][col], data, stood, index, name)
                    axes[panel][col].set_title(f"{frame_name}, {label}", fontsize="medium")
    with atomic_write(args.out, "wb") as handle:
        figure.savefig(handle, format="png", dpi=110)
    print(f"\nwrote {args.out}")


if __name__ == "__main__":
    main()
