"""The ranking's parts: the peers against closed forms and independent spectra, the exact
ranking's order and overturning factor, the stated intensity, the tiers' plan, bad input."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from stepframe.errors import InputError
from stepframe.pipeline.selection import SelectionOptions
from stepframe.pipeline.selection.exact import (
    LADDER,
    RESOLUTION,
    overturn_peak_m,
    ranking_order,
    simulated_response,
    tied_across,
)
from stepframe.pipeline.selection.intensity import (
    check_target_covers,
    onset_psa_t1_g,
    ranking_intensity,
)
from stepframe.pipeline.selection.peers import (
    FIV_ALPHA,
    PEERS,
    PeerPeriods,
    at_intensity,
    fiv3_m_s,
    record_peers,
)
from stepframe.pipeline.selection.tiers import agreement, best_rows, plan, recall
from stepframe.structure.frame import PortalFrame

G = 9.80665


def test_fiv3_of_a_sinusoid_is_its_closed_form() -> None:
    """A steady sinusoid A sin ωt well below the cut-off: the filter keeps the amplitude
    G = 1/√(1 + (f/f_c)⁴) (second-order Butterworth), the window integral is
    (2GA/ω) sin(ωαT/2) sin(...), and its three peaks sum to 3 times that."""
    dt, period_s, frequency_hz, amplitude = 0.005, 1.0, 0.2, 2.0
    time_s = np.arange(0.0, 60.0, dt)
    omega = 2 * math.pi * frequency_hz
    gain = 1 / math.sqrt(1 + (frequency_hz / (0.85 / period_s)) ** 4)
    expected = 3 * 2 * gain * amplitude / omega * abs(math.sin(omega * FIV_ALPHA * period_s / 2))
    value = fiv3_m_s(amplitude * np.sin(omega * time_s), dt, period_s)
    assert value == pytest.approx(expected, rel=1e-3)
    assert math.isnan(fiv3_m_s(np.ones(10), 0.01, 1.0))  # shorter than the window


def test_fiv3_filter_remembered_is_the_one_designed() -> None:
    """The low-pass remembered across records (same cut-off, same sampling) filters as the
    Butterworth filter designed afresh: FIV3 of a second record at the same dt, computed after
    the first, equals a direct computation with scipy's butter/lfilter, bit for bit."""
    from scipy.signal import butter, find_peaks, lfilter

    dt, period_s = 0.01, 0.8
    rng = np.random.default_rng(4)
    fiv3_m_s(rng.normal(size=3000), dt, period_s)  # designs and remembers the filter
    acc = rng.normal(size=2500)
    b, a = butter(2, 0.85 / period_s, fs=1.0 / dt)
    filtered = lfilter(b, a, acc)
    velocity = np.concatenate([[0.0], np.cumsum(0.5 * dt * (filtered[1:] + filtered[:-1]))])
    time_s = np.arange(acc.size) * dt
    starts = time_s[time_s + FIV_ALPHA * period_s <= time_s[-1]]
    fiv = np.interp(starts + FIV_ALPHA * period_s, time_s, velocity) - velocity[: starts.size]
    peaks = np.sort(fiv[find_peaks(fiv)[0]])[::-1][:3]
    troughs = np.sort(fiv[find_peaks(-fiv)[0]])[:3]
    assert fiv3_m_s(acc, dt, period_s) == max(np.sum(peaks), abs(np.sum(troughs)))


