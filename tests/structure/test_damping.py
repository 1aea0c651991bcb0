"""Equivalent viscous damping from C_r (eq. 4.17) and damping-reduction formulas."""

from __future__ import annotations

import math

import pytest

from stepframe.errors import InputError
from stepframe.structure.damping import (
    beta_from_cr,
    damping_reduction,
    equivalent_damping_from_cr,
)


def test_eq_4_17_endpoints_and_velocity_ratio() -> None:
    assert equivalent_damping_from_cr(1.0) == 0.0  # elastic impact: no loss
    assert equivalent_damping_from_cr(0.0) == pytest.approx(0.48)
    # C_r is a velocity ratio: the energy kept is C_r², so C_r = 0.9 loses 19 % of the energy.
    assert equivalent_damping_from_cr(0.9) == pytest.approx(0.48 * 0.19)


@pytest.mark.parametrize("method", ["ec8", "ec8-1998", "aashto-isolation"])
def test_every_formula_is_one_at_five_percent(method: str) -> None:
    assert damping_reduction(0.05, method) == pytest.approx(1.0)  # type: ignore[arg-type]


def test_ec8_values_and_floor() -> None:
    assert damping_reduction(0.0) == pytest.approx(math.sqrt(2.0))
    assert damping_reduction(0.10) == pytest.approx(math.sqrt(10 / 15))
    # η = 0.55 where 10/(5 + 100ξ) = 0.3025, ξ = 0.28058; beyond it the floor holds.
    assert damping_reduction(0.28) == pytest.approx(math.sqrt(10 / 33))
    assert damping_reduction(0.48) == 0.55
    assert damping_reduction(5.0) == 0.55  # ξ ≥ 1 is accepted and floored


def test_other_formulas() -> None:
    assert damping_reduction(0.20, "ec8-1998") == pytest.approx(math.sqrt(7 / 22))
    assert damping_reduction(0.20, "aashto-isolation") == pytest.approx(4.0**-0.3)
    assert damping_reduction(0.45, "aashto-isolation") == pytest.approx(1 / 1.7)


def test_beta_from_cr_chains_both_steps() -> None:
    xi = 0.48 * (1 - 0.8**2)
    assert beta_from_cr(0.8) == pytest.approx(math.sqrt(10 / (5 + 100 * xi)))
    assert beta_from_cr(1.0) == pytest.approx(math.sqrt(2.0))


def test_bad_inputs() -> None:
    with pytest.raises(InputError, match="expected a velocity ratio 0 ≤ c_r ≤ 1"):
        equivalent_damping_from_cr(1.2)
    with pytest.raises(InputError, match="expected a damping ratio ≥ 0"):
        damping_reduction(-0.01)
    with pytest.raises(InputError, match="expected xi > 0"):
        damping_reduction(0.0, "aashto-isolation")
    with pytest.raises(InputError, match="expected one of ec8, ec8-1998, aashto-isolation"):
        damping_reduction(0.05, "newmark")  # type: ignore[arg-type]
