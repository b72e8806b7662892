"""A chain of nine joints outside the built-in models: a spatial 9R snake.

Equal links, no offsets and twists alternating between +pi/2 and -pi/2 make a locus of many
components (96 with numeric parameters).  Its lost directions once asked FLINT for 6.4 GB
(a cofactor product of 25258 by 174532 terms) and ended the process; the locus now finishes in
about 50 s here.  Each component's sample point is checked to be singular, and singular points
found by minimising sigma_min/sigma_max from random starts to lie on a component.  Not every
component is sound yet: at 6 points solved onto the equations of each, 9 of the 96 components
have regular ones (13 before factors excluded by their branch were divided out of their
equations, see ``finalize._without_excluded_factors``), and the self-check of ``rankloci
locus`` reports the locus incomplete.  A minimum
counts as singular as in ``rankloci check``, where Newton steps on the ratio bring it to
PROBE_DESCENT_RTOL.  (One start here ends at 9.4e-11, a minimum that neither those steps nor
bounded searches within 0.01 rad bring lower, 1.7e-3 (scaled) off the component {q4 = pi,
q6 = 0, q8 = pi, ...}: nearly, not exactly, singular by that rule.)
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import least_squares

import locus_helpers as H
from rankloci.io.toml_model import parse_model
from rankloci.jacobian import task_matrix
from rankloci.methods import compute_locus
from rankloci.numeric.equations import NumericMatrix, descend_to_singular
from rankloci.tolerances import COVER_DISTANCE, COVER_RESIDUAL, PROBE_DESCENT_RTOL, RANK_RTOL


def _snake_text(n: int = 9) -> str:
    head = ('name = "snake9"\nconvention = "dh"\ntask = "full"\nframe = "base"\n'
            '[parameters]\nl = 0.1\n')
    twists = ["pi/2" if i % 2 == 0 else "-pi/2" for i in range(n)]
    joints = "".join(f'[[joint]]\nkind = "revolute"\na = "l"\nalpha = "{t}"\nd = 0\ntheta = "0"\n'
                     for t in twists)
    return head + joints


def _covers(eqs, q, nj) -> bool:
    """Is the singular point ``q`` on ``eqs``, or next to it (COVER_DISTANCE)?"""
    if eqs.residual(q) <= COVER_RESIDUAL:
        return True
    p = least_squares(eqs, q, method="trf", xtol=1e-15, ftol=1e-15, gtol=1e-15).x
    return (eqs.residual(p) <= COVER_RESIDUAL and np.linalg.norm(p - q) <= COVER_DISTANCE
            and H.sigma_ratio(nj(p)) <= RANK_RTOL)


@pytest.fixture(scope="module")
def snake():
    tm = task_matrix(parse_model(_snake_text(), name="snake9"), frame="auto", numeric=True)
    return tm, compute_locus(tm, "svm", rng=np.random.default_rng(0))


@pytest.mark.slow
def test_nine_joint_snake_sample_points_are_singular(snake):
    tm, locus = snake
    comps = H.model_components(locus)
    assert len(comps) >= 9
    nj = H.numeric_j(tm)
    for comp in comps:
        q = H.sample_point(comp, tm)
        assert H.sigma_ratio(nj(q)) <= RANK_RTOL, H.describe(comp)


@pytest.mark.slow
def test_nine_joint_snake_singular_points_lie_on_components(snake):
    tm, locus = snake
    nj = H.numeric_j(tm)
    nm = NumericMatrix(tm.matrix, tm.variables, tm.angles)
    eqs = [H.ComponentEquations(c, tm, None) for c in H.model_components(locus)]
    rng = np.random.default_rng(7)
    singular = 0
    for _ in range(12):
        q, ratio = H.minimise_sigma_ratio(nj, H.random_q(tm, rng))
        if ratio > RANK_RTOL:
            continue
        q, ratio = descend_to_singular(nm, q)
        if ratio > PROBE_DESCENT_RTOL:
            continue
        singular += 1
        assert any(_covers(e, q, nj) for e in sorted(eqs, key=lambda e: e.residual(q))), \
            f"singular point {H.fmt(q, tm.variables)} on no component"
    assert singular >= 3
