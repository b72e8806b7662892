"""Tests of the FSP reducer (rankloci.numeric.fsp).

The worked examples are those of section 6 of K. A. Morgansen, F. G. Pin,
ORNL/TM-12816 (1995): 6x10 Jacobians of a mobile manipulator (seven arm
joints, then base x, base y, base rotation).  The stored text of the report
lost some numbers of these matrices (rows print with nine of their ten
entries); each matrix below says how those were put back, from the report's
own equations.  Indices in the code are 0-based; the comments about the
report count rows and columns from 1, as the report does.
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rankloci.errors import ShapeError
from rankloci.numeric.fsp import (
    Restriction,
    dependent_rows,
    is_trivial_motion,
    null_space,
    reduced_system,
)
from rankloci.tolerances import FSP_K2_BND

# --- Section 6.1 "Typical J and dx", p. 17, eqs. (30)-(31) -----------------
# Columns print in a fixed format: seven arm columns with three decimals, base
# x and y with one, base rotation with three.  Rows 3, 4, 5 and 6 print 9, 9,
# 8 and 9 numbers.  Row 3 lacks a base "0.0" and row 6 a base "0.0" (their
# arm groups are complete).  Row 4's arm group has six numbers: the lost one
# is a 0.000 before the -1.000, which is in column 7; with -1.000 in column 6,
# g^2 of eq. (32) (-0.053 in column 6) would give 0.053 for dx_4 = -0.000.
# Row 5 lacks one arm 0.000 and one base 0.0, put at the end of each group.
# (Eq. (32) is printed to three decimals and fits none of these rows exactly,
# so it decides only between readings.)
J_6_1 = np.array([
    [0.371, -0.635, -0.015, 0.001, -0.000, -0.006, 0.000, 1.0, 0.0, -0.245],
    [-0.860, -0.011, 0.880, 0.000, 0.000, 0.343, 0.000, 0.0, 1.0, -0.528],
    [0.000, -0.867, 0.000, -0.851, -0.343, 0.000, 0.000, 0.0, 0.0, 0.000],
    [0.000, 0.000, -0.021, 0.000, 0.000, 0.000, -1.000, 0.0, 0.0, 0.000],
    [0.000, -1.000, -0.000, -1.000, 0.000, -0.001, 0.000, 0.0, 0.0, 0.000],
    [1.000, 0.000, -1.000, -0.000, -1.000, -0.000, 0.001, 0.0, 0.0, 0.001],
])
DX_6_1 = np.array([0.009, 0.000, 0.001, -0.000, 0.000, 0.018])

# --- Section 6.2 "J with restrictions", p. 18, eqs. (34)-(35) ---------------
# Rows 1-5 print nine numbers; the lost one is a 0.0.  The restricted values
# of eq. (38), x_1..x_5 = (2, -1, 3, 0, -1), place row 1's second 1.0 in
# column 5 (x_5 = 1 - x_1 = -1, and column 4 is a column of zeros, x_4 = 0);
# in rows 2-5 the lost 0.0 is among the trailing zeros.
J_6_2 = np.array([
    [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 2.0, 3.0, 4.0, 5.0],
])
DX_6_2 = np.array([1.0, 2.0, 3.0, 0.0, 5.0, 6.0])

# --- Section 6.3 "Completely restricted J", p. 19, eqs. (41)-(44) -----------
# Rows 2 and 6 of eq. (41) print nine numbers; the reduced system of eq. (43),
# rows 2, 3, 5, 6 without columns 1 and 2, fixes them: the lost 0.0 of row 2
# is between its 1.0 and -0.5, that of row 6 is a leading zero.  Rows 2 and 3
# of eq. (43) print seven numbers and are completed from eq. (41).
J_6_3 = np.array([
    [1.00, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.00, 0.0, 1.0, 0.0, 0.0, 0.0, -0.5, 0.0, 0.0, -0.6],
    [0.00, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.3, 0.0, 0.0],
    [0.01, 0.1, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.00, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 4.0, -3.0],
    [0.00, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 2.0, 3.0, 0.4],
])
DX_6_3 = np.array([0.00, 0.00, 0.00, 0.01, 0.00, 0.00])
J_6_3_REDUCED = np.array([  # eq. (43)
    [1.0, 0.0, 0.0, 0.0, -0.5, 0.0, 0.0, -0.6],
    [0.0, 1.0, 0.0, 0.0, 0.0, 1.3, 0.0, 0.0],
    [0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 4.0, -3.0],
    [0.0, 0.0, 0.0, 1.0, 0.0, 2.0, 3.0, 0.4],
])


# --- Section 6.4 "J with loss of row rank", p. 19, eqs. (48)-(49) -----------
# Eq. (48) carries a stray transpose sign; rows 1, 3, 5, 6 print nine numbers
# and dx five.  The solution vectors of eq. (50) settle rows 1 and 3: g^2 =
# (0, 1, 0, 0, 0, 0, -1.78, -1, 0.66, 0.88) gives row 3 . g^2 = dx_3 = 0 only
# with row 3's last 1.00 in column 8, and row 1 = row 3 + row 4 (the
# dependency of the example) has it there too.  dx: row 1 . g^6 = row 4 . g^6
# = 1 with g^6 = e_1, the rest are 0.  Row 6 lacks a leading 0.00 (g^2, g^4,
# g^5 then solve it).  Row 5 prints "0 0 0 0 1 0 0 0 -3": g^2, g^4 and g^5
# solve it only with 4.00 in column 9, the same row as in eq. (41); reading
# the lost number as 0.00 instead changes nothing the reducer reports, so both
# readings are tested.  (g^3 fits neither row 5 nor row 6 and is misprinted.)
def j_6_4(row_5):
    return np.array([
        [1.00, 2.00, 0.00, 1.00, 0.00, 0.00, 0.00, 1.00, 0.00, 0.00],
        [0.00, 0.00, 1.00, 0.00, 0.00, 0.00, -0.50, 0.00, 0.00, -1.00],
        [0.00, 1.00, 0.00, 1.00, 0.00, 0.00, 0.00, 1.00, 0.00, 0.00],
        [1.00, 1.00, 0.00, 0.00, 0.00, 0.00, 0.00, 0.00, 0.00, 0.00],
        row_5,
        [0.00, 0.00, 0.00, 0.00, 0.00, 1.00, 0.00, 2.00, 3.00, 0.00],
    ])


ROW_5_OF_6_4 = {
    "as-eq50": [0.00, 0.00, 0.00, 0.00, 1.00, 0.00, 0.00, 0.00, 4.00, -3.00],
    "zero-filled": [0.00, 0.00, 0.00, 0.00, 1.00, 0.00, 0.00, 0.00, 0.00, -3.00],
}
DX_6_4 = np.array([1.00, 0.00, 0.00, 1.00, 0.00, 0.00])


# --- The report's examples ---------------------------------------------------

def test_6_1_typical_j_is_not_reduced():
    # "None of the elements of dx are restricted, no rows of J are dependent,
    # and J has no rows or columns of zeros." (section 6.1)
    r = reduced_system(J_6_1, DX_6_1)
    assert r.restrictions == ()
    assert r.zero_rows == () and r.zero_columns == ()
    assert r.dependent_rows == ()
    assert r.rows == tuple(range(6)) and r.columns == tuple(range(10))
    np.testing.assert_array_equal(r.a, J_6_1)
    np.testing.assert_array_equal(r.b, DX_6_1)
    assert r.small == 1.0e-3  # max|J| = 1.0, divided by 1000
    assert not r.completely_restricted


def test_6_1_would_lose_a_row_under_the_text_condition_bound():
    # Why k2_bnd does not default to FSP.h's K2_BND = 10: cond(J) is 12.5, so
    # with 10 the smallest singular value counts as zero and row 3 (1-based)
    # is called dependent, against section 6.1.
    assert null_space(J_6_1.T).condition == pytest.approx(12.454, abs=1e-3)
    assert reduced_system(J_6_1, DX_6_1, k2_bnd=FSP_K2_BND).dependent_rows == (2,)


def test_6_2_restrictions_and_row_of_zeros():
    r = reduced_system(J_6_2, DX_6_2)
    # Eq. (38): x_1..x_5 = (2, -1, 3, 0, -1); x_4 = 0 because column 4 is a
    # column of zeros, the other four are restricted.
    np.testing.assert_array_equal(r.x_fixed, [2.0, -1.0, 3.0, 0.0, -1.0,
                                              0.0, 0.0, 0.0, 0.0, 0.0])
    assert sorted(x.column for x in r.restrictions) == [0, 1, 2, 4]
    assert r.zero_columns == (3,)
    # "After eliminating the restrictions and the row of zeros" (row 4)
    assert sorted(x.row for x in r.restrictions) == [0, 1, 2, 4]
    assert r.zero_rows == (3,)
    assert r.dependent_rows == ()
    # Eqs. (36)-(37): J = [1 2 3 4 5], dx = 6.
    np.testing.assert_array_equal(r.a, [[1.0, 2.0, 3.0, 4.0, 5.0]])
    np.testing.assert_array_equal(r.b, [6.0])
    assert r.rows == (5,) and r.columns == (5, 6, 7, 8, 9)


def test_6_2_is_a_chain_of_restrictions():
    # Only row 3 (1-based) starts with one nonzero entry.  Fixing x_3 leaves
    # one in row 5 (same sweep), and fixing x_1 then leaves one in rows 1 and
    # 2 (next sweep).
    r = reduced_system(J_6_2, DX_6_2)
    assert r.restrictions == (
        Restriction(row=2, column=2, value=3.0),
        Restriction(row=4, column=0, value=2.0),
        Restriction(row=0, column=4, value=-1.0),
        Restriction(row=1, column=1, value=-1.0),
    )


def test_6_3_completely_restricted():
    r = reduced_system(J_6_3, DX_6_3)
    # Eq. (45): the restricted components are x_1 = 0.0 and x_2 = 0.1.  Row 4
    # (0.01, 0.1, 0, ...) has two entries above SMALL = 0.004 until x_1 is
    # fixed by row 1: a chain inside one sweep.
    assert [(x.row, x.column) for x in r.restrictions] == [(0, 0), (3, 1)]
    assert r.restrictions[0].value == 0.0
    assert r.restrictions[1].value == pytest.approx(0.1, rel=1e-15)
    assert r.zero_rows == () and r.zero_columns == () and r.dependent_rows == ()
    # Eqs. (43)-(44).
    assert r.rows == (1, 2, 4, 5) and r.columns == tuple(range(2, 10))
    np.testing.assert_array_equal(r.a, J_6_3_REDUCED)
    np.testing.assert_array_equal(r.b, np.zeros(4))
    # "Since the system is completely restricted, the solution vectors must be
    # found from the nullspace."
    assert r.completely_restricted


@pytest.mark.parametrize("reading", sorted(ROW_5_OF_6_4))
def test_6_4_loss_of_row_rank(reading):
    J = j_6_4(ROW_5_OF_6_4[reading])
    r = reduced_system(J, DX_6_4)
    # "After eliminating the first row, the m - n + 2 = 6 solution vectors"
    assert r.dependent_rows == (0,)
    assert r.restrictions == () and r.zero_rows == () and r.zero_columns == ()
    np.testing.assert_array_equal(r.a, J[1:])
    np.testing.assert_array_equal(r.b, DX_6_4[1:])
    n_red, m_red = r.a.shape
    assert m_red - n_red + 1 == 10 - 6 + 2
    assert dependent_rows(J) == (0,)


@pytest.mark.parametrize("J, dx", [(J_6_1, DX_6_1), (J_6_2, DX_6_2),
                                   (J_6_3, DX_6_3),
                                   (j_6_4(ROW_5_OF_6_4["as-eq50"]), DX_6_4)],
                         ids=["6.1", "6.2", "6.3", "6.4"])
def test_examples_reduced_systems_keep_the_solutions(J, dx):
    # A solution of the reduced system with the restricted values solves the
    # original system (dx is in the range of J in every example).
    r = reduced_system(J, dx)
    x = r.x_fixed
    x[list(r.columns)] = np.linalg.lstsq(r.a, r.b, rcond=None)[0]
    np.testing.assert_allclose(J @ x, dx, rtol=0, atol=1e-12)


# --- Dependent rows of random matrices ---------------------------------------

@pytest.mark.parametrize("seed", range(10))
@pytest.mark.parametrize("shape", [(6, 10), (6, 7), (4, 9)])
def test_constructed_dependent_row_is_found(seed, shape):
    rng = np.random.default_rng(seed)
    n, m = shape
    A = rng.standard_normal((n, m))
    target, *sources = (int(i) for i in rng.choice(n, size=3, replace=False))
    weights = rng.uniform(0.5, 2.0, size=2) * rng.choice([-1.0, 1.0], size=2)
    A[target] = weights @ A[sources]
    r = reduced_system(A)
    assert len(r.dependent_rows) == 1
    assert set(r.dependent_rows) <= {target, *sources}
    assert r.restrictions == () and r.zero_rows == () and r.zero_columns == ()
    assert np.linalg.matrix_rank(r.a) == r.a.shape[0] == n - 1
    assert dependent_rows(A) == r.dependent_rows


@pytest.mark.parametrize("seed", range(10))
def test_two_constructed_dependent_rows_are_found(seed):
    rng = np.random.default_rng(seed)
    A = rng.standard_normal((6, 10))
    rows = [int(i) for i in rng.permutation(6)]
    involved = set(rows)
    A[rows[0]] = rng.uniform(0.5, 2.0, size=2) @ A[rows[2:4]]
    A[rows[1]] = rng.uniform(0.5, 2.0, size=2) @ A[rows[3:5]]
    involved -= {rows[5]}
    r = reduced_system(A)
    assert len(r.dependent_rows) == 2
    assert set(r.dependent_rows) <= involved
    assert np.linalg.matrix_rank(r.a) == r.a.shape[0] == 4


@pytest.mark.parametrize("seed", range(10))
@pytest.mark.parametrize("shape", [(6, 10), (6, 7), (4, 9), (5, 5)])
def test_full_rank_random_matrix_has_no_dependent_row(seed, shape):
    A = np.random.default_rng(seed).standard_normal(shape)
    r = reduced_system(A)
    assert r.dependent_rows == ()
    assert dependent_rows(A) == ()
    np.testing.assert_array_equal(r.a, A)


def test_equal_rows_each_mark_their_own_row():
    # Three equal rows: two null vectors.  The listing could mark the same
    # row for both (deviation 5); here two distinct rows go.
    A = np.random.default_rng(11).standard_normal((6, 10))
    A[3] = A[1]
    A[4] = A[1]
    r = reduced_system(A)
    assert len(r.dependent_rows) == 2
    assert set(r.dependent_rows) <= {1, 3, 4}
    assert np.linalg.matrix_rank(r.a) == 4


def test_dependency_through_a_restricted_row_is_found():
    # Rows 1 and 2 become equal once row 0 fixes x_0; the listing's null
    # vector of the original A^T names row 0 and is skipped (deviation 6).
    A = np.array([[1.0, 0.0, 0.0], [1.0, 1.0, 1.0], [0.0, 1.0, 1.0]])
    r = reduced_system(A, [1.0, 3.0, 2.0])
    assert r.restrictions == (Restriction(row=0, column=0, value=1.0),)
    assert r.dependent_rows == (1,)
    np.testing.assert_array_equal(r.a, [[1.0, 1.0]])
    np.testing.assert_array_equal(r.b, [2.0])
    assert dependent_rows(A) == (1,)


def test_row_of_zeros_counts_as_dependent():
    # A 2-link planar arm, stretched out along y: the x row of J vanishes.
    J = np.array([[0.0, 0.0], [3.0, 1.0]])
    r = reduced_system(J)
    assert r.zero_rows == (0,) and r.dependent_rows == ()
    assert dependent_rows(J) == (0,)


def test_row_emptied_by_back_substitution_is_a_row_of_zeros():
    A = np.array([[2.0, 0.0, 0.0], [4.0, 0.0, 0.0], [1.0, 1.0, 1.0]])
    r = reduced_system(A, [2.0, 4.0, 3.0])
    assert r.restrictions == (Restriction(row=0, column=0, value=1.0),)
    assert r.zero_rows == (1,)
    assert r.zero_columns == ()
    assert dependent_rows(A) == (1,)


# --- Restricted-row chains ---------------------------------------------------

def test_chain_needs_one_sweep_per_link():
    # Upper bidiagonal rows 0-3: only the last starts restricted, and each
    # back-substitution restricts the row above it, which the sweep has
    # passed, so each link takes a sweep.
    A = np.array([
        [1.0, 2.0, 0.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 3.0, 0.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 4.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, 2.0, 0.0, 0.0],
        [1.0, 1.0, 1.0, 1.0, 1.0, 2.0],
        [0.0, 1.0, 0.0, 1.0, 3.0, 1.0],
    ])
    b = np.array([1.0, 2.0, 3.0, 4.0, 5.0, 6.0])
    r = reduced_system(A, b)
    assert [(x.row, x.column) for x in r.restrictions] == [(3, 3), (2, 2),
                                                           (1, 1), (0, 0)]
    x_head = np.linalg.solve(A[:4, :4], b[:4])
    assert [x.value for x in r.restrictions] == [2.0, -5.0, 17.0, -33.0]
    np.testing.assert_allclose(x_head[::-1], [2.0, -5.0, 17.0, -33.0],
                               rtol=1e-14)
    assert r.zero_rows == () and r.zero_columns == () and r.dependent_rows == ()
    np.testing.assert_array_equal(r.a, [[1.0, 2.0], [3.0, 1.0]])
    np.testing.assert_array_equal(r.b, b[4:] - A[4:, :4] @ r.x_fixed[:4])
    assert not r.completely_restricted


def test_chain_inside_one_sweep():
    # Row 0 fixes x_0 and leaves row 1 with one entry, which fixes x_1 and
    # leaves row 2 with one: all in the first sweep.  Row 0's 1e-4 is below
    # SMALL = 2e-3 and never counts as an entry.
    A = np.array([[2.0, 0.0, 1e-4], [1.0, 1.0, 0.0], [0.0, 1.0, 1.0]])
    r = reduced_system(A, [4.0, 3.0, 2.0])
    assert r.restrictions == (Restriction(row=0, column=0, value=2.0),
                              Restriction(row=1, column=1, value=1.0),
                              Restriction(row=2, column=2, value=1.0))
    assert r.a.shape == (0, 0) and r.completely_restricted


# --- Invariants on exact integer matrices ------------------------------------

# Entries in {-2, ..., 2}, at most 4 x 6.  Then every nonzero singular value of
# every submatrix is above 1e-3 and every condition number below 1e4 (the
# squared product of the nonzero singular values is a sum of squared integer
# minors, at least 1, and s_max <= 2 sqrt(24) < 9.8), so the thresholds see
# exact rank and the invariants hold exactly.
entries = st.one_of(st.just(0), st.integers(-2, 2))


@st.composite
def integer_systems(draw):
    n = draw(st.integers(1, 4))
    m = draw(st.integers(1, 6))
    A = np.array(draw(st.lists(st.lists(entries, min_size=m, max_size=m),
                               min_size=n, max_size=n)), dtype=float)
    x = np.array(draw(st.lists(st.integers(-3, 3), min_size=m, max_size=m)),
                 dtype=float)
    return A, x


@settings(max_examples=300, deadline=None, derandomize=True)
@given(integer_systems())
def test_reduction_invariants(system):
    A, x_true = system
    b = A @ x_true
    A_before, b_before = A.copy(), b.copy()
    r = reduced_system(A, b)
    n = A.shape[0]
    # The rows removed for lack of rank are exactly n - rank(A) ...
    lost = dependent_rows(A)
    assert len(lost) == n - np.linalg.matrix_rank(A)
    assert lost == tuple(sorted(r.zero_rows + r.dependent_rows))
    # ... so the reduced matrix has full row rank ...
    assert np.linalg.matrix_rank(r.a) == r.a.shape[0]
    # ... rows and columns are partitioned ...
    assert sorted(r.rows + r.eliminated_rows) == list(range(n))
    assert sorted(r.columns + r.eliminated_columns) == list(range(A.shape[1]))
    # ... and the reduced system with the restricted values solves A x = b.
    x = r.x_fixed
    if r.columns:
        x[list(r.columns)] = np.linalg.lstsq(r.a, r.b, rcond=None)[0]
    np.testing.assert_allclose(A @ x, b, rtol=0, atol=1e-10)
    np.testing.assert_array_equal(A, A_before)
    np.testing.assert_array_equal(b, b_before)


# --- The listing's defects ("Deviations" in the docstrings of fsp and fsp_null_space) ---

def test_zero_matrix():
    # The listing's mat_null reads past its singular values here (deviation 3).
    r = reduced_system(np.zeros((3, 4)), np.zeros(3))
    assert r.zero_rows == (0, 1, 2) and r.zero_columns == (0, 1, 2, 3)
    assert r.a.shape == (0, 0) and r.completely_restricted
    ns = null_space(np.zeros((2, 3)))
    assert ns.vectors.shape == (3, 3) and ns.condition == np.inf


def test_null_space_uses_every_row():
    # The listing decomposes only the first C rows of a tall matrix
    # (deviation 1); those are singular here, the whole matrix is not.
    a = np.array([[1.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    assert null_space(a).vectors.shape == (2, 0)
    assert null_space(a[:2]).vectors.shape == (2, 1)


def test_ill_conditioned_null_vector_is_the_singular_vector():
    # Deviation 2: the vector added for the condition bound is the right
    # singular vector of s_min, so |a v| = s_min.
    q, _ = np.linalg.qr(np.random.default_rng(3).standard_normal((3, 3)))
    a = q @ np.diag([1.0, 0.5, 1e-3]) @ q.T
    assert null_space(a).vectors.shape == (3, 0)
    ns = null_space(a, k2_bnd=100.0)
    assert ns.vectors.shape == (3, 1)
    assert np.linalg.norm(a @ ns.vectors[:, 0]) == pytest.approx(1e-3, rel=1e-9)
    assert ns.condition == pytest.approx(1e3, rel=1e-9)


def test_wide_matrix_null_space_includes_padding():
    # mat_null pads a wide matrix with zero rows: R < C gives C - R zero
    # singular values, and the condition number uses the R-th one.
    a = np.array([[1.0, 0.0, 0.0], [0.0, 2.0, 0.0]])
    ns = null_space(a)
    assert ns.vectors.shape == (3, 1)
    np.testing.assert_allclose(np.abs(ns.vectors[:, 0]), [0.0, 0.0, 1.0])
    assert ns.condition == 2.0


def test_large_n_bnd_falls_back_to_largest_component():
    # The null vector (2, -1, 0)/sqrt(5) has no component >= 0.99; the listing
    # would run off its end (deviation 4), the row of the largest is taken.
    A = np.array([[1.0, 2.0, 0.0], [2.0, 4.0, 0.0], [0.0, 1.0, 1.0]])
    assert reduced_system(A, n_bnd=0.99).dependent_rows == (0,)


def test_entry_equal_to_small_is_zero_in_rows_and_columns():
    # SMALL = 1000/1000 = 1: the 1.0 entries are zero both when sweeping rows
    # and when looking for columns of zeros (deviation 7).
    A = np.array([[1000.0, 0.0, 1.0], [0.0, 1.0, 1.0]])
    r = reduced_system(A, [2000.0, 0.0])
    assert r.small == 1.0
    assert r.restrictions == (Restriction(row=0, column=0, value=2.0),)
    assert r.zero_rows == (1,)
    assert r.zero_columns == (1, 2)


def test_is_trivial_motion():
    # The listing's CheckB always answers "all zeros" (deviation 8).
    assert not is_trivial_motion([0.0, 0.5], small=0.1)
    assert is_trivial_motion([0.05, -0.1], small=0.1)
    assert is_trivial_motion([], small=0.1)
    with pytest.raises(ShapeError):
        is_trivial_motion([[0.0]], small=0.1)


# --- Inputs and arguments ----------------------------------------------------

def test_inputs_are_not_mutated():
    A = j_6_4(ROW_5_OF_6_4["as-eq50"])
    b = DX_6_4.copy()
    A_list = J_6_2.tolist()
    b_list = DX_6_2.tolist()
    A_copy, b_copy = A.copy(), b.copy()
    r = reduced_system(A, b)
    reduced_system(A_list, b_list)
    dependent_rows(A)
    null_space(A)
    is_trivial_motion(b, 0.1)
    np.testing.assert_array_equal(A, A_copy)
    np.testing.assert_array_equal(b, b_copy)
    assert A_list == J_6_2.tolist() and b_list == DX_6_2.tolist()
    # The results own their data and cannot be written.
    assert not np.shares_memory(r.a, A) and not np.shares_memory(r.b, b)
    with pytest.raises(ValueError):
        r.a[0, 0] = 5.0
    with pytest.raises(ValueError):
        r.b[0] = 5.0
    with pytest.raises(AttributeError):
        r.small = 0.0


def test_b_defaults_to_zeros():
    r = reduced_system(J_6_2)
    assert [x.value for x in r.restrictions] == [0.0, 0.0, 0.0, 0.0]
    np.testing.assert_array_equal(r.b, [0.0])
    assert r.completely_restricted


@pytest.mark.parametrize("A, b", [
    (np.zeros(3), None),
    (np.zeros((2, 3)), np.zeros(3)),
    (np.zeros((2, 3)), np.zeros((2, 1))),
])
def test_shape_errors(A, b):
    with pytest.raises(ShapeError):
        reduced_system(A, b)


@pytest.mark.parametrize("kwargs, name", [
    ({"small_fraction": -1e-3}, "small_fraction"),
    ({"sv_small": 0.0}, "sv_small"),
    ({"k2_bnd": float("nan")}, "k2_bnd"),
    ({"n_bnd": 1.5}, "n_bnd"),
])
def test_threshold_errors_name_the_parameter(kwargs, name):
    with pytest.raises(ValueError, match=name):
        reduced_system(np.eye(2), **kwargs)


def test_non_finite_input_is_rejected():
    with pytest.raises(ValueError, match="finite"):
        reduced_system([[1.0, np.nan]])
    with pytest.raises(ValueError, match="finite"):
        reduced_system([[1.0, 2.0]], [np.inf])
