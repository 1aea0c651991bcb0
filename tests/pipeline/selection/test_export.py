"""The chosen motions out: read back by the project's reader, the manifest documented."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pandas as pd

from stepframe.pipeline.selection.chosen import Motion
from stepframe.pipeline.selection.export import MANIFEST_COLUMNS, export_motions
from stepframe.records import read

DOCS = Path(__file__).resolve().parents[3] / "docs" / "selection.md"


def test_exported_files_read_back_to_the_scaled_samples(tmp_path: Path) -> None:
    rng = np.random.default_rng(7)
    motions = [
        Motion("a/RSN8883_x_90.AT2", "90", "RSN8883", 1.7, rng.standard_normal(1001), 0.005,
               "14383980", "Anaheim"),
        Motion("b/AOM0011801241951.NS.gz", "NS", "AOM001 1801241951", 0.35,
               rng.standard_normal(517) * 3.0, 0.01),
        Motion("../c/odd.v1", "H1", "../c/odd.v1", 2.0, rng.standard_normal(300), 0.00390625),
    ]  # fmt: skip
    paths = export_motions(motions, tmp_path)
    manifest = pd.read_csv(paths["manifest"])
    assert list(manifest.columns) == list(MANIFEST_COLUMNS)
    for motion, row in zip(motions, manifest.to_dict("records"), strict=True):
        expected = motion.acc_m_s2 * motion.scale
        (at2,) = read(tmp_path / "motions" / row["at2_file"])
        assert at2.stats.delta == motion.dt_s  # DT written exactly
        np.testing.assert_allclose(at2.data, expected, rtol=1e-9, atol=1e-12)
        (text,) = read(
            tmp_path / "motions" / row["text_file"], format="text", units="g", dt=row["dt_s"]
        )
        np.testing.assert_allclose(text.data, expected, rtol=1e-9, atol=1e-12)
        assert row["npts"] == motion.acc_m_s2.size and row["units"] == "g"
        assert row["scale"] == motion.scale and row["dt_s"] == motion.dt_s
        # nothing but numbers, one a line: what OpenSees' timeSeries Path reads
        lines = (tmp_path / "motions" / row["text_file"]).read_text().splitlines()
        assert len(lines) == row["npts"] and all(len(line.split()) == 1 for line in lines)
    # a record named by its path is named by its file's name (was 03_.._c_odd.v1_H1)
    assert manifest["at2_file"].tolist() == [
        "01_RSN8883_90.AT2", "02_AOM001_1801241951_NS.AT2", "03_odd.v1_H1.AT2"
    ]  # fmt: skip
    assert manifest["record"].tolist()[2] == "../c/odd.v1"


def test_the_manifest_columns_are_documented() -> None:
    text = DOCS.read_text(encoding="utf-8")
    documented = set(re.findall(r"^\| `([a-z_0-9]+)` \|", text, flags=re.MULTILINE))
    assert set(MANIFEST_COLUMNS) <= documented
    assert "timeSeries Path" in text


def test_the_written_lines_name_what_the_folder_holds(tmp_path: Path) -> None:
    """`select` and `demo` name the files their run wrote: spectra.csv and motions/ only when
    they are there (the demo's line named five tables and selection.json, leaving out the
    spectra.csv and motions/ its run had written)."""
    from stepframe.pipeline.selection.result import written_lines

    for name in ("selection.csv", "candidates.csv", "confirmation.csv", "failures.csv",
                 "columns.csv", "selection.json"):  # fmt: skip
        (tmp_path / name).write_text("x\n")
    tables = (
        f"{tmp_path}/ (selection.csv, candidates.csv, confirmation.csv, failures.csv, columns.csv"
    )
    assert written_lines(tmp_path, "tables") == [f"tables: {tables}, selection.json)"]
    (tmp_path / "spectra.csv").write_text("x\n")
    rng = np.random.default_rng(1)
    export_motions([Motion("r.AT2", "90", "r", 1.0, rng.standard_normal(10), 0.01)], tmp_path)
    assert written_lines(tmp_path) == [
        f"outputs: {tables}, spectra.csv, selection.json)",
        f"the chosen motions, scaled: {tmp_path}/motions/ (manifest.csv, one AT2 and one "
        "one-column text file per component)",
    ]
