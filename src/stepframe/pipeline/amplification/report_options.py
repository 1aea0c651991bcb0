"""The inputs of ``stepframe report amplification``: :class:`AmplificationReportOptions` (light:
the command line derives its options from the fields without loading numpy)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from stepframe.core.options import option

if TYPE_CHECKING:
    from stepframe.stochastic.model import AlphaReading


@dataclass(frozen=True)
class AmplificationReportOptions:
    """The site (its parameters or a folder of its records), the optional frame and the analysis
    of an amplification report (``stepframe report amplification``)."""

    fp_hz: float | None = option(None, "P-wave dominant f_p [Hz]", kind="positive", metavar="F")
    fs_hz: float | None = option(None, "S-wave dominant f_s [Hz]", kind="positive", metavar="F")
    fr_hz: float | None = option(None, "surface-wave f_r [Hz]", kind="positive", metavar="F")
    xi_p: float | None = option(None, "bandwidth ratio ξ_p", kind="positive", metavar="X")
    xi_r: float | None = option(None, "bandwidth ratio ξ_r", kind="positive", metavar="X")
    t_max_s: float | None = option(None, "time of peak I_g [s]", kind="positive", metavar="T")
    t_dur_s: float | None = option(None, "strong duration [s]", kind="positive", metavar="T")
    records: str | None = option(None, "a folder of the site's record files", metavar="DIR")
    t0: str = option(
        "auto",
        "with --records: time origin, the picked P onset when reliable, else the record "
        "start (auto, the default), or one of them",
        choices=("auto", "start", "p-pick"),
    )
    record_format: str | None = option(
        None, "with --records: file format if not sniffed", metavar="NAME", flag="--format"
    )
    units: str | None = option(None, "with --records: units if the files lack them", metavar="UNIT")
    site_name: str | None = option(None, "named in titles", metavar="NAME")
    frame: str | None = option(None, "frame file: band and frame-driven run", metavar="FRAME.toml")
    delta_star_m: float | None = option(
        None,
        "the frame's design displacement δ* [m] (stepframe structure design)",
        kind="positive",
        metavar="D",
    )
    alpha_reading: AlphaReading = option(
        "eq-6-11",
        "α_g ramp ends at t_dur (eq. 6.11 as printed, default) or at t_max (the paper)",
        choices=("eq-6-11", "paper"),
        flag="--alpha-at-tmax",
    )
    xi0: float = option(0.05, "oscillator damping (default 0.05)", kind="float", metavar="X")
    monte_carlo: int = option(
        50,
        "synthetic motions at each of 4 Monte Carlo frequencies (default 50; 0: none)",
        kind="int",
        metavar="N",
    )
    seed: int | None = option(1, "Monte Carlo seed (default 1)", kind="int")
    n_steps: int = option(2000, "time steps (default 2000)", kind="int", metavar="N")
    peak_intensity_m_s2: float | None = option(
        None,
        "peak I_g [m/s²] of the frame-driven run (default: the records' median, else 1)",
        kind="positive",
        metavar="I",
    )
