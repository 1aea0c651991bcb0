"""The simulator's interface: method registry, status vocabulary, FrameLike, one default g, the
batch through the one executor, and results that are never "ok" when physically impossible."""

from __future__ import annotations

import dataclasses
import importlib
import inspect
import math
import pkgutil
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Any, get_args

import numpy as np
import pytest

import stepframe.structure
from stepframe.core.results import STATUSES
from stepframe.errors import InputError
from stepframe.structure.frame import PAPER_G_M_S2, PortalFrame
from stepframe.structure.simulator import (
    METHODS,
    Method,
    Model,
    RawRun,
    SimulationSummary,
    simulate,
    simulate_batch,
)
from stepframe.structure.status import STATUS_NAMES, SimulationStatus

FRAME = PortalFrame(
    omega_1_rad_s=6.4581, omega_2_rad_s=0.6445, p_1=1.0901, p_2=1.2680, gamma_1_m_s2=0.1387,
    xi_1=0.05, xi_2=0.0, x_c_m=0.05, c_r=0.9, x_cap_m=0.6,
)  # fmt: skip


def _sine(amplitude: float, n: int = 1500, dt: float = 0.01) -> np.ndarray:
    return amplitude * np.sin(2.0 * np.pi * 0.5 * np.arange(n) * dt)


def test_method_literal_and_registry_name_the_same_methods() -> None:
    assert tuple(METHODS) == get_args(Method)


def test_statuses_come_from_the_project_vocabulary() -> None:
    assert set(get_args(SimulationStatus)) <= set(STATUSES)
    assert set(STATUS_NAMES.values()) <= set(STATUSES)
    field = next(f for f in dataclasses.fields(SimulationSummary) if f.name == "status")
    assert field.type in ("Status", "SimulationStatus")


def test_a_callable_is_accepted_where_a_method_name_is() -> None:
    calls: list[Model] = []

    def traced(model: Model, ag: np.ndarray, *args: Any) -> RawRun:
        calls.append(model)
        return METHODS["exact"](model, ag, *args)

    ag = _sine(2.0)
    by_name = simulate(FRAME, ag, 0.01, record_history=False).summary
    by_callable = simulate(FRAME, ag, 0.01, method=traced, record_history=False).summary
    assert len(calls) == 1 and calls[0].x_c_m == FRAME.x_c_m
    assert by_callable == by_name
    with pytest.raises(InputError, match="expected a name of METHODS or a callable"):
        simulate(FRAME, ag, 0.01, method=3)  # type: ignore[arg-type]


def test_physically_impossible_result_is_never_ok() -> None:
    """A method claiming a peak past the cap (or non-finite values) without an overturn."""

    def claims(peak: float) -> Any:
        def run(model: Model, ag: np.ndarray, *args: Any) -> RawRun:
            raw = METHODS["exact"](model, ag, *args)
            return dataclasses.replace(raw, peak_abs_x=peak, overturned=False)

        return run

    ag = _sine(0.5)
    honest = simulate(FRAME, ag, 0.01, record_history=False).summary
    assert honest.status == "ok" and not honest.overturned
    past_cap = simulate(FRAME, ag, 0.01, method=claims(0.7), record_history=False).summary
    assert past_cap.status == "failed" and "without an overturning verdict" in past_cap.message
    nan = simulate(FRAME, ag, 0.01, method=claims(math.nan), record_history=False).summary
    assert nan.status == "nonfinite"
    # Without a cap the bound is y_e = (γ₁ + P₂ max|ẍ_g|)/ω₂².
    free = dataclasses.replace(FRAME, x_cap_m=None)
    reach = (free.gamma_1_m_s2 + free.p_2 * 0.5) / free.omega_2_rad_s**2
    beyond = simulate(free, ag, 0.01, method=claims(1.01 * reach), record_history=False)
    assert beyond.summary.status == "failed"
    within = simulate(free, ag, 0.01, method=claims(0.99 * reach), record_history=False)
    assert within.summary.status == "ok"


