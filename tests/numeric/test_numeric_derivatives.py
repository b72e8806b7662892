"""NumericMatrix derivatives (complex step or symbolic) and the batched residuals of points_on.

Seeds are fixed (SEED below).
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from rankloci.io import load_model
from rankloci.jacobians import task_matrix
from rankloci.numeric.equations import Equations, NumericMatrix, is_analytic, points_on
from rankloci.tolerances import ON_COMPONENT_RESIDUAL

SEED = 20261201

#: What this test accepts (the library compares no derivatives): dJ/dq by the complex step
#: (rankloci.numeric.equations.NumericMatrix) and by the symbolic derivative agree to this,
#: relative to the largest |dJ/dq_k| entry at the same q.  Both are exact up to rounding (the
#: complex step subtracts nothing); on the built-in arms they differ by <= 6e-16, and 1e-12
#: leaves room for the cancellation among the ~100 terms of an entry.
DERIVATIVE_RTOL = 1e-12
MODELS = ["puma560", "ur5", "pa10", "ssrms", "mobile10", "planar3r"]


def _symbolic_derivatives(M, variables, q):
    f = sp.lambdify(variables, [list(M.diff(v)) for v in variables], modules="numpy")
    return np.array(f(*q), dtype=float).reshape((len(variables),) + M.shape)


@pytest.mark.parametrize("name", MODELS)
def test_complex_step_matches_the_symbolic_derivative(name):
    tm = task_matrix(load_model(name))
    M = sp.Matrix(tm.matrix).subs(tm.parameters)
    nm = NumericMatrix(M, tm.variables, tm.angles)
    assert nm.complex_step
    for q in nm.random_q(np.random.default_rng(SEED), 5):
        exact = _symbolic_derivatives(M, nm.variables, q)
        got = nm.derivatives(q)
        assert got.shape == exact.shape
        assert np.max(np.abs(got - exact)) <= DERIVATIVE_RTOL * np.max(np.abs(exact))


def test_non_analytic_entries_use_the_symbolic_derivative():
    x, y = sp.symbols("x y", real=True)
    M = sp.Matrix([[sp.Abs(x) * y, sp.sin(x)],
                   [sp.Piecewise((x**2, x > 0), (-x, True)), sp.Max(x, y)]])
    nm = NumericMatrix(M, (x, y))
    assert not nm.complex_step
    for q in ([0.7, -1.3], [-0.4, 2.1]):
        exact = _symbolic_derivatives(M, (x, y), q)
        assert np.allclose(nm.derivatives(q), exact, rtol=0, atol=DERIVATIVE_RTOL)
        # the complex step would get these wrong: |x| is not analytic
        assert nm.derivatives(q)[0, 0, 0] == pytest.approx(np.sign(q[0]) * q[1])


def test_is_analytic():
    x = sp.Symbol("x")
    assert is_analytic([sp.sin(x) * sp.cos(x) ** 3 + sp.sqrt(3) * x / 7, sp.sqrt(1 + x**2)])
    assert is_analytic([sp.Integer(2), sp.pi * x])
    for bad in (sp.Abs(x), sp.sign(x), sp.Max(x, 0), sp.floor(x),
                sp.Piecewise((x, x > 0), (0, True))):
        assert not is_analytic([sp.sin(x), bad])


def test_batched_residuals_agree_with_pointwise_ones():
    q1, q2, q3 = sp.symbols("q1 q2 q3", real=True)
    eqs = Equations([sp.sin(q1) * sp.cos(q2) ** 3 - sp.Rational(1, 3), q3**2 - sp.sin(q2)],
                    (q1, q2, q3), {}, excluding=[sp.cos(q1) + q3, 5 * q2**3 - 1])
    Q = np.random.default_rng(SEED).uniform(-3, 3, (50, 3))
    rows = eqs.batch(Q).T
    excl = eqs.excluded_batch(Q)
    assert rows.shape == (50, 2) and excl.shape == (50, 2)
    for q, r, e in zip(Q, rows, excl):
        assert np.allclose(r, eqs(q), rtol=1e-15, atol=1e-15)
        assert np.allclose(e, eqs.excluded_values(q), rtol=1e-15, atol=1e-15)


def test_points_on_solves_onto_the_equations_and_avoids_exclusions():
    q1, q2, q3 = sp.symbols("q1 q2 q3", real=True)
    nm = NumericMatrix(sp.Matrix([[sp.cos(q1), q2, q3]]), (q1, q2, q3), (q1, q2, q3))
    eqs = Equations([sp.sin(q1) * sp.sin(q2) - sp.cos(q3) / 2], (q1, q2, q3), {},
                    excluding=[sp.sin(q3)])
    pts = points_on(eqs, nm, np.random.default_rng(SEED), 5)
    assert len(pts) == 5
    for q in pts:
        assert eqs.residual(q) <= ON_COMPONENT_RESIDUAL
        assert eqs.admits(q)


def test_points_on_gives_up_on_equations_without_real_points():
    q1, q2, q3 = sp.symbols("q1 q2 q3", real=True)
    nm = NumericMatrix(sp.Matrix([[q1, q2, q3]]), (q1, q2, q3), (q1, q2, q3))
    # positive everywhere: every start ends at a positive minimum of the cost
    eqs = Equations([sp.sin(q1) ** 2 + sp.sin(q2) ** 2 + sp.cos(q3) ** 2 * sp.sin(q1) + 1],
                    (q1, q2, q3), {})
    assert points_on(eqs, nm, np.random.default_rng(SEED), 1) == []
