"""The package's one file hash, the one place of a table's column dictionary and the one
formatter of numbers for people."""

from __future__ import annotations

import hashlib
from pathlib import Path

from stepframe.core.io import columns_path, file_sha256


def test_file_sha256_gives_the_published_digest_and_hashlibs_on_large_files(
    tmp_path: Path,
) -> None:
    """FIPS 180-2's example "abc" and the empty message, and a file over the 1 MiB block read
    in blocks against hashlib on all of its bytes at once (records.catalog, the store, the
    reports' provenance and the selection folder all hashed files; each had its own copy)."""
    abc = tmp_path / "abc"
    abc.write_bytes(b"abc")
    assert file_sha256(abc) == ("ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad")
    empty = tmp_path / "empty"
    empty.write_bytes(b"")
    assert file_sha256(empty) == (
        "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855"
    )
    data = bytes(range(256)) * 5000  # 1.28 MB: two blocks
    large = tmp_path / "large.bin"
    large.write_bytes(data)
    assert file_sha256(large) == hashlib.sha256(data).hexdigest()


def test_the_column_dictionary_sits_beside_its_table() -> None:
    assert columns_path("out/catalog.csv") == Path("out/catalog.columns.csv")
    assert columns_path(Path("features")) == Path("features.columns.csv")


def test_numbers_for_people_never_print_nan() -> None:
    """The selection's summary lines had two formatters: result's printed "not run" for NaN,
    ranking's printed "nan" (a Spearman ρ of constant values, a median of no records)."""
    import math

    import numpy as np

    from stepframe.core.text import number_text

    assert number_text(0.123456, ".2f") == "0.12"
    assert number_text(np.float64(2.0 / 3.0), ".3g") == "0.667"
    assert number_text(np.float32(0.5), ".1f") == "0.5"
    assert number_text(7, ".3g") == "7"
    for missing in (None, math.nan, np.nan, math.inf, "text"):
        assert number_text(missing, ".2f") == "—"
        assert number_text(missing, ".2f", "not run") == "not run"