def test_peers_against_independent_spectra(example_inputs: Any) -> None:
    """Sa_avg, SaRatio, N_p and the PGV ratios re-computed from response_spectrum and
    intensity_measures, one period at a time."""
    from stepframe.records.intensity import intensity_measures
    from stepframe.records.spectra import response_spectrum

    acc, dt = next(iter(example_inputs[1].values()))
    t1, band_end = 0.97, 6.0
    peers = record_peers(acc, dt, PeerPeriods(t1, band_end))

    def sa(periods: Any) -> Any:
        return response_spectrum(acc, dt, np.atleast_1d(periods), 0.05).psa_m_s2

    def geometric_mean(low: float, high: float) -> float:
        return float(np.exp(np.mean(np.log(sa(np.linspace(low, high, 10))))))

    sa_t1 = float(sa(t1)[0])
    measures = intensity_measures(acc, dt)
    expected = {
        "sa_t1_g": sa_t1 / G,
        "sa_avg_g": geometric_mean(0.2 * t1, 3 * t1) / G,
        "sa_ratio": sa_t1 / geometric_mean(0.2 * t1, 3 * t1),
        "n_p_2t1": geometric_mean(t1, 2 * t1) / sa_t1,
        "n_p_band": geometric_mean(t1, band_end) / sa_t1,
        "sa_1_5t1_ratio": float(sa(1.5 * t1)[0]) / sa_t1,
        "pgv_pga_s": measures["pgv_pga_s"],
        "pgv_sa_t1_s": measures["pgv_m_s"] / sa_t1,
    }
    for name, value in expected.items():
        assert peers[name] == pytest.approx(value, rel=1e-10), name
    assert set(peers) == set(PEERS)
    # N_p over the band stops at 10 s: T(A_max) beyond it reads the same as 10 s
    far = record_peers(acc, dt, PeerPeriods(t1, 40.0))
    assert far["n_p_band"] == pytest.approx(geometric_mean(t1, 10.0) / sa_t1, rel=1e-10)


def test_peers_at_an_intensity_scale_and_sign() -> None:
    values = np.array([0.2, 0.4, 0.1])
    scales = np.array([2.0, 0.5, 1.0])
    assert np.allclose(at_intensity("sa_t1_g", values, scales), [0.4, 0.2, 0.1])
    assert np.allclose(at_intensity("sa_ratio", values, scales), -values)  # lower is worse
    # equal S_a(T_1) up to rounding ranks as a tie
    equal = at_intensity("sa_t1_g", np.array([1.0, 2.0]), np.array([1.0, 0.5 * (1 + 1e-13)]))
    assert equal[0] == equal[1]


def test_ranking_order_overturning_first() -> None:
    factor = np.array([np.nan, 1.2, np.nan, 0.8, 1.2, np.nan])
    response = np.array([0.5, 5.0, 0.9, 5.0, 5.0, np.nan])
    # overturners by factor (ties by index), then the rest by response, failed last
    assert ranking_order(factor, response).tolist() == [3, 1, 4, 2, 0, 5]


def test_ties_across_the_chosen_sets_edge() -> None:
    """A tie needs both keys within the bisection's resolution, (1 - 1/√2)/256, and a chosen
    and an unchosen candidate; NaN factors (never overturning) tie with each other only."""
    assert abs(RESOLUTION - 0.29289321881 / 256) < 1e-13
    near = 1.0 + 0.9 * RESOLUTION  # within the resolution of 1
    far = 1.0 + 1.1 * RESOLUTION
    factor = np.array([1.0, 1.0, near, far, 1.0, np.nan, np.nan, np.nan, 1.0])
    response = np.array([1.2, 1.2, 1.2, 1.2, 1.2 * far, 0.4, 0.4 * near, 0.4, np.nan])
    chosen = np.array([True, True, False, False, False, True, False, False, False])
    tied = tied_across(factor, response, chosen)
    # 2: factor within; 3: factor beyond; 4: response beyond; 6: both never overturn, response
    # within; 7: the same keys as 5 (chosen); 8: not ranked (NaN response)
    assert tied.tolist() == [True, True, True, False, False, True, True, True, False]
    # nothing across an edge: all chosen, or none
    assert not tied_across(factor, response, np.ones(9, dtype=bool)).any()
    assert not tied_across(factor, response, np.zeros(9, dtype=bool)).any()


