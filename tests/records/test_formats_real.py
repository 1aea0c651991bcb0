"""Every real file in tests/data/formats read in the right units, header peaks reproduced.

Each stated peak is compared to the data's peak in the header's own units, to half a unit of the
header's last printed digit (the header value is that peak, rounded).
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

from stepframe.records import read
from stepframe.records.units import factor_to_m_s2

FORMATS = Path(__file__).parents[1] / "data" / "formats"

# (file, format, units_in, dt_s, [(channel, npts, stated peak text, header unit)])
CASES = [
    (
        "cosmos/Cosmos12TimeSeriesTest.v1.gz",
        "cosmos",
        "cm/s2",
        0.01,
        [("1", 7000, "161.962", "cm/s2")],
    ),
    (
        "cosmos/us1000hyfh_akbmrp_AKBMR--n.1000hyfh.BNZ.--.acc.V2c.gz",
        "cosmos",
        "cm/s2",
        0.005,
        [("BNZ", 42000, "6.851512", "cm/s2")],
    ),
    (
        "dmg/CE58667.V2.gz",
        "dmg",
        "cm/s2",
        0.01,
        [
            ("H1", 7500, "27.114", "cm/s2"),
            ("Up", 7500, "11.244", "cm/s2"),
            ("H2", 7500, "26.411", "cm/s2"),
        ],
    ),
    (
        "dmg/CICLC.v1.gz",
        "dmg",
        "g",
        0.01,
        [("90", 31932, ".344", "g"), ("360", 32080, ".511", "g"), ("Up", 32190, ".347", "g")],
    ),
    (
        "geonet/20161113_110300_HSES_20.V1A.gz",
        "geonet",
        "mm/s2",
        0.005,
        [
            ("N10E", 65536, "2394.8", "mm/s2"),
            ("N80W", 65536, "2584.4", "mm/s2"),
            ("Up", 65536, "1589.9", "mm/s2"),
        ],
    ),
    (
        "geonet/20180212_211557_WPWS_20.V2A.gz",
        "geonet",
        "mm/s2",
        0.02,
        [
            ("S16W", 5800, "41.6", "mm/s2"),
            ("S74E", 5800, "194.0", "mm/s2"),
            ("Up", 5800, "27.3", "mm/s2"),
        ],
    ),
    (
        "esm/HI.ARS1..HNE.D.20190728.160908.C.ACC.ASC.gz",
        "esm",
        "cm/s2",
        0.005,
        [("HNE", 19128, "0.300022", "cm/s2")],
    ),
    (
        "esm/HI.ARS1..HNN.D.20190728.160908.C.ACC.ASC.gz",
        "esm",
        "cm/s2",
        0.005,
        [("HNN", 19128, "0.359017", "cm/s2")],
    ),
    ("knet/AOM0011801241951.EW.gz", "knet", "gal", 0.01, [("EW", 10200, "4.078", "gal")]),
    ("knet/AOM0011801241951.NS.gz", "knet", "gal", 0.01, [("NS", 10200, "4.954", "gal")]),
    ("knet/AOM0011801241951.UD.gz", "knet", "gal", 0.01, [("UD", 10200, "2.240", "gal")]),
    ("kiknet/NGNH311106302345.EW2.gz", "kiknet", "gal", 0.01, [("EW2", 12000, "0.708", "gal")]),
    ("kiknet/NGNH311106302345.NS2.gz", "kiknet", "gal", 0.01, [("NS2", 12000, "0.618", "gal")]),
    ("kiknet/NGNH311106302345.UD2.gz", "kiknet", "gal", 0.01, [("UD2", 12000, "0.672", "gal")]),
]


def _half_digit(text: str) -> float:
    decimals = len(text.split(".")[1]) if "." in text else 0
    return 0.5 * 10.0**-decimals


@pytest.mark.parametrize(("name", "fmt", "units_in", "dt_s", "channels"), CASES)
def test_header_peaks_reproduced(
    name: str, fmt: str, units_in: str, dt_s: float, channels: list[tuple[str, int, str, str]]
) -> None:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        stream = read(FORMATS / name)
    assert not [w for w in caught if "peak" in str(w.message)]
    assert [t.stats.channel for t in stream] == [c[0] for c in channels]
    for trace, (_, npts, peak_text, unit) in zip(stream, channels, strict=True):
        info = trace.stats.stepframe
        assert (info.format, info.units_in) == (fmt, units_in)
        assert trace.stats.delta == dt_s and trace.stats.npts == npts
        assert info.source_file == str(FORMATS / name)
        peak = np.abs(trace.data).max() / factor_to_m_s2(unit)
        assert abs(peak - float(peak_text)) <= _half_digit(peak_text) * (1 + 1e-9)


def test_nied_mean_removal_recorded() -> None:
    trace = read(FORMATS / "knet/AOM0011801241951.EW.gz")[0]
    steps = trace.stats.stepframe.processing
    assert [s["step"] for s in steps] == ["nied_scale_factor", "remove_mean"]
    assert steps[0]["gal_per_count"] == pytest.approx(3920 / 6182761, rel=1e-15)
    assert abs(trace.data.mean()) < 1e-12
    assert trace.stats.stepframe.magnitude == 6.2


def test_cosmos_v0_counts_use_header_sensitivity() -> None:
    # LSB 0.794729 µV/count (Real(22)) and 1.20 V/g (Real(42), also in the comment lines).
    with pytest.warns(UserWarning, match="offset"):
        stream = read(FORMATS / "cosmos/NP1795-n.305.v0c.gz")
    assert [t.stats.channel for t in stream] == ["HNE", "HNN", "HNZ"]
    factor = 0.794729e-6 / 1.20 * 9.80665
    for trace in stream:
        info = trace.stats.stepframe
        assert info.units_in == "counts" and trace.stats.delta == 0.005
        assert info.processing[0]["factor_m_s2_per_count"] == pytest.approx(factor, rel=1e-15)
    # Real(64) of HNE: peak 985881 counts.
    assert np.abs(stream[0].data).max() / factor == pytest.approx(985881, abs=1e-6)


def test_cosmos_start_time_and_magnitude() -> None:
    trace = read(FORMATS / "cosmos/us1000hyfh_akbmrp_AKBMR--n.1000hyfh.BNZ.--.acc.V2c.gz")[0]
    assert str(trace.stats.starttime) == "2018-11-30T17:29:39.137490Z"
    assert trace.stats.stepframe.magnitude == 7.0
    assert (trace.stats.network, trace.stats.station) == ("AK", "BMR")


def test_geonet_v2a_pad_puts_peak_at_header_time() -> None:
    from obspy import UTCDateTime

    trace = read(FORMATS / "geonet/20180212_211557_WPWS_20.V2A.gz")[0]
    peak_time = trace.stats.starttime + np.argmax(np.abs(trace.data)) * trace.stats.delta
    # Header: "Acceleration: peak -41.6 mm/s/s at 43.68 sec" from 2018-02-12 21:15:54.
    assert peak_time - UTCDateTime(2018, 2, 12, 21, 15, 54) == pytest.approx(43.68, abs=1e-9)


def test_napa_miniseed_with_stationxml() -> None:
    stream = read(
        FORMATS / "miniseed/CE.68150.unprocessed_counts.mseed",
        inventory=FORMATS / "miniseed/CE.68150.stationxml.xml",
    )
    assert [t.stats.channel for t in stream] == ["HNE", "HNN", "HNZ"]
    hne = stream[0]
    assert hne.stats.stepframe.units_in == "counts"
    step = hne.stats.stepframe.processing[0]
    assert step["step"] == "remove_sensitivity"
    assert step["sensitivity_counts_per_m_s2"] == pytest.approx(213744.03778)
    assert round(np.abs(hne.data).max() / 9.80665, 3) == 0.375


def test_miniseed_without_inventory_refused() -> None:
    with pytest.raises(Exception, match="expected --inventory STATIONXML"):
        read(FORMATS / "miniseed/CE.68150.unprocessed_counts.mseed")
