"""Output safety, the format registry's order, and the validation helpers' messages."""

from __future__ import annotations

import importlib
import os
import shutil
from pathlib import Path

import pandas as pd
import pytest

from stepframe.cli import main
from stepframe.core import validation
from stepframe.core.text import spreadsheet_cell, spreadsheet_safe, terminal_safe
from stepframe.errors import InputError
from stepframe.records import formats
from stepframe.records.catalog import catalog, write_catalog

AT2 = Path(__file__).parents[1] / "data" / "peer_nga_west2" / "RSN8883_14383980_13849090.AT2"


def test_terminal_escapes_control_characters() -> None:
    assert terminal_safe("\x1b[31mRED\x1b[0m\x07") == "\\x1b[31mRED\\x1b[0m\\x07"
    assert terminal_safe("tab\tand\nnewline stay, é stays") == "tab\tand\nnewline stay, é stays"


def test_spreadsheet_cells() -> None:
    assert spreadsheet_cell('=HYPERLINK("http://x","y")') == '\'=HYPERLINK("http://x","y")'
    assert [spreadsheet_cell(v) for v in ("+1+1", "@SUM(A1)", "-x", "\tcmd")] == [
        "'+1+1", "'@SUM(A1)", "'-x", "'\tcmd",
    ]  # fmt: skip
    assert [spreadsheet_cell(v) for v in ("-0.5", "+3", -2.0, "plain")] == [
        "-0.5", "+3", -2.0, "plain",
    ]  # fmt: skip
    frame = pd.DataFrame({"station": ["=cmd|' /C calc'!A0", "ok"], "pga": [-1.0, 2.0]})
    safe = spreadsheet_safe(frame)
    assert safe["station"].tolist() == ["'=cmd|' /C calc'!A0", "ok"]
    assert safe["pga"].tolist() == [-1.0, 2.0] and frame["station"][0].startswith("=")


def test_catalogue_csv_and_terminal_are_safe(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    lines = AT2.read_text().splitlines()
    lines[1] = '14383980, 7/29/2008, =HYPERLINK("http://evil"), \x1b[2J90'
    folder = tmp_path / "in"
    folder.mkdir()
    (folder / "rec.AT2").write_text("\n".join(lines) + "\n")
    table, failures = catalog(folder)
    out = tmp_path / "cat.csv"
    write_catalog(table, failures, out)
    text = out.read_text()
    assert "'=HYPERLINK" in text and ",=HYPERLINK" not in text
    umask = os.umask(0)
    os.umask(umask)
    assert out.stat().st_mode & 0o777 == 0o666 & ~umask  # the user's umask, not mkstemp's 0600
    assert main(["records", "info", str(folder / "rec.AT2")]) == 0
    printed = capsys.readouterr().out
    assert "\x1b" not in printed and "\\x1b[2J" in printed


def test_new_format_is_sniffed_before_plain_text(tmp_path: Path) -> None:
    def sniff(head: bytes, path: Path) -> bool:
        return head.startswith(b"0.1")

    def read(path: Path, options: formats.ReadOptions) -> object:
        raise InputError("claimed by the new format", path)

    registered = formats.registered_formats()
    try:
        formats.register(formats.RecordFormat("newfmt", sniff, read))
        order = list(formats.registered_formats())
        assert order.index("newfmt") < order.index("text") and order.index("at2") < order.index(
            "newfmt"
        )
        record = tmp_path / "values.txt"
        record.write_text("0.1\n0.2\n0.3\n")
        from stepframe.records import read as read_record

        with pytest.raises(InputError, match="claimed by the new format"):
            read_record(record, units="g", dt=0.01)
    finally:
        formats._REGISTERED.pop("newfmt", None)
    assert list(formats.registered_formats()) == list(registered)


def test_format_names_light_and_complete() -> None:
    assert formats.format_names() == ("fema", "cosmos", "geonet", "dmg", "esm", "at2", "text")
    assert set(formats.format_names()) <= set(formats.registered_formats())
    assert "obspy" in formats.format_names_help()


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: validation.damping_fraction("xi_1", 5), r"xi_1 5\.0, .*5 % is 0\.05"),
        (lambda: validation.damping_fraction("xi_1", -0.1), r"expected ≥ 0"),
        (lambda: validation.positive("dt", float("nan")), r"dt = nan, expected a finite"),
        (lambda: validation.positive("x", 10**400), r"expected a finite number"),
        (lambda: validation.integer("n", 2.5), r"n = 2.5, expected an integer"),
        (lambda: validation.seed("seed", -1), r"seed = -1, expected an integer 0\.\."),
        (
            lambda: validation.count("bootstrap", 10**9, bytes_each=40.0, budget_bytes=4 * 1024**3),
            r"bootstrap = 1000000000 needs about 37\.3 GiB of memory, over the budget of 4 GiB "
            r"\(as given\), expected work that fits it: at most 107374182$",
        ),
        (lambda: validation.length("window_s", 1e308), r"window_s = 1e\+308 s, expected"),
        (lambda: validation.frequency("f0", 0.0), r"f0 = 0 Hz, expected a value in \(0"),
    ],
)
def test_validation_messages(call: object, message: str) -> None:
    with pytest.raises(InputError, match=message):
        call()  # type: ignore[operator]


def test_validation_accepts() -> None:
    assert validation.damping_fraction("xi", 0.05) == 0.05
    assert validation.count("n", 3.0, bytes_each=8) == 3
    assert validation.seed("seed", None) is None and validation.seed("seed", 7) == 7
    assert validation.in_range("t", 1, 0, 1) == 1.0


def test_catalogue_outputs_replaced_together(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # (the package attribute ``catalog`` is the function, so the module comes from importlib)
    catalog_module = importlib.import_module("stepframe.records.catalog")

    folder = tmp_path / "in"
    folder.mkdir()
    shutil.copy(AT2, folder / AT2.name)
    table, failures = catalog(folder)
    out = tmp_path / "cat.csv"
    paths = write_catalog(table, failures, out)
    before = {p: p.read_bytes() for p in paths}
    calls = []

    def failing(frame: pd.DataFrame) -> pd.DataFrame:
        calls.append(1)
        if len(calls) == 3:  # the last of the three outputs fails mid-write
            raise OSError("disk full")
        return spreadsheet_safe(frame)

    monkeypatch.setattr(catalog_module, "spreadsheet_safe", failing)
    changed = table.assign(station="other")
    with pytest.raises(OSError, match="disk full"):
        write_catalog(changed, failures, out)
    assert {p: p.read_bytes() for p in paths} == before  # no output replaced
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(["in", *(p.name for p in paths)])
