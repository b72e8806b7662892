"""Singular-value rank decisions, batched over leading axes.

Every decision is relative to sigma_max, as in ``numpy.linalg.matrix_rank``,
with the package threshold :data:`rankloci.tolerances.RANK_RTOL`.
"""

from __future__ import annotations

import numpy as np

from ..tolerances import GRAM_SCREEN, RANK_RTOL

__all__ = ["sigma_ratio", "numeric_rank_drop", "rank_deficient", "null_directions",
           "principal_axes", "GRAM_SCREEN"]


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


def rank_deficient(J, rtol: float = RANK_RTOL) -> np.ndarray:
    """Boolean per matrix: sigma_min <= rtol * sigma_max, batched and fast.

    The eigenvalues of the Gram matrix J J^T (or J^T J) settle every clearly
    regular matrix; only the rest get a singular value decomposition, so the
    decision is the SVD's while random configurations cost one small
    symmetric eigenproblem each.

    Examples
    --------
    >>> rank_deficient(np.array([[[1.0, 0.0], [0.0, 1e-12]], [[1.0, 0.0], [0.0, 0.5]]])).tolist()
    [True, False]
    """
    J = np.asarray(J, dtype=float)
    if J.ndim == 2:
        return rank_deficient(J[None], rtol)[0]
    G = J @ np.swapaxes(J, -1, -2) if J.shape[-2] <= J.shape[-1] else np.swapaxes(J, -1, -2) @ J
    lam = np.linalg.eigvalsh(G)
    top = lam[..., -1]
    clear = lam[..., 0] > GRAM_SCREEN * np.where(top > 0, top, np.inf)
    out = np.zeros(J.shape[0], dtype=bool)
    unsure = ~clear
    if np.any(unsure):
        out[unsure] = numeric_rank_drop(J[unsure], rtol) > 0
    return out


def null_directions(J, drop: int, tall: bool = False) -> tuple:
    """The ``drop`` unit null vectors of J from its SVD: left ones, or right ones for a tall J.

    The singular vectors of the ``drop`` smallest singular values, as tuples of floats.

    Examples
    --------
    >>> [abs(x) for x in null_directions(np.array([[1.0, 0.0], [0.0, 0.0]]), 1)[0]]
    [0.0, 1.0]
    >>> u = null_directions(np.array([[1.0, 1.0], [1.0, 1.0], [1.0, 1.0]]), 1, tall=True)[0]
    >>> round(u[0] + u[1], 12), round(abs(u[0]), 6)
    (0.0, 0.707107)
    """
    U, _, Vt = np.linalg.svd(J)
    vecs = Vt[-drop:] if tall else U[:, -drop:].T
    return tuple(tuple(float(x) for x in v) for v in vecs)


def principal_axes(J) -> tuple:
    """The axes and semi-axis lengths of the ellipsoid {J x : |x| <= 1}: J's left singular
    vectors (columns of U) and its singular values, largest first.

    Examples
    --------
    >>> U, s = principal_axes(np.array([[0.0, 2.0], [1.0, 0.0]]))
    >>> s.tolist(), np.abs(U[:, 0]).tolist()
    ([2.0, 1.0], [1.0, 0.0])
    """
    U, s, _ = np.linalg.svd(np.asarray(J, dtype=float))
    return U, s
