"""Compiled kernels of the frame's frequency and of the ground's work on it
(:mod:`stepframe.structure.frame_frequency`): the zero crossings and turning points of a
history, the measured frequency of its half-cycles, the swing amplitude and the
period-amplitude law's frequency at it, and the work over each sample interval. The law's
quarter periods (:func:`quarter_periods`) are the ones
:func:`stepframe.structure.period_amplitude.quarter_periods_s` evaluates.

Compiled because each is a short computation per sample: written with numpy they cost some
fifty calls over the history, fixed costs that made the moving-resonance index several times
dearer than the exact simulation it reads (docs/benchmarks.md, issue 26). The numpy-facing
functions of :mod:`~stepframe.structure.frame_frequency` call these, and the index's kernel
(:mod:`stepframe.pipeline.dynamics._resonance_kernel`) calls :func:`zero_crossings` and
:func:`interval_work`: one home for each formula.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from stepframe.core.jit import njit


@njit(cache=True)
def hermite(s: float, x0: float, h0: float, x1: float, h1: float) -> float:
    """The cubic Hermite interpolant through x0, x1 with slopes h0, h1 (per unit s), at s."""
    return (
        (2 * s**3 - 3 * s**2 + 1) * x0
        + (s**3 - 2 * s**2 + s) * h0
        + (3 * s**2 - 2 * s**3) * x1
        + (s**3 - s**2) * h1
    )


@njit(cache=True)
def crossing_fraction(x0: float, h0: float, x1: float, h1: float) -> float:
    """Where in [0, 1] x passes zero between two samples of opposite sign: the linear
    interpolation, refined by one Newton step on the cubic through x and its slopes h = Δt·ẋ
    (kept only if it stays finite and inside the interval)."""
    s = x0 / (x0 - x1)
    slope = (6 * s**2 - 6 * s) * (x0 - x1) + (3 * s**2 - 4 * s + 1) * h0 + (3 * s**2 - 2 * s) * h1
    if slope != 0.0:
        refined = s - hermite(s, x0, h0, x1, h1) / slope
        if math.isfinite(refined) and 0.0 <= refined <= 1.0:
            return refined
    return s


@njit(cache=True)
def zero_crossings(
    x_m: NDArray[np.float64], v_m_s: NDArray[np.float64], dt_s: float
) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
    """Samples i after which x changes sign (x > 0 against x ≤ 0 at i + 1) and the crossing
    times [s] (:func:`crossing_fraction` between the two samples)."""
    n = x_m.size
    count = 0
    for i in range(n - 1):
        if (x_m[i] > 0.0) != (x_m[i + 1] > 0.0):
            count += 1
    samples = np.empty(count, dtype=np.int64)
    times = np.empty(count)
    k = 0
    for i in range(n - 1):
        if (x_m[i] > 0.0) != (x_m[i + 1] > 0.0):
            s = crossing_fraction(x_m[i], dt_s * v_m_s[i], x_m[i + 1], dt_s * v_m_s[i + 1])
            samples[k] = i
            times[k] = (i + s) * dt_s
            k += 1
    return samples, times


@njit(cache=True)
def turning_fraction(x0: float, h0: float, x1: float, h1: float) -> float:
    """Where in [0, 1] the cubic through x0, x1 with slopes h0, h1 (of opposite signs) has zero
    slope: the root of its derivative a s² + b s + h0 inside the interval, in the form that
    stays accurate when a → 0; the zero of the linear slope between h0 and h1 if neither root
    is inside (rounding)."""
    a = 6.0 * (x0 - x1) + 3.0 * (h0 + h1)
    b = -6.0 * (x0 - x1) - 4.0 * h0 - 2.0 * h1
    disc = math.sqrt(max(b * b - 4.0 * a * h0, 0.0))
    q = -0.5 * (b + math.copysign(disc, b))
    if a != 0.0:
        root = q / a
        if 0.0 <= root <= 1.0:
            return root
    if q != 0.0:
        root = h0 / q
        if 0.0 <= root <= 1.0:
            return root
    return h0 / (h0 - h1)


@njit(cache=True, inline="always")
def _turns_between(v_m_s: NDArray[np.float64], i: int) -> bool:
    """ẋ changes sign strictly between samples i and i + 1 (a sample with ẋ = 0 exactly, a hold
    on the surface, is not a turning point)."""
    return bool(np.sign(v_m_s[i]) * np.sign(v_m_s[i + 1]) < 0.0)


@njit(cache=True, inline="always")
def _turning_point(
    x_m: NDArray[np.float64], v_m_s: NDArray[np.float64], dt_s: float, i: int
) -> tuple[float, float]:
    """Time [s] and |x| [m] of the turning point between samples i and i + 1
    (:func:`_turns_between` holds), at :func:`turning_fraction` of the interval."""
    x0, x1 = x_m[i], x_m[i + 1]
    h0, h1 = dt_s * v_m_s[i], dt_s * v_m_s[i + 1]
    s = turning_fraction(x0, h0, x1, h1)
    return (i + s) * dt_s, abs(hermite(s, x0, h0, x1, h1))


@njit(cache=True)
def turning_points(
    x_m: NDArray[np.float64], v_m_s: NDArray[np.float64], dt_s: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Times [s] and |x| [m] of the turning points of x (:func:`_turns_between`,
    :func:`_turning_point`)."""
    n = x_m.size
    count = 0
    for i in range(n - 1):
        if _turns_between(v_m_s, i):
            count += 1
    times = np.empty(count)
    amplitudes = np.empty(count)
    k = 0
    for i in range(n - 1):
        if _turns_between(v_m_s, i):
            times[k], amplitudes[k] = _turning_point(x_m, v_m_s, dt_s, i)
            k += 1
    return times, amplitudes


