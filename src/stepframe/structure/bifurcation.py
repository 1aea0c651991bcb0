"""Brute-force bifurcation diagrams and basins of overturning under harmonic forcing.

Each (amplitude, initial state) pair is iterated through the stroboscopic map for many forcing
periods by the closed-form kernel; the last few map points are kept (a period-n orbit shows n
points, chaos a cloud) with the overturning flag. Amplitudes are split into chunks run through
:func:`stepframe.core.execution.map_items` (all cores, or any executor), so a chunk that fails is
recorded and the others are kept.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from stepframe.errors import InputError
from stepframe.structure.harmonic import (
    DEFAULT_MAX_EVENTS,
    frame_parameters,
    harmonic_work_units,
)

if TYPE_CHECKING:
    from concurrent.futures import Executor

    import xarray as xr
    from numpy.typing import ArrayLike

    from stepframe.structure.simulator import FrameLike

#: Outcome codes of a basin cell and of a diagram run.
OUTCOME_SURVIVES = 0
OUTCOME_OVERTURNS = 1
OUTCOME_STOPPED = 2


def _chunk(item: tuple[Any, ...]) -> tuple[np.ndarray, np.ndarray]:
    """Run :func:`~stepframe.structure._harmonic_kernel.strobe_grid` on one chunk (picklable)."""
    from stepframe.structure import _harmonic_kernel as hk

    prm, amps, om, phi, x0s, v0s, n_periods, n_keep, max_events = item
    out, flags = hk.strobe_grid(prm, amps, om, phi, x0s, v0s, n_periods, n_keep, max_events)
    return np.asarray(out), np.asarray(flags)


def _chunk_name(item: tuple[Any, ...]) -> str:
    return f"A = {item[1][0]:.6g}..{item[1][-1]:.6g} m/s²"


def _omega_chunk(item: tuple[Any, ...]) -> tuple[np.ndarray, np.ndarray]:
    """One amplitude at several frequencies (picklable)."""
    from stepframe.structure import _harmonic_kernel as hk

    prm, amp, oms, phi, x0s, v0s, n_periods, n_keep, max_events = item
    outs, flags = [], []
    for om in oms:
        out, flag = hk.strobe_grid(
            prm, np.array([amp]), float(om), phi, x0s, v0s, n_periods, n_keep, max_events
        )
        outs.append(out[0])
        flags.append(flag[0])
    return np.asarray(outs), np.asarray(flags)


def _omega_chunk_name(item: tuple[Any, ...]) -> str:
    return f"ω = {item[2][0]:.6g}..{item[2][-1]:.6g} rad/s"


#: Peak memory of a bifurcation diagram per map point kept (value × initial state × period
#: kept) [bytes]: x, ẋ and impacts in the workers' chunks and in the assembled dataset, its
#: outcome and the orbit search (measured 65-66 on 10⁵ and 8·10⁵ points), and what ``--plot``
#: adds (measured 37) (tracemalloc, docs/benchmarks.md "Memory of the commands").
DIAGRAM_BYTES_PER_POINT, DIAGRAM_FIGURE_BYTES_PER_POINT = 72.0, 48.0


def diagram_memory_bytes(points: int, figure: bool = False) -> float:
    """The estimated peak memory of a diagram of ``points`` map points [bytes]."""
    return points * (DIAGRAM_BYTES_PER_POINT + (DIAGRAM_FIGURE_BYTES_PER_POINT if figure else 0))


def _check_sweep_work(
    prm: np.ndarray, omegas: list[float], periods_each: float, samples: float, workers: int,
    what: str,
) -> None:  # fmt: skip
    """Refuse a sweep whose work (``periods_each`` forcing periods at every ω) passes the limit
    times the workers (:mod:`stepframe.structure.work`), or whose ``samples`` map points kept
    pass the memory budget (:func:`diagram_memory_bytes`)."""
    from stepframe.core.memory import check_memory
    from stepframe.structure import work

    units = sum(
        harmonic_work_units(prm, om, periods_each * 2.0 * math.pi / om, 0.0) for om in omegas
    )
    work.check_work(
        units + samples, what, "ask for fewer values, initial states or periods",
        limit=work.MAX_WORK_UNITS * max(workers, 1),
    )  # fmt: skip
    check_memory(
        diagram_memory_bytes(int(samples)), f"{what}: {int(samples)} map points kept",
        "ask for fewer values or initial states",
    )  # fmt: skip


def initial_states(frame: FrameLike, n: int, *, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """n initial states spread over the region the frame can survive from.

    x is uniform in (-x_0, x_0) and ẋ in (-ω₂x*, ω₂x*) (the velocity that carries the free
    stepped frame from x_c to x*), drawn by a seeded generator so runs repeat; x_0 is x*, or the
    overturning cap x_cap when that is lower (a frame derived from its physical parameters can
    have its geometric cap below x*: a start past the cap has no overturning verdict).

    Returns
    -------
    (x0_m, v0_m_s)
    """
    prm = frame_parameters(frame)
    x_star = prm[4] / prm[1] ** 2
    reach = min(x_star, prm[9])
    rng = np.random.default_rng(seed)
    x0 = rng.uniform(-reach, reach, n)
    v0 = rng.uniform(-1.0, 1.0, n) * prm[1] * x_star
    return x0, v0


def bifurcation_diagram(
    frame: FrameLike,
    amplitudes_m_s2: ArrayLike,
    omega_rad_s: float,
    *,
    x0_m: ArrayLike | None = None,
    v0_m_s: ArrayLike | None = None,
    n_initial: int = 50,
    n_periods: int = 100,
    n_keep: int = 20,
    phase_rad: float = 0.0,
    jobs: int | None = None,
    executor: Executor | None = None,
    chunk_amplitudes: int | None = None,
    seed: int = 0,
) -> xr.Dataset:
    """Stroboscopic points after the transient, for every amplitude and initial state.

    Parameters
    ----------
    frame
        A :class:`~stepframe.structure.frame.PortalFrame`.
    amplitudes_m_s2
        Forcing amplitudes A [m/s²] (ẍ_g = A cos(ωt + φ)).
    omega_rad_s, phase_rad
        ω [rad/s] and φ [rad].
    x0_m, v0_m_s
        Initial states (arrays of one length); None: :func:`initial_states` (``n_initial``,
        ``seed``).
    n_periods
        Forcing periods simulated per run.
    n_keep
        Map points kept from the end of each run.
    jobs, executor
        As in :func:`stepframe.core.execution.map_items`.
    chunk_amplitudes
        Amplitudes per task (default: spread over about four tasks per worker).

    Returns
    -------
    xarray.Dataset
        ``x_m``, ``v_m_s`` (amplitude, initial, sample), ``impacts`` per period (same dims),
        ``outcome`` (amplitude, initial: 0 survives, 1 overturns, 2 stopped by a kernel
        status), ``x0_m``, ``v0_m_s`` (initial); failures of whole chunks in
        ``attrs["failures"]`` (their rows are NaN with outcome 2).
    """
    import os

    from stepframe.core.execution import map_items

    prm = frame_parameters(frame)
    amps = np.atleast_1d(np.asarray(amplitudes_m_s2, dtype=float))
    if amps.size == 0 or not np.all(np.isfinite(amps)) or np.any(amps < 0):
        raise InputError("amplitudes_m_s2 must be finite and ≥ 0, expected at least one")
    if not (math.isfinite(omega_rad_s) and omega_rad_s > 0):
        raise InputError(f"omega_rad_s = {omega_rad_s}, expected > 0")
    if n_keep < 1 or n_periods < n_keep:
        raise InputError(
            f"n_keep = {n_keep}, n_periods = {n_periods}, expected 1 ≤ n_keep ≤ n_periods"
        )
    if x0_m is None or v0_m_s is None:
        x0, v0 = initial_states(frame, n_initial, seed=seed)
    else:
        x0 = np.atleast_1d(np.asarray(x0_m, dtype=float))
        v0 = np.atleast_1d(np.asarray(v0_m_s, dtype=float))
        if x0.shape != v0.shape:
            raise InputError("x0_m and v0_m_s have different lengths, expected equal")
    workers = jobs if jobs is not None else (os.cpu_count() or 1)
    runs = amps.size * x0.size
    _check_sweep_work(
        prm, [float(omega_rad_s)], runs * n_periods, runs * n_keep, workers,
        f"{amps.size} amplitudes × {x0.size} initial states × {n_periods} periods",
    )  # fmt: skip
    size = chunk_amplitudes or max(1, math.ceil(amps.size / (4 * max(workers, 1))))
    starts = list(range(0, amps.size, size))
    items = [
        (
            prm,
            amps[s : s + size],
            float(omega_rad_s),
            float(phase_rad),
            x0,
            v0,
            int(n_periods),
            int(n_keep),
            DEFAULT_MAX_EVENTS,
        )
        for s in starts
    ]
    outcome = map_items(
        _chunk,
        items,
        jobs=jobs,
        executor=executor,
        chunk_size=1,
        stage="bifurcation",
        name_of=_chunk_name,
    )
    return _diagram(
        outcome, starts, x0, v0, n_keep, ("amplitude", amps, "m/s2"),
        {"omega_rad_s": float(omega_rad_s), "phase_rad": float(phase_rad),
         "n_periods": int(n_periods)},
    )  # fmt: skip


def orbit_period(x_points: np.ndarray, *, max_period: int = 8, rtol: float = 1e-6) -> int:
    """Smallest p ≤ max_period with x_{k+p} = x_k on the kept map points (0: none found).

    Parameters
    ----------
    x_points
        The last map points of one run (NaN after overturning gives 0).
    """
    x = np.asarray(x_points, dtype=float)
    if x.size < 2 or not np.all(np.isfinite(x)):
        return 0
    scale = max(float(np.max(np.abs(x))), 1e-300)
    for p in range(1, min(max_period, x.size - 1) + 1):
        if np.max(np.abs(x[p:] - x[:-p])) <= rtol * scale:
            return p
    return 0


def basin_of_overturning(
    frame: FrameLike,
    amplitude_m_s2: float,
    omega_rad_s: float,
    x_m: Any,
    v_m_s: Any,
    *,
    n_periods: int = 50,
    phase_rad: float = 0.0,
    jobs: int | None = None,
    executor: Executor | None = None,
) -> xr.DataArray:
    """Which initial states (x, ẋ) at t = 0 overturn within n_periods forcing periods.

    Returns
    -------
    xarray.DataArray
        Outcome on the (v, x) grid: 0 survives, 1 overturns, 2 stopped by a kernel status.
    """
    import xarray as xr

    xs = np.asarray(x_m, dtype=float)
    vs = np.asarray(v_m_s, dtype=float)
    gx, gv = np.meshgrid(xs, vs)
    ds = bifurcation_diagram(
        frame,
        [amplitude_m_s2],
        omega_rad_s,
        x0_m=gx.ravel(),
        v0_m_s=gv.ravel(),
        n_periods=n_periods,
        n_keep=1,
        phase_rad=phase_rad,
        jobs=jobs,
        executor=executor,
    )
    grid = ds["outcome"].values[0].reshape(gv.shape)
    return xr.DataArray(
        grid,
        dims=("v", "x"),
        coords={"x": ("x", xs, {"units": "m"}), "v": ("v", vs, {"units": "m/s"})},
        attrs={
            "meaning": "0 survives, 1 overturns, 2 stopped (kernel status)",
            "amplitude_m_s2": float(amplitude_m_s2),
            "omega_rad_s": float(omega_rad_s),
        },
        name="outcome",
    )


def frequency_diagram(
    frame: FrameLike,
    amplitude_m_s2: float,
    omegas_rad_s: ArrayLike,
    *,
    x0_m: ArrayLike | None = None,
    v0_m_s: ArrayLike | None = None,
    n_initial: int = 50,
    n_periods: int = 100,
    n_keep: int = 20,
    phase_rad: float = 0.0,
    jobs: int | None = None,
    executor: Executor | None = None,
    seed: int = 0,
) -> xr.Dataset:
    """:func:`bifurcation_diagram` over the forcing frequency at one amplitude.

    Same outputs with the dimension ``omega`` [rad/s] in place of ``amplitude``; each frequency's
    runs last ``n_periods`` of its own forcing periods.
    """
    import os

    from stepframe.core.execution import map_items

    prm = frame_parameters(frame)
    oms = np.atleast_1d(np.asarray(omegas_rad_s, dtype=float))
    if oms.size == 0 or not np.all(np.isfinite(oms)) or np.any(oms <= 0):
        raise InputError("omegas_rad_s must be finite and > 0, expected at least one")
    if not (math.isfinite(amplitude_m_s2) and amplitude_m_s2 >= 0):
        raise InputError(f"amplitude_m_s2 = {amplitude_m_s2}, expected a finite number ≥ 0")
    if n_keep < 1 or n_periods < n_keep:
        raise InputError(
            f"n_keep = {n_keep}, n_periods = {n_periods}, expected 1 ≤ n_keep ≤ n_periods"
        )
    if x0_m is None or v0_m_s is None:
        x0, v0 = initial_states(frame, n_initial, seed=seed)
    else:
        x0 = np.atleast_1d(np.asarray(x0_m, dtype=float))
        v0 = np.atleast_1d(np.asarray(v0_m_s, dtype=float))
        if x0.shape != v0.shape:
            raise InputError("x0_m and v0_m_s have different lengths, expected equal")
    workers = jobs if jobs is not None else (os.cpu_count() or 1)
    _check_sweep_work(
        prm, list(oms), x0.size * n_periods, x0.size * n_keep * oms.size, workers,
        f"{oms.size} frequencies × {x0.size} initial states × {n_periods} periods",
    )  # fmt: skip
    size = max(1, math.ceil(oms.size / (4 * max(workers, 1))))
    starts = list(range(0, oms.size, size))
    items = [
        (prm, float(amplitude_m_s2), oms[s : s + size], float(phase_rad), x0, v0, int(n_periods),
         int(n_keep), DEFAULT_MAX_EVENTS)
        for s in starts
    ]  # fmt: skip
    outcome = map_items(
        _omega_chunk, items, jobs=jobs, executor=executor, chunk_size=1, stage="bifurcation",
        name_of=_omega_chunk_name,
    )  # fmt: skip
    return _diagram(
        outcome, starts, x0, v0, n_keep, ("omega", oms, "rad/s"),
        {"amplitude_m_s2": float(amplitude_m_s2), "phase_rad": float(phase_rad),
         "n_periods": int(n_periods)},
    )  # fmt: skip


def _diagram(
    outcome: Any,
    starts: list[int],
    x0: Any,
    v0: Any,
    n_keep: int,
    swept: tuple[str, Any, str],
    attrs: dict[str, Any],
) -> xr.Dataset:
    """The diagram's dataset from the chunks' results: one row per swept value and start."""
    import xarray as xr

    name, values, unit = swept
    pts = np.full((values.size, x0.size, n_keep, 4), np.nan)
    code = np.full((values.size, x0.size), OUTCOME_STOPPED, dtype=np.int8)
    for idx, (out, flags) in zip(outcome.indices, outcome.results, strict=True):
        s = starts[idx]
        pts[s : s + out.shape[0]] = out
        code[s : s + out.shape[0]] = np.where(flags[..., 0] != 0, OUTCOME_STOPPED, flags[..., 1])
    dims = (name, "initial", "sample")
    return xr.Dataset(
        {
            "x_m": (dims, pts[..., 0], {"units": "m"}),
            "v_m_s": (dims, pts[..., 1], {"units": "m/s"}),
            "impacts": (dims, pts[..., 2], {"units": "1/period"}),
            "outcome": (
                (name, "initial"),
                code,
                {"meaning": "0 survives, 1 overturns, 2 stopped (kernel status)"},
            ),
            "x0_m": (("initial",), x0, {"units": "m"}),
            "v0_m_s": (("initial",), v0, {"units": "m/s"}),
        },
        coords={name: (name, values, {"units": unit})},
        attrs={**attrs, "failures": [f.message for f in outcome.failures]},
    )