def test_simulated_response_and_overturning_factor(example4: PortalFrame) -> None:
    """A ramped sinusoid at ω_1 and one ten times above it: the ladder's response re-computed
    with ``simulate`` level by level, the resonant one first, and its overturning factor the
    bisection's bracket: the frame overturns at it and stands 2⁻⁸ of the ladder step below."""
    from stepframe.structure.simulator import simulate

    dt = 0.01
    time_s = np.arange(0.0, 20.0, dt)
    ramp = np.minimum(time_s / 5.0, 1.0)
    resonant = ramp * np.sin(example4.omega_1_rad_s * time_s)
    high = ramp * np.sin(10 * example4.omega_1_rad_s * time_s)
    records = [(resonant, dt), (high, dt)]
    base = np.array([1.0, 1.0])
    result = simulated_response(example4, records, base)
    for k, (acc, _) in enumerate(records):
        peaks = []
        for factor in LADDER:
            run = simulate(example4, acc, dt, scale=base[k] * factor).summary
            peaks.append(overturn_peak_m(example4) if run.overturned else run.peak_abs_x_m)
        assert result.response_m[k] == pytest.approx(np.exp(np.mean(np.log(peaks))), rel=1e-9)
    assert result.order().tolist() == [0, 1]
    factor = result.overturn_factor[0]
    assert math.isnan(result.overturn_factor[1]) and result.n_overturned.tolist() == [3, 0]
    assert LADDER[1] < factor <= LADDER[2]  # the first ladder level that overturns is 1
    below = factor - (LADDER[2] - LADDER[1]) / 2**8
    assert simulate(example4, resonant, dt, scale=factor).summary.overturned
    assert not simulate(example4, resonant, dt, scale=below).summary.overturned


def test_stated_intensity_scales(example4: PortalFrame) -> None:
    sd_t1 = np.array([0.05, 0.2])
    psa_t1_g = np.array([0.3, 0.6])
    scale_factor = np.array([1.5, 0.5])
    as_used = ranking_intensity(SelectionOptions(), example4, LADDER)
    assert as_used.kind == "as-used" and "as recorded" in as_used.describe()
    assert np.array_equal(
        as_used.base_scales(example4, sd_t1, psa_t1_g, scale_factor), scale_factor
    )
    onset = ranking_intensity(SelectionOptions(rank_onset_ratio=2.0), example4, LADDER)
    scales = onset.base_scales(example4, sd_t1, psa_t1_g, scale_factor)
    assert np.allclose(example4.p_1 * sd_t1 * scales, 2.0 * example4.x_c_m, rtol=1e-14)
    assert onset.to_dict()["onset_psa_t1_g"] == pytest.approx(
        example4.omega_1_rad_s**2 * example4.x_c_m / example4.p_1 / G, rel=1e-14
    )
    in_g = ranking_intensity(SelectionOptions(rank_psa_t1_g=0.4), example4, LADDER)
    assert np.allclose(in_g.base_scales(example4, sd_t1, psa_t1_g, scale_factor) * psa_t1_g, 0.4)
    assert f"{0.4 / onset_psa_t1_g(example4):.3g} × the onset" in in_g.describe()


def test_plan_budget_rule_and_recall() -> None:
    options = SelectionOptions(n=10)
    assert plan(options, 1000, 10**6, 5).method == "exact"
    over = plan(SelectionOptions(n=10, exact_budget_s=1e-6), 1000, 10**9, 5)
    # the measured share of the candidates (tiers.PREFILTER_SHARE), at least 10 n
    assert (over.method, over.tier, over.k) == ("prefilter", "n_p_band", 910)
    small = plan(SelectionOptions(n=10, exact_budget_s=1e-6), 105, 10**9, 5)
    assert small.method == "prefilter" and small.k == 100
    assert "over the budget" in over.reason
    asked = plan(SelectionOptions(n=10, prefilter="fiv3_m_s", prefilter_k=30), 1000, 10, 5)
    assert (asked.method, asked.tier, asked.k) == ("prefilter", "fiv3_m_s", 30)
    assert plan(SelectionOptions(n=10, rank_by="n_p_band"), 1000, 10, 5).method == "tier"
    values = np.array([5.0, np.nan, 3.0, 4.0, 1.0])
    assert best_rows(values, 3).tolist() == [0, 3, 2]
    assert recall(np.array([0, 4]), values, 2) == 0.5
    exact = np.linspace(1.0, 0.0, 20)
    rows = agreement(exact, {"same": exact.copy(), "reversed": -exact}, 2)
    assert rows[0]["spearman"] == pytest.approx(1.0) and rows[0]["recall_at_1n"] == 1.0
    assert rows[1]["spearman"] == pytest.approx(-1.0) and rows[1]["recall_at_10n"] == 1.0
    assert rows[1]["recall_at_5n"] == 0.0


