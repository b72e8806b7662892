"""Exact decisions at points of a branch modulo a prime (rankloci.tree.modular).

Generators of the ring below: C_q, S_q, C_r, S_r (half angles of q, r), u, v (polynomial
variables), a (a parameter).
"""

from __future__ import annotations

import flint
import numpy as np
import sympy as sp

from rankloci.algebra import PolyRing
from rankloci.tree.branch import Branch
from rankloci.tree.modular import ModularProbe, evaluate
from rankloci.tree.probe import Probe

q, r, u, v, a = sp.symbols("q r u v a")
RING = PolyRing((q, r), (u, v), (a,))
Cq, Sq, Cr, Sr, U, V, A = RING.gens
ONE = RING.ctx.constant(1)


def probe(seed=0):
    return ModularProbe(RING, np.random.default_rng(seed))


def branch_of(*conditions):
    b = Branch()
    for c in conditions:
        b, _ = b.with_condition(c, RING)
    return b


def test_points_satisfy_the_implicit_equations_and_avoid_the_exclusions():
    f = U * U + V * U - 3 * Cq * Cq + Sq * Sq          # not solvable by a substitution
    b = branch_of(f).excluding(U - V)
    assert b.implicit
    P, pts = probe().points(b)
    assert flint.fmpz(P).is_prime() and P > 2 ** 61
    for g in pts:
        assert evaluate(f, g, P) == 0
        assert evaluate(U - V, g, P) != 0


def test_substitutions_hold_at_the_points():
    b = branch_of(U * Cq + (V + 1) * Sq, Sr)             # a pair and q_r = 0
    P, pts = probe().points(b)
    for g in pts:
        assert evaluate(U * Cq + (V + 1) * Sq, g, P) == 0
        assert evaluate(Sr, g, P) == 0 and evaluate(Cr, g, P) != 0


def test_exact_rank_where_the_numeric_rank_is_fooled():
    # det = 1e-9 * u: regular for u != 0, but sigma_min/sigma_max ~ 5e-10 < RANK_RTOL
    tiny = flint.fmpq(1, 10 ** 9)
    M = [[ONE, ONE], [ONE, ONE + tiny * U]]
    b = Branch()
    assert probe().rank(M, b) == 2
    g = np.zeros(len(RING.names))
    g[RING.names.index("u")] = 1.0
    assert Probe(RING).rank_at(M, g) == 1


def test_rank_drops_exactly_on_the_branch_of_the_determinant():
    M = [[U, V * Cq], [Sq, U + Cq]]
    det = U * (U + Cq) - V * Cq * Sq
    b = branch_of(det)
    assert b.implicit
    assert probe().rank(M, b) == 1
    assert probe().rank(M, Branch()) == 2
    assert probe().vanishes(det, b)
    assert not probe().vanishes(U, b)


def test_dimension_counts_solved_joint_generators():
    m = probe()
    assert m.dimension(Branch()) == 4                              # q, r, u, v
    assert m.dimension(branch_of(Sq)) == 3
    assert m.dimension(branch_of(Sq, U - V * V)) == 2
    # a parameter condition fixes no joint variable
    assert m.dimension(branch_of(U * U + A * V * V - Cr * Cr)) == 3


def test_a_squared_equation_counts_once():
    # the gradient of (u - v)**2 vanishes on its zero set; its zero set is still 3-dimensional
    b = Branch(conditions=((U - V) ** 2,), implicit=((U - V) ** 2,))
    assert probe().dimension(b) == 3


def test_non_square_discriminant_needs_another_prime():
    # C**2 + 1600 C S - S**2 has roots mod P only when 640001 is a square mod P
    f = Cq * Cq + 1600 * Cq * Sq - Sq * Sq
    got = probe(3).points(branch_of(f))
    assert got is not None
    P, pts = got
    assert pow(640001, (P - 1) // 2, P) == 1
    assert all(evaluate(f, g, P) == 0 for g in pts)


def test_too_many_implicit_equations_are_left_to_the_numeric_probes():
    eqs = [U * U - V * Cq * Cq + Sq * Sq, V * V - U * Cr * Cr + Sr * Sr,
           U * V - A * Cq * Cq + Sr * Sr, U * U * V - Cr * Cr + Sq * Sq]
    b = Branch(conditions=tuple(eqs), implicit=tuple(eqs))
    assert probe().points(b) is None
    assert probe().rank([[U]], b) is None
