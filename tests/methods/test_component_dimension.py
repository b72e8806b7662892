"""A component's dimension is that of the set its equations describe.

On tiago's arm (example-robot-data, ``base_footprint -> arm_7_link``, 8 joints, 6x8) the
branch tree gives a component at q7 = pi (arm_6_joint) by three equations whose gradients are
independent at its sample point: a manifold of dimension 8 - 3 = 5 there.  The count of the
branch's conditions modulo a prime said 4, one short, and the certificate then left the
component out as lying "below the dimension bound of its rank drop".  Singular
configurations such as q = (0.2298, 2.1742, 0.6892, 1.3047, 3.2698, -0.9622, -pi, 2.4697),
where Pinocchio's sigma_min/sigma_max is 2e-17, then lay on no component of the locus shown.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from scipy.optimize import least_squares

import rankloci
from rankloci.numeric.svd import sigma_ratio
from rankloci.tolerances import RANK_RTOL

#: The singular configuration above, to the four decimals it was written down with.
MISSED = (0.2298, 2.1742, 0.6892, 1.3047, 3.2698, -0.9622, -np.pi, 2.4697)


@pytest.mark.slow
def test_a_component_at_q7_pi_keeps_its_dimension_and_covers_its_points(robots):
    model = rankloci.load_model(robots / "tiago_description" / "robots" / "tiago.urdf",
                                base_link="base_footprint", tip="arm_7_link")
    locus = rankloci.locus(model, jobs=1)
    q7 = sp.Symbol("q7", real=True)
    at_pi = [c for c in locus.components
             if any(sp.simplify(e - sp.cos(q7 / 2)) == 0 for e in c.equations)]
    assert len(at_pi) == 1, [c.equations for c in locus.components]
    comp = at_pi[0]
    assert comp.dimension == 5
    assert not any("below the dimension bound" in n for n in locus.notes)

    # the configuration written down above, moved onto the component's equations (each
    # scaled by its value's size at the start), is on the locus and singular
    f = sp.lambdify(locus.variables, list(comp.equations), "numpy")
    x0 = np.array(MISSED)
    scale = np.maximum(np.abs(np.array(f(*x0), dtype=float)), 1.0)
    fit = least_squares(lambda x: np.array(f(*x), dtype=float) / scale, x0, xtol=1e-15,
                        ftol=1e-15, gtol=1e-15)
    assert np.max(np.abs(fit.x - x0)) < 1e-3           # it was within rounding of the set
    assert locus.contains(fit.x)
    tm = rankloci.jacobian(model, numeric=True)
    J = np.array(sp.lambdify(tm.variables, tm.matrix, "numpy")(*fit.x), dtype=float)
    assert float(sigma_ratio(J)) <= RANK_RTOL