@pytest.mark.parametrize(
    ("values", "message"),
    [
        ({"n": 10, "prefilter_k": 5}, "prefilter_k = 5 < n = 10, expected at least n"),
        ({"n": 1, "prefilter": "nope"}, "prefilter = 'nope', expected one of auto, none"),
        ({"n": 1, "rank_onset_ratio": 0.0}, "rank_onset_ratio = 0.0, expected in (0, 20]"),
        ({"n": 1, "rank_psa_t1_g": 25.0}, "rank_psa_t1_g = 25.0, expected in (0, 20]"),
        (
            {"n": 1, "rank_onset_ratio": 1.0, "rank_psa_t1_g": 0.3},
            "rank_onset_ratio and rank_psa_t1_g both given, expected at most one",
        ),
        ({"n": 1, "rank_by": "n_p_band", "prefilter": "fiv3_m_s"}, "prefilter options with"),
        ({"n": 1, "scores": ["nope"]}, "scores = ['nope'], expected names among"),
        ({"n": 1, "prefilter": "none", "prefilter_k": 3}, "prefilter_k given with prefilter"),
    ],
)
def test_bad_ranking_options(values: dict[str, Any], message: str) -> None:
    with pytest.raises(InputError) as error:
        SelectionOptions.from_dict(values)
    assert message in error.value.one_line()


def test_a_target_that_does_not_cover_t1() -> None:
    from stepframe.structure.design_spectrum import TabulatedSpectrum

    target = TabulatedSpectrum((0.1, 0.5), (3.0, 2.0))
    with pytest.raises(InputError) as error:
        check_target_covers(target, 0.97)
    assert error.value.one_line() == (
        "the target spectrum covers 0.1-0.5 s, expected it to cover T_1 = 0.97 s (the frame's "
        "period, where the selection reads it)"
    )
    check_target_covers(TabulatedSpectrum((0.1, 2.0), (3.0, 2.0)), 0.97)


