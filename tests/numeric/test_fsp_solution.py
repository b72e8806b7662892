"""Tests of the FSP solution space (rankloci.numeric.fsp_solution).

The worked examples are those of section 6 of K. A. Morgansen, F. G. Pin,
ORNL/TM-12816 (1995), with the matrices of tests/numeric/test_fsp.py where
that reading fits the report's solution vectors (6.2 to 6.4).  Example 6.1
needs four printed entries of two rows corrected, as derived below.  Indices in the code are
0-based; comments about the report count from 1, as it does.  Every result
is also checked against numpy's pseudo-inverse, and random systems (full
rank, held joints, rank deficient, sparse integer ones with restrictions)
check that every point of the solution space solves the system.
"""

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from rankloci.errors import ShapeError
from rankloci.numeric.fsp_solution import solve
from test_fsp import (
    DX_6_1,
    DX_6_2,
    DX_6_3,
    DX_6_4,
    J_6_1,
    J_6_2,
    J_6_3,
    J_6_3_REDUCED,
    ROW_5_OF_6_4,
    j_6_4,
)

# The report prints its results to 2 to 4 decimals; a printed value agrees
# when it is within one unit of its last digit.
PRINTED_3 = 1e-3
PRINTED_2 = 1e-2
PRINTED_4 = 1e-4


def assert_solves(A, b, X, rtol=1e-9):
    """Every row of X solves A x = b, relative to the size of the terms."""
    X = np.atleast_2d(X)
    size = np.abs(X) @ np.abs(A).T + np.abs(b)
    assert np.all(np.abs(X @ A.T - b) <= rtol * size.max(initial=0.0))


def pinv_solution(A, b):
    return np.linalg.pinv(A, rcond=1e-10) @ b


def points_of(s, rng, count=5):
    """Points sum t_k g^k of the solution space: weights that meet the constraints."""
    C, r = s.constraints, s.constraint_rhs
    t0 = np.linalg.lstsq(C, r, rcond=None)[0]
    _, sv, vt = np.linalg.svd(C)
    rank = int(np.sum(sv > 1e-9 * sv[0]))
    free = vt[rank:].T
    return np.array([(t0 + free @ rng.standard_normal(free.shape[1])) @ s.vectors
                     for _ in range(count)])


# --- Section 6.1 "Typical J and dx", eqs. (30)-(33) -------------------------
# With rows 5 and 6 of eq. (30) read as test_fsp.py reads them, no solution
# vector of eq. (32) solves row 6 (residuals up to 0.03 against dx_6 = 0.018)
# and every one of them, and dq of eq. (33), gives row 5 = 0.002 against
# dx_5 = 0.000.  The columns of a Jacobian settle it: rows 4-6 of a revolute
# column are its unit axis, and as printed joints 5 and 6 have no unit axis
# and the base rotation (column 10, whose rows 1-2 are its -y, x lever arms)
# none at all.  J_6_1_FITTED is therefore a correction, not a reading: it
# changes four printed entries, the bracketed ones below (row 5 column 5;
# row 6 columns 5, 6 and 10), to the values that make eqs. (32) and (33) hold:
#   row 5: 0 -1 -0 -1 [-1] -0.001 0 | 0 0 0    (printed 0 at column 5; -1 makes
#          joint 5 a rotation about -y, as its linear part (0, 0, -0.343) fits)
#   row 6: 1 0 -1 -0 [0] [-1] 0.001 | 0 0 [1]  (printed -1, -0 and 0.001 at
#          columns 5, 6 and 10; these make joint 6 a rotation about -z, whose
#          linear part (-0.006, 0.343, 0) puts it at joint 5's point, a wrist,
#          and the base rotation one about z)
# With it every column has a unit axis, and the search finds the blocking the
# zeros of eq. (32) show (its first blocking is the third in lexicographic
# order), vectors within 0.001 of eq. (32) except two printed entries (see the
# test) and dq of eq. (33) to 0.0007.
J_6_1_FITTED = J_6_1.copy()
J_6_1_FITTED[4] = [0.000, -1.000, -0.000, -1.000, -1.000, -0.001, 0.000, 0.0, 0.0, 0.000]
J_6_1_FITTED[5] = [1.000, 0.000, -1.000, -0.000, 0.000, -1.000, 0.001, 0.0, 0.0, 1.0]

