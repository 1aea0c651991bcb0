"""Mean-square response of the time-varying oscillator (eqs. 6.1-6.2) to the B-P ground motion.

The oscillator is ``ẍ + 2β ẋ + ω(t)² x = -I_g(t) y(t)`` with a constant decay rate β = ξ_0 ω_0
(the damping coefficient of eq. 6.4; ω_0 is the oscillator's small-amplitude frequency, its
frequency at the start of the analysis) and ``y`` the unit-variance eq. 6.12 process
(:mod:`stepframe.stochastic.model`). Three methods, one function (:func:`mean_square_response`):

``"scalar"``: eq. 6.4, the slowly-varying first-order equation for q_11 = E[x²], with the closed
    form R_g of :mod:`stepframe.stochastic.correlation`. Integrated exactly as
    ``d/dt[q_11 ω_d e^{2βt}] = e^{2βt} ω_d I_g² R_g/(2ω²)`` (per step, the weight e^{2βt} times
    the quadratic through 3 Gauss-Legendre nodes integrated exactly, whatever 2βh), so
    its only error is eq. 6.4's own: exact in the stationary limit, it misses the oscillating part
    of transients and the lag of the response behind a fast-changing ω(t) or envelope (measured in
    bench/bench_mean_square.py). Cost: O(n_osc · n_steps) vectorised numpy, the cheapest.
    Needs an underdamped oscillator (ω(t) > β throughout).
``"covariance"``: the exact Liapunov matrix ODE ``Ṗ = AP + PAᵀ + GGᵀ`` of the augmented linear
    system (filter states y, ẏ and oscillator x, ẋ). Each step freezes the coefficients at its
    midpoint and advances P exactly for the frozen system:
    ``P_{k+1} = Φ (P_k - P_∞) Φᵀ + P_∞`` with Φ = exp(A h) (closed-form 2×2 blocks; the coupling
    block by 4-point Gauss-Legendre) and P_∞ the closed-form stationary covariance of the frozen
    system. Exact for constant coefficients whatever h (a step where ω h, ω_g h, β h/2 or
    α_g h/2 exceeds 2 is split into equal substeps, as the 4-point rule cannot integrate the
    coupling block over several oscillator periods); O(h²) in the time variation of the
    coefficients (6e-7 relative at 4,000 steps over 40 s for the paper's site; see
    bench/bench_mean_square.py). Cost: a numba kernel, O(n_osc · n_steps), about 0.2-0.35 µs per
    oscillator-step whose ω changes, 0.1 µs for a constant ω (its propagators kept).
    Needs ξ_0 ≥ 1e-6 (P_∞ grows like 1/ξ_0).
``"monte-carlo"``: N synthetic motions (:func:`stepframe.stochastic.synthetic.synthetic_motions`)
    through the oscillator, stepped exactly for frozen ω with linear interpolation of the samples
    (bias O((ω h_mc)²/12), about 0.1 % at the default ω_max h_mc = 0.1). Its statistical error is
    given by an exact chi-square confidence band (x is Gaussian with zero mean). Cost:
    O(N · n_osc · duration/h_mc) time (3-8 ms per realisation and oscillator for 40 s) and
    8·N·(duration/h_mc + n_osc·n_t) bytes (the motions and the kept x²).

The oscillator's frequency ω(t) is one of :class:`Constant`, :class:`Tracking`
(ω_0·ω_g(t)/ω_p), :class:`Given` (array or callable) or :class:`FrameDriven` (2π/T(A) with
A = factor·σ_x(t), solved self-consistently in time by a predictor-corrector per step).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

from stepframe.core import validation
from stepframe.core.jit import njit
from stepframe.core.memory import check_memory
from stepframe.core.results import Status
from stepframe.errors import InputError
from stepframe.stochastic.correlation import r_g
from stepframe.stochastic.envelope import default_envelope
from stepframe.stochastic.methods import MeanSquareMethod

if TYPE_CHECKING:
    import xarray as xr
from stepframe.stochastic.model import GroundMotionModel

Method = MeanSquareMethod
#: Smallest ξ_0 the covariance method accepts (its P_∞ grows like 1/ξ_0; see module docstring).
MIN_XI0_COVARIANCE = 1e-6

_GL4_X, _GL4_W = np.polynomial.legendre.leggauss(4)
_GL3_X, _GL3_W = np.polynomial.legendre.leggauss(3)

Floats = NDArray[np.float64]


# --------------------------------------------------------------------------------------------
# ω(t) specifications
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Constant:
    """ω(t) = ω_0 for each oscillator frequency in ``omega_0_rad_s`` [rad/s]."""

    omega_0_rad_s: ArrayLike


@dataclass(frozen=True)
class Tracking:
    """ω(t) = ω_0·ω_g(t)/ω_p: equal to ω_0 at the start, to ω_g(t) when ω_0 = ω_p [rad/s]."""

    omega_0_rad_s: ArrayLike


@dataclass(frozen=True)
class Given:
    """ω(t) given as samples on the analysis grid or as a callable of time [rad/s].

    ``omega_rad_s`` is an array of shape ``(n_t,)`` or ``(n_osc, n_t)`` on ``time_s`` (linearly
    interpolated between samples), or a callable taking record times ``t`` [s] (1-D array) and
    returning shape ``(n_t,)`` or ``(n_osc, n_t)``. ω_0 is ω at the first time.
    """

    omega_rad_s: ArrayLike | Callable[[Floats], ArrayLike]


@dataclass(frozen=True)
class FrameDriven:
    """ω(t) = 2π/T(A(t)) from a frame's period-amplitude law, with A = factor·σ_x(t).

    ``period_s_of_amplitude_m`` maps an amplitude A ≥ 0 [m] to the period T [s] (finite, > 0);
    ``amplitude_factor`` is √2 by default (the amplitude of a harmonic of RMS σ_x). ω_0 = 2π/T(0).
    """

    period_s_of_amplitude_m: Callable[[float], float]
    amplitude_factor: float = math.sqrt(2.0)


OmegaSpec = Constant | Tracking | Given | FrameDriven


@dataclass(frozen=True)
class MeanSquareResult:
    """Mean-square displacement response over time, for one or more oscillators.

    Attributes
    ----------
    method
        The method used.
    omega_path
        ``"constant"``, ``"tracking"``, ``"given"`` or ``"frame"``.
    alpha_reading
        The ground-motion model's reading of eq. 6.11 (``"eq-6-11"`` or ``"paper"``).
    time_s
        Record times [s], shape ``(n_t,)``.
    omega_0_rad_s
        Small-amplitude frequencies ω_0 [rad/s], shape ``(n_osc,)``.
    xi0
        Damping ratio at ω_0 (β = ξ_0 ω_0).
    omega_rad_s
        The frequency path ω(t) [rad/s], shape ``(n_osc, n_t)``.
    mean_square_m2
        E[x²] [m²] for the intensity in m/s², shape ``(n_osc, n_t)``.
    lower_m2, upper_m2
        Monte Carlo confidence band of E[x²] (None for the other methods).
    n_realisations, seed, confidence
        Monte Carlo settings (None for the other methods).
    status
        ``"ok"``, or ``"lower_bound"`` when the integration stopped early (a frame's period law
        gave no finite period: overturning); values after that time are NaN, so the peak so far
        is a lower bound of the true one.
    message
        Where and why it stopped (empty when ``"ok"``).
    """

    method: Method
    omega_path: str
    alpha_reading: str
    time_s: Floats
    omega_0_rad_s: Floats
    xi0: float
    omega_rad_s: Floats
    mean_square_m2: Floats
    lower_m2: Floats | None = None
    upper_m2: Floats | None = None
    n_realisations: int | None = None
    seed: int | None = None
    confidence: float | None = None
    status: Status = "ok"
    message: str = ""
    samples: dict[str, Floats] = field(default_factory=dict, repr=False)

    @property
    def rms_m(self) -> Floats:
        """σ_x(t) [m], shape ``(n_osc, n_t)``."""
        return np.asarray(np.sqrt(self.mean_square_m2))

    @property
    def peak_rms_m(self) -> Floats:
        """max_t σ_x [m] per oscillator, shape ``(n_osc,)`` (NaN-free part only)."""
        return np.asarray(np.sqrt(np.nanmax(self.mean_square_m2, axis=1)))

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary: method, path, reading, status, ω_0 [rad/s], peak σ_x [m]."""
        return {
            "method": self.method,
            "omega_path": self.omega_path,
            "alpha_reading": self.alpha_reading,
            "status": self.status,
            "message": self.message,
            "xi0": self.xi0,
            "omega_0_rad_s": self.omega_0_rad_s.tolist(),
            "peak_rms_m": self.peak_rms_m.tolist(),
            "n_realisations": self.n_realisations,
            "seed": self.seed,
            "confidence": self.confidence,
        }

    def to_dataset(self) -> xr.Dataset:
        """The result as an ``xarray.Dataset`` with dims ``(oscillator, time)`` and units."""
        import xarray as xr

        dims = ("oscillator", "time")
        data: dict[str, Any] = {
            "mean_square": (dims, self.mean_square_m2, {"units": "m2"}),
            "omega": (dims, self.omega_rad_s, {"units": "rad/s"}),
        }
        if self.lower_m2 is not None and self.upper_m2 is not None:
            data["mean_square_lower"] = (dims, self.lower_m2, {"units": "m2"})
            data["mean_square_upper"] = (dims, self.upper_m2, {"units": "m2"})
        return xr.Dataset(
            data,
            coords={
                "time": ("time", self.time_s, {"units": "s"}),
                "omega_0": ("oscillator", self.omega_0_rad_s, {"units": "rad/s"}),
            },
            attrs={
                "method": self.method,
                "omega_path": self.omega_path,
                "alpha_reading": self.alpha_reading,
                "xi0": self.xi0,
                "status": self.status,
                "message": self.message,
            },
        )


