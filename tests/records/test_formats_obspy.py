"""Formats read through obspy: SAC and Kinemetrics EVT on obspy's own real test files."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from stepframe.errors import FormatError, InputError
from stepframe.records import read

FORMATS = Path(__file__).parents[1] / "data" / "formats"
EVT = FORMATS / "kinemetrics" / "BI008_MEMA-04823.evt"
SAC_UNKNOWN = FORMATS / "sac" / "test.sac"
SAC_VOLTS = FORMATS / "sac" / "seism.sac"


def test_evt_counts_calibrated_from_header() -> None:
    import obspy

    stream = read(EVT)
    assert [t.stats.channel for t in stream] == ["0", "1", "2"]
    raw = obspy.read(str(EVT), format="KINEMETRICS_EVT")
    # obspy's own calibration divides by 9.81 (its comment: "mean value of g"); ours uses
    # standard gravity, so the two differ by exactly 9.80665/9.81.
    calibrated = obspy.read(str(EVT), format="KINEMETRICS_EVT", apply_calib=True)
    for ours, counts, theirs in zip(stream, raw, calibrated, strict=True):
        assert ours.stats.stepframe.units_in == "counts"
        assert ours.stats.delta == 0.004 and ours.stats.npts == 5750
        np.testing.assert_allclose(ours.data, theirs.data * 9.80665 / 9.81, rtol=1e-6)
        step = ours.stats.stepframe.processing[0]
        header = counts.stats.kinemetrics_evt
        assert header.a2dbits == 24 and header.chan_fullscale == 2.5
        expected = header.chan_fullscale / 2**23 / header.chan_sensitivity * 9.80665
        assert step["factor_m_s2_per_count"] == expected
        np.testing.assert_allclose(ours.data, counts.data * expected, rtol=1e-15)
    # Header peaks of channel 0 in counts: max -19494, min -22142.
    counts0 = stream[0].data / stream[0].stats.stepframe.processing[0]["factor_m_s2_per_count"]
    assert (round(counts0.max()), round(counts0.min())) == (-19494, -22142)


def test_sac_without_units_refused_with_how() -> None:
    with pytest.raises(FormatError, match=r"expected --inventory STATIONXML .* or --units"):
        read(SAC_UNKNOWN)


def test_sac_with_units() -> None:
    import obspy

    stream = read(SAC_UNKNOWN, units="cm/s2")
    reference = obspy.read(str(SAC_UNKNOWN), format="SAC")[0]
    assert stream[0].stats.stepframe.units_in == "cm/s2"
    assert stream[0].stats.stepframe.format == "sac"
    np.testing.assert_array_equal(stream[0].data, reference.data.astype(np.float64) * 0.01)
    assert stream[0].stats.delta == reference.stats.delta


def test_sac_volts_refused() -> None:
    with pytest.raises(FormatError, match="idep says volts, expected acceleration"):
        read(SAC_VOLTS)
    with pytest.raises(FormatError, match="volts"):
        read(SAC_VOLTS, units="g")


def test_sac_iacc_is_nm_s2(tmp_path: Path) -> None:
    import obspy

    trace = obspy.read(str(SAC_UNKNOWN), format="SAC")[0]
    trace.stats.sac.idep = 8
    path = tmp_path / "acc.sac"
    trace.write(str(path), format="SAC")
    record = read(path)[0]
    assert record.stats.stepframe.units_in == "nm/s2"
    np.testing.assert_allclose(record.data, trace.data * 1e-9, rtol=1e-7)
    with pytest.raises(FormatError, match="expected them to agree"):
        read(path, units="g")


def test_unknown_obspy_name_and_pickle_refused(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="unknown format 'nosuch'"):
        read(SAC_UNKNOWN, format="nosuch")
    with pytest.raises(InputError, match="unknown format 'pickle'"):
        read(SAC_UNKNOWN, format="pickle")


def test_obspy_name_outside_registry_list() -> None:
    # Any obspy waveform name works, registered or not; here SAC under its own name.
    assert read(SAC_UNKNOWN, format="SAC", units="g")[0].stats.npts == 100


def test_inventory_errors(tmp_path: Path) -> None:
    mseed = FORMATS / "miniseed" / "CE.68150.unprocessed_counts.mseed"
    bad = tmp_path / "bad.xml"
    bad.write_text("<not stationxml/>")
    with pytest.raises(InputError, match="not a readable StationXML"):
        read(mseed, inventory=bad)
    with pytest.raises(InputError, match="no such inventory file"):
        read(mseed, inventory=tmp_path / "missing.xml")
    with pytest.raises(InputError, match="no response for"):
        read(SAC_UNKNOWN, inventory=FORMATS / "miniseed" / "CE.68150.stationxml.xml")


def test_velocity_seismometer_response_removed_to_acceleration(tmp_path: Path) -> None:
    """A broadband velocity channel (obspy's example BW.RJOB..EHZ, STS-2) read with its StationXML.

    Independent check: inside the band where the STS-2 is flat in velocity (0.5-5 Hz, gain within
    1 % of the sensitivity), the acceleration must equal the time derivative of counts divided by
    the scalar sensitivity, without any pole-zero deconvolution.
    """
    import obspy
    from scipy import signal

    example = obspy.read().select(channel="EHZ")  # obspy's bundled example data
    mseed = tmp_path / "rjob.mseed"
    stationxml = tmp_path / "rjob.xml"
    example.write(str(mseed), format="MSEED")
    obspy.read_inventory().write(str(stationxml), format="STATIONXML")

    trace = read(mseed, inventory=stationxml)[0]
    assert trace.stats.stepframe.units_in == "counts"
    step = trace.stats.stepframe.processing[0]
    assert step["step"] == "remove_response" and step["output"] == "ACC"
    assert step["input_units"] == "M/S"

    counts = np.asarray(example[0].data, dtype=np.float64)
    dt = example[0].stats.delta
    velocity = (counts - counts.mean()) / 2.5168e9  # sensitivity from the StationXML [counts/(m/s)]
    by_derivative = np.gradient(velocity, dt)
    band = signal.butter(4, [0.5, 5.0], btype="bandpass", fs=1.0 / dt, output="sos")
    ours = signal.sosfiltfilt(band, trace.data)
    reference = signal.sosfiltfilt(band, by_derivative)
    middle = slice(300, -300)  # away from the taper and filter edges
    rms_ratio = np.sqrt(np.mean(ours[middle] ** 2) / np.mean(reference[middle] ** 2))
    assert rms_ratio == pytest.approx(1.0, abs=0.02)  # measured 1.003
    assert np.corrcoef(ours[middle], reference[middle])[0, 1] > 0.99  # measured 0.995


def test_a_binary_file_obspy_guesses_as_win_is_not_called_a_win_file(tmp_path: Path) -> None:
    # obspy's WIN check takes bytes 0, 1, 2, ... for WIN; the message blamed a WIN file that
    # never was ("obspy could not read it as win"). A guess says it was one; a format the user
    # named keeps the reader's own message.
    junk = tmp_path / "a.bin"
    junk.write_bytes(bytes(range(256)) * 8)
    with pytest.raises(FormatError) as guessed:
        read(junk)
    assert guessed.value.what.startswith(
        "obspy's check took it for WIN but its reader failed ([Errno 22] Invalid argument): a "
        "damaged WIN file, or no record, expected FEMA P695 text, "
    )
    assert guessed.value.what.endswith("(give it with --format)")
    with pytest.raises(FormatError) as named:
        read(junk, format="win")
    assert named.value.what == "obspy could not read it as win: [Errno 22] Invalid argument"
