"""Pruning tests: is a point, or a branch, on a component already found?"""

from __future__ import annotations

import numpy as np

from rankloci.io.toml_model import parse_model
from rankloci.jacobian import task_matrix
from rankloci.tree.branch import Branch
from rankloci.tree.context import Context
from rankloci.tree.cover import cover
from rankloci.tree.prune import on_leaf

RAW = 'variables = ["x", "y"]\nmatrix = [["sin(x)*cos(y) + sin(y)", "cos(x)"]]\n'


def _context():
    tm = task_matrix(parse_model(RAW, name="raw"), frame="auto")
    return Context(tm, method="svm", rng=np.random.default_rng(0))


def test_configuration_with_an_angle_at_pi_is_on_the_leaf_of_that_angle():
    """The leaf {cos(y/2) = 0} (y = pi) has one single-term condition.  At a configuration given
    by its joint values with y = float(pi), cos(y/2) is 6e-17, which is all of that term's size
    there: tested against its terms at the point it never vanishes.  Against its coefficient
    (the cosine at 1) it does, and the point is on the leaf; y = 3 is not."""
    ctx = _context()
    (leaf,) = cover(ctx, Branch(), [ctx.ring.C(1)])
    assert not leaf.implicit and not leaf.nonzero
    assert on_leaf(ctx, leaf, np.array([0.3, np.pi]))
    assert on_leaf(ctx, leaf, np.array([-2.0, -np.pi]))
    assert not on_leaf(ctx, leaf, np.array([0.3, 3.0]))