# --------------------------------------------------------------------------------------------
# numba kernels (small on purpose: compile time counts in cold start)
# --------------------------------------------------------------------------------------------


@njit(cache=True)
def _propagator(w2: float, beta: float, t: float) -> tuple[float, float, float, float]:
    """exp([[0, 1], [-w2, -2β]] t) as (p00, p01, p10, p11); any damping, any t ≥ 0."""
    big_w = w2 - beta * beta
    x2 = big_w * t * t
    if abs(x2) < 1e-8:  # series: avoids 0/0 at critical damping
        c = 1.0 - x2 / 2.0
        s = t * (1.0 - x2 / 6.0)
    elif big_w > 0.0:
        r = math.sqrt(big_w)
        c = math.cos(r * t)
        s = math.sin(r * t) / r
    else:
        r = math.sqrt(-big_w)
        c = math.cosh(r * t)
        s = math.sinh(r * t) / r
    e = math.exp(-beta * t)
    return e * (c + beta * s), e * s, -e * w2 * s, e * (c - beta * s)


@njit(cache=True)
def _stationary(
    w: float, b: float, wg: float, a: float, ig: float
) -> tuple[float, float, float, float, float, float]:
    """P_∞ of the frozen system: E[xy], E[xẏ], E[ẋy], E[ẋẏ], E[x²], E[ẋ²] (see correlation)."""
    w2, wg2 = w * w, wg * wg
    d = (wg2 - w2) ** 2 + 4.0 * (a + b) * (b * wg2 + a * w2)
    big_a = wg2 - w2 + 2.0 * b * (a + b)
    big_b = 2.0 * (a + b)
    i_c = ((b + 2.0 * a) * big_a + big_b * (w2 - b * b)) / d
    i_s = (w2 - wg2 + 4.0 * a * (a + b)) / d
    m_c = -wg2 * big_a / d
    m_s = -wg2 * big_b / d
    xx = (i_c + b * i_s) / (2.0 * b * w2)
    return (
        -ig * i_s,
        -ig * m_s,
        -ig * (i_c - b * i_s),
        -ig * (m_c - b * m_s),
        ig * ig * xx,
        ig * ig * (w2 * xx - i_s),
    )


@njit(cache=True)
def _advance(
    state: tuple[float, float, float, float, float, float, float],
    o00: float, o01: float, o10: float, o11: float,
    x00: float, x01: float, x10: float, x11: float,
    w: float, b: float, wg: float, a: float, ig: float,
    pff0: float, pff1: float, pff2: float,
    p00: float, p01: float, p10: float, p11: float,
) -> tuple[float, float, float, float, float, float, float]:  # fmt: skip
    """One oscillator's 7 moments after one step, from the step's propagators (scalars only).

    state = (E[xy], E[xẏ], E[ẋy], E[ẋẏ], E[x²], E[xẋ], E[ẋ²]); o = exp(O h) of the oscillator,
    x = its coupling block, pff = the filter's moments at the step start (E[y²], E[yẏ], E[ẏ²]),
    p = exp(F h) of the filter. Scalars and a tuple, not arrays: a compiled function called
    with arrays costs tens of nanoseconds of reference counting per call, a sixth of a step.
    """
    sxy, sxyd, svy, svyd, sxx, svv = _stationary(w, b, wg, a, ig)
    # deviations from the frozen system's stationary covariance
    f00 = pff0 - 1.0
    f01 = pff1
    f11 = pff2 - wg * wg
    c00 = state[0] - sxy
    c01 = state[1] - sxyd
    c10 = state[2] - svy
    c11 = state[3] - svyd
    q00 = state[4] - sxx
    q01 = state[5]
    q11 = state[6] - svv
    # Y = X Δ_FF + Φ_O Δ_OF (rows: x, ẋ; columns: y, ẏ)
    y00 = x00 * f00 + x01 * f01 + o00 * c00 + o01 * c10
    y01 = x00 * f01 + x01 * f11 + o00 * c01 + o01 * c11
    y10 = x10 * f00 + x11 * f01 + o10 * c00 + o11 * c10
    y11 = x10 * f01 + x11 * f11 + o10 * c01 + o11 * c11
    # Z = X Δ_FO + Φ_O Δ_OO (Δ_FO = Δ_OFᵀ)
    z00 = x00 * c00 + x01 * c01 + o00 * q00 + o01 * q01
    z01 = x00 * c10 + x01 * c11 + o00 * q01 + o01 * q11
    z10 = x10 * c00 + x11 * c01 + o10 * q00 + o11 * q01
    z11 = x10 * c10 + x11 * c11 + o10 * q01 + o11 * q11
    return (
        y00 * p00 + y01 * p01 + sxy,
        y00 * p10 + y01 * p11 + sxyd,
        y10 * p00 + y11 * p01 + svy,
        y10 * p10 + y11 * p11 + svyd,
        y00 * x00 + y01 * x01 + z00 * o00 + z01 * o01 + sxx,
        y00 * x10 + y01 * x11 + z00 * o10 + z01 * o11,
        y10 * x10 + y11 * x11 + z10 * o10 + z11 * o11 + svv,
    )


#: Largest phase (rate × time step) the 4-point Gauss-Legendre coupling block is trusted with:
#: the largest of the oscillator's ω and β/2 and the filter's ω_g and α/2 times the (sub)step
#: (a decay, e^{-2βs}, is far easier for the rule than an oscillation: the broadband ξ = 3 site,
#: 2αh = 2.8, was within 1.2e-10 unsplit). Beyond it a frozen
#: step is split into equal substeps (exact composition of the same frozen system). Unsplit, the
#: block's error was 1e-7 at a phase of 2 (far below the O(h²) error of the frozen coefficients
#: on such a grid; the site band's coarse grids, four steps a period, keep their phase π/2), the
#: peak σ_x² 1.5 % low at ω h = 12.6 (200 Hz on the default 0.01 s grid of the paper's site) and
#: 3.75 times too high at ω h = 100.
MAX_STEP_PHASE = 2.0


