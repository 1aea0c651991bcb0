"""The frame's instantaneous frequency ω_f(t) and the work the ground does on it, from a
simulated history.

**Energy and amplitude.** Without damping, impacts or ground motion, eqs. 4.11-4.12 conserve

    E = ½ẋ² + V(|x|),   V(y) = ½ω₁²y² (y ≤ x_c),
                        V(y) = ½ω₁²x_c² + γ₁(y - x_c) - ½ω₂²(y² - x_c²) (y > x_c),

(ẋ is continuous at lift-off, and V is the integral of the restoring term of each phase: ω₁²x
unstepped, γ₁ sign x - ω₂²x stepped). V rises to its maximum V(x*) at the unstable equilibrium
x* = γ₁/ω₂². A state (x, ẋ) with |x| < x* and E < V(x*) lies on a periodic orbit of the free
conservative frame, whose amplitude A solves V(A) = E:

    A = √(2E)/ω₁                                     if E ≤ V(x_c)   (never steps),
    A = x* - √((x* - x_c)² - 2(E - V(x_c))/ω₂²)       otherwise;

any other state has no periodic orbit (the free frame would overturn). This is the period-
amplitude law's own model (:mod:`stepframe.structure.period_amplitude`, which builds T(A) from the
same two phases joined at x_c with the same speed).

**ω_f(t).** The frame's instantaneous frequency is read from its own swings, half-cycle by
half-cycle, between the zero crossings of x (located by linear interpolation between samples;
x passes zero at its fastest, so a ripple from the ground does not add crossings):

- a half-cycle in which the frame never leaves the unstepped phase is linear motion at ω₁,
  ω_f = ω₁ exactly, however it is forced;
- a half-cycle in which it steps (any sample stepped or held on the surface) has the frequency
  of its duration τ, ω_f = π/τ (at most ω₁): the period the frame actually swings with, which a
  free conservative cycle of amplitude A makes 2π/T(A) of the period-amplitude law, and which a
  ground motion that has captured the frame sets to its own;
- the swings before the first crossing and after the last (the start, an excursion that ends by
  overturning, the end of the history) have no measured duration: there ω_f is the law's
  2π/T(A(t)) at the swing amplitude A(t).

The swing amplitude A(t) is read where the state itself says it: at each turning point (ẋ = 0,
located between samples on the cubic through x and ẋ at both ends) E = V(|x|), so the swing's
amplitude is |x| there; between turning points A(t) is interpolated linearly in time; before
the first one it starts from the energy amplitude of the initial state; after the last one it
is held, or, on an excursion that ends by overturning, it is the larger of that and the energy
amplitude of the state (∞, so the law's frequency 0, once the free frame could not return).
2π/T(A(t)) is the frame's free frequency at its amplitude; under a ground motion strong enough
to entrain the stepped frame (its force P₂ẍ_g as large as the stepped phase's restoring
γ₁ - ω₂²|x|) the swings are longer than that frequency says, and the measured π/τ is where the
frame actually is. A rigid block (x_c = 0) at rest has T(0) = 0 and a law frequency ∞.

**Work of the ground.** Multiplying either phase's equation by ẋ gives
dE/dt = -P ẍ_g ẋ - (viscous) with P = P₁ unstepped and P₂ stepped: the ground's power on the
frame, per unit of the model's mass (the relative input energy of Uang and Bertero 1990,
"Evaluation of seismic energy in structures", EESD 19, 77-90, for the two-phase model). Over a
sample interval, with ẍ_g linear and x known with ẋ at both ends,

    ∫ ẍ_g ẋ dt = Δx·(a_i + a_{i+1})/2 + (a_{i+1} - a_i)(ẋ_{i+1} - ẋ_i)·Δt/12,

exact for a cubic x(t) (integration by parts, then the trapezoid rule with its end correction
for ∫x dt). An interval holding a lift-off or a touchdown takes the mean of the two ends' P and
is approximate (ẍ jumps there, and ẋ at an impact): the energy balance of a run with ten
stepping episodes closes within 0.12 % (tests/structure/test_frame_frequency.py), and to 1e-7
between switches.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from stepframe.structure.status import Model

if TYPE_CHECKING:
    import xarray as xr

    from stepframe.structure.simulator import SimulationResult

Floats = NDArray[np.float64]

AMPLITUDE = "swing amplitude: |x| at the turning points, interpolated"
LAW = "the period-amplitude law's frequency at the swing amplitude, 2π/T(A)"


@dataclass(frozen=True)
class ModelBackbone:
    """The constants of the period-amplitude law taken from the simulator's :class:`Model`
    (a :class:`~stepframe.structure.period_amplitude.Backbone`)."""

    omega_1_rad_s: float
    omega_2_rad_s: float
    x_c_m: float
    x_star_m: float

    @property
    def is_rigid_block(self) -> bool:
        """True for x_c = 0 (no unstepped phase)."""
        return self.x_c_m == 0.0

    @property
    def gamma_1_m_s2(self) -> float:
        """γ₁ = ω₂² x* [m/s²]."""
        return self.omega_2_rad_s**2 * self.x_star_m


def backbone_of(model: Model) -> ModelBackbone:
    """The backbone constants of a simulator model (ω₁, ω₂, x_c and x* = γ₁/ω₂²)."""
    return ModelBackbone(
        float(model.omega_1_rad_s),
        float(model.omega_2_rad_s),
        float(model.x_c_m),
        float(model.gamma_1_m_s2) / float(model.omega_2_rad_s) ** 2,
    )


def potential(y_m: Floats, backbone: ModelBackbone) -> Floats:
    """V(y) of the conservative two-phase model at |x| = y [m²/s²] (module docstring)."""
    from stepframe.structure._frequency_kernel import potentials

    y = np.asarray(y_m, dtype=np.float64)
    return np.asarray(potentials(y.ravel(), *backbone_constants(backbone))).reshape(y.shape)


def backbone_constants(backbone: ModelBackbone) -> tuple[float, float, float, float]:
    """ω₁, ω₂, x_c and x* of the backbone, the kernels' arguments."""
    return (backbone.omega_1_rad_s, backbone.omega_2_rad_s, backbone.x_c_m, backbone.x_star_m)


