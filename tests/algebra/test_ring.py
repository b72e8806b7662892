"""The exact polynomial ring: numeric evaluation and variable bookkeeping against sympy."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from rankloci.algebra import PolyRing

x, y = sp.symbols("x y")
t = sp.Symbol("t")
a = sp.Symbol("a")

EXPRS = [
    sp.sin(x) * sp.cos(y) + a * sp.sin(y),
    sp.cos(x) ** 3 - 2 * t * sp.sin(x) * sp.sin(y) + 5,
    a ** 2 + t,
    sp.Integer(7),
    sp.Integer(0),
]


def _ring():
    return PolyRing((x, y), (t,), (a,))


def _generators(ring, q):
    """Generator values (C, S per angle, then t, then a) at rows q = (x, y, t, a)."""
    X = np.empty((len(q), len(ring.names)))
    X[:, 0], X[:, 1] = np.cos(q[:, 0] / 2), np.sin(q[:, 0] / 2)
    X[:, 2], X[:, 3] = np.cos(q[:, 1] / 2), np.sin(q[:, 1] / 2)
    X[:, 4], X[:, 5] = q[:, 2], q[:, 3]
    return X


@pytest.mark.parametrize("batch", [1, 5, 64, 65, 300])
def test_compiled_values_equal_sympy(batch):
    """One evaluator for several polynomials (one of them zero, one constant) gives the
    values of the original trig expressions, for single points and for batches on both
    sides of the size where the evaluator changes its gather strategy."""
    ring = _ring()
    polys = [ring.from_sympy(e) for e in EXPRS]
    f = ring.compile(polys)
    rng = np.random.default_rng(1)
    q = rng.uniform(-3, 3, (batch, 4))
    got = f(_generators(ring, q))
    want = np.array([[float(e.subs({x: r[0], y: r[1], t: r[2], a: r[3]})) for e in EXPRS]
                     for r in q])
    assert got.shape == (batch, len(EXPRS))
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12)
    single = f(_generators(ring, q[:1])[0])
    assert single.shape == (len(EXPRS),)
    np.testing.assert_allclose(single, want[0], rtol=1e-12, atol=1e-12)


def test_variable_indices_names_the_generators_used():
    ring = _ring()
    p = ring.from_sympy(t * a + 1)
    assert {ring.names[i] for i in ring.variable_indices(p)} == {"t", "a"}
    assert ring.variable_indices(ring.from_sympy(sp.Integer(3))) == set()
    assert ring.variable_indices(ring.from_sympy(sp.Integer(0))) == set()


def test_compile_reuses_the_evaluator_of_equal_polynomials(monkeypatch):
    """Equal lists (term for term, other objects) share one evaluator; a list that differs in
    one coefficient, with the same terms and degrees, gets its own; the memo is bounded."""
    import rankloci.algebra.ring as ring_module

    ring = _ring()
    polys = [ring.from_sympy(e) for e in EXPRS]
    f = ring.compile(polys)
    assert ring.compile([ring.from_sympy(e) for e in EXPRS]) is f
    other = [ring.from_sympy(EXPRS[0] + sp.sin(x) * sp.cos(y))] + polys[1:]  # 2 sin x cos y
    g = ring.compile(other)
    assert g is not f
    point = _generators(ring, np.array([[0.3, -1.1, 0.7, 2.0]]))[0]
    assert g(point)[0] != f(point)[0] and np.all(g(point)[1:] == f(point)[1:])
    # past its size the memo starts afresh when the next new list comes
    monkeypatch.setattr(ring_module, "COMPILE_MEMO_TERMS", 0)
    ring.compile(polys[2:])
    assert ring.compile(polys) is not f


@pytest.mark.parametrize("batch", [1, 5, 300])
def test_absolute_evaluator_is_that_of_the_absolute_coefficients(batch):
    """``compile(polys, absolute=True)`` evaluates the polynomials with every coefficient
    replaced by its absolute value (abs_poly), bit for bit, and is kept beside the evaluator
    of the polynomials themselves."""
    from rankloci.algebra import abs_poly

    ring = _ring()
    polys = [ring.from_sympy(e) for e in EXPRS]
    size = ring.compile(polys, absolute=True)
    assert size is not ring.compile(polys)
    assert ring.compile([ring.from_sympy(e) for e in EXPRS], absolute=True) is size
    G = np.abs(_generators(ring, np.random.default_rng(2).uniform(-3, 3, (batch, 4))))
    want = ring.compile([abs_poly(p, ring) for p in polys])(G)
    assert np.array_equal(size(G), want)
    assert not np.array_equal(size(G), ring.compile(polys)(G))


@pytest.mark.parametrize("batch", [1, 5, 300])
def test_sized_evaluator_gives_values_and_term_sizes_at_once(batch):
    """``compile(polys, sized=True)`` returns, from one product of the terms, the values and
    the term sizes that the value and absolute evaluators give at x and |x|, bit for bit
    (negative generator values included)."""
    ring = _ring()
    polys = [ring.from_sympy(e) for e in EXPRS]
    G = _generators(ring, np.random.default_rng(3).uniform(-3, 3, (batch, 4)))
    G[:, 4:] *= -1.5
    values, sizes = ring.compile(polys, sized=True)(G)
    assert np.array_equal(values, ring.compile(polys)(G))
    assert np.array_equal(sizes, ring.compile(polys, absolute=True)(np.abs(G)))
    one = ring.compile(polys, sized=True)(G[0])
    assert one[0].shape == one[1].shape == (len(EXPRS),)
    assert np.array_equal(one[1], sizes[0])


@pytest.mark.parametrize("batch", [1, 5, 64])
def test_small_batches_gathered_at_once_give_the_per_generator_values(batch, monkeypatch):
    """A small evaluation gathers all its factors at once; it multiplies them in the order of
    the per-generator gather, so both give the same values and sizes, bit for bit."""
    import rankloci.algebra.ring as ring_module

    ring = _ring()
    polys = [ring.from_sympy(e) for e in EXPRS]
    G = _generators(ring, np.random.default_rng(4).uniform(-3, 3, (batch, 4)))
    G[:, 4:] *= -1.5
    at_once = [ring.compile(polys, **kw)(G) for kw in ({}, {"absolute": True})]
    sized = ring.compile(polys, sized=True)(G)
    monkeypatch.setattr(ring_module, "SMALL_GATHER", 0)
    assert np.array_equal(at_once[0], ring.compile(polys)(G))
    assert np.array_equal(at_once[1], ring.compile(polys, absolute=True)(G))
    per_generator = ring.compile(polys, sized=True)(G)
    assert all(np.array_equal(s, p) for s, p in zip(sized, per_generator))


@pytest.mark.parametrize("batch", [65, 300])
def test_large_batches_are_evaluated_64_points_at_a_time(batch, monkeypatch):
    """Above MANY_GATHER factors, a batch of more than 64 points is evaluated in chunks of
    64: the values and sizes are those of each chunk evaluated alone, bit for bit, and
    those of the single gather to rounding."""
    import rankloci.algebra.ring as ring_module

    ring = _ring()
    polys = [ring.from_sympy(e) for e in EXPRS]
    G = _generators(ring, np.random.default_rng(5).uniform(-3, 3, (batch, 4)))
    whole = ring.compile(polys, sized=True)(G)
    monkeypatch.setattr(ring_module, "MANY_GATHER", 0)
    values, sizes = ring.compile(polys, sized=True)(G)
    plain = ring.compile(polys)(G)
    assert values.shape == sizes.shape == plain.shape == (batch, len(EXPRS))
    for i in range(0, batch, 64):
        chunk = ring.compile(polys, sized=True)(G[i:i + 64])
        assert np.array_equal(values[i:i + 64], chunk[0])
        assert np.array_equal(sizes[i:i + 64], chunk[1])
        assert np.array_equal(plain[i:i + 64], chunk[0])
    np.testing.assert_allclose(values, whole[0], rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(sizes, whole[1], rtol=1e-12, atol=1e-12)