@njit(cache=True)
def _substeps(rate: float, h: float) -> int:
    """How many equal substeps keep ``rate · h`` per substep within :data:`MAX_STEP_PHASE`."""
    return max(1, math.ceil(rate * h / MAX_STEP_PHASE))


@njit(cache=True)
def _split_step(
    state: tuple[float, float, float, float, float, float, float],
    w: float, b: float, wg: float, a: float, ig: float,
    pf0: float, pf1: float, pf2: float,
    h: float, n_sub: int, nodes: Floats, weights: Floats,
) -> tuple[float, float, float, float, float, float, float]:  # fmt: skip
    """One frozen step of length h as ``n_sub`` frozen substeps (the same system: exact).

    ``nodes``, ``weights`` are the full step's quadrature; each substep uses them scaled by
    1/n_sub, and the filter's moments are carried from the step's start through the substeps.
    """
    hs = h / n_sub
    w2, wg2 = w * w, wg * wg
    o00, o01, o10, o11 = _propagator(w2, b, hs)
    f00, f01, f10, f11 = _propagator(wg2, a, hs)
    n_nodes = nodes.size
    x00 = x01 = x10 = x11 = 0.0
    for n in range(n_nodes):
        s = nodes[n] / n_sub
        _, u0, _, u1 = _propagator(w2, b, hs - s)
        r0, r1, _, _ = _propagator(wg2, a, s)
        g = -ig * weights[n] / n_sub
        x00 += g * u0 * r0
        x01 += g * u0 * r1
        x10 += g * u1 * r0
        x11 += g * u1 * r1
    for _ in range(n_sub):
        state = _advance(state, o00, o01, o10, o11, x00, x01, x10, x11, w, b, wg, a, ig,
                         pf0, pf1, pf2, f00, f01, f10, f11)  # fmt: skip
        # the frozen filter's moments at the next substep (stationary E[y²] = 1, E[ẏ²] = ω_g²)
        d00, d01, d11 = pf0 - 1.0, pf1, pf2 - wg2
        z00, z01 = f00 * d00 + f01 * d01, f00 * d01 + f01 * d11
        z10, z11 = f10 * d00 + f11 * d01, f10 * d01 + f11 * d11
        pf0 = z00 * f00 + z01 * f01 + 1.0
        pf1 = z00 * f10 + z01 * f11
        pf2 = z10 * f10 + z11 * f11 + wg2
    return state


@njit(cache=True)
def _covariance_step(
    state: Floats,
    w: float,
    b: float,
    wg: float,
    a: float,
    ig: float,
    pff: Floats,
    phif: Floats,
    frows: Floats,
    h: float,
    nodes: Floats,
    weights: Floats,
) -> None:
    """Advance one oscillator's 7 moments in place over one step (coefficients frozen).

    state = [E[xy], E[xẏ], E[ẋy], E[ẋẏ], E[x²], E[xẋ], E[ẋ²]]; pff = filter moments at the step
    start [E[y²], E[yẏ], E[ẏ²]]; phif = exp(F h) flattened; frows[n] = first row of exp(F s_n).
    """
    moments = (state[0], state[1], state[2], state[3], state[4], state[5], state[6])
    n_sub = _substeps(max(w, wg, 0.5 * b, 0.5 * a), h)
    if n_sub > 1:
        new = _split_step(moments, w, b, wg, a, ig, pff[0], pff[1], pff[2], h, n_sub, nodes,
                          weights)  # fmt: skip
        for m in range(7):
            state[m] = new[m]
        return
    w2 = w * w
    o00, o01, o10, o11 = _propagator(w2, b, h)
    # coupling block X = -I_g ∫ exp(O(h-s))[:, 1] ⊗ exp(F s)[0, :] ds
    x00 = x01 = x10 = x11 = 0.0
    for n in range(nodes.size):
        _, u0, _, u1 = _propagator(w2, b, h - nodes[n])
        g = -ig * weights[n]
        x00 += g * u0 * frows[n, 0]
        x01 += g * u0 * frows[n, 1]
        x10 += g * u1 * frows[n, 0]
        x11 += g * u1 * frows[n, 1]
    new = _advance(moments, o00, o01, o10, o11, x00, x01, x10, x11, w, b, wg, a, ig,
                   pff[0], pff[1], pff[2], phif[0], phif[1], phif[2], phif[3])  # fmt: skip
    for m in range(7):
        state[m] = new[m]


@njit(cache=True)
def _covariance_run(
    omega_mid: Floats,
    beta: Floats,
    wg_mid: Floats,
    a_mid: Floats,
    ig_mid: Floats,
    pff: Floats,
    phif: Floats,
    frows: Floats,
    h: float,
    nodes: Floats,
    weights: Floats,
) -> Floats:
    """E[x²] for every oscillator (rows of omega_mid) at every grid time, from rest.

    The step of :func:`_covariance_step`, written out with scalars (no array passed per step)
    and with the oscillator's propagators kept while its ω does not change: the fixed
    oscillator of every amplification curve computes them once instead of at every step
    (5 times cheaper; the tracking one 1.6 times, docs/benchmarks.md, issue 30's band).
    """
    n_osc, n_steps = omega_mid.shape
    n_nodes = nodes.size
    out = np.zeros((n_osc, n_steps + 1))
    u0 = np.empty(n_nodes)
    u1 = np.empty(n_nodes)
    for i in range(n_osc):
        state = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
        b = beta[i]
        last_w = math.nan
        o00 = o01 = o10 = o11 = 0.0
        for k in range(n_steps):
            w = omega_mid[i, k]
            # a step too coarse for the coupling quadrature is split (the rule of
            # _covariance_step, step by step, so that a frame's run and a fixed one agree)
            n_sub = _substeps(max(w, wg_mid[k], 0.5 * b, 0.5 * a_mid[k]), h)
            if n_sub > 1:
                state = _split_step(state, w, b, wg_mid[k], a_mid[k], ig_mid[k], pff[k, 0],
                                    pff[k, 1], pff[k, 2], h, n_sub, nodes, weights)  # fmt: skip
                out[i, k + 1] = state[4]
                continue
            if w != last_w:
                w2 = w * w
                o00, o01, o10, o11 = _propagator(w2, b, h)
                for n in range(n_nodes):
                    _, u0[n], _, u1[n] = _propagator(w2, b, h - nodes[n])
                last_w = w
            ig = ig_mid[k]
            # coupling block X = -I_g ∫ exp(O(h-s))[:, 1] ⊗ exp(F s)[0, :] ds
            x00 = x01 = x10 = x11 = 0.0
            for n in range(n_nodes):
                g = -ig * weights[n]
                x00 += g * u0[n] * frows[k, n, 0]
                x01 += g * u0[n] * frows[k, n, 1]
                x10 += g * u1[n] * frows[k, n, 0]
                x11 += g * u1[n] * frows[k, n, 1]
            state = _advance(state, o00, o01, o10, o11, x00, x01, x10, x11, w, b, wg_mid[k],
                             a_mid[k], ig, pff[k, 0], pff[k, 1], pff[k, 2], phif[k, 0],
                             phif[k, 1], phif[k, 2], phif[k, 3])  # fmt: skip
            out[i, k + 1] = state[4]
    return out


