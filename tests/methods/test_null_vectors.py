"""Cofactor null vectors from determinants without their circle powers."""

from __future__ import annotations

import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from rankloci.algebra import PolyRing, circle_free_det, laplace_det, transpose
from rankloci.methods.null_vectors import _on_common_scale

x, y = sp.symbols("x y")
a = sp.Symbol("a")
RING = PolyRing((x, y), (), (a,))

trig_terms = st.sampled_from([sp.Integer(1), sp.cos(x), sp.sin(x), sp.cos(y), sp.sin(y), a,
                              sp.cos(x) * sp.sin(y), a * sp.sin(x) ** 2, sp.cos(x + y),
                              sp.sin(x) * sp.cos(x) * sp.cos(y)])
trig_entries = st.lists(st.tuples(st.integers(-3, 3), trig_terms), min_size=1, max_size=3).map(
    lambda ts: sp.Add(*[c * t for c, t in ts]))


def _cofactors(A, order, cols, det):
    u = [RING.ctx.constant(0)] * len(A)
    for t, r in enumerate(order):
        rest = [order[s] for s in range(len(order)) if s != t]
        minor = det([[A[i][j] for j in cols] for i in rest], RING)
        u[r] = minor if t % 2 == 0 else -minor
    return u


@settings(max_examples=30, deadline=None, derandomize=True, database=None)
@given(st.lists(st.lists(trig_entries, min_size=3, max_size=3), min_size=3, max_size=3),
       st.booleans())
def test_cofactors_without_circles_are_one_null_vector_as_polynomials(entries, columns):
    """Each minor loses its own powers of C**2 + S**2; brought to a common scale, the
    cofactors are the exact ones divided by one common polynomial, and they annihilate the
    block's columns as polynomials, not only on the circles."""
    A = RING.from_sympy_rows(sp.Matrix(entries))
    if columns:
        A = transpose(A)
    order, cols = [0, 1, 2], [0, 1]
    exact = _cofactors(A, order, cols, laplace_det)
    scaled = _on_common_scale(RING, A, order, cols, _cofactors(A, order, cols, circle_free_det))
    assert scaled is not None
    for r in order:
        for s in order:
            assert scaled[r] * exact[s] == scaled[s] * exact[r]
    for c in cols:
        assert sum((scaled[r] * A[r][c] for r in order), RING.ctx.constant(0)).is_zero()
    live = [r for r in order if not exact[r].is_zero()]
    assert [r for r in order if not scaled[r].is_zero()] == live
