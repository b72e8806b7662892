"""Solving a condition and substituting the solution: the substituted polynomial has, at every
point, the value of the original at the point the substitution stands for.

Generators of the ring below: C_q, S_q, C_r, S_r (half angles of q, r), u, v (polynomial
variables), a, b (parameters).
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from rankloci.algebra import PolyRing, TermLimit
from rankloci.tree.branch import Branch, SubstitutedMatrices, apply_substitution, solve_condition

q, r, u, v, a, b = sp.symbols("q r u v a b")
RING = PolyRing((q, r), (u, v), (a, b))
CTX = RING.ctx
Cq, Sq, Cr, Sr, U, V, A, B = RING.gens
NV = len(RING.names)
SEED = 7

SMALL = settings(max_examples=50, deadline=None, derandomize=True, database=None)

#: condition -> the kind of substitution that solves it
CONDITIONS = {
    "S_q": (Sq, "zero"),
    "2*S_q": (2 * Sq, "zero"),
    "C_q": (Cq, "pi"),
    "-C_r/3": (-Cr / 3, "pi"),
    "u - 2*v": (U - 2 * V, "linear"),
    "3*u - v + a": (3 * U - V + A, "linear"),
    "a - 2*b": (A - 2 * B, "linear"),
    "a*C_q + b*S_q": (A * Cq + B * Sq, "pair"),
    "u*C_q + (v + 1)*S_q": (U * Cq + (V + 1) * Sq, "pair"),
    "C_q*C_r + S_q*S_r": (Cq * Cr + Sq * Sr, "pair"),
    "C_q + S_q": (Cq + Sq, "pair"),
}


def _solved(name):
    f, kind = CONDITIONS[name]
    sub, exceptional = solve_condition(f, RING)
    assert sub is not None and sub.kind == kind, (name, sub)
    return f, sub, exceptional


def _replaced(sub):
    """Generator indices the substitution replaces."""
    return (sub.index,) if sub.kind == "linear" else (2 * sub.index, 2 * sub.index + 1)


def _points(n=6, seed=SEED):
    return np.random.default_rng(seed).uniform(-2, 2, (n, NV))


def _at_substituted(sub, G):
    """Generator rows with the replaced generators set to the values of ``sub`` there."""
    H = G.copy()
    H[:, list(_replaced(sub))] = RING.compile(list(sub.values))(G)
    return H


def _polys(pair=0, max_degree=3):
    """Polynomials homogeneous in angle pair ``pair``, anything in the other generators."""
    def monomial(d):
        return st.tuples(st.integers(0, d), st.lists(st.integers(0, 2), min_size=NV, max_size=NV)).map(
            lambda im: tuple(im[0] if k == 2 * pair else d - im[0] if k == 2 * pair + 1 else e
                             for k, e in enumerate(im[1])))

    return st.integers(0, max_degree).flatmap(
        lambda d: st.dictionaries(monomial(d), st.integers(-3, 3).filter(bool), min_size=1, max_size=4)
    ).map(CTX.from_dict)


def test_simple_conditions_are_solved_by_the_expected_kind():
    for name in CONDITIONS:
        f, sub, exceptional = _solved(name)
        if sub.kind == "pair":
            # (C, S) proportional to (b, -a) where f = a*C + b*S; (a, b) = (0, 0) is left over
            assert exceptional and len(exceptional[0]) == 2
        else:
            assert exceptional == []


@pytest.mark.parametrize("name", CONDITIONS)
def test_condition_vanishes_after_its_own_substitution(name):
    f, sub, _ = _solved(name)
    assert apply_substitution(f, sub, RING).is_zero()


@pytest.mark.parametrize("name", CONDITIONS)
@settings(SMALL, max_examples=25)
@given(p=_polys(pair=0))
def test_substituted_value_is_the_value_at_the_substituted_point(name, p):
    """At any generator point g: (p after sub)(g) = p(g with the replaced generators set to the
    substitution's values at g); the result no longer contains the replaced generators."""
    _, sub, _ = _solved(name)
    G = _points()
    got = apply_substitution(p, sub, RING)
    assert not RING.variable_indices(got) & set(_replaced(sub))
    want = RING.compile([p])(_at_substituted(sub, G))[:, 0]
    scale = RING.compile([abs(c) * CTX.from_dict({m: 1}) for m, c in zip(p.monoms(), p.coeffs())])(
        np.abs(_at_substituted(sub, G))).sum(axis=1)
    err = np.abs(RING.compile([got])(G)[:, 0] - want)
    assert np.all(err <= 1e-12 * (1 + scale)), (f"seed {SEED}", err, scale)


@pytest.mark.parametrize("name", [n for n, (_, kind) in CONDITIONS.items() if kind == "pair"])
@settings(SMALL, max_examples=25)
@given(p=_polys(pair=0))
def test_pair_substitution_is_the_point_on_the_circle_scaled(name, p):
    """sub = (b, -a) for f = a*C_q + b*S_q: the angle is the point (C, S) = (b, -a)/rho of the
    circle, rho = sqrt(a**2 + b**2), where f vanishes; p homogeneous of degree d in the pair gives
    (p after sub) = rho**d * p(that point)."""
    f, sub, _ = _solved(name)
    G = _points()
    H = _at_substituted(sub, G)
    rho = np.hypot(H[:, 0], H[:, 1])
    assert np.all(rho > 1e-6), f"seed {SEED}: a point of the exceptional set"
    on_circle = H.copy()
    on_circle[:, :2] /= rho[:, None]
    np.testing.assert_allclose(RING.compile([f])(on_circle)[:, 0], 0, atol=1e-12)
    d = int(RING.pair_degrees(p)[0])
    got = RING.compile([apply_substitution(p, sub, RING)])(G)[:, 0]
    want = rho ** d * RING.compile([p])(on_circle)[:, 0]
    np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-9 * max(1.0, np.max(np.abs(want))))