@njit(cache=True)
def _forced_step(w_mid: Floats, beta: Floats, h: float) -> tuple[Floats, Floats, Floats]:
    """Φ, Γ_0, Γ_1 of the exact step ``z' = Φ z + Γ_0 f_0 + Γ_1 f_1`` for forcing f linear in
    the step (f_0 at the start, f_1 at the end), frozen ω; shapes (m, 2, 2), (m, 2), (m, 2).

    Γ_0 = ∫ exp(O(h-s)) e_2 (1 - s/h) ds, Γ_1 = ∫ exp(O(h-s)) e_2 s/h ds by 4-point
    Gauss-Legendre (the integrand is smooth; error far below 1e-10 for ω h ≤ 0.5).
    """
    m = w_mid.size
    phi = np.empty((m, 2, 2))
    g0 = np.zeros((m, 2))
    g1 = np.zeros((m, 2))
    for k in range(m):
        w2 = w_mid[k] ** 2
        p = _propagator(w2, beta[k], h)
        phi[k, 0, 0], phi[k, 0, 1], phi[k, 1, 0], phi[k, 1, 1] = p
        for n in range(_GL4_X.size):
            s = h * (1.0 + _GL4_X[n]) / 2.0
            wt = h * _GL4_W[n] / 2.0
            _, u0, _, u1 = _propagator(w2, beta[k], h - s)
            g0[k, 0] += wt * u0 * (1.0 - s / h)
            g0[k, 1] += wt * u1 * (1.0 - s / h)
            g1[k, 0] += wt * u0 * s / h
            g1[k, 1] += wt * u1 * s / h
    return phi, g0, g1


@njit(cache=True)
def _white_noise_run(
    omega_mid: Floats, beta: float, q: Floats, h: float
) -> tuple[Floats, Floats, Floats]:
    """E[x²], E[xẋ], E[ẋ²] of ẍ + 2βẋ + ω²x = w, E[w w'] = q δ, from rest (exact per step)."""
    n = omega_mid.size
    xx, xv, vv = np.zeros(n + 1), np.zeros(n + 1), np.zeros(n + 1)
    for k in range(n):
        w2 = omega_mid[k] ** 2
        o00, o01, o10, o11 = _propagator(w2, beta, h)
        sxx = q[k] / (4.0 * beta * w2)
        svv = q[k] / (4.0 * beta)
        d00, d01, d11 = xx[k] - sxx, xv[k], vv[k] - svv
        z00 = o00 * d00 + o01 * d01
        z01 = o00 * d01 + o01 * d11
        z10 = o10 * d00 + o11 * d01
        z11 = o10 * d01 + o11 * d11
        xx[k + 1] = z00 * o00 + z01 * o01 + sxx
        xv[k + 1] = z00 * o10 + z01 * o11
        vv[k + 1] = z10 * o10 + z11 * o11 + svv
    return xx, xv, vv


def white_noise_response(
    omega_rad_s: ArrayLike, xi: float, noise_intensity: ArrayLike, time_s: ArrayLike
) -> tuple[Floats, Floats, Floats]:
    """Covariance of ``ẍ + 2ξω_0 ẋ + ω(t)² x = w`` from rest, w white with E[w(t)w(t+τ)] = q δ(τ).

    The simplest rung of the covariance method (same exact frozen-coefficient step), used to check
    it against Caughey and Stumpf's closed form. ``omega_rad_s`` and ``noise_intensity`` are
    constants or arrays on the uniform grid ``time_s`` [s]; β = ξ ω(t_0).

    Returns
    -------
    E[x²] [m²], E[xẋ] [m²/s], E[ẋ²] [m²/s²] at ``time_s`` (for w in m/s² · √s).
    """
    t = _uniform_grid(time_s)
    n = t.size
    w = np.broadcast_to(np.asarray(omega_rad_s, dtype=np.float64), (n,))
    q = np.broadcast_to(np.asarray(noise_intensity, dtype=np.float64), (n,))
    if not (math.isfinite(xi) and xi >= MIN_XI0_COVARIANCE):
        raise InputError(f"xi = {xi}, expected ≥ {MIN_XI0_COVARIANCE}")
    if np.any(~np.isfinite(w)) or np.any(w <= 0):
        raise InputError("omega has values ≤ 0 or not finite, expected > 0")
    h = float(t[1] - t[0])
    return _white_noise_run((w[:-1] + w[1:]) / 2, xi * float(w[0]), (q[:-1] + q[1:]) / 2, h)


# --------------------------------------------------------------------------------------------
# grid, envelope and ω(t)
# --------------------------------------------------------------------------------------------


def _uniform_grid(time_s: ArrayLike) -> Floats:
    t = np.asarray(time_s, dtype=np.float64)
    if t.ndim != 1 or t.size < 2 or not np.all(np.isfinite(t)):
        raise InputError("time_s must be a 1-D array of ≥ 2 finite times, expected a uniform grid")
    step = np.diff(t)
    if not (np.all(step > 0) and np.allclose(step, step[0], rtol=1e-9, atol=0)):
        raise InputError("time_s is not uniform and increasing, expected a uniform grid")
    return t


def analysis_grid(
    model: GroundMotionModel, duration_s: float | None = None, n_steps: int = 4000
) -> Floats:
    """The default time grid: ``n_steps`` steps from 0 to ``duration_s`` (default t0 + 2 t_dur)."""
    if duration_s is None:
        duration_s = model.t0_s + 2.0 * model.t_dur_s
    if not (math.isfinite(duration_s) and duration_s > 0):
        raise InputError(f"duration_s = {duration_s}, expected a positive number")
    # The covariance and Monte Carlo paths keep a few float64 arrays per step.
    n_steps = validation.count("n_steps", n_steps, bytes_each=8 * 16, low=2)
    return np.linspace(0.0, duration_s, n_steps + 1)


EnvelopeFn = Callable[[Floats], ArrayLike]
#: Fewest samples of the analysis grid within the default envelope's strong motion (I_g at or
#: above :data:`~stepframe.stochastic.envelope.DEFAULT_DURATION_THRESHOLD` of its peak). The
#: paper's site on the default 4,000 steps has 1,961. At 100 Hz, against 32,000 steps, the
#: amplification vs fixed is 3.8 % off with 30 samples, 2.1 % with 40, 0.9 % with 60 and 0.5 %
#: with 80; with 2 (t_max = 19.99 s, t_dur = 20 s) it read 16.4 for a converged 6.67, status ok.
MIN_STRONG_MOTION_SAMPLES = 64


def _check_envelope_resolved(
    model: GroundMotionModel, grid: Floats, values: Floats, peak_intensity: float
) -> None:
    """Refuse a default envelope whose strong motion falls between the grid's times.

    As t_max nears t_dur the envelope's exponent grows without bound (t_max = 19.999 s, t_dur
    = 20 s: a ≈ 2·10⁹, a pulse some 2 ms wide): on a grid of 0.01 s the motion is nowhere, the
    response ~1e-19 m, and every ratio of two such responses is rounding noise.
    """
    from stepframe.stochastic.envelope import DEFAULT_DURATION_THRESHOLD

    strong = int(np.count_nonzero(values >= DEFAULT_DURATION_THRESHOLD * peak_intensity))
    peak_time = model.t0_s + model.t_max_s
    if strong < MIN_STRONG_MOTION_SAMPLES and not grid[0] <= peak_time <= grid[-1]:
        raise InputError(
            f"time_s runs from {grid[0]:g} to {grid[-1]:g} s, which misses the envelope's peak at "
            f"t0 + t_max = {peak_time:g} s, expected a grid over the strong motion (default "
            f"0 to t0 + 2 t_dur = {model.t0_s + 2 * model.t_dur_s:g} s)"
        )
    if strong < MIN_STRONG_MOTION_SAMPLES:
        step = float(grid[1] - grid[0])
        raise InputError(
            f"t_max_s = {model.t_max_s:g}, t_dur_s = {model.t_dur_s:g}: the envelope's strong "
            f"motion (I_g ≥ {DEFAULT_DURATION_THRESHOLD:g} of its peak) holds {strong} of the "
            f"analysis's {grid.size - 1} time steps of {step:.3g} s, expected ≥ "
            f"{MIN_STRONG_MOTION_SAMPLES} (t_dur - t_max = {model.t_dur_s - model.t_max_s:.3g} "
            "s: more time steps, or a t_max further from t_dur)"
        )