G_6_1 = np.array([  # eq. (32); the first column prints as "0.00", "0.00 0", "0.02 2"
    [0.000, 0.000, 0.000, -0.002, -0.002, 0.000, 0.000, 0.013, 0.010, 0.018],
    [0.000, 0.000, 0.000, -0.002, 0.002, -0.053, -0.000, 0.000, -0.000, -0.034],
    [0.000, 0.000, -0.052, -0.002, 0.002, 0.000, 0.001, 0.000, 0.028, -0.034],
    [0.000, -0.021, 0.000, 0.020, 0.001, 0.000, 0.000, 0.000, 0.009, 0.018],
    [0.022, 0.000, 0.000, -0.002, 0.002, 0.000, 0.000, 0.000, 0.017, -0.004],
])
DQ_6_1 = np.array([0.004, -0.003, -0.002, 0.001, 0.002, -0.007, 0.000, 0.007,
                   0.010, 0.004])  # eq. (33)


def test_6_1_correction_gives_unit_axes():
    axes = J_6_1_FITTED[3:]
    np.testing.assert_allclose(np.linalg.norm(axes[:, :7], axis=0), 1.0, atol=3e-4)
    np.testing.assert_array_equal(axes[:, 7:9], 0.0)   # base translations
    np.testing.assert_array_equal(axes[:, 9], [0.0, 0.0, 1.0])
    # As test_fsp.py reads rows 5 and 6, joints 5 and 6 have no unit axis.
    assert np.linalg.norm(J_6_1[3:, 4]) == pytest.approx(1.0)
    assert np.linalg.norm(J_6_1[3:, 5]) == pytest.approx(0.001)


def test_6_1_solution_vectors():
    s = solve(J_6_1_FITTED, DX_6_1)
    assert s.construction == "blocking pattern" and not s.rank_lost
    assert s.restricted == () and s.inactive == () and s.rank == 6
    # The blocked columns are the zeros of eq. (32): 1-based {1,2,3,6},
    # {1,2,3,8}, {1,2,6,8}, {1,3,6,8}, {2,3,6,8}.  (The printed blocking
    # pattern of section 6.1 has these with its fourth column where eq. (32)
    # has its zeros in the sixth.)  Each vector frees the first vector's
    # blocks from the last to the first and adds one block at the end.
    assert s.blocked == ((0, 1, 2, 5), (0, 1, 2, 7), (0, 1, 7, 5), (0, 7, 5, 2),
                         (7, 5, 2, 1))
    for g, blocks in zip(s.vectors, s.blocked):
        np.testing.assert_array_equal(g[list(blocks)], 0.0)
    assert s.condition < 10.0  # FSP.h K2_BND
    assert_solves(J_6_1_FITTED, DX_6_1, s.vectors)
    # Eq. (32), except two printed entries: g^1_5 prints -0.002 where row 3
    # (-0.851 g_4 - 0.343 g_5 = 0.001 with g_4 = -0.002) needs +0.002, and
    # g^2_10 prints -0.034 for -0.0354.
    diff = np.abs(s.vectors - G_6_1)
    assert s.vectors[0, 4] == pytest.approx(-G_6_1[0, 4], abs=PRINTED_3)
    assert s.vectors[1, 9] == pytest.approx(G_6_1[1, 9], abs=2 * PRINTED_3)
    diff[0, 4] = diff[1, 9] = 0.0
    assert diff.max() <= PRINTED_3


def test_6_1_least_norm():
    s = solve(J_6_1_FITTED, DX_6_1)
    np.testing.assert_allclose(s.least_norm, DQ_6_1, rtol=0, atol=PRINTED_3)
    np.testing.assert_allclose(s.least_norm, pinv_solution(J_6_1_FITTED, DX_6_1),
                               rtol=0, atol=1e-14)
    assert np.sum(s.weights) == pytest.approx(1.0, rel=1e-14)


