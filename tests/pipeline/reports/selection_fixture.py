"""A small selection output folder, laid out as `stepframe select -o DIR` writes it.

Built from real records of the embedded FEMA P695 catalogue: each candidate's ω_g(t) parameters
come from fitting that record (stepframe.stochastic), so the figures draw real paths. The scores
are how close the fitted path ends to the frame's ω_1 (a stand-in for the selection's own scores:
the report draws whatever score the folder names). Used until the selection stage's own writer is
on main.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd

from stepframe.pipeline.selection.options import SelectionOptions
from stepframe.pipeline.selection.spectral import target_record
from stepframe.records.examples import fema_p695
from stepframe.records.units import STANDARD_GRAVITY_M_S2
from stepframe.stochastic.features import record_features
from stepframe.stochastic.fit import fit_model
from stepframe.stochastic.model import MODEL_FIELDS
from stepframe.structure.code_spectra import Asce7TwoPeriod
from stepframe.structure.frame_file import frame_template, read_frame_file
from stepframe.structure.period_amplitude import period_amplitude

#: Example-catalogue components the fixture uses (row numbers of the metadata table).
ROWS = (0, 7, 15, 22, 40, 55, 70, 88)


def _closeness(model, omega_1: float) -> float:
    """exp(-|ln(ω_g(t_dur)/ω_1)|): 1 when the path ends at the frame's frequency."""
    end = float(model.omega_g(model.t0_s + model.t_dur_s))
    return float(np.exp(-abs(np.log(end / omega_1))))


def make_selection_folder(
    folder: Path,
    *,
    n_selected: int = 4,
    confirm: bool = True,
    rows: tuple[int, ...] | range = ROWS,
) -> Path:
    """Write the fixture folder (candidates: the catalogue ``rows``); returns it."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "frame.toml").write_text(frame_template(), encoding="utf-8")
    frame = read_frame_file(folder / "frame.toml")
    a_max = frame.x_c_m + 0.5 * (frame.x_star_m - frame.x_c_m)
    band = (2 * math.pi / float(period_amplitude(frame, a_max)), frame.omega_1_rad_s)
    stream, table = fema_p695()
    records = []
    for index in rows:
        trace = stream[index]
        fit = fit_model(record_features(trace))
        model = fit.model
        start, end = model.t0_s, model.t0_s + model.t_dur_s
        row = {
            "file": trace.stats.stepframe.source_file,
            "component": trace.stats.channel,
            "event": table.loc[index, "event"],
            "magnitude": table.loc[index, "magnitude"],
            "end_closeness": _closeness(model, frame.omega_1_rad_s),
            "spectral_ratio_eq_6_18": math.nan,
            **{k: getattr(model, k) for k in MODEL_FIELDS},
            "strong_motion_start_s": start,
            "strong_motion_end_s": end,
            "fit_quality": fit.fit_quality,
            "dropped_by": "",
        }
        records.append(row)
    candidates = pd.DataFrame(records)
    candidates.loc[candidates["magnitude"] <= 6.6, "dropped_by"] = "magnitude"
    kept = candidates[candidates["dropped_by"] == ""].sort_values("end_closeness", ascending=False)
    selection = kept.head(n_selected).copy()
    selection.insert(2, "rank", np.arange(1, len(selection) + 1))
    selection.insert(3, "scale_factor", 1.0)
    selection.to_csv(folder / "selection.csv", index=False)
    candidates.to_csv(folder / "candidates.csv", index=False)
    pd.DataFrame(
        {
            "column": ["file", "end_closeness"],
            "meaning": ["record file", "exp(-|ln(ω_g(t_dur)/ω_1)|), 1 = ends at ω_1"],
        }
    ).to_csv(folder / "candidates.columns.csv", index=False)
    pd.DataFrame(
        [
            {
                "item": "fema_p695/broken.txt",
                "stage": "fit",
                "error_type": "InputError",
                "message": "fewer than 5 strong-motion frames",
            }
        ]
    ).to_csv(folder / "failures.csv", index=False)
    if confirm:
        rng = np.random.default_rng(3)
        confirmation = kept[["file", "component", "end_closeness"]].copy()
        confirmation["group"] = np.where(
            confirmation["file"].isin(selection["file"]), "selected", "control"
        )
        confirmation["peak_drift_m"] = (
            0.05 + 0.2 * confirmation["end_closeness"] + rng.normal(0, 0.01, len(confirmation))
        )
        confirmation.to_csv(folder / "confirmation.csv", index=False)
    summary = {
        "band_rad_s": list(band),
        "rank_by": "end_closeness",
        "n_candidates": len(candidates),
        "n_filtered": int((candidates["dropped_by"] != "").sum()),
        "n_failures": 1,
        "frame_file": "frame.toml",
        "frame_name": "Example 4 frame",
        "a_max_m": a_max,
        "scale": "none",
        "target": target_record(
            Asce7TwoPeriod(1.0, 0.6, None, STANDARD_GRAVITY_M_S2),
            SelectionOptions(target_s_ds_g=1.0, target_s_d1_g=0.6),
            np.geomspace(0.05, 10.0, 60),
        ),
        "selected": selection[["file", "component", "rank", "scale_factor"]].to_dict("records"),
    }
    (folder / "selection.json").write_text(json.dumps(summary, indent=2), encoding="utf-8")
    return folder