def energy(x_m: Floats, v_m_s: Floats, backbone: ModelBackbone) -> Floats:
    """E = ½ẋ² + V(|x|) of each state [m²/s²]."""
    return np.asarray(0.5 * v_m_s**2 + potential(np.abs(x_m), backbone))


def energy_amplitude_m(x_m: Floats, v_m_s: Floats, backbone: ModelBackbone) -> Floats:
    """Amplitude A of the free conservative orbit through each state [m]; ∞ where there is none
    (|x| ≥ x* or E ≥ V(x*): the free frame would overturn)."""
    from stepframe.structure._frequency_kernel import energy_amplitudes

    x, v = np.broadcast_arrays(np.asarray(x_m, dtype=np.float64), np.asarray(v_m_s, np.float64))
    flat = energy_amplitudes(np.ravel(x), np.ravel(v), *backbone_constants(backbone))
    return np.asarray(flat).reshape(x.shape)


def turning_points(
    x_m: Floats, v_m_s: Floats, dt_s: float
) -> tuple[Floats, Floats]:  # fmt: skip
    """Times [s] and |x| [m] of the turning points of x (ẋ = 0) between or at the samples.

    Where ẋ changes sign between samples i and i+1, the turning point is the zero of the
    derivative of the cubic Hermite interpolant through (x, ẋ) at both ends (error O(Δt⁴) for a
    smooth x); a sample with ẋ = 0 exactly (a hold on the surface) is not a turning point
    (:func:`stepframe.structure._frequency_kernel.turning_points`).
    """
    from stepframe.structure import _frequency_kernel

    times, amplitudes = _frequency_kernel.turning_points(
        np.ascontiguousarray(x_m, dtype=np.float64),
        np.ascontiguousarray(v_m_s, dtype=np.float64),
        float(dt_s),
    )
    return np.asarray(times), np.asarray(amplitudes)


def swing_amplitude_m(
    x_m: Floats,
    v_m_s: Floats,
    dt_s: float,
    backbone: ModelBackbone,
    *,
    overturns: bool = False,
    at: NDArray[np.intp] | None = None,
) -> Floats:
    """The swing amplitude A(t) at each sample [m] (module docstring).

    Parameters
    ----------
    x_m, v_m_s
        The history up to the end of motion (overturning), at spacing ``dt_s`` [s].
    backbone
        The frame's law constants.
    overturns
        The history ends by overturning: after its last turning point A(t) also follows the
        energy amplitude (∞ once the free frame could not return).
    at
        Sample numbers to evaluate A at (default every sample); the turning points are looked
        for only around them (the two either side of each sample are all its A reads).
    """
    from stepframe.structure._frequency_kernel import swing_law

    samples = np.arange(x_m.size) if at is None else np.asarray(at, dtype=np.intp)
    amplitude, _ = swing_law(
        np.ascontiguousarray(x_m, dtype=np.float64), np.ascontiguousarray(v_m_s, dtype=np.float64),
        float(dt_s), samples.astype(np.int64), bool(overturns), *backbone_constants(backbone),
    )  # fmt: skip
    return np.asarray(amplitude)


