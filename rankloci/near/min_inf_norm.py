"""Minimum infinity-norm solutions of underdetermined linear systems A x = y.

Three interchangeable methods share one contract, :func:`min_inf_norm`:

- ``"ha_lee"`` (the default): the algorithm of I. Ha and J. Lee, *Analysis on
  a Minimum Infinity-norm Solution for Kinematically Redundant Manipulators*,
  section III.2, steps 1 to 13.  It starts from the minimum two-norm solution
  x2 = A^+ y and a null-space basis N, and finds z in x = x2 + N z from the
  n - m + 1 saturated components (their theorem 3), exchanging columns with
  Cadzow's rule.  It needs no Haar condition.
- ``"cadzow"``: J. A. Cadzow's column-exchange algorithm (SIAM J. Numer. Anal.
  10(4), 1973), C-steps 1 to 11 as Ha and Lee summarise them, kept as the
  baseline.  It needs the Haar condition (every m columns of A independent);
  where that fails it can cycle, which :func:`~rankloci.near.cadzow.cadzow`
  records.
- ``"lp"``: the linear program min t subject to A x = y, -t <= x_i <= t,
  solved by scipy's HiGHS: the independent check.

Every method returns an :class:`InfNormSolution`; a method that does not
reach a certified optimum says so in ``converged`` and ``reason``.

A of full row rank is solved as it is.  A rank-deficient A (rank r < m, decided
at RANK_RTOL) is solved on its range: when y lies in the range of A, A x = y has
the same solutions as the r x n system S_r V_r' x = U_r' y of its SVD, which has
full row rank and goes to the method; when y does not, no x solves A x = y and
the result says so (``consistent`` False, x NaN).
"""

from __future__ import annotations

import itertools

import numpy as np

from ..tolerances import INF_NORM_RTOL, INF_NORM_ZERO_RTOL, MAX_SIGN_CHOICES, RANK_RTOL
from .inf_norm import InfNormSolution, checked_system, on_range, solution

__all__ = ["METHODS", "InfNormSolution", "min_inf_norm", "ha_lee", "linear_program",
           "haar_condition", "sign_choices", "MAX_SIGN_CHOICES"]

#: The methods of :func:`min_inf_norm`.
METHODS = ("ha_lee", "cadzow", "lp")


def haar_condition(A) -> bool:
    """Whether every set of m columns of the m x n matrix A is linearly independent.

    Examples
    --------
    >>> haar_condition([[0.7, 0.1, -1.6], [2.0, -0.2, 0.6]])
    True
    >>> haar_condition([[1, 2, 3, 4], [1, 2, 3, 5]])
    False
    """
    A = np.asarray(A, dtype=float)
    m, n = A.shape
    scale = np.linalg.norm(A, 2)
    for cols in itertools.combinations(range(n), m):
        s = np.linalg.svd(A[:, cols], compute_uv=False)
        if s[-1] <= RANK_RTOL * scale:
            return False
    return True


def _dual_vector(A1, y, m):
    """Steps 4-5: the unit vector orthogonal to the columns of A_1, oriented so y'nu >= 0."""
    if A1.shape[1] == 0:
        nu = np.ones(m)
    else:
        U = np.linalg.svd(A1, full_matrices=True)[0]
        nu = U[:, -1]
    return nu if y @ nu >= 0 else -nu


def sign_choices(g, fallback, limit: int = MAX_SIGN_CHOICES):
    """Sign vectors of ``g`` in which each zero entry (|g_i| <= INF_NORM_ZERO_RTOL) takes +-1.

    The first choice gives each zero entry the sign of ``fallback`` (+1 where that is 0
    too); with k <= ``limit`` zero entries all 2**k choices follow.

    Examples
    --------
    >>> g, x2 = np.array([0.0, 0.0, -1.0]), np.array([1.0, -1.0, 0.0])
    >>> [list(map(int, s)) for s in sign_choices(g, x2)]
    [[1, -1, -1], [1, 1, -1], [-1, -1, -1], [-1, 1, -1]]
    """
    zero = np.abs(g) <= INF_NORM_ZERO_RTOL
    base = np.where(zero, np.where(fallback < 0, -1.0, 1.0), np.sign(g))
    yield base
    idx = np.flatnonzero(zero)
    if 0 < len(idx) <= limit:
        for flips in itertools.product((False, True), repeat=len(idx)):
            if any(flips):
                s = base.copy()
                s[idx[list(flips)]] *= -1
                yield s


def _saturated_solution(S, N, x2, sat):
    """Steps 6-8: x = x2 + N z with S_i x_i equal over the saturated columns (None if singular)."""
    B = S[:, None] * N[sat]
    chi = S * x2[sat]
    Bf = B[:-1] - B[-1]
    chif = chi[-1] - chi[:-1]
    if Bf.shape[0] == 0:
        return x2.copy()
    try:
        z = np.linalg.solve(Bf, chif)
    except np.linalg.LinAlgError:
        return None
    if not np.all(np.isfinite(z)):
        return None
    return x2 + N @ z


