"""A sympy matrix from the caller is data already: any symbol names, any entry that is a
polynomial in the variables and in sines and cosines of them; the rest refused at once."""

from __future__ import annotations

import pytest
import sympy as sp

import rankloci
from rankloci.errors import LocusError, ModelError


def test_symbols_of_any_name_come_back_as_the_callers():
    th, y, s0 = sp.Symbol("θ"), sp.Symbol("y'"), sp.Symbol("_s0")   # _s0: no clash
    M = sp.Matrix([[sp.cos(th), y + s0], [sp.sin(th), 1]])
    L = rankloci.locus(M, parameters={s0: 0})
    assert L.variables == (y, th) and L.complete is True      # natural order of the names
    (c,) = L.components
    assert c.equations[0].free_symbols == {th, y, s0}               # the caller's own symbols
    assert c.equations[0].subs({th: sp.pi / 4, y: 1, s0: 0}) == 0
    assert L.contains({"θ": 0.7853981633974483, "y'": 1.0}) and not L.contains([1.0, 0.0])
    J = rankloci.jacobian(M, parameters={s0: 0})
    assert J.variables == (y, th) and J.matrix[0, 1] == y + s0


@pytest.mark.parametrize("entry, named", [
    (sp.Abs(sp.Symbol("t")), "Abs"), (sp.exp(sp.Symbol("t")), "exp"),
    (sp.Function("f")(sp.Symbol("t")), "f"), (sp.tan(sp.Symbol("t")), "tan")])
def test_an_entry_with_another_function_is_refused_when_loaded(entry, named):
    t, y = sp.symbols("t y")
    with pytest.raises(ModelError, match=rf"matrix entry \[1\]\[0\] .*: not a polynomial in the "
                                         rf"variables and in sines and cosines of them.*uses {named}"):
        rankloci.load_model(sp.Matrix([[sp.sin(t), y], [entry, 1]]))


@pytest.mark.parametrize("entry", ["1/t", "sqrt(t)", "sin(t/2)", "t**(1/3)"])
def test_an_entry_that_is_no_polynomial_is_refused_when_loaded(entry):
    t, y = sp.symbols("t y")
    e = sp.sympify(entry, locals={"t": t})
    with pytest.raises(ModelError, match=r"matrix entry \[0\]\[1\] .*not a polynomial"):
        rankloci.load_model(sp.Matrix([[sp.sin(t), e], [y, 1]]))


def test_a_variable_inside_and_outside_sin_is_refused_when_loaded():
    t, y = sp.symbols("t y")
    with pytest.raises(ModelError, match="t appears both inside sin/cos and outside"):
        rankloci.load_model(sp.Matrix([[sp.sin(t), t], [y, 1]]))


def test_a_parameter_under_a_root_needs_its_value():
    """sqrt(k) is no polynomial in the parameter k; with numeric=True it is sqrt(2)."""
    t, y, k = sp.symbols("t y k")
    M = sp.Matrix([[sp.sqrt(k) * sp.sin(t), y], [sp.sin(t), 1]])
    with pytest.raises(LocusError, match=r"sqrt\(k\)\*sin\(t\) is not a polynomial.*numeric=True"):
        rankloci.locus(M, parameters={k: 2})
    L = rankloci.locus(M, parameters={k: 2}, numeric=True)
    assert sorted(str(c.equations[0]) for c in L.components) == ["sin(t)", "y - sqrt(2)"]


def test_an_entry_longer_than_a_files_expression_is_taken_as_it_is():
    """A model file's expression has at most MAX_LENGTH characters; the caller's sympy entry is
    data already, taken by the same rules (floats exact, symbols real, caller's back)."""
    import numpy as np

    from rankloci.expr import MAX_LENGTH

    x, y = sp.symbols("x y")
    long = sum(sp.Float(k / 8) * sp.cos(x) ** k * y ** (k % 3) for k in range(1, 120))
    assert len(sp.sstr(long)) > MAX_LENGTH
    M = sp.Matrix([[long, y], [sp.sin(x), 1]])
    m = rankloci.load_model(M)
    entry = m.matrix[0, 0]
    assert not entry.atoms(sp.Float) and all(s.is_real for s in entry.free_symbols)
    assert entry.coeff(sp.cos(m.variables[0]) ** 4 * m.variables[1]) == sp.Rational(1, 2)
    J = rankloci.jacobian(M)
    assert J.variables == (x, y)
    q = np.array([0.3, -0.7])
    want = np.array(M.subs({x: q[0], y: q[1]}).evalf(), dtype=float)
    np.testing.assert_allclose(J.evaluate(q), want, rtol=1e-13)
