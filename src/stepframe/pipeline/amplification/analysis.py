"""What a site amplification is given: each option declared once (light: no numpy at import).

The command line (``stochastic amplify``, ``report amplification``), the library
(:func:`~stepframe.pipeline.amplification.study.amplify_study`,
:func:`~stepframe.pipeline.amplification.report.write_amplification_report`) and the workflow's
``[site]``, ``[amplification]`` and ``[amplification_report]`` tables all take their options from
the dataclasses below, so each option has one name, one default and one check
(:func:`stepframe.core.options.check_fields`):

- :class:`SiteParameters`: the site's seven Beck-Papadimitriou parameters, in Hz and s;
- :class:`AmplificationAnalysis`: the oscillator's damping, the time grid, the f0 grid, the
  Monte Carlo check and the frame-driven run's intensity;
- :class:`AmplifyOptions` (``stochastic amplify``), :class:`AmplificationOptions` (a report's
  choices: the site's name, the frame's δ*, the band from the parameters' standard errors, the
  search for maxima beyond the grid) and :class:`AmplificationReportOptions` (``report
  amplification``) built from them.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal

from stepframe.core.options import SEEDS, Range, check_fields, option

if TYPE_CHECKING:
    from stepframe.pipeline.amplification.site import SiteStatistic
    from stepframe.stochastic.features import TimeOrigin
    from stepframe.stochastic.model import AlphaReading

#: The site's parameters, in the order eqs. 6.10-6.11 take them.
SITE_PARAMETERS = ("fp_hz", "fs_hz", "fr_hz", "xi_p", "xi_r", "t_max_s", "t_dur_s")

#: The oscillator damping when neither the user nor a frame gives one.
DEFAULT_XI0 = 0.05

#: Monte Carlo motions per check frequency in a report when not given (a single f0: none).
REPORT_MONTE_CARLO = 50

#: Frequencies of a site and of an oscillator [Hz]: 100 Hz is past any accelerograph's band
#: and any structure's small-amplitude frequency.
_HERTZ = Range(0, 100, low_open=True)
#: Bandwidth ratios ξ_p, ξ_r: from a nearly pure tone to a spectrum ten times wider than its
#: centre (the paper's site: 0.096 and 0.655).
_BANDWIDTH = Range(1e-3, 10)
#: Times of a site's envelope [s]: up to 10⁶ s, the longest record the features accept.
_SECONDS = Range(0, 1e6, low_open=True)
#: Lengths of a frame [m] (a design displacement).
_METRES = Range(0, 100, low_open=True)
#: Parameter sets of the Monte Carlo band when not given (scrambled Sobol points): at N = 512 the
#: band's edges move between seeds by at most 7.3 % of its half-width (median 3.4 %) for RSN
#: 8883's site and the example catalogue's; 256 sets: 12 % (docs/benchmarks.md, "Issue 30").
BAND_SAMPLES = 512

#: How the band from the parameters' standard errors is computed
#: (:func:`stepframe.pipeline.amplification.band.parameter_band`).
BandMethod = Literal["monte-carlo", "delta", "none"]


@dataclass(frozen=True)
class SiteParameters:
    """The site's Beck-Papadimitriou parameters (eqs. 6.10-6.11), each optional here: the
    function that takes them says which it needs."""

    fp_hz: float | None = option(
        None,
        "P-wave dominant f_p [Hz] (omega_p_rad_s/2π; `stochastic fit` prints both)",
        kind="positive",
        metavar="F",
        valid=_HERTZ,
    )
    fs_hz: float | None = option(
        None, "S-wave dominant f_s [Hz]", kind="positive", metavar="F", valid=_HERTZ
    )
    fr_hz: float | None = option(
        None, "surface-wave f_r [Hz]", kind="positive", metavar="F", valid=_HERTZ
    )
    xi_p: float | None = option(
        None, "bandwidth ratio ξ_p", kind="positive", metavar="X", valid=_BANDWIDTH
    )
    xi_r: float | None = option(
        None, "bandwidth ratio ξ_r", kind="positive", metavar="X", valid=_BANDWIDTH
    )
    t_max_s: float | None = option(
        None,
        "time of peak I_g [s] (`stochastic fit` prints t_max_s; the paper's site: 5); not "
        "needed for eqs. 6.18-6.19 alone with --alpha-at-tmax paper",
        kind="positive",
        metavar="T",
        valid=_SECONDS,
    )
    t_dur_s: float | None = option(
        None,
        "strong duration [s] (`stochastic fit` prints t_dur_s; the paper's site: 20)",
        kind="positive",
        metavar="T",
        valid=_SECONDS,
    )

    @property
    def parameters(self) -> dict[str, float | None]:
        """:data:`SITE_PARAMETERS` → value (None: not given)."""
        return {name: getattr(self, name) for name in SITE_PARAMETERS}


@dataclass(frozen=True)
class SiteCombination:
    """How the fits of a site's records are combined into one site
    (:func:`stepframe.pipeline.amplification.site.site_from_features`)."""

    statistic: SiteStatistic = option(
        "median",
        "with records: how the components' fits are combined (median, the default; mean; "
        "inverse-variance)",
        choices=("median", "mean", "inverse-variance"),
    )
    plausible_only: bool = option(
        True, "with records: only components that pass the plausibility checks"
    )


@dataclass(frozen=True)
class AmplificationAnalysis:
    """How the amplification is computed: the oscillator, the grids and the checks."""

    alpha_reading: AlphaReading = option(
        "eq-6-11",
        "α_g ramp ends at t_dur (eq. 6.11 as printed, default) or at t_max (the paper)",
        choices=("eq-6-11", "paper"),
        flag="--alpha-at-tmax",
    )
    xi0: float | None = option(
        None,
        f"oscillator damping ratio ξ_0 (fraction; default {DEFAULT_XI0}, or the frame's xi_1 "
        "for a frame's own oscillator)",
        kind="float",
        metavar="X",
        valid=Range(0, 1, low_open=True, high_open=True),
    )
    n_steps: int = option(
        4000,
        "time steps of the mean-square (covariance) integration (default %(default)s)",
        kind="int",
        metavar="N",
        valid=Range(100, 1_000_000),
    )
    f_min_hz: float = option(
        0.1, "lowest f0 of the curve [Hz]", kind="positive", metavar="F", valid=_HERTZ
    )
    f_max_hz: float = option(
        10.0, "highest f0 of the curve [Hz]", kind="positive", metavar="F", valid=_HERTZ
    )
    n_frequencies: int = option(
        60, "f0 values of the curve, log-spaced", kind="int", metavar="N", valid=Range(2, 10_000)
    )
    monte_carlo: int | None = option(
        None,
        "synthetic motions per Monte Carlo check frequency (0: none; default "
        f"{REPORT_MONTE_CARLO} in a report, none for one f0)",
        kind="int",
        metavar="N",
        valid=Range(2, 100_000, also=(0,)),
    )
    seed: int = option(1, "Monte Carlo seed (default 1)", kind="int", valid=SEEDS)
    peak_intensity_m_s2: float | None = option(
        None,
        "peak I_g [m/s²] of a frame-driven run (default: the records', else 1); only with a "
        "frame (an error without)",
        kind="positive",
        metavar="I",
        valid=Range(0, 100, low_open=True),  # ten times the largest records' RMS
    )

    def __post_init__(self) -> None:
        check_fields(self)
        if not self.f_min_hz < self.f_max_hz:
            from stepframe.errors import InputError

            raise InputError(
                f"f_min_hz = {self.f_min_hz:g}, f_max_hz = {self.f_max_hz:g}, expected "
                "f_min_hz < f_max_hz",
                key="f_min_hz",
            )
        from stepframe.stochastic.mean_square import check_mean_square_memory

        # The curve's oscillators over the grid, refused before any work (a workflow at its
        # file's line); a single f0 or a frame is one oscillator and fits whenever this does.
        check_mean_square_memory(self.n_frequencies, self.n_steps)

    @property
    def xi0_or_default(self) -> float:
        """ξ_0 for an oscillator given by its frequency (:data:`DEFAULT_XI0` when not given)."""
        return DEFAULT_XI0 if self.xi0 is None else self.xi0

    @property
    def report_monte_carlo(self) -> int:
        """Monte Carlo motions of a report (:data:`REPORT_MONTE_CARLO` when not given)."""
        return REPORT_MONTE_CARLO if self.monte_carlo is None else self.monte_carlo


@dataclass(frozen=True)
class AmplifyOptions(SiteParameters, AmplificationAnalysis):
    """The site (its parameters, or a record), the oscillator (f0, or a frame file) and the
    analysis of ``stepframe stochastic amplify``."""

    record: str | None = option(None, "estimate the site from this record (one)", metavar="FILE")
    t0: TimeOrigin = option(
        "auto",
        "with --record: time origin, auto (default: reliable P pick, else record start), "
        "start or p-pick",
        choices=("auto", "start", "p-pick"),
    )
    f0_hz: float | None = option(
        None, "small-amplitude f0 [Hz]", kind="positive", metavar="F", valid=_HERTZ
    )
    frame: str | None = option(None, "frame file: ω(t) = 2π/T(A)", metavar="FRAME.toml")


@dataclass(frozen=True)
class AmplificationOptions(AmplificationAnalysis):
    """The choices of an amplification report beyond the site and the frame."""

    site_name: str | None = option(None, "named in titles", metavar="NAME")
    delta_star_m: float | None = option(
        None,
        "the frame's design displacement δ* [m] (stepframe structure design)",
        kind="positive",
        metavar="D",
        valid=_METRES,
    )
    t0: TimeOrigin = option(
        "auto",
        "with --records: time origin, the picked P onset when reliable, else the record "
        "start (auto, the default), or one of them",
        choices=("auto", "start", "p-pick"),
    )
    band: BandMethod = option(
        "monte-carlo",
        "band of the response amplification from the site parameters' standard errors: "
        "monte-carlo (the default: --band-samples parameter sets, one curve each), delta (the "
        "delta method on ln A, 11 curves: cheap, blind to the curve's curvature) or none; a "
        "site given by its parameters has no standard errors, so no band",
        choices=("monte-carlo", "delta", "none"),
    )
    band_samples: int | None = option(
        None,
        f"with --band monte-carlo: parameter sets drawn (default {BAND_SAMPLES})",
        kind="int",
        metavar="N",
        valid=Range(20, 100_000),  # one curve each: 10⁵ curves is hours of CPU
    )
    grid_only: bool = option(
        False,
        "keep the curve on the f0 grid: where the response amplification still rises at an "
        "edge, say so ('at the edge, rising') instead of extending the grid past the edge (up "
        "to a decade) until the curve turns",
    )

    def __post_init__(self) -> None:
        super().__post_init__()
        from stepframe.errors import InputError

        if self.band_samples is not None and self.band != "monte-carlo":
            raise InputError(
                f"band_samples = {self.band_samples} with band = {self.band!r}, expected band = "
                "'monte-carlo' with it (only the Monte Carlo band draws samples)",
                key="band_samples",
            )
        if self.seed != AmplificationOptions.__dataclass_fields__["seed"].default and (
            self.report_monte_carlo == 0
        ):
            raise InputError(
                f"seed = {self.seed} with monte_carlo = 0, expected it only with Monte Carlo "
                "motions (it seeds them)",
                key="seed",
            )

    @property
    def band_samples_or_default(self) -> int:
        """Parameter sets of a Monte Carlo band (:data:`BAND_SAMPLES` when not given)."""
        return BAND_SAMPLES if self.band_samples is None else self.band_samples


def band_without_errors(options: AmplificationOptions) -> str | None:
    """The band option given that a site from its parameters cannot use (it has no standard
    errors, so no band): ``band`` (delta), ``band_samples``, or None. The one rule of
    ``report amplification`` and a workflow's ``[amplification_report]``; ``band = "none"``
    asks for what such a site has, and is accepted."""
    if options.band == "delta":
        return "band"
    if options.band_samples is not None:
        return "band_samples"
    return None


@dataclass(frozen=True)
class AmplificationReportOptions(SiteParameters, SiteCombination, AmplificationOptions):
    """The site (its parameters or a folder of its records), the optional frame and the
    analysis of an amplification report (``stepframe report amplification``)."""

    records: str | None = option(None, "a folder of the site's record files", metavar="DIR")
    record_format: str | None = option(
        None, "with --records: file format if not sniffed", metavar="NAME", flag="--format"
    )
    units: str | None = option(None, "with --records: units if the files lack them", metavar="UNIT")
    frame: str | None = option(None, "frame file: band and frame-driven run", metavar="FRAME.toml")
