"""Incremental dynamic analysis by hunt-trace-fill, with resurrection detection.

For each item (a record, or a pulse of one frequency) the intensity is raised until the frame
overturns (hunt: steps growing by a fixed increment, Vamvatsikos and Cornell 2004); when the
hunt's first run already overturns, the intensity is halved until a run survives or the lowest
overturning run is below the resolution (the capacity lies below every intensity run, not at
the first). Then every change of outcome between neighbouring intensities is bisected until the
gap is below the resolution (trace), and the largest gaps between surviving runs are filled
(fill) while the budget lasts. Rocking systems can *resurrect*: overturn at one intensity and
survive a higher one (the safe islands of Zhang and Makris 2001 under pulses). Hunt-trace-fill
as published stops looking at the first overturning, so once the first change is traced the
intensities up to ``probe_factor`` times the traced first overturning are probed (from it, not
from the hunt's coarser overturning point, which can lie above a survival band); any survivor
there is a resurrection, and its band edges are traced like the first one.

All items advance in lockstep: each round gathers every item's next intensities and evaluates
them in one batch (:func:`stepframe.structure.simulator.simulate_batch` on all cores for records).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from stepframe.core.results import Status
from stepframe.errors import InputError

if TYPE_CHECKING:
    import pandas as pd

    from stepframe.structure.frame import RockingBlock
    from stepframe.structure.simulator import FrameLike

#: evaluate(items, intensities) -> (overturned, peak |x| [m], status per run).
Evaluator = Callable[[list[int], list[float]], tuple[np.ndarray, np.ndarray, list[str]]]


@dataclass(frozen=True)
class IdaSettings:
    """Hunt-trace-fill controls (intensities in the caller's unit, e.g. PGA [g]).

    Attributes
    ----------
    start
        First intensity of the hunt.
    step
        First hunt step.
    step_increment
        Added to the step after each survival (steps grow: 1, 2, 3 ... × step_increment + step).
    resolution
        Target width of every traced outcome change.
    max_intensity
        Stop hunting here (the item is reported as never overturning).
    probe_factor
        After the first overturning s_c, probe (s_c, probe_factor·s_c] for resurrection.
    n_probe
        Probes in that range, evenly spaced: a survival band above s_c is seen when it is wider
        than (probe_factor - 1)·s_c/n_probe and lies below probe_factor·s_c.
    n_fill
        Extra runs filling the largest gaps below the first overturning.
    max_runs
        Run budget per item.
    """

    start: float = 0.05
    step: float = 0.1
    step_increment: float = 0.05
    resolution: float = 0.005
    max_intensity: float = 10.0
    probe_factor: float = 2.0
    n_probe: int = 8
    n_fill: int = 4
    max_runs: int = 80

    def __post_init__(self) -> None:
        for name in ("start", "step", "resolution", "max_intensity", "probe_factor"):
            value = getattr(self, name)
            if not (isinstance(value, int | float) and math.isfinite(value) and value > 0):
                raise InputError(f"{name} = {value!r}, expected a finite number > 0")
        if not self.step_increment >= 0:
            raise InputError(f"step_increment = {self.step_increment}, expected ≥ 0")
        if self.probe_factor < 1:
            raise InputError(f"probe_factor = {self.probe_factor}, expected ≥ 1")
        if self.start > self.max_intensity:
            raise InputError(
                f"start = {self.start:g} is above max_intensity = {self.max_intensity:g}, "
                "expected a hunt that starts at or below its cap"
            )
        for name in ("n_probe", "n_fill", "max_runs"):
            if getattr(self, name) < 0:
                raise InputError(f"{name} = {getattr(self, name)}, expected ≥ 0")


@dataclass
class ItemIda:
    """IDA of one item.

    Attributes
    ----------
    intensity, overturned, peak_abs_x_m
        Every run, in order of intensity.
    first_overturning
        Lowest intensity seen to overturn (None: none up to max_intensity).
    last_survival_below
        Highest surviving intensity below it (the capacity lies between the two).
    overturning_bands
        Closed intervals [lo, hi] of intensities seen to overturn (edges traced to the
        resolution, except at the top of the probed range).
    resurrections
        (overturning intensity, higher surviving intensity) pairs: the lower edge of each
        survival band above an overturning band.
    status
        ``ok``; ``lower_bound`` when no overturning was found (capacity above max_intensity) or
        the budget ran out before tracing finished; ``degraded`` when some runs failed.
    """

    intensity: list[float] = field(default_factory=list)
    overturned: list[bool] = field(default_factory=list)
    peak_abs_x_m: list[float] = field(default_factory=list)
    run_status: list[str] = field(default_factory=list)
    first_overturning: float | None = None
    last_survival_below: float | None = None
    overturning_bands: list[tuple[float, float]] = field(default_factory=list)
    resurrections: list[tuple[float, float]] = field(default_factory=list)
    status: Status = "ok"
    message: str = ""

    @property
    def n_runs(self) -> int:
        """Simulations used."""
        return len(self.intensity)

    def add(self, s: float, over: bool, peak: float, status: str) -> None:
        """Insert one run keeping intensity order."""
        j = int(np.searchsorted(self.intensity, s))
        self.intensity.insert(j, s)
        self.overturned.insert(j, over)
        self.peak_abs_x_m.insert(j, peak)
        self.run_status.insert(j, status)


def _next_requests(item: ItemIda, st: IdaSettings, hunt: dict[str, Any]) -> list[float]:
    """Intensities this item wants next (empty: done)."""
    budget = st.max_runs - item.n_runs
    if budget <= 0:
        return []
    s = item.intensity
    o = item.overturned
    if not any(o):
        if hunt["next"] > st.max_intensity:
            return []
        return [hunt["next"]]
    # Down: the lowest run overturned, so the capacity lies below every run; halve until a run
    # survives or the bracket (0, s[0]] is within the resolution.
    if o[0] and s[0] > st.resolution:
        return [0.5 * s[0]]
    # Trace: bisect every neighbouring pair whose outcomes differ and whose gap is too wide.
    wanted = []
    for a in range(len(s) - 1):
        if o[a] != o[a + 1] and s[a + 1] - s[a] > st.resolution:
            wanted.append(0.5 * (s[a] + s[a + 1]))
    if wanted:
        return wanted[:budget]
    # Probe above the traced first overturning for survival (resurrection), once; the probes
    # that coincide with runs already made (probe_factor 1) leave nothing to probe.
    first = s[o.index(True)]
    if not hunt["probed"]:
        hunt["probed"] = True
        top = st.probe_factor * first
        probes = [first + (top - first) * (k + 1) / st.n_probe for k in range(st.n_probe)]
        existing = set(s)
        fresh = [p for p in probes if p not in existing][:budget]
        if fresh:
            return fresh
    # Fill: the widest gaps between survivals below the first overturning (the IDA curve).
    if hunt["filled"] < st.n_fill:
        below = [x for x, ov in zip(s, o, strict=True) if x < first and not ov]
        pts = [0.0, *below]
        gaps = sorted(((pts[k + 1] - pts[k], k) for k in range(len(pts) - 1)), reverse=True)
        n = min(st.n_fill - hunt["filled"], budget, len(gaps))
        hunt["filled"] += n
        return [0.5 * (pts[k] + pts[k + 1]) for _g, k in gaps[:n] if pts[k + 1] - pts[k] > 0]
    return []


def _finish(item: ItemIda, st: IdaSettings) -> None:
    s, o = item.intensity, item.overturned
    if any(r != "success" and r != "ok" for r in item.run_status):
        item.status = "degraded"
        item.message = "some runs stopped with a numerical status"
    if not any(o):
        item.status = "lower_bound"
        item.message = f"no overturning up to {s[-1] if s else st.start:.6g}"
        return
    k = o.index(True)
    item.first_overturning = s[k]
    item.last_survival_below = s[k - 1] if k > 0 else None
    if k == 0:
        item.message = (
            f"overturned at every intensity run, down to {s[0]:.6g}: the capacity is below it"
        )
    bands: list[tuple[float, float]] = []
    lo = None
    for a in range(len(s)):
        if o[a] and lo is None:
            lo = s[a]
        if lo is not None and (a == len(s) - 1 or not o[a + 1]):
            bands.append((lo, s[a]))
            if a < len(s) - 1:
                item.resurrections.append((s[a], s[a + 1]))
            lo = None
    item.overturning_bands = bands
    unresolved = any(
        o[a] != o[a + 1] and s[a + 1] - s[a] > st.resolution for a in range(len(s) - 1)
    )
    if unresolved and item.status == "ok":
        item.status = "lower_bound"
        item.message = "run budget spent before every outcome change was traced"


def hunt_trace_fill(
    evaluate: Evaluator, n_items: int, settings: IdaSettings | None = None
) -> list[ItemIda]:
    """Run hunt-trace-fill on every item in lockstep.

    Parameters
    ----------
    evaluate
        Called with (item indices, intensities), returns (overturned, peak |x| [m], statuses).
    n_items
        Number of items.
    settings
        :class:`IdaSettings` (defaults when None).
    """
    st = settings or IdaSettings()
    items = [ItemIda() for _ in range(n_items)]
    hunts = [{"next": st.start, "k": 0, "probed": False, "filled": 0} for _ in range(n_items)]
    while True:
        req_items: list[int] = []
        req_s: list[float] = []
        for i in range(n_items):
            for s in _next_requests(items[i], st, hunts[i]):
                req_items.append(i)
                req_s.append(float(s))
        if not req_items:
            break
        over, peak, status = evaluate(req_items, req_s)
        for i, s, ov, pk, stt in zip(req_items, req_s, over, peak, status, strict=True):
            items[i].add(s, bool(ov), float(pk), str(stt))
            h = hunts[i]
            if not any(items[i].overturned) and s == h["next"]:
                h["next"] = s + st.step + h["k"] * st.step_increment
                h["k"] += 1
    for item in items:
        _finish(item, st)
    return items


def fixed_step_runs(items: Sequence[ItemIda], settings: IdaSettings) -> int:
    """Runs a fixed-step grid needs to find each first overturning to the same resolution.

    The grid start, start + resolution, ... is run up to the first overturning (then stops).
    """
    total = 0
    for item in items:
        top = (
            item.first_overturning
            if item.first_overturning is not None
            else (item.intensity[-1] if item.intensity else settings.start)
        )
        # at least the grid's first run (a capacity below the start is not found by the grid)
        total += max(1, math.floor((top - settings.start) / settings.resolution + 1e-9) + 1)
    return total


def ida_table(items: Sequence[ItemIda], names: Sequence[str] | None = None) -> pd.DataFrame:
    """One row per item: first overturning, bracket, resurrections, runs, status."""
    import pandas as pd

    rows = []
    for i, item in enumerate(items):
        rows.append(
            {
                "item": names[i] if names is not None else str(i),
                "first_overturning": item.first_overturning,
                "last_survival_below": item.last_survival_below,
                "n_bands": len(item.overturning_bands),
                "resurrected": bool(item.resurrections),
                "resurrections": ";".join(f"{a:.6g}->{b:.6g}" for a, b in item.resurrections),
                "n_runs": item.n_runs,
                "status": item.status,
                "message": item.message,
            }
        )
    return pd.DataFrame(rows)


def capacity_fractiles(
    items: Sequence[ItemIda], quantiles: Sequence[float] = (0.16, 0.5, 0.84)
) -> dict[str, float]:
    """Fractiles of the first-overturning intensity over items, NaN where the items that never
    overturned leave them undefined.

    An item with no overturning up to its last intensity is right-censored: its capacity is
    only known to exceed that intensity. A fractile is defined when it is the same with those
    items at their bound and with them beyond every value (it then rests on found capacities
    alone); otherwise it is NaN, not the bound (before, the bounds counted as capacities: two
    pulses with none found up to 48.25 gave "q0.5 48.25").
    """
    found = [it.first_overturning for it in items if it.first_overturning is not None]
    bounds = [it.intensity[-1] for it in items if it.first_overturning is None and it.intensity]
    values = np.asarray([*found, *bounds], dtype=float)
    values = values[np.isfinite(values)]
    if values.size == 0:
        return {f"q{q:g}": math.nan for q in quantiles}
    beyond = 2.0 * float(np.max(np.abs(values))) + 1.0  # above every value: "somewhere higher"
    at_bound = np.asarray([*found, *bounds], dtype=float)
    high = np.asarray([*found, *([beyond] * len(bounds))], dtype=float)
    out = {}
    for q in quantiles:
        low_q, high_q = float(np.quantile(at_bound, q)), float(np.quantile(high, q))
        out[f"q{q:g}"] = low_q if low_q == high_q else math.nan
    return out


def ida_records(
    frame: FrameLike,
    records: Sequence[tuple[Any, float]],
    *,
    settings: IdaSettings | None = None,
    intensity_of: Callable[[np.ndarray, float], float] | None = None,
    tail_s: float = 10.0,
) -> list[ItemIda]:
    """IDA of a frame under records, intensities in units of each record's PGA [g].

    Parameters
    ----------
    frame
        A :class:`~stepframe.structure.frame.PortalFrame`.
    records
        (ground acceleration [m/s²], dt [s]) pairs.
    settings
        :class:`IdaSettings`, intensities in g of PGA by default.
    intensity_of
        Intensity of the unscaled record (acc [m/s²], dt [s]) in the unit of the settings;
        default PGA [g] (9.80665 m/s² per g).
    tail_s
        Free vibration after each record [s] (as in
        :func:`~stepframe.structure.simulator.simulate`).
    """
    from stepframe.records.units import STANDARD_GRAVITY_M_S2
    from stepframe.structure.simulator import simulate_batch

    recs = [(np.asarray(a, dtype=float), float(dt)) for a, dt in records]
    if intensity_of is None:
        base = [float(np.max(np.abs(a))) / STANDARD_GRAVITY_M_S2 for a, _dt in recs]
    else:
        base = [float(intensity_of(a, dt)) for a, dt in recs]
    for j, b in enumerate(base):
        if not (math.isfinite(b) and b > 0):
            raise InputError(f"records[{j}] has intensity {b}, expected > 0")

    def evaluate(idx: list[int], s: list[float]) -> tuple[np.ndarray, np.ndarray, list[str]]:
        scales = [s_k / base[i] for i, s_k in zip(idx, s, strict=True)]
        table = simulate_batch(frame, [recs[i] for i in idx], scales, pairs="zip", tail_s=tail_s)
        return (
            table["overturned"].to_numpy(),
            table["peak_abs_x_m"].to_numpy(),
            [str(x) for x in table["status"]],
        )

    return hunt_trace_fill(evaluate, len(recs), settings)


def ida_pulse(
    frame: FrameLike | RockingBlock,
    omegas_rad_s: Sequence[float],
    *,
    kind: str = "cosine",
    settings: IdaSettings | None = None,
) -> list[ItemIda]:
    """IDA of a frame under one-cycle pulses, one item per pulse frequency.

    Intensities are the pulse amplitude in units of the static uplift acceleration: γ₁/P₂ for a
    frame (g·α for the linearised Housner block: 1 is the amplitude that just lifts it), g·tan α
    for the nonlinear :class:`~stepframe.structure.frame.RockingBlock` (whose peaks are
    then rotations [rad]).
    """
    from stepframe.structure.frame import RockingBlock

    oms = [float(w) for w in omegas_rad_s]
    if isinstance(frame, RockingBlock):
        from stepframe.structure.rocking_block import block_pulse

        block = frame
        unit = block.uplift_acceleration_m_s2

        def run(amplitude: float, omega: float) -> tuple[bool, float, str]:
            out = block_pulse(block, amplitude, omega, kind=kind)
            return out.overturned, out.peak_rotation_rad, out.status

    else:
        from stepframe.structure.harmonic import frame_parameters, simulate_pulse

        prm = frame_parameters(frame)
        unit = prm[4] / prm[3]
        portal = frame

        def run(amplitude: float, omega: float) -> tuple[bool, float, str]:
            out = simulate_pulse(portal, amplitude, omega, kind=kind)  # type: ignore[arg-type]
            return out.overturned, out.peak_abs_x_m, out.status

    def evaluate(idx: list[int], s: list[float]) -> tuple[np.ndarray, np.ndarray, list[str]]:
        outs = [run(s_k * unit, oms[i]) for i, s_k in zip(idx, s, strict=True)]
        return (
            np.array([o[0] for o in outs]),
            np.array([o[1] for o in outs]),
            [o[2] for o in outs],
        )

    return hunt_trace_fill(evaluate, len(oms), settings)
