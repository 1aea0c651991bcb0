"""``stepframe stochastic fit`` and ``features``: JSON keys, outputs, one-line errors."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from stepframe.cli import main
from stepframe.records.units import STANDARD_GRAVITY_M_S2
from stepframe.stochastic.model import MODEL_FIELDS, GroundMotionModel
from stepframe.stochastic.synthetic import synthetic_motions

TRUE = GroundMotionModel.from_hz(7.43, 3.12, 1.11, 0.096, 0.655, t_max_s=5.0, t_dur_s=20.0)
KEYS = (*MODEL_FIELDS, "fit_quality")


def _write_fema(path: Path, acc_m_s2: np.ndarray, dt: float) -> None:
    values = acc_m_s2 / STANDARD_GRAVITY_M_S2
    lines = [f"# NPTS= {values.size} DT= {dt} SEC  PGA_g= {np.abs(values).max():.6f}"]
    lines += [" ".join(f"{v:.8E}" for v in values[i : i + 5]) for i in range(0, values.size, 5)]
    path.write_text("\n".join(lines) + "\n")


@pytest.fixture(scope="module")
def record(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("records")
    _, acc = synthetic_motions(TRUE, duration_s=40.0, dt_s=0.01, n_realisations=2, seed=8)
    for i, x in enumerate(acc):
        _write_fema(folder / f"syn{i}.txt", x, 0.01)
    return folder / "syn0.txt"


def test_fit_json_keys_plot_and_netcdf(
    record: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    import xarray as xr

    png, nc = tmp_path / "fit.png", tmp_path / "fit.nc"
    code = main(["stochastic", "fit", str(record), "--json", "--plot", str(png), "--out", str(nc)])
    out = capsys.readouterr().out
    assert code == 0
    (data,) = json.loads(out)  # a list, one object per component
    for key in KEYS:
        assert isinstance(data[key], float)
    for key in (*KEYS[:5], "t_max_s"):  # every fitted value (t_max: the envelope fit)
        assert data[f"{key}_stderr"] > 0
    assert abs(data["omega_s_rad_s"] / TRUE.omega_s_rad_s - 1) < 0.3
    assert data["t0_s"] == 0.0
    assert png.stat().st_size > 10_000 and png.read_bytes()[:4] == b"\x89PNG"
    with xr.open_dataset(nc) as saved:  # xarray's default engine
        psd = saved["psd"]
        assert psd.dims == ("time", "omega")
        assert saved["omega"].attrs["units"] == "rad/s" and saved["time"].attrs["units"] == "s"
        assert psd.attrs["units"] == "(m/s2)2 s/rad"
        assert saved["intensity"].attrs["units"] == "m/s2"
        omega = saved["omega"].values
        assert omega[0] == 0.0 and np.all(np.diff(omega) > 0)  # ω ≥ 0 only
        # Two-sided S on ω ≥ 0: I_g² = (1/π)∫_0^∞ S dω, frame by frame, from the file alone.
        mean_square = np.trapezoid(psd.values, omega, axis=-1) / np.pi
        np.testing.assert_allclose(mean_square, saved["intensity"].values ** 2, rtol=1e-10)
        assert saved.attrs["omega_s_rad_s"] == pytest.approx(data["omega_s_rad_s"])
    assert not list(tmp_path.glob(".*tmp*"))  # nothing half-written left behind


def test_parametric_spectrum_bootstrap_and_chosen_estimator(
    record: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    import xarray as xr

    nc = tmp_path / "para.nc"
    args = ["stochastic", "fit", str(record), "--spectrum", "parametric", "--frequency", "ridge"]
    args += ["--bootstrap", "20", "--seed", "1", "--out", str(nc), "--json"]
    assert main(args) == 0
    (data,) = json.loads(capsys.readouterr().out)
    assert data["frequency_method"] == "ridge"
    for key in KEYS[:5]:
        assert data[f"{key}_bootstrap_stderr"] > 0
    with xr.open_dataset(nc) as saved:
        psd = saved["psd"]
        # The drawn eq. 6.12 spectrum is the model printed (same estimator), and it integrates
        # to the record's I_g² up to the tail beyond Nyquist.
        for key in KEYS[:5]:
            assert psd.attrs[key] == pytest.approx(data[key], rel=1e-12)
        strong = saved["intensity"].values > 0.1 * float(saved["intensity"].max())
        mean_square = np.trapezoid(psd.values, saved["omega"].values, axis=-1) / np.pi
        np.testing.assert_allclose(
            mean_square[strong], saved["intensity"].values[strong] ** 2, rtol=0.03
        )


def test_fit_text_and_options(record: Path, capsys: pytest.CaptureFixture[str]) -> None:
    args = ["stochastic", "fit", str(record), "--frequency", "ridge"]  # --spectrum alone is refused
    assert main(args) == 0
    text = capsys.readouterr().out
    assert "omega_s_rad_s" in text and "±" in text


def test_features_folder_writes_table_and_failures(
    record: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (record.parent / "broken.txt").write_text("# NPTS= 10 DT= 0.01 SEC\n1 2 x\n")
    out = tmp_path / "features.csv"
    code = main(["stochastic", "features", str(record.parent), "-o", str(out), "--json"])
    captured = capsys.readouterr()
    assert code == 0
    summary = json.loads(captured.out)
    assert summary == {
        "table": str(out),
        "columns": str(tmp_path / "features.columns.csv"),
        "failures": str(tmp_path / "features.failures.csv"),
        "n_components": 2,
        "n_plausible": summary["n_plausible"],
        "n_failures": 1,
    }
    table = pd.read_csv(out)
    assert len(table) == 2 and "omega_s_rad_s_stderr" in table.columns
    failures = pd.read_csv(tmp_path / "features.failures.csv")
    assert list(failures["stage"]) == ["read"] and "broken.txt" in failures["item"].iloc[0]
    assert captured.err == ""  # --json: no progress (issue 11, item 5)
    assert main(["stochastic", "features", str(record.parent), "-o", str(out)]) == 0
    assert "features:" in capsys.readouterr().err  # without --json: progress on stderr


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["stochastic", "fit", "MISSING.AT2"], "no such file"),
        (["stochastic", "features", "-o", "x.csv"], "exactly one"),
        (["stochastic", "fit", "REC", "--window-s", "-1"], "not positive"),
        (["stochastic", "fit", "REC", "--out", "/no/such/dir/x.nc"], "output folder"),
        (["stochastic", "features", "DIR", "-o", "/no/such/dir/f.csv"], "output folder"),
    ],
)
def test_errors_are_one_line_exit_2(
    args: list[str], message: str, record: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    names = {"REC": str(record), "DIR": str(record.parent)}
    args = [names.get(a, a) for a in args]
    assert main(args) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("stepframe: error: ") and message in lines[0]


@pytest.mark.parametrize(
    ("values", "message"),
    [
        (np.zeros(3000), "all samples equal 0.0, expected a varying accelerogram"),
        (np.r_[np.sin(np.arange(3000.0)), np.nan], "1 NaN/inf samples (first at sample 3000)"),
    ],
    ids=["all-zero", "nan"],
)
def test_bad_values_name_the_file_once(
    values: np.ndarray, message: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "bad.txt"
    lines = [f"# NPTS= {values.size} DT= 0.01 SEC"]
    lines += [" ".join(f"{v:.8E}" for v in values[i : i + 5]) for i in range(0, values.size, 5)]
    path.write_text("\n".join(lines) + "\n")
    assert main(["stochastic", "fit", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"stepframe: error: {path}: {message}")
    assert err.count(str(path)) == 1 and "\n" not in err


def test_record_too_short_for_window(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    short = tmp_path / "short.txt"
    _write_fema(short, np.sin(np.arange(50.0)), 0.01)
    assert main(["stochastic", "fit", str(short)]) == 2
    err = capsys.readouterr().err
    assert "shorter than the 2.0 s window" in err and str(short) in err


def test_real_record_p_pick(data_dir: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """RSN 8883 (quiet until about 24 s): the AIC pick finds the onset, the fit is plausible."""
    path = data_dir / "peer_nga_west2" / "RSN8883_14383980_13849090.AT2"
    assert main(["stochastic", "fit", str(path), "--t0", "p-pick", "--json"]) == 0
    (data,) = json.loads(capsys.readouterr().out)
    assert 22.0 < data["p_onset_s"] < 26.0
    assert data["p_onset_s"] < data["s_arrival_s"] < data["p_onset_s"] + data["t_max_s"] + 1.0
    assert data["t0_s"] == data["p_onset_s"]
    assert data["omega_p_rad_s"] >= data["omega_s_rad_s"] >= data["omega_r_rad_s"]
    assert data["omega_p_rad_s"] < 0.5 * np.pi / 0.005


def test_dt_too_coarse_for_requested_band(record: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # dt = 0.01 s: Nyquist 314 rad/s, below the 400 rad/s asked for.
    assert main(["stochastic", "fit", str(record), "--omega-max-rad-s", "400"]) == 2
    err = capsys.readouterr().err
    assert "Nyquist" in err and str(record) in err


def test_corner_option(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """--corner on a record high-passed at ω_c = 4 rad/s: the documented low-biased estimate."""
    from scipy import signal

    omega_c = 4.0
    _, acc = synthetic_motions(TRUE, duration_s=40.0, dt_s=0.01, seed=8)
    b, a = signal.bilinear([1.0, 0.0, 0.0], [1.0, 2 * omega_c, omega_c**2], fs=100.0)
    path = tmp_path / "high_passed.txt"
    _write_fema(path, signal.lfilter(b, a, acc[0]), 0.01)
    assert main(["stochastic", "fit", str(path), "--corner", "--json"]) == 0
    (data,) = json.loads(capsys.readouterr().out)
    assert 0.4 * omega_c < data["omega_c_rad_s"] < 1.05 * omega_c
    assert 0 < data["omega_c_rad_s_stderr"] < data["omega_c_rad_s"]


@pytest.mark.parametrize(
    ("options", "message"),
    [
        (["--spectrum", "wavelet"], "--spectrum wavelet without --plot or --out"),
        (["--seed", "3"], "--seed 3 without --bootstrap"),
        (["--bootstrap", "1"], "--bootstrap 1, expected 0 (none) or at least 2"),
        (["--plot", "DIR.png"], "--plot target is a directory, expected a file name"),
        (["--out", "DIR.nc"], "output target is a directory, expected a file name"),
    ],
)
def test_fit_options_that_would_do_nothing_are_refused_before_the_work(
    record: Path,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    options: list[str],
    message: str,
) -> None:
    """Each ran the fit and ignored the option (or printed 'bootstrap ± nan', or failed at
    the end naming a hidden temporary file)."""
    (tmp_path / "DIR.png").mkdir()
    (tmp_path / "DIR.nc").mkdir()
    options = [str(tmp_path / o) if o.startswith("DIR") else o for o in options]
    assert main(["stochastic", "fit", str(record), *options]) == 2
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert captured.out == "" and len(lines) == 1 and message in lines[0]
