"""Every result the pipeline stores comes back equal: write, read back, compare."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import xarray as xr

from stepframe.core.results import get_column_dictionary
from stepframe.core.tables import read_table, write_table
from stepframe.pipeline.amplification.amplify import amplification_curve, read_curve, write_curve
from stepframe.pipeline.amplification.site import (
    SiteModel,
    read_site_model,
    site_from_parameters,
    site_from_record,
    write_site_model,
)
from stepframe.pipeline.catalogue.fitted import (
    FitOptions,
    fit_records,
    fit_table,
    fitted_dataset,
    read_fitted,
    record_spectrum,
    write_features,
    write_fitted,
)
from stepframe.pipeline.dynamics.design import (
    design_case,
    read_design_result,
    run_design,
    write_design_result,
)
from stepframe.records.trace import make_trace
from stepframe.stochastic.catalog_features import catalog_features
from stepframe.stochastic.model import GroundMotionModel
from stepframe.stochastic.synthetic import synthetic_motions

TRUE = GroundMotionModel.from_hz(7.43, 3.12, 1.11, 0.096, 0.655, t_max_s=5.0, t_dur_s=20.0)


@pytest.fixture(scope="module")
def traces() -> list:  # type: ignore[type-arg]  # obspy traces (obspy ships no types)
    _, acc = synthetic_motions(
        TRUE, duration_s=40.0, dt_s=0.01, n_realisations=2, seed=3, peak_intensity=2.0
    )
    return [make_trace(x, 0.01, station="SYN", channel=f"HN{i}") for i, x in enumerate(acc)]


def _only_files(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir())


def test_features_table_round_trip(traces: list, tmp_path: Path) -> None:  # type: ignore[type-arg]
    from obspy import Stream

    table, failures = catalog_features(Stream(traces), n_jobs=1)
    assert len(table) == 2 and failures.empty
    paths = write_features(table, failures, tmp_path / "features.csv")
    assert [p.name for p in paths] == ["features.csv", "features.failures.csv"]
    back = read_table(tmp_path / "features.csv")
    pd.testing.assert_frame_equal(back, table)
    dictionary = get_column_dictionary(back)
    assert dictionary.set_index("column").loc["omega_s_rad_s", "unit"] == "rad/s"
    assert list(pd.read_csv(paths[1]).columns) == ["item", "stage", "error_type", "message"]
    assert _only_files(tmp_path) == [
        "features.columns.csv",
        "features.csv",
        "features.failures.csv",
    ]


def test_fit_table_round_trip(traces: list, tmp_path: Path) -> None:  # type: ignore[type-arg]
    records = fit_records(traces, FitOptions(corner=True), file="syn.mseed")
    table = fit_table(records)
    assert list(table["component"]) == ["HN0", "HN1"]
    assert table["omega_s_rad_s"].iloc[0] == records[0].summary["omega_s_rad_s"]
    write_table(table, tmp_path / "fit.csv")
    pd.testing.assert_frame_equal(read_table(tmp_path / "fit.csv"), table)


def test_fitted_netcdf_round_trip(traces: list, tmp_path: Path) -> None:  # type: ignore[type-arg]
    record = fit_records(traces[:1], FitOptions(), file="syn.mseed")[0]
    dataset = fitted_dataset(record_spectrum(traces[0], record, "stft"), record)
    write_fitted(dataset, tmp_path / "fit.nc")
    back = read_fitted(tmp_path / "fit.nc")
    xr.testing.assert_identical(back, dataset)
    assert back.attrs["omega_s_rad_s"] == record.summary["omega_s_rad_s"]
    assert _only_files(tmp_path) == ["fit.nc"]


def test_site_model_round_trip(traces: list, tmp_path: Path) -> None:  # type: ignore[type-arg]
    given = site_from_parameters(
        7.43, 3.12, 1.11, 0.096, 0.655, t_max_s=5.0, t_dur_s=20.0, alpha_reading="paper"
    )
    assert given.model.omega_p_rad_s == pytest.approx(2 * math.pi * 7.43, rel=1e-15)
    fitted = site_from_record(traces[0], name="syn.mseed")
    assert fitted.source["record"] == "syn.mseed" and fitted.peak_intensity_m_s2 > 1.0
    for index, site in enumerate((given, fitted)):
        path = write_site_model(site, tmp_path / f"site{index}.json")
        back = read_site_model(path)
        assert back == site
        assert isinstance(back, SiteModel)
        assert json.loads(path.read_text())["ground_motion_model"] == site.model.to_dict()


def test_amplification_curve_round_trip(tmp_path: Path) -> None:
    site = site_from_parameters(7.43, 3.12, 1.11, 0.096, 0.655, t_max_s=5.0, t_dur_s=20.0)
    frequencies = np.array([0.5, 2.0, 7.43])
    curve = amplification_curve(site, frequencies, 0.05, n_steps=600)
    assert curve["frequency"].attrs["units"] == "Hz"
    # eq. 6.19's last approximation is (ω_p/ω_s)², the paper's 5.67 for its site
    assert curve.attrs["approx_eq_6_19_last"] == pytest.approx((7.43 / 3.12) ** 2, rel=1e-12)
    assert np.all(curve["response_amplification_vs_fixed"].values > 0)
    write_curve(curve, tmp_path / "curve.nc")
    xr.testing.assert_identical(read_curve(tmp_path / "curve.nc"), curve)


def test_design_result_round_trip(tmp_path: Path) -> None:
    overrides = {
        "weight_super_n": 1.472e6, "weight_col_n": 0.0, "weight_total_n": 2.807e6,
        "footing_length_m": 8.839, "block_width_m": 1.166, "height_m": 29.944,
        "s_ds_g": 1.038, "s_d1_g": 0.456, "beta": 0.8,
    }  # fmt: skip
    run = run_design(design_case(None, overrides, delta0_m=[0.00254, 0.3048]))
    assert run.status == "ok" and run.design.delta_m is not None
    path = write_design_result(run, tmp_path / "design.json")
    back = read_design_result(path)
    assert back == json.loads(json.dumps(run.to_dict()))
    assert back["design"]["delta_m"] == run.design.delta_m
    assert [t["status"] for t in back["iterations"]] == [t.status for t in run.traces]
