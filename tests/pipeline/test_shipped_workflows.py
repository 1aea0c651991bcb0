"""Every shipped workflow (stepframe/workflows/) runs and produces its outputs (from a copy)."""

from __future__ import annotations

import json
import math
import shutil
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import xarray as xr

from stepframe.pipeline.engine.shipped import SHIPPED_DIR
from stepframe.pipeline.stages import shipped_stages

from .conftest import run_json, stepframe

WORKFLOWS = SHIPPED_DIR


@pytest.fixture
def copy(tmp_path: Path) -> Path:
    """The shipped workflows copied (without any workspace), as ``stepframe run NAME --copy``."""
    target = tmp_path / "workflows"
    shutil.copytree(WORKFLOWS, target, ignore=shutil.ignore_patterns("stepframe-work"))
    return target


def test_every_shipped_workflow_is_tested() -> None:
    shipped = sorted(p.name for p in WORKFLOWS.glob("*.toml"))
    assert shipped == [
        "ida.toml",
        "inbox.toml",  # tests/pipeline/test_scheduling.py
        "selection.toml",  # stepframe demo: tests/test_cli.py
        "site-amplification-records.toml",
        "site-amplification.toml",
    ]


def test_site_amplification_from_the_papers_parameters(copy: Path) -> None:
    report = run_json(str(copy / "site-amplification.toml"), cwd=copy.parent)
    # no records read
    assert [s["name"] for s in report["stages"]] == [
        "site",
        "amplification",
        "amplification_report",
    ]
    outputs = copy / "stepframe-work" / "outputs"
    site = pd.read_parquet(outputs / "site_model.parquet").iloc[0]
    assert site["omega_p_rad_s"] == pytest.approx(2 * math.pi * 7.43, rel=1e-15)
    assert site["alpha_reading"] == "paper"
    stored = json.loads((outputs / "site_model.json").read_text())
    assert stored["ground_motion_model"]["omega_s_rad_s"] == site["omega_s_rad_s"]
    curve = xr.open_dataset(outputs / "amplification.nc", engine="h5netcdf")
    f = curve["frequency"].values
    assert f[0] == pytest.approx(0.1) and f[-1] == pytest.approx(10.0) and f.size == 60
    # eq. 6.19, last approximation: the paper's "5.67" for this site
    assert curve.attrs["approx_eq_6_19_last"] == pytest.approx((7.43 / 3.12) ** 2, rel=1e-14)
    assert round(curve.attrs["approx_eq_6_19_last"], 2) == 5.67
    assert curve.attrs["approx_eq_6_19_first"] == pytest.approx(
        (7.43 * 0.096) / (1.11 * 0.655) * (7.43 / 3.12) ** 2, rel=1e-14
    )
    # eq. 6.18 as printed, recomputed here in Hz (2π cancels), α_g(t_max) = ω_r ξ_r
    fp, fs, fr, xp, xr_ = 7.43, 3.12, 1.11, 0.096, 0.655
    printed = (
        ((f**2 - fp**2) ** 2 + 4 * (fp * xp) ** 2 * f**2)
        / (4 * (fr * xr_) * (fp * xp) * fp**2)
        * (f / fs) ** 2
    )
    np.testing.assert_allclose(curve["spectral_ratio_eq_6_18"].values, printed, rtol=1e-12)
    # the response amplification at one frequency equals `stepframe stochastic amplify`'s
    k = 40
    done = stepframe(
        "stochastic", "amplify", "--fp-hz", "7.43", "--fs-hz", "3.12", "--fr-hz", "1.11",
        "--xi-p", "0.096", "--xi-r", "0.655", "--t-max-s", "5", "--t-dur-s", "20",
        "--f0-hz", repr(float(f[k])), "--alpha-at-tmax", "paper", "--json",
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    single = json.loads(done.stdout)
    assert curve["response_amplification_vs_fixed"].values[k] == pytest.approx(
        single["response_amplification_vs_fixed"], rel=1e-12
    )
    table = pd.read_csv(outputs / "amplification.csv")
    np.testing.assert_allclose(table["spectral_ratio_eq_6_18"], printed, rtol=1e-12)
    # the report stage shows the same site and eq. 6.19 numbers as the curve
    assert (outputs / "amplification_report.html").stat().st_size > 0
    numbers = json.loads((outputs / "amplification_report_files" / "numbers.json").read_text())
    assert numbers["ground_motion_model"]["omega_p_rad_s"] == site["omega_p_rad_s"]
    assert numbers["approx_eq_6_19_last"] == pytest.approx(
        curve.attrs["approx_eq_6_19_last"], rel=1e-14
    )
    assert numbers["approx_eq_6_19_first"] == pytest.approx(
        curve.attrs["approx_eq_6_19_first"], rel=1e-14
    )
    curve.close()


@pytest.mark.slow
def test_site_amplification_from_records(copy: Path) -> None:
    report = run_json(str(copy / "site-amplification-records.toml"), cwd=copy.parent)
    names = [s["name"] for s in report["stages"]]
    assert names == ["inventory", "features", "site", "amplification"]
    assert report["stages"][1]["items"] == 100
    outputs = copy / "stepframe-work" / "outputs"
    features = pd.read_parquet(outputs / "features.parquet")
    plausible = features[features["plausible"]]
    site = pd.read_parquet(outputs / "site_model.parquet").iloc[0]
    assert site["n_components"] == len(plausible) > 0
    for name in ("omega_p_rad_s", "omega_s_rad_s", "omega_r_rad_s", "xi_p", "xi_r", "t_dur_s"):
        assert site[name] == pytest.approx(float(np.median(plausible[name])), rel=1e-14)
    assert (outputs / "amplification.nc").is_file()


def test_selection_workflow_is_the_demo(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """``stepframe run selection`` plans what ``stepframe demo`` runs (tests/test_cli.py runs it):
    the demo's settings (10 components, confirmation) are the shipped file's."""
    from stepframe.pipeline.engine.runner import run_workflow
    from stepframe.pipeline.engine.workflow import load_workflow
    from stepframe.pipeline.selection.stage import _selection_options

    monkeypatch.chdir(tmp_path)
    report = run_workflow("selection", shipped_stages(), dry_run=True)
    assert [s.name for s in report.stages] == [
        "inventory",
        "features",
        "responses",
        "selection",
        "selection_report",
    ]
    assert report.workspace == "stepframe-work"  # the current folder's, not the package's
    options = _selection_options(load_workflow(WORKFLOWS / "selection.toml", shipped_stages()))
    assert (options.n, options.confirm) == (10, True)
    assert list(tmp_path.iterdir()) == []  # a dry run writes nothing


@pytest.mark.slow
def test_ida_workflow(copy: Path) -> None:
    """Each record's traced bracket holds when the simulator is run at its two ends."""
    from stepframe.records.examples import fema_p695
    from stepframe.structure.frame_file import read_frame_file
    from stepframe.structure.simulator import simulate

    report = run_json(str(copy / "ida.toml"), cwd=copy.parent)
    assert [s["name"] for s in report["stages"]] == ["inventory", "ida"]
    outputs = copy / "stepframe-work" / "outputs"
    table = pd.read_parquet(outputs / "ida.parquet")
    summary = json.loads((outputs / "ida_summary.json").read_text())
    assert len(table) == summary["n_records"] == 100
    assert summary["n_resurrected"] == int(table["resurrected"].sum())
    found = table["first_overturning"].dropna()
    assert summary["first_overturning_pga_g_fractiles"]["q0.5"] == pytest.approx(
        float(np.quantile(found, 0.5)), rel=1e-12
    )
    frame = read_frame_file(copy / "frames" / "example-4.toml")
    stream, _ = fema_p695()
    for row in (
        table.dropna(subset=["first_overturning", "last_survival_below"]).head(5).itertuples()
    ):
        trace = next(t for t in stream if row.item.endswith(f"[{t.stats.channel}]"))
        pga_g = float(np.max(np.abs(trace.data))) / 9.80665
        at = {
            level: simulate(
                frame, trace.data, trace.stats.delta, scale=level / pga_g, tail_s=10.0
            ).summary.overturned
            for level in (row.first_overturning, row.last_survival_below)
        }
        assert at == {row.first_overturning: True, row.last_survival_below: False}