def test_6_1_as_test_fsp_reads_it():
    # The reading of test_fsp.py is a full-rank system too; its solution space
    # is right, but its vectors are not those of eq. (32).
    s = solve(J_6_1, DX_6_1)
    assert_solves(J_6_1, DX_6_1, s.vectors)
    np.testing.assert_allclose(s.least_norm, pinv_solution(J_6_1, DX_6_1),
                               rtol=0, atol=1e-14)
    assert np.abs(s.least_norm - DQ_6_1).max() > 0.004


# --- Section 6.2 "J with restrictions", eqs. (34)-(40) ----------------------

def test_6_2_vectors_and_least_norm():
    s = solve(J_6_2, DX_6_2)
    assert s.restricted == (0, 1, 2, 4) and s.inactive == (3,)
    assert s.lost_rows == (3,) and s.rank_lost and s.rank == 5
    # Eq. (38) in every vector, then eq. (39) in the report's order.  The
    # lexicographically first blocking of the reduced [1 2 3 4 5] (columns 6-9
    # blocked) fails at its last vector, where the null vector of columns 6
    # and 7, (2, -1)/sqrt(5), has 0.447 < N_BND = 0.9/2 at column 7; so do
    # the next ones, until the blocking of columns 7-10 completes.
    fixed = [2.0, -1.0, 3.0, 0.0, -1.0]
    np.testing.assert_array_equal(s.vectors[:, :5], np.tile(fixed, (5, 1)))
    np.testing.assert_allclose(s.vectors[:, 5:], [
        [6.0, 0.0, 0.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, 0.0, 1.2],
        [0.0, 0.0, 0.0, 1.5, 0.0],
        [0.0, 0.0, 2.0, 0.0, 0.0],
        [0.0, 3.0, 0.0, 0.0, 0.0],
    ], rtol=1e-15)
    # The printed pattern lists the same blockings with the first one last.
    assert [sorted(set(range(5, 10)) - set(b)) for b in s.blocked] == [
        [5], [9], [8], [7], [6]]
    # Eq. (40); 0.546 is printed for 6 * 5/55 = 0.54545.
    dq = [2.0, -1.0, 3.0, 0.0, -1.0, 0.109, 0.218, 0.327, 0.436, 0.546]
    np.testing.assert_allclose(s.least_norm, dq, rtol=0, atol=PRINTED_3)
    np.testing.assert_allclose(s.least_norm, pinv_solution(J_6_2, DX_6_2),
                               rtol=0, atol=1e-14)
    assert s.consistent


# --- Section 6.3 "Completely restricted J", eqs. (41)-(47) ------------------
G_6_3_REDUCED = np.array([  # eq. (46), the components of columns 3-10
    [0.0000, -0.0241, 0.6047, -0.5454, -0.4355, 0.0185, 0.1210, 0.3629],
    [0.0000, 0.2132, -0.7183, -0.5454, -0.1516, -0.1640, 0.2743, 0.1263],
    [0.0000, -0.6331, -0.1001, -0.4593, 0.2671, 0.4870, -0.1419, -0.2226],
    [-0.5087, -0.1942, -0.1843, 0.2010, -0.7285, 0.1494, -0.1345, -0.2408],
    [0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000],
])
DQ_6_3 = np.array([0.000, 0.100, -0.127, -0.160, -0.100, -0.337, -0.262, 0.123,
                   0.030, 0.007])  # eq. (47)


