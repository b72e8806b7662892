"""Left null vectors of a square polynomial matrix on a branch, fraction free.

On a branch where the n x n block J_sq has rank r, its n - r left null
vectors are built from the cofactors of an r x r block that is regular on
the branch: exact polynomials, no division.  They are independent wherever
that block's determinant d is nonzero; the caller analyses the points where
d = 0 on their own sub-branch.  Each vector is divided by the common factor
of its entries, which divides its entry +-d: that scales the vector by a
polynomial that is nonzero wherever d is, and keeps the matrices of the
levels below small.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..algebra import primitive_vector
from .blocks import choose_block

if TYPE_CHECKING:
    from ..tree.context import Context

__all__ = ["left_null_vectors"]


def left_null_vectors(ctx: "Context", A, rank, points, *, branch=None, max_terms=None,
                      candidates: int = 24):
    """Left null vectors of ``A`` (n x n, rank ``rank`` on the branch), fraction free.

    Returns the vectors and the polynomial ``d`` (the determinant of the
    regular block used): the vectors are independent wherever d != 0.  With
    ``max_terms``, no vectors are returned (and the remaining cofactors are
    not formed) once the cofactors formed hold more terms than that.  ``candidates`` is
    passed to :func:`~.blocks.choose_block`: 0 takes the block pivoting proposes, where the
    factors of d do not matter.
    """
    n = len(A)
    rows, cols = choose_block(ctx, A, rank, points, candidates, branch=branch)
    block = [[A[i][j] for j in cols] for i in rows]
    d = ctx.det(block) if rank else ctx.ring.ctx.constant(1)
    vectors = []
    zero = ctx.ring.ctx.constant(0)
    terms = 0
    for i in range(n):
        if i in rows:
            continue
        order = rows + [i]
        u = [zero] * n
        for t, r in enumerate(order):
            rest = [order[s] for s in range(len(order)) if s != t]
            if rest:
                minor = ctx.det([[A[x][j] for j in cols] for x in rest])
            else:
                minor = ctx.ring.ctx.constant(1)
            u[r] = minor if t % 2 == 0 else -minor
            terms += len(minor)
            if max_terms is not None and terms > max_terms:
                return [], d
        vectors.append(primitive_vector(u))
    return vectors, d