def frequency_rad_s(amplitude_m: Floats, backbone: ModelBackbone) -> Floats:
    """ω = 2π/T(A) of the law at each amplitude [rad/s]; 0 where A is ∞ (no periodic orbit)."""
    from stepframe.structure._frequency_kernel import law_frequencies

    a = np.asarray(amplitude_m, dtype=np.float64)
    return np.asarray(law_frequencies(a.ravel(), *backbone_constants(backbone))).reshape(a.shape)


def zero_crossings(
    x_m: Floats, v_m_s: Floats, dt_s: float
) -> tuple[NDArray[np.intp], Floats]:  # fmt: skip
    """Samples i after which x changes sign (x > 0 against x ≤ 0 at i + 1) and the crossing times
    [s]: the linear interpolation between the two samples, refined by one Newton step on the
    cubic through x and ẋ at both ends (error O(Δt⁴) for a smooth x;
    :func:`stepframe.structure._frequency_kernel.zero_crossings`)."""
    from stepframe.structure import _frequency_kernel

    samples, times = _frequency_kernel.zero_crossings(
        np.ascontiguousarray(x_m, dtype=np.float64),
        np.ascontiguousarray(v_m_s, dtype=np.float64),
        float(dt_s),
    )
    return np.asarray(samples, dtype=np.intp), np.asarray(times)


def swing_frequency_rad_s(
    x_m: Floats, v_m_s: Floats, phase: NDArray[np.int8], dt_s: float, backbone: ModelBackbone,
    *, overturns: bool = False, law_everywhere: bool = True,
    crossings: tuple[NDArray[np.intp], Floats] | None = None,
) -> tuple[Floats, Floats, Floats]:  # fmt: skip
    """ω_f(t) [rad/s], the swing amplitude A(t) [m] and the law's frequency at it 2π/T(A(t))
    [rad/s] at each sample (module docstring).

    Parameters
    ----------
    x_m, v_m_s, phase
        The history up to the end of motion (overturning), at spacing ``dt_s`` [s].
    backbone
        The frame's law constants.
    overturns
        The history ends by overturning (see :func:`swing_amplitude_m`).
    law_everywhere
        False: A(t) and the law's frequency only where ω_f needs them (before the first zero
        crossing and after the last), NaN between: ω_f is the same, at a third of the cost for
        a history of many half-cycles (the moving-resonance index's path, docs/benchmarks.md).
    crossings
        :func:`zero_crossings` of this history when the caller has them already (the index
        cuts the response into half-cycles at the same crossings); found here otherwise.
    """
    from stepframe.structure._frequency_kernel import swing_frequencies

    i, z = zero_crossings(x_m, v_m_s, dt_s) if crossings is None else crossings
    omega, amplitude, law = swing_frequencies(
        np.ascontiguousarray(x_m, dtype=np.float64), np.ascontiguousarray(v_m_s, dtype=np.float64),
        np.ascontiguousarray(phase, dtype=np.int8), float(dt_s), np.asarray(i, dtype=np.int64),
        np.asarray(z, dtype=np.float64), bool(law_everywhere), bool(overturns),
        *backbone_constants(backbone), True,
    )  # fmt: skip
    return np.asarray(omega), np.asarray(amplitude), np.asarray(law)


def interval_work(
    x_m: Floats, v_m_s: Floats, phase: NDArray[np.int8], ground_acc_m_s2: Floats, dt_s: float,
    p_1: float, p_2: float,
) -> Floats:  # fmt: skip
    """Work of the ground on the frame over each sample interval [m²/s²] (module docstring).

    Parameters
    ----------
    x_m, v_m_s, phase
        The history at the sample times (n samples).
    ground_acc_m_s2
        The ground acceleration the frame felt at the same times (n samples; zeros in a tail).
    dt_s
        Sampling interval [s].
    p_1, p_2
        Participation factors of the two phases [-].

    Returns
    -------
    numpy.ndarray
        n - 1 values: the work over [t_i, t_{i+1}].
    """
    from stepframe.structure import _frequency_kernel

    return np.asarray(
        _frequency_kernel.interval_work(
            np.ascontiguousarray(x_m, dtype=np.float64),
            np.ascontiguousarray(v_m_s, dtype=np.float64),
            np.ascontiguousarray(phase, dtype=np.int8),
            np.ascontiguousarray(ground_acc_m_s2, dtype=np.float64),
            float(dt_s), float(p_1), float(p_2),
        )
    )  # fmt: skip


