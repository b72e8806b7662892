"""Determinants and factorisations in the half-angle ring, against sympy and against their
defining identities (multilinearity, det(AB) = det(A) det(B), unique factorisation)."""

from __future__ import annotations

import functools
import math
import operator

import flint
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from rankloci.algebra import (PolyRing, TermLimit, circle_free_det, irreducible_factors,
                              laplace_det, primitive_vector, transpose)

x, y = sp.symbols("x y")
a = sp.Symbol("a")
RING = PolyRing((x, y), (), (a,))
CTX = RING.ctx
NV = len(RING.names)                     # C_x, S_x, C_y, S_y, a
GEN_SYMBOLS = sp.symbols(RING.names)     # the generators as plain sympy symbols

SMALL = settings(max_examples=60, deadline=None, derandomize=True, database=None)


def _sympy(p):
    """``p`` as an expanded sympy polynomial in the generator symbols (exact, no trig)."""
    return sp.Add(*[sp.Rational(int(c.p), int(c.q)) * sp.Mul(*[g ** e for g, e in zip(GEN_SYMBOLS, m)])
                    for m, c in zip(p.monoms(), p.coeffs())])


def _matmul(A, B):
    return [[functools.reduce(operator.add, (A[i][k] * B[k][j] for k in range(len(B))))
             for j in range(len(B[0]))] for i in range(len(A))]


# small polynomials: up to three terms, each generator to degree <= 2, integer coefficients
monomials = st.tuples(*[st.integers(0, 2)] * NV)
polys = st.dictionaries(monomials, st.integers(-3, 3).filter(bool), max_size=3).map(
    lambda d: CTX.from_dict(d) if d else CTX.constant(0))
constants = st.integers(-4, 4).map(CTX.constant)


def square(entries, n_min=1, n_max=4):
    return st.integers(n_min, n_max).flatmap(
        lambda n: st.lists(st.lists(entries, min_size=n, max_size=n), min_size=n, max_size=n))


# --- laplace_det ------------------------------------------------------------------------------

@SMALL
@given(square(st.one_of(polys, constants)))
def test_det_equals_sympy_det(M):
    """Exact equality with sympy's determinant of the same matrix written in the generators."""
    want = sp.expand(sp.Matrix([[_sympy(p) for p in row] for row in M]).det(method="berkowitz"))
    got = laplace_det(M)
    assert isinstance(got, flint.fmpq_mpoly)
    assert sp.expand(_sympy(got) - want) == 0


@SMALL
@given(square(st.one_of(polys, constants), n_max=3).flatmap(
    lambda A: st.tuples(st.just(A), st.lists(st.lists(st.one_of(polys, constants), min_size=len(A),
                                                      max_size=len(A)), min_size=len(A), max_size=len(A)))))
def test_det_is_multiplicative(AB):
    A, B = AB
    assert laplace_det(_matmul(A, B)) == laplace_det(A) * laplace_det(B)


@SMALL
@given(square(polys, n_min=2), st.data())
def test_det_is_alternating_and_multilinear(M, data):
    n = len(M)
    i, j = data.draw(st.lists(st.integers(0, n - 1), min_size=2, max_size=2, unique=True), label="rows")
    d = laplace_det(M)
    swapped = list(M)
    swapped[i], swapped[j] = M[j], M[i]
    assert laplace_det(swapped) == -d
    repeated = list(M)
    repeated[i] = M[j]
    assert laplace_det(repeated).is_zero()
    # row i -> u + t*v: the determinant is linear in that row with polynomial weights
    v = data.draw(st.lists(polys, min_size=n, max_size=n), label="v")
    t = data.draw(polys, label="t")
    mixed = list(M)
    mixed[i] = [u + t * w for u, w in zip(M[i], v)]
    other = list(M)
    other[i] = v
    assert laplace_det(mixed) == d + t * laplace_det(other)
    assert laplace_det(transpose(M)) == d


def test_det_of_one_by_one_is_the_entry_and_empty_is_refused():
    C, S = RING.C(0), RING.S(0)
    assert laplace_det([[C * S + 3]]) == C * S + 3
    zero = laplace_det([[CTX.constant(0), C], [CTX.constant(0), S]])
    assert isinstance(zero, flint.fmpq_mpoly) and zero.is_zero()
    with pytest.raises(ValueError, match="empty"):
        laplace_det([])


def _dense(k):
    """A polynomial of (k + 1)**2 terms: (1 + C_x + ... + C_x**k) * (1 + S_y + ... + S_y**k)."""
    C, S = RING.C(0), RING.S(1)
    return sum((C ** i for i in range(1, k + 1)), CTX.constant(1)) * \
        sum((S ** i for i in range(1, k + 1)), CTX.constant(1))


