"""The determinant method for a square matrix: the factors of det J."""

from __future__ import annotations

from ..algebra import laplace_det
from ..errors import LocusError
from ._common import Context

__all__ = ["determinant_tree"]


def determinant_tree(ctx: Context) -> bool:
    from ..branch import Branch

    n, m = len(ctx.M), len(ctx.M[0])
    if n != m:
        raise LocusError(f"the determinant method needs a square matrix, this one is {n}x{m}; "
                         "use --method svm or subdeterminant")
    root = Branch()
    D = laplace_det(ctx.M)
    if D.is_zero():
        node = ctx.add_node(None, root, outcome="degenerate")
        ctx.leaf(root, node, "degenerate")
        return True
    node = ctx.add_node(None, root, outcome="refined", columns=list(range(1, m + 1)))
    for f in ctx.factors(D):
        for child in ctx.children(root, f):
            cnode = ctx.add_node(node, child, k=1)
            if ctx.sampler.points(child):
                ctx.leaf(child, cnode, "no redundant column")
            else:
                ctx.tree.nodes[cnode]["outcome"] = "empty"
    return False