def ha_lee(A, y, *, max_iter: int | None = None) -> InfNormSolution:
    """Ha and Lee's minimum infinity-norm solution of A x = y (A of full row rank).

    Parameters
    ----------
    A : array_like, shape (m, n), m <= n
    y : array_like, shape (m,)
    max_iter : int, optional
        Column exchanges allowed (default 50 n).

    Returns
    -------
    InfNormSolution
        ``converged`` False, with the reason, when the exchanges do not reach a
        certified optimum, or when A is rank deficient and y is not in its range
        (``consistent`` False).  A rank-deficient A with y in its range is
        solved on its range.

    Examples
    --------
    >>> s = ha_lee([[0.7, 0.1, -1.6], [2.0, -0.2, 0.6]], [-1.0, 0.2])
    >>> np.round(s.x, 4), s.converged
    (array([-0.1162, -0.5404,  0.5404]), True)

    Rank one, y in the range: the solutions are those of x1 + 2 x2 + 3 x3 = 1.

    >>> s = ha_lee([[1, 2, 3], [2, 4, 6]], [1, 2])
    >>> round(s.norm, 12), s.rank, s.converged
    (0.166666666667, 1, True)
    >>> ha_lee([[1, 2, 3], [2, 4, 6]], [1, 0]).consistent
    False
    """
    A, y = checked_system(A, y)
    return on_range(A, y, "ha_lee", lambda A, y: _ha_lee(A, y, max_iter))


def _ha_lee(A, y, max_iter):
    """Steps 1 to 13 on A of full row rank and y != 0."""
    m, n = A.shape
    max_iter = 50 * n if max_iter is None else max_iter
    # step 1: minimum two-norm solution and an orthonormal null-space basis
    U, s, Vt = np.linalg.svd(A, full_matrices=True)
    x2 = Vt[:m].T @ ((U.T @ y) / s)
    N = Vt[m:].T
    # steps 2-3: A_1 from the m - 1 smallest |x2_i| (skipping a column dependent on those taken)
    free = []
    for j in np.argsort(np.abs(x2), kind="stable").tolist():
        if len(free) < m - 1 and _independent(A, free + [j], s[0]):
            free.append(j)
    free.sort()
    history, seen = [], set()
    x, bound = x2, 0.0
    for it in range(max_iter + 1):
        sat = [j for j in range(n) if j not in free]
        nu = _dual_vector(A[:, free], y, m)
        g = A[:, sat].T @ nu
        u = nu / np.abs(g).sum()                      # step 5: ||A_2'u||_1 = 1
        g = A[:, sat].T @ u
        bound = float(y @ u)
        best = None
        for S in sign_choices(g, x2[sat]):            # step 6, sgn(0) = +-1
            cand = _saturated_solution(S, N, x2, sat)
            if cand is None:
                continue
            x1n = float(np.max(np.abs(cand[free]))) if free else 0.0
            if best is None or x1n < best[1]:
                best = (cand, x1n, S)
            if x1n <= (1 + INF_NORM_RTOL) * bound:    # step 9(a)
                break
        zeros = [sat[i] for i in np.flatnonzero(np.abs(g) <= INF_NORM_ZERO_RTOL)]
        if best is None:
            history.append(dict(free=tuple(free), bound=bound, x1_norm=np.inf, zeros=zeros))
            return solution(np.full(n, np.nan), bound, False, "ha_lee", it, sat, free, history,
                           "the saturated components give a singular system for every sign choice")
        x, x1n, S = best
        history.append(dict(free=tuple(free), bound=bound, x1_norm=x1n, zeros=zeros))
        if x1n <= (1 + INF_NORM_RTOL) * bound:
            return solution(x, bound, True, "ha_lee", it, sat, free, history)
        if tuple(free) in seen:
            return solution(x, bound, False, "ha_lee", it, sat, free, history,
                           f"the column exchange returned to the basis {tuple(free)} (cycling)")
        seen.add(tuple(free))
        free = _exchange(A, u, x, free, sat, S)
    return solution(x, bound, False, "ha_lee", max_iter, sat, free, history,
                   f"no certified optimum after {max_iter} column exchanges")


