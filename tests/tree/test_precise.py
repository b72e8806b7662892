"""Rank decisions at real points of a branch in extended precision (rankloci.tree.precise).

Generators of the ring below: C_q, S_q (half angle of q), u, v (polynomial variables), and
the surd generator sqrt(3).
"""

from __future__ import annotations

import flint
import mpmath
import numpy as np
import sympy as sp

from rankloci.algebra import PolyRing
from rankloci.tree.branch import Branch
from rankloci.tree.precise import PreciseProbe, _det, _dyadic

q, u, v = sp.symbols("q u v")
RING = PolyRing((q,), (u, v), (), surds=(3,))
Cq, Sq, U, V, R3 = RING.gens
ONE = RING.ctx.constant(1)


def test_values_are_exact_whatever_the_cancellation():
    # (u - 1/3)**10 expanded: terms of size ~1 that cancel to 1e-48 at u = 1/3 + 1e-5
    p = (U - flint.fmpq(1, 3)) ** 10
    probe = PreciseProbe(RING, [[ONE]])
    with mpmath.workdps(60):
        x = [mpmath.mpf(0), mpmath.mpf(1), mpmath.mpf(1) / 3 + mpmath.mpf("1e-5"),
             mpmath.mpf(0), mpmath.sqrt(3)]
        value, size = probe._value(p, x), probe._size(p, x)
        exact = (_dyadic(x[2]) - flint.fmpq(1, 3)) ** 10
        assert abs(value - mpmath.mpf(int(exact.p)) / int(exact.q)) <= abs(value) * 1e-50
        assert abs(value / mpmath.mpf("1e-50") - 1) < 1e-4
        assert size > 1e-3          # the terms' sizes: nothing like the value


def test_singular_and_nearly_singular_points_are_told_apart():
    # det = sqrt(3) u**2 - 1, zero on the branch 3 u**2 = sqrt(3); the second matrix has
    # det = 1e-12 u there: regular, with sigma_min/sigma_max ~1e-12.  With sqrt(3) taken from
    # double precision the first would show ~1e-16 and be called regular too.
    singular = [[U, ONE], [ONE, R3 * U]]
    nearly = [[U, ONE], [ONE, R3 * U + flint.fmpq(1, 10 ** 12) * ONE]]
    b, _ = Branch().with_condition(3 * U * U - R3, RING)  # u^2 = 1/sqrt(3)
    g = np.zeros(len(RING.names))
    g[0], g[1] = 1.0, 0.0                                 # q = 0
    g[2] = 1 / 3 ** 0.25 + 1e-9                          # near the root, in double precision
    g[4] = 3 ** 0.5
    assert PreciseProbe(RING, singular).singular(b, g) is True
    assert PreciseProbe(RING, nearly).singular(b, g) is False


def test_determinant_of_singular_blocks_with_a_zero_column_below_the_diagonal():
    # mpmath.det fails with a TypeError on the first two (its pivot search finds no row);
    # regular_columns needs 0 for them
    singular = [[[1, 2, 3], [0, 0, 5], [0, 0, 7]],
                [[0, 1], [0, 1]],
                [[1, 2], [2, 4]]]
    for rows in singular:
        assert _det(mpmath.matrix(rows)) == 0
    rng = np.random.default_rng(0)
    for n in (1, 2, 3, 5):
        A = rng.standard_normal((n, n))
        with mpmath.workdps(30):
            got = _det(mpmath.matrix(A.tolist()))
        assert abs(float(got) - np.linalg.det(A)) <= 1e-12 * max(1.0, abs(np.linalg.det(A)))
