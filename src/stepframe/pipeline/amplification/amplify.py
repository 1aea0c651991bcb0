"""Moving-resonance amplification of a site for one oscillator, and its curve over f0.

Two kinds of oscillator: one given by its small-amplitude frequency f0 (its ω(t) tracks the
ground, ω_0·ω_g(t)/ω_p), and a stepping frame (ω(t) = 2π/T(A) from the frame's period-amplitude
law, A = √2·σ_x). :func:`amplify` reports the paper's spectral ratio (eq. 6.18) and its two
approximations (eq. 6.19) next to the response amplification computed by the exact covariance
method (optionally confirmed by Monte Carlo): two kinds of amplification, each named for what it
is (DESIGN.md). :func:`spectral_ratios` gives the first kind alone for a site known without its
envelope times: under the paper's reading (α_g(t_max) = ω_r ξ_r) neither eq. 6.18 nor eq. 6.19
depends on t_max or t_dur; the response amplification does. :func:`amplification_curve` gives
both over a range of f0 as an ``xarray.Dataset``, stored and read back with :func:`write_curve`
and :func:`read_curve`.
"""

from __future__ import annotations

import math
import textwrap
from dataclasses import asdict, dataclass, field, fields
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING, Any

from stepframe.core.results import Status
from stepframe.core.tables import read_dataset, write_dataset
from stepframe.errors import InputError
from stepframe.pipeline.amplification.headlines import Stepping, frame_stepping
from stepframe.pipeline.amplification.site import SiteModel

if TYPE_CHECKING:
    import xarray as xr
    from numpy.typing import ArrayLike

    from stepframe.stochastic.mean_square import FrameDriven
    from stepframe.structure.frame import PortalFrame

#: Damping ratio of an oscillator given by f0 when none is given (fraction).
from stepframe.pipeline.amplification.analysis import DEFAULT_XI0


@dataclass(frozen=True)
class Oscillator:
    """The oscillator whose response is amplified.

    Attributes
    ----------
    f0_hz
        Small-amplitude frequency [Hz].
    xi0
        Damping ratio at f0 (fraction).
    frame_law
        The frame's ω(t) = 2π/T(A) (None: ω(t) tracks the ground, ω_0·ω_g(t)/ω_p).
    participation
        Factor on the ground intensity: the frame's p_1 (its equation of motion takes
        -p_1 ẍ_g in the unstepped phase, eq. 4.11), 1 for a plain oscillator.
    inputs
        What describes it in the result's ``inputs`` (the frame file, p_1).
    x_c_m
        A frame's uplift amplitude [m]: its period changes only above it (None for an
        oscillator given by f0).
    """

    f0_hz: float
    xi0: float
    frame_law: FrameDriven | None = None
    participation: float = 1.0
    inputs: dict[str, Any] = field(default_factory=dict)
    x_c_m: float | None = None

    def __post_init__(self) -> None:
        if not (math.isfinite(self.xi0) and self.xi0 > 0):
            raise InputError(
                f"oscillator damping xi0 = {self.xi0}, expected a fraction > 0 (e.g. 0.05; a "
                "frame's oscillator takes its xi_1 unless xi0 is given)"
            )


def tracking_oscillator(f0_hz: float, xi0: float | None = None) -> Oscillator:
    """An oscillator of small-amplitude frequency ``f0_hz`` [Hz] (default damping 0.05)."""
    return Oscillator(float(f0_hz), DEFAULT_XI0 if xi0 is None else float(xi0))


def frame_oscillator(
    frame: PortalFrame, xi0: float | None = None, name: str | PathLike[str] | None = None
) -> Oscillator:
    """A stepping frame: ω(t) = 2π/T(A) from its period-amplitude law (default damping xi_1).

    Parameters
    ----------
    frame
        The frame.
    xi0
        Damping ratio (fraction; default the frame's ``xi_1``).
    name
        The frame file, reported in the result's ``inputs``.
    """
    from stepframe.stochastic.mean_square import FrameDriven
    from stepframe.structure.period_amplitude import period_amplitude

    def period_s(amplitude_m: float) -> float:
        return float(period_amplitude(frame, amplitude_m, beyond_x_star="inf"))

    return Oscillator(
        f0_hz=1.0 / period_s(0.0),
        xi0=frame.xi_1 if xi0 is None else float(xi0),
        frame_law=FrameDriven(period_s),
        participation=frame.p_1,
        inputs={"frame": None if name is None else str(name), "participation_p_1": frame.p_1},
        x_c_m=frame.x_c_m,
    )