def _envelope_fn(
    model: GroundMotionModel, envelope: EnvelopeFn | None, peak_intensity: float
) -> Callable[[Floats], Floats]:
    if envelope is None:
        if not (math.isfinite(peak_intensity) and peak_intensity > 0):
            raise InputError(f"peak_intensity = {peak_intensity}, expected a positive number")

        def default(t: Floats) -> Floats:
            return default_envelope(
                t, model.t_max_s, model.t_dur_s, peak_intensity, t0_s=model.t0_s
            )

        default(np.zeros(1))  # raises the envelope's own InputError early (t_max must be < t_dur)
        return default

    def given(t: Floats) -> Floats:
        values = np.broadcast_to(np.asarray(envelope(t), dtype=np.float64), t.shape)
        if not np.all(np.isfinite(values)):
            raise InputError("envelope returned NaN or infinite values, expected finite values")
        return np.asarray(values)

    return given


class _Path:
    """ω(t) evaluated at arbitrary times for the non-frame specifications."""

    def __init__(self, spec: OmegaSpec, model: GroundMotionModel, grid: Floats) -> None:
        self.spec = spec
        self.model = model
        self.grid = grid
        self.name: str
        if isinstance(spec, Constant):
            self.name = "constant"
            self.omega_0 = _positive_vector(spec.omega_0_rad_s, "omega_0_rad_s")
        elif isinstance(spec, Tracking):
            self.name = "tracking"
            self.omega_0 = _positive_vector(spec.omega_0_rad_s, "omega_0_rad_s")
        elif isinstance(spec, Given):
            self.name = "given"
            self.samples: Floats | None = None
            if not callable(spec.omega_rad_s):
                samples = np.atleast_2d(np.asarray(spec.omega_rad_s, dtype=np.float64))
                if samples.ndim != 2 or samples.shape[1] != grid.size:
                    raise InputError(
                        f"omega array has shape {np.shape(spec.omega_rad_s)}, expected "
                        f"({grid.size},) or (n_osc, {grid.size}) on the time grid"
                    )
                self.samples = samples
            self.omega_0 = self.at(grid[:1])[:, 0]
        else:
            raise InputError(f"omega specification {spec!r}, expected Constant, Tracking, Given")

    def at(self, t: Floats) -> Floats:
        """ω at times t [rad/s], shape (n_osc, t.size)."""
        spec = self.spec
        if isinstance(spec, Constant):
            out = np.repeat(self.omega_0[:, None], t.size, axis=1)
        elif isinstance(spec, Tracking):
            ratio = self.model.omega_g(t) / self.model.omega_p_rad_s
            out = self.omega_0[:, None] * ratio[None, :]
        elif isinstance(spec, Given) and self.samples is not None:
            out = np.array([np.interp(t, self.grid, row) for row in self.samples])
        else:
            assert isinstance(spec, Given) and callable(spec.omega_rad_s)
            out = np.atleast_2d(np.asarray(spec.omega_rad_s(t), dtype=np.float64))
            if out.shape[1] != t.size:
                raise InputError(
                    f"omega callable returned shape {out.shape}, expected ({t.size},) or "
                    f"(n_osc, {t.size})"
                )
        if not (np.all(np.isfinite(out)) and np.all(out > 0)):
            raise InputError("omega(t) has values ≤ 0 or not finite, expected positive values")
        return np.asarray(out)


#: Oscillator frequencies accepted [rad/s] (periods from 63 µs to 6,000 s): outside, the time
#: step or the transient of the Liapunov solution leaves floating point.
OMEGA_RANGE_RAD_S = (1e-3, 1e5)


def _positive_vector(values: ArrayLike, name: str) -> Floats:
    vector = validation.finite_array(name, values, positive_values=True)
    low, high = OMEGA_RANGE_RAD_S
    for value in vector:
        validation.in_range(name, float(value), low, high, unit="rad/s")
    return vector


class _FrameLaw:
    """ω = 2π/T(factor·σ) from the frame's period law, with a clear message when T fails."""

    def __init__(self, spec: FrameDriven) -> None:
        if not (math.isfinite(spec.amplitude_factor) and spec.amplitude_factor > 0):
            raise InputError(
                f"amplitude_factor = {spec.amplitude_factor}, expected a positive number"
            )
        self.spec = spec
        self.omega_0 = self.omega(0.0)
        if not math.isfinite(self.omega_0):
            raise InputError(
                "period law T(A = 0) is not a finite positive period, expected T(0) > 0"
            )

    def omega(self, sigma_m: float) -> float:
        """2π/T(A) [rad/s]; NaN when T(A) is not finite and positive (overturning)."""
        amplitude = self.spec.amplitude_factor * float(sigma_m)
        period = float(self.spec.period_s_of_amplitude_m(amplitude))
        if not (math.isfinite(period) and period > 0):
            return math.nan
        return 2 * math.pi / period


# --------------------------------------------------------------------------------------------
# the three methods
# --------------------------------------------------------------------------------------------


def _filter_tables(
    model: GroundMotionModel, grid: Floats
) -> tuple[Floats, Floats, Floats, Floats, Floats, Floats]:
    """Per-step filter quantities: midpoint ω_g, α_g, exp(F h), first rows of exp(F s_n), P_FF."""
    h = float(grid[1] - grid[0])
    mid = grid[:-1] + h / 2
    wg = np.asarray(model.omega_g(mid), dtype=np.float64)
    ag = np.asarray(model.alpha_g(mid), dtype=np.float64)
    nodes = h * (1 + _GL4_X) / 2
    w0 = float(model.omega_g(grid[0]))
    phif, frows, pff = _filter_kernel(wg, ag, h, nodes, w0)
    return wg, ag, phif, frows, pff, nodes


@njit(cache=True)
def _filter_kernel(
    wg: Floats, ag: Floats, h: float, nodes: Floats, w0: float
) -> tuple[Floats, Floats, Floats]:
    """The step propagators of the filter and its covariance P_FF at every grid time (compiled:
    a Python loop here cost about half of a 150-step covariance run)."""
    n = wg.size
    phif = np.empty((n, 4))
    frows = np.empty((n, nodes.size, 2))
    for k in range(n):
        phif[k, 0], phif[k, 1], phif[k, 2], phif[k, 3] = _propagator(wg[k] ** 2, ag[k], h)
        for m in range(nodes.size):
            p = _propagator(wg[k] ** 2, ag[k], nodes[m])
            frows[k, m, 0] = p[0]
            frows[k, m, 1] = p[1]
    pff = np.empty((n + 1, 3))
    # stationary start, as synthetic_motions(initial="stationary")
    pff[0, 0], pff[0, 1], pff[0, 2] = 1.0, 0.0, w0**2
    for k in range(n):
        p00, p01, p10, p11 = phif[k, 0], phif[k, 1], phif[k, 2], phif[k, 3]
        d00, d01, d11 = pff[k, 0] - 1.0, pff[k, 1], pff[k, 2] - wg[k] ** 2
        z00, z01 = p00 * d00 + p01 * d01, p00 * d01 + p01 * d11
        z10, z11 = p10 * d00 + p11 * d01, p10 * d01 + p11 * d11
        pff[k + 1, 0] = z00 * p00 + z01 * p01 + 1.0
        pff[k + 1, 1] = z00 * p10 + z01 * p11
        pff[k + 1, 2] = z10 * p10 + z11 * p11 + wg[k] ** 2
    return phif, frows, pff


