"""Compiled kernel of the confirmation's bootstrap: Spearman's ρ of each resample from the drawn
indices, without sorting (:mod:`stepframe.pipeline.selection.confirm`).

Compiled because each resample is a few passes over the candidates with gathers through each
variable's order: as numpy operations on blocks of resamples they moved some fifteen
catalogue-sized arrays per resample through memory, 10-14 s of CPU per interval at 43,000
candidates and about 660 s for the intervals of one selection run (docs/benchmarks.md, issue
29). The arithmetic is the numpy version's, in the same order (sequential sums over the
candidates in input order), so the intervals are the same to the last bit.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from stepframe.core.jit import njit


@njit(cache=True, error_model="numpy")
def resampled_rhos(
    picks: NDArray[np.int64],
    orders: NDArray[np.int64],
    groups: NDArray[np.int64],
    n_groups: NDArray[np.int64],
    pairs: NDArray[np.int64],
) -> NDArray[np.float64]:
    """Spearman's ρ of pairs of variables in each resample (resamples × pairs).

    Parameters
    ----------
    picks
        The drawn candidates of each resample (resamples × n, indices into 0 … n-1).
    orders, groups
        Per variable (rows): the candidates in the variable's order, and the group of equal
        values of each position in that order (0, 1, …; ties share a group).
    n_groups
        Per variable: its number of groups.
    pairs
        Rows of two variable indices: the ρ computed for each.

    Returns
    -------
    numpy.ndarray
        ρ of each resample and pair: the Pearson correlation of the two variables' ranks over the
        drawn candidates, each counted as often as drawn, ties averaged (NaN when a variable is
        constant over the resample).

    Notes
    -----
    In a variable's order a group of equal values drawn T times in all, after S draws of smaller
    values, has the average rank S + (T + 1)/2; the ranks are centred on (n + 1)/2.
    """
    n_resamples, n = picks.shape
    n_variables = orders.shape[0]
    out = np.empty((n_resamples, pairs.shape[0]))
    counts = np.zeros(n, dtype=np.int64)
    ranks = np.empty((n_variables, n))
    totals = np.empty(n)
    centre = 0.5 * (n + 1.0)
    for j in range(n_resamples):
        counts[:] = 0
        for k in range(n):
            counts[picks[j, k]] += 1
        for v in range(n_variables):
            totals[: n_groups[v]] = 0.0
            for p in range(n):
                totals[groups[v, p]] += counts[orders[v, p]]
            running = 0.0
            for g in range(n_groups[v]):
                running += totals[g]
                totals[g] = running - 0.5 * (totals[g] - 1.0) - centre
            for p in range(n):
                ranks[v, orders[v, p]] = totals[groups[v, p]]
        for q in range(pairs.shape[0]):
            a, b = pairs[q, 0], pairs[q, 1]
            cross = 0.0
            square_a = 0.0
            square_b = 0.0
            for i in range(n):
                weighted = counts[i] * ranks[b, i]
                cross += weighted * ranks[a, i]
                square_a += counts[i] * ranks[a, i] ** 2
                square_b += weighted * ranks[b, i]
            out[j, q] = cross / math.sqrt(square_a * square_b)
    return out
