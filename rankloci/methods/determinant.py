"""The determinant method for a square matrix: the factors of det J."""

from __future__ import annotations

from ..algebra import laplace_det
from ..errors import LocusError
from ..loci import Outcome
from ..tree.branch import Branch
from ..tree.context import Context
from ..tree.cover import children

__all__ = ["determinant_tree"]


def determinant_tree(ctx: Context) -> bool:
    """Grow the branch tree in ``ctx``; return True if the matrix is degenerate."""
    n, m = len(ctx.M), len(ctx.M[0])
    if n != m:
        raise LocusError(f"the determinant method needs a square matrix, this one is {n}x{m}; "
                         "use the svm or subdeterminant method")
    root = Branch()
    D = laplace_det(ctx.M, ctx.ring, poll=ctx.tick)
    if D.is_zero():
        node = ctx.add_node(None, root, outcome=Outcome.DEGENERATE)
        ctx.leaf(root, node, Outcome.DEGENERATE)
        return True
    node = ctx.add_node(None, root, outcome=Outcome.REFINED, columns=list(range(1, m + 1)))
    for f in ctx.factors(D):
        ctx.leaves_below(node, children(ctx, root, f), Outcome.NO_REDUNDANT_COLUMN, k=1)
    return False
