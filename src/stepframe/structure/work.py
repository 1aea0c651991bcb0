"""Work estimates: what an integration will cost, checked before it starts.

A run is refused with one line (:class:`~stepframe.errors.InputError`) when its estimate passes
:data:`MAX_WORK_UNITS`, so no request (a forcing frequency near 0, a million periods at 10⁴
rad/s, a tail of 10¹² s) runs for hours or exhausts memory without an answer.

The unit is one closed-form piece of the harmonic kernel (about 1 µs on the machine of
docs/benchmarks.md, "Structure models"): its pieces are a sixteenth of the forcing period and of
the homogeneous time scale of every phase the frame can be in, and each output sample costs
:data:`SAMPLE_UNITS` pieces (a call of the kernel from Python). The sampled simulator's intervals
are cheaper (:data:`INTERVAL_UNITS` each: the event-free fast path). Events are not in the
estimate: the hold state ends impact sequences, and each call of a kernel bounds its own.
"""

from __future__ import annotations

import math

from stepframe.errors import InputError

#: Largest estimate run [pieces]: about 30 s of integration at 1 µs per piece.
MAX_WORK_UNITS = 3e7
#: Measured cost of one piece [s] (docs/benchmarks.md), for the time stated when refusing.
SECONDS_PER_UNIT = 1e-6
#: Cost of one output sample of the harmonic integrator, in pieces.
SAMPLE_UNITS = 4.0
#: Cost of one sample interval of the sampled-record simulator, in pieces.
INTERVAL_UNITS = 0.05
#: Output samples any run may keep (each holds x, ẋ and its time: 24 bytes).
MAX_SAMPLES = 50_000_000

_PIECES_PER_CYCLE = 16.0


def pieces_per_second(omega_rad_s: float, frame_rates_per_s: float) -> float:
    """Closed-form pieces per second of motion under forcing at ω [rad/s].

    ``frame_rates_per_s`` is the frame's own rate (:func:`frame_piece_rate`).
    """
    return max(_PIECES_PER_CYCLE * omega_rad_s / (2.0 * math.pi), frame_rates_per_s)


def frame_piece_rate(
    omega_1_rad_s: float,
    omega_2_rad_s: float,
    xi_1: float,
    xi_2: float,
    x_c_m: float,
) -> float:
    """Pieces per second the frame's phases need without forcing [1/s].

    An oscillating phase (damping below critical) is cut sixteen times per damped period, an
    exponential one once per 1/√(β² - k) (the growth time scale); x_c = 0 has no unstepped phase.
    """
    rate = math.sqrt(omega_2_rad_s**2 * (1.0 + xi_2 * xi_2))
    if x_c_m > 0.0:
        if xi_1 < 1.0:
            damped = omega_1_rad_s * math.sqrt(1.0 - xi_1 * xi_1)
            rate = max(rate, _PIECES_PER_CYCLE * damped / (2.0 * math.pi))
        else:
            rate = max(rate, omega_1_rad_s * math.sqrt(xi_1 * xi_1 - 1.0))
    return rate


def check_work(units: float, what: str, advice: str, limit: float = MAX_WORK_UNITS) -> None:
    """Refuse a run whose estimate ``units`` [pieces] passes ``limit``.

    Parameters
    ----------
    units
        The estimate (not finite counts as above any limit).
    what
        The request, as the user gave it ("--omega-rad-s 1e-12 for 1 period").
    advice
        What to change, for the message.
    limit
        Largest estimate run [pieces].

    Raises
    ------
    InputError
        One line: the request, its estimate and time, the limit, the advice.
    """
    if math.isfinite(units) and units <= limit:
        return
    seconds = units * SECONDS_PER_UNIT
    took = f"about {_duration(seconds)}" if math.isfinite(seconds) else "without end"
    raise InputError(
        f"{what} would take {took} ({units:.3g} closed-form pieces), expected at most "
        f"{limit:.3g} (about {_duration(limit * SECONDS_PER_UNIT)}): {advice}"
    )


def check_samples(n: float, what: str, advice: str) -> None:
    """Refuse a run that would keep more than :data:`MAX_SAMPLES` output samples."""
    if not n <= MAX_SAMPLES:
        raise InputError(
            f"{what} keeps {n:.3g} output samples, expected ≤ {MAX_SAMPLES:,}: {advice}"
        )


def _duration(seconds: float) -> str:
    for unit, size in (("years", 3.15576e7), ("days", 86400.0), ("h", 3600.0), ("min", 60.0)):
        if seconds >= size:
            return f"{seconds / size:.3g} {unit}"
    return f"{seconds:.2g} s"
