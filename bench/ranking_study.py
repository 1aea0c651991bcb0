"""Shared inputs of the ranking studies (bench/ranking_robustness.py, bench/ranking_tiers.py):
the catalogues, the family of frames, every candidate's scores and peers, and the simulations,
each cached under bench/out/ranking/ (git-ignored) so that a table is re-printed in seconds.

Catalogues: the 100 embedded FEMA P695 components, and 300 synthetic Beck-Papadimitriou motions
(bench/selection_confirmation.py's, seed 7). Every component is a candidate: no fit is needed to
simulate a record, so no fit-quality gate applies (a score that reads the fit is computed for
every row that has finite parameters).

Frames (:func:`frame_family`), written as FRAME.toml tables (docs/frame-file.md): the paper's
Example 4 (printed constants: T_1 = 0.97 s, x_c/x* = 0.57), the "wide" frame (the same physical
inputs through eqs. 4.6-4.7 with l = L_F/2: x_c/x* = 0.03), and the same two with K_b changed so
that T_1 = 0.5 s and 2 s (the physical route; x_c and x* do not depend on K_b). Frames with a
large x_c/x* are ranked at the onset intensity (ratio 1), those with a small one at twice it
(ratio 2): at ratio 1 a wide frame barely steps, at ratio 2 a narrow one overturns under
nearly every record.

Perturbed frames (:data:`PERTURBATIONS`): ξ_1, γ_1 and x_c each ×0.7 and ×1.3, and C_r set to
0.8 and to 0.97. A record keeps the scale factor the nominal frame gave it (the engineer's
model sets the scale; the real frame differs).
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
import os
import tomllib
from pathlib import Path
from typing import Any

import numpy as np

OUT = Path(__file__).resolve().parent / "out" / "ranking"
#: Onset ratios of the nominal simulation grid: 2^(k/2), k = -6..4 (0.125 to 4 times the
#: stated intensity), plus 1.5 (a judge: the peak at 1.5 times the stated intensity).
GRID = tuple(float(2.0 ** (k / 2)) for k in range(-6, 5))
JUDGE_FACTOR = 1.5
#: Ladders the library's own ranking is run with: 0.5 to 2 times the stated intensity, this many
#: log-spaced levels (the ladder is also the overturning scan, so its step sets what it sees).
LIBRARY_LADDERS = (5, 9, 13)
PERTURBATIONS: dict[str, dict[str, float]] = {
    "xi_1 x0.7": {"xi_1": 0.7},
    "xi_1 x1.3": {"xi_1": 1.3},
    "gamma_1 x0.7": {"gamma_1_m_s2": 0.7},
    "gamma_1 x1.3": {"gamma_1_m_s2": 1.3},
    "x_c x0.7": {"x_c_m": 0.7},
    "x_c x1.3": {"x_c_m": 1.3},
    "C_r 0.8": {"c_r": math.nan},
    "C_r 0.97": {"c_r": math.nan},
}
C_R_VALUES = {"C_r 0.8": 0.8, "C_r 0.97": 0.97}


def perturbed(frame: Any, name: str) -> Any:
    """``frame`` with the perturbation ``name`` applied."""
    if name in C_R_VALUES:
        return dataclasses.replace(frame, c_r=C_R_VALUES[name])
    ((field, factor),) = PERTURBATIONS[name].items()
    return dataclasses.replace(frame, **{field: getattr(frame, field) * factor})


def frame_family() -> dict[str, tuple[Any, float]]:
    """(frame, stated onset ratio) by name (module docstring)."""
    from stepframe.structure.frame_file import FRAME_TEMPLATE, frame_from_mapping

    base = tomllib.loads(FRAME_TEMPLATE)
    example4 = frame_from_mapping(base)
    t_1 = 2 * math.pi / example4.omega_1_rad_s
    l_example4 = 0.2263  # the l in γ_1 that reproduces Example 4's printed γ_1 (the template)
    family: dict[str, tuple[Any, float]] = {}
    for period_s in (0.5, t_1, 2.0):
        for narrow in (True, False):
            tables = tomllib.loads(FRAME_TEMPLATE)
            if math.isclose(period_s, t_1) and narrow:
                frame = example4
            else:
                del tables["constants"]
                tables["physical"]["k_b_n_m"] *= (t_1 / period_s) ** 2
                if narrow:
                    tables["conventions"]["l_m"] = l_example4
                frame = frame_from_mapping(tables)
            period = 2 * math.pi / frame.omega_1_rad_s
            shape = f"T1 {period:.2g} s, x_c/x* {frame.x_c_m / frame.x_star_m:.2f}"
            name = (
                "Example 4"
                if frame is example4
                else ("wide" if math.isclose(period_s, t_1) else "")
            )
            label = f"{name} ({shape})" if name else shape
            family[label] = (frame, 1.0 if narrow else 2.0)
    return family


def catalogues(jobs: int | None) -> dict[str, tuple[Any, list[tuple[str, str]], list[Any]]]:
    """(features table, keys, records) by catalogue name, every component a candidate."""
    import pandas as pd

    OUT.mkdir(parents=True, exist_ok=True)
    out = {}
    for name in ("FEMA P695", "synthetic"):
        table_path = OUT / f"{name.split()[0]}_features.parquet"
        samples_path = OUT / f"{name.split()[0]}_samples.npz"
        if table_path.is_file() and samples_path.is_file():
            table = pd.read_parquet(table_path)
            packed = np.load(samples_path)
            records = [(packed[f"a{k}"], float(packed["dt"][k])) for k in range(len(packed["dt"]))]
        else:
            if name == "FEMA P695":
                from stepframe.pipeline.selection.inputs import example_catalogue

                table, by_key, _ = example_catalogue(jobs)
            else:
                from selection_confirmation import synthetic_catalogue

                table, by_key = synthetic_catalogue(300, seed=7)
            table = table.reset_index(drop=True)
            keys = list(zip(table["file"].astype(str), table["component"].astype(str), strict=True))
            records = [by_key[k] for k in keys]
            table.to_parquet(table_path)
            np.savez(
                samples_path,
                dt=np.array([dt for _, dt in records]),
                **{f"a{k}": acc for k, (acc, _) in enumerate(records)},
            )
        keys = list(zip(table["file"].astype(str), table["component"].astype(str), strict=True))
        out[name] = (table, keys, records)
    return out


def _cached(path: Path, compute: Any) -> dict[str, np.ndarray]:
    if path.is_file():
        with np.load(path, allow_pickle=False) as data:
            return {k: data[k] for k in data.files}
    values = compute()
    np.savez(path, **values)
    return values


def slug(text: str) -> str:
    return "".join(c if c.isalnum() else "_" for c in text)


def scores_and_peers(frame: Any, table: Any, records: list[Any], tag: str) -> dict[str, Any]:
    """Every tier's value per candidate (fit scores, substitute score, peers), cached."""
    from stepframe.pipeline.selection import scores as sc
    from stepframe.pipeline.selection.band import frame_band
    from stepframe.pipeline.selection.path import MODEL_COLUMNS, strong_motion_paths
    from stepframe.pipeline.selection.peers import PEERS, PeerPeriods, record_peers
    from stepframe.pipeline.selection.substitute import (
        substitute_demand_ratio,
        substitute_levels,
    )
    from stepframe.records.spectra import peak_displacements_m

    def compute() -> dict[str, np.ndarray]:
        band = frame_band(frame)
        paths = strong_motion_paths(table, 0.3)
        out: dict[str, np.ndarray] = {
            "band_coverage": sc.band_coverage(paths, band),
            "spectral_ratio_eq_6_18": sc.spectral_ratio_eq_6_18(table, band.omega_1_rad_s),
            "omega_p_over_s_sq": sc.omega_p_over_s_sq(table),
        }
        xi_levels = sc.equivalent_damping(frame.xi_2, frame.c_r)
        backbone = np.full(len(table), np.nan)
        descent = np.full(len(table), np.nan)
        rows = table.to_dict(orient="records")
        for i, row in enumerate(rows):
            params = [row[c] for c in MODEL_COLUMNS]
            if not (all(np.isfinite(params)) and np.isfinite(paths.end_s[i])):
                continue
            # a score that cannot be computed stays NaN, as in the run
            with contextlib.suppress(Exception):
                backbone[i], descent[i] = sc.physics_scores(
                    row, band, frame.xi_1, xi_levels, (paths.start_s[i], paths.end_s[i])
                )
        out["backbone_amplification"] = backbone
        out["descent_amplification"] = descent
        levels = substitute_levels(band)
        sd = np.array(
            [
                levels.gather(
                    [peak_displacements_m(a, dt, p, z) for p, z in levels.spectrum_groups()]
                )
                for a, dt in records
            ]
        )
        out["substitute_demand_ratio"] = substitute_demand_ratio(sd, levels)
        out["sd_t1_xi1_m"] = sd[:, 0]
        periods = PeerPeriods(band.period_1_s, 2 * math.pi / band.omega_low_rad_s)
        values = [record_peers(a, dt, periods) for a, dt in records]
        for name in PEERS:
            out[name] = np.array([v[name] for v in values])
        return out

    return _cached(OUT / f"scores_{tag}.npz", compute)