def test_6_3_null_space_vectors():
    s = solve(J_6_3, DX_6_3)
    assert s.completely_restricted and s.construction == "null space"
    assert s.restricted == (0, 1) and not s.rank_lost
    # Eq. (45) in every vector; the last vector is zero besides.
    np.testing.assert_allclose(s.vectors[:, :2], np.tile([0.0, 0.1], (5, 1)),
                               rtol=1e-15)
    np.testing.assert_array_equal(s.vectors[-1, 2:], 0.0)
    null = s.vectors[:4, 2:]
    np.testing.assert_allclose(null @ null.T, np.eye(4), atol=1e-14)
    np.testing.assert_allclose(J_6_3_REDUCED @ null.T, 0.0, atol=1e-14)
    # Eq. (46) is another orthonormal basis of the same null space (an SVD's
    # basis of a repeated singular value is arbitrary): its vectors are null
    # vectors, orthonormal and inside the span of ours, to the printed digits.
    # Rounding to 4 decimals moves each entry by at most h = 5e-5, so a
    # product with a vector w moves by at most h |w|_1, and a vector by at
    # most h sqrt(8) in length.
    report = G_6_3_REDUCED[:4]
    h = PRINTED_4 / 2
    bound = h * np.abs(J_6_3_REDUCED).sum(axis=1)[:, None]
    assert np.all(np.abs(J_6_3_REDUCED @ report.T) <= bound)
    l1 = np.abs(report).sum(axis=1)
    np.testing.assert_array_less(np.abs(report @ report.T - np.eye(4)),
                                 h * (l1[:, None] + l1[None, :]) + h * h * 8)
    outside = report - (report @ null.T) @ null
    assert np.linalg.norm(outside, axis=1).max() <= h * np.sqrt(8)
    assert_solves(J_6_3, DX_6_3, s.vectors)


def test_6_3_least_norm_and_the_reports_dq():
    s = solve(J_6_3, DX_6_3)
    # The least-norm point of S = x_fixed + null space is x_fixed itself.
    np.testing.assert_allclose(s.least_norm, [0.0, 0.1] + [0.0] * 8, atol=1e-15)
    np.testing.assert_allclose(s.least_norm, pinv_solution(J_6_3, DX_6_3),
                               atol=1e-15)
    # Eq. (47) is the listing's LeastNorm on eq. (46): its Gram matrix of the
    # reduced components is diag(1, 1, 1, 1, 0), singular, and mat_pseudoinv
    # makes t = (1, 1, 1, 1, 0)/4, the mean of the null vectors.  That point is
    # in S but is not its least-norm point (deviation 1 of the module).
    G = G_6_3_REDUCED @ G_6_3_REDUCED.T
    Gp = np.linalg.pinv(G, rcond=1e-6)  # matrix.c SVD_THRESHOLD
    e = np.ones(5)
    t = Gp @ e / (e @ Gp @ e)
    np.testing.assert_allclose(t, [0.25, 0.25, 0.25, 0.25, 0.0], atol=4 * PRINTED_4)
    x = np.concatenate([[0.0, 0.1], t @ G_6_3_REDUCED])
    np.testing.assert_allclose(x, DQ_6_3, rtol=0, atol=PRINTED_3)
    residual = np.abs(J_6_3 @ DQ_6_3 - DX_6_3)   # dq rounded to 3 decimals
    assert np.all(residual <= PRINTED_3 / 2 * np.abs(J_6_3).sum(axis=1))
    assert np.linalg.norm(DQ_6_3) > 5 * np.linalg.norm(s.least_norm)


# --- Section 6.4 "J with loss of row rank", eqs. (48)-(52) ------------------
G_6_4 = np.array([  # eq. (50); g^5 prints nine numbers, a 0.00 is lost before -1.00
    [0.00, 1.00, 0.00, -1.00, 0.00, 0.00, 0.00, -0.00, 0.00, 0.00],
    [0.00, 1.00, 0.00, 0.00, 0.00, 0.00, -1.78, -1.00, 0.66, 0.88],
    [0.00, 1.00, 0.00, 0.00, 0.00, 1.99, 0.00, -1.00, 0.67, 0.00],
    [0.00, 1.00, 0.00, 0.00, -2.67, 0.00, 0.00, -1.00, 0.67, 0.00],
    [0.00, 1.00, 0.89, 0.00, 0.00, 0.00, 0.00, -1.00, 0.67, 0.89],
    [1.00, 0.00, 0.00, 0.00, 0.00, 0.00, 0.00, 0.00, 0.00, 0.00],
])
X_6_4 = np.array([0.6273, 0.3727, 0.0497, -0.2547, -0.0373, 0.0683, -0.0248,
                  -0.1180, 0.0559, 0.0621])  # eq. (52)


