"""Stepping frames and rigid blocks under harmonic and pulse ground motion, in closed form.

The ground acceleration is ẍ_g(t) = A cos(ωt + φ) [m/s²] (a sine is φ = -π/2), for all time
(:func:`simulate_harmonic`, :func:`stroboscopic_map`) or for one cycle followed by free motion
(:func:`simulate_pulse`). Each phase of eqs. 4.11-4.12 is integrated in closed form by
:mod:`stepframe.structure._harmonic_kernel`, so the forcing carries no sampling error and the
stroboscopic map comes with its exact Jacobian (phase transition matrices composed with the
saltation matrices of lift-off and impact).

Overturning: under forcing bounded by A the stepped-phase coordinate u = s·x - x*, w = s·ẋ obeys
z' = λ₁z + f with z = w - λ₂u (λ₁ > 0 > λ₂ the roots of λ² + 2ξ₂ω₂λ - ω₂² = 0) and
|f| ≤ P₂A; once z > P₂A/λ₁, z grows without bound and the frame cannot return: the run stops with
``overturned=True``. With A = 0 this is the simulator's escape test. A frame with ``x_cap_m`` also
stops when |x| reaches it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from stepframe.core import validation
from stepframe.core.results import Status
from stepframe.errors import InputError
from stepframe.structure.work import check_samples

if TYPE_CHECKING:
    from stepframe.structure.simulator import FrameLike

PulseKind = Literal["cosine", "sine"]
PULSE_KINDS: tuple[str, ...] = ("cosine", "sine")

#: Default bound on events per integration call (Zeno sequences are cut by the hold state).
DEFAULT_MAX_EVENTS = 200_000


def _checked(
    prm: np.ndarray, amp_bound: float, x0: float, code: int, overturned: bool, peak: float,
    *values: float,
) -> tuple[Status, str]:  # fmt: skip
    """Status and message of a run after the run-level invariant every result passes.

    Non-finite values, or a peak beyond the cap or beyond y_e = (γ₁ + P₂A)/ω₂² without an
    overturning verdict (:func:`stepframe.structure.status.run_invariant`), are a failure with
    its reason, never "ok".
    """
    from stepframe.structure.status import (
        STATUS_MESSAGES,
        STATUS_NAMES,
        no_escape_bound_m,
        run_invariant,
    )

    bound = no_escape_bound_m(prm[4], prm[3], prm[1], amp_bound, x0, prm[9])
    code = run_invariant(code, overturned, peak, bound, *values)
    return STATUS_NAMES[code], STATUS_MESSAGES[code]


def harmonic_work_units(
    prm: np.ndarray, omega_rad_s: float, duration_s: float, n_samples: float
) -> float:
    """Work estimate of a closed-form run [pieces] (:mod:`stepframe.structure.work`).

    Parameters
    ----------
    prm
        :func:`frame_parameters` of the frame.
    omega_rad_s, duration_s
        Forcing frequency [rad/s] and the time integrated [s].
    n_samples
        Output samples (each a call of the kernel).
    """
    from stepframe.structure import work

    rate = work.pieces_per_second(
        omega_rad_s, work.frame_piece_rate(prm[0], prm[1], prm[5], prm[6], prm[7])
    )
    return float(duration_s * rate + work.SAMPLE_UNITS * n_samples)


def check_harmonic_work(
    prm: np.ndarray,
    omega_rad_s: float,
    duration_s: float,
    n_samples: float,
    what: str,
    advice: str = "ask for fewer periods or a higher forcing frequency",
) -> None:
    """Refuse a closed-form run whose :func:`harmonic_work_units` pass the limit, in one line."""
    from stepframe.structure import work

    work.check_work(harmonic_work_units(prm, omega_rad_s, duration_s, n_samples), what, advice)


def _small_angle(frame: FrameLike, prm: np.ndarray, peak_m: float) -> str:
    """The note of a linearised rigid block that rotated beyond small angles ("" else)."""
    from stepframe.structure.status import small_angle_note

    return small_angle_note(prm[7], prm[4] / prm[1] ** 2, getattr(frame, "h_r_m", None), peak_m)


def _lifts_at_start(phase: int, x: float, prm: np.ndarray) -> int:
    """1 when a run starts on the switching surface in a stepped phase (a lift-off at t = 0)."""
    return int(phase in (1, -1) and abs(x) == prm[7])


def frame_parameters(frame: FrameLike) -> np.ndarray:
    """Kernel parameter vector (ω₁, ω₂, P₁, P₂, γ₁, ξ₁, ξ₂, x_c, C_r, x_cap) of a frame.

    Parameters
    ----------
    frame
        A :class:`~stepframe.structure.frame.PortalFrame` (or any object with its fields).
    """
    from stepframe.structure.simulator import model_of

    m = model_of(frame)
    return np.array(
        [
            m.omega_1_rad_s,
            m.omega_2_rad_s,
            m.p_1,
            m.p_2,
            m.gamma_1_m_s2,
            m.xi_1,
            m.xi_2,
            m.x_c_m,
            m.c_r,
            m.x_cap_m,
        ],
        dtype=float,
    )


@dataclass(frozen=True)
class HarmonicRun:
    """Response to harmonic ground acceleration, exact at the output times.

    Attributes
    ----------
    time_s, x_m, v_m_s
        Output times [s] and the state there [m, m/s] (NaN after an overturn).
    status
        One of :data:`stepframe.core.results.STATUSES`.
    overturned
        True when the frame left on the escaping branch or reached x_cap.
    t_end_s
        Time the run ended [s] (the overturn time when it overturned).
    n_liftoffs, n_impacts
        Event counts.
    peak_abs_x_m
        Largest |x| [m].
    """

    time_s: np.ndarray
    x_m: np.ndarray
    v_m_s: np.ndarray
    status: Status
    overturned: bool
    t_end_s: float
    n_liftoffs: int
    n_impacts: int
    peak_abs_x_m: float
    message: str = ""

    def to_dict(self) -> dict[str, Any]:
        """Summary fields (not the histories) as plain Python values."""
        return {
            "status": self.status,
            "message": self.message,
            "overturned": self.overturned,
            "t_end_s": self.t_end_s,
            "n_liftoffs": self.n_liftoffs,
            "n_impacts": self.n_impacts,
            "peak_abs_x_m": self.peak_abs_x_m,
        }


def simulate_harmonic(
    frame: FrameLike,
    amplitude_m_s2: float,
    omega_rad_s: float,
    duration_s: float,
    *,
    phase_rad: float = 0.0,
    x0_m: float = 0.0,
    v0_m_s: float = 0.0,
    samples_per_period: int = 64,
    max_events: int = DEFAULT_MAX_EVENTS,
) -> HarmonicRun:
    """Response to ẍ_g = A cos(ωt + φ) from (x₀, v₀) at t = 0 over ``duration_s``.

    Parameters
    ----------
    frame
        A :class:`~stepframe.structure.frame.PortalFrame` (x_c = 0: Housner's block).
    amplitude_m_s2
        A [m/s²], ≥ 0.
    omega_rad_s
        ω [rad/s], > 0.
    duration_s
        Length of the run [s], > 0.
    phase_rad
        φ [rad] (-π/2: a sine).
    x0_m, v0_m_s
        Initial state [m, m/s].
    samples_per_period
        Output samples per forcing period (the integration itself is exact between them).
    max_events
        Bound on events between two output samples (status ``too_many_events`` beyond).
    """
    prm = frame_parameters(frame)
    amp = validation.non_negative("amplitude_m_s2", amplitude_m_s2)
    om = validation.positive("omega_rad_s", omega_rad_s)
    if duration_s == math.inf:
        # Periods of a frequency so near 0 that their length overflows: refused as work.
        check_harmonic_work(prm, om, math.inf, 0, "a run of more than 1e308 s")
    dur = validation.positive("duration_s", duration_s)
    phi = validation.finite("phase_rad", phase_rad)
    x = validation.finite("x0_m", x0_m)
    v = validation.finite("v0_m_s", v0_m_s)
    if abs(x) >= prm[9]:  # the cap (inf: none); a start past it never crosses it: no verdict
        raise InputError(
            f"x0_m = {x}, expected |x0_m| < x_cap_m = {prm[9]:g} (the overturning cap)"
        )
    if samples_per_period < 1:
        raise InputError(f"samples_per_period = {samples_per_period}, expected ≥ 1")
    periods = dur * om / (2 * math.pi)
    what = f"a run of {dur:.6g} s ({periods:.6g} forcing periods of {2 * math.pi / om:.6g} s)"
    check_samples(
        periods * samples_per_period,
        what,
        "fewer forcing periods (--periods) or samples per period",
    )
    n = max(1, math.ceil(periods * samples_per_period))
    check_harmonic_work(prm, om, dur, n, what)
    # The kernel (numba) is loaded only for a run that passed the checks: a refusal is instant.
    from stepframe.structure import _harmonic_kernel as hk

    times = np.linspace(0.0, dur, n + 1)
    xs = np.full(n + 1, np.nan)
    vs = np.full(n + 1, np.nan)
    xs[0] = x
    vs[0] = v
    phase = int(hk.start_phase(x, v, amp * math.cos(phi), prm))
    jac = np.eye(2)
    n_lift = _lifts_at_start(phase, x, prm)
    n_imp = 0
    peak = abs(x)
    code = hk.K_OK
    overturned = False
    t_end = dur
    for i in range(n):
        st, x, v, phase, nl, ni, pk, ov, te = hk.advance(
            prm, amp, om, phi, times[i], times[i + 1], x, v, phase, jac, False, max_events, amp
        )
        n_lift += nl
        n_imp += ni
        peak = max(peak, pk)
        if st != hk.K_OK:
            code = int(st)
            t_end = float(te)
            break
        if ov:
            overturned = True
            t_end = float(te)
            break
        xs[i + 1] = x
        vs[i + 1] = v
    status, message = _checked(prm, amp, xs[0], code, overturned, float(peak), x, v)
    if status != "ok":
        message = f"{message} (stopped at t = {t_end:.6g} s)"
    elif not overturned:
        message = _small_angle(frame, prm, float(peak))
    return HarmonicRun(
        times, xs, vs, status, overturned, t_end, n_lift, n_imp, float(peak), message
    )


@dataclass(frozen=True)
class PulseOutcome:
    """Response of a frame at rest to one cycle of a sinusoidal pulse, then free motion.

    Attributes
    ----------
    overturned
        True when the frame overturns (during the pulse or, decided exactly, after it).
    peak_abs_x_m
        Largest |x| while it is decided [m].
    status
        One of :data:`stepframe.core.results.STATUSES`.
    n_impacts
        Impacts counted.
    """

    overturned: bool
    peak_abs_x_m: float
    status: Status
    n_impacts: int
    message: str = ""


def pulse_phase_rad(kind: PulseKind) -> float:
    """φ of a pulse kind: ``"cosine"`` A cos(ωt), ``"sine"`` A sin(ωt) = A cos(ωt - π/2)."""
    if kind == "cosine":
        return 0.0
    if kind == "sine":
        return -0.5 * math.pi
    raise InputError(f"kind = {kind!r}, expected one of {PULSE_KINDS}")


def simulate_pulse(
    frame: FrameLike,
    amplitude_m_s2: float,
    omega_rad_s: float,
    *,
    kind: PulseKind = "cosine",
    free_periods: float = 20.0,
    max_events: int = DEFAULT_MAX_EVENTS,
) -> PulseOutcome:
    """Frame at rest hit by one cycle ẍ_g = A cos(ωt + φ), 0 ≤ t ≤ 2π/ω, then free motion.

    After the pulse the ground is still: a stepped state overturns exactly when it is on the
    escaping branch, which the kernel tests on every piece. The free motion is followed for
    ``free_periods`` forcing periods (a frame that has not escaped by then is losing energy at
    every impact and cannot escape later); the result is ``lower_bound`` if it was still moving
    with enough energy to reach x* (never seen in practice).

    Parameters
    ----------
    frame
        A :class:`~stepframe.structure.frame.PortalFrame`.
    amplitude_m_s2, omega_rad_s
        Pulse amplitude A [m/s²] and circular frequency ω [rad/s].
    kind
        ``"cosine"`` (φ = 0) or ``"sine"`` (φ = -π/2).
    free_periods
        Free motion followed after the pulse, in pulse periods.
    """
    prm = frame_parameters(frame)
    amp = validation.non_negative("amplitude_m_s2", amplitude_m_s2)
    om = validation.positive("omega_rad_s", omega_rad_s)
    phi = pulse_phase_rad(kind)
    free = validation.non_negative("free_periods", free_periods)
    tp = 2.0 * math.pi / om
    check_harmonic_work(
        prm, om, tp * (1.0 + free), 2, f"a pulse of {tp:.6g} s and {free:g} periods after it",
        "ask for a higher pulse frequency or fewer free periods",
    )  # fmt: skip
    from stepframe.structure import _harmonic_kernel as hk

    jac = np.eye(2)
    phase = int(hk.start_phase(0.0, 0.0, amp * math.cos(phi), prm))
    st, x, v, phase, _nl, ni, pk, ov, _te = hk.advance(
        prm, amp, om, phi, 0.0, tp, 0.0, 0.0, phase, jac, False, max_events, amp
    )
    peak = float(pk)
    if st == hk.K_OK and not ov:
        phase = int(hk.start_phase(x, v, 0.0, prm)) if phase in (2, -2) else phase
        st, x, v, phase, _nl2, ni2, pk2, ov, _te2 = hk.advance(
            prm, 0.0, om, phi, tp, tp * (1.0 + free), x, v, phase, jac, False,
            max_events, 0.0,
        )  # fmt: skip
        peak = float(max(pk, pk2))
        ni += ni2
    status, message = _checked(prm, amp, 0.0, int(st), bool(ov), peak, x, v)
    if status == "ok" and not ov:
        message = _small_angle(frame, prm, peak)
    return PulseOutcome(bool(ov), peak, status, int(ni), message)


@dataclass(frozen=True)
class MapStep:
    """The stroboscopic map applied n times from one state.

    Attributes
    ----------
    x_m, v_m_s
        State after n forcing periods [m, m/s].
    jacobian
        ∂(x, v)/∂(x₀, v₀) (2×2), exact (saltation matrices at every event).
    status
        One of :data:`stepframe.core.results.STATUSES`.
    overturned
        True when the frame overturned inside (the state is the one at overturning).
    n_impacts, n_liftoffs
        Events over the n periods.
    phases
        Phase code at the end.
    """

    x_m: float
    v_m_s: float
    jacobian: np.ndarray
    status: Status
    overturned: bool
    n_impacts: int
    n_liftoffs: int
    phases: list[int] = field(default_factory=list)


def stroboscopic_map(
    frame: FrameLike,
    amplitude_m_s2: float,
    omega_rad_s: float,
    x_m: float,
    v_m_s: float,
    *,
    n_periods: int = 1,
    phase_rad: float = 0.0,
    max_events: int = DEFAULT_MAX_EVENTS,
    params: np.ndarray | None = None,
) -> MapStep:
    """P^n(x, v): the state n forcing periods after (x, v) at a period boundary (t = 0 mod T).

    ``params`` (from :func:`frame_parameters`) skips re-reading the frame in tight loops.
    """
    from stepframe.structure import _harmonic_kernel as hk

    prm = frame_parameters(frame) if params is None else params
    period = 2.0 * math.pi / omega_rad_s
    jac = np.eye(2)
    x = float(x_m)
    v = float(v_m_s)
    phase = int(hk.start_phase(x, v, amplitude_m_s2 * math.cos(phase_rad), prm))
    n_imp = n_lift = 0
    phases = []
    st, ov, peak = hk.K_OK, 0, abs(x)
    for i in range(n_periods):
        st, x, v, phase, nl, ni, pk, ov, _te = hk.advance(
            prm,
            amplitude_m_s2,
            omega_rad_s,
            phase_rad,
            i * period,
            (i + 1) * period,
            x,
            v,
            phase,
            jac,
            True,
            max_events,
            amplitude_m_s2,
        )
        n_imp += ni
        n_lift += nl
        peak = max(peak, pk)
        phases.append(int(phase))
        if st != hk.K_OK or ov:
            break
    status, _message = _checked(prm, amplitude_m_s2, x_m, int(st), bool(ov), peak, x, v)
    return MapStep(x, v, jac, status, bool(ov), n_imp, n_lift, phases)