@dataclass(frozen=True)
class MonteCarloCheck:
    """The Monte Carlo confirmation of a response amplification (95 % bands)."""

    n_realisations: int
    seed: int | None
    confidence: float
    response_amplification_vs_fixed: float
    response_amplification_vs_fixed_band: list[float]
    response_amplification_vs_stationary: float
    response_amplification_vs_stationary_band: list[float]
    status: Status
    message: str = ""

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form."""
        return dict(self.__dict__)


@dataclass(frozen=True)
class AmplificationResult:
    """Both kinds of amplification for one site and one oscillator.

    ``status`` is ``"ok"``; ``"lower_bound"`` when a frame stopped the run (its period law gave
    no finite period: overturning), so the peak RMS so far is only a lower bound; or
    ``"degraded"`` when the site was fitted to a record and the fit is not plausible (its
    parameters are where the search stopped: :func:`stepframe.stochastic.flags.implausible`).
    ``message`` says where the run stopped or which flags the fit has. ``frame_stepping`` (a
    frame only) says whether the frame stepped in the run, so whether its frequency moved at
    all, and from which site intensity it would.
    """

    spectral_ratio_eq_6_18: float
    approx_eq_6_19_first: float
    approx_eq_6_19_last: float
    response_amplification_vs_fixed: float
    response_amplification_vs_stationary: float
    peak_rms_moving_m: float
    peak_rms_fixed_m: float
    stationary_rms_m: float
    omega_path: str
    alpha_reading: str
    method: str
    status: Status
    message: str
    f0_hz: float
    xi0: float
    peak_intensity_m_s2: float
    duration_s: float
    n_steps: int
    inputs: dict[str, Any]
    monte_carlo: MonteCarloCheck | None = None
    frame_stepping: Stepping | None = None

    @property
    def lower_bound(self) -> bool:
        """Whether the response values are lower bounds (a frame stopped the run)."""
        return self.status == "lower_bound"

    def describe(self) -> str:
        """The result as text, one quantity a line (what ``stochastic amplify`` prints)."""
        return _describe(self.to_dict())

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form (what ``stepframe stochastic amplify --json`` prints)."""
        nested = ("monte_carlo", "frame_stepping")
        out = {key: value for key, value in self.__dict__.items() if key not in nested}
        out["lower_bound"] = self.lower_bound
        if self.monte_carlo is not None:
            out["monte_carlo"] = self.monte_carlo.to_dict()
        if self.frame_stepping is not None:
            out["frame_stepping"] = asdict(self.frame_stepping)
        return out


