"""A unit's mean spectrum (the records chosen as pairs): one summation over the rows sorted by
unit, equal to the bit to the mean of each unit's members taken one unit at a time."""

from __future__ import annotations

import numpy as np

from stepframe.pipeline.selection.run import _unit_means


def test_unit_means_equal_each_units_own_mean_to_the_bit() -> None:
    rng = np.random.default_rng(7)
    log_psa = rng.normal(size=(60, 12)) * 3.0
    rows = rng.permutation(60)[:45].astype(np.int64)
    # units of 1, 2 and 3 members, their codes in first-seen order as pd.factorize gives them
    sizes = rng.integers(1, 4, size=45)
    codes = np.repeat(np.arange(sizes.size), sizes)[:45]
    codes = codes[rng.permutation(45)]
    _, first = np.unique(codes, return_index=True)
    relabel = np.empty(codes.max() + 1, dtype=np.int64)
    relabel[codes[np.sort(first)]] = np.arange(first.size)
    codes = relabel[codes]
    expected = np.array(
        [log_psa[rows[codes == u]].mean(axis=0) for u in range(int(codes.max()) + 1)]
    )
    got = _unit_means(log_psa, rows, codes)
    assert got.shape == expected.shape and np.array_equal(got, expected)
    # one value per row (a single period), and no rows at all
    assert np.array_equal(
        _unit_means(log_psa[:, 0], rows, codes),
        np.array([log_psa[rows[codes == u], 0].mean() for u in range(int(codes.max()) + 1)]),
    )
    assert _unit_means(log_psa, rows[:0], codes[:0]).size == 0