def test_det_with_a_term_budget_stops_before_a_large_product():
    """Entries of 400 terms: each 2 x 2 product pairs 160000 terms, over 100 times a budget of
    1000, so the expansion stops before forming it; the same determinant with room is exact."""
    M = [[_dense(19), _dense(18)], [_dense(17), _dense(19) + 1]]
    with pytest.raises(TermLimit):
        laplace_det(M, RING, max_terms=1000)
    with pytest.raises(TermLimit):
        circle_free_det(M, RING, max_terms=1000)
    full = laplace_det(M, RING)
    assert laplace_det(M, RING, max_terms=len(full) + 10 ** 6) == full


def test_det_with_a_term_budget_stops_on_a_large_sum():
    """Products of 16 x 16 term pairs are within 100 times the budget of 80, but the
    determinant has 98 terms: it stops at the sum."""
    M = [[_dense(3), _dense(3) * RING.C(1)], [_dense(3) * RING.S(0), _dense(3) + 2]]
    full = laplace_det(M, RING)
    assert len(full) == 98
    with pytest.raises(TermLimit):
        laplace_det(M, RING, max_terms=80)
    assert laplace_det(M, RING, max_terms=98) == full


trig_terms = st.sampled_from([sp.Integer(1), sp.cos(x), sp.sin(x), sp.cos(y), sp.sin(y), a,
                              sp.cos(x) * sp.sin(y), a * sp.sin(x) ** 2, sp.cos(x + y)])
trig_entries = st.lists(st.tuples(st.integers(-3, 3), trig_terms), min_size=1, max_size=3).map(
    lambda ts: sp.Add(*[c * t for c, t in ts]))


@settings(SMALL, max_examples=25)
@given(square(trig_entries, n_max=3))
def test_det_of_padded_rows_is_homogeneous_of_the_summed_row_degrees(entries):
    """Rows padded to one degree per (C, S) pair give a determinant homogeneous in every pair,
    of the sum of the row degrees: its factors are then homogeneous too (module docstring)."""
    rows = RING.from_sympy_rows(sp.Matrix(entries))
    row_degrees = [[max(RING.pair_degrees(p)[k] for p in row) for k in range(RING.n_angles)] for row in rows]
    for row, degs in zip(rows, row_degrees):
        for p in row:
            if not p.is_zero():
                for mon in p.monoms():
                    assert [mon[2 * k] + mon[2 * k + 1] for k in range(RING.n_angles)] == degs
    d = laplace_det(rows)
    want = [sum(col) for col in zip(*row_degrees)]
    for mon in d.monoms():
        assert [mon[2 * k] + mon[2 * k + 1] for k in range(RING.n_angles)] == want


@settings(SMALL, max_examples=25)
@given(square(trig_entries, n_max=3), st.booleans())
def test_circle_free_det_is_the_det_without_its_circle_powers(entries, columns):
    """The determinant expanded on the circles and made homogeneous again is exactly the
    determinant divided by every power of C**2 + S**2 that divides it, for a matrix homogeneous
    by rows or (transposed) by columns."""
    rows = RING.from_sympy_rows(sp.Matrix(entries))
    if columns:
        rows = transpose(rows)
    want = laplace_det(rows)
    if not want.is_zero():
        for k in range(RING.n_angles):
            want, _ = _strip(want, _circle(k))
    assert circle_free_det(rows, RING) == want


