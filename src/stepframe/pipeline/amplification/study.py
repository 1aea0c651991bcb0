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
from dataclasses import dataclass, fields
from typing import TYPE_CHECKING, Any

from stepframe.errors import InputError
from stepframe.pipeline.amplification.analysis import SITE_PARAMETERS, AmplifyOptions
from stepframe.records.read_options import RecordSource

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from stepframe.pipeline.amplification.amplify import (
        AmplificationResult,
        Oscillator,
        SpectralRatios,
    )
    from stepframe.pipeline.amplification.site import SiteModel

#: The site parameters that are the envelope's times.
ENVELOPE_TIMES = ("t_max_s", "t_dur_s")

#: Where the envelope's times of a site can be found (said in the errors that ask for them).
_TIMES_HINT = (
    "`stepframe stochastic fit` prints t_max_s and t_dur_s of a record of the site, the paper's "
    "site has 5 and 20 s"
)


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
    options
        What was asked (the figure's curve uses the same grids).
    """

    result: AmplificationResult | SpectralRatios
    site: SiteModel | None
    oscillator: Oscillator
    options: AmplifyOptions

    def to_dict(self) -> dict[str, Any]:
        """The result's JSON-ready form."""
        return self.result.to_dict()

    def describe(self) -> str:
        """The result as text."""
        return self.result.describe()

    def figure(self) -> Figure:
        """Eq. 6.18 and both response amplifications over the f0 grid, this f0 marked."""
        import numpy as np

        from stepframe.pipeline.amplification.amplify import (
            AmplificationResult,
            amplification_curve,
        )
        from stepframe.stochastic.plots import amplification_figure

        result = self.result
        if self.site is None or not isinstance(result, AmplificationResult):
            raise InputError("a figure without the envelope's times, expected both times")
        options = self.options
        frequencies = np.geomspace(options.f_min_hz, options.f_max_hz, options.n_frequencies)
        check = result.monte_carlo
        monte_carlo = None
        if check is not None:  # --monte-carlo N: drawn, not only printed
            band = check.response_amplification_vs_fixed_band
            interval = (float(band[0]), float(band[1]))
            monte_carlo = (check.response_amplification_vs_fixed, interval, check.n_realisations)
        curve = amplification_curve(
            self.site, frequencies, self.oscillator.xi0, n_steps=options.n_steps
        )
        return amplification_figure(
            curve,
            f0_hz=result.f0_hz,
            at_f0=result.response_amplification_vs_fixed,
            lower_bound=result.lower_bound,
            site=str(self.site.source.get("record") or "site from parameters"),
            # the curves are tracking oscillators; the point, with a frame, is its own run
            point_name="frame-driven ω(t) = 2π/T(A), f_1" if result.omega_path == "frame" else "f0",
            monte_carlo=monte_carlo,
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
    _check_applies(options, source or RecordSource(), figure)
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
    elif not _envelope_free(parameters, record, alpha_reading, options.monte_carlo or 0, figure):
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
            n_steps=options.n_steps, monte_carlo=options.monte_carlo or 0, seed=options.seed,
        )  # fmt: skip
    return AmplifyStudy(result, site, oscillator, options)


def _check_applies(options: AmplifyOptions, source: RecordSource, figure: bool) -> None:
    """Options that nothing reads in this run are an error, not a silent no-op (each ran and
    printed the same numbers): record options without a record, the peak intensity without a
    frame, the Monte Carlo seed without Monte Carlo motions, the figure's grid without --plot."""
    reads_a_record = options.record is not None or source.example is not None
    record_flags = source.given_flags() + (["--t0"] if options.t0 != "auto" else [])
    defaults = {f.name: f.default for f in fields(options)}
    grid = [
        "--" + name.replace("_", "-")
        for name in ("f_min_hz", "f_max_hz", "n_frequencies")
        if getattr(options, name) != defaults[name]
    ]
    for flags, applies, expected in (
        (record_flags, reads_a_record, "--record FILE or --example (they read the record)"),
        (["--peak-intensity-m-s2"] if options.peak_intensity_m_s2 is not None else [],
         options.frame is not None, "--frame (it scales the frame-driven run)"),
        (["--seed"] if options.seed != defaults["seed"] else [], bool(options.monte_carlo),
         "--monte-carlo N (it seeds the synthetic motions)"),
        (grid, figure, "--plot (the figure's f0 grid)"),
    ):  # fmt: skip
        if flags and not applies:
            verb, pronoun = ("does", "it") if len(flags) == 1 else ("do", "them")
            raise InputError(
                f"{', '.join(flags)} {verb} nothing here, expected {pronoun} only with {expected}"
            )


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
