"""Maximal minors, scale-free.

For an n x m matrix with n <= m (transpose it otherwise), every n x n minor
is at most the product of the row norms (Hadamard's inequality), so
``max |minor| / prod(row norms)`` lies in [0, 1] and does not change when a
row is rescaled (metres versus radians).  It is 0 exactly when the matrix
loses rank.
"""

from __future__ import annotations

from itertools import combinations

import numpy as np

__all__ = ["relative_max_minor"]


def relative_max_minor(J) -> float:
    """Largest |maximal minor| of `J` over the product of its row norms (rows <= cols).

    A matrix with more rows than columns is transposed first.  A matrix with
    a zero row gives 0.

    Examples
    --------
    >>> relative_max_minor(np.eye(3))
    1.0
    >>> relative_max_minor([[1.0, 2.0, 0.0], [2.0, 4.0, 0.0]])
    0.0
    >>> round(relative_max_minor([[1.0, 0.0], [1.0, 1.0]]), 6)
    0.707107
    """
    A = np.asarray(J, dtype=float)
    if A.ndim != 2:
        raise ValueError(f"J must be 2-D, got shape {A.shape}")
    if A.shape[0] > A.shape[1]:
        A = A.T
    n, m = A.shape
    norms = np.prod(np.linalg.norm(A, axis=1))
    if n == 0 or norms == 0:
        return 0.0
    cols = list(combinations(range(m), n))
    dets = np.abs(np.linalg.det(np.stack([A[:, c] for c in cols])))
    return float(np.max(dets) / norms)
