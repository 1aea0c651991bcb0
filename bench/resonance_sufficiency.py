"""Does the moving-resonance share explain the response beyond N_p? (issue 26, item 4)

Writes docs/resonance_sufficiency.png and prints the table quoted in docs/selection.md, "Moving
resonance, measured". Run: ``python bench/resonance_sufficiency.py [--n-synthetic 150]``.

Frames (:func:`family`): Example 4's (x* = 1.75 x_c) and the wide one of the selection's
confirmation (bench/selection_confirmation.py :func:`frames`, x* = 34 x_c, T_1 = 0.97 s) with its
legs' bending stiffness K_b times 4 and 1/4 (T_1 = 0.49 s and 1.95 s; x_c, x* unchanged).
Catalogues: the 100 FEMA P695 components, and Beck-Papadimitriou motions (60 s at 0.02 s,
seeded) whose ω_g(t) falls into the frames' band: ω_p in [8, 40] rad/s, ω_r in [0.5, 4] rad/s,
ω_s between, ξ_p, ξ_r in [0.1, 0.6], t_max in [3, 10] s, t_dur = t_max + [10, 30] s, all
log-uniform or uniform as written.

Each record is scaled to equal PSA(T_1) at ``ratio`` × the onset of stepping (x_c / (P_1 SD(T_1)))
for the ratios of :data:`RATIOS`, and simulated exactly with the index
(:func:`stepframe.pipeline.dynamics.resonance.moving_resonance`). The response is ln(peak |x| /
x_c) of the runs that stepped and stood; runs that overturned are counted apart. The standard
measures are N_p over [T_1, 2 T_1] and over [T_1, T(A_max)] (Bojórquez and Iervolino 2011: the
geometric mean of PSA at ten periods over the range, over PSA(T_1); T(A_max) the period at the
bottom of the frame's band, 2π/ω(0.8 x*)), the best standard measures of issue 24's study. For
each frame, catalogue and measure:

    ln(peak/x_c) = a + b ln N_p + c ln ratio + residual,

then the residual regressed on the moving-resonance share M (and on R_m where it is defined):
slope, its two-sided p-value (t test), the effect of one standard deviation of M on the response
(exp(slope · sd M) - 1), and the share of the residual variance it explains, beside the share
that the work depth alone explains (M = R_m × depth, and the depth is itself a response: how
far down its band the frame's amplitude took its frequency). The same on the
subset of runs with at least :data:`MANY_HALF_CYCLES` stepping half-cycles, the only ones in
which a moving resonance can build up.
"""

from __future__ import annotations

import argparse
import math
from typing import Any

import numpy as np

from selection_confirmation import frames

#: Intensities: multiples of the onset of stepping at equal PSA(T_1).
RATIOS = (1.5, 2.0, 3.0)
#: Stepping half-cycles of a run "that steps for many cycles".
MANY_HALF_CYCLES = 6
#: Periods over [T_1, 2 T_1] in N_p.
N_PERIODS = 10


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


def family() -> dict[str, Any]:
    """The frames of the study by name (module docstring)."""
    import tomllib

    from stepframe.structure.frame_file import FRAME_TEMPLATE, frame_from_mapping

    out = {name: frame for name, (frame, _) in frames().items()}
    for factor in (4.0, 0.25):
        tables = tomllib.loads(FRAME_TEMPLATE)
        del tables["constants"]
        tables["physical"]["k_b_n_m"] *= factor
        frame = frame_from_mapping(tables)
        out[f"wide, T_1 = {2 * math.pi / frame.omega_1_rad_s:.2f} s"] = frame
    return out


def _ln_np(sd_m: np.ndarray, periods_s: np.ndarray) -> float:
    """ln N_p from SD at T_1 (first) and the range's periods (the rest) [-]."""
    psa = sd_m * (2 * np.pi / periods_s) ** 2
    return float(np.mean(np.log(psa[1:])) - math.log(psa[0]))


def runs(frame: Any, records: list[tuple[np.ndarray, float]]) -> dict[str, np.ndarray]:
    """Every record at every ratio: ln N_p over [T_1, 2 T_1] and over [T_1, T(A_max)], ln ratio,
    peak/x_c, overturned, M, R_m, stepping half-cycles, work depth."""
    from stepframe.pipeline.dynamics.resonance import default_band, moving_resonance
    from stepframe.records.spectra import peak_displacements_m

    t1 = 2 * math.pi / frame.omega_1_rad_s
    band = default_band(frame)
    short = np.append(t1, np.geomspace(t1, 2 * t1, N_PERIODS))
    long = np.append(t1, np.geomspace(t1, 2 * math.pi / band[0], N_PERIODS))
    rows = []
    for acc, dt_s in records:
        sd = peak_displacements_m(acc, dt_s, np.concatenate([short, long[1:]]), frame.xi_1)
        ln_np = _ln_np(sd[: short.size], short)
        ln_np_band = _ln_np(np.append(sd[0], sd[short.size :]), long)
        onset = frame.x_c_m / (frame.p_1 * sd[0])
        for ratio in RATIOS:
            run = moving_resonance(frame, acc, dt_s, scale=ratio * onset, band_rad_s=band)
            m, s = run.measures, run.result.summary
            rows.append((
                ln_np, ln_np_band, math.log(ratio), s.peak_abs_x_m / frame.x_c_m,
                float(s.overturned), m.moving_resonance_share, m.moving_resonance_index,
                m.n_stepping_half_cycles, m.work_depth,
            ))  # fmt: skip
    table = np.array(rows)
    names = (
        "ln_np",
        "ln_np_band",
        "ln_ratio",
        "peak_ratio",
        "overturned",
        "M",
        "R_m",
        "n_step",
        "depth",
    )
    return {name: table[:, k] for k, name in enumerate(names)}


def residual_test(
    data: dict[str, np.ndarray], keep: np.ndarray, index: str, measure: str = "ln_np"
) -> dict[str, float]:
    """ln(peak/x_c) on ``measure`` and ln ratio over ``keep``; the residual on ``index``."""
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
    """The residual of ln(peak/x_c) on ln N_p and ln ratio against ``index``, the runs that
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
    figure.suptitle("Residual of ln(peak/x_c) on ln N_p [T_1, 2T_1] and ln ratio against the "
                    "index (runs that stepped and stood)")  # fmt: skip
    print("| frame | catalogue | stood / stepped / overturned | subset | measure | n | b | "
          "residual sd | slope on M | p | 1 sd of M | R² (M) | R² (depth) | slope on R_m "
          "| p (R_m) | 1 sd of R_m |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    measures = {"ln_np": "N_p [T_1, 2T_1]", "ln_np_band": "N_p [T_1, T(A_max)]"}
    for frame_name, frame in family().items():
        for col, (label, records) in enumerate(catalogues.items()):
            data = runs(frame, records)
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
            if frame_name.startswith("wide (l"):  # Example 4's frame stands too rarely to show
                shown = (("M", "moving-resonance share M"), ("R_m", "moving-resonance index R_m"))
                for panel, (index, name) in enumerate(shown):
                    _panel(axes[panel][col], data, stood, index, name)
                    axes[panel][col].set_title(f"{frame_name}, {label}", fontsize="medium")
    with atomic_write(args.out, "wb") as handle:
        figure.savefig(handle, format="png", dpi=110)
    print(f"\nwrote {args.out}")


if __name__ == "__main__":
    main()