@njit(cache=True)
def _knot_intervals(
    x_m: NDArray[np.float64], v_m_s: NDArray[np.float64], dt_s: float,
    samples: NDArray[np.int64],
) -> NDArray[np.int64]:  # fmt: skip
    """The sample intervals whose turning points A(t) at the given samples (ascending) depends
    on, as rows (first, last) in ascending order, merged: around each run of consecutive
    samples, back to the last turning point after 0 at or before its first sample, through it,
    and on to the first turning point after its last. Linear interpolation at a time reads
    only the knots either side of it, so these give :func:`swing_law` the same A as every
    turning point would; every interval when the samples are not ascending."""
    intervals = x_m.size - 1
    ranges = np.empty((samples.size + 1, 2), dtype=np.int64)
    if intervals < 1:
        return ranges[:0]
    for k in range(samples.size - 1):
        if samples[k + 1] <= samples[k]:
            ranges[0, 0], ranges[0, 1] = 0, intervals - 1
            return ranges[:1]
    count, k = 0, 0
    while k < samples.size:
        first = last = samples[k]
        while k + 1 < samples.size and samples[k + 1] == last + 1:
            k += 1
            last = samples[k]
        k += 1
        low = min(first, intervals - 1)
        while low > 0:
            if _turns_between(v_m_s, low):
                when = _turning_point(x_m, v_m_s, dt_s, low)[0]
                if 0.0 < when <= first * dt_s:
                    break
            low -= 1
        high = min(max(low, first), intervals - 1)
        while high < intervals - 1:
            if (
                high >= last
                and _turns_between(v_m_s, high)
                and _turning_point(x_m, v_m_s, dt_s, high)[0] > last * dt_s
            ):
                break
            high += 1
        if count and low <= ranges[count - 1, 1] + 1:
            ranges[count - 1, 0] = min(ranges[count - 1, 0], low)
            ranges[count - 1, 1] = max(ranges[count - 1, 1], high)
        else:
            ranges[count, 0], ranges[count, 1] = low, high
            count += 1
    return ranges[:count]


