"""Catalogues: rows per component, unit-named columns, failures recorded, atomic outputs."""

from __future__ import annotations

import shutil
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import pytest

from stepframe.errors import InputError
from stepframe.records import read
from stepframe.records.catalog import (
    COLUMNS,
    catalog,
    column_dictionary,
    intensity_table,
    record_files,
    write_catalog,
)
from stepframe.records.examples import fema_p695
from stepframe.records.intensity import intensity_measures
from stepframe.records.spectra import response_spectrum

PEER = Path(__file__).parents[1] / "data" / "peer_nga_west2"
FORMATS = Path(__file__).parents[1] / "data" / "formats"


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    root = tmp_path / "records"
    (root / "chino" / "deep").mkdir(parents=True)
    for name in ("RSN8883_14383980_13849090.AT2", "RSN8883_14383980_13849360.AT2"):
        shutil.copy(PEER / name, root / "chino" / name)
    shutil.copy(FORMATS / "dmg" / "CE58667.V2.gz", root / "chino" / "deep")
    (root / "empty.AT2").write_bytes(b"")
    (root / "binary.dat").write_bytes(bytes(range(256)) * 4)
    lines = (PEER / "RSN8883_14383980_13849090.AT2").read_text().splitlines()
    (root / "truncated.AT2").write_text("\n".join(lines[:100]) + "\n")
    (root / ".hidden").write_text("not a record")
    return root


def test_catalog_rows_failures_and_values(folder: Path) -> None:
    table, failures = catalog(folder)
    assert list(table.columns) == COLUMNS
    # 2 AT2 components + 3 DMG channels; the hidden file is not walked.
    assert len(table) == 5
    assert len(record_files(folder)) == 6
    assert sorted(Path(f).name for f in failures["item"]) == [
        "binary.dat",
        "empty.AT2",
        "truncated.AT2",
    ]
    assert set(failures["stage"]) == {"read"}
    assert all(reason.startswith(str(folder)) for reason in failures["message"])
    row = table[table["file"].str.endswith("13849360.AT2")].iloc[0]
    trace = read(PEER / "RSN8883_14383980_13849360.AT2")[0]
    expected = intensity_measures(trace.data, 0.005)
    for key in ("pga_g", "pgv_m_s", "pgd_m", "arias_m_s", "d5_95_s", "cav_m_s"):
        assert row[key] == pytest.approx(expected[key], rel=1e-12)
    psa = response_spectrum(trace.data, 0.005, [0.2, 1.0]).psa_g
    assert row["psa_0.2s_g"] == pytest.approx(psa[0]) and row["psa_1s_g"] == pytest.approx(psa[1])
    assert (row["component"], row["units_in"], row["npts"], row["format"]) == (
        "360",
        "g",
        16396,
        "at2",
    )
    dmg = table[table["file"].str.endswith("CE58667.V2.gz")]
    assert sorted(dmg["component"]) == ["H1", "H2", "Up"]


def test_a_copy_is_catalogued_once_and_named_in_the_failures(folder: Path) -> None:
    kept = folder / "chino" / "RSN8883_14383980_13849090.AT2"
    copy = folder / "chino" / "deep" / "saved again.AT2"
    shutil.copy(kept, copy)
    table, failures = catalog(folder)
    # The five components of the fixture's folder, not six: the copy is not a second row.
    assert len(table) == 5
    assert not table["file"].str.endswith("saved again.AT2").any()
    same = failures[failures["error_type"] == "SameContent"]
    assert list(same["item"]) == [str(copy)]
    assert list(same["stage"]) == ["read"]
    assert list(same["message"]) == [f"the same bytes as {kept}: read once"]
    # The other failures are the fixture's, unchanged.
    assert len(failures) == 4


def test_write_catalog_outputs(folder: Path, tmp_path: Path) -> None:
    table, failures = catalog(folder)
    paths = write_catalog(table, failures, tmp_path / "cat.csv")
    assert [p.name for p in paths] == ["cat.csv", "cat.columns.csv", "cat.failures.csv"]
    back = pd.read_csv(paths[0])
    assert list(back.columns) == COLUMNS and len(back) == 5
    np.testing.assert_allclose(back["pga_g"], table["pga_g"], rtol=1e-12)
    columns = pd.read_csv(paths[1])
    assert list(columns["column"]) == COLUMNS
    assert dict(zip(columns["column"], columns["unit"].fillna(""), strict=True))["pgv_m_s"] == "m/s"
    assert len(pd.read_csv(paths[2])) == 3
    # No temporary files are left beside the outputs.
    assert sorted(p.name for p in tmp_path.iterdir() if p.name.startswith(".")) == []
    with pytest.raises(InputError, match="output folder"):
        write_catalog(table, failures, tmp_path / "missing" / "cat.csv")


def test_example_catalogue_table_matches_its_metadata() -> None:
    stream, metadata = fema_p695()
    table = intensity_table(stream[:6])
    np.testing.assert_allclose(table["pga_g"], metadata["pga_g"][:6], rtol=1e-6)
    np.testing.assert_allclose(table["vs30_m_s"], metadata["vs30_m_s"][:6])
    assert list(column_dictionary()["column"]) == COLUMNS
    assert set(COLUMNS) >= {
        "file",
        "format",
        "event",
        "station",
        "component",
        "dt_s",
        "npts",
        "units_in",
        "magnitude",
        "repi_km",
        "rrup_km",
        "rjb_km",
        "vs30_m_s",
    }


def test_missing_folder() -> None:
    with pytest.raises(InputError, match="no such file or folder"):
        catalog("/nonexistent/folder")


def test_failure_in_measures_is_recorded_and_the_batch_goes_on(
    folder: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import sys

    # ``stepframe.records.catalog`` is the function (the package exports it); patch the module.
    module = sys.modules["stepframe.records.catalog"]
    real = module.trace_intensity_measures

    def failing(trace: Any) -> dict[str, float]:
        if float(trace.stats.delta) == 0.01:  # the three DMG channels
            raise RuntimeError("simulated failure")
        return real(trace)  # type: ignore[no-any-return]

    monkeypatch.setattr(module, "trace_intensity_measures", failing)
    table, failures = catalog(folder)
    assert len(table) == 2
    measured = failures[failures["stage"] == "measures"]
    assert len(measured) == 3
    assert set(measured["error_type"]) == {"RuntimeError"}
    assert set(measured["message"]) == {"simulated failure"}
    assert all(f.endswith(("[H1]", "[H2]", "[Up]")) for f in measured["item"])


def test_catalog_to_file_counts_what_it_wrote(data_dir: Path, tmp_path: Path) -> None:
    from stepframe.records.catalog import catalog_to_file

    folder = tmp_path / "records"
    folder.mkdir()
    source = data_dir / "peer_nga_west2" / "RSN8883_14383980_13849360.AT2"
    shutil.copy(source, folder)
    (folder / "broken.AT2").write_text("not a record\n")
    out = folder / "catalog.csv"  # inside the folder: not catalogued itself
    written = catalog_to_file(folder, out)
    table, failures = pd.read_csv(written.table), pd.read_csv(written.failures)
    assert (written.n_components, written.n_failures) == (len(table), len(failures)) == (1, 1)
    assert written.to_dict()["columns"] == str(folder / "catalog.columns.csv")
    again = catalog_to_file(read(source), tmp_path / "one.csv")
    assert again.n_components == 1 and again.n_failures == 0
    assert pd.read_csv(again.table)["pga_g"].iloc[0] == pytest.approx(table["pga_g"].iloc[0])
