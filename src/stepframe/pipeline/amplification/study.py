"""One site's amplification for one oscillator, from what a user gives (``stochastic amplify``).

The site is given by its parameters (all seven, or under the paper's reading the five without
the envelope times, for eqs. 6.18-6.19 alone), by a record file, or by a component of the
embedded example catalogue; the oscillator by its small-amplitude frequency or by a frame file.
:func:`amplify_study` picks the route, refuses mixed or incomplete inputs with one line saying
what to give, and runs :func:`stepframe.pipeline.amplification.amplify.amplify` or
:func:`~stepframe.pipeline.amplification.amplify.spectral_ratios`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from stepframe.core.options import option
from stepframe.errors import InputError
from stepframe.pipeline.amplification.site import SITE_PARAMETERS
from stepframe.records.read_options import RecordSource

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from stepframe.pipeline.amplification.amplify import (
        AmplificationResult,
        Oscillator,
        SpectralRatios,
    )
    from stepframe.pipeline.amplification.site import SiteModel
    from stepframe.stochastic.features import TimeOrigin
    from stepframe.stochastic.model import AlphaReading

#: The site parameters that are the envelope's times.
ENVELOPE_TIMES = ("t_max_s", "t_dur_s")

#: Where the envelope's times of a site can be found (said in the errors that ask for them).
_TIMES_HINT = (
    "`stepframe stochastic fit` prints t_max_s and t_dur_s of a record of the site, the paper's "
    "site has 5 and 20 s"
)


@dataclass(frozen=True)
class AmplifyOptions:
    """The site (its parameters, or a record), the oscillator (f0, or a frame file) and the
    analysis of ``stepframe stochastic amplify``."""

    fp_hz: float | None = option(
        None,
        "P-wave dominant f_p [Hz] (omega_p_rad_s/2π; `stochastic fit` prints both)",
        kind="positive",
        metavar="F",
    )
    fs_hz: float | None = option(None, "S-wave dominant f_s [Hz]", kind="positive", metavar="F")
    fr_hz: float | None = option(None, "surface-wave f_r [Hz]", kind="positive", metavar="F")
    xi_p: float | None = option(None, "bandwidth ratio ξ_p", kind="positive", metavar="X")
    xi_r: float | None = option(None, "bandwidth ratio ξ_r", kind="positive", metavar="X")
    t_max_s: float | None = option(
        None,
        "time of peak I_g [s] (`stochastic fit` prints t_max_s; the paper's site: 5); not "
        "needed for eqs. 6.18-6.19 alone with --alpha-at-tmax paper",
        kind="positive",
        metavar="T",
    )
    t_dur_s: float | None = option(
        None,
        "strong duration [s] (`stochastic fit` prints t_dur_s; the paper's site: 20)",
        kind="positive",
        metavar="T",
    )
    record: str | None = option(None, "estimate the site from this record (one)", metavar="FILE")
    t0: TimeOrigin = option(
        "auto",
        "with --record: time origin, auto (default: reliable P pick, else record start), "
        "start or p-pick",
        choices=("auto", "start", "p-pick"),
    )
    f0_hz: float | None = option(None, "small-amplitude f0 [Hz]", kind="positive", metavar="F")
    frame: str | None = option(None, "frame file: ω(t) = 2π/T(A)", metavar="FRAME.toml")
    xi0: float | None = option(
        None,
        "damping ratio at f0 (fraction; default 0.05, or the frame's xi_1 with --frame)",
        kind="float",
        metavar="X",
    )
    alpha_reading: AlphaReading = option(
        "eq-6-11",
        "α_g ramp ends at t_dur (eq. 6.11 as printed, default) or at t_max (the paper)",
        choices=("eq-6-11", "paper"),
        flag="--alpha-at-tmax",
    )
    peak_intensity_m_s2: float | None = option(
        None,
        "max I_g [m/s²] (default 1, or the record's); matters only with --frame",
        kind="positive",
        metavar="I",
    )
    monte_carlo: int = option(0, "confirm with N synthetic motions", kind="int", metavar="N")
    seed: int | None = option(None, "seed of the Monte Carlo motions", kind="int")
    n_steps: int = option(4000, "time steps (default 4000)", kind="int", metavar="N")

    @property
    def parameters(self) -> dict[str, float | None]:
        """:data:`~stepframe.pipeline.amplification.site.SITE_PARAMETERS` → value (None: none)."""
        return {name: getattr(self, name) for name in SITE_PARAMETERS}


@dataclass(frozen=True)
class AmplifyStudy:
    """A site's amplification for one oscillator, with what the figure needs.

    Attributes
    ----------
    result
        :class:`AmplificationResult`, or :class:`SpectralRatios` (no envelope times).
    site
        The site (None on the envelope-free route).
    oscillator
        The oscillator.
    n_steps
        Time steps of the analysis grid (the figure's curve uses the same).
    """

    result: AmplificationResult | SpectralRatios
    site: SiteModel | None
    oscillator: Oscillator
    n_steps: int

    def to_dict(self) -> dict[str, Any]:
        """The result's JSON-ready form."""
        return self.result.to_dict()

    def describe(self) -> str:
        """The result as text."""
        return self.result.describe()

    def figure(self) -> Figure:
        """Eq. 6.18 and both response amplifications over 0.1-10 Hz, this f0 marked."""
        import numpy as np

        from stepframe.pipeline.amplification.amplify import (
            AmplificationResult,
            amplification_curve,
        )
        from stepframe.stochastic.plots import amplification_figure

        result = self.result
        if self.site is None or not isinstance(result, AmplificationResult):
            raise InputError("a figure without the envelope's times, expected both times")
        curve = amplification_curve(
            self.site, np.geomspace(0.1, 10.0, 60), self.oscillator.xi0, n_steps=self.n_steps
        )
        return amplification_figure(
            curve,
            f0_hz=result.f0_hz,
            at_f0=result.response_amplification_vs_fixed,
            lower_bound=result.lower_bound,
            site=str(self.site.source.get("record") or "site from parameters"),
        )


def amplify_study(
    options: AmplifyOptions,
    *,
    source: RecordSource | None = None,
    figure: bool = False,
) -> AmplifyStudy:
    """Pick the site and the oscillator from the inputs given, and compute the amplification.

    Parameters
    ----------
    options
        :class:`AmplifyOptions`: the site's parameters (all seven; or, with
        ``alpha_reading="paper"``, the five without the envelope times for eqs. 6.18-6.19
        alone) or a ``record`` to fit, exactly one of ``f0_hz`` [Hz] and ``frame`` (ω(t) =
        2π/T(A)), the damping and the analysis (as
        :func:`~stepframe.pipeline.amplification.amplify.amplify`).
    source
        The read options of ``options.record``; or, when it names an example catalogue, the
        site from that catalogue's one component (chosen by its ``component``).
    figure
        Whether a figure will be asked for (it needs the envelope's times).
    """
    from stepframe.pipeline.amplification import amplify as stage
    from stepframe.pipeline.amplification.site import site_from_options, site_from_record

    if (options.f0_hz is None) == (options.frame is None):
        raise InputError("expected exactly one of --f0-hz F and --frame FRAME.toml")
    parameters = options.parameters
    given = [name for name in SITE_PARAMETERS if parameters[name] is not None]
    record, alpha_reading = options.record, options.alpha_reading
    site: SiteModel | None = None
    source = source or RecordSource()
    if source.example is not None:
        if given or record is not None:
            raise InputError(
                f"--example with {'--record' if record else '--' + given[0].replace('_', '-')}"
                ", expected the site from one of the parameters, --record or --example"
            )
        stream = source.read(None)
        if len(stream) != 1:
            raise InputError(
                f"--example {source.example}: {len(stream)} components, expected one "
                "(pick it with --component, such as MUL009)"
            )
        site = site_from_record(
            stream[0], t0=options.t0, alpha_reading=alpha_reading, name=source.name(None)
        )
    elif not _envelope_free(parameters, record, alpha_reading, options.monte_carlo, figure):
        site = site_from_options(
            parameters, record=record, record_options=source.read_kwargs(), t0=options.t0,
            alpha_reading=alpha_reading,
        )  # fmt: skip
    if options.frame is not None:
        from stepframe.structure.frame_file import read_frame_file

        frame = read_frame_file(options.frame)
        oscillator = stage.frame_oscillator(frame, options.xi0, options.frame)
    else:
        assert options.f0_hz is not None
        oscillator = stage.tracking_oscillator(options.f0_hz, options.xi0)
    result: AmplificationResult | SpectralRatios
    if site is None:
        values = {key: float(value) for key, value in parameters.items() if value is not None}
        result = stage.spectral_ratios(
            values["fp_hz"], values["fs_hz"], values["fr_hz"], values["xi_p"], values["xi_r"],
            oscillator, peak_intensity_m_s2=options.peak_intensity_m_s2,
        )  # fmt: skip
    else:
        result = stage.amplify(
            site, oscillator, peak_intensity_m_s2=options.peak_intensity_m_s2,
            n_steps=options.n_steps, monte_carlo=options.monte_carlo, seed=options.seed,
        )  # fmt: skip
    return AmplifyStudy(result, site, oscillator, options.n_steps)


def _envelope_free(
    parameters: Mapping[str, float | None],
    record: str | None,
    alpha_reading: str,
    monte_carlo: int,
    figure: bool,
) -> bool:
    """Whether the site is given by its parameters without both envelope times (none given).

    Under the paper's reading that is the envelope-free route; under eq. 6.11's it is an error
    saying why (α_g(t_max) then depends on t_max/t_dur) and what to give.
    """
    if record is not None or any(parameters.get(name) is not None for name in ENVELOPE_TIMES):
        return False
    others = [name for name in SITE_PARAMETERS if name not in ENVELOPE_TIMES]
    if not all(parameters.get(name) is not None for name in others):
        return False  # site_from_options names the first one missing
    if alpha_reading != "paper":
        raise InputError(
            f"no --t-max-s and --t-dur-s with --alpha-at-tmax {alpha_reading}, expected both "
            f"(eq. 6.18's α_g(t_max) then depends on t_max/t_dur; {_TIMES_HINT}), "
            "or --alpha-at-tmax paper for eqs. 6.18-6.19 alone"
        )
    for flag, given in (("--monte-carlo", monte_carlo), ("--plot", figure)):
        if given:
            raise InputError(
                f"{flag} without --t-max-s and --t-dur-s, expected both times (the response "
                f"amplification needs the envelope; {_TIMES_HINT})"
            )
    return True


__all__ = ["ENVELOPE_TIMES", "AmplifyOptions", "AmplifyStudy", "amplify_study"]