@njit(cache=True)
def fill_half_cycles(
    phase: NDArray[np.int8],
    crossings: NDArray[np.int64],
    crossing_times_s: NDArray[np.float64],
    omega_1_rad_s: float,
    omega_rad_s: NDArray[np.float64],
) -> None:
    """Write each measured half-cycle's frequency into ``omega_rad_s`` (in place): half-cycle k
    holds the samples crossings[k] + 1 ... crossings[k + 1]; ω₁ if none of them stepped, else
    π/τ_k (τ_k between its two crossing times), at most ω₁."""
    for k in range(crossings.size - 1):
        first, last = crossings[k] + 1, crossings[k + 1]
        stepped = False
        for i in range(first, last + 1):
            if phase[i] != 0:
                stepped = True
                break
        value = omega_1_rad_s
        duration = crossing_times_s[k + 1] - crossing_times_s[k]
        if stepped and duration > 0.0:
            value = min(omega_1_rad_s, math.pi / duration)
        for i in range(first, last + 1):
            omega_rad_s[i] = value


@njit(cache=True)
def interval_work(
    x_m: NDArray[np.float64],
    v_m_s: NDArray[np.float64],
    phase: NDArray[np.int8],
    ground_acc_m_s2: NDArray[np.float64],
    dt_s: float,
    p_1: float,
    p_2: float,
) -> NDArray[np.float64]:
    """Work of the ground on the frame over each interval [t_i, t_{i+1}] [m²/s²] (n - 1
    values): -P·∫ẍ_g ẋ dt, the integral exact for a cubic x and a linear ẍ_g, P the mean of
    the two ends' participation factors (:mod:`stepframe.structure.frame_frequency`)."""
    n = x_m.size
    work = np.empty(max(n - 1, 0))
    for i in range(n - 1):
        a0, a1 = ground_acc_m_s2[i], ground_acc_m_s2[i + 1]
        integral = (x_m[i + 1] - x_m[i]) * 0.5 * (a0 + a1) + (a1 - a0) * (
            v_m_s[i + 1] - v_m_s[i]
        ) * (dt_s / 12.0)
        factor_0 = p_1 if phase[i] == 0 else p_2
        factor_1 = p_1 if phase[i + 1] == 0 else p_2
        work[i] = -0.5 * (factor_0 + factor_1) * integral
    return work


@njit(cache=True)
def quarter_period_parts(
    amplitude_m: float, omega_1: float, omega_2: float, x_c_m: float, x_star_m: float
) -> tuple[float, float]:
    """Time in the unstepped and in the stepped phase of a quarter period of the free
    conservative frame released at rest from 0 ≤ A < x* [s] (closed forms of
    :mod:`stepframe.structure.period_amplitude`)."""
    if amplitude_m > x_c_m:
        gap_a = x_star_m - amplitude_m
        gap_c = x_star_m - x_c_m
        t_stepped = math.acosh(gap_c / gap_a) / omega_2
        # (x* - x_c)² - (x* - A)² written as a product to keep accuracy for A just above x_c.
        v_c = omega_2 * math.sqrt((amplitude_m - x_c_m) * (gap_c + gap_a))
        if x_c_m > 0.0:
            return math.asin(x_c_m / math.hypot(x_c_m, v_c / omega_1)) / omega_1, t_stepped
        return 0.0, t_stepped
    if x_c_m > 0.0:
        return 0.5 * math.pi / omega_1, 0.0
    return 0.0, 0.0


