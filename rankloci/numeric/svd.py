"""Singular-value rank decisions, batched over leading axes.

Every decision is relative to sigma_max, as in ``numpy.linalg.matrix_rank``,
with the package threshold :data:`rankloci.tolerances.RANK_RTOL`.
"""

from __future__ import annotations

import numpy as np

from ..tolerances import RANK_RTOL

__all__ = ["sigma_ratio", "numeric_rank_drop"]


def sigma_ratio(J) -> np.ndarray:
    """Smallest over largest singular value, batched over leading axes (0 for a zero matrix).

    Examples
    --------
    >>> float(sigma_ratio([[1.0, 0.0], [0.0, 2.0]]))
    0.5
    >>> sigma_ratio(np.zeros((3, 2, 2))).tolist()
    [0.0, 0.0, 0.0]
    """
    s = np.linalg.svd(np.asarray(J, dtype=float), compute_uv=False)
    top = s[..., 0]
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(top > 0, s[..., -1] / np.where(top > 0, top, 1.0), 0.0)


def numeric_rank_drop(J, rtol: float = RANK_RTOL) -> np.ndarray:
    """min(rows, cols) minus the number of singular values above ``rtol * sigma_max``.

    Examples
    --------
    >>> int(numeric_rank_drop([[1.0, 2.0], [2.0, 4.0]]))
    1
    >>> int(numeric_rank_drop(np.eye(3)))
    0
    """
    s = np.linalg.svd(np.asarray(J, dtype=float), compute_uv=False)
    return np.sum(s <= rtol * s[..., :1], axis=-1)