def simulations(frame: Any, ratio: float, records: list[Any], sd_t1: np.ndarray, tag: str) -> dict:
    """The nominal frame on :data:`GRID` and at the judge factor, and its overturning scan; each
    perturbed frame at the stated intensity and its overturning scan (cached)."""
    from stepframe.pipeline.selection.confirm import (
        equal_intensity_scales,
        overturn_onset_ratios,
    )
    from stepframe.pipeline.selection.exact import ladder_runs, simulated_response

    base = equal_intensity_scales(sd_t1, frame, ratio)

    def nominal() -> dict[str, np.ndarray]:
        runs = ladder_runs(frame, records, base, (*GRID, JUDGE_FACTOR))
        onset = overturn_onset_ratios(frame, records, sd_t1)
        return {
            "peaks": runs.peaks_m[:, : len(GRID)],
            "overturned": runs.overturned[:, : len(GRID)],
            "judge_peak": runs.peaks_m[:, -1],
            "onset": onset,
            "failed": np.array([bool(m) for m in runs.failed]),
        }

    def library(levels: int) -> Any:
        def compute() -> dict[str, np.ndarray]:
            ladder = tuple(float(f) for f in np.geomspace(0.5, 2.0, levels))
            response = simulated_response(frame, records, base, ladder)
            return {
                f"library{levels}_response": response.response_m,
                f"library{levels}_overturn": response.overturn_factor,
            }

        return compute

    out = {
        "nominal": {
            **_cached(OUT / f"sim_{tag}_nominal.npz", nominal),
            **{
                key: value
                for levels in LIBRARY_LADDERS
                for key, value in _cached(
                    OUT / f"sim_{tag}_library{levels}.npz", library(levels)
                ).items()
            },
        },
        "perturbed": {},
    }
    for name in PERTURBATIONS:
        other = perturbed(frame, name)

        def compute(other: Any = other) -> dict[str, np.ndarray]:
            runs = ladder_runs(other, records, base, (1.0,))
            # the scan in the nominal frame's onset units (the records keep their scales)
            onset = overturn_onset_ratios(other, records, sd_t1 * other.x_c_m / frame.x_c_m)
            return {"peak": runs.peaks_m[:, 0], "onset": onset}

        out["perturbed"][name] = _cached(OUT / f"sim_{tag}_{slug(name)}.npz", compute)
    return out


def load_note() -> str:
    """The load average beside the timings (the machine is shared)."""
    return f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs"