def half_cycle_starts(x_m: Floats, v_m_s: Floats, dt_s: float) -> NDArray[np.intp]:
    """First sample of each half-cycle: 0, and the sample after each zero crossing of x
    (:func:`zero_crossings`), the half-cycles of :func:`swing_frequency_rad_s`."""
    crossings, _ = zero_crossings(x_m, v_m_s, dt_s)
    return np.concatenate(([0], crossings + 1)).astype(np.intp)


def motion_samples(result: SimulationResult) -> int:
    """How many samples of the history are motion: those up to the overturning time (the kernel
    holds its last state after it), else all of them."""
    n = result.raw.hist_x.size
    t_over = result.summary.overturn_time_s
    if result.summary.overturned and t_over is not None:
        return min(n, math.floor(t_over / result.dt_s + 1e-9) + 1)
    return n


def felt_ground_acc(result: SimulationResult) -> Floats:
    """The ground acceleration at the history's samples [m/s²]: the scaled record, then the
    tail's zeros."""
    if result.ground_acc_m_s2 is None:
        raise ValueError("the result keeps no ground motion, expected one from simulate()")
    n = result.raw.hist_x.size
    acc = np.zeros(n)
    m = min(n, result.ground_acc_m_s2.size)
    acc[:m] = result.ground_acc_m_s2[:m]
    return acc


def motion_frequency(
    result: SimulationResult,
    *,
    law_everywhere: bool = True,
    crossings: tuple[NDArray[np.intp], Floats] | None = None,
) -> tuple[Floats, Floats, Floats]:
    """ω_f(t) [rad/s], A(t) [m] and 2π/T(A(t)) [rad/s] over the samples of motion
    (:func:`motion_samples`) of a simulation with history and model (``law_everywhere`` and
    ``crossings``, those of the samples of motion, as :func:`swing_frequency_rad_s`)."""
    if result.model is None or not result.raw.hist_x.size:
        raise ValueError("the simulation kept no history, expected record_history=True")
    n = motion_samples(result)
    raw = result.raw
    return swing_frequency_rad_s(
        raw.hist_x[:n], raw.hist_v[:n], raw.hist_p[:n], result.dt_s, backbone_of(result.model),
        overturns=result.summary.overturned, law_everywhere=law_everywhere, crossings=crossings,
    )  # fmt: skip


def frequency_history(result: SimulationResult) -> xr.DataArray | None:
    """ω_f(t) of a simulation with history [rad/s] (NaN after overturning), with the swing
    amplitude A(t) [m] and the law's 2π/T(A(t)) [rad/s] as coordinates; None without a history
    or a model."""
    import xarray as xr

    history = result.history
    if history is None or result.model is None:
        return None
    parts = motion_frequency(result)
    omega, amplitude, law = (np.full(result.raw.hist_x.size, np.nan) for _ in range(3))
    for full, part in zip((omega, amplitude, law), parts, strict=True):
        full[: part.size] = part
    return xr.DataArray(
        omega,
        dims="time",
        coords={
            "time": history["time"],
            "amplitude": ("time", amplitude, {"units": result.units, "long_name": AMPLITUDE}),
            "omega_law": ("time", law, {"units": "rad/s", "long_name": LAW}),
        },
        name="omega_f",
        attrs={
            "units": "rad/s",
            "long_name": "frame's instantaneous frequency: ω_1 unstepped, π/half-cycle stepping",
        },
    )


def input_energy_history(result: SimulationResult) -> xr.DataArray | None:
    """Work of the ground on the frame since t = 0 at each sample (constant after overturning)
    [units²/s², per unit of the model's mass]; None without a history or a model."""
    import xarray as xr

    history = result.history
    if history is None or result.model is None:
        return None
    n = motion_samples(result)
    raw, model = result.raw, result.model
    acc = felt_ground_acc(result)[:n]
    work = interval_work(
        raw.hist_x[:n], raw.hist_v[:n], raw.hist_p[:n], acc, result.dt_s, model.p_1, model.p_2
    )
    cumulative = np.zeros(raw.hist_x.size)
    cumulative[1:n] = np.cumsum(work)
    cumulative[n:] = cumulative[n - 1]
    return xr.DataArray(
        cumulative,
        dims="time",
        coords={"time": history["time"]},
        name="input_energy",
        attrs={
            "units": f"{result.units}2/s2",
            "long_name": "work of the ground on the frame since t = 0, per unit mass",
        },
    )


__all__ = [
    "ModelBackbone",
    "backbone_of",
    "energy",
    "energy_amplitude_m",
    "felt_ground_acc",
    "frequency_history",
    "frequency_rad_s",
    "half_cycle_starts",
    "input_energy_history",
    "interval_work",
    "motion_frequency",
    "motion_samples",
    "potential",
    "swing_amplitude_m",
    "swing_frequency_rad_s",
    "turning_points",
    "zero_crossings",
]
