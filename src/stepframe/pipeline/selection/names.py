"""Names of the selection's choices (no heavy imports: the command line reads them for --help)."""

from __future__ import annotations

from typing import Literal

#: Scores a run can rank by (:mod:`stepframe.pipeline.selection.scores` defines each).
RANKABLE = (
    "band_coverage",
    "spectral_ratio_eq_6_18",
    "omega_p_over_s_sq",
    "backbone_amplification",
    "descent_amplification",
    "substitute_demand_ratio",
)
#: Scores computed per candidate by the covariance method (the others are closed forms).
PHYSICS_SCORES = ("backbone_amplification", "descent_amplification")
#: Scores computed from the record's samples (its response spectrum), not from the fit.
RECORD_SCORES = ("substitute_demand_ratio",)

ScalePolicy = Literal["none", "psa-at-t1", "target-mse"]
SCALE_POLICIES: tuple[ScalePolicy, ...] = ("none", "psa-at-t1", "target-mse")
DistanceMetric = Literal["rrup", "rjb", "repi"]
DISTANCE_METRICS: tuple[DistanceMetric, ...] = ("rrup", "rjb", "repi")
Unit = Literal["component", "record"]
UNITS: tuple[Unit, ...] = ("component", "record")