def _exchange(A, u, x, free, sat, S):
    """Steps 10-13 (Cadzow's rule): the new free columns after one exchange.

    Step 12's ratio -[A_2'gamma]_i / [A_2'u]_i is 1/eps for the step eps at which entry i
    of A_2'(u + eps gamma) reaches zero.  An entry that is zero already (no Haar
    condition) has the sign S_i chosen for it: it limits the step at once (ratio +inf)
    when gamma moves it against S_i, and never otherwise (ratio -inf).
    """
    m = A.shape[0]
    p = int(np.argmax(np.abs(x[free])))                       # step 10
    rhs = np.zeros(m)
    rhs[p] = np.sign(x[free[p]])
    M = np.vstack([A[:, free].T, u])                          # step 11, b = u
    gamma = np.linalg.lstsq(M, rhs, rcond=None)[0]
    num = -(A[:, sat].T @ gamma)
    den = A[:, sat].T @ u
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(np.abs(den) > INF_NORM_ZERO_RTOL, num / den,
                         np.where(S * num > 0, np.inf, -np.inf))  # step 12
    scale = np.linalg.norm(A, 2)
    for q in np.argsort(-ratio, kind="stable"):
        new = list(free)
        new[p] = sat[q]                                       # step 13
        if _independent(A, new, scale):
            return sorted(new)
    return sorted(free)


def _independent(A, cols, scale) -> bool:
    """Whether the columns ``cols`` of A are linearly independent (RANK_RTOL of ``scale``).

    Without the Haar condition the column of largest ratio in step 12 can be parallel
    to a column kept in A_1; A_1 then loses rank and u is no longer determined.  The
    exchange takes the largest ratio whose column keeps A_1 of full rank.
    """
    if not cols:
        return True
    s = np.linalg.svd(A[:, cols], compute_uv=False)
    return bool(s[-1] > RANK_RTOL * scale)


def linear_program(A, y) -> InfNormSolution:
    """The minimum infinity-norm solution as a linear program (scipy HiGHS).

    min t subject to A x = y and -t <= x_i <= t.  A rank-deficient A is handled as
    by every method: solved on its range when y is in it, reported otherwise.

    Examples
    --------
    >>> s = linear_program([[1, 2, 3, 4], [1, 2, 3, 5]], [1, 0])
    >>> round(s.norm, 6), s.converged
    (1.0, True)
    """
    A, y = checked_system(A, y)
    return on_range(A, y, "lp", _linear_program)


def _linear_program(A, y):
    """The linear program on A of full row rank and y != 0."""
    from scipy.optimize import linprog

    m, n = A.shape
    c = np.zeros(n + 1)
    c[-1] = 1.0
    eye = np.eye(n)
    A_ub = np.block([[eye, -np.ones((n, 1))], [-eye, -np.ones((n, 1))]])
    A_eq = np.hstack([A, np.zeros((m, 1))])
    res = linprog(c, A_ub=A_ub, b_ub=np.zeros(2 * n), A_eq=A_eq, b_eq=y,
                  bounds=[(None, None)] * n + [(0, None)], method="highs")
    if res.status != 0:
        return InfNormSolution(np.full(n, np.nan), np.nan, np.nan, False, "lp",
                               reason=f"HiGHS: {res.message}")
    x = res.x[:n]
    t = float(res.x[-1])
    at_norm = np.abs(np.abs(x) - t) <= INF_NORM_RTOL * max(t, 1e-300)
    sat = tuple(int(j) for j in np.flatnonzero(at_norm))
    return InfNormSolution(x=x, norm=float(np.max(np.abs(x))), bound=t, converged=True, method="lp",
                           iterations=int(getattr(res, "nit", 0)), saturated=sat,
                           free=tuple(j for j in range(n) if j not in sat))


def min_inf_norm(A, y, *, method: str = "ha_lee") -> InfNormSolution:
    """The solution of A x = y of least ``max |x_i|``, by ``method``.

    Parameters
    ----------
    A : array_like, shape (m, n), m <= n
        Of full row rank, or rank deficient with y in its range (then solved on
        its range: see :mod:`rankloci.near.min_inf_norm`).
    y : array_like, shape (m,)
    method : {"ha_lee", "cadzow", "lp"}

    Returns
    -------
    InfNormSolution
        ``consistent`` is False, and x NaN, when A is rank deficient and y is
        not in its range: no x solves A x = y.

    Raises
    ------
    ValueError
        ``method`` is not one of the three; A is not m x n with 1 <= m <= n;
        y does not have m entries; A or y is not finite.

    Examples
    --------
    >>> A, y = [[1, 2, 3, 4], [1, 2, 3, 5]], [1, 0]
    >>> (min_inf_norm(A, y).x.round(6) + 0.0).tolist()   # + 0.0: no signed zero
    [0.0, 1.0, 1.0, -1.0]
    >>> min_inf_norm(A, y, method="cadzow").converged
    False
    """
    if method == "ha_lee":
        return ha_lee(A, y)
    if method == "lp":
        return linear_program(A, y)
    if method == "cadzow":
        from .cadzow import cadzow

        return cadzow(A, y)
    raise ValueError(f"method={method!r}: choose one of {', '.join(METHODS)}")
