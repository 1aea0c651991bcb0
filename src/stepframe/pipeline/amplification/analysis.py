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
  choices) and :class:`AmplificationReportOptions` (``report amplification``) built from them.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from stepframe.core.options import Range, check_fields, option

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

_POSITIVE = Range(0, low_open=True)


@dataclass(frozen=True)
class SiteParameters:
    """The site's Beck-Papadimitriou parameters (eqs. 6.10-6.11), each optional here: the
    function that takes them says which it needs."""

    fp_hz: float | None = option(
        None,
        "P-wave dominant f_p [Hz] (omega_p_rad_s/2π; `stochastic fit` prints both)",
        kind="positive",
        metavar="F",
        valid=_POSITIVE,
    )
    fs_hz: float | None = option(
        None, "S-wave dominant f_s [Hz]", kind="positive", metavar="F", valid=_POSITIVE
    )
    fr_hz: float | None = option(
        None, "surface-wave f_r [Hz]", kind="positive", metavar="F", valid=_POSITIVE
    )
    xi_p: float | None = option(
        None, "bandwidth ratio ξ_p", kind="positive", metavar="X", valid=_POSITIVE
    )
    xi_r: float | None = option(
        None, "bandwidth ratio ξ_r", kind="positive", metavar="X", valid=_POSITIVE
    )
    t_max_s: float | None = option(
        None,
        "time of peak I_g [s] (`stochastic fit` prints t_max_s; the paper's site: 5); not "
        "needed for eqs. 6.18-6.19 alone with --alpha-at-tmax paper",
        kind="positive",
        metavar="T",
        valid=_POSITIVE,
    )
    t_dur_s: float | None = option(
        None,
        "strong duration [s] (`stochastic fit` prints t_dur_s; the paper's site: 20)",
        kind="positive",
        metavar="T",
        valid=_POSITIVE,
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
        valid=Range(100),
    )
    f_min_hz: float = option(
        0.1, "lowest f0 of the curve [Hz]", kind="positive", metavar="F", valid=_POSITIVE
    )
    f_max_hz: float = option(
        10.0, "highest f0 of the curve [Hz]", kind="positive", metavar="F", valid=_POSITIVE
    )
    n_frequencies: int = option(
        60, "f0 values of the curve, log-spaced", kind="int", metavar="N", valid=Range(2)
    )
    monte_carlo: int | None = option(
        None,
        "synthetic motions per Monte Carlo check frequency (0: none; default "
        f"{REPORT_MONTE_CARLO} in a report, none for one f0)",
        kind="int",
        metavar="N",
        valid=Range(2, also=(0,)),
    )
    seed: int = option(1, "Monte Carlo seed (default 1)", kind="int", valid=Range(0))
    peak_intensity_m_s2: float | None = option(
        None,
        "peak I_g [m/s²] of a frame-driven run (default: the records', else 1); matters only "
        "for a frame",
        kind="positive",
        metavar="I",
        valid=_POSITIVE,
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
        None, "small-amplitude f0 [Hz]", kind="positive", metavar="F", valid=_POSITIVE
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
        valid=_POSITIVE,
    )
    t0: TimeOrigin = option(
        "auto",
        "with --records: time origin, the picked P onset when reliable, else the record "
        "start (auto, the default), or one of them",
        choices=("auto", "start", "p-pick"),
    )


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
