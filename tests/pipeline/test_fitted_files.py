"""pipeline.fitted_files: a record file's fit with its NetCDF, a folder's features table."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from stepframe.core.tables import read_table
from stepframe.errors import InputError
from stepframe.pipeline.catalogue.fitted import FitOptions, fit_records, read_fitted
from stepframe.pipeline.catalogue.fitted_files import features_to_file, fit_file
from stepframe.records import read

RECORD = "peer_nga_west2/RSN8883_14383980_13849360.AT2"


def test_fit_file_equals_the_fit_and_its_netcdf_reads_back(data_dir: Path, tmp_path: Path) -> None:
    path = data_dir / RECORD
    stream = read(path)
    out = tmp_path / "rec.nc"
    fitted = fit_file(stream, FitOptions(), file=str(path), path=str(path), out=out)
    assert fitted.to_dict() == [r.to_dict() for r in fit_records(stream, file=str(path))]
    dataset = read_fitted(out)
    record = fitted.records[0]
    assert np.allclose(
        dataset["omega_g_fit"].values, record.fitted.model.omega_g(record.features.time_s)
    )
    assert dataset.attrs["spectrum_method"] == "stft"
    # the text says where the NetCDF went, as a figure's "plot written to" does
    assert fitted.describe() == f"{record.describe()}\nPSD and features written to {out}"
    assert fit_file(stream, FitOptions(), file=str(path)).describe() == record.describe()
    with pytest.raises(InputError, match="output folder does not exist"):
        fit_file(stream, FitOptions(), file="x", out=tmp_path / "missing" / "x.nc")


def test_features_to_file_counts_what_it_wrote(data_dir: Path, tmp_path: Path) -> None:
    folder = tmp_path / "records"
    folder.mkdir()
    shutil.copy(data_dir / RECORD, folder)
    (folder / "broken.AT2").write_text("not a record\n")
    written = features_to_file(str(tmp_path / "f.csv"), folder=str(folder), progress=False)
    table = read_table(written.table)
    failures = pd.read_csv(written.failures)
    assert (written.n_components, written.n_failures) == (len(table), len(failures)) == (1, 1)
    assert written.n_plausible == int(table["plausible"].sum())
    assert written.columns.is_file()
    assert written.describe().startswith("1 components (")
    with pytest.raises(InputError, match="expected exactly one"):
        features_to_file(str(tmp_path / "g.csv"))
