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

from ..algebra import TermLimit, laplace_det, primitive_vector
from ..tree.blocks import choose_block

if TYPE_CHECKING:
    from ..tree.context import Context

__all__ = ["left_null_vectors"]


def left_null_vectors(ctx: "Context", A, rank, points, *, branch=None, max_terms=None,
                      candidates: int = 24):
    """Left null vectors of ``A`` (n x n, rank ``rank`` on the branch), fraction free.

    Returns the vectors and the polynomial ``d`` (the determinant of the
    regular block used): the vectors are independent wherever d != 0.  With
    ``max_terms``, no vectors are returned (and the remaining cofactors are
    not formed) once the cofactors formed hold more terms than that, nor d when d
    alone does.  ``candidates`` is
    passed to :func:`~.blocks.choose_block`: 0 takes the block pivoting proposes, where the
    factors of d do not matter.
    """
    n = len(A)
    rows, cols = choose_block(ctx, A, rank, points, candidates, branch=branch)
    block = [[A[i][j] for j in cols] for i in rows]
    try:
        d = ctx.det(block, max_terms=max_terms) if rank else ctx.ring.ctx.constant(1)
    except TermLimit:
        return [], None
    vectors = []
    terms = 0
    for i in range(n):
        if i in rows:
            continue
        order = rows + [i]
        budget = None if max_terms is None else max_terms - terms
        u = _cofactors(ctx.ring, A, order, cols, ctx.det, budget)
        if u is None:
            return [], d
        terms += sum(len(p) for p in u)
        scaled = _on_common_scale(ctx.ring, A, order, cols, u)
        if scaled is None:
            # A is homogeneous in neither way: the cofactors as they are
            scaled = _cofactors(ctx.ring, A, order, cols, lambda B: laplace_det(B, ctx.ring))
        vectors.append(primitive_vector(scaled))
    return vectors, d


def _cofactors(ring, A, order, cols, det, budget=None):
    """The signed minors of the rows ``order`` of ``A`` (columns ``cols``), by ``det``.

    Entry r of the result (length len(A)) is the determinant without row r, signed by
    its place in ``order``; rows outside ``order`` are zero.  None, with the remaining
    minors not formed, as soon as the minors formed hold more than ``budget`` terms (``det``
    then takes ``max_terms``, as :meth:`Context.det` does).
    """
    u = [ring.ctx.constant(0)] * len(A)
    terms = 0
    for t, r in enumerate(order):
        rest = [order[s] for s in range(len(order)) if s != t]
        block = [[A[x][j] for j in cols] for x in rest]
        try:
            # with a budget, a minor is stopped while it is formed: a single one can need
            # gigabytes (see rankloci.algebra.polys.PRODUCT_BUDGET_FACTOR)
            minor = (ring.ctx.constant(1) if not rest else
                     det(block) if budget is None else det(block, max_terms=budget - terms))
        except TermLimit:
            return None
        u[r] = minor if t % 2 == 0 else -minor
        terms += len(minor)
        if budget is not None and terms > budget:
            return None
    return u


def _on_common_scale(ring, A, order, cols, u):
    """The cofactors ``u``, each divided by the same power of C**2 + S**2; None if unknown.

    :meth:`Context.det` divides each minor by its own powers of C**2 + S**2, so that the
    entries of ``u`` are a null vector on the circles but not, as polynomials, one vector
    scaled by a common factor, which the branch substitutions (C, S) ~ (b, -a) need.  The
    true degree of the minor without row r is K - deg(row r) in each pair when ``A`` is
    homogeneous by rows (and K when by columns): each entry is brought to that degree less
    the largest common power (:meth:`PolyRing.homogenized`).  None when ``A`` is homogeneous
    in neither way.
    """
    live = [r for r in order if not u[r].is_zero()]
    if len(live) <= 1:
        return u
    na = ring.n_angles

    def shared(entries):
        degs = {ring.pair_degrees(p) for p in entries if not p.is_zero()}
        return degs.pop() if len(degs) == 1 else (None if degs else (0,) * na)

    offset = {x: shared(A[x][j] for j in cols) for x in order}
    if any(o is None for o in offset.values()):
        if any(shared(A[x][j] for x in order) is None for j in cols):
            return None
        offset = {x: (0,) * na for x in order}
    degs = {r: ring.pair_degrees(u[r]) for r in live}
    top = [max(degs[r][k] + offset[r][k] for r in live) for k in range(na)]
    out = list(u)
    try:
        for r in live:
            out[r] = ring.homogenized(u[r], tuple(top[k] - offset[r][k] for k in range(na)))
    except ValueError:
        return None
    return out
