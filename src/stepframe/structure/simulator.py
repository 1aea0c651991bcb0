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
with ẋ outward (see docs/paper-notes.md). Under forcing a trajectory may return from beyond x*, so
nothing is decided before the record ends.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, Any, Literal, NamedTuple

import numpy as np

from stepframe.errors import InputError

if TYPE_CHECKING:
    import pandas as pd
    import xarray as xr

    from stepframe.structure.frame import PortalFrame

Method = Literal["exact", "RK45", "DOP853", "Radau", "LSODA"]
Status = Literal["success", "nonfinite", "too_many_events", "solver_failed"]

_METHODS: tuple[str, ...] = ("exact", "RK45", "DOP853", "Radau", "LSODA")
#: Status codes of a run (:class:`RawRun`), set by the kernel and by the solve_ivp reference.
STATUS_OK = 0
STATUS_NONFINITE = 1
STATUS_TOO_MANY_EVENTS = 2
STATUS_SOLVER_FAILED = 3
_STATUS: dict[int, Status] = {
    STATUS_OK: "success",
    STATUS_NONFINITE: "nonfinite",
    STATUS_TOO_MANY_EVENTS: "too_many_events",
    STATUS_SOLVER_FAILED: "solver_failed",
}

#: Event kinds stored in :attr:`RawRun.ev_kind`, by the kernel and by the solve_ivp reference.
EVENT_LIFTOFF = 1
EVENT_TOUCHDOWN = 2
EVENT_CAP = 3
EVENT_ESCAPE = 4
_EVENT_NAMES = {
    EVENT_LIFTOFF: "liftoff",
    EVENT_TOUCHDOWN: "touchdown",
    EVENT_CAP: "cap",
    EVENT_ESCAPE: "escape",
}

#: Default free-vibration tail after the record [s].
DEFAULT_TAIL_S = 10.0


class Model(NamedTuple):
    """Model constants passed to the kernels (SI; x_c may be 0 for the rigid-block limit)."""

    omega_1_rad_s: float
    omega_2_rad_s: float
    p_1: float
    p_2: float
    gamma_1_m_s2: float
    xi_1: float
    xi_2: float
    x_c_m: float
    c_r: float
    x_cap_m: float  # math.inf when there is no cap


@dataclass
class RawRun:
    """What an integrator hands back, before it is turned into a :class:`SimulationResult`."""

    status: int
    n_liftoffs: int
    n_impacts: int
    peak_abs_x: float
    peak_time_s: float
    overturned: bool
    overturn_time_s: float
    x_end: float
    v_end: float
    phase_end: int
    ev_t: np.ndarray
    ev_kind: np.ndarray
    ev_v_in: np.ndarray
    ev_v_out: np.ndarray
    ev_peak: np.ndarray
    hist_x: np.ndarray
    hist_v: np.ndarray
    hist_p: np.ndarray


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
        "success", or the numerical failure met ("nonfinite", "too_many_events",
        "solver_failed").
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
        ``pandas.DataFrame``: time_s, kind (liftoff, touchdown, cap, escape), v_in_m_s,
        v_out_m_s (velocity before and after, C_r applied at touchdown).
    episodes
        ``pandas.DataFrame``: start_s, end_s (NaN if still stepped at the end), side (+1/-1),
        peak_abs_x_m; :meth:`episode_records` gives the same rows as dictionaries.
    """

    summary: SimulationSummary
    raw: RawRun = field(repr=False)
    dt_s: float
    units: str

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
    def event_kinds(self) -> list[str]:
        """Kind of each event in time order (liftoff, touchdown, cap, escape)."""
        return [_EVENT_NAMES.get(int(k), "unknown") for k in self.raw.ev_kind]

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


def model_of(frame: PortalFrame | Any) -> Model:
    """Model constants of a frame (any object with the fields of PortalFrame)."""
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
    return model


def _check_motion(ground_acc_m_s2: Any, dt_s: float, name: str = "ground_acc_m_s2") -> np.ndarray:
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


def _check_scalar(name: str, value: float, minimum: float | None = None) -> float:
    if not (isinstance(value, int | float) and math.isfinite(value)):
        raise InputError(f"{name} = {value!r}, expected a finite number")
    if minimum is not None and value < minimum:
        raise InputError(f"{name} = {value}, expected ≥ {minimum}")
    return float(value)


def _height(frame: Any, height_m: float | None) -> float | None:
    if height_m is not None:
        height = _check_scalar("height_m", height_m)
        if height <= 0:
            raise InputError(f"height_m = {height_m}, expected > 0")
        return height
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


def _result(raw: RawRun, dt_s: float, height: float | None, units: str) -> SimulationResult:
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
        status=_STATUS.get(raw.status, "solver_failed"),
    )
    return SimulationResult(summary=summary, raw=raw, dt_s=dt_s, units=units)


def simulate(
    frame: PortalFrame | Any,
    ground_acc_m_s2: Any,
    dt_s: float,
    *,
    scale: float = 1.0,
    tail_s: float = DEFAULT_TAIL_S,
    method: Method = "exact",
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
        ``"exact"`` (piecewise-analytic, default) or a ``solve_ivp`` method name for the
        cross-check (``"RK45"``, ``"DOP853"``, ``"Radau"``, ``"LSODA"``).
    rtol, atol
        Tolerances of the ``solve_ivp`` methods (unused by ``"exact"``).
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
    scale = _check_scalar("scale", scale)
    tail_s = _check_scalar("tail_s", tail_s, minimum=0.0)
    x0 = _check_scalar("x0_m", x0_m)
    v0 = _check_scalar("v0_m_s", v0_m_s)
    if method not in _METHODS:
        raise InputError(f"method = {method!r}, expected one of {', '.join(_METHODS)}")
    if model.x_cap_m < math.inf and abs(x0) >= model.x_cap_m:
        raise InputError(f"x0_m = {x0}, expected |x0_m| < x_cap_m = {model.x_cap_m}")
    height = _height(frame, height_m)
    n_tail = math.ceil(tail_s / dt_s - 1e-9)
    ag = ag * scale
    if method == "exact":
        raw = _run_exact(model, ag, float(dt_s), n_tail, x0, v0, record_history)
    else:
        from stepframe.structure.reference import integrate_reference

        for name, tol in (("rtol", rtol), ("atol", atol)):
            if not (isinstance(tol, int | float) and math.isfinite(tol) and tol > 0):
                raise InputError(f"{name} = {tol!r}, expected a finite tolerance > 0")
        raw = integrate_reference(
            model, ag, float(dt_s), n_tail, x0, v0, method, rtol, atol, record_history
        )
    return _result(raw, float(dt_s), height, "m")


def simulate_rigid_block(
    p_rad_s: float,
    alpha_rad: float,
    c_r: float,
    ground_acc_m_s2: Any,
    dt_s: float,
    *,
    theta0_rad: float = 0.0,
    omega0_rad_s: float = 0.0,
    g_m_s2: float = 9.80665,
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
        Gravity [m/s²].
    tail_s, record_history
        As in :func:`simulate`.
    """
    for name, value in (("p_rad_s", p_rad_s), ("alpha_rad", alpha_rad), ("g_m_s2", g_m_s2)):
        if not (_check_scalar(name, value) > 0):
            raise InputError(f"{name} = {value}, expected > 0")
    if not 0 <= _check_scalar("c_r", c_r) <= 1:
        raise InputError(f"c_r = {c_r}, expected 0 ≤ c_r ≤ 1")
    model = Model(p_rad_s, p_rad_s, 0.0, p_rad_s**2 / g_m_s2, p_rad_s**2 * alpha_rad,
                  0.0, 0.0, 0.0, c_r, math.inf)  # fmt: skip
    ag = _check_motion(ground_acc_m_s2, dt_s)
    tail_s = _check_scalar("tail_s", tail_s, minimum=0.0)
    n_tail = math.ceil(tail_s / dt_s - 1e-9)
    raw = _run_exact(
        model,
        ag,
        float(dt_s),
        n_tail,
        _check_scalar("theta0_rad", theta0_rad),
        _check_scalar("omega0_rad_s", omega0_rad_s),
        record_history,
    )
    return _result(raw, float(dt_s), None, "rad")


