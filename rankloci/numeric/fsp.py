"""The FSP reducer: ReduceA, mat_null and CheckB of ORNL/TM-12816.

A port of the matrix-reduction step of the Full Space Parameterization (FSP)
method: K. A. Morgansen and F. G. Pin, *Enhanced Code for the Full Space
Parameterization Approach to Solving Underspecified Systems of Algebraic
Equations*, ORNL/TM-12816 (1995), section 4 (flow chart of Fig. 1) and the C
listings ``ReduceA`` and ``CheckB`` (FSP.c) and ``mat_null`` (matrix.c) of
appendix B.  ``mat_null`` lives in :mod:`rankloci.numeric.fsp_null_space`
(:func:`null_space` and :class:`NullSpace` are importable from here too), the
checks of the inputs in :mod:`rankloci.numeric.fsp_inputs`.

Given ``A`` (n x m) and ``b`` of the system ``A x = b``,
:func:`reduced_system`

1. sets the zero threshold ``SMALL = small_fraction * max|A_ij|``; an entry
   with ``|A_ij| <= SMALL`` counts as zero;
2. sweeps the rows in order.  A row with exactly one nonzero entry ``A_ij`` is
   *restricted*: it fixes ``x_j = b_i / A_ij``, which is back-substituted
   (``b -= x_j * A[:, j]``), column ``j`` is set to zero and the row is
   marked.  A row with no nonzero entry left is marked as a row of zeros.
   Sweeps repeat until a whole sweep marks no row, so a restriction that
   empties all but one entry of another row restricts that row too;
3. marks the columns of zeros of ``A``;
4. marks dependent rows: it takes the null space of the transpose of what is
   left (:func:`null_space`), and for each null vector the first row whose
   component reaches ``n_bnd = 0.9 / (N + 1)``, N the number of rows of A, is
   dependent and removed.

What is left is the reduced system; :func:`is_trivial_motion` (``CheckB``)
tells whether its right-hand side is all zeros, the report's "completely
restricted" case (section 6.3).  All indices are 0-based, as in the C code
(the report's prose counts from 1).  Computation is in double precision (the
listing uses ``float``).

Deviations from the listing
---------------------------
Each is a defect of the C code; the behaviour section 4 describes is kept.
Deviations 1 to 3 are those of ``mat_null`` and are described with it in
:mod:`rankloci.numeric.fsp_null_space`.

4. ReduceA scans a null vector for the first component reaching N_BND with no
   bound on the index.  A unit vector of length N always has a component of
   at least ``1/sqrt(N) > 0.9/(N+1)``, so with the default N_BND this cannot
   run off; with a larger ``n_bnd`` it can, and then the row of the largest
   component is taken.
5. ReduceA marks a row for every null vector, also a row that an earlier null
   vector already marked (``RowElim[j] != 1``; it then counts it twice in
   Nred), and two null vectors can name the same row, leaving the reduced
   matrix rank deficient.  Here the null vectors are taken in turn, each with
   its components at the rows already marked eliminated (Gaussian elimination
   within the null space) and normalized before the scan, so each marks
   another row and the rows kept are independent.  With one null vector (all
   of section 6) nothing changes.
6. ReduceA takes the null space of the original ``A^T``, restricted rows and
   rows of zeros included, and ignores a null vector whose first large
   component falls on a row already eliminated.  A dependency among the rows
   kept that runs through a restricted row is then missed: with rows
   ``(1, 0, 0)``, ``(1, 1, 1)``, ``(0, 1, 1)`` the first is restricted and the
   other two become equal, but the only null vector ``(1, -1, 1)/sqrt(3)``
   names row 0.  Here the null space is that of the rows and columns left
   after steps 2 and 3, so every null vector is a dependency of the reduced
   system (section 4 makes the dependency check the final step).
7. The listing counts ``|a| > SMALL`` as nonzero when sweeping rows but
   ``|a| < SMALL`` as zero when looking for columns of zeros (and in
   CheckB), so an entry equal to SMALL was both; a column of such entries
   stayed in the reduced matrix.  Here ``|a| <= SMALL`` is zero everywhere.
8. CheckB tests ``if (i=m)``, an assignment, and so reports every right-hand
   side as all zeros.  :func:`is_trivial_motion` compares.

The thresholds are parameters with the listing's values as defaults
(:mod:`rankloci.tolerances`); :mod:`rankloci.numeric.fsp_null_space` says why
the condition-number bound of the null space step is not the report's 10.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ShapeError
from ..tolerances import (
    FSP_N_BND_NUMERATOR,
    FSP_NULL_K2_BND,
    FSP_SMALL_FRACTION,
    FSP_SV_SMALL,
)
from .fsp_inputs import check_number, finite_matrix, finite_vector
from .fsp_null_space import NullSpace, null_space

__all__ = [
    "Restriction",
    "NullSpace",
    "ReduceResult",
    "reduced_system",
    "null_space",
    "is_trivial_motion",
    "dependent_rows",
]


@dataclass(frozen=True, slots=True)
class Restriction:
    """A component of x fixed by a row with a single nonzero entry.

    Attributes
    ----------
    row : int
        Row of A (0-based) with exactly one nonzero entry left.
    column : int
        Column of A (0-based) of that entry: the component of x it fixes.
    value : float
        ``x[column] = b[row] / A[row, column]``, with ``b`` as modified by the
        restrictions found before this one.
    """

    row: int
    column: int
    value: float


@dataclass(frozen=True, slots=True, eq=False)
class ReduceResult:
    """The system ``A x = b`` reduced by :func:`reduced_system`.

    All indices are 0-based indices into the original A and b.

    Attributes
    ----------
    a : numpy.ndarray, shape (len(rows), len(columns))
        The reduced A: the original entries of the rows and columns kept.
        Read-only.
    b : numpy.ndarray, shape (len(rows),)
        The reduced b, after back-substitution of the restrictions.
        Read-only.
    shape : tuple of int
        ``(n, m)``, the shape of the original A.
    restrictions : tuple of Restriction
        The restricted components, in the order they were found.
    zero_rows : tuple of int
        Rows with no nonzero entry, in A as given or once the columns of
        earlier restrictions were set to zero (as in the listing, both are
        rows of zeros).
    zero_columns : tuple of int
        Columns of A with no nonzero entry.
    dependent_rows : tuple of int
        Rows marked dependent from the null space.
    small : float
        The zero threshold SMALL.
    """

    a: np.ndarray
    b: np.ndarray
    shape: tuple[int, int]
    restrictions: tuple[Restriction, ...]
    zero_rows: tuple[int, ...]
    zero_columns: tuple[int, ...]
    dependent_rows: tuple[int, ...]
    small: float

    @property
    def eliminated_rows(self) -> tuple[int, ...]:
        """Rows removed: restricted, of zeros or dependent (sorted)."""
        return tuple(sorted([r.row for r in self.restrictions]
                            + list(self.zero_rows) + list(self.dependent_rows)))

    @property
    def eliminated_columns(self) -> tuple[int, ...]:
        """Columns removed: restricted or of zeros (sorted)."""
        return tuple(sorted([r.column for r in self.restrictions]
                            + list(self.zero_columns)))

    @property
    def rows(self) -> tuple[int, ...]:
        """Original index of each row of :attr:`a`."""
        gone = set(self.eliminated_rows)
        return tuple(i for i in range(self.shape[0]) if i not in gone)

    @property
    def columns(self) -> tuple[int, ...]:
        """Original index of each column of :attr:`a`."""
        gone = set(self.eliminated_columns)
        return tuple(j for j in range(self.shape[1]) if j not in gone)

    @property
    def x_fixed(self) -> np.ndarray:
        """Length-m x holding the restricted values, zero elsewhere (Xelim)."""
        x = np.zeros(self.shape[1])
        for r in self.restrictions:
            x[r.column] = r.value
        return x

    @property
    def completely_restricted(self) -> bool:
        """Whether the reduced b is all zeros (CheckB returning 0)."""
        return is_trivial_motion(self.b, self.small)


def _check_thresholds(small_fraction, sv_small, k2_bnd, n_bnd) -> None:
    check_number("small_fraction", small_fraction, 0.0, 1.0, low_inclusive=True)
    check_number("sv_small", sv_small, 0.0)
    check_number("k2_bnd", k2_bnd, 0.0)
    if n_bnd is not None:
        check_number("n_bnd", n_bnd, 0.0, 1.0)


def is_trivial_motion(b, small: float) -> bool:
    """Whether every component of `b` is zero, as the listing's ``CheckB``.

    CheckB returns 0 ("completely restricted", section 6.3) when no
    ``|b_i|`` exceeds SMALL, and the length of `b` otherwise.

    Parameters
    ----------
    b : array_like, shape (k,)
        Right-hand side, usually the reduced b.
    small : float
        Zero threshold, the reducer's SMALL; ``|b_i| <= small`` is zero.

    Returns
    -------
    bool
        True when all components are zero (also when `b` is empty).

    Examples
    --------
    >>> is_trivial_motion([0.0, 5e-4], small=1e-3)
    True
    >>> is_trivial_motion([0.0, 0.01], small=1e-3)
    False
    """
    vec = np.asarray(b, dtype=float)
    if vec.ndim != 1:
        raise ShapeError(f"b must be 1-D, got shape {vec.shape}")
    return bool(np.all(np.abs(vec) <= small))


def _restrictions(a: np.ndarray, b: np.ndarray, small: float):
    """Sweep the rows for restrictions and rows of zeros (ReduceA's loop).

    Returns the back-substituted b, the restrictions in the order found and
    the rows of zeros.
    """
    work = a.copy()
    rhs = b.copy()
    eliminated = np.zeros(a.shape[0], dtype=bool)
    restrictions: list[Restriction] = []
    zero_rows: list[int] = []
    found = True
    while found:
        found = False
        for i in np.flatnonzero(~eliminated):
            nonzero = np.flatnonzero(np.abs(work[i]) > small)
            if nonzero.size > 1:
                continue
            eliminated[i] = found = True
            if nonzero.size == 0:
                zero_rows.append(int(i))
                continue
            j = int(nonzero[0])
            value = rhs[i] / work[i, j]
            rhs -= value * work[:, j]
            work[:, j] = 0.0
            restrictions.append(Restriction(row=int(i), column=j,
                                            value=float(value)))
    return rhs, tuple(restrictions), tuple(sorted(zero_rows))


def _dependent_indices(vectors: np.ndarray, n_bnd: float) -> list[int]:
    """Row marked by each null vector (ReduceA's scan, deviations 4 and 5)."""
    marked: list[int] = []
    pivots: list[np.ndarray] = []
    for v in vectors.T:
        v = v.copy()
        for p, w in zip(marked, pivots):
            v -= (v[p] / w[p]) * w
        v[marked] = 0.0
        v /= np.linalg.norm(v)
        large = np.flatnonzero(np.abs(v) >= n_bnd)
        marked.append(int(large[0]) if large.size else int(np.argmax(np.abs(v))))
        pivots.append(v)
    return marked


def _read_only(x: np.ndarray) -> np.ndarray:
    x.setflags(write=False)
    return x


def reduced_system(A, b=None, *, small_fraction: float = FSP_SMALL_FRACTION,
                   sv_small: float = FSP_SV_SMALL,
                   k2_bnd: float = FSP_NULL_K2_BND,
                   n_bnd: float | None = None) -> ReduceResult:
    """Reduce ``A x = b`` as the FSP code's ``ReduceA`` (report section 4).

    Restricted rows fix their component of x and are removed with that
    column; rows and columns of zeros are removed; then dependent rows are
    removed.  See the module docstring for the steps and for where this
    departs from the C listing.  Inputs are not modified.

    Parameters
    ----------
    A : array_like, shape (n, m)
        The matrix (in the report a 6 x 10 Jacobian).
    b : array_like, shape (n,), optional
        The right-hand side (the report's dx); zeros if omitted, which changes
        the restricted values but nothing else.
    small_fraction : float, optional
        ``SMALL = small_fraction * max|A_ij|``; the report divides by 1000.
    sv_small : float, optional
        Absolute singular value threshold of :func:`null_space` (SV_SMALL).
    k2_bnd : float, optional
        Condition-number bound of :func:`null_space` (``1/SV_SMALL``; see the
        module docstring for why not the report's K2_BND = 10).
    n_bnd : float, optional
        A null vector names the first row whose component reaches it.
        Default ``0.9 / (n + 1)``, n the number of rows of A (ReduceA's
        ``N_BND = 0.9/(N+1)``).

    Returns
    -------
    ReduceResult
        Reduced A and b, restrictions, rows and columns of zeros, dependent
        rows, all with 0-based indices into A.

    Raises
    ------
    ShapeError
        If `A` is not 2-D or `b` does not have one entry per row of A.
    ValueError
        If an input is not finite or a threshold is out of range.

    Examples
    --------
    >>> import numpy as np
    >>> A = np.array([[2.0, 0.0, 0.0, 0.0],
    ...               [1.0, 1.0, 1.0, 0.0],
    ...               [0.0, 0.0, 0.0, 0.0]])
    >>> r = reduced_system(A, [4.0, 5.0, 0.0])
    >>> r.restrictions
    (Restriction(row=0, column=0, value=2.0),)
    >>> r.zero_rows, r.zero_columns, r.dependent_rows
    ((2,), (3,), ())
    >>> r.a, r.b
    (array([[1., 1.]]), array([3.]))
    >>> r.rows, r.columns
    ((1,), (1, 2))
    """
    a = finite_matrix(A, "A")
    n, m = a.shape
    rhs = np.zeros(n) if b is None else finite_vector(b, n, "b")
    _check_thresholds(small_fraction, sv_small, k2_bnd, n_bnd)
    if n_bnd is None:
        n_bnd = FSP_N_BND_NUMERATOR / (n + 1)
    small = small_fraction * float(np.max(np.abs(a), initial=0.0))

    rhs, restrictions, zero_rows = _restrictions(a, rhs, small)
    zero_columns = tuple(int(j) for j in
                         np.flatnonzero(~np.any(np.abs(a) > small, axis=0)))
    gone_rows = {r.row for r in restrictions} | set(zero_rows)
    gone_columns = {r.column for r in restrictions} | set(zero_columns)
    rows = [i for i in range(n) if i not in gone_rows]
    columns = [j for j in range(m) if j not in gone_columns]

    core = a[np.ix_(rows, columns)]
    null = null_space(core.T, sv_small=sv_small, k2_bnd=k2_bnd)
    dependent = tuple(sorted(rows[k] for k in
                             _dependent_indices(null.vectors, n_bnd)))
    kept = [i for i in rows if i not in dependent]

    return ReduceResult(
        a=_read_only(a[np.ix_(kept, columns)]),
        b=_read_only(rhs[kept]),
        shape=(n, m),
        restrictions=restrictions,
        zero_rows=zero_rows,
        zero_columns=zero_columns,
        dependent_rows=dependent,
        small=small,
    )


def dependent_rows(A, *, small_fraction: float = FSP_SMALL_FRACTION,
                   sv_small: float = FSP_SV_SMALL,
                   k2_bnd: float = FSP_NULL_K2_BND,
                   n_bnd: float | None = None) -> tuple[int, ...]:
    """Rows of `A` the reducer finds dependent on the rows it keeps.

    These are the rows :func:`reduced_system` removes for lack of rank: its
    ``dependent_rows`` (from the null space) together with its ``zero_rows``
    (a row of zeros is the simplest dependent row, and section 3 of the
    report says it "may be dealt with in the same manner as A having
    dependent rows"; a row emptied by back-substitution is a combination of
    restricted rows).  Restricted rows are independent of all others, so for
    exact data the number of rows returned is ``n - rank(A)``, and a
    rank-deficient A always has at least one.

    Parameters
    ----------
    A : array_like, shape (n, m)
        The matrix.
    small_fraction, sv_small, k2_bnd, n_bnd : float, optional
        Thresholds, as in :func:`reduced_system`.

    Returns
    -------
    tuple of int
        Sorted 0-based row indices; empty when A has full row rank.

    Examples
    --------
    >>> import numpy as np
    >>> dependent_rows(np.array([[1.0, 2.0, 0.0],
    ...                          [2.0, 4.0, 0.0],
    ...                          [0.0, 1.0, 1.0]]))
    (0,)
    >>> dependent_rows(np.array([[0.0, 0.0], [3.0, 1.0]]))
    (0,)
    >>> dependent_rows(np.eye(3))
    ()
    """
    result = reduced_system(A, small_fraction=small_fraction,
                            sv_small=sv_small, k2_bnd=k2_bnd, n_bnd=n_bnd)
    return tuple(sorted(result.zero_rows + result.dependent_rows))