@SMALL
@given(st.lists(st.tuples(polys, st.integers(0, 2), st.integers(0, 2)), min_size=1, max_size=3))
def test_on_circles_and_homogenized_go_back_and_forth(parts):
    """A polynomial homogeneous in each pair (terms padded to common degrees) is recovered from
    its reduced form at its own degrees, and both take the same values on the circles."""
    target = (6, 6)
    p = CTX.constant(0)
    for f, i, j in parts:
        for mon, c in zip(f.monoms(), f.coeffs()):
            dx, dy = mon[0] + mon[1], mon[2] + mon[3]
            pad_x, pad_y = target[0] - dx - 2 * i, target[1] - dy - 2 * j
            term = CTX.from_dict({mon: c})
            # odd remainders are made up with one more C, so every term has the target degrees
            term *= RING.C(0) ** (pad_x % 2) * RING.C(1) ** (pad_y % 2)
            term *= _circle(0) ** (i + pad_x // 2) * _circle(1) ** (j + pad_y // 2)
            p += term
    reduced = RING.on_circles(p)
    assert all(m[0] <= 1 and m[2] <= 1 for m in reduced.monoms())
    if p.is_zero():
        assert reduced.is_zero()
        return
    assert RING.homogenized(reduced, RING.pair_degrees(p)) == p
    rest = p
    for k in range(RING.n_angles):
        rest, _ = _strip(rest, _circle(k))
    assert RING.homogenized(reduced) == rest
    for t in (0.3, 1.9, -2.4):
        point = [math.cos(t / 2), math.sin(t / 2), math.cos(1.3 * t), math.sin(1.3 * t), 0.7]
        assert math.isclose(_value(p, point), _value(reduced, point), rel_tol=1e-9, abs_tol=1e-9)


def _value(p, point):
    return sum(float(c) * math.prod(v ** int(e) for v, e in zip(point, m))
               for m, c in zip(p.monoms(), p.coeffs()))


def test_homogenized_refuses_what_no_homogeneous_polynomial_reduces_to():
    C, S = RING.C(0), RING.S(0)
    with pytest.raises(ValueError):
        RING.homogenized(C * S + C, (2, 0))
    with pytest.raises(ValueError):
        RING.homogenized(C ** 3, (1, 0))


# --- irreducible_factors -----------------------------------------------------------------------

def _circle(k):
    return RING.C(k) ** 2 + RING.S(k) ** 2


def _strip(p, f):
    """``p`` divided by ``f`` as often as it divides exactly, and that number."""
    m = 0
    while True:
        q, r = divmod(p, f)
        if not r.is_zero():
            return p, m
        p, m = q, m + 1


nonconstant = polys.filter(lambda p: not p.is_constant())


@SMALL
@given(st.lists(st.tuples(nonconstant, st.integers(1, 2)), min_size=1, max_size=3),
       st.lists(st.integers(0, 2), min_size=2, max_size=2),
       st.fractions(min_value=-5, max_value=5).filter(bool))
def test_factors_rebuild_the_polynomial_without_the_circles(parts, circles, scale):
    """p = const * (C_x**2+S_x**2)**i * (C_y**2+S_y**2)**j * prod f**m: the factors, each
    irreducible, normalised and distinct, rebuild p with their multiplicities, and what is
    left over is a constant times circle factors only."""
    p = CTX.constant(flint.fmpq(scale.numerator, scale.denominator))
    for f, m in parts:
        p *= f ** m
    for k, e in enumerate(circles):
        p *= _circle(k) ** e
    factors = irreducible_factors(p, RING)
    assert len(set(map(str, factors))) == len(factors)
    rest = p
    for f in factors:
        assert not f.is_constant()
        assert f.leading_coefficient() == 1
        assert all(f != _circle(k) for k in range(RING.n_angles))
        _, facs = f.factor()
        assert len(facs) == 1 and facs[0][1] == 1, f"{f} factors as {facs}"
        rest, m = _strip(rest, f)
        assert m >= 1
    for k in range(RING.n_angles):
        rest, _ = _strip(rest, _circle(k))
    assert rest.is_constant() and not rest.is_zero()


def test_circle_is_dropped_and_nothing_else():
    C, S = RING.C(0), RING.S(0)
    Cy, Sy = RING.C(1), RING.S(1)
    assert irreducible_factors(_circle(0) * _circle(1) * 7, RING) == []
    # not the circle of one pair: kept
    for keep in (C ** 2 + 2 * S ** 2, C ** 2 + Sy ** 2, C * Cy + S * Sy):
        assert irreducible_factors(keep * _circle(0), RING) == [keep]
    got = irreducible_factors(-6 * S ** 2 * (3 * C + S) * _circle(0), RING)
    assert sorted(map(str, got)) == sorted(map(str, [C + S / 3, S]))


def test_constant_has_no_factors_and_zero_is_refused():
    assert irreducible_factors(CTX.constant(-3), RING) == []
    with pytest.raises(ValueError, match="zero"):
        irreducible_factors(CTX.constant(0), RING)


# --- primitive_vector ---------------------------------------------------------------------------

@SMALL
@given(st.lists(st.one_of(polys, constants), min_size=1, max_size=4), nonconstant,
       st.lists(st.integers(0, 2), min_size=2, max_size=2))
def test_primitive_vector_divides_out_exactly_the_common_factor(v, f, circles):
    """(f * circles * v) comes back as a polynomial multiple of it whose nonzero entries have no
    common factor: v itself, up to the common factor v already had."""
    g = f
    for k, e in enumerate(circles):
        g *= _circle(k) ** e
    w = primitive_vector([g * p for p in v])
    assert [p.is_zero() for p in w] == [p.is_zero() for p in v]
    nonzero = [p for p in w if not p.is_zero()]
    if not nonzero:
        return
    assert functools.reduce(lambda a, b: a.gcd(b), nonzero).is_constant()
    # w = (g * v) / h for one polynomial h: every ratio of entries is kept
    i = next(k for k, p in enumerate(v) if not p.is_zero())
    for p, q in zip(v, w):
        assert p * w[i] == q * v[i]
