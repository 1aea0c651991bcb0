"""Options of a selection run (a frozen dataclass, readable from a TOML table).

The fields carry their command-line help (:func:`stepframe.core.options.option`): ``stepframe
select`` derives its options from them, so a ``[selection]`` table and the command line name the
same fields.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, fields
from typing import Any

from stepframe.core.options import Range, check_fields, option
from stepframe.errors import InputError
from stepframe.pipeline.selection.io_names import (
    CODES,
    EC8_GROUNDS,
    EC8_TYPES,
    PAIR_SPECTRA,
    UNMATCHED,
    Code,
    Ec8Ground,
    Ec8Type,
    PairSpectrum,
    Unmatched,
)
from stepframe.pipeline.selection.names import (
    DISTANCE_METRICS,
    FIT_TIERS,
    PREFILTER_CHOICES,
    RANK_BY_CHOICES,
    SCALE_POLICIES,
    SIMULATED_RESPONSE,
    TIERS,
    UNITS,
    DistanceMetric,
    ScalePolicy,
    Unit,
    ranks_by_fit,
)

#: Amplitude limits accepted [m]: a frame's overturning displacement is a few metres.
_METRES = Range(0, 100, low_open=True)
#: Design spectral accelerations accepted [g] (ASCE 7-22 S_DS and S_D1 stay below 5 g).
_DESIGN_G = Range(0, 10, low_open=True)
#: Scale factors accepted: a record scaled 100 times is another record.
_SCALES = Range(0, 100, low_open=True)


@dataclass(frozen=True)
class SelectionOptions:
    """Everything a selection run needs besides the features table and the frame.

    Attributes
    ----------
    n
        Number of components (``unit="component"``) or records (``"record"``: both horizontal
        components of a station and event) to select.
    unit
        ``"component"`` or ``"record"``.
    rank_by
        The ranking (:data:`stepframe.pipeline.selection.names.RANK_BY_CHOICES`): default
        ``simulated_response``, the frame's own simulated response at the ranking intensity
        (docs/selection.md); or a tier (a score of the project or a standard intensity measure)
        at the same intensity.
    spectral_weight
        Weight of the spectral misfit (target spectrum) against the ranking score in the
        combined objective (0: rank only).
    a_max_m, design_displacement_m, x_star_fraction, n_levels
        The frame's band (:func:`stepframe.pipeline.selection.band.frame_band`).
    strong_motion_fraction
        The strong-motion window is I_g ≥ this fraction of its peak.
    n_bootstrap, seed
        Bootstrap replicates over the fit's standard errors (rank stability) and their seed.
    magnitude_min, magnitude_max, distance_min_km, distance_max_km, distance_metric,
    vs30_min_m_s, vs30_max_m_s, d5_95_min_s, d5_95_max_s, pga_min_g, pga_max_g
        Metadata filters (each needs its column in the table; None: not applied).
    lowest_usable_below_band
        Drop components whose lowest usable frequency (column ``lowest_usable_hz``) is above
        the bottom of the band.
    require_plausible
        Drop fits that fail the features table's plausibility checks (ω_p at its bound, ω_r at
        its floor, a clipped ξ). Off by default: a record needs no fitted model to be simulated,
        so the flag is information (column ``plausible``), a gate only when asked.
    exclude
        Files or RSNs to leave out.
    max_per_event, max_per_station
        Caps on the chosen set (None: no cap).
    target_s_ds_g, target_s_d1_g, target_csv
        Target spectrum: the two-period design spectrum (S_DS, S_D1 in g) or a CSV of
        ``period_s,sa_g`` rows.
    target_periods_s
        (low, high) period range of the spectral misfit [s] (None: T_1 to T(A_max), capped at
        10 s).
    scale
        ``"none"`` (default, as the paper), ``"psa-at-t1"`` (the target's PSA at T_1, or the
        candidates' median without a target) or ``"target-mse"`` (least squares in ln PSA).
    scale_min, scale_max
        Bounds of the scale factor.
    confirm
        Run the confirmation by simulation.
    confirm_onset_ratio
        Common intensity of the confirmation: every record scaled so that the linear frame's
        peak P_1·SD(T_1, ξ_1) is this multiple of x_c (equal PSA at T_1).
    verticals
        Keep vertical components (default: horizontals only; never with ``unit="record"``).
    exclude_unmatched
        An exclusion entry that matches no candidate: ``"error"`` (default) or ``"warn"``.
    pgv_min_m_s, pgv_max_m_s, psa_t1_min_g, psa_t1_max_g, arias_min_m_s, arias_max_m_s
        Amplitude filters, with ``pga_*`` and ``d5_95_*``: from the metadata where it gives
        the value, else computed from the records (PSA(T_1) at 5 % damping).
    pair_spectrum
        How a record's two horizontal components make one spectrum (``unit="record"``):
        ``"rotd50"`` (default), ``"geomean"`` or ``"rotd100"`` (maximum direction).
    target_t_l_s
        ASCE 7-22 two-period spectrum: the long-period transition T_L [s] (None: none).
    target_code
        The code whose suite rule checks a ``target_csv`` spectrum (``"asce7-22"``: its
        multi-period spectrum; ``"ec8"``); the built-in spectra name their own.
    target_ec8, target_ground, target_ag_g, target_importance
        Eurocode 8 (EN 1998-1 §3.2.2.2) elastic spectrum: ``"type1"`` or ``"type2"``, ground
        type A-E, the reference peak ground acceleration a_gR [g] and the importance factor
        γ_I (a_g = γ_I a_gR).
    target_damping
        Damping ratio of the target spectrum and of the records' spectra compared with it in
        the code check (Eurocode 8's η; ASCE 7-22 spectra are for 0.05).
    rank_onset_ratio, rank_psa_t1_g
        The ranking intensity (:mod:`stepframe.pipeline.selection.intensity`): every record at
        equal PSA(T_1), given as a multiple of the onset of stepping or in g (5 % damping); at
        most one. Neither (default): the records as they will be used (their scale factors;
        ``scale = "none"``: as recorded).
    prefilter, prefilter_k, exact_budget_s
        ``"auto"`` (default) simulates every candidate while the estimated cost stays under
        ``exact_budget_s`` [s], else ranks by the measured best tier first and simulates its
        best ``prefilter_k`` (default: the share of the candidates that kept the exact top 10
        in every case measured, :mod:`stepframe.pipeline.selection.tiers`); ``"none"`` always
        simulates every candidate; a tier name always prefilters by that tier.
    scores
        Scores to compute and compare besides the defaults (the dominated ones of
        :data:`stepframe.pipeline.selection.names.DOMINATED` are computed only when named here,
        by ``rank_by`` or by ``prefilter``).
    """

    n: int = 10
    unit: Unit = option("component", "select components, or records with both components")
    rank_by: str = option(
        SIMULATED_RESPONSE, "ranking (default: %(default)s)", choices=RANK_BY_CHOICES
    )
    spectral_weight: float = 0.0
    a_max_m: float | None = option(
        None, "amplitude limit A_max [m]", kind="positive", valid=_METRES
    )
    design_displacement_m: float | None = None
    x_star_fraction: float = option(
        0.8,
        "A_max = fraction·x* otherwise (default: %(default)s)",
        kind="positive",
        valid=Range(0, 1, low_open=True, high_open=True),
    )
    n_levels: int = 6
    strong_motion_fraction: float = option(
        0.3,
        "strong motion: I_g ≥ fraction of its peak (default: %(default)s)",
        kind="positive",
        valid=Range(0.1, 1, low_open=True, high_open=True),
    )
    n_bootstrap: int = 10
    seed: int = 0
    magnitude_min: float | None = None
    magnitude_max: float | None = None
    distance_min_km: float | None = None
    distance_max_km: float | None = None
    distance_metric: DistanceMetric = "rrup"
    vs30_min_m_s: float | None = None
    vs30_max_m_s: float | None = None
    d5_95_min_s: float | None = None
    d5_95_max_s: float | None = None
    pga_min_g: float | None = None
    pga_max_g: float | None = None
    lowest_usable_below_band: bool = option(
        False, "drop records whose lowest usable frequency is above the band"
    )
    require_plausible: bool = option(
        False, "drop records whose fit fails the plausibility checks (default: rank them)"
    )
    exclude: tuple[str, ...] = ()
    max_per_event: int | None = None
    max_per_station: int | None = None
    target_s_ds_g: float | None = option(
        None, "two-period S_DS [g]", kind="positive", valid=_DESIGN_G
    )
    target_s_d1_g: float | None = option(
        None, "two-period S_D1 [g]", kind="positive", valid=_DESIGN_G
    )
    target_csv: str | None = option(None, "tabulated target: period_s,sa_g", metavar="CSV")
    target_periods_s: tuple[float, float] | None = option(
        None, kind="floats", metavar="LOW,HIGH", valid=Range(0.001, 100)
    )
    scale: ScalePolicy = option("none", "scaling policy (default: %(default)s)")
    scale_min: float = option(0.25, kind="positive", valid=_SCALES)
    scale_max: float = option(4.0, kind="positive", valid=_SCALES)
    confirm: bool = option(False, "confirm by simulation")
    confirm_onset_ratio: float = option(
        1.0,
        "equal intensity: P_1·SD(T_1)/x_c of every record (default 1)",
        kind="positive",
        valid=Range(0, 100, low_open=True),
    )
    # What goes in and out (issue 25): records, filters computed from the records, code targets.
    verticals: bool = option(False, "keep vertical components (default: horizontals only)")
    exclude_unmatched: Unmatched = option(
        "error", "an --exclude entry matching nothing: error or warn (default: %(default)s)"
    )
    pgv_min_m_s: float | None = option(None, "PGV at least [m/s]", valid=Range(0))
    pgv_max_m_s: float | None = option(None, "PGV at most [m/s]", valid=Range(0))
    psa_t1_min_g: float | None = option(None, "PSA(T_1, 5 %) at least [g]", valid=Range(0))
    psa_t1_max_g: float | None = option(None, "PSA(T_1, 5 %) at most [g]", valid=Range(0))
    arias_min_m_s: float | None = option(None, "Arias intensity at least [m/s]", valid=Range(0))
    arias_max_m_s: float | None = option(None, "Arias intensity at most [m/s]", valid=Range(0))
    pair_spectrum: PairSpectrum = option(
        "rotd50", "one spectrum of a record's two horizontals (default: %(default)s)"
    )
    target_t_l_s: float | None = option(
        None, "ASCE 7-22 two-period: long-period transition T_L [s]", valid=Range(0, low_open=True)
    )
    target_code: Code | None = option(
        None, "the code whose suite rule checks --target-csv (asce7-22: multi-period)"
    )
    target_ec8: Ec8Type | None = option(None, "Eurocode 8 elastic spectrum type")
    target_ground: Ec8Ground | None = option(None, "Eurocode 8 ground type")
    target_ag_g: float | None = option(
        None, "Eurocode 8 reference a_gR [g]", valid=Range(0, low_open=True)
    )
    target_importance: float = option(
        1.0, "Eurocode 8 importance factor γ_I (default 1)", valid=Range(0, low_open=True)
    )
    target_damping: float = option(
        0.05, "damping ratio of the target and the code check (default 0.05)",
        valid=Range(0, 1, low_open=True, high_open=True),
    )  # fmt: skip
    # The ranking: its intensity, its prefilter and the scores it reports (the ranking's own
    # block; docs/selection.md, "Ranking by the simulated response").
    rank_onset_ratio: float | None = option(
        None,
        "rank at equal PSA(T_1): P_1·SD(T_1, xi_1) = this multiple of x_c (default: the "
        "records as used)",
        kind="positive",
        metavar="R",
        valid=Range(0.0, 20.0, low_open=True),
    )
    rank_psa_t1_g: float | None = option(
        None,
        "rank at equal PSA(T_1) of this many g, 5 % damping (default: the records as used)",
        kind="positive",
        metavar="G",
        valid=Range(0.0, 20.0, low_open=True),
    )
    prefilter: str = option(
        "auto",
        "simulate only the best prefilter_k by this tier: auto (when over the budget), none, "
        "or a tier (default: %(default)s)",
        choices=PREFILTER_CHOICES,
    )
    prefilter_k: int | None = option(
        None,
        "candidates the prefilter keeps (≥ n)",
        kind="positive_int",
        metavar="K",
        valid=Range(1.0),
    )
    exact_budget_s: float = option(
        1200.0,
        "auto prefilter: simulate every candidate while their estimated CPU time on one core "
        "is under this [s] (default: %(default)s, 10 min on 2 cores)",
        kind="positive",
        metavar="S",
        valid=Range(0.0, low_open=True),
    )
    scores: tuple[str, ...] = option(
        (), "also compute and compare this tier (repeat)", kind="repeated", metavar="TIER"
    )

    def __post_init__(self) -> None:
        check_fields(self)
        self._check_inputs_and_targets()

        def bad(name: str, expected: str) -> InputError:
            return InputError(f"{name} = {getattr(self, name)!r}, expected {expected}")

        if not (isinstance(self.n, int) and not isinstance(self.n, bool) and self.n >= 1):
            raise bad("n", "an integer ≥ 1")
        if self.unit not in UNITS:
            raise bad("unit", f"one of {UNITS}")
        if self.rank_by not in RANK_BY_CHOICES:
            raise bad("rank_by", f"one of {RANK_BY_CHOICES}")
        if self.scale not in SCALE_POLICIES:
            raise bad("scale", f"one of {SCALE_POLICIES}")
        if self.distance_metric not in DISTANCE_METRICS:
            raise bad("distance_metric", f"one of {DISTANCE_METRICS}")
        for name in ("n_bootstrap", "seed"):
            value = getattr(self, name)
            if not (isinstance(value, int) and not isinstance(value, bool) and value >= 0):
                raise bad(name, "an integer ≥ 0")
        if not (isinstance(self.n_levels, int) and self.n_levels >= 2):
            raise bad("n_levels", "an integer ≥ 2")
        for name in ("max_per_event", "max_per_station"):
            value = getattr(self, name)
            if value is not None and not (isinstance(value, int) and value >= 1):
                raise bad(name, "an integer ≥ 1 or None")
        for f in fields(self):
            value = getattr(self, f.name)
            if isinstance(value, float) and not math.isfinite(value):
                raise bad(f.name, "a finite number")
        for name in ("spectral_weight",):
            if getattr(self, name) < 0:
                raise bad(name, "≥ 0")
        if self.design_displacement_m is not None and not self.design_displacement_m > 0:
            raise bad("design_displacement_m", "a positive number or None")
        if not 0 < self.scale_min <= 1 <= self.scale_max:
            raise InputError(
                f"scale_min = {self.scale_min}, scale_max = {self.scale_max}, expected "
                "0 < scale_min ≤ 1 ≤ scale_max"
            )
        if (self.target_s_ds_g is None) != (self.target_s_d1_g is None):
            raise InputError(
                "target_s_ds_g and target_s_d1_g: only one given, expected both or neither"
            )
        if self.target_periods_s is not None:
            low, high = self.target_periods_s
            if not 0 < low < high:
                raise bad("target_periods_s", "(low, high) with 0 < low < high")
        self._check_ranking()
        if self.scale == "target-mse" and not self.has_target:
            raise InputError(
                "scale = 'target-mse' without a target spectrum, expected target_s_ds_g and "
                "target_s_d1_g, or target_csv"
            )
        self._check_applies()

    def _check_applies(self) -> None:
        """An option set away from its default where nothing reads it is an error, not a silent
        no-op (tried: each of these ran and changed nothing)."""
        defaults = {f.name: f.default for f in fields(self)}

        def given(name: str) -> bool:
            return bool(getattr(self, name) != defaults[name])

        needs = [
            ("confirm_onset_ratio", self.confirm, "confirm = true (--confirm): the intensity "
             "of the confirmation"),
            ("spectral_weight", self.has_target, "a target spectrum: it weighs the set's misfit "
             "to the target"),
            ("target_periods_s", self.has_target, "a target spectrum: the misfit's periods"),
            ("target_damping", self.has_target, "a target spectrum"),
            ("target_importance", self.target_ec8 is not None, "a Eurocode 8 target "
             "(target_ec8)"),
            ("distance_metric", self.distance_min_km is not None
             or self.distance_max_km is not None, "a distance filter (distance_min_km or "
             "distance_max_km)"),
            ("scale_min", self.scale != "none", "a scaling policy (scale = 'psa-at-t1' or "
             "'target-mse'): the records as recorded have scale factor 1"),
            ("scale_max", self.scale != "none", "a scaling policy (scale = 'psa-at-t1' or "
             "'target-mse'): the records as recorded have scale factor 1"),
            ("seed", self.confirm or (self.n_bootstrap > 0 and ranks_by_fit(self.rank_by)),
             "confirm = true (--confirm) or the bootstrap of a ranking by a fitted score "
             f"({', '.join(FIT_TIERS)}; n_bootstrap > 0): it seeds their draws"),
            ("n_bootstrap", self.n_bootstrap == 0 or ranks_by_fit(self.rank_by),
             f"a ranking by a fitted score ({', '.join(FIT_TIERS)}): the bootstrap redraws "
             f"the fits, which {self.rank_by} does not read"),
            ("x_star_fraction", self.a_max_m is None and self.design_displacement_m is None,
             "no a_max_m and no design displacement: A_max is fraction·x* only without them"),
            ("exclude_unmatched", bool(self.exclude), "exclude entries: it says what an entry "
             "matching nothing does"),
            ("exact_budget_s", self.rank_by == SIMULATED_RESPONSE and self.prefilter == "auto",
             f"rank_by = {SIMULATED_RESPONSE!r} with prefilter = 'auto': the budget decides "
             "whether the simulation is prefiltered"),
            ("pair_spectrum", self.unit == "record", "unit = 'record' (--unit record): it makes "
             "one spectrum of a record's two horizontals"),
        ]  # fmt: skip
        for name, applies, expected in needs:
            if given(name) and not applies:
                raise InputError(
                    f"{name} = {getattr(self, name)!r} does nothing here, expected it only with "
                    f"{expected}",
                    key=name,
                )

    def _check_ranking(self) -> None:
        """The ranking's options: their ranges, then the rules between them."""
        check_fields(self)
        object.__setattr__(self, "scores", tuple(str(name) for name in self.scores))
        if self.rank_onset_ratio is not None and self.rank_psa_t1_g is not None:
            raise InputError(
                "rank_onset_ratio and rank_psa_t1_g both given, expected at most one ranking "
                "intensity"
            )
        if self.prefilter not in PREFILTER_CHOICES:
            raise InputError(
                f"prefilter = {self.prefilter!r}, expected one of {', '.join(PREFILTER_CHOICES)}",
                key="prefilter",
            )
        if self.rank_by != SIMULATED_RESPONSE and (
            self.prefilter != "auto" or self.prefilter_k is not None
        ):
            raise InputError(
                f"prefilter options with rank_by = {self.rank_by!r}, expected them only with "
                f"rank_by = {SIMULATED_RESPONSE!r} (a tier ranks alone, nothing to prefilter)",
                key="prefilter",
            )
        if self.prefilter_k is not None:
            if self.prefilter_k < self.n:
                raise InputError(
                    f"prefilter_k = {self.prefilter_k} < n = {self.n}, expected at least n",
                    key="prefilter_k",
                )
            if self.prefilter == "none":
                raise InputError(
                    "prefilter_k given with prefilter = 'none', expected a tier or 'auto'",
                    key="prefilter_k",
                )
        unknown = [name for name in self.scores if name not in TIERS]
        if unknown:
            raise InputError(
                f"scores = {list(self.scores)}, expected names among {', '.join(TIERS)}",
                key="scores",
            )

    @property
    def has_target(self) -> bool:
        """Whether a target spectrum is given."""
        return (
            self.target_csv is not None
            or self.target_s_ds_g is not None
            or self.target_ec8 is not None
        )

    def amplitude_range(self, name: str) -> tuple[float | None, float | None]:
        """(low, high) of the amplitude filter ``name`` (``pga``, ``pgv``, ``psa_t1``,
        ``d5_95``, ``arias``)."""
        suffix = {"pga": "_g", "pgv": "_m_s", "psa_t1": "_g", "d5_95": "_s", "arias": "_m_s"}
        unit = suffix[name]
        return getattr(self, f"{name}_min{unit}"), getattr(self, f"{name}_max{unit}")

    def _check_inputs_and_targets(self) -> None:
        """The rules between the fields of the inputs and targets block."""
        if self.verticals and self.unit == "record":
            raise InputError(
                "verticals = true with unit = 'record', expected unit = 'component' (a record "
                "is its two horizontal components)"
            )
        if self.exclude_unmatched not in UNMATCHED:
            raise InputError(
                f"exclude_unmatched = {self.exclude_unmatched!r}, expected {UNMATCHED}"
            )
        if self.pair_spectrum not in PAIR_SPECTRA:
            raise InputError(f"pair_spectrum = {self.pair_spectrum!r}, expected {PAIR_SPECTRA}")
        for name in ("pgv", "psa_t1", "arias", "pga", "d5_95"):
            low, high = self.amplitude_range(name)
            if low is not None and high is not None and not low <= high:
                raise InputError(f"{name} range {low} to {high}, expected min ≤ max")
        ec8 = (self.target_ec8, self.target_ground, self.target_ag_g)
        if any(v is not None for v in ec8) and any(v is None for v in ec8):
            raise InputError(
                "target_ec8, target_ground and target_ag_g: only some given, expected all three "
                "for a Eurocode 8 spectrum"
            )
        if self.target_ec8 is not None and self.target_ec8 not in EC8_TYPES:
            raise InputError(f"target_ec8 = {self.target_ec8!r}, expected one of {EC8_TYPES}")
        if self.target_ground is not None and self.target_ground not in EC8_GROUNDS:
            raise InputError(
                f"target_ground = {self.target_ground!r}, expected one of {EC8_GROUNDS}"
            )
        kinds = [
            name
            for name, given in (
                ("target_csv", self.target_csv is not None),
                ("target_s_ds_g", self.target_s_ds_g is not None),
                ("target_ec8", self.target_ec8 is not None),
            )
            if given
        ]
        if len(kinds) > 1:
            raise InputError(f"{' and '.join(kinds)} both given, expected one target spectrum")
        if self.target_t_l_s is not None and self.target_s_ds_g is None:
            raise InputError(
                "target_t_l_s without target_s_ds_g/target_s_d1_g, expected T_L only for the "
                "ASCE 7-22 two-period spectrum"
            )
        if self.target_code is not None:
            if self.target_code not in CODES:
                raise InputError(f"target_code = {self.target_code!r}, expected one of {CODES}")
            if self.target_csv is None:
                raise InputError(
                    f"target_code = {self.target_code!r} without target_csv, expected it only "
                    "for a tabulated target (the built-in spectra name their code)"
                )
        if self.target_damping != 0.05 and (
            self.target_s_ds_g is not None or self.target_code == "asce7-22"
        ):
            raise InputError(
                f"target_damping = {self.target_damping} with an ASCE 7-22 spectrum, expected "
                "0.05 (its spectra are for 5 % damping)"
            )
        if self.target_damping != 0.05 and (self.scale != "none" or self.spectral_weight > 0):
            raise InputError(
                f"target_damping = {self.target_damping} with scale = {self.scale!r} and "
                f"spectral_weight = {self.spectral_weight}, expected target_damping = 0.05, or "
                "scale = 'none' and spectral_weight = 0 (scaling and the misfit compare the "
                "records' 5 % spectra)"
            )

    def to_dict(self) -> dict[str, Any]:
        """Plain dictionary (TOML/JSON ready: tuples become lists, None stays None)."""
        data = asdict(self)
        data["exclude"] = list(self.exclude)
        data["scores"] = list(self.scores)
        if self.target_periods_s is not None:
            data["target_periods_s"] = list(self.target_periods_s)
        return data

    @classmethod
    def from_dict(cls, data: dict[str, Any], where: str = "selection options") -> SelectionOptions:
        """Inverse of :meth:`to_dict`, e.g. a ``[selection]`` TOML table; unknown keys are an
        error; ints are accepted where floats are expected."""
        import difflib

        known = {f.name: f for f in fields(cls)}
        unknown = sorted(set(data) - set(known))
        if unknown:
            # each with its nearest name (the list of some 60 names said nothing of the typo)
            named = []
            for key in unknown:
                close = difflib.get_close_matches(key, list(known), n=1, cutoff=0.6)
                named.append(f"{key!r}" + (f" (did you mean {close[0]!r}?)" if close else ""))
            raise InputError(
                f"{where}: unknown key{'s' * (len(unknown) > 1)} {', '.join(named)}, expected "
                "the options of docs/selection.md (`stepframe select --help` lists them)",
                key=unknown[0],
            )
        values = dict(data)
        if "exclude" in values:
            values["exclude"] = tuple(str(v) for v in values["exclude"])
        if "scores" in values:
            values["scores"] = tuple(str(v) for v in values["scores"])
        if values.get("target_periods_s") is not None:
            pair = tuple(float(v) for v in values["target_periods_s"])
            if len(pair) != 2:
                raise InputError(f"{where}: target_periods_s = {pair}, expected [low, high]")
            values["target_periods_s"] = pair
        for name, f in known.items():
            value = values.get(name)
            if "float" in str(f.type) and isinstance(value, int) and not isinstance(value, bool):
                values[name] = float(value)
        return cls(**values)


def selection_options(path: str | None, overrides: dict[str, Any]) -> SelectionOptions:
    """The ``[selection]`` table of the TOML file ``path`` (if given) with ``overrides`` on top.

    Parameters
    ----------
    path
        A TOML file with a ``[selection]`` table (:meth:`SelectionOptions.from_dict` keys), or
        None.
    overrides
        Values that replace the file's (the command line's options, only those given).
    """
    from stepframe.core.io import read_toml

    values: dict[str, Any] = {}
    if path:
        data, _ = read_toml(path, "a TOML file with a [selection] table")
        table = data.get("selection")
        if not isinstance(table, dict):
            raise InputError("no [selection] table, expected one", path)
        values.update(table)
    values.update(overrides)
    return SelectionOptions.from_dict(values, where=path or "selection options")
