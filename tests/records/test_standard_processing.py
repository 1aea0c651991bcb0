"""Intensity measures of raw counts: the stated standard processing, checked against obspy's own
detrend/taper/filter chain computed independently (CE.68150 MiniSEED + StationXML)."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import cumulative_trapezoid

from stepframe.records import read
from stepframe.records.intensity import ProcessingWarning, trace_intensity_measures
from stepframe.records.processing import bandpass, needs_standard_processing

DATA = Path(__file__).resolve().parents[1] / "data" / "formats" / "miniseed"
MSEED = DATA / "CE.68150.unprocessed_counts.mseed"
XML = DATA / "CE.68150.stationxml.xml"


def _obspy_chain() -> dict[str, dict[str, float]]:
    """PGA, PGV, PGD by obspy alone: sensitivity removed, demean, linear detrend, 5 % Hann
    taper, 4-corner zero-phase Butterworth high-pass at 0.1 Hz; trapezoidal integration."""
    import obspy

    stream = obspy.read(str(MSEED))
    stream.remove_sensitivity(obspy.read_inventory(str(XML)))
    out = {}
    for trace in stream:
        trace.data = trace.data.astype(np.float64)
        trace.detrend("demean")
        trace.detrend("linear")
        trace.taper(max_percentage=0.05, type="hann")
        trace.filter("highpass", freq=0.1, corners=4, zerophase=True)
        dt = trace.stats.delta
        vel = cumulative_trapezoid(trace.data, dx=dt, initial=0.0)
        disp = cumulative_trapezoid(vel, dx=dt, initial=0.0)
        out[trace.id] = {
            "pga_m_s2": float(np.abs(trace.data).max()),
            "pgv_m_s": float(np.abs(vel).max()),
            "pgd_m": float(np.abs(disp).max()),
        }
    return out


def test_raw_counts_are_processed_before_intensity_measures_as_obspy_does() -> None:
    stream = read(MSEED, inventory=XML)
    reference = _obspy_chain()
    assert len(stream) == 3
    for trace in stream:
        assert needs_standard_processing(trace)
        with pytest.warns(ProcessingWarning, match="high-pass at 0.1 Hz"):
            measures = trace_intensity_measures(trace)
        ref = reference[trace.id]
        # obspy's zero-phase filter runs forward-backward without padding, scipy's sosfiltfilt
        # pads: the two differ at the tapered ends only.
        assert measures["pga_m_s2"] == pytest.approx(ref["pga_m_s2"], rel=0.01)
        assert measures["pgv_m_s"] == pytest.approx(ref["pgv_m_s"], rel=0.02)
        assert measures["pgd_m"] == pytest.approx(ref["pgd_m"], rel=0.05)
        assert measures["pgv_m_s"] < 1.0 and measures["pgd_m"] < 0.5  # not the raw 37 m/s, 2 km
        assert len(trace.stats.stepframe.processing) == 1  # the caller's record is untouched


def test_high_passed_or_calibrated_records_are_measured_as_they_are() -> None:
    trace = read(MSEED, inventory=XML)[0]
    bandpass(trace, 0.05, None)
    assert not needs_standard_processing(trace)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ProcessingWarning)
        trace_intensity_measures(trace)


def test_every_output_of_a_counts_record_is_of_the_processed_copy(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """records spectrum and records catalog used the record as read (the sensor's offset
    dominated PSA(10 s): 0.059 g on HNN) while records info measured it processed; each now
    gives the PSA of the standard-processed copy, computed here with obspy's own chain."""
    import json
    import shutil

    from obspy import read as obspy_read
    from obspy import read_inventory

    from stepframe.cli import main
    from stepframe.records.spectra import response_spectrum

    expected_trace = obspy_read(str(MSEED)).select(channel="HNN")[0]
    expected_trace.remove_sensitivity(read_inventory(str(XML)))
    expected_trace.detrend("demean")
    expected_trace.detrend("linear")
    expected_trace.taper(0.05, "hann")
    expected_trace.filter("highpass", freq=0.1, corners=4, zerophase=True)
    periods = [1.0, 3.0, 10.0]
    expected = response_spectrum(expected_trace.data, 0.005, periods, 0.05).psa_g
    args = [str(MSEED), "--inventory", str(XML), "--periods-s", "1,3,10", "--json"]
    assert main(["records", "spectrum", *args]) == 0
    data = json.loads(capsys.readouterr().out)
    psa = next(c["psa_g"] for c in data["components"] if c["component"] == "HNN")
    # obspy filters without padding, scipy pads: the ends differ (module docstring)
    np.testing.assert_allclose(psa, expected, rtol=0.05)
    assert psa[2] < 0.01  # 0.0588 g as read

    folder = tmp_path / "in"
    folder.mkdir()
    shutil.copyfile(MSEED, folder / MSEED.name)
    out = tmp_path / "cat.csv"
    assert main(["records", "catalog", str(folder), "-o", str(out), "--inventory",
                 str(XML), "--json"]) == 0  # fmt: skip
    import pandas as pd

    row = pd.read_csv(out).set_index("component").loc["HNN"]
    # the catalogue's PSA columns are of the copy its PGA is measured on (was: as read)
    assert row["psa_1s_g"] == pytest.approx(psa[0], rel=1e-9)
    assert row["pga_g"] == pytest.approx(np.max(np.abs(expected_trace.data)) / 9.80665, rel=0.01)


def test_each_catalogue_row_has_its_own_components_warnings(tmp_path: Path) -> None:
    """A three-channel file's rows each repeated all three channels' processing warnings; a
    row has those that name it (and those that name no channel of the file)."""
    import shutil

    from stepframe.records.catalog import catalog

    folder = tmp_path / "records"
    folder.mkdir()
    shutil.copy(MSEED, folder / MSEED.name)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        table, failures = catalog(folder, inventory=XML)
    assert failures.empty and len(table) == 3
    for row in table.itertuples():
        own = f"CE.68150..{row.component}: made from raw counts"
        assert own in row.warnings
        others = [c for c in table["component"] if c != row.component]
        assert not any(f"CE.68150..{c}:" in row.warnings for c in others)


def test_a_selection_ranks_and_writes_out_raw_counts_after_the_standard_processing() -> None:
    """A COSMOS V0 record (raw counts, a header calibration) as read is a constant -0.89 g of
    sensor offset: a selection over a folder holding it ranked it first and wrote it out as a
    chosen motion. Its samples, for the ranking (record pass) and the motions (read_samples),
    are now the standard-processed record every other output measures."""
    import pandas as pd

    from stepframe.pipeline.selection import record_pass
    from stepframe.pipeline.selection.samples import read_samples
    from stepframe.records.io import read_measured
    from stepframe.records.processing import measured, standard_processing

    v0 = Path(__file__).resolve().parents[1] / "data" / "formats" / "cosmos" / "NP1795-n.305.v0c.gz"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        raw = read(v0)
        processed = read_measured(v0)
        table = pd.DataFrame({"file": [str(v0)], "component": [raw[0].stats.channel]})
        samples, failures = read_samples(table, np.array([0]), None, None)
        ranked = record_pass.read_samples(str(v0), raw[0].stats.channel, {}, {})
    assert abs(raw[0].data.mean()) > 1.0  # m/s²: the offset, as read
    expected = standard_processing(raw[0].copy()).data
    np.testing.assert_array_equal(processed[0].data, expected)
    assert failures == [] and np.array_equal(samples[0][0], expected)
    assert np.array_equal(ranked[0], expected)
    assert abs(expected.mean()) < 1e-3 * expected.std()
    assert measured(processed[0]) is processed[0]  # high-passed: not processed twice
