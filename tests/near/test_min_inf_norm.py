"""Minimum infinity-norm solutions: Ha and Lee's worked examples, Cadzow's failure without the
Haar condition, and every method against the HiGHS linear program on random systems."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rankloci.io import load_model
from rankloci.near.cadzow import cadzow
from rankloci.near.min_inf_norm import (METHODS, haar_condition, ha_lee, linear_program,
                                        min_inf_norm)
from rankloci.tolerances import INF_NORM_RTOL

# Ha and Lee, section III.2, the example of figures 6 and 7 (Haar condition holds)
A1 = np.array([[0.7, 0.1, -1.6], [2.0, -0.2, 0.6]])
Y1 = np.array([-1.0, 0.2])
X1 = np.array([-0.1162, -0.5404, 0.5404])           # printed to 4 decimals
# the example after step 13: columns 1, 2, 3 are parallel (no Haar condition)
A2 = np.array([[1.0, 2.0, 3.0, 4.0], [1.0, 2.0, 3.0, 5.0]])
Y2 = np.array([1.0, 0.0])
X2 = np.array([0.0, 1.0, 1.0, -1.0])
#: The paper prints 4 decimals; a printed value is within half a unit of the last digit.
PRINTED = 0.5e-4


@pytest.mark.parametrize("method", METHODS)
def test_first_example_gives_the_printed_solution(method):
    s = min_inf_norm(A1, Y1, method=method)
    assert s.converged, s.reason
    np.testing.assert_allclose(s.x, X1, atol=PRINTED)
    np.testing.assert_allclose(A1 @ s.x, Y1, atol=1e-12)
    # theorem 3: n - m + 1 = 2 components saturated, the first one free
    assert abs(abs(s.x[1]) - s.norm) <= 1e-12 and abs(abs(s.x[2]) - s.norm) <= 1e-12
    assert abs(s.x[0]) < s.norm


def test_first_example_exact_value():
    """The optimum in closed form: x2 = -x3 = -t, and 0.7 x1 - 1.7 t = -1, 2 x1 + 0.8 t = 0.2."""
    x1, t = np.linalg.solve([[0.7, -1.7], [2.0, 0.8]], Y1)
    s = ha_lee(A1, Y1)
    np.testing.assert_allclose(s.x, [x1, -t, t], rtol=1e-12)
    assert s.norm == pytest.approx(t, rel=1e-12) and s.bound == pytest.approx(t, rel=1e-12)


def test_second_example_ha_lee_gives_the_printed_solution():
    assert not haar_condition(A2)
    s = ha_lee(A2, Y2)
    assert s.converged, s.reason
    np.testing.assert_allclose(s.x, X2, atol=1e-12)
    assert s.norm == pytest.approx(1.0, rel=1e-12)
    # the minimum infinity norm is 1 (the LP agrees); the optimum is not unique:
    # (1, 0.5, 1, -1) has the same norm, so only the norm is compared with the LP
    assert linear_program(A2, Y2).norm == pytest.approx(1.0, rel=1e-9)
    other = np.array([1.0, 0.5, 1.0, -1.0])
    np.testing.assert_allclose(A2 @ other, Y2)


def test_second_example_step_one_and_z():
    """Step 1's x2 as printed, and the printed z reproduced in the printed null-space basis.

    The printed intermediates S = [1, -1, 1], B and chi are not consistent with the printed z
    and x* (with S = [1, -1, 1], x3 would be -t): the solution x* = [0, 1, 1, -1] needs
    S = [1, 1, -1] over columns 2, 3, 4.  z is reconstructed here from x* and the printed N.
    """
    s = ha_lee(A2, Y2)
    x2 = np.linalg.pinv(A2) @ Y2
    np.testing.assert_allclose(x2, [0.3571, 0.7143, 1.0714, -1.0000], atol=PRINTED)
    N_printed = np.array([[-0.9636, 0.1482, 0.2224, 0.0], [0.0, -0.8321, 0.5547, 0.0]]).T
    np.testing.assert_allclose(A2 @ N_printed, 0, atol=1e-3)
    z = np.linalg.lstsq(N_printed, s.x - x2, rcond=None)[0]
    np.testing.assert_allclose(z, [0.3706, -0.2774], atol=2e-4)
    # the saturated columns are 2, 3, 4 (0-based 1, 2, 3) with signs +, +, -
    assert s.saturated == (1, 2, 3) and s.free == (0,)
    assert s.history[0]["zeros"] == [1, 2], "A_2'u vanishes on the columns parallel to A_1"


def test_cadzow_fails_on_the_second_example_and_how():
    """Without the Haar condition Cadzow's algorithm cycles and never certifies an optimum.

    Columns 1-3 are parallel, so the dual vector u orthogonal to column 1 is orthogonal to
    columns 2 and 3 too: A_2'u = (0, 0, -1).  C-step 5 sets x = (y'u) sgn(A_2'u) with
    sgn(0) = 0, so x_2 = x_3 = 0 although u is already optimal (y'u = 1, the minimum norm):
    column 1 must then carry all of y - a_4 x_4 and gets x_1 = 5 > y'u.  The exchange
    rule divides by the zero entries, swaps column 1 for column 4 and back to a column
    parallel to the first, and the basis repeats.
    """
    s = cadzow(A2, Y2)
    assert not s.converged
    assert "cycling" in s.reason and "Haar condition" in s.reason
    first = s.history[0]
    assert first["bound"] == pytest.approx(1.0, rel=1e-12), "the dual bound is already optimal"
    assert first["zeros"] == [1, 2]
    assert first["x1_norm"] == pytest.approx(5.0, rel=1e-12)
    assert all(h["x1_norm"] > h["bound"] * (1 + INF_NORM_RTOL) for h in s.history)
    assert len({h["free"] for h in s.history}) < len(s.history), "a basis repeats"
    assert s.norm > 1.0 + 1e-6, "the x it ends with is not a minimum infinity-norm solution"
    # where the Haar condition holds, Cadzow's algorithm and Ha and Lee's agree
    assert cadzow(A1, Y1).converged


@pytest.mark.parametrize("method", METHODS)
def test_zero_right_hand_side(method):
    s = min_inf_norm(A1, [0.0, 0.0], method=method)
    assert s.converged and s.norm == 0.0


def scipy_min_inf_norm(A, y):
    """scipy's linprog on min t, A x = y, -t <= x_i <= t, on A as given (any rank).

    Returns the optimum t, or None when HiGHS finds the equations infeasible."""
    from scipy.optimize import linprog

    A = np.asarray(A, dtype=float)
    m, n = A.shape
    ones = np.ones((n, 1))
    res = linprog(np.r_[np.zeros(n), 1.0],
                  A_ub=np.block([[np.eye(n), -ones], [-np.eye(n), -ones]]), b_ub=np.zeros(2 * n),
                  A_eq=np.hstack([A, np.zeros((m, 1))]), b_eq=y,
                  bounds=[(None, None)] * n + [(0, None)], method="highs")
    assert res.status in (0, 2), res.message   # solved, or infeasible
    return float(res.x[-1]) if res.status == 0 else None


@pytest.mark.parametrize("method", METHODS)
def test_consistent_rank_deficient_system_is_solved(method):
    """Rank 1, y in the range: the solutions are those of x1 + 2 x2 + 3 x3 = 1, least
    infinity norm 1/6 at x = (1/6, 1/6, 1/6), as scipy's linprog finds on A itself."""
    A, y = [[1.0, 2.0, 3.0], [2.0, 4.0, 6.0]], [1.0, 2.0]
    s = min_inf_norm(A, y, method=method)
    assert s.converged and s.consistent and s.rank == 1, s.reason
    assert s.norm == pytest.approx(scipy_min_inf_norm(A, y), rel=1e-9)
    assert s.norm == pytest.approx(1 / 6, rel=1e-12)
    np.testing.assert_allclose(np.asarray(A) @ s.x, y, atol=1e-12)
    assert s.bound <= s.norm * (1 + INF_NORM_RTOL), "y'u is a lower bound (weak duality)"


@pytest.mark.parametrize("method", METHODS)
def test_inconsistent_rank_deficient_system_is_reported(method):
    A, y = [[1.0, 2.0, 3.0], [2.0, 4.0, 6.0]], [1.0, 0.0]
    assert scipy_min_inf_norm(A, y) is None, "no x solves it"
    s = min_inf_norm(A, y, method=method)
    assert not s.consistent and not s.converged and s.rank == 1
    assert np.all(np.isnan(s.x)) and "not in the range of A" in s.reason


@pytest.mark.parametrize("method", METHODS)
def test_zero_matrix(method):
    assert min_inf_norm(np.zeros((2, 3)), [0.0, 0.0], method=method).norm == 0.0
    s = min_inf_norm(np.zeros((2, 3)), [0.0, 1.0], method=method)
    assert not s.consistent and s.rank == 0


@settings(max_examples=100, deadline=None)
@given(m=st.integers(2, 6), extra=st.integers(0, 4), drop=st.integers(1, 5),
       seed=st.integers(0, 2**32 - 1))
def test_rank_deficient_systems_match_scipy_linprog(m, extra, drop, seed):
    """A = B C of rank r < m: with y = A x0 every method reaches scipy's optimum on A; with y
    moved out of the range of A, the result says that no x solves it."""
    rng = np.random.default_rng(seed)
    n, r = m + extra, max(m - drop, 1)
    A = rng.normal(size=(m, r)) @ rng.normal(size=(r, n))
    y = A @ rng.normal(size=n)
    reference = scipy_min_inf_norm(A, y)
    for method in METHODS:
        s = min_inf_norm(A, y, method=method)
        assert s.consistent and s.rank == r
        assert s.converged, (method, s.reason)   # the reduced r x n system is generic (Haar)
        np.testing.assert_allclose(A @ s.x, y, atol=1e-8 * (1 + np.abs(y).max()))
        assert s.norm == pytest.approx(reference, rel=1e-7)
    left_null = np.linalg.svd(A)[0][:, -1]           # orthogonal to the range of A
    outside = y + (1 + np.linalg.norm(y)) * left_null
    s = min_inf_norm(A, outside)
    assert not s.consistent and np.all(np.isnan(s.x))


@pytest.mark.parametrize("A, y, what", [
    (np.ones((3, 2)), np.ones(3), "1 <= m <= n"),
    (np.ones((2, 3)), np.ones(3), "must have 2 entries"),
    ([[1.0, np.nan]], [1.0], "finite"),
])
def test_bad_input_names_the_problem(A, y, what):
    with pytest.raises(ValueError, match=what):
        min_inf_norm(A, y)


def test_unknown_method_names_the_choices():
    with pytest.raises(ValueError, match="ha_lee, cadzow, lp"):
        min_inf_norm(A1, Y1, method="shim")


def test_inputs_are_not_mutated():
    A, y = A1.copy(), Y1.copy()
    ha_lee(A, y)
    cadzow(A, y)
    np.testing.assert_array_equal(A, A1)
    np.testing.assert_array_equal(y, Y1)


@settings(max_examples=150, deadline=None)
@given(m=st.integers(1, 6), extra=st.integers(0, 5), seed=st.integers(0, 2**32 - 1))
def test_every_method_matches_the_linear_program(m, extra, seed):
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(m, m + extra))
    y = rng.normal(size=m)
    lp = linear_program(A, y)
    for method in ("ha_lee", "cadzow"):
        s = min_inf_norm(A, y, method=method)
        assert s.converged, (method, s.reason)
        np.testing.assert_allclose(A @ s.x, y, atol=1e-9 * (1 + np.abs(y).max()))
        assert s.norm == pytest.approx(lp.norm, rel=1e-8)
        assert s.bound <= lp.norm * (1 + 1e-9), "y'u is a lower bound (weak duality)"


def test_degenerate_systems_with_repeated_columns_match_the_linear_program():
    """Columns repeated or scaled (no Haar condition): Ha and Lee still reach the optimum."""
    rng = np.random.default_rng(7)
    for _ in range(200):
        m = int(rng.integers(2, 5))
        base = rng.normal(size=(m, m + 1))
        extra = base[:, rng.integers(0, m + 1, size=2)] * rng.choice([-2.0, 1.0, 3.0], size=2)
        A = np.hstack([base, extra])
        y = rng.normal(size=m)
        s, lp = ha_lee(A, y), linear_program(A, y)
        assert s.converged, s.reason
        assert s.norm == pytest.approx(lp.norm, rel=1e-8)


@pytest.mark.parametrize("name", ["pa10", "mobile10"])
def test_robot_jacobians_ha_lee_always_cadzow_only_where_it_can(name):
    """Robot Jacobians rarely satisfy the Haar condition (the PA10's flange lies on axis 7, so
    column 7 has no linear part; the mobile base's columns are constant).  Ha and Lee reach
    the LP's optimum on every system; Cadzow's algorithm either does too or says it failed."""
    from rankloci.numeric.batch_jacobian import BatchJacobian

    model = load_model(name)
    rng = np.random.default_rng(11)
    Q = rng.uniform(-np.pi, np.pi, size=(40, len(model.joints)))
    failed = 0
    for J, y in zip(BatchJacobian(model)(Q), rng.normal(size=(40, 6))):
        lp = linear_program(J, y)
        s = ha_lee(J, y)
        assert s.converged and s.norm == pytest.approx(lp.norm, rel=1e-9)
        c = cadzow(J, y)
        if c.converged:
            assert c.norm == pytest.approx(lp.norm, rel=1e-9)
            np.testing.assert_allclose(J @ c.x, y, atol=1e-9)
        else:
            failed += 1
            assert "Haar condition" in c.reason or "cycling" in c.reason, c.reason
    assert not haar_condition(J)
    assert failed > 0, "some of these systems defeat Cadzow's algorithm"