def test_6_4_vectors():
    J = j_6_4(ROW_5_OF_6_4["as-eq50"])
    s = solve(J, DX_6_4)
    assert s.rank_lost and s.lost_rows == (0,) and s.rank == 5
    assert s.construction == "blocking pattern"
    assert s.vectors.shape == (10 - 6 + 2, 10)
    assert_solves(J, DX_6_4, s.vectors)
    # Eq. (50), in its order, to its two printed decimals, which are
    # truncated (0.66 for 2/3, 0.88 for 8/9, 1.99 for a float just below 2):
    # less than one unit of the last digit.  Except g^3_9: row 6 (g_6 + 2 g_8
    # + 3 g_9 = 0) holds for (1.99, -1, 0), not for the printed (1.99, -1, 0.67).
    diff = np.abs(s.vectors - G_6_4)
    assert s.vectors[2, 8] == pytest.approx(0.0, abs=1e-15)
    diff[2, 8] = 0.0
    assert diff.max() < PRINTED_2 + 1e-12
    # Eq. (51): every beta is 1, since row 1 is row 3 + row 4 exactly.
    np.testing.assert_allclose(s.beta, np.ones((1, 6)), rtol=1e-14)


def test_6_4_least_norm():
    J = j_6_4(ROW_5_OF_6_4["as-eq50"])
    s = solve(J, DX_6_4)
    np.testing.assert_allclose(s.least_norm, X_6_4, rtol=0, atol=PRINTED_4 / 2)
    np.testing.assert_allclose(s.least_norm, pinv_solution(J, DX_6_4), atol=1e-14)
    assert s.consistent


def test_6_4_closed_form_degenerates_to_least_norm():
    # With all beta = 1 the beta constraint repeats sum t = 1: in eqs.
    # (20)-(24) b1 = c1 = d11 = a, so A11 = c1 b1 - a d11 vanishes and eq. (25)
    # is 0/0.  Whatever finite nu rounding gives, eq. (27) as the listing
    # computes it, t = -mu G^-1 e - nu G^-1 beta, is then G^-1 e / a: the
    # LeastNorm weights, which give eq. (52).
    s = solve(j_6_4(ROW_5_OF_6_4["as-eq50"]), DX_6_4)
    g = s.vectors
    Gi = np.linalg.inv(g @ g.T)
    e = np.ones(6)
    beta = s.beta[0]
    a, b1, c1, d11 = e @ Gi @ e, e @ Gi @ beta, beta @ Gi @ e, beta @ Gi @ beta
    assert abs(c1 * b1 - a * d11) <= 1e-12 * a * a
    for nu in (-3.0, 0.0, 7.5):
        mu = -(1 + nu * b1) / a
        t = -mu * Gi @ e - nu * Gi @ beta
        np.testing.assert_allclose(t @ g, X_6_4, atol=PRINTED_4 / 2)
        np.testing.assert_allclose(t, s.weights, atol=1e-12)


def test_6_4_zero_filled_reading_has_no_blocking_pattern():
    # With row 5's lost number read as 0.00 the pattern cannot be completed
    # (the listing's "System did not complete!"), which supports the reading
    # of eq. (50).  The solution space is then built from the least-norm
    # solution and the null space, and is still right.
    J = j_6_4(ROW_5_OF_6_4["zero-filled"])
    s = solve(J, DX_6_4)
    assert s.construction == "particular solution and null space"
    assert_solves(J, DX_6_4, s.vectors)
    assert s.directions.shape == (5, 10)
    np.testing.assert_allclose(s.least_norm, pinv_solution(J, DX_6_4), atol=1e-14)


# --- The beta constraint when a row is only nearly dependent ----------------

