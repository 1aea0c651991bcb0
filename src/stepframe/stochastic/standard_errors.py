"""Parameter covariance of a least-squares fit, shared by every fit of the stochastic stage."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


def least_squares_covariance(
    jacobian: NDArray[np.float64], residual: NDArray[np.float64], inflation: float = 1.0
) -> NDArray[np.float64]:
    """Covariance of fitted parameters, ``s² (JᵀJ)⁺ · inflation`` with ``s² = r·r / (n - k)``.

    Parameters
    ----------
    jacobian
        J, shape (n, k): derivative of the n (weighted) residuals by the k parameters.
    residual
        r, shape (n,): the (weighted) residuals at the solution.
    inflation
        Factor for correlated residuals, such as the number of STFT frames per window
        (frames closer than a window share data, so n overstates the independent points).

    Returns
    -------
    numpy.ndarray, shape (k, k)
        In the units of the parameters squared. The pseudo-inverse keeps a rank-deficient fit
        finite (the columns of J are scaled first, so its cutoff is relative to each parameter's
        own scale); at least one degree of freedom is assumed.
    """
    n, k = jacobian.shape
    sigma2 = float(residual @ residual) / max(n - k, 1)
    # Columns scaled to a largest entry of 1 first: the pseudo-inverse's cutoff is relative to
    # the largest singular value, and a parameter with a huge derivative (a fit that ran to a
    # bound) would otherwise cut off, and zero, the variances of all the others.
    scale = np.max(np.abs(jacobian), axis=0)
    scale[~(scale > 0.0) | ~np.isfinite(scale)] = 1.0
    scaled = jacobian / scale
    inverse = np.linalg.pinv(scaled.T @ scaled) / np.outer(scale, scale)
    return np.asarray(inverse * (sigma2 * inflation))
