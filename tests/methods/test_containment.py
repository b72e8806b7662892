"""No component of a locus lies inside another one (decided at the model's values).

UR5 (Universal Robots' DH parameters) with the position task, 3x6: the set where the wrist
centre cannot move in some direction.  Its equations have coefficients up to 7e7 once the
parameters are numbers, so "lies on" must be decided relative to the size of the coefficients:
with an absolute threshold one component, inside another, was reported on its own.
"""

from __future__ import annotations

import numpy as np
import pytest

import locus_helpers as H

#: Scaled residual at which a point counts as on a component (as in tests/locus_helpers.py).
ON_RTOL = 1e-9


@pytest.mark.parametrize("task", ["position"])
def test_ur5_position_components_are_not_inside_each_other(task):
    from rankloci.io import load_model
    from rankloci.jacobians import task_matrix
    from rankloci.methods import compute_locus, method_for

    tm = task_matrix(load_model("ur5"), task=task, frame="auto", numeric=True)
    locus = compute_locus(tm, method_for(tm.shape), rng=np.random.default_rng(0))
    comps = list(locus.components)
    assert len(comps) >= 2, [H.describe(c) for c in comps]
    rng = np.random.default_rng(5)
    for i, inner in enumerate(comps):
        eqs = H.ComponentEquations(inner, tm, {})
        pts = [H.sample_point(inner, tm)] + H.points_on(eqs, tm, rng, 4)
        for j, outer in enumerate(comps):
            if i == j:
                continue
            on = H.ComponentEquations(outer, tm, {})
            inside = all(on.residual(q) <= ON_RTOL for q in pts)
            assert not inside, f"component {H.describe(inner)} lies inside {H.describe(outer)}"


def test_equations_with_coefficients_beyond_a_float():
    """det = 1 - (1e156 cos x + sin y)(1e156 sin x + cos y) has coefficients of 1e312, past the
    largest float: the component is formed (its dimension, its containment) all the same."""
    from rankloci.methods import compute_locus

    big = "*".join(["1" + "0" * 39] * 4)          # 1e156, from literals of 40 digits
    tm = H.raw_tm(f'name = "raw"\nvariables = ["x", "y"]\n'
                  f'matrix = [["1", "{big}*cos(x) + sin(y)"], ["{big}*sin(x) + cos(y)", "1"]]\n')
    locus = compute_locus(tm, "determinant", rng=np.random.default_rng(0))
    assert locus.components, "the locus of det = 0 is a curve"
    for comp in locus.components:
        assert comp.dimension == 1
        q = H.sample_point(comp, tm)
        assert H.sigma_ratio(H.numeric_j(tm)(q)) <= 1e-8
