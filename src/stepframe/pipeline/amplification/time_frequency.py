"""The site amplification report's time-frequency panel (issue 26, item 5): the site model's
evolutionary spectrum over the frame's band with the frame's frequency of the frame-driven
analysis drawn over it, the picture the selection report draws for a simulated record.

S(ω, t) is eq. 6.12 times the default envelope's I_g(t)² (the one the frame-driven mean-square
analysis integrates), on the band grid of :func:`stepframe.pipeline.dynamics.resonance.
band_grid_rad_s` (the frame's band widened by a third of an octave), twelve bands per octave:
more than the index's nine, since an analytic spectrum costs nothing per band and the finer
grid draws the smoother picture;
the path is that analysis's ω(t) (the period-amplitude law at the RMS amplitude), and the panel
below its RMS response σ_x(t).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure

    from stepframe.stochastic.mean_square import MeanSquareResult
    from stepframe.stochastic.model import GroundMotionModel


#: Bands per octave of the site model's picture (module docstring).
SITE_BANDS_PER_OCTAVE = 12


def model_band_spectrum(
    model: GroundMotionModel, band_rad_s: tuple[float, float], time_s: np.ndarray
) -> xr.DataArray:
    """Eq. 6.12 × I_g(t)² (unit peak intensity) on the band grid at ``time_s`` [s], dims
    (``time``, ``omega``) as :func:`stepframe.stochastic.spectra.evolutionary_spectrum`."""
    import xarray as xr

    from stepframe.pipeline.dynamics.resonance import band_grid_rad_s
    from stepframe.stochastic.envelope import default_envelope

    omega = band_grid_rad_s(band_rad_s, per_octave=SITE_BANDS_PER_OCTAVE)
    time = np.asarray(time_s, dtype=np.float64)
    intensity = default_envelope(time, model.t_max_s, model.t_dur_s, 1.0, t0_s=model.t0_s)
    psd = model.psd(omega[None, :], time[:, None], intensity[:, None])
    return xr.DataArray(
        np.asarray(psd, dtype=np.float64), dims=("time", "omega"),
        coords={"time": time, "omega": omega}, name="psd",
    )  # fmt: skip


def site_band_figure(
    model: GroundMotionModel,
    band_rad_s: tuple[float, float],
    moving: MeanSquareResult,
    *,
    title: str,
) -> Figure:
    """The site model's spectrum over the band with the frame-driven ω(t) over it and σ_x(t)
    below (:func:`stepframe.stochastic.plots.time_frequency_figure`)."""
    from stepframe.stochastic.plots import time_frequency_figure

    time = np.asarray(moving.time_s, dtype=np.float64)
    omega = np.asarray(moving.omega_rad_s, dtype=np.float64).reshape(-1, time.size)[0]
    sigma = np.sqrt(np.asarray(moving.mean_square_m2, dtype=np.float64).reshape(-1, time.size)[0])
    return time_frequency_figure(
        model_band_spectrum(model, band_rad_s, time),
        band_rad_s=band_rad_s,
        path=(time, omega),
        path_label="frame's ω(t), frame-driven analysis",
        cumulative=(time, sigma),
        cumulative_label="frame's σ_x [m]",
        title=title,
    )


__all__ = ["model_band_spectrum", "site_band_figure"]
