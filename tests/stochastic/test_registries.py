"""Method families: each registry and the Literal naming it hold the same names; callables work."""

from __future__ import annotations

import math
import subprocess
import sys
from typing import get_args

import numpy as np
import pytest

from stepframe.errors import InputError
from stepframe.stochastic import methods
from stepframe.stochastic.features import (
    FREQUENCY_ESTIMATORS,
    FrameSpectra,
    FrequencyEstimate,
    record_features,
    zero_crossing_estimate,
)
from stepframe.stochastic.mean_square import METHODS, MeanSquareProblem, mean_square_response
from stepframe.stochastic.model import GroundMotionModel
from stepframe.stochastic.spectra import SPECTRUM_METHODS, evolutionary_spectrum, stft_spectrum


def test_literals_and_registries_hold_the_same_names() -> None:
    assert set(get_args(methods.FrequencyMethod)) == set(FREQUENCY_ESTIMATORS)
    assert set(get_args(methods.SpectrumMethod)) == set(SPECTRUM_METHODS)
    assert set(get_args(methods.MeanSquareMethod)) == set(METHODS)


def test_the_names_module_is_light() -> None:
    probe = (
        "import sys, stepframe.stochastic.methods; "
        "print([m for m in ('numpy', 'scipy', 'numba', 'xarray') if m in sys.modules])"
    )
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "[]"


def _chirp() -> tuple[np.ndarray, float]:
    dt = 0.01
    t = np.arange(0, 30, dt)
    # A sine at 2 Hz: zero crossings at 4 per second, ω = π·4 = 4π rad/s.
    return np.sin(2 * math.pi * 2.0 * t) * np.exp(-(((t - 15) / 8) ** 2)), dt


def test_a_callable_estimator_is_accepted_where_a_name_is() -> None:
    data, dt = _chirp()
    seen: list[FrameSpectra] = []

    def doubled(frames: FrameSpectra) -> FrequencyEstimate:
        seen.append(frames)
        base = zero_crossing_estimate(frames)
        return FrequencyEstimate(2 * base.omega_g_rad_s, base.kernel)

    by_name = record_features(data, dt, frequency="zero-crossing")
    custom = record_features(data, dt, frequency=doubled)
    assert len(seen) == 1 and custom.frequency_method == "doubled"
    np.testing.assert_allclose(custom.omega_g_rad_s, 2 * by_name.omega_g_rad_s)
    strong = by_name.strong_motion()
    assert np.nanmedian(by_name.omega_g_rad_s[strong]) == pytest.approx(4 * math.pi, rel=0.02)
    with pytest.raises(InputError, match="frequency = 'nope'"):
        record_features(data, dt, frequency="nope")  # type: ignore[arg-type]  # on purpose


def test_a_callable_spectrum_method_is_accepted_where_a_name_is() -> None:
    data, dt = _chirp()
    named = evolutionary_spectrum(data, dt, "stft")
    custom = evolutionary_spectrum(data, dt, stft_spectrum)
    np.testing.assert_array_equal(named.values, custom.values)
    assert custom.attrs["method"] == "stft_spectrum"


def test_a_callable_mean_square_method_is_accepted_where_a_name_is() -> None:
    model = GroundMotionModel(20.0, 10.0, 5.0, 0.3, 0.6, t_max_s=5.0, t_dur_s=15.0)
    grid = np.linspace(0.0, 20.0, 801)
    calls: list[MeanSquareProblem] = []

    def recorded(problem: MeanSquareProblem):  # type: ignore[no-untyped-def]
        calls.append(problem)
        return METHODS["covariance"](problem)

    named = mean_square_response(model, 8.0, 0.05, method="covariance", time_s=grid)
    custom = mean_square_response(model, 8.0, 0.05, method=recorded, time_s=grid)
    assert len(calls) == 1 and calls[0].xi0 == 0.05
    np.testing.assert_array_equal(named.mean_square_m2, custom.mean_square_m2)


def test_mean_square_result_to_dict_reports_the_status_and_peaks() -> None:
    model = GroundMotionModel(20.0, 10.0, 5.0, 0.3, 0.6, t_max_s=5.0, t_dur_s=15.0)
    grid = np.linspace(0.0, 20.0, 801)
    result = mean_square_response(model, [6.0, 9.0], 0.05, time_s=grid)
    summary = result.to_dict()
    assert summary["status"] == "ok" and summary["message"] == ""
    assert summary["omega_0_rad_s"] == [6.0, 9.0]
    expected = np.sqrt(np.nanmax(result.mean_square_m2, axis=1))
    np.testing.assert_allclose(summary["peak_rms_m"], expected, rtol=0)
