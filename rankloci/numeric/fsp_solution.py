"""The FSP solution space of ``A x = b`` and its least-norm point.

The Full Space Parameterization (FSP) of K. A. Morgansen and F. G. Pin,
*Enhanced Code for the Full Space Parameterization Approach to Solving
Underspecified Systems of Algebraic Equations*, ORNL/TM-12816 (1995),
sections 5 and 6 and the listing's main program, ``LeastNorm`` and
``RankLostSoln`` (FSP.c, appendix B).

:func:`solve` reduces the system (:func:`rankloci.numeric.fsp.reduced_system`,
section 4), finds the solution vectors g^k of what is left
(:mod:`rankloci.numeric.fsp_solution_search`) and puts the restricted
components back into every vector.  The solution space is

    S = { x = sum_k t_k g^k  :  sum_k t_k = 1,  sum_k (A_j g^k) t_k = b_j }

with one constraint of the second kind per row j that the reducer removed for
lack of rank (eqs. 15 to 19; ``beta_k = A_j g^k / b_j``).  Three cases:

- *unrestricted* (eq. 15): ``m - n + 1`` vectors of the reduced n x m system
  by the blocking-pattern search of section 5.2;
- *completely restricted* (section 5.1): the reduced b is zero, the vectors
  are the null vectors of the reduced A and the zero vector, each with the
  restricted components inserted;
- *rank lost* (eq. 16): the reducer removed dependent rows, so there are
  ``m - n + 1 + d`` vectors (n the rows of A, d the rows removed) and the beta
  constraints.

The least-norm point of S minimises ``|sum t_k g^k|`` under the constraints:
``LeastNorm`` (``t = G^-1 e / e^T G^-1 e``, G the Gram matrix of the g^k) and
``RankLostSoln`` (eqs. 20 to 27 with one beta constraint) are the closed
forms of that problem.

Deviations from the listing
---------------------------
1. The closed forms invert G and, in RankLostSoln, the 2 x 2 matrix of a, b1,
   c1, d11.  G is singular when 0 is in the span of the g^k (b = 0, or a
   completely restricted system whose restricted components are all zero),
   and the listing's pseudo-inverse then returns a point of S that is not the
   least-norm one (example 6.3).  For an exactly dependent row every
   ``A_j g^k`` equals ``b_j`` (every g^k solves the kept rows, and row j is a
   combination of them), so all beta are 1 (eq. 51), the beta constraint is
   ``sum t_k = 1`` again, ``A11 = c1 b1 - a d11 = 0`` and eq. (25) is 0/0.
   Here a constraint that repeats ``sum t_k = 1`` is dropped (tolerance
   ``FSP_CONSTRAINT_RTOL``), the others are imposed exactly, and the minimum
   is found by least squares over the weights that meet them, without
   forming G: the same point where the closed forms are defined.
2. The listing's Gram matrix covers the reduced components only; here the
   vectors are whole (restricted values in place).  Since the weights sum to
   1 the restricted part of x is the same for all of S, so the minimiser is
   the same; with whole vectors the least-norm point is right also where the
   reduced part of G is singular.
3. When no blocking pattern completes, the listing stops ("System did not
   complete!").  That happens for a full-rank system whose b leaves too
   many components of the basic solutions at zero for the pattern's
   conditions (section 2) to be met: the zero-filled reading of example 6.4
   is one.  Here the vectors are then the least-norm solution p of the
   reduced system and p plus each null vector of the reduced A (the
   construction of section 5.1 moved to p), which span the same S.
4. ``CheckRange`` accepts x when each removed row is met to ``|b_j| / 10``;
   here :attr:`FspSolution.consistent` says whether x solves every row of
   A x = b to ``FSP_RESIDUAL_RTOL`` of the size of its terms.

The reducer's and the search's own deviations are listed in
:mod:`rankloci.numeric.fsp` and :mod:`rankloci.numeric.fsp_solution_search`.
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass

import numpy as np

from ..tolerances import (
    FSP_B_ZERO_RTOL,
    FSP_CONSTRAINT_RTOL,
    FSP_G_ZERO_RTOL,
    FSP_K2_BND,
    FSP_N_BND_NUMERATOR,
    FSP_RESIDUAL_RTOL,
    FSP_SOLVE_RTOL,
)
from .fsp import ReduceResult, reduced_system
from .fsp_inputs import check_number, finite_matrix, finite_vector
from .fsp_solution_search import blocking_pattern, null_space_vectors

__all__ = ["FspSolution", "solve"]


@dataclass(frozen=True, slots=True, eq=False)
class FspSolution:
    """The FSP solution space of ``A x = b`` and its least-norm point.

    Indices are 0-based columns (joints) and rows of A as given.  Arrays are
    read-only.

    Attributes
    ----------
    vectors : numpy.ndarray, shape (k, m)
        The solution vectors g^k as rows, restricted components in place:
        ``k = m_red - n_red + 1`` for the reduced n_red x m_red system, which
        is ``m - n + 1`` for a 6 x 10 Jacobian without restrictions, and one
        more per row removed for lack of rank (eq. 16).  Each solves the rows
        kept; a removed row holds for each vector when it is exactly
        dependent, and otherwise through the beta constraints.
    least_norm : numpy.ndarray, shape (m,)
        The point of the solution space of least Euclidean norm.
    restricted : tuple of int
        Joints whose value is the same in every vector: those held still by
        the caller (``restricted=`` of :func:`solve`) and those a row with one
        nonzero entry fixes (section 3), sorted.
    rank_lost : bool
        Whether the reducer removed rows for lack of rank (dependent rows or
        rows of zeros): the beta constraints of eq. (16) apply.
    rank : int
        Rank of the system solved (A without the held columns) as the reducer
        decides it: the rows of A minus those removed for lack of rank.
    weights : numpy.ndarray, shape (k,)
        The t_k of :attr:`least_norm` (``least_norm = weights @ vectors``).
    constraints : numpy.ndarray, shape (1 + d, k)
        The constraints on the weights, ``constraints @ t = constraint_rhs``:
        first ``sum t_k = 1``, then ``sum (A_j g^k) t_k = b_j`` for each row j
        of :attr:`lost_rows`.
    constraint_rhs : numpy.ndarray, shape (1 + d,)
        1, then ``b_j`` for each row j of :attr:`lost_rows`.
    directions : numpy.ndarray, shape (dim, m)
        Orthonormal rows spanning the directions of the solution space: S is
        ``least_norm + z @ directions`` for every z.
    held : tuple of int
        The joints the caller held still (their component is 0 everywhere).
    inactive : tuple of int
        Columns of zeros of A: those joints do not act on b and are 0 in every
        vector (the listing's Xelim), so S leaves them still.  Entries of at
        most the reducer's SMALL (1e-3 max|A_ij|) count as zero, as in section
        4; where such an entry is not exactly zero the least-norm point
        differs from the pseudo-inverse solution by about that much.
    lost_rows : tuple of int
        Rows removed for lack of rank: dependent rows, then rows of zeros.
    blocked : tuple of tuple of int
        Blocked columns of each vector (the search's list order, the block
        each vector added last); empty tuples for vectors that come from a
        null space.
    completely_restricted : bool
        Whether the reduced b was zero (section 5.1).
    construction : str
        How the vectors were found: ``"blocking pattern"`` (section 5.2),
        ``"null space"`` (the completely restricted case) or ``"particular
        solution and null space"`` (no blocking pattern completes; deviation
        3 of the module docstring).
    condition : float
        Condition number of the first vector's square submatrix (nan in the
        completely restricted case; that of the reduced matrix when no
        pattern completes).
    consistent : bool
        Whether :attr:`least_norm` solves every row of ``A x = b``; False when
        b is not in the range of A (the listing assumes it is).
    reduction : ReduceResult
        The reducer's result for A without the held columns (its indices
        count those columns only).
    """

    vectors: np.ndarray
    least_norm: np.ndarray
    restricted: tuple[int, ...]
    rank_lost: bool
    rank: int
    weights: np.ndarray
    constraints: np.ndarray
    constraint_rhs: np.ndarray
    directions: np.ndarray
    held: tuple[int, ...]
    inactive: tuple[int, ...]
    lost_rows: tuple[int, ...]
    blocked: tuple[tuple[int, ...], ...]
    completely_restricted: bool
    construction: str
    condition: float
    consistent: bool
    reduction: ReduceResult

    @property
    def beta(self) -> np.ndarray:
        """The beta values of eq. (19), ``A_j g^k / b_j``, one row per lost row.

        nan where ``b_j = 0`` (the constraint is then ``sum (A_j g^k) t_k =
        0``, as in :attr:`constraints`).
        """
        num = self.constraints[1:]
        den = np.broadcast_to(self.constraint_rhs[1:, None], num.shape)
        return np.divide(num, den, out=np.full(num.shape, np.nan),
                         where=den != 0)


def _held(restricted, m: int) -> tuple[int, ...]:
    try:
        items = tuple(restricted)
    except TypeError:
        raise ValueError(f"restricted must be a sequence of joint indices, "
                         f"got {restricted!r}") from None
    for j in items:
        if (not isinstance(j, numbers.Integral) or isinstance(j, bool)
                or not 0 <= j < m):
            raise ValueError(f"restricted must hold joint indices in 0..{m - 1}, "
                             f"got {j!r}")
    if len(set(items)) != len(items):
        raise ValueError(f"restricted names a joint twice: {items!r}")
    return tuple(sorted(int(j) for j in items))


def _read_only(x: np.ndarray) -> np.ndarray:
    x = np.ascontiguousarray(x, dtype=float)
    x.setflags(write=False)
    return x


def _independent_constraints(rows: np.ndarray, rhs: np.ndarray,
                             scale: np.ndarray, k: int):
    """Constraints beyond sum t = 1 as orthonormal rows ``W t = w`` with W e = 0.

    Each row ``rows[j] @ t = rhs[j]`` is taken minus its part along
    ``sum t = 1`` and divided by ``scale[j]``, the size of its terms; what is
    left at most FSP_CONSTRAINT_RTOL repeats ``sum t = 1`` and is dropped
    (when its right-hand side does not vanish too, b is not in the range of
    A, which :attr:`FspSolution.consistent` reports).
    """
    e = np.ones(k)
    along = rows @ e / k
    rows = rows - np.outer(along, e)
    rhs = rhs - along
    keep = scale > 0
    rows, rhs = rows[keep] / scale[keep, None], rhs[keep] / scale[keep]
    if rows.shape[0] == 0:
        return np.zeros((0, k)), np.zeros(0)
    u, s, vt = np.linalg.svd(rows, full_matrices=False)
    r = int(np.sum(s > FSP_CONSTRAINT_RTOL))
    return vt[:r], (u.T @ rhs)[:r] / s[:r]


def _least_norm(vectors: np.ndarray, w_rows: np.ndarray, w_rhs: np.ndarray):
    """Weights, least-norm point and direction basis of the constrained span."""
    k = vectors.shape[0]
    e = np.ones((1, k)) / np.sqrt(k)
    rows = np.vstack([e, w_rows])              # orthonormal rows
    t0 = rows.T @ np.concatenate([[1 / np.sqrt(k)], w_rhs])
    full = np.linalg.svd(rows, full_matrices=True)[2]
    free = full[rows.shape[0]:].T              # (k, k - 1 - r)
    moves = free.T @ vectors                   # directions of S, as rows
    z = np.linalg.lstsq(moves.T, -(t0 @ vectors), rcond=None)[0] if free.size else np.zeros(0)
    t = t0 + free @ z
    if moves.size:
        _, s, vt = np.linalg.svd(moves, full_matrices=False)
        dim = int(np.sum(s > FSP_CONSTRAINT_RTOL * max(s[0], 1e-300)))
        directions = vt[:dim]
    else:
        directions = np.zeros((0, vectors.shape[1]))
    return t, t @ vectors, directions


def _solves(a: np.ndarray, b: np.ndarray, x: np.ndarray) -> bool:
    """Whether ``a x = b`` holds to FSP_RESIDUAL_RTOL, normwise."""
    if a.shape[0] == 0:
        return True
    size = float(np.max(np.abs(a) @ np.abs(x)) + np.max(np.abs(b)))
    return bool(np.max(np.abs(a @ x - b)) <= FSP_RESIDUAL_RTOL * size)


def solve(A, b, *, restricted=(), tol=None) -> FspSolution:
    """The FSP solution space of ``A x = b`` and its least-norm point.

    Parameters
    ----------
    A : array_like, shape (n, m)
        The matrix (a Jacobian; any shape).
    b : array_like, shape (n,)
        The right-hand side (a task-space motion).
    restricted : sequence of int, optional
        Joints (0-based columns) held still: their component is 0 in every
        solution and the system solved is A without their columns.
    tol : float, optional
        Rank tolerance in (0, 1): singular values at most ``tol`` times the
        largest singular value of A count as zero when the reducer looks for
        dependent rows, and square submatrices with a condition number of
        ``1 / tol`` or more are not used.  Default
        :data:`rankloci.tolerances.FSP_SOLVE_RTOL` (1e-4, the listing's).

    Returns
    -------
    FspSolution
        The vectors, the constraints on their weights, the least-norm point
        and how the system was reduced.

    Raises
    ------
    ShapeError
        If `A` is not 2-D or `b` does not have one entry per row.
    ValueError
        If an input is not finite, `tol` is out of range or `restricted` is
        not a set of column indices.

    Examples
    --------
    Section 6.2 of the report, reduced: one row, five columns.

    >>> import numpy as np
    >>> s = solve(np.array([[1.0, 2.0, 3.0, 4.0, 5.0]]), np.array([6.0]))
    >>> s.vectors
    array([[6. , 0. , 0. , 0. , 0. ],
           [0. , 0. , 0. , 0. , 1.2],
           [0. , 0. , 0. , 1.5, 0. ],
           [0. , 0. , 2. , 0. , 0. ],
           [0. , 3. , 0. , 0. , 0. ]])
    >>> s.blocked[:2]
    ((1, 2, 3, 4), (1, 2, 3, 0))
    >>> bool(np.allclose(s.least_norm, np.arange(1, 6) * 6 / 55))
    True

    Holding joint 4 still:

    >>> solve(np.array([[1.0, 2.0, 3.0, 4.0, 5.0]]), np.array([6.0]),
    ...       restricted=(4,)).least_norm.round(4)
    array([0.2, 0.4, 0.6, 0.8, 0. ])
    """
    a = finite_matrix(A, "A")
    n, m = a.shape
    rhs = finite_vector(b, n, "b")
    held = _held(restricted, m)
    rtol = FSP_SOLVE_RTOL if tol is None else tol
    check_number("tol", rtol, 0.0, 1.0)
    if rtol >= 1.0:
        raise ValueError(f"tol must be a number in (0.0, 1.0), got {tol!r}")
    free = [j for j in range(m) if j not in set(held)]
    sub = a[:, free]
    smax = float(np.linalg.svd(sub, compute_uv=False)[0]) if sub.size else 0.0
    red = reduced_system(sub, rhs, sv_small=max(rtol * smax, np.finfo(float).tiny),
                         k2_bnd=1.0 / rtol)

    a_red, b_red = red.a, red.b
    n_red, m_red = a_red.shape
    x_fixed = red.x_fixed
    scale = max(float(np.max(np.abs(rhs), initial=0.0)),
                float(np.max(np.abs(sub), initial=0.0)
                      * np.max(np.abs(x_fixed), initial=0.0)))
    zero_b = bool(np.all(np.abs(b_red) <= FSP_B_ZERO_RTOL * scale))
    if zero_b:
        g_red = null_space_vectors(a_red, rtol)
        blocked_red: tuple[tuple[int, ...], ...] = ((),) * g_red.shape[0]
        condition, construction = float("nan"), "null space"
    else:
        pattern = blocking_pattern(
            a_red, b_red, k2_bnd=FSP_K2_BND,
            n_bnd=FSP_N_BND_NUMERATOR / (n_red + 1), g_rtol=FSP_G_ZERO_RTOL,
            rank_rtol=rtol)
        if pattern is not None:
            g_red, blocked_red, condition = (pattern.vectors, pattern.blocked,
                                             pattern.condition)
            construction = "blocking pattern"
        else:
            particular = np.linalg.lstsq(a_red, b_red, rcond=None)[0]
            g_red = null_space_vectors(a_red, rtol)[::-1] + particular
            blocked_red = ((),) * g_red.shape[0]
            condition = float(np.linalg.cond(a_red))
            construction = "particular solution and null space"

    k = g_red.shape[0]
    in_sub = np.tile(x_fixed, (k, 1))
    in_sub[:, list(red.columns)] = g_red
    vectors = np.zeros((k, m))
    vectors[:, free] = in_sub

    lost = red.dependent_rows + red.zero_rows
    terms = np.abs(a[list(lost)]) @ np.abs(vectors).T
    rows = a[list(lost)] @ vectors.T
    w_rows, w_rhs = _independent_constraints(
        rows, rhs[list(lost)], terms.max(axis=1, initial=0.0), k)
    weights, x, directions = _least_norm(vectors, w_rows, w_rhs)

    col = [free[j] for j in red.columns]
    return FspSolution(
        vectors=_read_only(vectors),
        least_norm=_read_only(x),
        restricted=tuple(sorted(held + tuple(free[r.column]
                                             for r in red.restrictions))),
        rank_lost=bool(lost),
        rank=n - len(lost),
        weights=_read_only(weights),
        constraints=_read_only(np.vstack([np.ones((1, k)), rows])),
        constraint_rhs=_read_only(np.concatenate([[1.0], rhs[list(lost)]])),
        directions=_read_only(directions),
        held=held,
        inactive=tuple(free[j] for j in red.zero_columns),
        lost_rows=lost,
        blocked=tuple(tuple(col[c] for c in blk) for blk in blocked_red),
        completely_restricted=zero_b,
        construction=construction,
        condition=condition,
        consistent=_solves(a, rhs, x),
        reduction=red,
    )
