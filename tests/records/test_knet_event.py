"""K-NET/KiK-net headers give the event (origin time) and the epicentral distance."""

from __future__ import annotations

import math
from pathlib import Path

from stepframe.records import read


def _haversine_km(lat1: float, lon1: float, lat2: float, lon2: float) -> float:
    """Great-circle distance on a sphere of the mean Earth radius 6371.0 km."""
    p1, p2 = math.radians(lat1), math.radians(lat2)
    dp, dl = p2 - p1, math.radians(lon2 - lon1)
    h = math.sin(dp / 2) ** 2 + math.cos(p1) * math.cos(p2) * math.sin(dl / 2) ** 2
    return 2 * 6371.0 * math.asin(math.sqrt(h))


def test_knet_event_is_the_origin_time_and_distance_from_coordinates(data_dir: Path) -> None:
    # AOM0011801241951.EW: Origin Time 2018/01/24 19:51:00 JST = 10:51:00 UTC, event at
    # (41.0, 142.5), station at (41.5267, 140.9244)
    (trace,) = read(data_dir / "formats" / "knet" / "AOM0011801241951.EW.gz")
    info = trace.stats.stepframe
    assert info.event == "2018-01-24T10:51:00"
    sphere = _haversine_km(41.0, 142.5, 41.5267, 140.9244)
    # the ellipsoid and the sphere differ by well under 0.5 % at this distance
    assert abs(info.repi_km / sphere - 1) < 5e-3
    assert 140 < info.repi_km < 145


def test_kiknet_components_share_the_event(data_dir: Path) -> None:
    folder = data_dir / "formats" / "kiknet"
    events = {read(f)[0].stats.stepframe.event for f in sorted(folder.glob("NGNH31*"))}
    assert events == {"2011-06-30T14:45:00"}
