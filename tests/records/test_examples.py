"""The embedded example catalogue against its source metadata."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from stepframe.core.results import get_column_dictionary
from stepframe.records import read
from stepframe.records.examples import COLUMNS, _decode, _encode, fema_p695
from stepframe.records.units import STANDARD_GRAVITY_M_S2


@pytest.fixture(scope="module")
def catalogue() -> tuple[object, pd.DataFrame]:
    return fema_p695()


def test_hundred_components_with_unit_named_columns(catalogue: tuple[object, pd.DataFrame]) -> None:
    stream, table = catalogue
    assert len(stream) == len(table) == 100  # type: ignore[arg-type]
    assert list(table.columns) == list(COLUMNS)
    assert set(get_column_dictionary(table)["column"]) == set(COLUMNS)


def test_one_earthquake_has_one_name(catalogue: tuple[object, pd.DataFrame]) -> None:
    # The source table names three mainshocks two ways ("Northridge" in the far-field set,
    # "Northridge-01" in the near-field sets): one name per (NGA name without its "-NN",
    # year, magnitude) now, and the traces carry it with the year.
    stream, table = catalogue
    base = table["event"].str.replace(r"-\d\d$", "", regex=True)
    assert (table.groupby([base, table["year"], table["magnitude"]])["event"].nunique() == 1).all()
    assert table["event"].nunique() == 19
    northridge = table["rsn"].isin([953, 960, 1004, 1048, 1063, 1086])
    assert set(table.loc[northridge, "event"]) == {"Northridge-01"}
    assert stream[0].stats.stepframe.event == "Northridge-01 1994"  # type: ignore[index]


def test_pga_npts_dt_match_metadata(catalogue: tuple[object, pd.DataFrame]) -> None:
    stream, table = catalogue
    for trace, row in zip(stream, table.itertuples(), strict=True):  # type: ignore[call-overload]
        assert trace.stats.npts == row.npts
        assert trace.stats.delta == row.dt_s
        pga_g = np.max(np.abs(trace.data)) / STANDARD_GRAVITY_M_S2
        assert abs(pga_g - row.pga_g) <= 1e-6
        assert trace.stats.stepframe.rsn == row.rsn
        assert trace.stats.stepframe.units_in == "g"


def test_metadata_matches_shared_source(shared_data: Path) -> None:
    source = pd.read_csv(shared_data / "fema_p695" / "records_metadata.csv")
    _, table = fema_p695()
    np.testing.assert_array_equal(table["pga_g"], source["pga_g"])
    np.testing.assert_array_equal(table["npts"], source["npts"])
    np.testing.assert_array_equal(table["dt_s"], source["dt"])


def test_values_bit_identical_to_source_text(shared_data: Path) -> None:
    stream, table = fema_p695()
    for i in (0, 57, 99):
        path = shared_data / "fema_p695" / table.file[i]
        source = read(path, format="fema")[0]
        np.testing.assert_array_equal(stream[i].data, source.data)


@pytest.mark.parametrize(
    "word",
    ["-7.55182000E-07", "9.99999999E+00", "1.00000000E-12", "-3.14159265E+05", "0.00000000E+00"],
)
def test_decimal_encoding_is_exact(word: str) -> None:
    mantissa, exponent = _encode([word])
    assert _decode(mantissa, exponent)[0] == float(word)


def test_example_stream_picks_one_component_by_name() -> None:
    from stepframe.errors import InputError
    from stepframe.records.examples import example_stream, fema_p695

    stream, table = fema_p695()
    one = example_stream("fema-p695", "MUL009")
    assert len(one) == 1 and one[0].stats.channel == "MUL009"
    index = [trace.stats.channel for trace in stream].index("MUL009")
    assert np.array_equal(one[0].data, stream[index].data)
    assert len(example_stream()) == len(table) == 100
    with pytest.raises(InputError, match="--component NOPE not in --example fema-p695"):
        example_stream("fema-p695", "NOPE")
