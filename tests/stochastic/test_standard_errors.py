"""Covariance of least-squares fits: the inverse where J has full rank, finite where it has not."""

from __future__ import annotations

import numpy as np

from stepframe.stochastic.standard_errors import least_squares_covariance


def test_full_rank_is_the_inverse_of_jtj() -> None:
    rng = np.random.default_rng(1)
    jacobian = rng.normal(size=(40, 3)) * np.array([1e-3, 1.0, 1e4])
    residual = rng.normal(size=40)
    expected = np.linalg.inv(jacobian.T @ jacobian) * (residual @ residual / 37) * 2.5
    np.testing.assert_allclose(
        least_squares_covariance(jacobian, residual, 2.5), expected, rtol=1e-9
    )


def test_a_huge_derivative_does_not_zero_the_other_variances() -> None:
    """A parameter at a bound where its derivative diverges (1e140 here) is pinned: the others
    keep the variances of the fit without it (the pseudo-inverse's cutoff is per column)."""
    rng = np.random.default_rng(2)
    others = rng.normal(size=(30, 2))
    pinned = np.zeros(30)
    pinned[0] = 1e140  # orthogonal to the others' columns except in one row
    others[0] = 0.0
    jacobian = np.column_stack([others[:, 0], pinned, others[:, 1]])
    residual = rng.normal(size=30)
    cov = least_squares_covariance(jacobian, residual)
    alone = np.linalg.inv(others.T @ others) * (residual @ residual / 27)
    np.testing.assert_allclose(cov[np.ix_([0, 2], [0, 2])], alone, rtol=1e-9)
    assert 0 <= cov[1, 1] < 1e-270