@pytest.mark.parametrize(
    ("words", "line"),
    [
        (["--prefilter", "nope"], "argument --prefilter: invalid choice: 'nope'"),
        (["--prefilter-k", "5"], "--prefilter-k 5 < n = 10, expected at least n"),
        (["--rank-psa-t1-g", "30"], "--rank-psa-t1-g 30.0, expected in (0, 20]"),
        (["--rank-onset-ratio", "0"], "'0' is not positive, expected a positive number"),
        (["--target-csv", "TARGET"], "the target spectrum covers 0.1-0.5 s, expected it to cover"),
    ],
)
def test_bad_ranking_input_is_one_line_exit_2(
    words: list[str], line: str, tmp_path: Any, capsys: pytest.CaptureFixture[str]
) -> None:
    """Refused before any work: nothing written, one line on stderr, exit 2."""
    from stepframe.cli import main
    from stepframe.structure.frame_file import FRAME_TEMPLATE

    frame = tmp_path / "FRAME.toml"
    frame.write_text(FRAME_TEMPLATE)
    target = tmp_path / "target.csv"
    target.write_text("period_s,sa_g\n0.1,1.0\n0.5,0.8\n")
    words = [str(target) if w == "TARGET" else w for w in words]
    out = tmp_path / "picks"
    command = ["select", "--frame", str(frame), "--example", "fema-p695", "-n", "10"]
    assert main([*command, "-o", str(out), *words]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("stepframe: error: ") and line in err[0]
    assert not out.exists()


def test_prefilter_simulates_the_tiers_best_k(example_inputs: Any, example4: PortalFrame) -> None:
    from stepframe.pipeline.selection import select_records

    table, records, _ = example_inputs
    options = SelectionOptions(
        n=3, prefilter="n_p_band", prefilter_k=20, n_bootstrap=0, rank_onset_ratio=1.0
    )
    result = select_records(table, example4, options, records=records, jobs=1)
    cands = result.candidates
    simulated = cands["simulated"].astype(bool).to_numpy()
    assert simulated.sum() == 20
    # independent: the 20 largest N_p over the band (a ratio: the same at any scale)
    n_p = cands["n_p_band"].to_numpy(dtype=float)
    assert set(np.flatnonzero(simulated)) == set(np.argsort(-n_p, kind="stable")[:20])
    assert cands.loc[cands["selected"].astype(bool), "simulated"].astype(bool).all()
    ranking = result.summary["ranking"]
    assert (ranking["method"], ranking["tier"], ranking["k"]) == ("prefilter", "n_p_band", 20)
    assert ranking["n_simulated"] == 20 and "prefiltered as asked" in ranking["text"]
    assert result.summary["tiers"] == []  # no exact ranking of every candidate to compare with
    # the printed summary says so (it did not: each pick read "rank k of 100")
    lines = result.summary_lines()
    said = [line for line in lines if line.startswith("  prefiltered: ")]
    assert said == [f"  prefiltered: {ranking['text']}; the others were not simulated and rank "
                    "after them"]  # fmt: skip


def test_the_plan_is_the_same_on_every_machine(monkeypatch: pytest.MonkeyPatch) -> None:
    # The estimate is CPU seconds of one core (samples × runs × the per-sample cost), so the
    # plan and selection.json do not change with the CPUs a machine has (they once did).
    import os

    from stepframe.pipeline.selection import tiers

    options = SelectionOptions(n=10, exact_budget_s=100.0)
    samples, runs = 10**9, 13
    expected = samples * runs * tiers.SIMULATION_S_PER_SAMPLE
    plans = []
    for cpus in ({0}, set(range(64))):
        monkeypatch.setattr(os, "sched_getaffinity", lambda _pid, c=cpus: c, raising=False)
        monkeypatch.setattr(os, "cpu_count", lambda c=cpus: len(c))
        plans.append(plan(options, 1000, samples, runs).to_dict())
    assert plans[0] == plans[1]
    assert plans[0]["estimated_exact_s"] == pytest.approx(expected, rel=1e-12)
    assert plans[0]["method"] == "prefilter"  # 481 CPU s over the budget of 100, on any machine


def test_overturning_scan_in_rounds_equals_every_level(example4: PortalFrame) -> None:
    """The confirmation's overturning scan stops a record at its first overturning level
    (rounds of SCAN_ROUND levels): the same factors as simulating every record at every level
    first (the verdict table of ladder_runs over all of SCAN_LEVELS, then first_overturn), for
    records that overturn in the first round, in the second, and never."""
    from stepframe.pipeline.selection import confirm
    from stepframe.pipeline.selection.exact import first_overturn, ladder_runs

    dt = 0.01
    time_s = np.arange(0.0, 20.0, dt)
    ramp = np.minimum(time_s / 5.0, 1.0)
    resonant = ramp * np.sin(example4.omega_1_rad_s * time_s)
    records = [(resonant, dt), (resonant, dt), (resonant, dt), (resonant * 0.0 + 1e-6, dt)]
    # the same record at three base scales: first overturning level low, in the second round,
    # and above the last level
    every = ladder_runs(example4, records[:1], np.ones(1), confirm.SCAN_LEVELS.tolist())
    first_level = int(np.argmax(every.overturned[0]))
    assert every.overturned[0].any() and first_level > 0
    top = float(confirm.SCAN_LEVELS[-1])
    base = np.array([
        confirm.SCAN_LEVELS[first_level] / confirm.SCAN_LEVELS[1],
        confirm.SCAN_LEVELS[first_level] / confirm.SCAN_LEVELS[confirm.SCAN_ROUND + 2],
        0.5 * confirm.SCAN_LEVELS[first_level] / top,
        1.0,
    ])  # fmt: skip
    got = confirm.overturn_factors(example4, records, base, confirm.SCAN_LEVELS)
    verdicts = ladder_runs(example4, records, base, confirm.SCAN_LEVELS.tolist()).overturned
    expected = first_overturn(example4, records, base, confirm.SCAN_LEVELS, verdicts)
    assert np.array_equal(got, expected, equal_nan=True)
    firsts = [int(np.argmax(row)) if row.any() else -1 for row in verdicts]
    assert firsts[0] < confirm.SCAN_ROUND <= firsts[1] and firsts[2:] == [-1, -1]
    assert np.isfinite(got[:2]).all() and np.isnan(got[2:]).all()
