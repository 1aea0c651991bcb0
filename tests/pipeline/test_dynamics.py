"""pipeline.dynamics: the studies behind `stepframe structure harmonic | bifurcation | ida`."""

from __future__ import annotations

import math

import numpy as np
import pytest

from stepframe.errors import InputError
from stepframe.pipeline.dynamics.studies import (
    G_M_S2,
    BifurcationOptions,
    HarmonicOptions,
    IdaOptions,
    bifurcation_sweep,
    frame_or_block,
    harmonic_study,
    ida_study,
)
from stepframe.structure.frame import PortalFrame
from stepframe.structure.harmonic import simulate_harmonic

BLOCK = (0.25, 1.0)


def test_harmonic_study_orbit_is_a_fixed_point_of_the_period_map() -> None:
    block = frame_or_block(None, BLOCK)
    study = harmonic_study(block, HarmonicOptions(0.3, 16.0, periods=60, orbit=1))
    period = 2 * math.pi / 16.0
    reference = simulate_harmonic(block, 0.3 * G_M_S2, 16.0, 60 * period, samples_per_period=32)
    data = study.to_dict()
    assert data["n_impacts"] == reference.n_impacts
    assert data["x_end_m"] == float(reference.x_m[-1])
    assert study.orbit is not None and study.orbit.status == "ok"
    # Independent check: one forcing period from the orbit's state comes back to it.
    again = simulate_harmonic(
        block, 0.3 * G_M_S2, 16.0, period, x0_m=study.orbit.x_m, v0_m_s=study.orbit.v_m_s
    )
    assert float(again.x_m[-1]) == pytest.approx(study.orbit.x_m, abs=1e-8)
    assert float(again.v_m_s[-1]) == pytest.approx(study.orbit.v_m_s, abs=1e-7)
    lines = study.describe().splitlines()
    assert lines[0].startswith("A = 0.3 g, ω = 16 rad/s, 60 periods: status ok")
    assert lines[1].startswith("period-1 orbit: status ok")
    assert "orbit_message" not in data


def test_an_orbit_asked_of_an_overturning_run_says_why_there_is_none() -> None:
    """Example 4's frame overturns at 0.25 g, 7.854 rad/s (8.45 s): no final state to start
    Newton from; the orbit asked for was dropped without a word before."""
    import tomllib

    from stepframe.structure.dynamics_plots import phase_portrait_figure
    from stepframe.structure.frame_file import FRAME_TEMPLATE, frame_from_mapping

    frame = frame_from_mapping(tomllib.loads(FRAME_TEMPLATE))
    study = harmonic_study(frame, HarmonicOptions(0.25, 7.854, orbit=1))
    assert study.run.overturned and study.orbit is None
    data = study.to_dict()
    assert "orbit" not in data and "overturned" in data["orbit_message"]
    assert study.describe().splitlines()[-1] == data["orbit_message"]
    # Its phase portrait draws the run up to overturning (its second half is all NaN).
    axes = phase_portrait_figure(study.run, x_c_m=frame.x_c_m, x_star_m=frame.x_star_m).axes[0]
    drawn = axes.lines[0].get_xdata()
    assert np.isfinite(drawn).sum() == np.isfinite(study.run.x_m).sum() > 0
    assert "up to overturning" in axes.get_title()


def test_frame_or_block_is_housners_block_and_refuses_three_numbers() -> None:
    block = frame_or_block(None, BLOCK)
    assert block == PortalFrame.housner_block(half_width_m=0.25, half_height_m=1.0)
    with pytest.raises(InputError, match="expected two numbers B,H"):
        frame_or_block(None, [0.25, 1.0, 2.0])


def test_bifurcation_text_says_which_values_it_shows() -> None:
    """200 values printed 20 rows (one in 10, not the last) under a header saying '200 values':
    the header now says which are shown, and the last value is among them."""
    import xarray as xr

    from stepframe.pipeline.dynamics.studies import BifurcationSweep

    values = np.linspace(0.05, 0.5, 200)
    points = [
        {"amplitude_g": v, "overturned_fraction": 0.5, "stopped": 0, "periods_found": [1]}
        for v in values
    ]
    sweep = BifurcationSweep("amplitude_g", 7.854, None, values, 50, 100, xr.Dataset(), points)
    lines = sweep.describe().splitlines()
    assert lines[0] == (
        "200 values × 50 initial states × 100 periods at ω = 7.854 rad/s "
        "(one value in 10 shown, and the last; --json or --plot: all)"
    )
    shown = [float(line.split()[0]) for line in lines[1:]]
    assert shown == pytest.approx([*values[::10], 0.5], rel=5e-4)
    few = BifurcationSweep(
        "amplitude_g", 7.854, None, values[:3], 50, 100, xr.Dataset(), points[:3]
    )
    assert few.describe().splitlines()[0].endswith("at ω = 7.854 rad/s")
    assert len(few.describe().splitlines()) == 4


def test_bifurcation_points_recount_the_dataset() -> None:
    block = frame_or_block(None, BLOCK)
    options = BifurcationOptions(16.0, (0.1, 0.3, 3), initial=4, periods=30, jobs=1)
    sweep = bifurcation_sweep(block, options)
    assert [round(p["amplitude_g"], 9) for p in sweep.points] == [0.1, 0.2, 0.3]
    outcome = sweep.dataset["outcome"].values
    for a, point in enumerate(sweep.points):
        assert point["overturned_fraction"] == float(np.mean(outcome[a] == 1))
        assert point["stopped"] == int(np.sum(outcome[a] == 2))
    assert sweep.describe().startswith("3 values × 4 initial states × 30 periods at ω = 16")
    with pytest.raises(InputError, match="expected exactly one sweep"):
        bifurcation_sweep(block, BifurcationOptions(amplitude_g=0.1, amplitudes_g=(0.1, 0.3, 3)))
    # an option of the other sweep beside a complete one was ignored (the same diagram): refused
    stray = BifurcationOptions(16.0, (0.1, 0.3, 3), amplitude_g=0.2, initial=4, periods=30)
    with pytest.raises(InputError, match="--amplitude-g with the amplitude sweep"):
        bifurcation_sweep(block, stray)
    other = BifurcationOptions(amplitude_g=0.2, omegas_rad_s=(5.0, 10.0, 2), omega_rad_s=16.0)
    with pytest.raises(InputError, match="--omega-rad-s with the frequency sweep"):
        bifurcation_sweep(block, other)


def test_ida_study_of_a_cosine_pulse_finds_the_resurrection() -> None:
    block = frame_or_block(None, BLOCK)
    options = IdaOptions(pulse="cosine", omegas_rad_s=(10.8,), resolution_g=0.001)
    study = ida_study(block, options)
    data = study.to_dict()
    assert study.names == ["cosine ω = 10.8 rad/s"]
    assert data["intensity"] == "amplitude / (γ₁/P₂)"
    assert data["resurrected"] == 1
    assert data["simulations"] == sum(item.n_runs for item in study.items)
    assert data["simulations"] < data["fixed_step_simulations"]
    with pytest.raises(InputError, match="no records"):
        ida_study(block, IdaOptions())
