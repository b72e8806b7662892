"""numpy in and out: batches of configurations, component equations and J as array functions."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

import rankloci
from rankloci.errors import ArgumentError


@pytest.fixture(scope="module")
def puma():
    return rankloci.locus("puma560", numeric=True)


def _samples(locus):
    """One point of every component, in the order of the variables."""
    names = [str(v) for v in locus.variables]
    return np.array([[c.sample[n] for n in names] for c in locus.components])


def test_contains_takes_n_configurations_and_answers_each(puma):
    rng = np.random.default_rng(4)
    on = _samples(puma)
    off = rng.uniform(-np.pi, np.pi, size=(5, 6))
    Q = np.vstack([on, off])
    got = puma.contains(Q)
    assert isinstance(got, np.ndarray) and got.dtype == bool and got.shape == (len(Q),)
    assert got.tolist() == [puma.contains(q) for q in Q]
    assert got[:len(on)].all() and not got[len(on):].any()
    one = puma.contains(on[0])
    assert type(one) is bool and one


def test_equations_function_takes_the_joint_vector_for_every_component(puma):
    on = _samples(puma)
    rng = np.random.default_rng(5)
    Q = rng.uniform(-np.pi, np.pi, size=(4, 6))
    for k, comp in enumerate(puma.components):
        f = puma.equations_function(k)
        assert f(on[k]).shape == (len(comp.equations),)
        assert np.allclose(f(on[k]), 0.0, atol=1e-9)
        values = f(Q)
        assert values.shape == (4, len(comp.equations))
        by_hand = comp.lambdify(puma.variables, puma.parameters)
        assert np.allclose(values, np.array([by_hand(*q) for q in Q], dtype=float))


def test_equations_function_substitutes_the_parameters():
    x, y, k = sp.symbols("x y k")
    L = rankloci.locus(sp.Matrix([[sp.cos(x), k * y], [sp.sin(x), 1]]), parameters={k: 2})
    (c,) = L.components
    f = L.equations_function(0)
    q = np.array([0.3, 0.7])
    expected = float(c.equations[0].subs({x: q[0], y: q[1], k: 2}))
    assert f(q) == pytest.approx([expected])
    assert f({"x": 0.3, y: 0.7}) == pytest.approx([expected])


def test_jacobian_evaluate_is_the_matrix_at_each_configuration(puma):
    J = rankloci.jacobian("puma560")
    q = np.array([0.1, -0.4, 0.9, 0.2, 0.5, -1.1])
    at_q = J.evaluate(q)
    exact = sp.Matrix(J.matrix).subs(J.parameters).subs(dict(zip(J.variables, q)))
    assert at_q.shape == J.shape
    assert np.allclose(at_q, np.array(exact, dtype=float))
    on = _samples(puma)
    batch = J.evaluate(on)
    assert batch.shape == (len(on),) + J.shape
    s = np.linalg.svd(batch, compute_uv=False)
    assert (s[:, -1] / s[:, 0] < 1e-8).all()            # singular on every component
    s_q = np.linalg.svd(at_q, compute_uv=False)
    assert s_q[-1] / s_q[0] > 1e-3


@pytest.mark.parametrize("bad", [[np.nan, 0.0], [[0.1, 0.2], [0.3, np.inf]]])
def test_a_value_that_is_no_finite_number_is_refused(bad):
    L = rankloci.locus("planar2r", numeric=True)
    J = rankloci.jacobian("planar2r")
    for call in (L.contains, L.equations_function(0), J.evaluate,
                 lambda q: rankloci.is_singular("planar2r", q, locus=L)):
        with pytest.raises(ArgumentError, match="not a finite number"):
            call(bad)
    assert isinstance(ArgumentError("x"), ValueError)


def test_is_singular_answers_a_batch_too():
    got = rankloci.is_singular("planar2r", np.array([[0.3, 0.0], [0.3, 1.0], [1.0, np.pi]]))
    assert got.tolist() == [True, False, True]


@pytest.mark.parametrize("q, words", [
    ([0.1, 0.2, 0.3], "3 values"),
    (np.zeros((2, 3)), r"shape \(2, 3\)"),
    ({"q1": 0.1}, "no value for 'q2'"),
    ({"q1": 0.1, "q2": 0.2, "q7": 0.0}, "'q7' is not a variable"),
    (["a", "b"], "must be numbers"),
])
def test_wrong_configurations_are_named(q, words):
    L = rankloci.locus("planar2r", numeric=True)
    with pytest.raises(ArgumentError, match=words):
        L.contains(q)