def _covariance(
    model: GroundMotionModel,
    path: _Path | _FrameLaw,
    xi0: float,
    grid: Floats,
    env: Callable[[Floats], Floats],
) -> tuple[Floats, Floats, Floats, str]:
    if not xi0 >= MIN_XI0_COVARIANCE:
        raise InputError(
            f"xi0 = {xi0}, expected ≥ {MIN_XI0_COVARIANCE} for method='covariance' (its step "
            "uses the stationary covariance, which grows like 1/xi0); use method='scalar' or "
            "'monte-carlo' for an undamped oscillator"
        )
    h = float(grid[1] - grid[0])
    mid = grid[:-1] + h / 2
    wg, ag, phif, frows, pff, nodes = _filter_tables(model, grid)
    weights = h * _GL4_W / 2
    ig = env(mid)
    beta = xi0 * np.atleast_1d(path.omega_0)
    if isinstance(path, _Path):
        omega_mid = path.at(mid)
        out = _covariance_run(omega_mid, beta, wg, ag, ig, pff, phif, frows, h, nodes, weights)
        return path.omega_0, path.at(grid), out, ""
    # frame-driven: a predictor-corrector per step on the single oscillator
    out = np.full((1, grid.size), np.nan)
    omegas = np.full((1, grid.size), np.nan)
    state = np.zeros(7)
    out[0, 0] = 0.0
    omegas[0, 0] = path.omega_0
    b = float(beta[0])
    for k in range(mid.size):
        w_start = omegas[0, k]
        trial = state.copy()
        args = (wg[k], ag[k], ig[k], pff[k], phif[k], frows[k], h, nodes, weights)
        _covariance_step(trial, w_start, b, *args)
        w_end = path.omega(math.sqrt(max(trial[4], 0.0)))
        if not math.isfinite(w_end):
            return (
                np.atleast_1d(path.omega_0),
                omegas,
                out,
                _overturned(grid[k + 1], trial[4], path),
            )
        _covariance_step(state, (w_start + w_end) / 2, b, *args)
        out[0, k + 1] = state[4]
        w_next = path.omega(math.sqrt(max(state[4], 0.0)))
        if not math.isfinite(w_next):
            return (
                np.atleast_1d(path.omega_0),
                omegas,
                out,
                _overturned(grid[k + 1], state[4], path),
            )
        omegas[0, k + 1] = w_next
    return np.atleast_1d(path.omega_0), omegas, out, ""


def _overturned(t: float, mean_square: float, law: _FrameLaw) -> str:
    amplitude = law.spec.amplitude_factor * math.sqrt(max(mean_square, 0.0))
    return (
        f"stopped at t = {t:.4g} s: the period law gave no finite period at amplitude "
        f"A = {amplitude:.4g} m (overturning?)"
    )


def _exponential_weights(rate: Floats, h: float, offsets: Floats) -> Floats:
    """Weights W[i, n] with ``∫_0^h e^{-rate_i (h - s)} f(s) ds = Σ_n W[i, n] f(offsets[n])``
    exact for f quadratic through the 3 ``offsets`` (product integration).

    Gauss-Legendre on the product lost the exponential once rate·h was large: for the stiff
    oscillator ω_0 = 1e4 rad/s, ξ_0 = 0.05 on a 0.01 s grid (2βh = 10) eq. 6.4 gave 0.93 of the
    quasi-static I²/ω⁴, at 1e5 rad/s 0.0004 of it.
    """
    c = np.asarray(rate, dtype=np.float64)[:, None] * h
    j = np.arange(3)[None, :]
    # moments m_j = ∫_0^1 e^{-c v} v^j dv (v = (h - s)/h): a series for small c, else the
    # stable upward recurrence m_j = (j m_{j-1} - e^{-c})/c
    terms = np.arange(30)[None, None, :]
    fact = np.cumprod(np.concatenate([[1.0], np.arange(1, 30)]))[None, None, :]
    small = np.sum(
        (-c[:, :, None]) ** terms / fact / (j[:, :, None] + terms + 1), axis=2
    )  # shape (n, 3)
    with np.errstate(divide="ignore", invalid="ignore"):
        big = np.empty((c.shape[0], 3))
        big[:, 0] = -np.expm1(-c[:, 0]) / c[:, 0]
        for order in (1, 2):
            big[:, order] = (order * big[:, order - 1] - np.exp(-c[:, 0])) / c[:, 0]
    moments = np.where(c > 1.0, big, small)
    # Σ_n W_n v_n^j = h m_j at the nodes' v_n = (h - s_n)/h
    v = (h - np.asarray(offsets)) / h
    vandermonde = v[None, :] ** np.arange(3)[:, None]  # [j, n]
    return np.asarray(h * np.linalg.solve(vandermonde, moments.T).T)


def _scalar(
    model: GroundMotionModel,
    path: _Path | _FrameLaw,
    xi0: float,
    grid: Floats,
    env: Callable[[Floats], Floats],
) -> tuple[Floats, Floats, Floats, str]:
    h = float(grid[1] - grid[0])
    omega_0 = np.atleast_1d(path.omega_0)
    beta = xi0 * omega_0
    offsets = h * (1 + _GL3_X) / 2  # nodes within each step

    def forcing(t: Floats, w: Floats) -> Floats:
        """e^{-2β(t_end - t)} ω_d I² R_g/(2ω²) at nodes t (columns) for rows of w."""
        b = beta[:, None]
        if np.any(w <= b):
            raise InputError(
                f"omega(t) falls to {float(np.min(w)):.4g} rad/s ≤ xi0·omega0: eq. 6.4 needs an "
                "underdamped oscillator, expected omega(t) > xi0·omega0; use method='covariance'"
            )
        rg = r_g(w, b, model.omega_g(t)[None, :], model.alpha_g(t)[None, :])
        return np.asarray(np.sqrt(w**2 - b**2) * env(t)[None, :] ** 2 * rg / (2 * w**2))

    decay = np.exp(-2 * beta * h)
    n_osc = omega_0.size
    if isinstance(path, _Path):
        nodes = (grid[:-1, None] + offsets[None, :]).ravel()
        w_nodes = path.at(nodes)
        f = forcing(nodes, w_nodes).reshape(n_osc, grid.size - 1, offsets.size)
        kernel = _exponential_weights(2 * beta, h, offsets)
        increments = np.einsum("ikn,in->ik", f, kernel)
        w_grid = path.at(grid)
        if np.any(w_grid <= beta[:, None]):
            forcing(grid, w_grid)  # raises the underdamped message
        wd = np.sqrt(w_grid**2 - beta[:, None] ** 2)
        out = np.zeros((n_osc, grid.size))
        action = np.zeros(n_osc)  # q_11 ω_d
        for k in range(grid.size - 1):
            action = decay * action + increments[:, k]
            out[:, k + 1] = action / wd[:, k + 1]
        return omega_0, w_grid, out, ""
    out = np.full((1, grid.size), np.nan)
    omegas = np.full((1, grid.size), np.nan)
    out[0, 0], omegas[0, 0] = 0.0, path.omega_0
    action_1 = 0.0
    b = float(beta[0])
    frame_weights = _exponential_weights(2 * beta[:1], h, offsets)[0]
    for k in range(grid.size - 1):
        t_nodes = grid[k] + offsets
        w_start = omegas[0, k]
        w_end = w_start
        for _ in range(2):  # predictor-corrector on the end-of-step frequency
            w_nodes = w_start + (w_end - w_start) * offsets / h
            f = forcing(t_nodes, w_nodes[None, :])[0]
            new_action = decay[0] * action_1 + float(np.sum(f * frame_weights))
            q = new_action / math.sqrt(w_end**2 - b**2)
            w_end = path.omega(math.sqrt(max(q, 0.0)))
            if not math.isfinite(w_end):
                return omega_0, omegas, out, _overturned(grid[k + 1], q, path)
        action_1 = new_action
        out[0, k + 1] = action_1 / math.sqrt(w_end**2 - b**2)
        omegas[0, k + 1] = w_end
    return omega_0, omegas, out, ""


#: Largest max(ω, ω_p)·h of the Monte Carlo's integration step: the sampled motions, linear
#: between samples, lose the input's high frequencies as it grows (E[x²] at the paper's site,
#: f_0 = 3.12 Hz, N = 3,000: within the sampling error to 1.0, 3 % low at 1.5, 10 % at 2.3,
#: 23 % at 4.6, with a 95 % band that excluded the exact value).
MAX_MC_PHASE = 1.0