def amplify(
    site: SiteModel,
    oscillator: Oscillator,
    *,
    peak_intensity_m_s2: float | None = None,
    n_steps: int = 4000,
    monte_carlo: int = 0,
    seed: int | None = None,
) -> AmplificationResult:
    """Spectral ratio (eqs. 6.18-6.19) and response amplification of one oscillator.

    Parameters
    ----------
    site
        The site model.
    oscillator
        :func:`tracking_oscillator` or :func:`frame_oscillator`.
    peak_intensity_m_s2
        max I_g [m/s²] (default the site's); multiplied by the oscillator's participation.
        Matters only for a frame (a linear oscillator's ratios do not depend on it).
    n_steps
        Time steps of the analysis grid.
    monte_carlo
        0, or N ≥ 2 synthetic motions to confirm the covariance result.
    seed
        Seed of the Monte Carlo motions.
    """
    from stepframe.stochastic.amplification import (
        approx_eq_6_19_first,
        approx_eq_6_19_last,
        response_amplification,
        spectral_ratio_eq_6_18,
    )
    from stepframe.stochastic.mean_square import analysis_grid

    if monte_carlo < 0 or monte_carlo == 1:
        raise InputError(f"--monte-carlo {monte_carlo}, expected 0 (none) or N ≥ 2")
    model = site.model
    base = site.peak_intensity_m_s2 if peak_intensity_m_s2 is None else peak_intensity_m_s2
    intensity = base * oscillator.participation
    grid = analysis_grid(model, n_steps=n_steps)
    omega_0 = 2 * math.pi * oscillator.f0_hz
    tracked = None if oscillator.frame_law is not None else [omega_0]
    covariance = response_amplification(
        model, tracked, oscillator.xi0, frame=oscillator.frame_law, peak_intensity=intensity,
        time_s=grid,
    )  # fmt: skip
    check = None
    if monte_carlo:
        mc = response_amplification(
            model, tracked, oscillator.xi0, frame=oscillator.frame_law, method="monte-carlo",
            peak_intensity=intensity, time_s=grid, n_realisations=monte_carlo, seed=seed,
        )  # fmt: skip
        if mc.vs_fixed_band is None or mc.vs_stationary_band is None:
            raise RuntimeError("the Monte Carlo method returned no confidence band")
        check = MonteCarloCheck(
            n_realisations=monte_carlo,
            seed=seed,
            confidence=0.95,
            response_amplification_vs_fixed=float(mc.vs_fixed[0]),
            response_amplification_vs_fixed_band=mc.vs_fixed_band[0].tolist(),
            response_amplification_vs_stationary=float(mc.vs_stationary[0]),
            response_amplification_vs_stationary_band=mc.vs_stationary_band[0].tolist(),
            status=mc.moving.status,
            message=mc.moving.message,
        )
    status, message = covariance.moving.status, covariance.moving.message
    unfit = _implausible_fit(site)
    if unfit:
        status = "degraded" if status == "ok" else status
        message = f"{message}; {unfit}" if message else unfit
    stepping = None
    if oscillator.frame_law is not None and oscillator.x_c_m is not None:
        stepping = frame_stepping(
            oscillator.x_c_m, covariance, base, oscillator.frame_law.amplitude_factor
        )
    return AmplificationResult(
        spectral_ratio_eq_6_18=float(spectral_ratio_eq_6_18(model, omega_0)),
        approx_eq_6_19_first=approx_eq_6_19_first(model),
        approx_eq_6_19_last=approx_eq_6_19_last(model),
        response_amplification_vs_fixed=float(covariance.vs_fixed[0]),
        response_amplification_vs_stationary=float(covariance.vs_stationary[0]),
        peak_rms_moving_m=float(covariance.peak_rms_moving_m[0]),
        peak_rms_fixed_m=float(covariance.peak_rms_fixed_m[0]),
        stationary_rms_m=float(covariance.stationary_rms_m[0]),
        omega_path=covariance.omega_path,
        alpha_reading=model.alpha_reading,
        method="covariance",
        status=status,
        message=message,
        f0_hz=oscillator.f0_hz,
        xi0=oscillator.xi0,
        peak_intensity_m_s2=intensity,
        duration_s=float(grid[-1]),
        n_steps=int(grid.size - 1),
        inputs={"ground_motion_model": model.to_dict(), **site.source, **oscillator.inputs},
        monte_carlo=check,
        frame_stepping=stepping,
    )


def _implausible_fit(site: SiteModel) -> str:
    """Why the site's fit to a record is not plausible ("" when it is, or when the site was
    given by its parameters): the flags that make its parameters a bound, not an estimate."""
    from stepframe.stochastic.flags import describe, implausible

    flags = implausible(site.source.get("flags", ()))
    if not flags:
        return ""
    component = site.source.get("component")
    where = f"{site.source.get('record')}" + (f" [{component}]" if component else "")
    return (
        f"the fit to {where} is not plausible ({'; '.join(describe(flags))}), so these "
        "amplifications are not the site's (`stepframe stochastic fit` says more)"
    )


#: Why an envelope-free result has no response amplification, and how to get one.
NO_ENVELOPE_MESSAGE = (
    "response amplification not computed: it needs the envelope's times, expected --t-max-s "
    "and --t-dur-s (`stepframe stochastic fit` prints t_max_s and t_dur_s of a record of the "
    "site; the paper's site has 5 and 20 s) or the site from --record FILE"
)

#: The keys of :meth:`AmplificationResult.to_dict` that need the envelope (absent without it).
ENVELOPE_KEYS = (
    "response_amplification_vs_fixed",
    "response_amplification_vs_stationary",
    "peak_rms_moving_m",
    "peak_rms_fixed_m",
    "stationary_rms_m",
    "method",
    "duration_s",
    "n_steps",
)


