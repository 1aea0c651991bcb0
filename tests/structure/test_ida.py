"""Hunt-trace-fill IDA: Housner's block under a one-cosine pulse against solve_ivp, resurrection."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from stepframe.errors import InputError
from stepframe.structure.frame import PortalFrame
from stepframe.structure.ida import (
    Evaluator,
    IdaSettings,
    capacity_fractiles,
    fixed_step_runs,
    hunt_trace_fill,
    ida_pulse,
    ida_records,
    ida_table,
)
from stepframe.structure.simulator import simulate

BLOCK = PortalFrame.housner_block(half_width_m=0.25, half_height_m=1.0)
SETTINGS = IdaSettings(
    start=1.0,
    step=0.5,
    step_increment=0.25,
    resolution=1e-3,
    max_intensity=20.0,
    probe_factor=4.0,
    n_probe=16,
)


def overturns_reference(a: float, omega_bar: float, c_r: float) -> bool:
    """Linearised Housner block, u = θ/α, τ = pt: u'' - u + sign(u) = -a cos(ω̄τ) on one
    period, then free rocking; solve_ivp with impact events (an independent implementation)."""
    t_p = 2 * math.pi / omega_bar
    if a <= 1.0:
        return False
    side = -1.0  # the ground pushes forward (+a) at τ = 0: the block rocks backwards
    t, y = 0.0, np.array([0.0, 0.0])
    for _ in range(400):

        def rhs(tau: float, z: np.ndarray, s: float = side) -> list[float]:
            forcing = a * math.cos(omega_bar * tau) if tau <= t_p else 0.0
            return [z[1], z[0] - s - forcing]

        def hit(tau: float, z: np.ndarray) -> float:
            return float(z[0])

        hit.terminal = True  # type: ignore[attr-defined]
        hit.direction = -side  # type: ignore[attr-defined]
        end = t_p if t < t_p else t + 60.0
        sol = solve_ivp(
            rhs, (t, end), y, method="DOP853", rtol=1e-12, atol=1e-14, events=hit, first_step=1e-6
        )
        t, y = sol.t[-1], sol.y[:, -1].copy()
        if sol.status == 1:
            y[0] = 0.0
            y[1] *= c_r
            side = -side
            if abs(y[1]) < 1e-9:
                return False
            continue
        if t >= t_p:
            # Free motion: escaping exactly when s·u' + (s·u - 1) > 0 (λ₁ = 1, λ₂ = -1).
            if side * y[1] + side * y[0] - 1.0 > 0:
                return True
            if t >= end:
                return False
    return False


def reference_minimum(omega_bar: float, c_r: float) -> float:
    grid = np.arange(1.0, 3.0, 0.01)
    hi = next(a for a in grid if overturns_reference(a, omega_bar, c_r))
    lo = hi - 0.01
    while hi - lo > 1e-6:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if overturns_reference(mid, omega_bar, c_r) else (mid, hi)
    return hi


@pytest.mark.parametrize("omega_bar", [2.0, 3.0])
def test_minimum_overturning_amplitude_matches_solve_ivp(omega_bar: float) -> None:
    items = ida_pulse(BLOCK, [omega_bar * BLOCK.omega_2_rad_s], settings=SETTINGS)
    item = items[0]
    assert item.status == "ok"
    ref = reference_minimum(omega_bar, BLOCK.c_r)
    assert item.last_survival_below is not None and item.first_overturning is not None
    assert item.last_survival_below - 1e-6 <= ref <= item.first_overturning + 1e-6
    assert item.first_overturning - item.last_survival_below <= SETTINGS.resolution


def test_resurrection_band_is_found_and_confirmed_independently() -> None:
    omega_bar = 2.0
    item = ida_pulse(BLOCK, [omega_bar * BLOCK.omega_2_rad_s], settings=SETTINGS)[0]
    assert item.resurrections, "a safe island above the first overturning"
    over_at, survive_at = item.resurrections[0]
    assert survive_at > over_at > item.first_overturning  # type: ignore[operator]
    survive_band_end = item.overturning_bands[1][0]
    middle = 0.5 * (survive_at + survive_band_end)
    assert not overturns_reference(middle, omega_bar, BLOCK.c_r)
    assert overturns_reference(over_at - 0.01, omega_bar, BLOCK.c_r)
    assert overturns_reference(survive_band_end + 0.01, omega_bar, BLOCK.c_r)


def test_hunt_trace_fill_needs_far_fewer_runs_than_a_fixed_grid() -> None:
    items = ida_pulse(BLOCK, [2.0 * BLOCK.omega_2_rad_s], settings=SETTINGS)
    assert fixed_step_runs(items, SETTINGS) > 5 * sum(i.n_runs for i in items)


def test_synthetic_evaluator_band_structure_is_traced_exactly() -> None:
    # Overturns on [1.234, 2.5] and above 4.0: two bands, one resurrection at 2.5 -> survive.
    def evaluate(idx: list[int], s: list[float]) -> tuple[np.ndarray, np.ndarray, list[str]]:
        over = np.array([(1.234 <= x <= 2.5) or x >= 4.0 for x in s])
        return over, np.asarray(s), ["ok"] * len(s)

    st = IdaSettings(start=0.1, step=0.2, step_increment=0.1, resolution=1e-3, probe_factor=5.0)
    item = hunt_trace_fill(evaluate, 1, st)[0]
    assert item.first_overturning == pytest.approx(1.234, abs=1e-3)
    assert len(item.overturning_bands) == 2
    assert item.resurrections[0][0] == pytest.approx(2.5, abs=1e-3)
    assert item.overturning_bands[1][0] == pytest.approx(4.0, abs=1e-3)
    table = ida_table([item])
    assert bool(table.loc[0, "resurrected"])
    assert capacity_fractiles([item])["q0.5"] == item.first_overturning


def test_records_ida_brackets_are_confirmed_by_single_simulations() -> None:
    from stepframe.records.examples import fema_p695

    stream, _table = fema_p695()
    frame = PortalFrame.housner_block(half_width_m=0.5, half_height_m=3.0)
    recs = [(tr.data.astype(float), tr.stats.delta) for tr in stream[:2]]
    st = IdaSettings(
        start=0.05, step=0.1, step_increment=0.05, resolution=0.01, max_intensity=5.0, n_probe=4
    )
    items = ida_records(frame, recs, settings=st, tail_s=5.0)
    for (acc, dt), item in zip(recs, items, strict=True):
        assert item.first_overturning is not None
        pga_g = np.max(np.abs(acc)) / 9.80665
        hit = simulate(
            frame, acc, dt, scale=item.first_overturning / pga_g, tail_s=5.0, record_history=False
        )
        assert hit.summary.overturned
        if item.last_survival_below is not None:
            safe = simulate(
                frame,
                acc,
                dt,
                scale=item.last_survival_below / pga_g,
                tail_s=5.0,
                record_history=False,
            )
            assert not safe.summary.overturned


def test_bad_settings_raise() -> None:
    with pytest.raises(InputError):
        IdaSettings(resolution=0.0)
    with pytest.raises(InputError):
        IdaSettings(probe_factor=0.5)


def test_fractiles_never_rest_on_a_lower_bound() -> None:
    """An item that never overturned up to its last intensity only bounds its capacity from
    below: a fractile that depends on it is undefined (NaN), one that rests on found capacities
    alone is their quantile (numpy's linear one, recomputed by hand)."""
    from stepframe.structure.ida import ItemIda

    found = [ItemIda(intensity=[c], overturned=[True], first_overturning=c)
             for c in (0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0)]  # fmt: skip
    censored = ItemIda(intensity=[0.1, 2.0], overturned=[False, False], first_overturning=None)
    fractiles = capacity_fractiles([*found, censored])
    # ten items: q = 0.16 sits between the 2nd and 3rd smallest (0.3 and 0.4), found ones
    assert fractiles["q0.16"] == pytest.approx(0.3 + 0.44 * 0.1)
    assert fractiles["q0.5"] == pytest.approx(0.65)
    assert fractiles["q0.84"] == pytest.approx(0.9 + 0.56 * 0.1)  # the 8th and 9th
    # q = 0.95 reaches the 10th item, whose capacity is only known to exceed 2.0
    assert math.isnan(capacity_fractiles([*found, censored], (0.95,))["q0.95"])
    # none overturned: nothing defined (the bounds were once printed as the fractiles)
    assert all(math.isnan(v) for v in capacity_fractiles([censored, censored]).values())
    # all found: numpy's quantiles of the capacities
    assert capacity_fractiles(found)["q0.84"] == pytest.approx(
        float(np.quantile([i.first_overturning for i in found], 0.84))
    )


def _threshold_evaluator(overturns: Callable[[float], bool]) -> Evaluator:
    """An evaluator whose outcome is a known function of the intensity (peak = intensity)."""

    def evaluate(idx: list[int], s: list[float]) -> tuple[np.ndarray, np.ndarray, list[str]]:
        return np.array([overturns(x) for x in s]), np.asarray(s), ["ok"] * len(s)

    return evaluate


def test_a_capacity_below_the_hunts_start_is_found_not_reported_as_the_start() -> None:
    """The first hunt run (0.05) already overturns: the capacity (0.02) lies below it, so the
    intensity is halved until a run survives, then traced; before, 0.05 was reported, "ok"."""
    st = IdaSettings(start=0.05, step=0.1, step_increment=0.05, resolution=0.001)
    item = hunt_trace_fill(_threshold_evaluator(lambda x: x >= 0.02), 1, st)[0]
    assert item.first_overturning is not None and item.last_survival_below is not None
    assert item.last_survival_below < 0.02 <= item.first_overturning
    assert item.first_overturning - item.last_survival_below <= st.resolution
    assert item.status == "ok"
    # Below the resolution itself: the bracket (0, lowest run] is within it, and said.
    tiny = hunt_trace_fill(_threshold_evaluator(lambda x: x >= 1e-6), 1, st)[0]
    assert tiny.first_overturning is not None and tiny.first_overturning <= st.resolution
    assert tiny.last_survival_below is None and "capacity is below it" in tiny.message


def test_probes_start_from_the_traced_first_overturning() -> None:
    """Overturns on [0.20, 0.24] and from 0.28: the hunt first overturns at 0.30, above the
    survival band (0.24, 0.28); probing from 0.30 (as before) never looked inside it."""
    st = IdaSettings(start=0.05, step=0.1, step_increment=0.05, resolution=1e-3, n_probe=8)
    item = hunt_trace_fill(_threshold_evaluator(lambda x: 0.2 <= x <= 0.24 or x >= 0.28), 1, st)
    found = item[0]
    assert found.first_overturning == pytest.approx(0.2, abs=1e-3)
    assert len(found.resurrections) == 1
    assert found.resurrections[0][0] == pytest.approx(0.24, abs=1e-3)
    assert found.overturning_bands[1][0] == pytest.approx(0.28, abs=1e-3)


def test_probe_factor_one_still_traces() -> None:
    """With probe_factor 1 every probe is the first overturning itself: nothing to probe, but
    the trace must still run (before, the item stopped at the hunt's coarse bracket)."""
    st = IdaSettings(start=0.05, step=0.1, step_increment=0.05, resolution=1e-3, probe_factor=1)
    item = hunt_trace_fill(_threshold_evaluator(lambda x: x >= 0.4321), 1, st)[0]
    assert item.first_overturning is not None and item.last_survival_below is not None
    assert item.last_survival_below < 0.4321 <= item.first_overturning
    assert item.first_overturning - item.last_survival_below <= st.resolution
    assert item.status == "ok"


def test_a_resolution_at_or_above_the_cap_is_refused() -> None:
    from stepframe.pipeline.dynamics.studies import IdaOptions

    with pytest.raises(InputError, match="--resolution-g 10 is not below --max-g 5"):
        IdaOptions(resolution_g=10.0)
    with pytest.raises(InputError, match="start = 6 is above max_intensity = 5"):
        IdaSettings(start=6.0, max_intensity=5.0)
