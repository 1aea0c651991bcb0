"""One site's amplification for one oscillator, from what a user gives (``stochastic amplify``).

The site is given by its parameters (all seven, or under the paper's reading the five without
the envelope times, for eqs. 6.18-6.19 alone), by a record file, or by a component of the
embedded example catalogue; the oscillator by its small-amplitude frequency or by a frame file.
:func:`amplify_study` picks the route, refuses mixed or incomplete inputs with one line saying
what to give, and runs :func:`stepframe.pipeline.amplification.amplify` or
:func:`~stepframe.pipeline.amplification.spectral_ratios`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from stepframe.errors import InputError
from stepframe.pipeline.amplification import (
    AmplificationResult,
    Oscillator,
    SpectralRatios,
    amplification_curve,
    amplify,
    frame_oscillator,
    spectral_ratios,
    tracking_oscillator,
)
from stepframe.pipeline.site import SITE_PARAMETERS, SiteModel, site_from_options, site_from_record

if TYPE_CHECKING:
    from matplotlib.figure import Figure
    from obspy import Stream

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
    parameters: Mapping[str, float | None],
    *,
    f0_hz: float | None = None,
    frame: str | None = None,
    xi0: float | None = None,
    record: str | None = None,
    record_options: Mapping[str, Any] | None = None,
    example: tuple[str, str | None, Stream] | None = None,
    t0: Any = "auto",
    alpha_reading: Any = "eq-6-11",
    peak_intensity_m_s2: float | None = None,
    n_steps: int = 4000,
    monte_carlo: int = 0,
    seed: int | None = None,
    figure: bool = False,
) -> AmplifyStudy:
    """Pick the site and the oscillator from the inputs given, and compute the amplification.

    Parameters
    ----------
    parameters
        :data:`~stepframe.pipeline.site.SITE_PARAMETERS` → value, None where not given.
    f0_hz, frame
        The oscillator: small-amplitude frequency [Hz], or a frame file (ω(t) = 2π/T(A));
        exactly one.
    xi0
        Damping ratio (fraction; default 0.05, or the frame's ``xi_1``).
    record, record_options
        A record file to fit the site to, and its read options.
    example
        ``(name, component, stream)``: the site from the one component of an example catalogue
        (``stream``, read with its ``component`` chosen).
    t0, alpha_reading
        Time origin of a fitted site, and where the α_g ramp ends.
    peak_intensity_m_s2, n_steps, monte_carlo, seed
        As :func:`~stepframe.pipeline.amplification.amplify`.
    figure
        Whether a figure will be asked for (it needs the envelope's times).
    """
    if (f0_hz is None) == (frame is None):
        raise InputError("expected exactly one of --f0-hz F and --frame FRAME.toml")
    given = [name for name in SITE_PARAMETERS if parameters.get(name) is not None]
    site: SiteModel | None = None
    if example is not None:
        name, component, stream = example
        if given or record is not None:
            raise InputError(
                f"--example with {'--record' if record else '--' + given[0].replace('_', '-')}"
                ", expected the site from one of the parameters, --record or --example"
            )
        if len(stream) != 1:
            raise InputError(
                f"--example {name}: {len(stream)} components, expected one "
                "(pick it with --component, such as MUL009)"
            )
        site = site_from_record(
            stream[0], t0=t0, alpha_reading=alpha_reading, name=f"example {name} {component}"
        )
    elif not _envelope_free(parameters, record, alpha_reading, monte_carlo, figure):
        site = site_from_options(
            parameters, record=record, record_options=record_options, t0=t0,
            alpha_reading=alpha_reading,
        )  # fmt: skip
    if frame is not None:
        from stepframe.structure.frame_file import read_frame_file

        oscillator = frame_oscillator(read_frame_file(frame), xi0, frame)
    else:
        assert f0_hz is not None
        oscillator = tracking_oscillator(f0_hz, xi0)
    result: AmplificationResult | SpectralRatios
    if site is None:
        values = {name: float(value) for name, value in parameters.items() if value is not None}
        result = spectral_ratios(
            values["fp_hz"], values["fs_hz"], values["fr_hz"], values["xi_p"], values["xi_r"],
            oscillator, peak_intensity_m_s2=peak_intensity_m_s2,
        )  # fmt: skip
    else:
        result = amplify(
            site, oscillator, peak_intensity_m_s2=peak_intensity_m_s2, n_steps=n_steps,
            monte_carlo=monte_carlo, seed=seed,
        )  # fmt: skip
    return AmplifyStudy(result, site, oscillator, n_steps)


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
    for option, given in (("--monte-carlo", monte_carlo), ("--plot", figure)):
        if given:
            raise InputError(
                f"{option} without --t-max-s and --t-dur-s, expected both times (the response "
                f"amplification needs the envelope; {_TIMES_HINT})"
            )
    return True


__all__ = ["ENVELOPE_TIMES", "AmplifyStudy", "amplify_study"]