@njit(cache=True)
def quarter_periods(
    amplitude_m: NDArray[np.float64], omega_1: float, omega_2: float, x_c_m: float,
    x_star_m: float,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:  # fmt: skip
    """:func:`quarter_period_parts` of each amplitude (0 ≤ A < x*, not checked) [s]."""
    unstepped = np.empty(amplitude_m.size)
    stepped = np.empty(amplitude_m.size)
    for k in range(amplitude_m.size):
        unstepped[k], stepped[k] = quarter_period_parts(
            amplitude_m[k], omega_1, omega_2, x_c_m, x_star_m
        )
    return unstepped, stepped


@njit(cache=True)
def law_frequency(
    amplitude_m: float, omega_1: float, omega_2: float, x_c_m: float, x_star_m: float
) -> float:
    """2π/T(A) of the period-amplitude law [rad/s]: 0 where A ≥ x* or A = ∞ (no periodic
    orbit), ∞ where T = 0 (a rigid block at rest)."""
    if not amplitude_m < x_star_m:
        return 0.0
    unstepped, stepped = quarter_period_parts(amplitude_m, omega_1, omega_2, x_c_m, x_star_m)
    period = 4.0 * (unstepped + stepped)
    return 2.0 * math.pi / period if period > 0.0 else math.inf


@njit(cache=True)
def potential_at(
    y_m: float, omega_1: float, omega_2: float, x_c_m: float, x_star_m: float
) -> float:
    """V(y) of the conservative two-phase model at |x| = y [m²/s²]
    (:mod:`stepframe.structure.frame_frequency`)."""
    if y_m <= x_c_m:
        return 0.5 * omega_1**2 * y_m**2
    gamma_1 = omega_2**2 * x_star_m
    return (
        0.5 * omega_1**2 * x_c_m**2
        + gamma_1 * (y_m - x_c_m)
        - 0.5 * omega_2**2 * (y_m**2 - x_c_m**2)
    )


@njit(cache=True)
def energy_amplitude(
    x_m: float, v_m_s: float, omega_1: float, omega_2: float, x_c_m: float, x_star_m: float
) -> float:
    """Amplitude A of the free conservative orbit through the state (x, ẋ) [m]; ∞ where there
    is none (|x| ≥ x* or E ≥ V(x*): the free frame would overturn)."""
    y = abs(x_m)
    energy = 0.5 * v_m_s**2 + potential_at(y, omega_1, omega_2, x_c_m, x_star_m)
    energy_c = 0.5 * omega_1**2 * x_c_m**2
    gap_sq = (x_star_m - x_c_m) ** 2 - 2.0 * (energy - energy_c) / omega_2**2
    if not (y < x_star_m and gap_sq > 0.0):
        return math.inf
    if energy <= energy_c:
        return math.sqrt(2.0 * max(energy, 0.0)) / omega_1
    return x_star_m - math.sqrt(gap_sq)


@njit(cache=True)
def swing_law(
    x_m: NDArray[np.float64],
    v_m_s: NDArray[np.float64],
    dt_s: float,
    samples: NDArray[np.int64],
    overturns: bool,
    omega_1: float,
    omega_2: float,
    x_c_m: float,
    x_star_m: float,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The swing amplitude A(t) [m] and the law's frequency 2π/T(A(t)) [rad/s] at the given
    samples (ascending): A is |x| at the turning points after t = 0, interpolated linearly in
    time, starting from the energy amplitude of the first state (at most x*) and held after
    the last turning point; on a history that ends by overturning, after the last turning
    point A is also at least the state's energy amplitude (module
    :mod:`stepframe.structure.frame_frequency`). Only the intervals around the samples are
    searched for turning points (:func:`_knot_intervals`): the index asks for the two ends of
    a history, where a search of the whole of it cost more than the rest of ω_f
    (docs/benchmarks.md, issue 26)."""
    ranges = _knot_intervals(x_m, v_m_s, dt_s, samples)
    scanned = 0
    for r in range(ranges.shape[0]):
        scanned += ranges[r, 1] - ranges[r, 0] + 1
    knots_t = np.empty(scanned + 1)
    knots_a = np.empty(scanned + 1)
    knots_t[0] = 0.0
    knots_a[0] = min(
        energy_amplitude(x_m[0], v_m_s[0], omega_1, omega_2, x_c_m, x_star_m), x_star_m
    )
    later = 0
    for r in range(ranges.shape[0]):
        for i in range(ranges[r, 0], ranges[r, 1] + 1):
            if _turns_between(v_m_s, i):
                when, size = _turning_point(x_m, v_m_s, dt_s, i)
                if when > 0.0:
                    later += 1
                    knots_t[later], knots_a[later] = when, size
    knots_t, knots_a = knots_t[: later + 1], knots_a[: later + 1]
    # The last turning point of the whole history (0 without one): A follows the energy
    # amplitude after it on a history that overturns.
    last_turn = 0.0
    for i in range(x_m.size - 2, -1, -1):
        if _turns_between(v_m_s, i):
            last_turn = max(_turning_point(x_m, v_m_s, dt_s, i)[0], 0.0)
            if last_turn > 0.0:
                break
    times = samples * dt_s
    amplitude = np.interp(times, knots_t, knots_a)
    omega = np.empty(samples.size)
    for k in range(samples.size):
        if overturns and times[k] > last_turn:
            i = samples[k]
            amplitude[k] = max(
                amplitude[k],
                energy_amplitude(x_m[i], v_m_s[i], omega_1, omega_2, x_c_m, x_star_m),
            )
        omega[k] = law_frequency(amplitude[k], omega_1, omega_2, x_c_m, x_star_m)
    return amplitude, omega


@njit(cache=True)
def swing_frequencies(
    x_m: NDArray[np.float64],
    v_m_s: NDArray[np.float64],
    phase: NDArray[np.int8],
    dt_s: float,
    crossings: NDArray[np.int64],
    crossing_times_s: NDArray[np.float64],
    law_everywhere: bool,
    overturns: bool,
    omega_1: float,
    omega_2: float,
    x_c_m: float,
    x_star_m: float,
    detail: bool,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """ω_f(t), A(t) and the law's 2π/T(A(t)) at every sample
    (:func:`stepframe.structure.frame_frequency.swing_frequency_rad_s`, which calls this):
    the law (:func:`swing_law`) everywhere, or with ``law_everywhere`` False only before the
    first and after the last of two or more zero crossings (NaN between), and each measured
    half-cycle's frequency between the crossings (:func:`fill_half_cycles`). Without
    ``detail`` A and the law are not kept (two empty arrays): the index reads ω_f only."""
    n = x_m.size
    if law_everywhere or crossings.size < 2:
        samples = np.arange(n)
    else:
        head, tail_start = crossings[0] + 1, crossings[crossings.size - 1] + 1
        samples = np.empty(head + n - tail_start, dtype=np.int64)
        samples[:head] = np.arange(head)
        samples[head:] = np.arange(tail_start, n)
    found_amplitude, found_law = swing_law(
        x_m, v_m_s, dt_s, samples, overturns, omega_1, omega_2, x_c_m, x_star_m
    )
    # Every sample is either one of the law's or inside a measured half-cycle.
    omega = np.empty(n)
    for k in range(samples.size):
        omega[samples[k]] = found_law[k]
    if crossings.size >= 2:
        fill_half_cycles(phase, crossings, crossing_times_s, omega_1, omega)
    amplitude = np.full(n if detail else 0, np.nan)
    law = np.full(n if detail else 0, np.nan)
    if detail:
        for k in range(samples.size):
            amplitude[samples[k]] = found_amplitude[k]
            law[samples[k]] = found_law[k]
    return omega, amplitude, law


@njit(cache=True)
def potentials(
    y_m: NDArray[np.float64], omega_1: float, omega_2: float, x_c_m: float, x_star_m: float
) -> NDArray[np.float64]:
    """:func:`potential_at` of each |x| [m²/s²]."""
    out = np.empty(y_m.size)
    for k in range(y_m.size):
        out[k] = potential_at(y_m[k], omega_1, omega_2, x_c_m, x_star_m)
    return out


@njit(cache=True)
def energy_amplitudes(
    x_m: NDArray[np.float64], v_m_s: NDArray[np.float64], omega_1: float, omega_2: float,
    x_c_m: float, x_star_m: float,
) -> NDArray[np.float64]:  # fmt: skip
    """:func:`energy_amplitude` of each state [m]."""
    out = np.empty(x_m.size)
    for k in range(x_m.size):
        out[k] = energy_amplitude(x_m[k], v_m_s[k], omega_1, omega_2, x_c_m, x_star_m)
    return out


@njit(cache=True)
def law_frequencies(
    amplitude_m: NDArray[np.float64], omega_1: float, omega_2: float, x_c_m: float,
    x_star_m: float,
) -> NDArray[np.float64]:  # fmt: skip
    """:func:`law_frequency` at each amplitude [rad/s]."""
    out = np.empty(amplitude_m.size)
    for k in range(amplitude_m.size):
        out[k] = law_frequency(amplitude_m[k], omega_1, omega_2, x_c_m, x_star_m)
    return out
