"""Catalogue features: one row per component, failures recorded and skipped, parallel = serial."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from stepframe.errors import InputError
from stepframe.records.trace import make_trace
from stepframe.records.units import STANDARD_GRAVITY_M_S2
from stepframe.stochastic.catalog_features import COLUMNS, catalog_features
from stepframe.stochastic.model import GroundMotionModel
from stepframe.stochastic.synthetic import synthetic_motions

TRUE = GroundMotionModel.from_hz(7.43, 3.12, 1.11, 0.096, 0.655, t_max_s=5.0, t_dur_s=20.0)


def _motions(n: int) -> np.ndarray:
    _, acc = synthetic_motions(
        TRUE, duration_s=40.0, dt_s=0.01, n_realisations=n, seed=5, peak_intensity=2.0
    )
    return acc


def _write_fema(path: Path, acc_m_s2: np.ndarray, dt: float) -> None:
    values = acc_m_s2 / STANDARD_GRAVITY_M_S2
    lines = [f"# NPTS= {values.size} DT= {dt} SEC  PGA_g= {np.abs(values).max():.6f}"]
    lines += [" ".join(f"{v:.8E}" for v in values[i : i + 5]) for i in range(0, values.size, 5)]
    path.write_text("\n".join(lines) + "\n")


def test_folder_rows_failures_and_parallel_equals_serial(tmp_path: Path) -> None:
    acc = _motions(3)
    for i, x in enumerate(acc):
        _write_fema(tmp_path / f"rec{i}.txt", x, 0.01)
    # Constant but not zero (read() refuses an all-zero record): fails at "features".
    _write_fema(tmp_path / "flat.txt", np.full(4000, 0.01), 0.01)
    (tmp_path / "junk.txt").write_text("not an accelerogram\n")  # fails at "read"
    (tmp_path / ".hidden").write_text("ignored")
    table, failures = catalog_features(tmp_path, n_jobs=1)
    assert list(table.columns) == list(COLUMNS)
    assert len(table) == 3
    assert sorted(failures["stage"]) == ["features", "read"]
    assert (
        failures.set_index("stage").loc["features", "item"].startswith(str(tmp_path / "flat.txt"))
    )
    assert "all samples equal" in failures.set_index("stage").loc["features", "message"]
    # Same rows in the same order from two processes.
    table2, failures2 = catalog_features(tmp_path, n_jobs=2, chunk_size=1)
    assert table.equals(table2) and failures.equals(failures2)
    # Values: the fitted ω_s of each row is near the truth (one realisation each: loose).
    assert np.all(np.abs(table["omega_s_rad_s"] / TRUE.omega_s_rad_s - 1) < 0.35)
    assert np.all(table["omega_p_rad_s"] >= table["omega_s_rad_s"])
    # max of a fluctuating 2-s RMS over the record: above the envelope's peak 2.0, not far.
    assert np.all(table["max_intensity_m_s2"].between(2.0, 3.2))


def test_a_file_given_twice_is_one_record(tmp_path: Path) -> None:
    """The same bytes under two names (a folder, or a list of files as `select --records`
    gives) are one row, the copy listed once as read (the first in order is kept); a missing
    file in the list is still the reader's failure, not a crash of the grouping."""
    import shutil

    acc = _motions(2)
    for i, x in enumerate(acc):
        _write_fema(tmp_path / f"rec{i}.txt", x, 0.01)
    (tmp_path / "sub").mkdir()
    shutil.copy(tmp_path / "rec0.txt", tmp_path / "sub" / "again.txt")
    table, failures = catalog_features(tmp_path, n_jobs=1)
    assert sorted(table["file"]) == [str(tmp_path / "rec0.txt"), str(tmp_path / "rec1.txt")]
    assert list(failures["item"]) == [str(tmp_path / "sub" / "again.txt")]
    assert list(failures["error_type"]) == ["SameContent"]
    files = [tmp_path / "rec1.txt", tmp_path / "sub" / "again.txt", tmp_path / "rec0.txt"]
    listed, listed_failures = catalog_features([*files, tmp_path / "gone.txt"], n_jobs=1)
    assert list(listed["file"]) == [str(tmp_path / "rec1.txt"), str(tmp_path / "sub" / "again.txt")]
    assert list(listed_failures["item"]) == [str(tmp_path / "rec0.txt"), str(tmp_path / "gone.txt")]
    assert list(listed_failures["stage"]) == ["read", "read"]
    assert listed_failures["message"][0] == (
        f"the same bytes as {tmp_path / 'sub' / 'again.txt'}: read once"
    )


def test_stream_input_and_plausibility(tmp_path: Path) -> None:
    from obspy import Stream

    acc = _motions(2)
    traces = [make_trace(x, 0.01, station="SYN", channel=f"HN{i}") for i, x in enumerate(acc)]
    table, failures = catalog_features(Stream(traces), n_jobs=1, lowest_usable_hz=[0.1, 5.0])
    assert failures.empty
    assert list(table["component"]) == ["HN0", "HN1"]
    # 5 Hz lowest usable frequency puts ω_r ≈ 7 rad/s below the usable band: flagged.
    assert not bool(table["plausible"].iloc[1])
    assert "below usable band" in table["implausible_reason"].iloc[1]


def test_bad_source(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="directory"):
        catalog_features(tmp_path / "missing")
    with pytest.raises(InputError, match="n_jobs"):
        catalog_features(tmp_path, n_jobs=0)


def test_unexpected_errors_are_recorded_not_fatal(monkeypatch: pytest.MonkeyPatch) -> None:
    from obspy import Stream

    import stepframe.stochastic.catalog_features as cf

    def broken_fit(*args: object, **kwargs: object) -> None:
        raise ZeroDivisionError("simulated numerical failure")

    monkeypatch.setattr(cf, "fit_model", broken_fit)
    acc = _motions(2)
    traces = [make_trace(x, 0.01, channel=f"HN{i}") for i, x in enumerate(acc)]
    table, failures = catalog_features(Stream(traces), n_jobs=1)
    assert table.empty and len(failures) == 2
    assert set(failures["stage"]) == {"fit"}
    assert failures["error_type"].iloc[0] == "ZeroDivisionError"
    assert failures["message"].iloc[0] == "simulated numerical failure"
