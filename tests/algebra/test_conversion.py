"""sympy <-> half-angle polynomials: conversions keep the values at every configuration.

The generator point of angles q is C = cos(q/2), S = sin(q/2); values are compared there,
never expressions (the readable form is normalised and its rational content cleared).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from rankloci.algebra import PolyRing
from rankloci.errors import LocusError

x, y = sp.symbols("x y")
t = sp.Symbol("t")
a = sp.Symbol("a")
RING = PolyRing((x, y), (t,), (a,))
SYMBOLS = (x, y, t, a)
SEED = 20240611

SMALL = settings(max_examples=40, deadline=None, derandomize=True, database=None)

factors = st.sampled_from([sp.cos(x), sp.sin(x), sp.cos(y), sp.sin(y), a, t,
                           sp.cos(x + y), sp.sin(2 * x), sp.cos(x - y)])
terms = st.tuples(st.fractions(min_value=-3, max_value=3, max_denominator=4),
                  st.lists(factors, max_size=3)).map(
    lambda ct: sp.Rational(ct[0].numerator, ct[0].denominator) * sp.Mul(*ct[1]))
trig_polys = st.lists(terms, min_size=1, max_size=4).map(lambda ts: sp.Add(*ts))


def _configurations(n=8, seed=SEED):
    """Rows (x, y, t, a), angles anywhere on their circles; the seed is in the name."""
    rng = np.random.default_rng(seed)
    return np.column_stack([rng.uniform(-np.pi, np.pi, (n, 2)), rng.uniform(-2, 2, (n, 2))])


def _generators(Q):
    """Generator rows (C_x, S_x, C_y, S_y, t, a) of configuration rows (x, y, t, a)."""
    return np.column_stack([np.cos(Q[:, 0] / 2), np.sin(Q[:, 0] / 2),
                            np.cos(Q[:, 1] / 2), np.sin(Q[:, 1] / 2), Q[:, 2], Q[:, 3]])


def _values(expr, Q):
    f = sp.lambdify(SYMBOLS, expr, "numpy")
    return np.broadcast_to(np.asarray(f(*Q.T), dtype=float), (len(Q),))


def _assert_proportional(got, want, what):
    """got = k * want for one nonzero constant k (or both zero)."""
    scale = max(np.max(np.abs(want)), 1.0)
    if np.max(np.abs(want)) < 1e-12:
        np.testing.assert_allclose(got, 0, atol=1e-12, err_msg=what)
        return
    k = got @ want / (want @ want)
    assert abs(k) > 1e-9, what
    np.testing.assert_allclose(got, k * want, atol=1e-9 * scale * max(abs(k), 1), err_msg=what)


@SMALL
@given(trig_polys)
def test_readable_form_has_the_values_of_the_expression(e):
    """to_sympy(from_sympy(e)) is e up to the cleared constant, at seed SEED's configurations,
    in the full-angle form and in the half-angle form."""
    Q = _configurations()
    want = _values(e, Q)
    p = RING.from_sympy(e)
    for full in (True, False):
        back = RING.to_sympy(p, full_angles=full)
        assert back.free_symbols <= set(SYMBOLS)
        _assert_proportional(_values(back, Q), want, f"{e} -> {back} (seed {SEED})")


@SMALL
@given(trig_polys, st.sampled_from([(0, 0), (1, 0), (0, 1), (1, 1), (3, 0)]))
def test_readable_form_of_odd_degree_keeps_half_angles(e, odd):
    """A pair of odd degree (a factor S or C) is written in q/2; the values still agree with
    the polynomial evaluated at the generator point."""
    p = RING.from_sympy(e) * RING.C(0) ** odd[0] * RING.S(1) ** odd[1]
    Q = _configurations()
    want = RING.compile([p])(_generators(Q))[:, 0]
    _assert_proportional(_values(RING.to_sympy(p), Q), want, f"{p} (seed {SEED})")


@SMALL
@given(trig_polys)
def test_compiled_polynomial_equals_the_expression_on_the_circles(e):
    Q = _configurations()
    got = RING.compile([RING.from_sympy(e)])(_generators(Q))[:, 0]
    np.testing.assert_allclose(got, _values(e, Q), rtol=1e-10, atol=1e-10, err_msg=f"seed {SEED}")


@SMALL
@given(st.lists(st.lists(trig_polys, min_size=2, max_size=2), min_size=1, max_size=3),
       st.floats(0.25, 4), st.floats(0.25, 4))
def test_padded_rows_keep_their_values_and_scale_by_their_degree(entries, lx, ly):
    """Padding a row with powers of C**2 + S**2 changes no value on the circles; off them,
    scaling pair k by lambda scales every entry of a row by lambda**(the row's degree in k)."""
    rows = RING.from_sympy_rows(sp.Matrix(entries))
    Q = _configurations(4)
    G = _generators(Q)
    scaled = G.copy()
    scaled[:, :2] *= lx
    scaled[:, 2:4] *= ly
    for row, exprs in zip(rows, entries):
        f = RING.compile(row)
        got = f(G)
        want = np.column_stack([_values(e, Q) for e in exprs])
        np.testing.assert_allclose(got, want, rtol=1e-10, atol=1e-10, err_msg=f"seed {SEED}")
        dx, dy = (int(max(RING.pair_degrees(p)[k] for p in row)) for k in range(2))
        np.testing.assert_allclose(f(scaled), got * lx ** dx * ly ** dy, rtol=1e-9, atol=1e-9 * 4 ** (dx + dy))


angles = st.floats(-math.pi, math.pi)
reals = st.floats(-1e3, 1e3)
pair_scales = st.floats(1e-3, 1e3).flatmap(lambda s: st.sampled_from([s, -s]))


@settings(SMALL, max_examples=200)
@given(angles, angles, reals, reals, pair_scales, pair_scales)
def test_joint_values_invert_the_generator_map(qx, qy, tv, av, lx, ly):
    """Any nonzero multiple of (cos(q/2), sin(q/2)) names the angle q (mod 2 pi: a negative
    multiple is q/2 + pi); the other variables and parameters are read off as they are."""
    g = [lx * math.cos(qx / 2), lx * math.sin(qx / 2), ly * math.cos(qy / 2), ly * math.sin(qy / 2), tv, av]
    joints = RING.joint_values(g)
    assert set(joints) == {x, y, t}
    for q, want in ((x, qx), (y, qy)):
        assert -math.pi <= joints[q] <= math.pi
        assert abs(math.remainder(joints[q] - want, 2 * math.pi)) < 1e-12
    assert joints[t] == tv
    assert RING.parameter_values(g) == {a: av}


@pytest.mark.parametrize("expr", [sp.tan(x), x, sp.sqrt(a), sp.cos(x / 2), sp.sin(x) / a, sp.Symbol("z")])
def test_non_polynomial_entries_are_refused_with_a_locus_error(expr):
    with pytest.raises(LocusError, match="polynomial"):
        RING.from_sympy(expr)