free_of_q = st.dictionaries(st.tuples(st.just(0), st.just(0), *[st.integers(0, 2)] * (NV - 2)),
                            st.integers(-3, 3).filter(bool), max_size=3).map(
    lambda d: CTX.from_dict(d) if d else CTX.constant(0))


@settings(SMALL, max_examples=25)
@given(free_of_q)
def test_polynomial_free_of_the_replaced_generators_is_returned_unchanged(p):
    """Same object, not a copy: memoised matrices and branch keys rely on it being cheap."""
    for name in ("S_q", "C_q", "a*C_q + b*S_q", "C_q + S_q"):
        _, sub, _ = _solved(name)
        assert apply_substitution(p, sub, RING) is p
    _, sub, _ = _solved("u - 2*v")
    w = p.compose(*[CTX.constant(0) if k == sub.index else g for k, g in enumerate(RING.gens)])
    assert apply_substitution(w, sub, RING) is w


def test_unsolvable_condition_is_carried_as_implicit():
    branch, exceptional = Branch().with_condition(U * V - 1, RING)
    assert branch.implicit == (U * V - 1,) and branch.substitutions == () and exceptional == []
    assert solve_condition(Sq * Sq + Cq * U, RING) == (None, [])


def test_substituted_matrices_equal_the_branch_reduction_and_are_memoised():
    M = [[Cq * U + Sq, V * Cr], [A * Sq - B * Cq, U * V + Sr]]
    branch = Branch()
    for f in (U - 2 * V, A * Cq + B * Sq, Cr):
        branch, _ = branch.with_condition(f, RING)
    assert [s.kind for s in branch.substitutions] == ["linear", "pair", "pi"]
    subs = SubstitutedMatrices(RING)
    got = subs.of(M, branch)
    assert got == [[branch.reduce(p, RING) for p in row] for row in M]
    assert subs.of(M, branch) is got
    assert subs.of(M, Branch()) is M


def test_substituted_matrices_with_a_term_budget():
    # (C_q, S_q) ~ (u + v + 1, -(u - v)) turns C_q**3 (1 term) into a cube of three terms
    # (10 terms), so the matrix holds 11: a budget of 10 refuses it, and the refusal leaves
    # nothing behind that a later call would return
    M = [[Cq ** 3, Sr]]
    branch, _ = Branch().with_condition((U - V) * Cq + (U + V + 1) * Sq, RING)
    subs = SubstitutedMatrices(RING)
    with pytest.raises(TermLimit):
        subs.of(M, branch, max_terms=len(branch.reduce(Cq ** 3, RING)))
    full = subs.of(M, branch)
    assert full == [[branch.reduce(Cq ** 3, RING), Sr]]
    assert sum(len(p) for p in full[0]) == 11
    assert subs.of(M, branch, max_terms=11) is full
