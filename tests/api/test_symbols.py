"""The caller's own symbols come back: a locus of a sympy matrix speaks in the caller's ``x``."""

from __future__ import annotations

import sympy as sp

import rankloci


def _symbols_of(locus):
    found = set(locus.variables) | set(locus.parameters)
    for c in locus.components:
        for e in (*c.equations, *c.excluding, *c.free, *c.solved,
                  *(v for vals in c.solved.values() for v in vals),
                  *(x for vec in c.direction for x in vec)):
            found |= sp.sympify(e, strict=True).free_symbols
    return found


def test_locus_equations_take_the_callers_symbols_in_subs():
    x, y, k = sp.symbols("x y k")          # no assumptions: the library's own are real
    L = rankloci.locus(sp.Matrix([[sp.cos(x), k * y], [sp.sin(x), 1]]), variables=[x, y],
                       parameters={k: 2})
    assert L.variables == (x, y) and list(L.parameters) == [k]
    (c,) = L.components
    value = c.equations[0].subs({x: sp.pi / 4, y: sp.Rational(1, 2), k: 2})
    assert value == 0                       # the real x of the parser would leave it symbolic
    assert c.equations[0].subs({x: 0.3, y: 0.0, k: 2}).is_number
    assert _symbols_of(L) <= {x, y, k}


def test_solved_free_and_direction_use_the_callers_symbols():
    x, y = sp.symbols("x y")
    L = rankloci.locus(sp.Matrix([[sp.sin(x), 0], [0, y]]), variables=[x, y])
    by_solved = {tuple(c.solved): c for c in L.components}
    assert set(by_solved) == {(x,), ()}
    assert by_solved[(x,)].free == (y,)
    assert _symbols_of(L) <= {x, y}
    assert all(s.is_real is None for s in _symbols_of(L))
    # the locus still answers, and the check maps it back to the model's symbols
    assert L.contains({x: 0.0, y: 0.4}) and not L.contains([0.1, 0.4])
    assert rankloci.check(sp.Matrix([[sp.sin(x), 0], [0, y]]), L, variables=[x, y],
                          samples=2).ok


def test_symbols_without_variables_and_the_jacobian_come_back_too():
    x, y = sp.symbols("x y")
    M = sp.Matrix([[sp.cos(x), y], [sp.sin(x), 1]])
    assert rankloci.locus(M).variables == (x, y)
    J = rankloci.jacobian(M)
    assert J.variables == (x, y) and J.matrix.free_symbols == {x, y}


def test_a_robot_keeps_its_real_joint_symbols():
    L = rankloci.locus("planar2r", numeric=True)
    assert [v.is_real for v in L.variables] == [True, True]
