"""Twists that are not multiples of pi/2: square roots in J, handled exactly.

The Kinova Jaco2 6-DOF curved-wrist arm has twists of pi/3 between joints 3-4 and 4-5, so
sqrt(3)/2 enters its Jacobian.  DH table from Kinova's published parameters (Kinova, "Jaco2
6DOF curved wrist: DH parameters", KINOVA JACO Robotic Arm User Guide, and the kinova-ros
documentation), in kinematics_models/extra/jaco2.toml with its source.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from rankloci.algebra import PolyRing, irreducible_factors, laplace_det
from rankloci.algebra.ring import square_root_primes
from rankloci.io.toml_model import parse_model
from rankloci.jacobians import task_matrix
from rankloci.methods import compute_locus, method_for
from rankloci.numeric.crosscheck import cross_check

EXTRA = Path(__file__).resolve().parents[2] / "kinematics_models" / "extra"
JACO2 = (EXTRA / "jaco2.toml").read_text()

SEED = 3


@pytest.mark.parametrize("numeric", [False, True])
def test_jaco2_locus_passes_the_numeric_check(numeric):
    """Every component is singular at its points, random configurations away from it are
    regular, and every singular minimum of sigma_min/sigma_max found from random starts lies on
    a component."""
    model = parse_model(JACO2, name="jaco2")
    tm = task_matrix(model, frame="auto", numeric=numeric)
    assert square_root_primes(tm.matrix) == (3,)
    locus = compute_locus(tm, method_for(tm.shape), rng=np.random.default_rng(SEED))
    assert [c for c in locus.components if c.for_model], locus.components
    J = task_matrix(model)
    report = cross_check(locus, J.matrix, J.variables, angles=J.angles, parameters=J.parameters,
                         samples=8, rng=np.random.default_rng(SEED), seed=SEED)
    assert report.ok, report.to_dict()


def test_surd_products_reduce_to_a_canonical_form():
    """sqrt(6) is sqrt(2)*sqrt(3); (sqrt(2) x - sqrt(3))(sqrt(2) x + sqrt(3)) = 2 x**2 - 3 once
    reduced, a polynomial over Q with no surd left; a factor in the surds alone is a nonzero
    number and is not a factor of the locus."""
    x = sp.Symbol("x")
    ring = PolyRing((), (x,), (), surds=square_root_primes([sp.sqrt(6)]))
    assert ring.surds == (2, 3)
    a = ring.from_sympy(sp.sqrt(2) * x - sp.sqrt(3))
    b = ring.from_sympy(sp.sqrt(2) * x + sp.sqrt(3))
    det = laplace_det([[a, ring.ctx.constant(0)], [ring.ctx.constant(0), b]], ring)
    assert det == ring.from_sympy(2 * x ** 2 - 3)
    assert ring.from_sympy(sp.sqrt(6) * x) == ring.from_sympy(sp.sqrt(2) * sp.sqrt(3) * x)
    (f,) = irreducible_factors(ring.from_sympy((sp.sqrt(3) + 1) * x), ring)
    assert f == ring.from_sympy(x)


def test_surd_values_are_exact_at_sample_points():
    """An identity that holds only at r = sqrt(3), such as (sqrt(3)/2)**2 + (1/2)**2 = 1, is
    zero in the ring: the matrix [[cos(pi/6), sin(pi/6)], [-sin(pi/6), cos(pi/6)]] times a
    rotation in q is regular everywhere, so the locus is empty."""
    q = sp.Symbol("q")
    c, s = sp.cos(sp.pi / 6), sp.sin(sp.pi / 6)
    text = ('name = "rot"\nvariables = ["q"]\nmatrix = [["' + sp.sstr(c * sp.cos(q) - s * sp.sin(q))
            + '", "' + sp.sstr(-c * sp.sin(q) - s * sp.cos(q)) + '"], ["'
            + sp.sstr(s * sp.cos(q) + c * sp.sin(q)) + '", "' + sp.sstr(c * sp.cos(q) - s * sp.sin(q))
            + '"]]\n')
    tm = task_matrix(parse_model(text, name="rot"), frame="auto")
    locus = compute_locus(tm, "determinant")
    assert locus.components == () and not locus.degenerate