@dataclass(frozen=True)
class BatchRecord:
    """One record of a batch: ground acceleration [m/s²] and its sampling interval [s]."""

    ground_acc_m_s2: np.ndarray
    dt_s: float


def simulate_batch(
    frame: PortalFrame | Any,
    records: Sequence[BatchRecord | tuple[Any, float]],
    scales: Sequence[float] | np.ndarray,
    *,
    pairs: Literal["product", "zip"] = "product",
    tail_s: float = DEFAULT_TAIL_S,
    x0_m: float = 0.0,
    v0_m_s: float = 0.0,
    height_m: float | None = None,
) -> pd.DataFrame:
    """Summaries of many (record, scale) pairs, run in parallel on all cores (exact method).

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

    Returns
    -------
    pandas.DataFrame
        One row per pair: record, scale, the :class:`SimulationSummary` fields.
    """
    import pandas as pd

    from stepframe.structure import _exact

    model = model_of(frame)
    tail_s = _check_scalar("tail_s", tail_s, minimum=0.0)
    x0 = _check_scalar("x0_m", x0_m)
    v0 = _check_scalar("v0_m_s", v0_m_s)
    height = _height(frame, height_m)
    series = []
    dts = []
    for j, rec in enumerate(records):
        acc, dt = (rec.ground_acc_m_s2, rec.dt_s) if isinstance(rec, BatchRecord) else rec
        series.append(_check_motion(acc, dt, name=f"records[{j}]"))
        dts.append(float(dt))
    scale_arr = np.asarray(scales, dtype=float).ravel()
    for j, s in enumerate(scale_arr):
        _check_scalar(f"scales[{j}]", float(s))
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
        rec_index = np.arange(len(series))
        pair_scales = scale_arr
    else:
        raise InputError(f"pairs = {pairs!r}, expected 'product' or 'zip'")
    offsets = np.zeros(len(series) + 1, dtype=np.int64)
    offsets[1:] = np.cumsum([s.size for s in series])
    flat = np.concatenate(series)
    dt_arr = np.asarray(dts)
    tails = np.asarray([math.ceil(tail_s / dt - 1e-9) for dt in dts], dtype=np.int64)
    params = np.asarray([*model, x0, v0], dtype=float)
    out = np.empty((rec_index.size, 10))
    _exact.integrate_batch(flat, offsets, rec_index.astype(np.int64), pair_scales, dt_arr,
                           tails, params, out)  # fmt: skip
    overturned = out[:, 5] > 0
    return pd.DataFrame(
        {
            "record": rec_index,
            "scale": pair_scales,
            "peak_abs_x_m": out[:, 3],
            "peak_time_s": out[:, 4],
            "peak_drift_ratio": out[:, 3] / height if height is not None else np.nan,
            "overturned": overturned,
            "overturn_time_s": np.where(overturned, out[:, 6], np.nan),
            "n_stepping_episodes": out[:, 1].astype(np.int64),
            "n_impacts": out[:, 2].astype(np.int64),
            "residual_x_m": out[:, 7],
            "residual_v_m_s": out[:, 8],
            "status": [_STATUS.get(int(s), "solver_failed") for s in out[:, 0]],
        }
    )
