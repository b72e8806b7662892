"""Gauss-Newton from many starts at once: roots where they are reachable, the documented stops
where they are not, and rows that do not influence one another."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rankloci.numeric.gauss_newton import LINE_LEVELS, gauss_newton, gauss_newton_rows

SEED = 3
STOP = 1e-14            # the documented residual norm at which a start stops

SMALL = settings(max_examples=50, deadline=None, derandomize=True, database=None)


def circle_line(X):
    """x**2 + y**2 = 1 and x = y: roots +-(1, 1)/sqrt(2)."""
    return np.column_stack([X[:, 0] ** 2 + X[:, 1] ** 2 - 1, X[:, 0] - X[:, 1]])


def square_two(X):
    return X ** 2 - 2


def no_real_root(X):
    return X ** 2 + 1


def _norms(residual, X):
    return np.linalg.norm(residual(X), axis=1)


class Counted:
    """A residual that records the number of rows of every call."""

    def __init__(self, residual):
        self.residual = residual
        self.batches = []

    def __call__(self, X):
        self.batches.append(len(X))
        return self.residual(X)


def test_circle_line_roots_from_many_starts():
    X0 = np.random.default_rng(SEED).uniform(-3, 3, (200, 2))
    X = gauss_newton_rows(circle_line, X0)
    assert X.shape == X0.shape
    norms = _norms(circle_line, X)
    assert np.all(norms < STOP), f"seed {SEED}: {np.sort(norms)[-3:]}"
    root = np.full(2, 1 / math.sqrt(2))
    dist = np.minimum(np.linalg.norm(X - root, axis=1), np.linalg.norm(X + root, axis=1))
    assert np.all(dist < 1e-12)
    # both roots are found, each from the starts on its side of the line x + y = 0
    side = np.sign(X0.sum(axis=1))
    np.testing.assert_array_equal(np.sign(X.sum(axis=1)), side)
    assert set(side) == {-1.0, 1.0}


def test_square_root_of_two_keeps_the_sign_of_the_start():
    rng = np.random.default_rng(SEED)
    X0 = rng.uniform(0.1, 5, (50, 1)) * rng.choice([-1, 1], (50, 1))
    X = gauss_newton_rows(square_two, X0)
    assert np.all(np.abs(square_two(X)) < STOP)
    np.testing.assert_allclose(X, np.sign(X0) * math.sqrt(2), rtol=1e-14)
    x = gauss_newton(square_two, [3.0])
    assert x.shape == (1,) and abs(x[0] - math.sqrt(2)) < 1e-14


def test_minimum_norm_step_lands_on_the_projection():
    """One equation in two unknowns: the minimum-norm solution from x0 is the orthogonal
    projection of x0 onto the line x + 2 y = 3."""
    def line(X):
        return (X[:, 0] + 2 * X[:, 1] - 3)[:, None]

    X0 = np.random.default_rng(SEED).uniform(-4, 4, (20, 2))
    n = np.array([1.0, 2.0])
    want = X0 - np.outer((X0 @ n - 3) / (n @ n), n)
    X = gauss_newton_rows(line, X0)
    np.testing.assert_allclose(X, want, atol=1e-6, err_msg=f"seed {SEED}")


starts = st.tuples(st.floats(-10, 10), st.floats(-10, 10)).map(lambda t: np.array([t]))


@SMALL
@given(starts)
def test_residual_never_grows(X0):
    X = gauss_newton_rows(circle_line, X0)
    assert np.all(np.isfinite(X))
    assert _norms(circle_line, X)[0] <= _norms(circle_line, X0)[0]


@SMALL
@given(st.floats(-3, 3))
def test_no_real_root_stops_without_a_spurious_root(x0):
    """x**2 + 1 >= 1: no start may report a root.  The stop "not halved in 8 steps" bounds
    the steps: while a start runs, its residual halves every 8 steps, from r0 down to at
    least 1, so at most 8 * (floor(log2 r0) + 1) Jacobians are formed."""
    f = Counted(no_real_root)
    X = gauss_newton_rows(f, np.array([[x0]]))
    r0 = x0 ** 2 + 1
    assert np.isfinite(X).all() and no_real_root(X)[0, 0] >= 1
    jacobians = sum(1 for m in f.batches if m == 2)     # start and its shifted copy: 2 rows
    assert jacobians <= 8 * (math.floor(math.log2(r0)) + 1)


def test_no_real_root_from_many_starts():
    X0 = np.random.default_rng(SEED).uniform(-5, 5, (100, 1))
    X = gauss_newton_rows(no_real_root, X0)
    assert np.isfinite(X).all()
    assert np.all(no_real_root(X) >= 1), f"seed {SEED}"


def test_no_unknowns_returns_the_input():
    f = Counted(circle_line)
    X0 = np.empty((4, 0))
    X = gauss_newton_rows(f, X0)
    assert X.shape == (4, 0)
    assert f.batches == []
    assert gauss_newton(f, []).shape == (0,)


def _poisoned(X):
    """circle_line, but NaN where x > 2.5 and inf where y > 2.5."""
    R = circle_line(X)
    R[X[:, 0] > 2.5] = np.nan
    R[X[:, 1] > 2.5, 0] = np.inf
    return R


def test_non_finite_rows_do_not_poison_the_others():
    rng = np.random.default_rng(SEED)
    healthy = rng.uniform(-2, 2, (30, 2))
    bad = np.array([[2.8, 0.0], [0.0, 2.8], [2.5 - 1e-8, 1.0], [np.nan, 0.0], [np.inf, 1.0]])
    X0 = np.vstack([healthy[:15], bad, healthy[15:]])
    X = gauss_newton_rows(_poisoned, X0)
    alone = gauss_newton_rows(_poisoned, healthy)
    ok = np.r_[0:15, 15 + len(bad):len(X0)]
    np.testing.assert_allclose(X[ok], alone, rtol=0, atol=1e-15)
    assert np.all(_norms(_poisoned, X[ok]) < STOP), f"seed {SEED}"
    # a start where the residual or its difference Jacobian is not finite stays put, reports no root
    np.testing.assert_array_equal(X[15:15 + len(bad)], bad)
    assert not np.any(_norms(_poisoned, X[15:15 + len(bad)]) < STOP)


def test_steps_into_a_non_finite_region_are_refused():
    """From (s, s) with small s the full step lands near (1, 1)/(4 s), inside the NaN region
    x > 2.5: it is halved back to finite residuals, and the starts still converge."""
    seen = []

    def watched(X):
        R = _poisoned(X)
        seen.append(not np.all(np.isfinite(R)))
        return R

    s = np.linspace(0.05, 0.095, 10)
    X0 = np.column_stack([s, s])
    X = gauss_newton_rows(watched, X0)
    assert any(seen), "no step reached the non-finite region: the test lost its point"
    assert np.all(np.isfinite(X))
    np.testing.assert_allclose(X, 1 / math.sqrt(2), rtol=1e-12)
    assert np.all(_norms(_poisoned, X) < STOP)


@pytest.mark.parametrize("x0", [[np.nan, 0.0], [np.inf, 1.0]])
def test_single_start_that_is_not_finite_gives_none(x0):
    assert gauss_newton(circle_line, x0) is None


def test_line_search_takes_the_longest_improving_halving_in_one_call():
    # Newton on atan from 1.5 overshoots to -1.69 (|atan| grows), half the step lands at
    # -0.097: sequential halving accepts the half step, and so must the batched search,
    # whose halvings of one row come in a single call
    f = Counted(np.arctan)
    x = gauss_newton_rows(f, np.array([[1.5]]), max_iter=1)[0, 0]
    newton = -math.atan(1.5) * (1 + 1.5 ** 2)
    assert x == pytest.approx(1.5 + newton / 2, abs=1e-6)
    # the start, the forward differences (2 rows), one line-search call of every level
    assert f.batches == [1, 2, LINE_LEVELS]
