"""The null space step of the FSP reducer: ``mat_null`` of ORNL/TM-12816.

A port of ``mat_null`` (matrix.c, appendix B of K. A. Morgansen and F. G.
Pin, ORNL/TM-12816, 1995), which :func:`rankloci.numeric.fsp.reduced_system`
calls on the transpose of what is left of A to find its dependent rows.

Deviations from the listing
---------------------------
Numbered as in :mod:`rankloci.numeric.fsp`, which lists those of ReduceA and
CheckB (4 to 8).  Each is a defect of the C code.

1. ``mat_null`` pads a wide matrix with zero rows, but calls
   ``svdcmp(U, C, C, ...)`` also when it has more rows R than columns C, so it
   decomposes only the first C rows.  ReduceA passes ``A^T`` (m x n, m > n)
   and so tested for dependencies among the rows of the first n columns of A
   only.  Here the whole matrix is decomposed.
2. When ``mat_null`` regards the smallest singular value as zero because the
   matrix is ill-conditioned, it copies ``V[order[j]][C-n_rank]``: column
   ``C-n_rank`` of V in svdcmp's unsorted order, its components permuted by
   the sort, instead of the singular vector ``V[j][order[C-n_rank]]``.  Here
   it is the singular vector.
3. ``mat_null`` counts singular values below SV_SMALL with no bound on the
   count, and reads past the singular values when all are below it (for
   instance ``A = 0``).  Here the count stops at C.

Thresholds
----------
Both are parameters with the listing's values as defaults
(:mod:`rankloci.tolerances`).  Section 4 quotes 1.0e-5 for the singular value
threshold (matrix.c: ``SV_SMALL = 1.0e-4``) and a maximum condition number of
10; the listing applies that bound (FSP.h ``K2_BND``) to the square
submatrices of the solution search, while ``mat_null`` regards the smallest
singular value as zero when ``s_min/s_max < SV_SMALL``.  The default
``k2_bnd`` is therefore ``1/SV_SMALL = 1e4``: with 10 the Jacobian of
example 6.1 (condition number 12.5) would lose its row 2 (the report's row 3)
as dependent, which the report says it does not.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..tolerances import FSP_NULL_K2_BND, FSP_SV_SMALL
from .fsp_inputs import check_number, finite_matrix

__all__ = ["NullSpace", "null_space"]


@dataclass(frozen=True, slots=True, eq=False)
class NullSpace:
    """Null space of a matrix as ``mat_null`` computes it.

    Attributes
    ----------
    vectors : numpy.ndarray, shape (C, nullity)
        Orthonormal null vectors as columns, the one of the smallest singular
        value first.  Read-only.
    condition : float
        ``K2 = s_max / s_min``, ``s_min`` the ``min(R, C)``-th singular value
        (``inf`` when it is zero).
    """

    vectors: np.ndarray
    condition: float


def null_space(a, *, sv_small: float = FSP_SV_SMALL,
               k2_bnd: float = FSP_NULL_K2_BND) -> NullSpace:
    """Null space of ``a`` from its SVD, as the listing's ``mat_null``.

    A matrix with fewer rows than columns is padded with zero rows, so it has
    C singular values.  Every singular value below `sv_small` counts as zero.
    If the ``min(R, C)``-th singular value ``s_min`` is not below `sv_small`
    but ``s_max / s_min > k2_bnd``, it counts as zero too.  The null vectors
    are the right singular vectors of the singular values that count as zero.

    Parameters
    ----------
    a : array_like, shape (R, C)
        The matrix.
    sv_small : float, optional
        Absolute singular value threshold (matrix.c ``SV_SMALL``).
    k2_bnd : float, optional
        Condition number above which the smallest singular value counts as
        zero; ``inf`` turns the test off.  The default ``1/SV_SMALL`` is the
        listing's.

    Returns
    -------
    NullSpace
        The null vectors (as columns, smallest singular value first) and the
        condition number.

    Raises
    ------
    ShapeError
        If `a` is not 2-D.
    ValueError
        If `a` is not finite or a threshold is not positive.

    Examples
    --------
    >>> import numpy as np
    >>> ns = null_space(np.array([[1.0, 1.0], [2.0, 2.0]]))
    >>> ns.vectors.shape
    (2, 1)
    >>> bool(np.allclose(np.abs(ns.vectors[:, 0]), np.sqrt(0.5)))
    True

    An ill-conditioned matrix loses its smallest singular value only past the
    condition-number bound:

    >>> null_space(np.diag([1.0, 1e-3])).vectors.shape
    (2, 0)
    >>> null_space(np.diag([1.0, 1e-3]), k2_bnd=100.0).vectors.shape
    (2, 1)
    >>> float(null_space(np.diag([1.0, 1e-3])).condition)
    1000.0
    """
    mat = finite_matrix(a, "a")
    check_number("sv_small", sv_small, 0.0)
    check_number("k2_bnd", k2_bnd, 0.0)
    rows, cols = mat.shape
    if mat.size:
        _, s, vt = np.linalg.svd(mat)
    else:
        s, vt = np.zeros(0), np.eye(cols)
    sigma = np.zeros(cols)           # padding with zero rows adds zero values
    sigma[:s.size] = s
    nullity = 0
    while nullity < cols and sigma[cols - 1 - nullity] < sv_small:
        nullity += 1
    k = min(rows, cols)
    s_min = float(sigma[k - 1]) if k else 0.0
    s_max = float(sigma[0]) if k else 0.0
    if s_min >= sv_small and s_max > k2_bnd * s_min:
        nullity += 1
    vectors = vt[cols - 1 - np.arange(nullity)].T.copy()
    vectors.setflags(write=False)
    condition = s_max / s_min if s_min > 0 else math.inf
    return NullSpace(vectors=vectors, condition=condition)
