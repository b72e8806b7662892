"""Pruning tests: is a point, or a branch, on a component already found?"""

from __future__ import annotations

import numpy as np
import pytest

import locus_helpers as H
from rankloci.jacobians import task_matrix
from rankloci.tree.branch import Branch
from rankloci.tree.cover import cover
from rankloci.tree.prune import below_bound, on_leaf

RAW = 'variables = ["x", "y"]\nmatrix = [["sin(x)*cos(y) + sin(y)", "cos(x)"]]\n'


def _context():
    return H.raw_context(RAW)[0]


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


# --- branches below the determinantal dimension bound -----------------------------------------

#: rank < 2 where sin(x) = sin(y) = 0 or cos(z) = sin(y) = 0: two components of dimension 1,
#: the bound for a 2x3 matrix in 3 variables (codimension at most 3 - 2 + 1).
BOUND_RAW = ('variables = ["x", "y", "z"]\n'
             'matrix = [["cos(z)", "sin(z)", "0"], ["0", "sin(x)", "sin(y)"]]\n')




def test_a_point_branch_with_a_regular_point_is_below_the_bound():
    """{x = pi/2, y = 0, z = 0} has dimension 0 < 1 and J is regular at its point."""
    ctx, ix = H.raw_context(BOUND_RAW)
    S, C = ctx.ring.S, ctx.ring.C
    (b,) = cover(ctx, Branch(), [S(ix["x"]) - C(ix["x"]), S(ix["y"]), S(ix["z"])])
    pts = ctx.sampler.points(b)
    assert pts and ctx.local_dimension(b, pts[0]) == 0
    assert below_bound(ctx, b, pts)


def test_a_singular_point_on_no_leaf_keeps_its_branch():
    """{x = y = z = 0} is below the bound too, but J is singular at its point: with no leaf
    found that holds the point, the branch may be a piece of smaller real dimension than any
    complex component, and it is analysed.  Once the leaf {x = y = 0} is found it is not."""
    ctx, ix = H.raw_context(BOUND_RAW)
    S = ctx.ring.S
    (b,) = cover(ctx, Branch(), [S(ix["x"]), S(ix["y"]), S(ix["z"])])
    pts = ctx.sampler.points(b)
    assert pts and ctx.probe.rank_at(ctx.M, pts[0]) < ctx.full_rank
    assert not below_bound(ctx, b, pts)
    (leaf,) = cover(ctx, Branch(), [S(ix["x"]), S(ix["y"])])
    ctx.leaves.append((leaf, 0))
    assert below_bound(ctx, b, pts)


def test_a_branch_of_the_bound_dimension_is_analysed():
    ctx, ix = H.raw_context(BOUND_RAW)
    (b,) = cover(ctx, Branch(), [ctx.ring.S(ix["y"])])
    pts = ctx.sampler.points(b)
    assert pts and ctx.local_dimension(b, pts[0]) == 2
    assert not below_bound(ctx, b, pts)


@pytest.mark.parametrize("name", ["pa10", "ssrms"])
def test_pruning_below_the_bound_keeps_the_locus(name, monkeypatch):
    """The same components with and without the pruning, on arms where it prunes branches."""
    from rankloci.io import load_model
    from rankloci.loci import Outcome
    from rankloci.methods import compute_locus
    from rankloci.tree import prune

    tm = task_matrix(load_model(name), frame="auto", numeric=True)
    loci = {}
    for flag in (True, False):
        monkeypatch.setattr(prune, "PRUNE_BELOW_BOUND", flag)
        loci[flag] = compute_locus(tm, "svm", rng=np.random.default_rng(0))
    pruned = [n for n, d in loci[True].tree.nodes(data=True)
              if d.get("outcome") == Outcome.BELOW_BOUND]
    assert pruned
    assert loci[True].tree.number_of_nodes() < loci[False].tree.number_of_nodes()

    def equations(locus):
        return sorted(tuple(map(str, c.equations)) for c in locus.components)

    assert equations(loci[True]) == equations(loci[False])
