"""Discontinuity indices of minimum infinity-norm solutions, and rate mixing.

The minimum infinity-norm solution of A x = y is not unique, and can jump
along a path, when the solution space x2 + null(A) is parallel to a face of
the hypercube ||x||_inf = t that it touches.  With an orthonormal null-space
basis N (n x (n - m)), a face spanned by the coordinate axes outside a set R of
n - m rows is parallel to a direction of null(A) exactly when the minor
det N[R] vanishes.

- :func:`subspace_index` (I. Gravagne's index, Ha and Lee eq. 39): the smallest
  |det N[R]| over all such R, whether or not the solution touches that face.
- :func:`discontinuity_index` (Ha and Lee, section IV.2): the smallest
  |det N[R]| over the faces that hold the solution: R is the saturated set
  (n - m + 1 columns of A_2) less one of its members.  A zero means a direction
  of null(A) along which every saturated component but one stays fixed, so the
  optimum is not unique there.

Both are in [0, 1] and do not depend on the choice of orthonormal basis.
By the complementary-minor identity for the orthogonal matrix [N, A'(AA')^(-1/2)],
|det N[R]| = |det A[:, C]| / sqrt(det(A A')) with C the m columns outside R:
:func:`discontinuity_index` equals min over k in the saturated set of
|det [A_1, a_k]| / sqrt(det A A'), the form in A that Ha and Lee describe.

Rate mixing (Ha and Lee eqs. 38, 40): x = r x_inf + (1 - r) x_2 with
r = 1 - exp(-a d).  Both terms solve A x = y, so every mixture does.
"""

from __future__ import annotations

import itertools

import numpy as np

__all__ = ["null_basis", "discontinuity_index", "minor_index", "subspace_index", "mixing_ratio",
           "mixed_rates", "DEFAULT_MIXING_GAIN"]

#: The gain a of r = 1 - exp(-a d).  Ha and Lee do not give theirs.  With a = 20 the
#: mixture is almost pure minimum infinity-norm (r > 0.98) for d > 0.2, and half and
#: half at d = 0.035.
DEFAULT_MIXING_GAIN = 20.0


def null_basis(A) -> np.ndarray:
    """An orthonormal basis of the null space of a full-row-rank A (n x (n - m), from the SVD)."""
    A = np.asarray(A, dtype=float)
    m = A.shape[0]
    return np.linalg.svd(A, full_matrices=True)[2][m:].T


def _minor(N, rows) -> float:
    if len(rows) == 0:
        return 1.0
    return float(abs(np.linalg.det(N[list(rows)])))


def discontinuity_index(A, saturated) -> float:
    """Ha and Lee's discontinuity index: min |det N[R]| over R = saturated less one column.

    Parameters
    ----------
    A : array_like, shape (m, n), full row rank
    saturated : sequence of int
        The n - m + 1 saturated columns (``InfNormSolution.saturated``).

    Returns
    -------
    float
        In [0, 1]; 0 where the minimum infinity-norm solution is not unique.

    Examples
    --------
    >>> A = np.array([[0.7, 0.1, -1.6], [2.0, -0.2, 0.6]])
    >>> round(discontinuity_index(A, (1, 2)), 4)
    0.0933
    """
    A = np.asarray(A, dtype=float)
    m, n = A.shape
    sat = list(saturated)
    if len(sat) != n - m + 1:
        raise ValueError(f"saturated must name n - m + 1 = {n - m + 1} columns, got {len(sat)}")
    N = null_basis(A)
    return min(_minor(N, [j for j in sat if j != k]) for k in sat)


def minor_index(A, saturated) -> float:
    """min over k of |det [A_1, a_k]| / sigma_max(A)^m: the discontinuity index formed with A.

    Ha and Lee (section IV.2) replace N by A in the index.  Formed with A,
    the index equals :func:`~rankloci.near.discontinuity.discontinuity_index`
    times prod_i sigma_i / sigma_max, so unlike it, it vanishes where A loses
    rank: on the locus, every m x m minor of A is zero.

    Examples
    --------
    >>> A = np.array([[0.7, 0.1, -1.6], [2.0, -0.2, 0.6]])
    >>> s = np.linalg.svd(A, compute_uv=False)
    >>> bool(np.isclose(minor_index(A, (1, 2)), discontinuity_index(A, (1, 2)) * s[1] / s[0]))
    True
    """
    A = np.asarray(A, dtype=float)
    m, n = A.shape
    sat = list(saturated)
    free = [j for j in range(n) if j not in sat]
    smax = np.linalg.norm(A, 2)
    return min(abs(float(np.linalg.det(A[:, free + [k]]))) for k in sat) / smax ** m


def subspace_index(A) -> float:
    """Gravagne's index: the smallest |det N[R]| over every set R of n - m rows.

    Examples
    --------
    >>> A = np.array([[0.7, 0.1, -1.6], [2.0, -0.2, 0.6]])
    >>> round(subspace_index(A), 4)
    0.0713
    """
    A = np.asarray(A, dtype=float)
    m, n = A.shape
    N = null_basis(A)
    return min(_minor(N, R) for R in itertools.combinations(range(n), n - m))


def mixing_ratio(d, gain: float = DEFAULT_MIXING_GAIN):
    """r = 1 - exp(-gain d) (Ha and Lee eq. 40).

    Examples
    --------
    >>> float(mixing_ratio(0.0)), round(float(mixing_ratio(0.2)), 4)
    (0.0, 0.9817)
    """
    if not gain > 0:
        raise ValueError(f"gain must be positive, got {gain!r}")
    return 1.0 - np.exp(-gain * np.asarray(d, dtype=float))


def mixed_rates(x_inf, x_2, r):
    """r x_inf + (1 - r) x_2 (Ha and Lee eq. 38)."""
    return r * np.asarray(x_inf, dtype=float) + (1.0 - r) * np.asarray(x_2, dtype=float)