@dataclass(frozen=True)
class SpectralRatios:
    """Eq. 6.18's spectral ratio and eq. 6.19's approximations of a site without its envelope.

    What :func:`spectral_ratios` returns. :meth:`to_dict` has the keys of
    :meth:`AmplificationResult.to_dict` in the same order, but not :data:`ENVELOPE_KEYS` nor
    the model's ``t_max_s`` and ``t_dur_s`` (a number is a number or absent, never null), and
    ``message`` saying how to get the rest.
    """

    spectral_ratio_eq_6_18: float
    approx_eq_6_19_first: float
    approx_eq_6_19_last: float
    omega_path: str
    alpha_reading: str
    f0_hz: float
    xi0: float
    peak_intensity_m_s2: float
    inputs: dict[str, Any]
    message: str = NO_ENVELOPE_MESSAGE
    status: Status = "ok"

    def describe(self) -> str:
        """The result as text, one quantity a line (what ``stochastic amplify`` prints)."""
        return _describe(self.to_dict())

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form, shaped as :meth:`AmplificationResult.to_dict` without what needs the
        envelope."""
        out: dict[str, Any] = {}
        for item in fields(AmplificationResult):
            if item.name not in ("monte_carlo", "frame_stepping", *ENVELOPE_KEYS):
                out[item.name] = getattr(self, item.name)
        out["lower_bound"] = False
        return out


def spectral_ratios(
    fp_hz: float,
    fs_hz: float,
    fr_hz: float,
    xi_p: float,
    xi_r: float,
    oscillator: Oscillator,
    *,
    peak_intensity_m_s2: float | None = None,
) -> SpectralRatios:
    """Eqs. 6.18-6.19 for a site known without its envelope times, the paper's reading.

    With α_g(t_max) = ω_r ξ_r (``alpha_reading="paper"``) eq. 6.18 and both approximations of
    eq. 6.19 depend on the dominant frequencies and bandwidth ratios only; the values are those
    :func:`amplify` gives for the same site with any t_max ≤ t_dur.

    Parameters
    ----------
    fp_hz, fs_hz, fr_hz
        Dominant frequencies of the P, S and surface waves [Hz].
    xi_p, xi_r
        Bandwidth ratios.
    oscillator
        :func:`tracking_oscillator` or :func:`frame_oscillator` (eq. 6.18 at its f0).
    peak_intensity_m_s2
        max I_g [m/s²] (default 1), reported times the participation; nothing depends on it.
    """
    from stepframe.stochastic.amplification import (
        approx_eq_6_19_first,
        approx_eq_6_19_last,
        spectral_ratio_eq_6_18,
    )
    from stepframe.stochastic.model import GroundMotionModel

    # The times are placeholders (validated as 0 < t_max ≤ t_dur): under the paper's reading
    # α_g(t0 + t_max) = ω_r ξ_r whatever they are, and eq. 6.19 does not use them.
    model = GroundMotionModel.from_hz(
        fp_hz, fs_hz, fr_hz, xi_p, xi_r, t_max_s=1.0, t_dur_s=1.0, alpha_reading="paper"
    )
    described = {k: v for k, v in model.to_dict().items() if k not in ("t_max_s", "t_dur_s")}
    omega_0 = 2 * math.pi * oscillator.f0_hz
    base = 1.0 if peak_intensity_m_s2 is None else peak_intensity_m_s2
    return SpectralRatios(
        spectral_ratio_eq_6_18=float(spectral_ratio_eq_6_18(model, omega_0)),
        approx_eq_6_19_first=approx_eq_6_19_first(model),
        approx_eq_6_19_last=approx_eq_6_19_last(model),
        omega_path="frame" if oscillator.frame_law is not None else "tracking",
        alpha_reading=model.alpha_reading,
        f0_hz=oscillator.f0_hz,
        xi0=oscillator.xi0,
        peak_intensity_m_s2=base * oscillator.participation,
        inputs={"ground_motion_model": described, "site": "parameters", **oscillator.inputs},
    )


def _describe(data: dict[str, Any]) -> str:
    """The result as text, one quantity a line."""
    lines = [
        f"oscillator f0 = {data['f0_hz']:.4g} Hz, xi0 = {data['xi0']:.3g}, "
        f"omega path: {data['omega_path']}, alpha reading: {data['alpha_reading']}",
        f"  spectral ratio eq. 6.18 at f0          {data['spectral_ratio_eq_6_18']:.4g}",
        f"  eq. 6.19 first approximation           {data['approx_eq_6_19_first']:.4g}",
        f"  eq. 6.19 last approximation (ωp/ωs)²   {data['approx_eq_6_19_last']:.4g}",
    ]
    if "response_amplification_vs_fixed" not in data:
        lines += textwrap.wrap(data["message"], 96, initial_indent="  ", subsequent_indent="    ")
        return "\n".join(lines)
    lines += [
        f"  response amplification vs fixed       {data['response_amplification_vs_fixed']:.4g}",
        "  response amplification vs stationary  "
        f"{data['response_amplification_vs_stationary']:.4g}",
    ]
    mc = data.get("monte_carlo")
    if mc:
        lo, hi = mc["response_amplification_vs_fixed_band"]
        lines.append(
            f"  Monte Carlo (N = {mc['n_realisations']}): vs fixed "
            f"{mc['response_amplification_vs_fixed']:.4g} [{lo:.4g}, {hi:.4g}] (95 %)"
        )
    if data["status"] != "ok":
        lines.append(f"  status: {data['status']}")
        if data["status"] == "degraded":
            lines += textwrap.wrap(
                data["message"], 96, initial_indent="  ", subsequent_indent="    "
            )
    if "frame_stepping" in data:
        sentence = Stepping(**data["frame_stepping"]).describe()
        lines += textwrap.wrap(sentence, 96, initial_indent="  ", subsequent_indent="    ")
    return "\n".join(lines)


#: Column dictionary of an amplification curve: variable → (unit, meaning).
CURVE_VARIABLES: dict[str, tuple[str, str]] = {
    "spectral_ratio_eq_6_18": ("1", "ratio of spectral densities at f0, eq. 6.18"),
    "response_amplification_vs_fixed": ("1", "peak RMS, moving ω(t) / held at ω_0"),
    "response_amplification_vs_stationary": ("1", "peak RMS, moving ω(t) / stationary"),
}


def amplification_curve(
    site: SiteModel, frequencies_hz: ArrayLike, xi0: float = DEFAULT_XI0, *, n_steps: int = 4000
) -> xr.Dataset:
    """Both amplifications of tracking oscillators over a range of f0.

    Parameters
    ----------
    site
        The site model.
    frequencies_hz
        Small-amplitude frequencies f0 [Hz].
    xi0
        Damping ratio (fraction).
    n_steps
        Time steps of the analysis grid.

    Returns
    -------
    xarray.Dataset
        :data:`CURVE_VARIABLES` on ``frequency`` [Hz], with ``units`` and ``long_name``
        attributes; attributes ``xi0``, ``alpha_reading``, ``omega_path``,
        ``approx_eq_6_19_last``, ``status`` and the site model's parameters.
    """
    import numpy as np
    import xarray as xr

    from stepframe.stochastic.amplification import (
        approx_eq_6_19_last,
        response_amplification,
        spectral_ratio_eq_6_18,
    )
    from stepframe.stochastic.mean_square import analysis_grid

    model = site.model
    frequencies = np.asarray(frequencies_hz, dtype=np.float64)
    grid = analysis_grid(model, n_steps=n_steps)
    curve = response_amplification(model, 2 * np.pi * frequencies, xi0, time_s=grid)
    values = {
        "spectral_ratio_eq_6_18": spectral_ratio_eq_6_18(model, 2 * np.pi * frequencies),
        "response_amplification_vs_fixed": curve.vs_fixed,
        "response_amplification_vs_stationary": curve.vs_stationary,
    }
    attrs: dict[str, Any] = {
        "xi0": float(xi0),
        "alpha_reading": model.alpha_reading,
        "omega_path": curve.omega_path,
        "approx_eq_6_19_last": approx_eq_6_19_last(model),
        "status": curve.moving.status,
        "peak_intensity_m_s2": site.peak_intensity_m_s2,
    }
    attrs |= {
        f"model_{key}": value
        for key, value in model.to_dict().items()
        if value is not None and key != "alpha_reading"
    }
    return xr.Dataset(
        {
            name: ("frequency", np.asarray(values[name], dtype=np.float64),
                   {"units": unit, "long_name": meaning})
            for name, (unit, meaning) in CURVE_VARIABLES.items()
        },
        coords={"frequency": ("frequency", frequencies, {"units": "Hz"})},
        attrs=attrs,
    )  # fmt: skip


def write_curve(curve: xr.Dataset, path: str | PathLike[str]) -> Path:
    """Write an amplification curve as NetCDF (atomically); :func:`read_curve` reads it back."""
    return write_dataset(curve, path)


def read_curve(path: str | PathLike[str]) -> xr.Dataset:
    """An amplification curve written by :func:`write_curve` (loaded into memory)."""
    return read_dataset(path, "an amplification curve (NetCDF)")


__all__ = [
    "CURVE_VARIABLES",
    "DEFAULT_XI0",
    "ENVELOPE_KEYS",
    "NO_ENVELOPE_MESSAGE",
    "AmplificationResult",
    "MonteCarloCheck",
    "Oscillator",
    "SpectralRatios",
    "amplification_curve",
    "amplify",
    "frame_oscillator",
    "read_curve",
    "spectral_ratios",
    "tracking_oscillator",
    "write_curve",
]