@pytest.mark.parametrize("seed", range(5))
def test_beta_constraint_keeps_the_removed_row(seed):
    # Row 0 is rows 2 + 3 plus 1e-3 of noise: with tol = 1e-2 the reducer
    # removes it, beta is no longer all ones, and the constraint of eq. (16)
    # makes S the solution set of the whole system.  The least-norm point is
    # then the pseudo-inverse solution of the full-rank A, and RankLostSoln's
    # closed form (eqs. 20-27, as the listing codes them) gives it too.
    rng = np.random.default_rng(seed)
    A = rng.standard_normal((6, 10))
    A[0] = A[2] + A[3] + 1e-3 * rng.standard_normal(10)
    b = A @ rng.standard_normal(10)
    s = solve(A, b, tol=1e-2)
    assert s.rank_lost and s.lost_rows == (0,)
    assert np.abs(s.beta - 1).max() > 1e-5
    np.testing.assert_allclose(s.least_norm, np.linalg.pinv(A) @ b, rtol=1e-9,
                               atol=1e-9)
    assert_solves(A, b, points_of(s, rng))
    g = s.vectors
    Gi = np.linalg.inv(g @ g.T)
    e, beta = np.ones(len(g)), s.beta[0]
    a, b1, c1, d11 = e @ Gi @ e, e @ Gi @ beta, beta @ Gi @ e, beta @ Gi @ beta
    nu = (a - c1) / (c1 * b1 - a * d11)
    mu = -(1 + nu * b1) / a
    t = -mu * Gi @ e - nu * Gi @ beta
    np.testing.assert_allclose(t @ g, s.least_norm, rtol=1e-6, atol=1e-6)


def test_inconsistent_b_is_reported():
    A = np.array([[1.0, 2.0, 0.0], [2.0, 4.0, 0.0], [0.0, 1.0, 1.0]])
    s = solve(A, [1.0, 3.0, 1.0])
    assert s.rank_lost and s.rank == 2
    assert not s.consistent
    assert solve(A, [1.0, 2.0, 1.0]).consistent


# --- Random systems against the pseudo-inverse ------------------------------

def check_space(A, b, s, rng):
    """Every point of S solves A x = b; S is the whole solution set of the
    system solved with the held joints and the inactive ones still.

    The vectors solve the rows kept; a row removed for lack of rank holds
    for them only when it is exactly dependent, and otherwise through the
    beta constraints, which every point of S meets.
    """
    kept = [i for i in range(A.shape[0]) if i not in set(s.lost_rows)]
    assert_solves(A[kept], b[kept], s.vectors)
    assert_solves(A, b, points_of(s, rng))
    np.testing.assert_allclose(s.constraints @ s.weights, s.constraint_rhs,
                               rtol=1e-9, atol=1e-9 * np.abs(s.constraint_rhs).max())
    np.testing.assert_allclose(s.weights @ s.vectors, s.least_norm, atol=1e-12)
    d = s.directions
    np.testing.assert_allclose(d @ d.T, np.eye(len(d)), atol=1e-10)
    assert np.abs(d @ s.least_norm).max(initial=0.0) <= 1e-9 * (
        1 + np.linalg.norm(s.least_norm))
    moved = s.least_norm + rng.standard_normal((4, len(d))) @ d
    assert_solves(A, b, moved)
    still = list(s.held) + list(s.inactive)
    np.testing.assert_array_equal(s.vectors[:, still], 0.0)
    free = [j for j in range(A.shape[1]) if j not in set(s.held)]
    rank = np.linalg.matrix_rank(A[:, free]) if free else 0
    assert s.rank == rank
    assert len(d) == len(free) - rank - len(s.inactive)


@pytest.mark.parametrize("seed", range(8))
@pytest.mark.parametrize("shape", [(6, 10), (6, 7), (3, 8), (2, 4), (5, 5)])
def test_full_rank_random_systems(seed, shape):
    rng = np.random.default_rng(seed)
    A = rng.standard_normal(shape)
    b = rng.standard_normal(shape[0])
    s = solve(A, b)
    n, m = shape
    assert s.vectors.shape == (m - n + 1, m) and not s.rank_lost
    assert s.construction == "blocking pattern"
    # m - n + 1 affinely independent vectors
    assert np.linalg.matrix_rank(s.vectors[1:] - s.vectors[0]) == m - n
    np.testing.assert_allclose(s.least_norm, np.linalg.pinv(A) @ b, rtol=1e-10,
                               atol=1e-12)
    check_space(A, b, s, rng)


