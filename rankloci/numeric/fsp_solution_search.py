"""The solution vectors of a reduced FSP system: section 5 of ORNL/TM-12816.

K. A. Morgansen and F. G. Pin, *Enhanced Code for the Full Space
Parameterization Approach to Solving Underspecified Systems of Algebraic
Equations*, ORNL/TM-12816 (1995): section 5.2 (the flow chart of Fig. 2 and
the main loop of FSP.c in appendix B) and section 5.1 (the completely
restricted case).  The input is the system left by the reducer
(:func:`rankloci.numeric.fsp.reduced_system`): n x m with full row rank.

The blocking-pattern search (:func:`blocking_pattern`)
-------------------------------------------------------
A *blocked* column is left out of a square submatrix; its component of the
solution vector is zero.  Each of the ``m - n + 1`` vectors blocks ``m - n``
columns and solves the ``n x n`` system of the others.

1. The first blocking is the first combination of ``m - n`` columns, in
   lexicographic order, whose square submatrix has a condition number of at
   most ``k2_bnd`` (FSP.h K2_BND).
2. Vector ``k + 1`` (k = 1 .. m - n) shares all blocks of vector k but one:
   the block at position ``m - n - k`` of vector k's list (so the first
   vector's blocks are freed from the last to the first) is freed, and the
   freed column is appended to the submatrix of vector k.  The null vector v
   of these ``n + 1`` columns is their linear dependency.  The new block is
   the first column c of vector k's submatrix, in ascending order, with
   ``|v_c| >= n_bnd`` (c is in the decomposition of the freed column, so the
   new submatrix is invertible) and ``g^k_c != 0`` (section 2: otherwise
   g^(k+1) = g^k).  It is appended at the end of the list.
3. When no column qualifies, the search returns to the previous vector and
   takes its next candidate; when the first vector has none left, the next
   first blocking of step 1 is tried.

The vectors are then affinely independent, and every ``sum t_k g^k`` with
``sum t_k = 1`` solves the system (eq. 15).

Deviations from the listing
---------------------------
1. The listing tests ``|g^k_c| < SMALL/10``, an absolute threshold with the
   units of A, so a small motion b (one step of a trajectory) finds no
   pattern.  Here ``|g^k_c| <= g_rtol * max|g^k|``: the same test for A, b
   and x of unit size.
2. When no first blocking has a condition number within ``k2_bnd`` the
   listing stops ("NO WELL-CONDITIONED SUBMATRICES FOUND").  Here the other
   invertible blockings (condition number below ``1 / rank_rtol``) are tried
   after those, best conditioned first; the result carries the condition
   number of the first submatrix used.
3. The listing computes the null vector of the ``n + 1`` columns with
   ``mat_null``, which pads the matrix with a zero row; the null vector is the
   same (the columns have rank n).  Submatrices are solved with an LU solve
   instead of the SVD pseudo-inverse (the same for an invertible matrix).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np

__all__ = ["Pattern", "blocking_pattern", "null_space_vectors"]


@dataclass(frozen=True, slots=True, eq=False)
class Pattern:
    """The solution vectors of a reduced system and how they were found.

    Attributes
    ----------
    vectors : numpy.ndarray, shape (m - n + 1, m)
        The vectors g^k as rows, in the order found.
    blocked : tuple of tuple of int
        The blocked columns of each vector, in the search's list order (the
        last entry is the block that vector added).
    condition : float
        Condition number of the first vector's square submatrix.
    first_blockings_tried : int
        How many first blockings were examined (each costs one SVD).
    """

    vectors: np.ndarray
    blocked: tuple[tuple[int, ...], ...]
    condition: float
    first_blockings_tried: int


def _condition(sub: np.ndarray) -> float:
    s = np.linalg.svd(sub, compute_uv=False)
    return float(s[0] / s[-1]) if s[-1] > 0 else np.inf


def _vector(a: np.ndarray, b: np.ndarray, blocks) -> np.ndarray | None:
    """g with zeros at `blocks` and the square solve elsewhere (BLOCK_COL_FIND_X)."""
    m = a.shape[1]
    keep = [j for j in range(m) if j not in set(blocks)]
    g = np.zeros(m)
    try:
        g[keep] = np.linalg.solve(a[:, keep], b)
    except np.linalg.LinAlgError:
        return None
    return g


def _extend(a, b, blocks: list, gs: list, n_bnd: float, g_rtol: float) -> bool:
    """Depth-first completion of the pattern from the vectors found so far."""
    n, m = a.shape
    p = m - n
    level = len(gs)
    if level == p + 1:
        return True
    prev, g = blocks[-1], gs[-1]
    freed = prev[p - level]
    base = prev[:p - level] + prev[p - level + 1:]
    unblocked = [j for j in range(m) if j not in set(prev)]
    null = np.linalg.svd(a[:, [freed] + unblocked])[2][-1]
    scale = float(np.max(np.abs(g)))
    for pos, c in enumerate(unblocked):
        if abs(null[pos + 1]) < n_bnd or abs(g[c]) <= g_rtol * scale:
            continue
        new = base + (c,)
        g_new = _vector(a, b, new)
        if g_new is None:
            continue
        blocks.append(new)
        gs.append(g_new)
        if _extend(a, b, blocks, gs, n_bnd, g_rtol):
            return True
        blocks.pop()
        gs.pop()
    return False


def blocking_pattern(a: np.ndarray, b: np.ndarray, *, k2_bnd: float,
                     n_bnd: float, g_rtol: float,
                     rank_rtol: float) -> Pattern | None:
    """The m - n + 1 solution vectors of ``a x = b`` by the blocking search.

    See the module docstring for the search and where it departs from the
    listing.

    Parameters
    ----------
    a : numpy.ndarray, shape (n, m)
        Reduced matrix with full row rank, n <= m, n >= 1.
    b : numpy.ndarray, shape (n,)
        Reduced right-hand side, not all zero.
    k2_bnd : float
        Largest condition number of an acceptable first submatrix (K2_BND).
    n_bnd : float
        Smallest null-vector component of a column that may be blocked next.
    g_rtol : float
        A component of a vector is zero when at most ``g_rtol`` times its
        largest component.
    rank_rtol : float
        First submatrices with a condition number of ``1 / rank_rtol`` or
        more are singular and never used.

    Returns
    -------
    Pattern or None
        None when no blocking completes a pattern.

    Examples
    --------
    >>> import numpy as np
    >>> p = blocking_pattern(np.array([[2.0, 3.0, 4.0]]), np.array([12.0]),
    ...                      k2_bnd=10.0, n_bnd=0.45, g_rtol=1e-4,
    ...                      rank_rtol=1e-4)
    >>> p.blocked
    ((0, 1), (0, 2), (2, 1))
    >>> p.vectors
    array([[0., 0., 3.],
           [0., 4., 0.],
           [6., 0., 0.]])
    """
    n, m = a.shape
    tried = 0
    later: list[tuple[float, tuple[int, ...]]] = []

    def attempt(first: tuple[int, ...], cond: float) -> Pattern | None:
        g = _vector(a, b, first)
        if g is None:
            return None
        blocks, gs = [first], [g]
        if _extend(a, b, blocks, gs, n_bnd, g_rtol):
            return Pattern(vectors=np.array(gs), blocked=tuple(blocks),
                           condition=cond, first_blockings_tried=tried)
        return None

    for first in itertools.combinations(range(m), m - n):
        tried += 1
        keep = [j for j in range(m) if j not in set(first)]
        cond = _condition(a[:, keep])
        if cond > k2_bnd:
            if cond * rank_rtol < 1.0:
                later.append((cond, first))
            continue
        found = attempt(first, cond)
        if found is not None:
            return found
    for cond, first in sorted(later):
        found = attempt(first, cond)
        if found is not None:
            return found
    return None


def null_space_vectors(a: np.ndarray, rank_rtol: float) -> np.ndarray:
    """The solution vectors of ``a x = 0``: section 5.1, the completely restricted case.

    The null vectors of `a` from its SVD (orthonormal, smallest singular
    value first) and, last, the zero vector: ``m - rank + 1`` rows in all.
    Every combination with weights summing to 1 is a null vector, and every
    null vector is one.

    Parameters
    ----------
    a : numpy.ndarray, shape (n, m)
        Reduced matrix (n may be 0).
    rank_rtol : float
        Singular values at most ``rank_rtol`` times the largest count as zero.

    Returns
    -------
    numpy.ndarray, shape (m - rank + 1, m)

    Examples
    --------
    >>> import numpy as np
    >>> v = null_space_vectors(np.array([[1.0, 0.0, 0.0]]), 1e-4)
    >>> np.abs(v)
    array([[0., 0., 1.],
           [0., 1., 0.],
           [0., 0., 0.]])
    """
    n, m = a.shape
    if a.size == 0:
        basis = np.eye(m)
    else:
        _, s, vt = np.linalg.svd(a)
        rank = int(np.sum(s > rank_rtol * s[0])) if s[0] > 0 else 0
        basis = vt[rank:][::-1]
    return np.vstack([basis, np.zeros((1, m))])