def _monte_carlo(
    model: GroundMotionModel,
    path: _Path | _FrameLaw,
    xi0: float,
    grid: Floats,
    env: Callable[[Floats], Floats],
    n_realisations: int,
    seed: int | None,
    mc_dt_s: float | None,
) -> tuple[Floats, Floats, Floats, Floats, str]:
    """Sample x² at the grid times, shape (n_osc, N, n_t), plus ω at the grid."""
    from stepframe.stochastic.synthetic import synthetic_motions

    if grid[0] != 0.0:
        raise InputError(
            f"time_s starts at {grid[0]} s, expected 0 for method='monte-carlo' (synthetic "
            "motions start at record time 0)"
        )
    h_grid = float(grid[1] - grid[0])
    omega_0 = np.atleast_1d(path.omega_0)
    if isinstance(path, _Path):
        w_max = max(float(np.max(path.at(grid))), model.omega_p_rad_s)
    else:
        w_max = max(float(path.omega_0), model.omega_p_rad_s)
    given = mc_dt_s is not None
    if mc_dt_s is None:
        mc_dt_s = 0.1 / w_max
    if not (math.isfinite(mc_dt_s) and mc_dt_s > 0):
        raise InputError(f"mc_dt_s = {mc_dt_s}, expected a positive number")
    if given and mc_dt_s > h_grid * (1 + 1e-9):
        raise InputError(
            f"mc_dt_s = {mc_dt_s:g} s is coarser than the analysis grid's step {h_grid:.4g} s, "
            "expected ≤ it (the motions are integrated at least once per grid step)"
        )
    if mc_dt_s * w_max > MAX_MC_PHASE:
        raise InputError(
            f"mc_dt_s = {mc_dt_s:g} s gives max(omega, omega_p)·mc_dt_s = {mc_dt_s * w_max:.3g} "
            f"rad, expected ≤ {MAX_MC_PHASE:g} (beyond it the sampled motions lose their high "
            f"frequencies: E[x²] 10 % low at 2.3; default 0.1/max(omega, omega_p) = "
            f"{0.1 / w_max:.3g} s)"
        )
    sub = max(1, math.ceil(h_grid / mc_dt_s))  # substeps per grid step
    n_fine = (grid.size - 1) * sub + 1
    # x² of each oscillator and motion on the grid; the motions (and their white noise and
    # forcing) and each oscillator's ω and step matrices on the fine grid.
    check_memory(
        8.0 * (omega_0.size * n_realisations * grid.size + n_fine * (3 * n_realisations + 12)),
        f"a Monte Carlo of {n_realisations} motions of {n_fine} steps for {omega_0.size} "
        "oscillator(s)",
        "fewer motions, frequencies or time steps",
    )
    h = h_grid / sub
    fine = grid[0] + h * np.arange((grid.size - 1) * sub + 1)
    duration = float(fine[-1] - fine[0])
    _, acc = synthetic_motions(
        model,
        duration_s=duration,
        dt_s=h,
        n_realisations=n_realisations,
        seed=seed,
        envelope=env(fine),
    )
    # synthetic_motions samples from 0 with step h; our fine grid starts at grid[0] (0 by default)
    forcing = -acc[:, : fine.size]
    beta = xi0 * omega_0
    n_osc = omega_0.size

    def step_matrices(w_mid: Floats, b: Floats) -> tuple[Floats, Floats, Floats]:
        return _forced_step(np.ascontiguousarray(w_mid), np.ascontiguousarray(b), h)

    x = np.zeros((n_osc, n_realisations))
    v = np.zeros((n_osc, n_realisations))
    squares = np.zeros((n_osc, n_realisations, grid.size))
    omegas = np.full((n_osc, grid.size), np.nan)
    status = ""
    if isinstance(path, _Path):
        omegas[:] = path.at(grid)
        w_mid_all = path.at(fine[:-1] + h / 2)
        for i in range(n_osc):
            phi, g0, g1 = step_matrices(w_mid_all[i], np.full(fine.size - 1, beta[i]))
            xi_, vi = x[i], v[i]
            for k in range(fine.size - 1):
                f0, f1 = forcing[:, k], forcing[:, k + 1]
                p, a0, a1 = phi[k], g0[k], g1[k]
                xi_, vi = (
                    p[0, 0] * xi_ + p[0, 1] * vi + a0[0] * f0 + a1[0] * f1,
                    p[1, 0] * xi_ + p[1, 1] * vi + a0[1] * f0 + a1[1] * f1,
                )
                if (k + 1) % sub == 0:
                    squares[i, :, (k + 1) // sub] = xi_**2
        return omega_0, omegas, squares, forcing, status
    omegas[0, 0] = path.omega_0
    b = np.array([beta[0]])
    xs, vs = x[0], v[0]
    w_now = float(path.omega_0)
    for k in range(fine.size - 1):
        f0, f1 = forcing[:, k], forcing[:, k + 1]
        w_trial = w_now
        new_x, new_v = xs, vs
        for _ in range(2):  # predictor-corrector on the ensemble's end-of-step frequency
            phi, g0, g1 = step_matrices(np.array([(w_now + w_trial) / 2]), b)
            p, a0, a1 = phi[0], g0[0], g1[0]
            new_x = p[0, 0] * xs + p[0, 1] * vs + a0[0] * f0 + a1[0] * f1
            new_v = p[1, 0] * xs + p[1, 1] * vs + a0[1] * f0 + a1[1] * f1
            w_trial = path.omega(math.sqrt(float(np.mean(new_x**2))))
            if not math.isfinite(w_trial):
                status = _overturned(float(fine[k + 1]), float(np.mean(new_x**2)), path)
                squares[0, :, k // sub + 1 :] = np.nan  # grid times not reached
                return omega_0, omegas, squares, forcing, status
        xs, vs, w_now = new_x, new_v, w_trial
        if (k + 1) % sub == 0:
            squares[0, :, (k + 1) // sub] = xs**2
            omegas[0, (k + 1) // sub] = w_now
    return omega_0, omegas, squares, forcing, status


@dataclass(frozen=True)
class MeanSquareProblem:
    """What a mean-square method receives (see :func:`mean_square_response`).

    Attributes
    ----------
    model
        The ground-motion model.
    path
        The oscillator's frequency path: ``omega_0`` [rad/s] and either ``at(t)`` (a given
        ω(t), shape ``(n_osc, n_t)``) or, for a frame, ``omega(amplitude_m)``.
    xi0
        Damping ratio at ω_0.
    time_s
        The uniform analysis grid [s].
    envelope
        I_g(t) [m/s²] as a callable of time.
    n_realisations, seed, confidence, mc_dt_s, keep_samples
        Monte Carlo settings (ignored by the other methods).
    """

    model: GroundMotionModel
    path: _Path | _FrameLaw
    xi0: float
    time_s: Floats
    envelope: Callable[[Floats], Floats]
    n_realisations: int = 500
    seed: int | None = None
    confidence: float = 0.95
    mc_dt_s: float | None = None
    keep_samples: bool = False

    def common(self) -> dict[str, Any]:
        """The fields every :class:`MeanSquareResult` of this problem shares."""
        return {
            "omega_path": "frame" if isinstance(self.path, _FrameLaw) else self.path.name,
            "alpha_reading": self.model.alpha_reading,
            "time_s": self.time_s,
            "xi0": self.xi0,
        }


class MeanSquareMethodFunction(Protocol):
    """A mean-square method: a :class:`MeanSquareProblem` in, a :class:`MeanSquareResult` out."""

    __name__: str

    def __call__(self, problem: MeanSquareProblem, /) -> MeanSquareResult: ...


def _deterministic(
    name: Method,
    solver: Callable[
        [GroundMotionModel, _Path | _FrameLaw, float, Floats, Callable[[Floats], Floats]],
        tuple[Floats, Floats, Floats, str],
    ],
    problem: MeanSquareProblem,
) -> MeanSquareResult:
    p = problem
    omega_0, omegas, out, stopped = solver(p.model, p.path, p.xi0, p.time_s, p.envelope)
    return MeanSquareResult(
        name, omega_0_rad_s=omega_0, omega_rad_s=omegas, mean_square_m2=out,
        status="lower_bound" if stopped else "ok", message=stopped, **p.common(),
    )  # fmt: skip


def covariance_method(problem: MeanSquareProblem) -> MeanSquareResult:
    """The exact covariance (Liapunov) ODE of the augmented linear system (module docstring)."""
    return _deterministic("covariance", _covariance, problem)


def scalar_method(problem: MeanSquareProblem) -> MeanSquareResult:
    """The scalar slowly-varying eq. 6.4 (module docstring)."""
    return _deterministic("scalar", _scalar, problem)


def monte_carlo_method(problem: MeanSquareProblem) -> MeanSquareResult:
    """Monte Carlo with simulated motions, χ² confidence band (module docstring)."""
    p = problem
    # Each realisation keeps its squared response on the grid and its motion (float64 each).
    n_realisations = validation.count(
        "n_realisations", p.n_realisations, bytes_each=8 * 2 * p.time_s.size, low=2
    )
    if not 0 < p.confidence < 1:
        raise InputError(f"confidence = {p.confidence}, expected 0 < confidence < 1")
    omega_0, omegas, squares, _, stopped = _monte_carlo(
        p.model, p.path, p.xi0, p.time_s, p.envelope, n_realisations, p.seed, p.mc_dt_s
    )
    mean, lower, upper = chi_square_band(squares, p.confidence)
    return MeanSquareResult(
        "monte-carlo",
        omega_0_rad_s=omega_0,
        omega_rad_s=omegas,
        mean_square_m2=mean,
        lower_m2=lower,
        upper_m2=upper,
        n_realisations=n_realisations,
        seed=p.seed,
        confidence=p.confidence,
        status="lower_bound" if stopped else "ok",
        message=stopped,
        samples={"x2": squares} if p.keep_samples else {},
        **p.common(),
    )


#: The mean-square methods by name, cheap to dear
#: (:data:`stepframe.stochastic.methods.MeanSquareMethod` names them).
METHODS: dict[str, MeanSquareMethodFunction] = {
    "scalar": scalar_method,
    "covariance": covariance_method,
    "monte-carlo": monte_carlo_method,
}


def check_mean_square_memory(n_oscillators: int, n_steps: int) -> None:
    """Refuse a deterministic mean square (covariance or scalar) of ``n_oscillators`` over
    ``n_steps`` time steps that would need more than the memory budget
    (:func:`stepframe.core.memory.check_memory`): E[x²] and ω at the grid and at the midpoints
    per oscillator, and the filter's tables per step, float64 each."""
    check_memory(
        8.0 * (n_steps + 1) * (3 * n_oscillators + 20),
        f"the mean square of {n_oscillators} oscillator(s) over {n_steps} time steps",
        "fewer frequencies or time steps",
    )


def mean_square_response(
    model: GroundMotionModel,
    omega: OmegaSpec | float | Callable[[Floats], ArrayLike],
    xi0: float,
    *,
    method: Method | MeanSquareMethodFunction = "covariance",
    time_s: ArrayLike | None = None,
    envelope: EnvelopeFn | None = None,
    peak_intensity: float = 1.0,
    n_realisations: int = 500,
    seed: int | None = None,
    confidence: float = 0.95,
    mc_dt_s: float | None = None,
    keep_samples: bool = False,
) -> MeanSquareResult:
    """Mean-square displacement E[x²](t) of ``ẍ + 2ξ_0ω_0 ẋ + ω(t)² x = -I_g(t) y(t)``.

    Parameters
    ----------
    model
        The ground-motion model (ω_g(t), α_g(t); its ``alpha_reading`` is reported).
    omega
        The oscillator frequency: :class:`Constant`, :class:`Tracking`, :class:`Given` or
        :class:`FrameDriven`; a plain number means ``Constant``, a callable ``Given``.
    xi0
        Damping ratio at ω_0 (a fraction, ≥ 0): the decay rate β = ξ_0 ω_0 is held constant.
    method
        ``"scalar"`` (eq. 6.4), ``"covariance"`` (exact Liapunov ODE) or ``"monte-carlo"``; see
        the module docstring for each one's cost and error.
    time_s
        Uniform analysis grid [s] (record time); default :func:`analysis_grid` (4,000 steps to
        t0 + 2 t_dur). The oscillator starts at rest at its first time.
    envelope
        I_g(t) [m/s²] as a callable of time; default ``default_envelope`` with ``peak_intensity``.
    peak_intensity
        max I_g of the default envelope [m/s²].
    n_realisations, seed, confidence, mc_dt_s
        Monte Carlo: number of motions, seed of ``numpy.random.default_rng``, level of the band,
        and the integration step [s] (default 0.1/max(ω, ω_p); at most the grid's step and
        1/max(ω, ω_p), :data:`MAX_MC_PHASE`).
    keep_samples
        Monte Carlo: keep the per-realisation x² at the grid in ``result.samples["x2"]``.

    Returns
    -------
    MeanSquareResult

    Raises
    ------
    InputError
        Bad arguments, or a method's limits (scalar: ω(t) ≤ β; covariance: ξ_0 < 1e-6).
    """
    if callable(method):
        implementation: MeanSquareMethodFunction = method
    elif method in METHODS:
        implementation = METHODS[method]
    else:
        raise InputError(f"method = {method!r}, expected one of {tuple(METHODS)} or a function")
    # Over-damped oscillators are modelled (ξ₀ up to 5); 5 and above read as a percentage.
    xi0 = validation.damping_fraction("xi0", xi0, high=5.0)
    grid = analysis_grid(model) if time_s is None else _uniform_grid(time_s)
    spec: OmegaSpec
    if isinstance(omega, Constant | Tracking | Given | FrameDriven):
        spec = omega
    elif callable(omega):
        spec = Given(omega)
    else:
        spec = Constant(omega)
    path: _Path | _FrameLaw = (
        _FrameLaw(spec) if isinstance(spec, FrameDriven) else _Path(spec, model, grid)
    )
    env = _envelope_fn(model, envelope, peak_intensity)
    if envelope is None:
        _check_envelope_resolved(model, grid, env(grid), peak_intensity)
    check_mean_square_memory(np.atleast_1d(path.omega_0).size, grid.size - 1)
    problem = MeanSquareProblem(
        model, path, float(xi0), grid, env, n_realisations, seed, confidence, mc_dt_s, keep_samples
    )
    return implementation(problem)


def chi_square_band(squares: Floats, confidence: float) -> tuple[Floats, Floats, Floats]:
    """Sample mean of x² over axis -2 and its exact band for a zero-mean Gaussian x.

    N·mean/σ² follows χ²_N, so σ² lies in [N·mean/χ²_{N,1-a/2}, N·mean/χ²_{N,a/2}] with
    probability ``confidence`` = 1 - a.
    """
    from scipy import stats

    n = squares.shape[-2]
    mean = np.mean(squares, axis=-2)
    tail = (1 - confidence) / 2
    lower = n * mean / stats.chi2.ppf(1 - tail, n)
    upper = n * mean / stats.chi2.ppf(tail, n)
    return np.asarray(mean), np.asarray(lower), np.asarray(upper)


__all__ = [
    "METHODS",
    "Constant",
    "FrameDriven",
    "Given",
    "MeanSquareMethodFunction",
    "MeanSquareProblem",
    "MeanSquareResult",
    "Method",
    "Tracking",
    "analysis_grid",
    "chi_square_band",
    "covariance_method",
    "mean_square_response",
    "monte_carlo_method",
    "scalar_method",
    "white_noise_response",
]