@pytest.mark.parametrize("seed", range(8))
def test_held_joints(seed):
    rng = np.random.default_rng(seed)
    A = rng.standard_normal((6, 10))
    b = rng.standard_normal(6)
    held = tuple(int(j) for j in rng.choice(10, size=int(rng.integers(1, 4)),
                                            replace=False))
    s = solve(A, b, restricted=held)
    assert s.held == tuple(sorted(held)) and set(held) <= set(s.restricted)
    free = [j for j in range(10) if j not in held]
    expected = np.zeros(10)
    expected[free] = np.linalg.pinv(A[:, free]) @ b
    np.testing.assert_allclose(s.least_norm, expected, rtol=1e-10, atol=1e-12)
    assert s.vectors.shape[0] == len(free) - 6 + 1
    check_space(A, b, s, rng)
    # Holding a joint costs norm: the unrestricted least-norm point is shorter.
    assert np.linalg.norm(solve(A, b).least_norm) <= np.linalg.norm(s.least_norm)


@pytest.mark.parametrize("seed", range(8))
@pytest.mark.parametrize("shape, rank", [((6, 10), 5), ((6, 10), 4), ((6, 7), 5),
                                         ((4, 4), 2), ((7, 5), 5), ((8, 6), 4)])
def test_rank_deficient_random_systems(seed, shape, rank):
    rng = np.random.default_rng(seed)
    n, m = shape
    A = rng.standard_normal((n, rank)) @ rng.standard_normal((rank, m))
    b = A @ rng.standard_normal(m)
    s = solve(A, b)
    assert s.rank_lost and s.rank == rank and len(s.lost_rows) == n - rank
    assert s.vectors.shape == (m - rank + 1, m)
    np.testing.assert_allclose(s.least_norm, pinv_solution(A, b), rtol=1e-9,
                               atol=1e-9)
    assert s.consistent
    check_space(A, b, s, rng)


def test_small_motion_is_solved_like_a_large_one():
    # The listing's absolute thresholds would call every component of the
    # vectors zero for b of 1e-7 and find no pattern; here the space scales.
    rng = np.random.default_rng(5)
    A = rng.standard_normal((6, 10))
    b = rng.standard_normal(6)
    big, small = solve(A, b), solve(A, 1e-7 * b)
    assert small.blocked == big.blocked
    np.testing.assert_allclose(small.vectors, 1e-7 * big.vectors, rtol=1e-12,
                               atol=1e-20)
    np.testing.assert_allclose(small.least_norm, 1e-7 * big.least_norm,
                               rtol=1e-12)


def test_zero_motion():
    A = np.random.default_rng(2).standard_normal((3, 5))
    s = solve(A, np.zeros(3))
    assert s.completely_restricted
    np.testing.assert_allclose(s.least_norm, 0.0, atol=1e-15)
    check_space(A, np.zeros(3), s, np.random.default_rng(0))


# Entries in {-2, ..., 2}, at most 4 x 6, as in test_fsp.py: the thresholds see
# exact rank, and there are many restrictions, rows and columns of zeros; up to
# two joints held.  (Of the 200 examples about 60 % lose a row for lack of
# rank, 40 % have restrictions, 70 % columns of zeros; 30 % reach the search.)
entries = st.one_of(st.just(0), st.integers(-2, 2))


@st.composite
def integer_systems(draw):
    n = draw(st.integers(1, 4))
    m = draw(st.integers(1, 6))
    A = np.array(draw(st.lists(st.lists(entries, min_size=m, max_size=m),
                               min_size=n, max_size=n)), dtype=float)
    x = np.array(draw(st.lists(st.sampled_from([-3, -2, -1, 1, 2, 3]),
                               min_size=m, max_size=m)), dtype=float)
    held = draw(st.lists(st.integers(0, m - 1), unique=True, max_size=2))
    return A, x, tuple(held)


