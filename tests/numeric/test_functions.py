"""Numeric functions of expressions too long for one lambdify (a sum of thousands of terms)."""

import numpy as np
import pytest
import sympy as sp

from rankloci.numeric.functions import CHUNK_TERMS, numpy_function


def _long_sum(n_terms):
    x, y, z = sp.symbols("x y z", real=True)
    terms = [(k % 7 + 1) * x ** (k % 13) * sp.cos(y) ** (k % 11) * sp.sin(z) ** (k // 143)
             for k in range(n_terms)]
    return (x, y, z), sp.Add(*terms)


def test_a_sum_that_lambdify_cannot_compile_is_evaluated_exactly_as_sympy_does():
    variables, e = _long_sum(12000)
    assert len(e.args) == 12000
    with pytest.raises(RecursionError):
        sp.lambdify(variables, e, modules="numpy")
    f = numpy_function(variables, [e, variables[0]])
    point = (0.3, 1.1, -0.7)
    got = f(*point)
    want = float(e.evalf(30, subs=dict(zip(variables, point))))
    assert got[0] == pytest.approx(want, rel=1e-12)
    assert got[1] == 0.3


def test_small_expressions_are_compiled_as_lambdify_compiles_them():
    x, y = sp.symbols("x y")
    f = numpy_function([x, y], [x * y + 1, sp.sin(x)])
    assert f(2.0, 3.0) == [7.0, pytest.approx(np.sin(2.0))]
    g = numpy_function([x, y], sp.Add(*[x ** k for k in range(3 * CHUNK_TERMS)]))
    assert g(np.array([0.5, 0.0]), 1.0) == pytest.approx([2.0, 1.0])
