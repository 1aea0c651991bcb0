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
        finite; at least one degree of freedom is assumed.
    """
    n, k = jacobian.shape
    sigma2 = float(residual @ residual) / max(n - k, 1)
    return np.asarray(np.linalg.pinv(jacobian.T @ jacobian) * (sigma2 * inflation))
