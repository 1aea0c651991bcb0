"""Stepping-frame response to ground acceleration (eqs. 4.11-4.12 with impact at touchdown).

:func:`simulate` integrates the two-phase model held by a
:class:`~stepframe.structure.frame.PortalFrame` for ground acceleration sampled at ``dt_s`` and
linear between samples, through the record and a free-vibration tail. ``method="exact"`` (the
default) is the piecewise-analytic integrator of :mod:`stepframe.structure._exact`: exact for
the model up to rounding, with switching times found by root finding on the closed form. The
``solve_ivp`` names run the independent cross-check of :mod:`stepframe.structure.reference`
(restarted at every sample, slower by orders of magnitude). :func:`simulate_batch` runs many
(record, scale) pairs on all cores and returns summaries (the basis of incremental dynamic
analysis).

Overturning: the frame has overturned when |x| passes ``x_cap_m`` (if the frame sets one), or
when, in free vibration after the record, a stepped state lies on the escaping branch. For the
stepped phase in free motion, u = s·x - x* and w = s·ẋ (s the side) obey ü + 2ξ₂ω₂u̇ - ω₂²u = 0,
whose solution is c₁e^{λ₁t} + c₂e^{λ₂t} with λ₁ > 0 > λ₂; the frame escapes exactly when
c₁ ∝ w - λ₂u > 0. For ξ₂ = 0 this is w + ω₂u > 0, which contains the set E = ẋ² - ω₂²(x - x*)² ≥ 0
with ẋ outward (see docs/paper-notes.md). Under forcing a trajectory may return from beyond x*;
without a cap it is declared overturned at the first sample where it cannot return whatever the
rest of the record does (the same test with x* replaced by (γ₁ + P₂·max remaining |ẍ_g|)/ω₂²).

Impacts that accumulate (chatter, the Zeno sequence of a rocking frame or block coming to rest)
are summed in closed form and the frame is then seated on the surface until the ground can lift
it again; C_r = 0 is the limit C_r → 0+. A result that is not a solution of the model (a state on
the wrong side of its phase) or not physically possible (past the cap, or past the bound a
frame that does not escape respects, without an overturn verdict) has status "failed", never
"ok" (docs/paper-notes.md, "Chatter, C_r → 0+ and the certain-escape verdict").

Methods are a registry, :data:`METHODS` (``{name: Integrator}``); ``method=`` takes a name or
any :class:`Integrator` callable. Status and event codes live in
:mod:`stepframe.structure.status`, shared by every integrator.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from concurrent.futures import Executor
from dataclasses import asdict, dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, Any, Literal, Protocol

import numpy as np

from stepframe.core import validation
from stepframe.errors import InputError
from stepframe.structure.frame import PAPER_G_M_S2
from stepframe.structure.status import (
    EVENT_LIFTOFF,
    EVENT_NAMES,
    EVENT_TOUCHDOWN,
    INVARIANT_RTOL,
    STATUS_MESSAGES,
    STATUS_NAMES,
    STATUS_OK,
    Model,
    RawRun,
    SimulationStatus,
    no_escape_bound_m,
    run_invariant,
)

if TYPE_CHECKING:
    import pandas as pd
    import xarray as xr
    from numpy.typing import ArrayLike

Method = Literal["exact", "RK45", "DOP853", "Radau", "LSODA"]
#: Status of a run: a state of :data:`stepframe.core.results.STATUSES`.
Status = SimulationStatus

#: Default free-vibration tail after the record [s].
DEFAULT_TAIL_S = 10.0


@dataclass(frozen=True)
class SimulationSummary:
    """Scalar results of one simulation (SI units).

    Attributes
    ----------
    peak_abs_x_m
        True peak |x| [m] (extrema located inside sample intervals, not sampled).
    peak_time_s
        Time of the peak [s].
    peak_drift_ratio
        Peak |x| divided by the height [-]; None when no height is known.
    overturned
        Whether the frame overturned (cap passed, or escaping in free vibration).
    overturn_time_s
        Time the cap was passed, or (without a cap) the time from which free motion was certain
        to escape [s]; None when not overturned.
    n_stepping_episodes
        Number of lift-offs (episodes in the stepped phase).
    n_impacts
        Number of touchdowns (impacts, each applying C_r).
    residual_x_m, residual_v_m_s
        State at the end of the simulation (record plus tail) [m], [m/s].
    status
        "ok", or a failure state of :data:`stepframe.core.results.STATUSES`: "nonfinite",
        "too_many_events", "not_converged" (solve_ivp failed a step) or "failed" (the state
        broke its phase invariant, or the result is physically impossible without an overturn
        verdict); see ``message``.
    message
        One line saying what went wrong; with "ok", "" or a note (a linearised rigid block that
        rotated beyond small angles: :func:`stepframe.structure.status.small_angle_note`).
    """

    peak_abs_x_m: float
    peak_time_s: float
    peak_drift_ratio: float | None
    overturned: bool
    overturn_time_s: float | None
    n_stepping_episodes: int
    n_impacts: int
    residual_x_m: float
    residual_v_m_s: float
    status: Status
    message: str = ""

    def to_dict(self) -> dict[str, Any]:
        """Plain dictionary (JSON-ready)."""
        return asdict(self)


@dataclass(frozen=True)
class SimulationResult:
    """Result of :func:`simulate`.

    The tables are built from the integrator's arrays when first asked for, so a caller that
    needs only the summary (the command line, a batch) never imports pandas or xarray.

    Attributes
    ----------
    summary
        Scalar results.
    history
        ``xarray.Dataset`` with ``x`` [m], ``v`` [m/s] and ``phase`` (0 unstepped, ±1 stepped on
        that side, ±2 held on the surface x = ±x_c) on ``time`` [s] at the sample times; None
        when ``record_history=False``.
    events
        ``pandas.DataFrame``: time_s, kind (liftoff, touchdown, cap, escape, settle), v_in_m_s,
        v_out_m_s (velocity before and after, C_r applied at touchdown). A ``settle`` event
        ends an accumulating sequence of impacts summed in closed form (chatter): from then on
        the frame is seated on the surface until the ground can lift it again.
    episodes
        ``pandas.DataFrame``: start_s, end_s (NaN if still stepped at the end), side (+1/-1),
        peak_abs_x_m; :meth:`episode_records` gives the same rows as dictionaries.
    frame_frequency
        ``xarray.DataArray`` ω_f(t) [rad/s] on the history's ``time``: the frame's instantaneous
        frequency 2π/T(A), A the amplitude of the free conservative orbit through the state
        (coordinate ``amplitude`` [m]; :mod:`stepframe.structure.frame_frequency`); None
        without a history.
    input_energy
        ``xarray.DataArray`` of the work the ground has done on the frame since t = 0
        [m²/s², per unit of the model's mass] on the history's ``time``; None without a history.
    model, ground_acc_m_s2
        The model constants integrated and the ground acceleration the frame felt (scaled,
        [m/s²], without the tail), kept for ``frame_frequency`` and ``input_energy``.
    """

    summary: SimulationSummary
    raw: RawRun = field(repr=False)
    dt_s: float
    units: str
    model: Model | None = field(default=None, repr=False, compare=False)
    ground_acc_m_s2: np.ndarray | None = field(default=None, repr=False, compare=False)

    @cached_property
    def history(self) -> xr.Dataset | None:
        import xarray as xr

        raw = self.raw
        if not raw.hist_x.size:
            return None
        time_s = np.arange(raw.hist_x.size) * self.dt_s
        units = self.units
        return xr.Dataset(
            {
                "x": ("time", raw.hist_x, {"units": units, "long_name": "displacement x"}),
                "v": ("time", raw.hist_v, {"units": units + "/s", "long_name": "velocity"}),
                "phase": (
                    "time",
                    raw.hist_p,
                    {"long_name": "phase: 0 unstepped, ±1 stepped, ±2 held at ±x_c"},
                ),
            },
            coords={"time": ("time", time_s, {"units": "s"})},
        )

    @cached_property
    def frame_frequency(self) -> xr.DataArray | None:
        from stepframe.structure.frame_frequency import frequency_history

        return frequency_history(self)

    @cached_property
    def input_energy(self) -> xr.DataArray | None:
        from stepframe.structure.frame_frequency import input_energy_history

        return input_energy_history(self)

    @cached_property
    def event_kinds(self) -> list[str]:
        """Kind of each event in time order (liftoff, touchdown, cap, escape, settle)."""
        return [EVENT_NAMES.get(int(k), "unknown") for k in self.raw.ev_kind]

    @cached_property
    def events(self) -> pd.DataFrame:
        import pandas as pd

        return pd.DataFrame(
            {
                "time_s": self.raw.ev_t,
                "kind": self.event_kinds,
                "v_in_m_s": self.raw.ev_v_in,
                "v_out_m_s": self.raw.ev_v_out,
            }
        )

    def episode_records(self) -> list[dict[str, float]]:
        """Stepping episodes as dictionaries: start_s, end_s, side, peak_abs_x_m."""
        raw, kinds = self.raw, self.event_kinds
        rows: list[dict[str, float]] = []
        for j, kind in enumerate(kinds):
            if kind != "liftoff":
                continue
            # The kernel stores the episode peak signed by its side.
            side = math.copysign(1.0, float(raw.ev_peak[j]))
            end = math.nan
            for jj in range(j + 1, len(kinds)):
                if kinds[jj] == "touchdown":
                    end = float(raw.ev_t[jj])
                    break
                if kinds[jj] == "liftoff":
                    break
            rows.append(
                {
                    "start_s": float(raw.ev_t[j]),
                    "end_s": end,
                    "side": side,
                    "peak_abs_x_m": abs(float(raw.ev_peak[j])),
                }
            )
        return rows

    @cached_property
    def episodes(self) -> pd.DataFrame:
        import pandas as pd

        return pd.DataFrame(
            self.episode_records(), columns=["start_s", "end_s", "side", "peak_abs_x_m"]
        )

    @property
    def impact_velocities_m_s(self) -> np.ndarray:
        """Velocities just before each impact [m/s]."""
        return np.asarray(self.raw.ev_v_in[self.raw.ev_kind == EVENT_TOUCHDOWN], dtype=float)

    @property
    def switching_times_s(self) -> np.ndarray:
        """Times of lift-offs and touchdowns, in order [s]."""
        keep = np.isin(self.raw.ev_kind, (EVENT_LIFTOFF, EVENT_TOUCHDOWN))
        return np.asarray(self.raw.ev_t[keep], dtype=float)


class FrameLike(Protocol):
    """What the simulator reads from a frame: the model constants of eqs. 4.11-4.12.

    :class:`~stepframe.structure.frame.PortalFrame` is one; any object with these attributes
    (SI units, as documented there) is accepted. A height for drift ratios is taken from
    ``h_r_m`` or ``drift_ratio_per_m`` when the object has one.
    """

    @property
    def omega_1_rad_s(self) -> float: ...
    @property
    def omega_2_rad_s(self) -> float: ...
    @property
    def p_1(self) -> float: ...
    @property
    def p_2(self) -> float: ...
    @property
    def gamma_1_m_s2(self) -> float: ...
    @property
    def xi_1(self) -> float: ...
    @property
    def xi_2(self) -> float: ...
    @property
    def x_c_m(self) -> float: ...
    @property
    def c_r(self) -> float: ...
    @property
    def x_cap_m(self) -> float | None: ...


def model_of(frame: FrameLike) -> Model:
    """Model constants of a frame (any object with the fields of PortalFrame).

    An x_c below ``INVARIANT_RTOL``·x* (1e-9 x*) is taken as the rigid-block limit x_c = 0: the
    unstepped phase is then narrower than the rounding of x near the surface, so no integrator
    can tell which side of it a state is on, and crossing it takes no time at any finite speed.
    """
    names = Model._fields
    values = []
    for name in names:
        if not hasattr(frame, name):
            raise InputError(f"frame has no field {name!r}, expected a PortalFrame")
        value = getattr(frame, name)
        if name == "x_cap_m" and value is None:
            value = math.inf
        values.append(float(value))
    model = Model(*values)
    if not model.x_c_m >= 0:
        raise InputError(f"x_c_m = {model.x_c_m}, expected ≥ 0")
    for name in ("omega_1_rad_s", "omega_2_rad_s", "gamma_1_m_s2"):
        if not getattr(model, name) > 0:
            raise InputError(f"{name} = {getattr(model, name)}, expected > 0")
    x_star = model.gamma_1_m_s2 / model.omega_2_rad_s**2
    if model.x_c_m < INVARIANT_RTOL * x_star:
        model = model._replace(x_c_m=0.0)
    return model


def _check_motion(
    ground_acc_m_s2: ArrayLike, dt_s: float, name: str = "ground_acc_m_s2"
) -> np.ndarray:
    ag = np.asarray(ground_acc_m_s2, dtype=float)
    if ag.ndim != 1 or ag.size < 2:
        raise InputError(f"{name} has shape {ag.shape}, expected a 1-D series of ≥ 2 samples")
    bad = np.flatnonzero(~np.isfinite(ag))
    if bad.size:
        raise InputError(
            f"{name}[{bad[0]}] = {ag[bad[0]]} ({bad.size} non-finite samples), "
            "expected finite accelerations [m/s²]"
        )
    if not (isinstance(dt_s, int | float) and math.isfinite(dt_s) and dt_s > 0):
        raise InputError(f"dt_s = {dt_s!r}, expected a finite time step > 0 s")
    return ag


def _check_run_work(
    n_samples: int, n_tail: int, dt_s: float, tail_s: float, record_history: bool, runs: int = 1
) -> None:
    """Refuse a run (or ``runs`` runs) whose intervals or kept history pass the limits of
    :mod:`stepframe.structure.work`, before any array is allocated."""
    from stepframe.structure import work

    intervals = float(n_samples - 1 + n_tail)
    what = f"{runs} run(s) of {n_samples} samples at {dt_s:g} s with a {tail_s:g} s tail"
    work.check_work(runs * work.INTERVAL_UNITS * intervals, what, "shorten the tail or the record")
    if record_history:
        work.check_samples(intervals + 1, what, "shorten the tail or pass record_history=False")


def _height(frame: FrameLike, height_m: float | None) -> float | None:
    if height_m is not None:
        return validation.positive("height_m", height_m)
    per_m = getattr(frame, "drift_ratio_per_m", None)
    if isinstance(per_m, int | float) and per_m > 0:
        return 1.0 / float(per_m)
    for name in ("h_r_m", "height_m"):
        value = getattr(frame, name, None)
        if isinstance(value, int | float) and value > 0:
            return float(value)
    return None


def _run_exact(
    model: Model,
    ag: np.ndarray,
    dt_s: float,
    n_tail: int,
    x0: float,
    v0: float,
    record_history: bool,
) -> RawRun:
    from stepframe.structure import _exact

    n_hist = ag.size + n_tail if record_history else 0
    capacity = 256
    while True:
        hist_x = np.empty(n_hist)
        hist_v = np.empty(n_hist)
        hist_p = np.zeros(n_hist, dtype=np.int8)
        ev_t = np.empty(capacity)
        ev_kind = np.empty(capacity, dtype=np.int8)
        ev_v_in = np.empty(capacity)
        ev_v_out = np.empty(capacity)
        ev_peak = np.empty(capacity)
        res = _exact.integrate(
            ag, dt_s, n_tail, *model, x0, v0, hist_x, hist_v, hist_p,
            ev_t, ev_kind, ev_v_in, ev_v_out, ev_peak,
        )  # fmt: skip
        n_ev = int(res[1])
        if n_ev <= capacity:
            break
        capacity = n_ev  # rerun once with room for every event
    return RawRun(
        status=int(res[0]),
        n_liftoffs=int(res[2]),
        n_impacts=int(res[3]),
        peak_abs_x=float(res[4]),
        peak_time_s=float(res[5]),
        overturned=bool(res[6]),
        overturn_time_s=float(res[7]),
        x_end=float(res[8]),
        v_end=float(res[9]),
        phase_end=int(res[10]),
        ev_t=ev_t[:n_ev],
        ev_kind=ev_kind[:n_ev],
        ev_v_in=ev_v_in[:n_ev],
        ev_v_out=ev_v_out[:n_ev],
        ev_peak=ev_peak[:n_ev],
        hist_x=hist_x,
        hist_v=hist_v,
        hist_p=hist_p,
    )


class Integrator(Protocol):
    """A simulator method: integrates :class:`Model` under ``ag`` and returns a :class:`RawRun`.

    ``ag`` is the scaled ground acceleration [m/s²] at spacing ``dt_s`` [s], linear between
    samples, followed by ``n_tail`` free intervals; ``rtol``/``atol`` are for methods that take
    tolerances (others ignore them). Pass one as ``method=`` to :func:`simulate` to add a method
    without registering it, or add it to :data:`METHODS` under a name.
    """

    def __call__(
        self,
        model: Model,
        ag: np.ndarray,
        dt_s: float,
        n_tail: int,
        x0: float,
        v0: float,
        record_history: bool,
        rtol: float,
        atol: float,
    ) -> RawRun: ...


def _exact_method(
    model: Model, ag: np.ndarray, dt_s: float, n_tail: int, x0: float, v0: float,
    record_history: bool, rtol: float, atol: float,
) -> RawRun:  # fmt: skip
    return _run_exact(model, ag, dt_s, n_tail, x0, v0, record_history)


@dataclass(frozen=True)
class _SolveIvpMethod:
    """The solve_ivp reference with one of scipy's methods (imported only when run)."""

    name: str

    def __call__(
        self, model: Model, ag: np.ndarray, dt_s: float, n_tail: int, x0: float, v0: float,
        record_history: bool, rtol: float, atol: float,
    ) -> RawRun:  # fmt: skip
        from stepframe.structure.reference import integrate_reference

        return integrate_reference(
            model, ag, dt_s, n_tail, x0, v0, self.name, rtol, atol, record_history
        )


#: Simulator methods by name: the exact piecewise-analytic kernel, and the solve_ivp
#: cross-checks. :data:`Method` lists the same names (a test keeps them in sync).
METHODS: dict[str, Integrator] = {
    "exact": _exact_method,
    **{name: _SolveIvpMethod(name) for name in ("RK45", "DOP853", "Radau", "LSODA")},
}


def _checked_status(raw: RawRun, model: Model, ag: np.ndarray, x0: float) -> int:
    """The run's status, downgraded when the result is not physically possible.

    Applied to every method (a user's callable too): non-finite values are never "ok", and a
    frame that did not overturn can pass neither its cap nor y_e = (γ₁ + P₂ max|ẍ_g|)/ω₂², the
    displacement beyond which a stepped frame moving outward cannot return (docs/paper-notes.md).
    """
    bound = no_escape_bound_m(
        model.gamma_1_m_s2, model.p_2, model.omega_2_rad_s, float(np.max(np.abs(ag))), x0,
        model.x_cap_m,
    )  # fmt: skip
    return run_invariant(raw.status, raw.overturned, raw.peak_abs_x, bound, raw.x_end, raw.v_end)


def _result(
    raw: RawRun, dt_s: float, height: float | None, units: str, status: int, model: Model,
    ag: np.ndarray,
) -> SimulationResult:  # fmt: skip
    from stepframe.structure.status import small_angle_note

    message = STATUS_MESSAGES.get(status, f"unknown status code {status}")
    if status == STATUS_OK:
        # x = hθ for a linearised block (θ itself, h = 1, for simulate_rigid_block).
        h = 1.0 if units == "rad" else height
        message = small_angle_note(model.x_c_m, model.gamma_1_m_s2 / model.omega_2_rad_s**2, h,
                                   raw.peak_abs_x)  # fmt: skip
    summary = SimulationSummary(
        peak_abs_x_m=raw.peak_abs_x,
        peak_time_s=raw.peak_time_s,
        peak_drift_ratio=None if height is None else raw.peak_abs_x / height,
        overturned=raw.overturned,
        overturn_time_s=(
            None if not raw.overturned or math.isnan(raw.overturn_time_s) else raw.overturn_time_s
        ),
        n_stepping_episodes=raw.n_liftoffs,
        n_impacts=raw.n_impacts,
        residual_x_m=raw.x_end,
        residual_v_m_s=raw.v_end,
        status=STATUS_NAMES.get(status, "failed"),
        message=message,
    )
    return SimulationResult(summary, raw, dt_s, units, model, ag)


def simulate(
    frame: FrameLike,
    ground_acc_m_s2: ArrayLike,
    dt_s: float,
    *,
    scale: float = 1.0,
    tail_s: float = DEFAULT_TAIL_S,
    method: Method | Integrator = "exact",
    rtol: float = 1e-10,
    atol: float = 1e-14,
    x0_m: float = 0.0,
    v0_m_s: float = 0.0,
    record_history: bool = True,
    height_m: float | None = None,
) -> SimulationResult:
    """Response of a stepping frame to a ground-acceleration record.

    Parameters
    ----------
    frame
        The model constants (a :class:`~stepframe.structure.frame.PortalFrame`, or any object
        with its fields; ``x_c_m = 0`` gives the rigid-block limit, impact at x = 0).
    ground_acc_m_s2
        Ground acceleration samples [m/s²], linear between samples.
    dt_s
        Sampling interval [s].
    scale
        Factor applied to the record [-].
    tail_s
        Free vibration (zero ground acceleration) after the record [s]; rounded up to whole
        steps of ``dt_s``.
    method
        A name of :data:`METHODS`: ``"exact"`` (piecewise-analytic, default) or a ``solve_ivp``
        method for the cross-check (``"RK45"``, ``"DOP853"``, ``"Radau"``, ``"LSODA"``); or an
        :class:`Integrator` callable.
    rtol, atol
        Tolerances of the ``solve_ivp`` methods (checked and passed to any method; unused by
        ``"exact"``).
    x0_m, v0_m_s
        Initial displacement [m] and velocity [m/s].
    record_history
        Keep x, v and phase at every sample time.
    height_m
        Height for the drift ratio [m]; by default taken from the frame if it has one.

    Returns
    -------
    SimulationResult
        Numerical failure is reported in ``summary.status``, not raised.

    Raises
    ------
    InputError
        Non-finite ground motion, ``dt_s ≤ 0``, unknown method, or non-physical constants.

    Examples
    --------
    >>> from stepframe.structure.frame import PortalFrame
    >>> frame = PortalFrame(omega_1_rad_s=10.0, omega_2_rad_s=1.5, p_1=1.0, p_2=0.8,
    ...                     gamma_1_m_s2=0.5, xi_1=0.05, xi_2=0.0, x_c_m=0.02, c_r=0.9)
    >>> import numpy as np
    >>> t = np.arange(0, 10, 0.01)
    >>> result = simulate(frame, 3.0 * np.sin(2 * np.pi * t), 0.01)
    >>> result.summary.n_stepping_episodes > 0
    True
    """
    model = model_of(frame)
    ag = _check_motion(ground_acc_m_s2, dt_s)
    scale = validation.finite("scale", scale)
    tail_s = validation.non_negative("tail_s", tail_s)
    x0 = validation.finite("x0_m", x0_m)
    v0 = validation.finite("v0_m_s", v0_m_s)
    if isinstance(method, str):
        if method not in METHODS:
            raise InputError(f"method = {method!r}, expected one of {', '.join(METHODS)}")
        integrator = METHODS[method]
    elif callable(method):
        integrator = method
    else:
        raise InputError(f"method = {method!r}, expected a name of METHODS or a callable")
    if model.x_cap_m < math.inf and abs(x0) >= model.x_cap_m:
        raise InputError(f"x0_m = {x0}, expected |x0_m| < x_cap_m = {model.x_cap_m}")
    for name, tol in (("rtol", rtol), ("atol", atol)):
        if not (isinstance(tol, int | float) and math.isfinite(tol) and tol > 0):
            raise InputError(f"{name} = {tol!r}, expected a finite tolerance > 0")
    height = _height(frame, height_m)
    n_tail = math.ceil(tail_s / dt_s - 1e-9)
    _check_run_work(ag.size, n_tail, dt_s, tail_s, record_history)
    ag = ag * scale
    raw = integrator(model, ag, float(dt_s), n_tail, x0, v0, record_history, rtol, atol)
    status = _checked_status(raw, model, ag, x0)
    return _result(raw, float(dt_s), height, "m", status, model, ag)


def simulate_rigid_block(
    p_rad_s: float,
    alpha_rad: float,
    c_r: float,
    ground_acc_m_s2: ArrayLike,
    dt_s: float,
    *,
    theta0_rad: float = 0.0,
    omega0_rad_s: float = 0.0,
    g_m_s2: float = PAPER_G_M_S2,
    tail_s: float = DEFAULT_TAIL_S,
    record_history: bool = True,
) -> SimulationResult:
    """Linearised Housner block, θ̈ = -p²(α·sgn θ - θ) - (p²/g)·ẍ_g, impact at θ = 0.

    The stepped phase of eq. 4.12 with ω₂ = p, γ₁ = p²α, P₂ = p²/g, ξ₂ = 0 and x_c = 0 (no
    unstepped phase: an impact at θ = 0 passes the block to the other side with its angular
    velocity times ``c_r``; Housner's value is η = 1 - 1.5 sin²α). ``x`` of the result is θ
    [rad]. Separate from PortalFrame, whose validation requires x_c > 0.

    Parameters
    ----------
    p_rad_s
        Frequency parameter p = √(3g/4R) of a rectangular block [rad/s].
    alpha_rad
        Slenderness angle α [rad].
    c_r
        Angular-velocity ratio at impact [-].
    ground_acc_m_s2, dt_s
        Ground acceleration [m/s²] and sampling interval [s].
    theta0_rad, omega0_rad_s
        Initial rotation [rad] and angular velocity [rad/s].
    g_m_s2
        Gravity [m/s²]; the structure API's one default, 9.81 (the paper's examples, as
        :meth:`~stepframe.structure.frame.PortalFrame.housner_block`).
    tail_s, record_history
        As in :func:`simulate`.
    """
    for name, value in (("p_rad_s", p_rad_s), ("alpha_rad", alpha_rad), ("g_m_s2", g_m_s2)):
        validation.positive(name, value)
    validation.in_range("c_r", c_r, 0.0, 1.0)
    model = Model(p_rad_s, p_rad_s, 0.0, p_rad_s**2 / g_m_s2, p_rad_s**2 * alpha_rad,
                  0.0, 0.0, 0.0, c_r, math.inf)  # fmt: skip
    ag = _check_motion(ground_acc_m_s2, dt_s)
    tail_s = validation.non_negative("tail_s", tail_s)
    n_tail = math.ceil(tail_s / dt_s - 1e-9)
    _check_run_work(ag.size, n_tail, dt_s, tail_s, record_history)
    theta0 = validation.finite("theta0_rad", theta0_rad)
    omega0 = validation.finite("omega0_rad_s", omega0_rad_s)
    raw = _run_exact(model, ag, float(dt_s), n_tail, theta0, omega0, record_history)
    status = _checked_status(raw, model, ag, theta0)
    return _result(raw, float(dt_s), None, "rad", status, model, ag)


@dataclass(frozen=True)
class BatchRecord:
    """One record of a batch: ground acceleration [m/s²] and its sampling interval [s]."""

    ground_acc_m_s2: np.ndarray
    dt_s: float


@dataclass(frozen=True)
class _BatchBlock:
    """A contiguous block of (record, scale) pairs with only the records it uses (picklable)."""

    series: tuple[np.ndarray, ...]
    dts: np.ndarray
    tails: np.ndarray
    rec_local: np.ndarray
    scales: np.ndarray
    params: np.ndarray
    first: int

    def __str__(self) -> str:
        return f"pairs {self.first}-{self.first + self.scales.size - 1}"


def _batch_threads() -> int:
    """Threads of an in-process batch: numba's thread count (``numba.set_num_threads`` when the
    caller set it, else ``NUMBA_NUM_THREADS``, by default the CPUs this process may use), read
    without starting numba's thread pool, which the batch does not use."""
    import numba
    from numba.np.ufunc import parallel

    if getattr(parallel, "_is_initialized", False):  # set_num_threads started the pool
        return int(numba.get_num_threads())
    return int(numba.config.NUMBA_NUM_THREADS)  # type: ignore[attr-defined]


def _run_block(block: _BatchBlock) -> np.ndarray:
    """Summaries of one block, on all cores through threads (the kernel releases the GIL).

    In a worker (a thread of a thread pool, or a process of a pool) the block runs on that one
    thread: the pool is the parallelism there. In the process's main thread the pairs are cut
    into four pieces per thread, taken in turn by :func:`_batch_threads` threads (records
    differ in length).
    """
    import multiprocessing
    import threading
    from concurrent.futures import ThreadPoolExecutor

    from stepframe.structure import _exact

    n_pairs = block.scales.size
    threads = min(_batch_threads(), n_pairs)
    worker_thread = threading.current_thread() is not threading.main_thread()
    if worker_thread or multiprocessing.parent_process() is not None:
        threads = 1
    flat = np.concatenate(block.series)
    offsets = np.zeros(len(block.series) + 1, dtype=np.int64)
    offsets[1:] = np.cumsum([a.size for a in block.series])
    out = np.empty((n_pairs, 10))

    def run(first: int, stop: int) -> None:
        _exact.integrate_batch(flat, offsets, block.rec_local[first:stop],
                               block.scales[first:stop], block.dts, block.tails, block.params,
                               out[first:stop])  # fmt: skip

    if threads <= 1:
        run(0, n_pairs)
        return out
    bounds = np.linspace(0, n_pairs, min(n_pairs, 4 * threads) + 1).astype(np.int64)
    with ThreadPoolExecutor(threads) as pool:
        list(pool.map(run, bounds[:-1].tolist(), bounds[1:].tolist()))
    return out


def _blocks(
    series: list[np.ndarray], dts: list[float], rec_index: np.ndarray, pair_scales: np.ndarray,
    tail_s: float, params: np.ndarray, n_blocks: int,
) -> list[_BatchBlock]:  # fmt: skip
    size = max(1, math.ceil(rec_index.size / n_blocks))
    blocks = []
    for first in range(0, rec_index.size, size):
        recs = rec_index[first : first + size]
        used, local = np.unique(recs, return_inverse=True)
        block_dts = np.asarray([dts[r] for r in used])
        blocks.append(
            _BatchBlock(
                series=tuple(series[r] for r in used),
                dts=block_dts,
                tails=np.asarray([math.ceil(tail_s / dt - 1e-9) for dt in block_dts], np.int64),
                rec_local=local.astype(np.int64),
                scales=pair_scales[first : first + size],
                params=params,
                first=first,
            )
        )
    return blocks


def simulate_batch(
    frame: FrameLike,
    records: Sequence[BatchRecord | tuple[ArrayLike, float]],
    scales: Sequence[float] | np.ndarray,
    *,
    pairs: Literal["product", "zip"] = "product",
    tail_s: float = DEFAULT_TAIL_S,
    x0_m: float = 0.0,
    v0_m_s: float = 0.0,
    height_m: float | None = None,
    jobs: int = 1,
    executor: Executor | None = None,
    progress: bool | str = False,
) -> pd.DataFrame:
    """Summaries of many (record, scale) pairs with the exact method, through the one executor.

    The pairs are cut into blocks handed to :func:`stepframe.core.execution.map_items`; each
    block runs on all the cores of its worker (threads running a kernel that releases the GIL;
    one thread in a pool's worker). With the default
    ``jobs=1`` there is one block, run in this process: on one machine that is the fastest way
    (docs/benchmarks.md measures it against a process pool). ``jobs`` > 1 or an ``executor``
    (a Dask client's ``get_executor()``) spreads blocks over workers, for clusters.

    Parameters
    ----------
    frame
        As in :func:`simulate`.
    records
        ``BatchRecord`` or ``(ground_acc_m_s2, dt_s)`` pairs.
    scales
        Scale factors [-]. With ``pairs="product"`` every record runs at every scale (an IDA
        grid); with ``pairs="zip"`` scales[j] goes with records[j].
    tail_s, x0_m, v0_m_s, height_m
        As in :func:`simulate`.
    jobs, executor, progress
        As in :func:`~stepframe.core.execution.map_items` (blocks: 4 per worker).

    Returns
    -------
    pandas.DataFrame
        One row per pair: record, scale, the :class:`SimulationSummary` fields. A block whose
        worker failed gives its rows status "failed", NaN values and the error as ``message``.
    """
    return batch_summaries(
        frame, records, scales, pairs=pairs, tail_s=tail_s, x0_m=x0_m, v0_m_s=v0_m_s,
        height_m=height_m, jobs=jobs, executor=executor, progress=progress,
    ).table()  # fmt: skip


@dataclass(frozen=True)
class BatchSummaries:
    """The runs of :func:`batch_summaries`, one per (record, scale) pair, as arrays.

    Attributes
    ----------
    record, scale
        Each pair's record index and scale factor [-].
    values
        The kernel's summary of each pair, shape (pairs, 10): status code, stepping episodes,
        impacts, peak |x| [m], its time [s], overturned (> 0), overturning time [s], x [m]
        and v [m/s] at the end, the phase at the end (NaN rows: a failed block).
    codes
        Each pair's status code (None: its block failed).
    messages
        Each pair's status message, or its block's error ("" when none).
    height_m
        The height that turns peak |x| into a drift ratio [m] (None: no drift ratio).
    """

    record: np.ndarray
    scale: np.ndarray
    values: np.ndarray
    codes: list[int | None]
    messages: list[str]
    height_m: float | None

    @property
    def overturned(self) -> np.ndarray:
        """Whether each run overturned the frame."""
        return np.asarray(self.values[:, 5] > 0)

    @property
    def peak_abs_x_m(self) -> np.ndarray:
        """Peak |x| of each run [m]."""
        return np.asarray(self.values[:, 3])

    @property
    def status(self) -> list[str]:
        """Each run's status name (``"ok"``, ...; ``"failed"`` for a failed block)."""
        return ["failed" if c is None else STATUS_NAMES.get(c, "failed") for c in self.codes]

    def table(self) -> pd.DataFrame:
        """One row per pair: record, scale, the :class:`SimulationSummary` fields (the table
        of :func:`simulate_batch`)."""
        import pandas as pd

        out, height, overturned = self.values, self.height_m, self.overturned
        return pd.DataFrame(
            {
                "record": self.record,
                "scale": self.scale,
                "peak_abs_x_m": out[:, 3],
                "peak_time_s": out[:, 4],
                "peak_drift_ratio": out[:, 3] / height if height is not None else np.nan,
                "overturned": overturned,
                "overturn_time_s": np.where(overturned, out[:, 6], np.nan),
                "n_stepping_episodes": np.nan_to_num(out[:, 1], nan=-1).astype(np.int64),
                "n_impacts": np.nan_to_num(out[:, 2], nan=-1).astype(np.int64),
                "residual_x_m": out[:, 7],
                "residual_v_m_s": out[:, 8],
                "status": self.status,
                "message": self.messages,
            }
        )


def batch_summaries(
    frame: FrameLike,
    records: Sequence[BatchRecord | tuple[ArrayLike, float]],
    scales: Sequence[float] | np.ndarray,
    *,
    pairs: Literal["product", "zip"] = "product",
    tail_s: float = DEFAULT_TAIL_S,
    x0_m: float = 0.0,
    v0_m_s: float = 0.0,
    height_m: float | None = None,
    jobs: int = 1,
    executor: Executor | None = None,
    progress: bool | str = False,
) -> BatchSummaries:
    """:func:`simulate_batch`'s runs as arrays (:class:`BatchSummaries`), without its table:
    what a caller that reads a few columns of many small batches needs (the selection's
    ranking calls it some ten times per group of records, and building the table took about
    as long as the runs of a group's bisection steps; docs/benchmarks.md, issue 29).

    Parameters and raises as :func:`simulate_batch`.
    """
    from stepframe.core.execution import map_items

    model = model_of(frame)
    tail_s = validation.non_negative("tail_s", tail_s)
    x0 = validation.finite("x0_m", x0_m)
    v0 = validation.finite("v0_m_s", v0_m_s)
    height = _height(frame, height_m)
    series = []
    dts = []
    for j, rec in enumerate(records):
        acc, dt = (rec.ground_acc_m_s2, rec.dt_s) if isinstance(rec, BatchRecord) else rec
        series.append(_check_motion(acc, dt, name=f"records[{j}]"))
        dts.append(float(dt))
    scale_arr = np.asarray(scales, dtype=float).ravel()
    for j, s in enumerate(scale_arr):
        validation.finite(f"scales[{j}]", float(s))
    if not series:
        raise InputError("records is empty, expected at least one record")
    if pairs == "product":
        rec_index = np.repeat(np.arange(len(series)), scale_arr.size)
        pair_scales = np.tile(scale_arr, len(series))
    elif pairs == "zip":
        if scale_arr.size != len(series):
            raise InputError(
                f"{scale_arr.size} scales for {len(series)} records, expected one per record"
            )
        # A record given for several pairs (an IDA's scales of one record) is one record: each
        # block concatenates its records, and a copy per pair held scales × samples (200
        # probes of one 200,000-sample record: 342 MiB, against 17 MiB for one scale).
        first_of: dict[tuple[int, float], int] = {}
        keys = [(id(a), dt) for a, dt in zip(series, dts, strict=True)]
        rec_index = np.asarray(
            [first_of.setdefault(key, j) for j, key in enumerate(keys)], dtype=np.int64
        )
        pair_scales = scale_arr
    else:
        raise InputError(f"pairs = {pairs!r}, expected 'product' or 'zip'")
    intervals = [
        a.size - 1 + math.ceil(tail_s / dt - 1e-9) for a, dt in zip(series, dts, strict=True)
    ]
    from stepframe.structure import work

    work.check_work(
        work.INTERVAL_UNITS * float(sum(intervals[r] for r in rec_index)),
        f"{rec_index.size} runs of {len(series)} record(s) with a {tail_s:g} s tail",
        "ask for fewer runs or a shorter tail",
    )  # fmt: skip
    params = np.asarray([*model, x0, v0], dtype=float)
    spread = executor is not None or jobs > 1
    n_blocks = 4 * max(1, jobs) if spread else 1
    blocks = _blocks(series, dts, rec_index, pair_scales, tail_s, params, n_blocks)
    outcome = map_items(
        _run_block, blocks, jobs=jobs, executor=executor, chunk_size=1, stage="simulate",
        progress=progress,
    )  # fmt: skip
    out = np.full((rec_index.size, 10), np.nan)
    messages = [""] * rec_index.size
    codes: list[int | None] = [None] * rec_index.size
    for k, result in zip(outcome.indices, outcome.results, strict=True):
        block = blocks[k]
        out[block.first : block.first + block.scales.size] = result
        for j in range(block.first, block.first + block.scales.size):
            codes[j] = int(result[j - block.first, 0])
            messages[j] = STATUS_MESSAGES.get(codes[j] or 0, "")
    for failure in outcome.failures:
        block = next(b for b in blocks if str(b) == failure.item)
        for j in range(block.first, block.first + block.scales.size):
            messages[j] = f"{failure.error_type}: {failure.message}"
    return BatchSummaries(rec_index, pair_scales, out, codes, messages, height)
