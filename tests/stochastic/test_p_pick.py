"""The P-onset pick: quantised and zero-padded starts, its confidence, the default time origin."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from stepframe.stochastic.features import aic_curve, pick_arrivals, quantum, record_features
from stepframe.stochastic.model import GroundMotionModel
from stepframe.stochastic.synthetic import synthetic_motions

PEER = Path(__file__).resolve().parents[1] / "data" / "peer_nga_west2"
DT = 0.01
MODEL = GroundMotionModel.from_hz(8, 3, 1, 0.2, 0.3, t_max_s=4.0, t_dur_s=12.0, t0_s=8.0)


def _event(seed: int, noise: float = 3e-3) -> np.ndarray:
    """A synthetic event starting at 8 s over Gaussian pre-event noise."""
    _, acc = synthetic_motions(MODEL, duration_s=40.0, dt_s=DT, seed=seed)
    rng = np.random.default_rng(seed)
    return np.asarray(acc[0] + noise * rng.standard_normal(acc.shape[1]))


def test_aic_matches_obspy_on_a_continuous_record() -> None:
    """Without a floor, the AIC is obspy's aic_simple (Maeda's formula) at interior points."""
    from obspy.signal.trigger import aic_simple

    x = _event(1)[:1200]
    ours = aic_curve(x, 0.0)  # split k = 1 .. n - 1 at index k - 1
    theirs = np.asarray(aic_simple(x))
    # Same values at the same index (obspy's index i: first i + 1 samples vs the rest); compare
    # away from the ends, where one-sample variances are 0.
    assert ours[10:-10] == pytest.approx(theirs[10:-11], rel=1e-9)


@pytest.mark.parametrize("seed", [2, 3, 4])
def test_quantised_zero_padded_start(seed: int) -> None:
    """3 s of zero padding, then noise that 0.01 quantisation turns mostly into zeros: obspy's
    AIC is -inf there (the pick lands on the edge); the floored AIC finds the onset at 8 s."""
    from obspy.signal.trigger import aic_simple

    clean = _event(seed)
    x = np.round(clean, 2)
    x[:300] = 0.0
    assert quantum(x) == pytest.approx(0.01)
    assert np.isneginf(np.asarray(aic_simple(x[:1000]))).any()
    arrivals = pick_arrivals(x, DT, 12.0)
    # The envelope rises from 0 at 8 s: the onset shows once the motion exceeds the noise.
    assert arrivals.p_onset_s is not None
    assert arrivals.p_onset_s == pytest.approx(8.0, abs=0.6)
    reference = pick_arrivals(clean, DT, 12.0).p_onset_s  # continuous, unpadded: no floor needed
    assert reference is not None and arrivals.p_onset_s == pytest.approx(reference, abs=0.4)
    # The noise section starts after the leading constant run (3 s of padding and the first
    # quantised zeros of the noise).
    assert 3.0 <= arrivals.p_onset_s - arrivals.noise_s < 4.0
    assert arrivals.reliable and arrivals.p_snr > 10
    f = record_features(x, DT)  # default t0="auto"
    assert f.t0_source == "p-pick" and f.t0_s == arrivals.p_onset_s


def test_no_onset_in_noise_is_unreliable_and_auto_keeps_the_start() -> None:
    rng = np.random.default_rng(5)
    t = np.arange(0, 30, DT)
    x = rng.standard_normal(t.size) * (1 + 0.2 * np.sin(2 * np.pi * t / 30))  # no event
    arrivals = pick_arrivals(x, DT, 20.0)
    assert not arrivals.reliable
    f = record_features(x, DT)
    assert f.t0_source == "start" and f.t0_s == 0.0 and f.p_onset_s is None
    forced = record_features(x, DT, t0="p-pick")  # asked for: used whatever its confidence
    assert forced.t0_source in ("p-pick", "start")
    assert (forced.t0_source == "start") == ("p_pick_failed" in forced.flags)


def test_rsn8883_default_origin_is_the_p_onset() -> None:
    """The README's record: the onset at about 24 s; fitted f_p near 14-18 Hz, t_max near 3 s
    (with the record start, ω_p sits on its bound, flagged and implausible)."""
    from stepframe.records import read
    from stepframe.stochastic.fit import fit_model

    for name in ("RSN8883_14383980_13849090.AT2", "RSN8883_14383980_13849360.AT2"):
        trace = read(PEER / name)[0]
        f = record_features(trace)
        assert f.t0_source == "p-pick"
        assert f.t0_s == pytest.approx(24.2, abs=0.3)
        assert f.p_pick_snr is not None and f.p_pick_snr > 50
        fitted = fit_model(f)
        assert fitted.model.omega_p_rad_s / (2 * np.pi) == pytest.approx(16, abs=3)
        assert f.t_max_s == pytest.approx(3.1, abs=0.5)
        assert "omega_p_at_bound" not in fitted.flags
        at_start = fit_model(record_features(trace, t0="start"))
        assert "omega_p_at_bound" in at_start.flags
