"""The near-the-locus functions at the top level of the package."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

import rankloci


def test_top_level_functions():
    s = rankloci.min_inf_norm([[0.7, 0.1, -1.6], [2.0, -0.2, 0.6]], [-1.0, 0.2])
    np.testing.assert_allclose(s.x, [-0.1162, -0.5404, 0.5404], atol=0.5e-4)
    m = rankloci.manipulability("puma560", [np.pi / 4] * 6, position_only=True)
    assert m.rows == (0, 1, 2) and m.J.shape == (3, 6)
    assert m.polytope.volume / m.ellipsoid.volume == pytest.approx(6 / np.pi, rel=1e-10)
    near = rankloci.nearest_component("planar4r", [0.2, 0.6, 0.6, 0.6])
    assert near.component == 1 and near.distance == pytest.approx(np.sqrt(3 * 0.36), abs=1e-9)
    path = rankloci.joint_rates("planar4r", [0.62, 0.23, 1.0, 0.46],
                                [[0.524572, 3.032596], [0.0, 3.0]], norm="2", steps=5)
    assert path.norm == "2" and path.q.shape == (6, 4)
    assert rankloci.near.min_inf_norm.METHODS == ("ha_lee", "cadzow", "lp")


def test_bad_arguments_name_the_problem():
    with pytest.raises(ValueError, match="4 values"):
        rankloci.manipulability("planar4r", [0.1, 0.2])
    x = sp.Symbol("x")
    with pytest.raises(ValueError, match="robot model"):
        rankloci.manipulability(sp.Matrix([[sp.cos(x), 1]]), [0.0])