@dataclass(frozen=True)
class _PlainFrame:
    """Not a PortalFrame: any object with the model constants (FrameLike)."""

    omega_1_rad_s: float = 6.4581
    omega_2_rad_s: float = 0.6445
    p_1: float = 1.0901
    p_2: float = 1.2680
    gamma_1_m_s2: float = 0.1387
    xi_1: float = 0.05
    xi_2: float = 0.0
    x_c_m: float = 0.05
    c_r: float = 0.9
    x_cap_m: float | None = 0.6


def test_any_frame_like_object_is_accepted() -> None:
    ag = _sine(2.0)
    plain = simulate(_PlainFrame(), ag, 0.01, record_history=False).summary
    assert plain == simulate(FRAME, ag, 0.01, record_history=False).summary


def test_one_default_gravity_across_the_structure_api() -> None:
    """Every function or method of stepframe.structure with a g_m_s2 argument defaults to the
    paper's 9.81 (PAPER_G_M_S2); simulate_rigid_block defaulted to 9.80665 before."""
    found = []
    for info in pkgutil.iter_modules(stepframe.structure.__path__):
        module = importlib.import_module(f"stepframe.structure.{info.name}")
        for _, obj in inspect.getmembers(module):
            if getattr(obj, "__module__", None) != module.__name__:
                continue
            members = [obj]
            if inspect.isclass(obj):
                members += [m for _, m in inspect.getmembers(obj) if callable(m)]
            for member in members:
                try:
                    parameters = inspect.signature(member).parameters
                except (TypeError, ValueError):
                    continue
                if "g_m_s2" in parameters and parameters["g_m_s2"].default is not inspect._empty:
                    found.append((member.__qualname__, parameters["g_m_s2"].default))
    assert any(name == "simulate_rigid_block" for name, _ in found)
    assert len(found) >= 5
    assert {default for _, default in found} == {PAPER_G_M_S2}


def test_batch_through_an_executor_equals_the_in_process_batch() -> None:
    records = [(_sine(a, 800), 0.01) for a in (0.5, 1.5, 3.0)]
    scales = [0.5, 1.0, 2.0]
    local = simulate_batch(FRAME, records, scales, tail_s=2.0)
    with ThreadPoolExecutor(max_workers=2) as pool:
        spread = simulate_batch(FRAME, records, scales, tail_s=2.0, executor=pool)
    # A process pool after this process ran numba's parallel loop (fork would be killed).
    pooled = simulate_batch(FRAME, records, scales, tail_s=2.0, jobs=2)
    np.testing.assert_array_equal(local["peak_abs_x_m"], pooled["peak_abs_x_m"])
    assert list(local.columns) == list(spread.columns)
    assert (local["status"] == "ok").all() and (local["message"] == "").all()
    np.testing.assert_array_equal(local["peak_abs_x_m"], spread["peak_abs_x_m"])
    np.testing.assert_array_equal(local["n_impacts"], spread["n_impacts"])
    assert local["overturned"].any() and not local["overturned"].all()
    for row in local.itertuples():
        ag, dt = records[row.record]
        one = simulate(FRAME, ag, dt, scale=row.scale, tail_s=2.0, record_history=False)
        assert row.peak_abs_x_m == one.summary.peak_abs_x_m
        assert row.status == one.summary.status


def test_the_three_declarations_of_the_model_constants_agree() -> None:
    """PortalFrame (what users build), FrameLike (what the simulator reads) and Model (what the
    compiled kernels take) each list the constants of eqs. 4.11-4.12; `model_of` copies them by
    name, so a constant added to one and not the others would be silently dropped."""
    from stepframe.structure.simulator import FrameLike

    frame_fields = tuple(f.name for f in dataclasses.fields(PortalFrame))
    protocol = tuple(name for name, value in vars(FrameLike).items() if isinstance(value, property))
    assert set(Model._fields) == set(protocol)
    assert set(Model._fields) == set(frame_fields) - {"h_r_m"}  # height: drift ratios only
