"""Records, not files: components grouped across files; verticals; the grouping reported."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import pytest

from stepframe.pipeline.selection.grouping import (
    group_records,
    grouping_line,
    grouping_summary,
)
from stepframe.pipeline.selection.inputs import header_table, join_headers
from stepframe.records.channels import is_vertical


@pytest.mark.parametrize(
    "channel",
    ["HNZ", "BHZ", "UD", "UD1", "UD2", "UP", "H-UP", "DWN", "V", "Z", "RIO-UP", "vert", "Down"],
)
def test_verticals(channel: str) -> None:
    assert is_vertical(channel)


@pytest.mark.parametrize(
    "channel",
    ["HNE", "HN1", "HN2", "EW", "NS2", "090", "360", "H-E11230", "CLW-TR", "ABBAR--T", "E", "N"],
)
def test_horizontals(channel: str) -> None:
    assert not is_vertical(channel)


def _table(rows: list[tuple[str, str, str, str]]) -> pd.DataFrame:
    return pd.DataFrame(rows, columns=["file", "component", "station", "event"])


def test_peer_and_nied_files_pair_across_files() -> None:
    table = _table(
        [
            ("a/RSN8883_14383980_13849090.AT2", "90", "Anaheim", "14383980"),
            ("a/RSN8883_14383980_13849360.AT2", "360", "Anaheim", "14383980"),
            ("b/AOM0011801241951.EW.gz", "EW", "AOM001", ""),
            ("b/AOM0011801241951.NS.gz", "NS", "AOM001", ""),
            ("b/AOM0011801241951.UD.gz", "UD", "AOM001", ""),
            ("c/NGNH311106302345.EW1", "EW1", "NGNH31", ""),
            ("c/NGNH311106302345.EW2", "EW2", "NGNH31", ""),
            ("c/NGNH311106302345.NS2", "NS2", "NGNH31", ""),
            ("d/one.v2", "HNE", "STA", "ev1"),
            ("d/two.v2", "HNN", "STA", "ev1"),
            ("e/alone.txt", "H1", "alone", ""),
        ]
    )
    grouping = group_records(table)
    assert grouping.record.tolist() == [
        "RSN8883", "RSN8883",
        "AOM001 1801241951", "AOM001 1801241951", "AOM001 1801241951",
        "NGNH31 1106302345 sensor 1", "NGNH31 1106302345 sensor 2",
        "NGNH31 1106302345 sensor 2",
        "STA / ev1", "STA / ev1",
        "e/alone.txt",
    ]  # fmt: skip
    assert grouping.rule.tolist() == [
        "rsn", "rsn", "nied", "nied", "nied", "nied", "nied", "nied", "header", "header", "file"
    ]  # fmt: skip
    assert grouping.vertical.tolist() == [False] * 4 + [True] + [False] * 6
    # a NIED file name gives the event (origin time, JST) when the header gave none
    assert grouping.event[2] == "1801241951 JST"
    table["record"], table["record_rule"] = grouping.record, grouping.rule
    table["vertical"] = grouping.vertical
    summary = grouping_summary(table)
    assert summary["records"] == 6 and summary["files"] == 11 and summary["vertical"] == 1
    assert summary["by_rule"] == {"rsn": 1, "nied": 3, "header": 1, "file": 1}
    assert summary["single"] == ["NGNH31 1106302345 sensor 1", "e/alone.txt"]
    assert grouping_line(summary).startswith("records: 11 files, 11 components → 6 records")


def test_plain_text_station_is_no_station() -> None:
    table = _table([("x/acc.txt", "", "acc", "")]).assign(format="text")
    assert group_records(table).station.tolist() == [""]


def test_headers_give_the_groups_of_real_files(data_dir: Path) -> None:
    # the real files: PEER's two AT2 of RSN 8883 and K-NET's three files of AOM001
    files = sorted(str(p) for p in (data_dir / "peer_nga_west2").glob("*.AT2"))
    files += sorted(str(p) for p in (data_dir / "formats" / "knet").glob("*.gz"))
    headers = header_table(files)
    table = join_headers(headers[["file", "component"]].assign(station=""), headers)
    grouping = group_records(table)
    assert grouping.record.tolist() == ["RSN8883"] * 2 + ["AOM001 1801241951"] * 3
    assert grouping.event.tolist()[2:] == ["2018-01-24T10:51:00"] * 3  # the header's event
    assert headers["rsn"].tolist()[:2] == [8883, 8883]
    assert grouping.vertical.tolist() == [False, False, False, False, True]
