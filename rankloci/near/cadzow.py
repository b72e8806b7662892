"""Cadzow's column-exchange algorithm for the minimum infinity-norm solution (the baseline).

J. A. Cadzow, "A finite algorithm for the minimum l-infinity solution to a
system of consistent linear equations", SIAM J. Numer. Anal. 10(4), 607-617
(1973), in the form of C-steps 1 to 11 of Ha and Lee, section II.1.  It keeps
a dual vector u orthogonal to m - 1 columns (A_1) with ||A_2'u||_1 = 1, sets
the other components to x_2 = (y'u) sgn(A_2'u) with sgn(0) = 0, solves A_1 x_1
for the rest, and exchanges columns until ||x_1||_inf <= y'u.

The algorithm assumes the Haar condition: every m columns of A independent.
Without it, columns of A_2 in the span of A_1 give zero entries of A_2'u: their
x_2 components are set to 0 instead of +-y'u, x_1 must absorb them and exceeds
y'u even when u is optimal, and the ratios of C-step 9 divide by zero.  The
exchange then cycles; :func:`cadzow` stops when a basis repeats and returns
the iterations in ``history``.
"""

from __future__ import annotations

import numpy as np

from ..tolerances import INF_NORM_RTOL, INF_NORM_ZERO_RTOL
from .inf_norm import InfNormSolution, checked_system, on_range, solution

__all__ = ["cadzow"]


def _initial_free(A):
    """C-step 1: the first m - 1 linearly independent columns, in column order."""
    m, n = A.shape
    free = []
    for j in range(n):
        if len(free) == m - 1:
            break
        trial = free + [j]
        if np.linalg.matrix_rank(A[:, trial]) == len(trial):
            free = trial
    return free


def cadzow(A, y, *, max_iter: int | None = None) -> InfNormSolution:
    """Cadzow's minimum infinity-norm solution of A x = y.

    Parameters
    ----------
    A : array_like, shape (m, n), m <= n
        Rank deficient: solved on its range when y is in it, as by every method
        of :func:`~rankloci.near.min_inf_norm.min_inf_norm`.
    y : array_like, shape (m,)
    max_iter : int, optional
        Column exchanges allowed (default 50 n).

    Returns
    -------
    InfNormSolution
        ``converged`` False, with the reason, when a basis repeats (cycling,
        which happens where the Haar condition fails) or ``max_iter`` runs out,
        or when A is rank deficient and y is not in its range (``consistent``
        False).

    Examples
    --------
    >>> s = cadzow([[0.7, 0.1, -1.6], [2.0, -0.2, 0.6]], [-1.0, 0.2])
    >>> np.round(s.x, 4), s.converged
    (array([-0.1162, -0.5404,  0.5404]), True)
    """
    A, y = checked_system(A, y)
    return on_range(A, y, "cadzow", lambda A, y: _cadzow(A, y, max_iter))


def _cadzow(A, y, max_iter):
    """C-steps 1 to 11 on A of full row rank and y != 0."""
    m, n = A.shape
    max_iter = 50 * n if max_iter is None else max_iter
    free = _initial_free(A)
    sat = [j for j in range(n) if j not in free]
    # C-steps 2-3: nu orthogonal to A_1, normalised so that ||A_2'u||_1 = 1 and y'u >= 0
    if free:
        nu = np.linalg.svd(A[:, free], full_matrices=True)[0][:, -1]
    else:
        nu = np.ones(m)
    u = nu * (1.0 if y @ nu >= 0 else -1.0) / np.abs(A[:, sat].T @ nu).sum()
    history, seen = [], set()
    x = np.full(n, np.nan)
    for it in range(max_iter + 1):
        sat = [j for j in range(n) if j not in free]
        g = A[:, sat].T @ u
        bound = float(y @ u)                                           # C-step 4
        sgn = np.where(np.abs(g) <= INF_NORM_ZERO_RTOL, 0.0, np.sign(g))
        x = np.empty(n)
        x[sat] = bound * sgn                                           # C-step 5
        rhs = y - A[:, sat] @ x[sat]
        if free:
            x[free] = np.linalg.lstsq(A[:, free], rhs, rcond=None)[0]
        x1n = float(np.max(np.abs(x[free]))) if free else 0.0
        zeros = [sat[i] for i in np.flatnonzero(sgn == 0)]
        history.append(dict(free=tuple(free), bound=bound, x1_norm=x1n, zeros=zeros))
        gap = float(np.linalg.norm(A @ x - y))
        if gap > INF_NORM_RTOL * (np.linalg.norm(y) + np.linalg.norm(A, 2) * np.linalg.norm(x)):
            return solution(x, bound, False, "cadzow", it, sat, free, history,
                           f"C-step 5: A_1 x_1 = y - A_2 x_2 has no solution (residual {gap:.1e}); "
                           f"A_1 = columns {tuple(free)} has rank < m - 1, the Haar condition "
                           "does not hold")
        if x1n <= (1 + INF_NORM_RTOL) * bound:                         # C-step 6(a)
            return solution(x, bound, True, "cadzow", it, sat, free, history)
        state = (tuple(free), round(bound, 12))
        if state in seen:
            why = (f"; A_2'u has zero entries (columns {', '.join(map(str, zeros))}): "
                   "the Haar condition does not hold" if any(h["zeros"] for h in history) else "")
            return solution(x, bound, False, "cadzow", it, sat, free, history,
                           f"the column exchange returned to the basis {tuple(free)} "
                           f"(cycling){why}")
        seen.add(state)
        # C-steps 7-8: p, then gamma with A_1'gamma = sgn(x_1(p)) e_p and u'gamma = 0
        p = int(np.argmax(np.abs(x[free])))
        e = np.zeros(m)
        e[p] = np.sign(x[free[p]])
        gamma = np.linalg.lstsq(np.vstack([A[:, free].T, u]), e, rcond=None)[0]
        num = -(A[:, sat].T @ gamma)
        with np.errstate(divide="ignore", invalid="ignore"):
            inv_eps = num / g                                          # C-step 9
        inv_eps = np.where(np.isnan(inv_eps), -np.inf, inv_eps)
        q = int(np.argmax(inv_eps))
        if inv_eps[q] == 0:
            return solution(x, bound, False, "cadzow", it, sat, free, history,
                           "C-step 9: the largest ratio 1/eps is 0")
        eps = 1.0 / inv_eps[q]
        new_free = list(free)
        new_free[p] = sat[q]                                           # C-step 10
        new_sat = [j for j in range(n) if j not in new_free]
        v = u + eps * gamma                                            # C-step 11
        norm1 = np.abs(A[:, new_sat].T @ v).sum()
        if not np.isfinite(norm1) or norm1 == 0:
            return solution(x, bound, False, "cadzow", it, sat, free, history,
                           "C-step 11 divides by zero: ||A_2'(u + eps gamma)||_1 = 0")
        u = np.sign(eps) * v / norm1
        free = sorted(new_free)
    return solution(x, bound, False, "cadzow", max_iter, sat, free, history,
                   f"no certified optimum after {max_iter} column exchanges")
