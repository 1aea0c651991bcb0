"""The band of the response amplification from the site parameters' standard errors.

A site combined from records (:func:`stepframe.pipeline.amplification.site.site_from_features`)
knows each of ω_p, ω_s, ω_r, ξ_p and ξ_r with a standard error; the response amplification
against f0 inherits that uncertainty. Two ways to carry it along the whole curve, chosen by name:

``"monte-carlo"`` (default)
    N parameter sets drawn from independent normals (mean the combined value, standard deviation
    its standard error) as scrambled Sobol points (randomised quasi-Monte Carlo: the percentiles
    settle in fewer sets than with independent draws); sets that break ω_p ≥ ω_s ≥ ω_r > 0 or
    ξ > 0 are drawn again and counted; the band is the sets' percentile interval at each f0.
    N curves: its cost is N times a curve's, and it sees the curve's curvature and asymmetry:
    with two records' standard errors (RSN 8883) the amplification at 0.1 Hz runs from 2.1 to
    6.3 over ω_p ± 2 SE, about 4.6. Each set's curve is computed f0 by f0 on the coarsest of
    the analysis's grid, a half, a quarter or an eighth of it that keeps four steps a period of
    that f0 (:func:`band_grids`, checked on the central curve): the covariance run's cost is in
    its steps, and low frequencies need few. For RSN 8883's report the band's 512 curves cost
    0.39 × their CPU on 4,000 steps everywhere, the curves within 1.3e-4 of those, the band's
    edges within 4e-5 (1e-4 of its half-width, against 2-7 % between seeds;
    docs/benchmarks.md, "The band's time grids").
``"delta"``
    The delta method on the logarithm (the amplification is a positive ratio): the derivative of
    ln A along each parameter by central differences (step a tenth of the parameter's standard
    error), σ(f0)² = Σ (∂ ln A/∂θ_i)² SE_i², band A·exp(± z σ) with z the normal quantile of the
    confidence: positive, and wider above than below. 1 + 2k curves for k parameters (11, the
    central one already computed). Exact for ln A linear in the parameters over ± a few
    standard errors: within 3 % of the Monte Carlo band for the example catalogue's 53 plausible
    components (standard errors of 6-11 %), but blind to the curve's curvature with two
    records' (RSN 8883, up to 18 %), where its lower edge lies up to 42 % above the Monte Carlo
    one (docs/benchmarks.md, "Issue 30").

Both treat the parameters as independent: the combined standard errors come from the scatter
of the records' fits one parameter at a time (the covariance between parameters across a
handful of records is not estimated). t_max, t_dur and the peak intensity have no standard error
and are held. docs/benchmarks.md ("Issue 30") measures both methods' cost and the Monte Carlo
band's stability in N.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Literal

import numpy as np
from numpy.typing import NDArray

from stepframe.errors import InputError
from stepframe.pipeline.amplification.analysis import BAND_SAMPLES, BandMethod

if TYPE_CHECKING:
    from concurrent.futures import Executor

    from stepframe.stochastic.model import GroundMotionModel

Floats = NDArray[np.float64]

#: How Monte Carlo parameter sets are drawn (:func:`monte_carlo_curves`).
Sampler = Literal["sobol", "random"]

#: The parameters that carry a standard error (the site's combined ones).
VARIED = ("omega_p_rad_s", "omega_s_rad_s", "omega_r_rad_s", "xi_p", "xi_r")

#: Central-difference step of the delta method, as a fraction of the parameter's standard error:
#: small against the curve's curvature over one standard error, large against rounding.
DELTA_STEP = 0.1

#: Time steps a period of f0 on the grid of each f0's curve in a Monte Carlo set
#: (:func:`band_grids`). The mean square's peak is read on the grid, and its ripple at twice the
#: oscillator's frequency aliases when a step nears half that period: on RSN 8883's site at 700
#: steps (two a period of 10 Hz) the curve there is off by 8e-3; at four a period the report's
#: 512 curves are within 1.3e-4 of 4,000 steps (docs/benchmarks.md, "The band's time grids").
BAND_STEPS_PER_PERIOD = 4.0

#: Fewest time steps of a band curve's grid: the envelope and ω_g(t) vary over the whole record
#: whatever the oscillator (at 500 steps over RSN 8883's 35 s, below 1 Hz within 2e-5).
MIN_BAND_STEPS = 500

#: Largest relative difference, at any f0, between the central curve on the band's grids and on
#: the analysis's: beyond it the band is computed on the analysis's grid (:func:`band_grids`).
BAND_STEP_TOLERANCE = 2e-4

#: Draws tried per accepted Monte Carlo parameter set before giving up (a site whose standard
#: errors put most draws outside ω_p ≥ ω_s ≥ ω_r has no meaningful band).
MAX_DRAWS_PER_SET = 5


@dataclass(frozen=True)
class ParameterBand:
    """The response amplification's band from the parameters' standard errors.

    Attributes
    ----------
    method
        ``"delta"`` or ``"monte-carlo"``.
    f0_hz
        Small-amplitude frequencies [Hz].
    low, high
        The band's edges [-] at each f0 (vs the fixed oscillator).
    confidence
        Its coverage (0.95).
    varied
        The parameters that had a standard error (the others were held).
    n_curves
        Amplification curves computed (delta: 1 + 2k; Monte Carlo: the accepted sets).
    n_rejected
        Monte Carlo draws refused by the model's constraints (delta: 0).
    grid_steps
        The time grids of the curves' covariance runs, in steps (Monte Carlo: each f0 on one of
        them, :func:`band_grids`; empty when not said).
    """

    method: str
    f0_hz: Floats
    low: Floats
    high: Floats
    confidence: float
    varied: tuple[str, ...]
    n_curves: int
    n_rejected: int = 0
    grid_steps: tuple[int, ...] = ()

    def describe(self) -> str:
        """One line: method, coverage and cost."""
        how = (
            f"delta method ({self.n_curves} curves)"
            if self.method == "delta"
            else f"Monte Carlo over N = {self.n_curves} parameter sets"
            + _grids_text(self.grid_steps)
            + (
                f" ({self.n_rejected} draw{'s' * (self.n_rejected > 1)} refused by ω_p ≥ ω_s ≥ ω_r)"
                if self.n_rejected
                else ""
            )
        )
        return f"{100 * self.confidence:g} % band from the standard errors of " + (
            ", ".join(self.varied) + f", {how}"
        )


def vs_fixed_curve(model: GroundMotionModel, f0_hz: Floats, xi0: float, n_steps: int) -> Floats:
    """The response amplification vs the fixed oscillator at ``f0_hz`` (covariance method)."""
    from stepframe.stochastic.amplification import response_amplification
    from stepframe.stochastic.mean_square import analysis_grid

    grid = analysis_grid(model, n_steps=n_steps)
    result = response_amplification(model, 2 * math.pi * f0_hz, xi0, time_s=grid)
    return np.asarray(result.vs_fixed, dtype=np.float64)


def _grids_text(grid_steps: tuple[int, ...]) -> str:
    if not grid_steps:
        return ""
    if len(grid_steps) == 1:
        return f" at {grid_steps[0]:,} time steps"
    return f" at {grid_steps[0]:,}-{grid_steps[-1]:,} time steps by f0"


def band_grids(
    model: GroundMotionModel,
    f0_hz: Floats,
    xi0: float,
    n_steps: int,
    central: Floats | None = None,
) -> NDArray[np.int64]:
    """Time steps of each f0's grid in a Monte Carlo set's curve: the coarsest of ``n_steps``,
    its half, quarter and eighth (not below :data:`MIN_BAND_STEPS`) with
    :data:`BAND_STEPS_PER_PERIOD` steps a period of that f0 over the analysis's duration;
    ``n_steps`` for every f0 when the central curve so computed differs from the central curve
    on the analysis's grid (``central``, else computed) by more than
    :data:`BAND_STEP_TOLERANCE` at any f0.

    The band is a percentile interval of N curves whose edges move between seeds by a few
    percent of its half-width (:data:`~stepframe.pipeline.amplification.analysis.BAND_SAMPLES`);
    a covariance run costs in proportion to its steps, and an oscillator needs a fine grid only
    at high f0 (docs/benchmarks.md).
    """
    from stepframe.stochastic.mean_square import analysis_grid

    f0 = np.asarray(f0_hz, dtype=np.float64)
    duration_s = float(analysis_grid(model, n_steps=n_steps)[-1])
    needed = BAND_STEPS_PER_PERIOD * f0 * duration_s
    grids = np.full(f0.shape, n_steps, dtype=np.int64)
    coarser = n_steps // 2
    while coarser >= MIN_BAND_STEPS:
        grids[needed <= coarser] = coarser
        coarser //= 2
    if np.all(grids == n_steps):
        return grids
    fine = vs_fixed_curve(model, f0, xi0, n_steps) if central is None else central
    differs = np.max(np.abs(grid_curve(model, f0, xi0, grids) / fine - 1.0))
    return grids if differs <= BAND_STEP_TOLERANCE else np.full(f0.shape, n_steps, np.int64)


def grid_curve(
    model: GroundMotionModel, f0_hz: Floats, xi0: float, grid_steps: NDArray[np.int64]
) -> Floats:
    """:func:`vs_fixed_curve` with each f0 on its own grid of ``grid_steps`` steps (one run per
    distinct grid: the oscillators of a covariance run are independent)."""
    f0 = np.asarray(f0_hz, dtype=np.float64)
    curve = np.empty(f0.size)
    for steps in np.unique(grid_steps):
        on_grid = grid_steps == steps
        curve[on_grid] = vs_fixed_curve(model, f0[on_grid], xi0, int(steps))
    return curve


def _with(model: GroundMotionModel, values: Mapping[str, float]) -> GroundMotionModel:
    """The model with some parameters replaced (raises InputError when they break it)."""
    return replace(model, **dict(values))  # type: ignore[arg-type]  # float fields only


def parameter_band(
    model: GroundMotionModel,
    stderr: Mapping[str, float],
    f0_hz: Floats,
    xi0: float,
    *,
    n_steps: int,
    method: BandMethod = "monte-carlo",
    n_samples: int = BAND_SAMPLES,
    seed: int = 1,
    confidence: float = 0.95,
    central: Floats | None = None,
    jobs: int | None = 1,
    executor: Executor | None = None,
) -> ParameterBand | None:
    """The band of the response amplification from the parameters' standard errors.

    Parameters
    ----------
    model
        The site's ground-motion model (the combined values).
    stderr
        Standard error of each of :data:`VARIED` (rad/s or -); missing, NaN or zero: held.
    f0_hz
        Small-amplitude frequencies [Hz].
    xi0
        Oscillator damping ratio (fraction).
    n_steps
        Time steps of each covariance run (Monte Carlo: at most; :func:`band_grids`).
    method
        ``"delta"`` or ``"monte-carlo"`` (module docstring); ``"none"``: no band.
    n_samples
        Monte Carlo parameter sets.
    seed
        Monte Carlo seed.
    confidence
        Coverage of the band.
    central
        The curve at the model's own parameters, when already computed (delta method).
    jobs, executor
        Where the Monte Carlo curves are computed
        (:func:`stepframe.core.execution.call_each`; default this process): the same curves,
        bit for bit, on any number of workers.

    Returns
    -------
    ParameterBand or None
        None for ``"none"`` or when no parameter has a standard error.
    """
    if method not in ("delta", "monte-carlo", "none"):
        raise InputError(f"band {method!r}, expected 'delta', 'monte-carlo' or 'none'")
    if not 0 < confidence < 1:
        raise InputError(f"confidence = {confidence}, expected in (0, 1)")
    varied = tuple(
        name
        for name in VARIED
        if name in stderr and math.isfinite(stderr[name]) and stderr[name] > 0
    )
    if method == "none" or not varied:
        return None
    f0 = np.asarray(f0_hz, dtype=np.float64)
    if method == "delta":
        return _delta_band(model, stderr, varied, f0, xi0, n_steps, confidence, central)
    grids = band_grids(model, f0, xi0, n_steps, central)
    curves, rejected = monte_carlo_curves(
        model, stderr, varied, f0, xi0, grids, n_samples, seed, jobs=jobs, executor=executor
    )
    return _monte_carlo_band(curves, rejected, f0, varied, confidence, grids)


def _delta_band(
    model: GroundMotionModel,
    stderr: Mapping[str, float],
    varied: tuple[str, ...],
    f0: Floats,
    xi0: float,
    n_steps: int,
    confidence: float,
    central: Floats | None,
) -> ParameterBand:
    from scipy.stats import norm

    centre = vs_fixed_curve(model, f0, xi0, n_steps) if central is None else central
    log_centre = np.log(centre)
    variance = np.zeros_like(centre)
    n_curves = 1  # the central curve, given or computed here
    for name in varied:
        value, se = float(getattr(model, name)), float(stderr[name])
        step = DELTA_STEP * se
        sides = []
        for sign in (1.0, -1.0):
            try:
                moved = _with(model, {name: value + sign * step})
                sides.append((sign, np.log(vs_fixed_curve(moved, f0, xi0, n_steps))))
                n_curves += 1
            except InputError:  # the step crosses ω_p ≥ ω_s ≥ ω_r: a one-sided difference
                continue
        if len(sides) == 2:
            slope = (sides[0][1] - sides[1][1]) / (2 * step)
        else:
            sign, curve = sides[0]
            slope = sign * (curve - log_centre) / step
        variance += (slope * se) ** 2
    spread = np.exp(float(norm.ppf(0.5 + confidence / 2)) * np.sqrt(variance))
    return ParameterBand(
        "delta", f0, centre / spread, centre * spread, confidence, varied, n_curves
    )


def _normal_draws(
    mean: Floats, sd: Floats, count: int, seed: int, sampler: Sampler
) -> Iterator[Floats]:
    """Parameter sets from independent normals, in blocks of ``count``: scrambled Sobol points
    through the normal quantile (``"sobol"``), or independent pseudo-random draws."""
    from scipy.stats import norm, qmc

    if sampler == "random":
        rng = np.random.default_rng(seed)
        while True:
            yield from rng.normal(mean, sd, size=(count, mean.size))
    engine = qmc.Sobol(mean.size, scramble=True, seed=seed)
    while True:
        # a power of two keeps the Sobol block balanced; the open interval keeps ppf finite
        block = engine.random_base2(max(1, math.ceil(math.log2(count))))
        yield from mean + sd * norm.ppf(np.clip(block, 1e-12, 1 - 1e-12))


def monte_carlo_curves(
    model: GroundMotionModel,
    stderr: Mapping[str, float],
    varied: tuple[str, ...],
    f0: Floats,
    xi0: float,
    n_steps: int | NDArray[np.int64],
    n_samples: int,
    seed: int,
    *,
    sampler: Sampler = "sobol",
    jobs: int | None = 1,
    executor: Executor | None = None,
) -> tuple[Floats, int]:
    """``n_samples`` curves of parameter sets drawn from independent normals, shape
    ``(n_samples, f0.size)``, and the number of draws the model refused (drawn again).

    ``sampler``: scrambled Sobol points (randomised quasi-Monte Carlo, the default: the band's
    percentiles settle in fewer sets than with independent draws; docs/benchmarks.md) or
    ``"random"`` (independent pseudo-random draws). ``jobs``, ``executor``: where the curves
    are computed (:func:`stepframe.core.execution.call_each`); the parameter sets are drawn
    here first, so the curves are the same on any number of workers. ``n_steps``: the time
    steps of every f0's grid, or of each f0's (:func:`band_grids`).
    """
    from functools import partial

    from stepframe.core.execution import call_each

    mean = np.array([float(getattr(model, name)) for name in varied])
    sd = np.array([float(stderr[name]) for name in varied])
    samples: list[GroundMotionModel] = []
    rejected = 0
    draws = _normal_draws(mean, sd, n_samples, seed, sampler)
    while len(samples) < n_samples:
        if rejected > MAX_DRAWS_PER_SET * n_samples:
            raise InputError(
                f"{rejected} of the parameter draws break ω_p ≥ ω_s ≥ ω_r > 0 or ξ > 0, expected "
                "standard errors small enough for a band (use band = 'delta')"
            )
        draw = next(draws)
        try:
            samples.append(_with(model, dict(zip(varied, map(float, draw), strict=True))))
        except InputError:
            rejected += 1
    grids = np.broadcast_to(np.asarray(n_steps, dtype=np.int64), f0.shape)
    calls = [partial(grid_curve, sample, f0, xi0, grids) for sample in samples]
    curves = call_each(calls, jobs=jobs, executor=executor, stage="band")
    return np.vstack(curves), rejected


def _monte_carlo_band(
    curves: Floats,
    rejected: int,
    f0: Floats,
    varied: tuple[str, ...],
    confidence: float,
    grids: NDArray[np.int64],
) -> ParameterBand:
    """The band between the curves' percentiles of the two tails."""
    tail = 100 * (1 - confidence) / 2
    low, high = np.percentile(curves, [tail, 100 - tail], axis=0)
    steps = tuple(int(n) for n in np.unique(grids))
    return ParameterBand(
        "monte-carlo", f0, low, high, confidence, varied, len(curves), rejected, steps
    )


__all__ = [
    "BAND_STEPS_PER_PERIOD",
    "BAND_STEP_TOLERANCE",
    "MIN_BAND_STEPS",
    "VARIED",
    "BandMethod",
    "ParameterBand",
    "band_grids",
    "grid_curve",
    "monte_carlo_curves",
    "parameter_band",
    "vs_fixed_curve",
]
