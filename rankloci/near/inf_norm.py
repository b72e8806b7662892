"""What the minimum infinity-norm solvers share: the problem A x = y and its solution type.

:mod:`rankloci.near.min_inf_norm` (Ha and Lee, the linear program) and
:mod:`rankloci.near.cadzow` solve the same problem: both check the system
with :func:`checked_system`, reduce a rank-deficient A to its range with
:func:`on_range`, and return an :class:`InfNormSolution`.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from ..tolerances import INF_NORM_RANGE_RTOL, RANK_RTOL

__all__ = ["InfNormSolution", "checked_system", "on_range", "solution"]


@dataclass(frozen=True)
class InfNormSolution:
    """A solution x of A x = y of (or on the way to) least infinity norm.

    Attributes
    ----------
    x : numpy.ndarray
        The solution (NaN when none was formed).
    norm : float
        ``max |x_i|``.
    bound : float
        y'u for the last dual-feasible u (||A'u||_1 = 1): no solution has a
        smaller infinity norm (weak duality).  For ``"lp"``, the LP optimum.
    converged : bool
        Whether x is certified optimal: ``norm <= (1 + INF_NORM_RTOL) bound``.
    method : str
    iterations : int
        Column exchanges (HiGHS's simplex iterations for ``"lp"``).
    saturated : tuple of int
        Indices of the columns of A_2: the components of x at +-norm.
    free : tuple of int
        Indices of the columns of A_1 (m - 1 of them).
    reason : str
        Why the method stopped without a certified optimum ("" when converged).
    history : tuple of dict
        One entry per iteration: ``free``, ``bound`` (y'u), ``x1_norm``
        (max |x_i| over the free columns) and ``zeros`` (columns of A_2 with
        A_2'u = 0), to show how an algorithm proceeds or fails.
    rank : int or None
        The numerical rank of A (RANK_RTOL).  Below m, the method solved the
        system on the range of A (see the module's description): ``free`` then
        has r - 1 columns, and the history is that of the reduced system (its
        bounds are bounds for A x = y too).
    consistent : bool
        False when A is rank deficient and y is not in its range: no x solves
        A x = y (``converged`` False, x NaN, ``reason`` gives the part of y
        outside the range).
    """

    x: np.ndarray
    norm: float
    bound: float
    converged: bool
    method: str
    iterations: int = 0
    saturated: tuple = ()
    free: tuple = ()
    reason: str = ""
    history: tuple = field(default=(), repr=False)
    rank: int | None = None
    consistent: bool = True


def checked_system(A, y):
    """``A`` and ``y`` as float arrays (copies), or ValueError naming what is wrong with them."""
    A = np.array(A, dtype=float, copy=True)
    y = np.array(y, dtype=float, copy=True).reshape(-1)
    if A.ndim != 2 or A.shape[0] == 0 or A.shape[1] < A.shape[0]:
        raise ValueError(f"A must be an m x n matrix with 1 <= m <= n, got shape {A.shape}")
    if y.shape != (A.shape[0],):
        raise ValueError(f"y must have {A.shape[0]} entries (the rows of A), got {y.shape[0]}")
    if not (np.all(np.isfinite(A)) and np.all(np.isfinite(y))):
        raise ValueError("A and y must be finite")
    return A, y



def on_range(A, y, method, solve):
    """``solve(A, y)`` on a system of full row rank: A itself, or A reduced to its range.

    ``A`` and ``y`` are checked (:func:`checked_system`).  y = 0 gives x = 0 at once.  A of rank
    r < m: when y is in the range of A (INF_NORM_RANGE_RTOL), ``solve`` gets the r x n
    system S_r V_r' x = U_r' y of the SVD A = U S V', with the same solutions; when it is
    not, the result says so.  Every result carries the rank.
    """
    m, n = A.shape
    s = np.linalg.svd(A, compute_uv=False)
    r = int(np.sum(s > RANK_RTOL * s[0])) if s[0] > 0 else 0
    if not np.any(y):
        return InfNormSolution(np.zeros(n), 0.0, 0.0, True, method, rank=r)
    if r == m:
        return dataclasses.replace(solve(A, y), rank=m)
    U, s, Vt = np.linalg.svd(A, full_matrices=False)
    outside = float(np.linalg.norm(U[:, r:].T @ y)) / float(np.linalg.norm(y))
    if outside > INF_NORM_RANGE_RTOL:
        return InfNormSolution(np.full(n, np.nan), np.nan, np.nan, False, method,
                               reason=f"y is not in the range of A (rank {r} < {m}): its part "
                                      f"outside the range is {outside:.1e} of |y|, so no x "
                                      f"solves A x = y",
                               rank=r, consistent=False)
    return dataclasses.replace(solve(s[:r, None] * Vt[:r], U[:, :r].T @ y), rank=r)


def solution(x, bound, converged, method, it, sat, free, history, reason=""):
    """The :class:`InfNormSolution` of an exchange method stopped at ``x`` after ``it`` steps."""
    return InfNormSolution(x=x, norm=float(np.max(np.abs(x))), bound=float(bound),
                           converged=converged, method=method, iterations=it,
                           saturated=tuple(int(j) for j in sat), free=tuple(int(j) for j in free),
                           reason=reason, history=tuple(history))
