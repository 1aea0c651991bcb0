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

#: Fit-based tiers: they need finite fitted parameters; the others read the record.
FIT_TIERS = (
    "band_coverage",
    "spectral_ratio_eq_6_18",
    "omega_p_over_s_sq",
    "backbone_amplification",
    "descent_amplification",
)


def ranks_by_fit(rank_by: str) -> bool:
    """Whether the ranking ``rank_by`` reads the fitted parameters: only then can the bootstrap
    over their standard errors move the chosen set, and ``selection_probability`` say more than
    1 for the chosen and 0 for the rest (the simulated response and the spectra read the
    record)."""
    return rank_by in FIT_TIERS


ScalePolicy = Literal["none", "psa-at-t1", "target-mse"]
SCALE_POLICIES: tuple[ScalePolicy, ...] = ("none", "psa-at-t1", "target-mse")
DistanceMetric = Literal["rrup", "rjb", "repi"]
DISTANCE_METRICS: tuple[DistanceMetric, ...] = ("rrup", "rjb", "repi")
Unit = Literal["component", "record"]
UNITS: tuple[Unit, ...] = ("component", "record")

# The ranking by the frame's simulated response, its peers and tiers (docs/selection.md,
# "Ranking by the simulated response").

#: The default ranking: the frame's simulated response over a ladder of intensities
#: (:mod:`stepframe.pipeline.selection.exact`).
SIMULATED_RESPONSE = "simulated_response"
#: The standard intensity measures an engineer would use instead
#: (:mod:`stepframe.pipeline.selection.peers` defines each).
PEER_NAMES = (
    "sa_t1_g",
    "sa_avg_g",
    "sa_ratio",
    "n_p_2t1",
    "n_p_band",
    "fiv3_m_s",
    "sa_1_5t1_ratio",
    "pgv_pga_s",
    "pgv_sa_t1_s",
)
#: Rankings cheaper than the simulation (the fidelity ladder's lower rungs): the project's
#: scores and the peers; each can rank on its own or prefilter the simulation.
TIERS = (*RANKABLE, *PEER_NAMES)
#: What ``rank_by`` accepts.
RANK_BY_CHOICES = (SIMULATED_RESPONSE, *TIERS)
#: What ``prefilter`` accepts: ``auto`` (the budget rule), ``none`` (simulate every candidate)
#: or a tier.
PREFILTER_CHOICES = ("auto", "none", *TIERS)
#: Scores another ranking beats at no greater cost (docs/selection.md, "Keep what earns its
#: place"): computed only when a run names them (``rank_by``, ``prefilter``, ``scores``).
DOMINATED = (
    "backbone_amplification",
    "descent_amplification",
    "spectral_ratio_eq_6_18",
    "substitute_demand_ratio",
)
