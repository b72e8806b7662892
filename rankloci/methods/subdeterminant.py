"""The subdeterminant method: the common zeros of all maximal minors.

The locus of an n x m matrix (n <= m) is the set where every n x n minor
vanishes.  Their greatest common divisor gives the components of
codimension one; the rest is found by branching on the factors of one minor
that does not vanish on the current branch, until every minor vanishes.
It is independent of the singular vector method (it uses no null vectors)
and serves as its symbolic cross-check; it grows as C(m, n).
"""

from __future__ import annotations

import itertools

from ..algebra import common_factor, laplace_det, transpose
from ..loci import Outcome
from ..tree.branch import Branch
from ..tree.context import Context
from ..tree.cover import children

__all__ = ["subdeterminant_tree", "maximal_minors"]


def subdeterminant_tree(ctx: Context) -> bool:
    """Grow the branch tree in ``ctx``; return True if the matrix is degenerate."""
    minors = maximal_minors(ctx, ctx.M)
    ctx.progress(f"{len(minors)} maximal minors computed")
    nonzero = [p for p in minors if not p.is_zero()]
    root = Branch()
    if not nonzero:
        node = ctx.add_node(None, root, outcome=Outcome.DEGENERATE, minors=len(minors))
        ctx.leaf(root, node, Outcome.DEGENERATE)
        return True
    g = common_factor(nonzero)
    node = ctx.add_node(None, root, outcome=Outcome.REFINED, minors=len(minors))
    if not g.is_constant():
        for f in ctx.factors(g):
            ctx.leaves_below(node, children(ctx, root, f), Outcome.ALL_MINORS_VANISH)
    _minors_branch(ctx, [p / g for p in nonzero], root, node)
    return False


def maximal_minors(ctx: Context, M) -> list:
    """All maximal minors of a matrix of polynomials."""
    if len(M) > len(M[0]):
        M = transpose(M)
    n, m = len(M), len(M[0])
    out = []
    for cols in itertools.combinations(range(m), n):
        ctx.tick()
        out.append(laplace_det([[row[c] for c in cols] for row in M], ctx.ring, poll=ctx.tick))
    return out


def _minors_branch(ctx: Context, minors, branch, parent):
    """Branch until every minor vanishes on the branch (a component) or the branch is empty."""
    pts = ctx.open_branch(branch, parent)
    if pts is None:
        return
    reduced = [branch.reduce(p, ctx.ring) for p in minors]
    alive = [p for p in reduced if not ctx.vanishes(p, branch, pts)]
    if not alive:
        ctx.leaf(branch, parent, Outcome.ALL_MINORS_VANISH)
        return
    ctx.split(branch, parent, min(alive, key=len), "a minor on a branch",
              lambda child, node: _minors_branch(ctx, alive, child, node),
              keep_parameter_only=not branch.conditions)
