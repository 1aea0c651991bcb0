"""select_records on the embedded example catalogue: outputs, round trip, failures, bad input."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from stepframe.core.results import get_column_dictionary
from stepframe.errors import InputError
from stepframe.pipeline.selection import SelectionOptions, read_selection, select_records
from stepframe.structure.frame import PortalFrame


@pytest.fixture(scope="module")
def run(example_inputs: tuple[Any, Any, Any], example4: PortalFrame) -> Any:
    table, records, _ = example_inputs
    records = dict(records)
    table = table.copy()
    # One component whose samples are missing: it lands in failures, the run goes on.
    lost = (str(table["file"].iat[0]), str(table["component"].iat[0]))
    del records[lost]
    options = SelectionOptions(
        n=6, confirm=True, scale="psa-at-t1", max_per_event=2,
        scores=("substitute_demand_ratio",),
    )  # fmt: skip
    return select_records(table, example4, options, records=records, jobs=1), lost


def test_selection_is_the_top_of_the_ranking_under_the_cap(run: Any) -> None:
    result, lost = run
    cands = result.candidates
    passed = cands[cands["dropped_by"] == ""]
    # Every component but the one without samples: a fit flagged implausible is ranked too.
    assert len(passed) == len(cands) - 1 and not passed["plausible"].astype(bool).all()
    assert cands.loc[cands["file"] == lost[0], "dropped_by"].tolist()[0] == "samples_failed"
    # Independent re-ranking with the event cap of 2: overturning first (lower factor first),
    # then the rest by the ladder's mean peak.
    assert result.summary["rank_by"] == "simulated_response"  # the default
    key = passed.assign(factor=passed["overturn_factor"].fillna(np.inf))
    ordered = key.sort_values(
        ["factor", "simulated_response"], ascending=[True, False], kind="stable"
    )
    expected, per_event = [], {}
    for row in ordered.itertuples():
        if per_event.get(row.event, 0) < 2 and len(expected) < 6:
            expected.append((row.file, row.component))
            per_event[row.event] = per_event.get(row.event, 0) + 1
    got = list(zip(result.selection["file"], result.selection["component"], strict=True))
    assert got == expected
    assert result.selection["rank"].tolist() == [1, 2, 3, 4, 5, 6]
    # psa-at-t1 with no target: every chosen record scaled to the candidates' median PSA(T_1).
    median = np.median(passed["psa_t1_g"])
    scaled = result.selection["scale_factor"] * result.selection["psa_t1_g"]
    unclipped = ~result.selection["scale_clipped"].astype(bool)
    assert np.allclose(scaled[unclipped], median, rtol=1e-12)
    assert result.status == "degraded" and "failed" in result.message
    assert result.failures["stage"].tolist() == ["samples"]
    assert result.summary["filters"][-1] == {
        "name": "computed",
        "rule": "samples read, spectra and scores computed (the rest in failures.csv)",
        "dropped": 1,
        "left": len(passed),
    }
    # The ranking intensity is the records as used: at their psa-at-t1 scale factors.
    assert result.summary["ranking_intensity"]["kind"] == "as-used"
    assert np.allclose(passed["ranking_scale"], passed["scale_factor"], rtol=0)
    # The response does not depend on the fit: every bootstrap replicate chooses the same set.
    probability = passed["selection_probability"].to_numpy()
    assert np.array_equal(probability, passed["selected"].astype(float).to_numpy())
    # ... so the summary does not print it as if the bootstrap had tested the set.
    picks = [line for line in result.summary_lines() if line.startswith("  pick ")]
    assert len(picks) == 6 and not any("P(in set)" in line for line in picks)


def test_substitute_score_is_the_records_own_spectrum(
    run: Any, example_inputs: Any, example4: PortalFrame
) -> None:
    from stepframe.records.spectra import response_spectrum

    result, _ = run
    levels = result.summary["substitute"]
    amplitudes = np.array(levels["amplitudes_m"])
    assert amplitudes[0] == example4.x_c_m and levels["damping"][0] == example4.xi_1
    records = example_inputs[1]
    cands = result.candidates[result.candidates["dropped_by"] == ""]
    for row in cands.head(3).itertuples():
        acc, dt = records[(row.file, row.component)]
        # Independent: one response spectrum per level at that level's damping.
        sd = np.array(
            [
                response_spectrum(acc, dt, [period], damping).sd_m[0]
                for period, damping in zip(levels["periods_s"], levels["damping"], strict=True)
            ]
        )
        scale = example4.x_c_m / (example4.p_1 * sd[0])
        ratio = scale * np.array(levels["participation"]) * sd / amplitudes
        assert row.substitute_demand_ratio == pytest.approx(ratio[1:].min(), rel=1e-10)
        assert row.substitute_overturn_ratio == pytest.approx(max(1.0, 1 / ratio[1:].min()))


def test_simulated_response_is_the_frames_own(
    run: Any, example_inputs: Any, example4: PortalFrame
) -> None:
    """Independent: each ladder level simulated on its own with ``simulate`` (not the batch),
    the geometric mean of the peaks with an overturned run at the cap."""
    from stepframe.structure.simulator import simulate

    result, _ = run
    records = example_inputs[1]
    ladder = result.summary["ranking_intensity"]["ladder"]
    cands = result.candidates[result.candidates["simulated"].astype(bool)]
    for row in cands.head(4).itertuples():
        acc, dt = records[(row.file, row.component)]
        peaks = []
        for factor in ladder:
            summary = simulate(example4, acc, dt, scale=row.ranking_scale * factor).summary
            peaks.append(example4.x_cap_m if summary.overturned else summary.peak_abs_x_m)
        assert row.simulated_response == pytest.approx(np.exp(np.mean(np.log(peaks))), rel=1e-9)
        assert row.ranking_peak_x_m == pytest.approx(peaks[ladder.index(1.0)], rel=1e-9)


def test_confirmation_tables(run: Any, example4: PortalFrame) -> None:
    result, _ = run
    conf = result.confirmation
    chosen = conf[conf["case"] == "chosen-scale"]
    assert (chosen["group"] == "selected").sum() == 6 and (chosen["group"] == "control").sum() == 6
    equal = conf[conf["case"] == "equal-psa-t1"]
    assert len(equal) == (result.candidates["dropped_by"] == "").sum()
    # Controls are the lowest ranked candidates.
    cands = result.candidates[result.candidates["dropped_by"] == ""]
    lowest = cands.sort_values("rank_score_percentile").head(6)
    assert set(chosen.loc[chosen["group"] == "control", "file"]) <= set(lowest["file"])
    # At onset ratio 1 the linear frame just reaches x_c: nothing stays below it.
    assert equal["peak_abs_x_m"].min() >= example4.x_c_m * (1 - 1e-3)
    onset = equal["overturn_onset_ratio"].to_numpy(dtype=float)
    assert np.all((onset[np.isfinite(onset)] >= 0.5) & (onset[np.isfinite(onset)] <= 4.0))
    # Ratio 1 is a scanned level: overturned there ⇒ the lowest overturning ratio is ≤ 1.
    over = equal["overturned"].to_numpy(dtype=bool)
    assert over.any() and np.all(onset[over] <= 1.0 + 1e-12)
    entry = next(
        e
        for e in result.summary["correlations"]
        if e["score"] == "simulated_response" and e["response"] == "peak_drift"
    )
    assert (
        entry["n"] == (result.candidates["dropped_by"] == "").sum()
        and entry["low"] <= entry["spearman"] <= entry["high"]
    )


def test_write_and_read_back(run: Any, tmp_path: Path) -> None:
    result, _ = run
    paths = result.write(tmp_path / "out")
    assert sorted(p.name for p in paths.values()) == sorted(
        [
            "selection.csv",
            "candidates.csv",
            "confirmation.csv",
            "failures.csv",
            "spectra.csv",
            "manifest.csv",
            "columns.csv",
            "selection.json",
        ]
    )
    summary = json.loads(paths["summary"].read_text())
    assert summary["band_rad_s"] == list(result.band_rad_s)
    assert [s["file"] for s in summary["selected"]] == result.selection["file"].tolist()
    back = read_selection(tmp_path / "out")
    assert back.status == result.status and back.message == result.message
    assert back.band_rad_s == result.band_rad_s
    for name in ("selection", "candidates", "confirmation", "failures"):
        mine, theirs = getattr(result, name), getattr(back, name)
        assert list(theirs.columns) == list(mine.columns)
        assert len(theirs) == len(mine)
        assert get_column_dictionary(theirs)["column"].tolist() == list(mine.columns)
    assert np.allclose(back.selection["score"], result.selection["score"], rtol=1e-12)
    assert back.summary["filters"] == result.summary["filters"]


def test_a_rewritten_folder_is_this_runs_alone(
    run: Any, example_inputs: Any, example4: PortalFrame, tmp_path: Path
) -> None:
    """A re-run into the same folder with fewer picks left the earlier run's motions beside a
    manifest of the new ones, and the selection report made of the earlier run ("Selected 10
    of 100" beside a selection of 2)."""
    import pandas as pd

    result, _ = run
    folder = tmp_path / "out"
    result.write(folder)
    (folder / "selection_report.html").write_text("<html>the earlier run</html>")
    (folder / "selection_report_files").mkdir()
    (folder / "selection_report_files" / "numbers.json").write_text("{}")
    earlier = sorted(p.name for p in (folder / "motions").iterdir())
    assert len(earlier) == 2 * len(result.selection) + 1  # AT2, text, and the manifest
    table, records, _ = example_inputs
    options = SelectionOptions(n=2, rank_by="omega_p_over_s_sq", n_bootstrap=0)
    fewer = select_records(table, example4, options, records=records, jobs=1)
    fewer.write(folder)
    manifest = pd.read_csv(folder / "motions" / "manifest.csv")
    listed = {*manifest["at2_file"], *manifest["text_file"], "manifest.csv"}
    assert len(manifest) == 2 and {p.name for p in (folder / "motions").iterdir()} == listed
    assert not (folder / "selection_report.html").exists()
    assert not (folder / "selection_report_files").exists()


def test_too_many_asked_names_each_filter(example_inputs: Any, example4: PortalFrame) -> None:
    table = example_inputs[0]
    options = SelectionOptions(n=80, rank_by="band_coverage", require_plausible=True)
    with pytest.raises(InputError) as error:
        select_records(table, example4, options, jobs=1)
    plausible = int(table["plausible"].astype(bool).sum())
    assert error.value.one_line() == (
        f"n = 80 but only {plausible} candidates left (100 candidates, path → 100, "
        f"vertical → 100, fit_quality → {plausible}), expected n ≤ {plausible}"
    )


def test_default_score_without_records_says_why(example_inputs: Any, example4: PortalFrame) -> None:
    # The default score reads the records; a features table whose files are not at hand fails
    # with one line naming the count, the first failure and what to do.
    table = example_inputs[0]
    with pytest.raises(InputError) as error:
        select_records(table, example4, SelectionOptions(n=3, n_bootstrap=0), jobs=1)
    line = error.value.one_line()
    assert line.startswith(
        "no candidate could be computed (100 candidates, path → 100, vertical → 100, "
        "computed → 0; first failure: RSN"
    )
    assert line.endswith(
        "expected readable records for simulated_response (records= or the files by path), "
        "or rank_by a score of the fit"
    )


@pytest.mark.parametrize("column", ["dt_s", "duration_s", "omega_p_rad_s"])
def test_a_table_without_a_needed_column_says_which(
    column: str, example_inputs: Any, example4: PortalFrame
) -> None:
    """dt_s and duration_s were read by the memory estimate before the columns' check: a
    pandas KeyError instead of the one line every other missing column gets."""
    table = example_inputs[0].drop(columns=[column])
    options = SelectionOptions(n=3, rank_by="band_coverage")
    with pytest.raises(InputError, match=rf"features table lacks columns \['{column}'\]"):
        select_records(table, example4, options, jobs=1)


def test_a_filter_removing_everything(example_inputs: Any, example4: PortalFrame) -> None:
    options = SelectionOptions(n=1, magnitude_min=9.5, rank_by="band_coverage")
    with pytest.raises(InputError, match=r"every candidate was filtered out .*magnitude → 0"):
        select_records(example_inputs[0], example4, options, jobs=1)


def test_options_round_trip_and_validation() -> None:
    options = SelectionOptions(
        n=3,
        exclude=("a", "b"),
        target_periods_s=(0.5, 3.0),
        target_s_ds_g=1.0,
        target_s_d1_g=0.6,
        scale="target-mse",
    )
    assert SelectionOptions.from_dict(options.to_dict()) == options
    scaled = {"n": 2, "scale": "psa-at-t1", "scale_max": 3}
    assert SelectionOptions.from_dict(scaled).scale_max == 3.0
    for bad in (
        {"n": 0},
        {"n": 1, "rank_by": "nope"},
        {"n": 1, "scale": "target-mse"},
        {"n": 1, "target_s_ds_g": 1.0},
        {"n": 1, "scale_min": 2.0},
        {"n": 1, "x_star_fraction": 1.0},
        {"n": 1, "unknown": 1},
    ):
        with pytest.raises(InputError):
            SelectionOptions.from_dict(bad)
    # a typo is named with its nearest option and its key (the workflow points at its line)
    with pytest.raises(
        InputError, match=r"unknown key 'rank_bye' \(did you mean 'rank_by'\?\)"
    ) as caught:
        SelectionOptions.from_dict({"n": 1, "rank_bye": "sa_t1_g"})
    assert caught.value.key == "rank_bye"
    assert math.isclose(SelectionOptions().strong_motion_fraction, 0.3)


def test_records_with_both_components(example_inputs: Any, example4: PortalFrame) -> None:
    table = example_inputs[0]
    options = SelectionOptions(n=3, unit="record", rank_by="omega_p_over_s_sq", n_bootstrap=0)
    result = select_records(table, example4, options, jobs=1)
    chosen = result.selection
    assert len(chosen) == 6
    pairs = chosen.groupby(["event", "station"])["component"].nunique()
    assert len(pairs) == 3 and (pairs == 2).all()
    # Independent: records ranked by the mean percentile of their components.
    passed = result.candidates[result.candidates["dropped_by"] == ""].copy()
    passed["pct"] = passed["omega_p_over_s_sq"].rank(method="average")
    passed["pct"] = (passed["pct"] - 1) / (len(passed) - 1)
    means = passed.groupby(["event", "station"])["pct"].mean().sort_values(ascending=False)
    assert set(pairs.index) == set(means.index[:3])
    # A tier simulates nothing: its intensity states the level, not the simulation's ladder.
    intensity = result.summary["ranking_intensity"]
    assert intensity["ladder"] == [] and "ladder" not in intensity["text"]
    assert intensity["text"] == "the records as they will be used (as recorded)"
    assert "ladder" not in result.message