@settings(max_examples=200, deadline=None, derandomize=True)
@given(integer_systems())
def test_integer_systems(system):
    A, x_true, held = system
    free = [j for j in range(A.shape[1]) if j not in held]
    b = A[:, free] @ x_true[free]      # consistent with the held joints still
    A_before, b_before = A.copy(), b.copy()
    s = solve(A, b, restricted=held)
    expected = np.zeros(A.shape[1])
    if free:
        expected[free] = np.linalg.pinv(A[:, free]) @ b
    np.testing.assert_allclose(s.least_norm, expected, rtol=1e-9, atol=1e-9)
    assert s.consistent
    check_space(A, b, s, np.random.default_rng(0))
    np.testing.assert_array_equal(A, A_before)
    np.testing.assert_array_equal(b, b_before)


@st.composite
def gaussian_systems(draw):
    n = draw(st.integers(1, 6))
    m = draw(st.integers(n, 10))
    rank = draw(st.integers(1, n))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    A = rng.standard_normal((n, rank)) @ rng.standard_normal((rank, m))
    held = draw(st.lists(st.integers(0, m - 1), unique=True, max_size=m - rank))
    return A, rng.standard_normal(m), tuple(held)


def clean(A):
    """Whether rank and zero entries are clear-cut for the reducer's thresholds.

    Every singular value is exactly zero (below 1e-12 sigma_max) or above
    1e-3 sigma_max, ten times the rank tolerance; and every entry is zero or
    above 2e-3 max|A|, twice the reducer's SMALL, which counts smaller entries
    as zero (section 4 of the report), where the pseudo-inverse does not.
    """
    if A.size == 0:
        return True
    sv = np.linalg.svd(A, compute_uv=False)
    top, big = sv[0], np.abs(A).max()
    return (np.all((sv <= 1e-12 * top) | (sv >= 1e-3 * top))
            and not np.any((np.abs(A) > 1e-12 * big) & (np.abs(A) < 2e-3 * big)))


@settings(max_examples=100, deadline=None, derandomize=True)
@given(gaussian_systems())
def test_gaussian_systems(system):
    A, x_true, held = system
    free = [j for j in range(A.shape[1]) if j not in held]
    assume(clean(A[:, free]))
    b = A[:, free] @ x_true[free]
    s = solve(A, b, restricted=held)
    expected = np.zeros(A.shape[1])
    expected[free] = np.linalg.pinv(A[:, free], rcond=1e-10) @ b
    np.testing.assert_allclose(s.least_norm, expected, rtol=1e-8, atol=1e-8)
    assert s.consistent
    check_space(A, b, s, np.random.default_rng(1))


# --- Inputs and arguments ----------------------------------------------------

def test_result_is_frozen_and_read_only():
    s = solve(J_6_2, DX_6_2)
    for arr in (s.vectors, s.least_norm, s.weights, s.constraints, s.directions):
        with pytest.raises(ValueError):
            arr[0] = 1.0
    with pytest.raises(AttributeError):
        s.rank = 3


@pytest.mark.parametrize("restricted, match", [
    ((10,), "0..9"), ((-1,), "0..9"), ((1.5,), "0..9"), ((True,), "0..9"),
    ((2, 2), "twice"), (3, "sequence"),
])
def test_bad_restricted(restricted, match):
    with pytest.raises(ValueError, match=match):
        solve(J_6_2, DX_6_2, restricted=restricted)


@pytest.mark.parametrize("tol", [0.0, 1.0, -1e-3, float("nan"), "1e-3"])
def test_bad_tol(tol):
    with pytest.raises(ValueError, match="tol"):
        solve(J_6_2, DX_6_2, tol=tol)


@pytest.mark.parametrize("A, b", [(np.zeros(3), np.zeros(3)),
                                  (np.zeros((2, 3)), np.zeros(3))])
def test_shape_errors(A, b):
    with pytest.raises(ShapeError):
        solve(A, b)


def test_non_finite_input():
    with pytest.raises(ValueError, match="finite"):
        solve([[1.0, np.inf]], [1.0])
