"""Newton descent on sigma_min/sigma_max: a singular point is reached, a near-singular one is not.

The completeness probe of ``rankloci check`` counts a minimum of the ratio as a singular
configuration only when the descent drives the ratio below PROBE_DESCENT_RTOL.
"""

from __future__ import annotations

import numpy as np
import sympy as sp

from rankloci.numeric.equations import NumericMatrix, descend_to_singular, minimise_ratio
from rankloci.numeric.svd import sigma_ratio
from rankloci.tolerances import PROBE_DESCENT_RTOL, PROBE_SINGULAR_RTOL

x, y = sp.symbols("x y")


def test_descent_reaches_a_singular_configuration():
    nm = NumericMatrix(sp.Matrix([[1, x], [x * y, 1]]), (x, y))      # singular where x**2 y = 1
    q, r = descend_to_singular(nm, np.array([1.3, 0.55]))
    assert r <= PROBE_DESCENT_RTOL
    assert abs(q[0] ** 2 * q[1] - 1) < 1e-12


def test_descent_stalls_at_a_positive_minimum():
    # sigma_min/sigma_max has its minimum 1e-10 at x = y = 0: nearly, but not exactly, singular
    nm = NumericMatrix(sp.Matrix([[1, 0], [0, sp.Rational(1, 10 ** 10) + x ** 2 + y ** 2]]), (x, y))
    q = minimise_ratio(nm, np.array([0.3, -0.2]))
    assert sigma_ratio(nm(q)) <= PROBE_SINGULAR_RTOL       # the old test would call it singular
    _, r = descend_to_singular(nm, q)
    assert r > PROBE_DESCENT_RTOL
    assert abs(r - 1e-10) < 1e-12
