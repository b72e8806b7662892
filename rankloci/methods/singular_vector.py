"""The singular vector method (Dupuis) as a recursive branch tree.

For an n x m matrix with n < m (more columns than rows):

1. choose n columns as J_sq, the others form J_r;
2. for every irreducible factor f of det J_sq, on the branch {f = 0}, find
   the k left null vectors U* of J_sq (fraction-free, from cofactors of a
   regular block);
3. form J-dagger = U*^T J_r and recurse on it;
4. stop when J-dagger has no rank-deficiency locus on the branch (the
   branch is empty), when k exceeds the number of redundant columns (the
   whole branch is in the locus), or when no redundant column is left (the
   square case: the factors of the determinant are the locus).

The chosen null vectors are independent only where the determinant d of
the regular block is nonzero; the points of the branch where d = 0 are
analysed again, on their own sub-branch, with the matrix of that level.
A matrix with more rows than columns is handled through its transpose
(right null vectors).
"""

from __future__ import annotations

from ..algebra import transpose
from ..errors import LocusError
from ..loci import Outcome
from ..tree.branch import Branch
from ..tree.context import Context
from ..tree import prune
from ..tree.cover import children, distinct
from ..tree.blocks import choose_columns
from .null_vectors import left_null_vectors
from ..tolerances import MINOR_CANDIDATES

__all__ = ["singular_vector_tree"]


def singular_vector_tree(ctx: Context) -> bool:
    """Grow the branch tree in ``ctx``; return True if the matrix is degenerate."""
    root = Branch()
    pts = ctx.sampler.points(root)
    M = ctx.M if len(ctx.M) <= len(ctx.M[0]) else transpose(ctx.M)
    rank = ctx.rank(M, root, pts)
    if rank < len(M):
        node = ctx.add_node(None, root, shape=_shape(M), k=len(M) - rank)
        ctx.leaf(root, node, Outcome.DEGENERATE)
        return True
    _svm(ctx, M, root, None, level=0)
    return False


def _shape(M):
    return f"{len(M)}x{len(M[0])}"


def _svm(ctx: Context, M, branch, parent, level):
    """One level: split on the factors of a square block's determinant."""
    if len(M) > len(M[0]):
        M = transpose(M)
    n, m = len(M), len(M[0])
    node = ctx.add_node(parent, branch, shape=_shape(M))
    pts = ctx.open_branch(branch, node)
    if pts is None:
        return
    M = ctx.substitute(M, branch)
    rank = ctx.rank(M, branch, pts)
    if rank < n:
        ctx.annotate(node, k=n - rank)
        ctx.leaf(branch, node, Outcome.BEYOND_REDUNDANCY)
        return
    cols, D = choose_columns(ctx, M, pts, branch=branch)
    rest = [c for c in range(m) if c not in cols]
    ctx.annotate(node, columns=[c + 1 for c in cols], outcome=Outcome.REFINED, level=level)
    ctx.progress(f"branch {node}: {n}x{m} matrix, determinant of columns {[c + 1 for c in cols]}")
    branches = []
    seen: set = set()
    for f in ctx.factors(D):
        if rest and ctx.parameter_only(f):
            ctx.special_parameters(f, f"det of columns {[c + 1 for c in cols]} at branch {node}")
            continue
        branches.extend(distinct(children(ctx, branch, f), seen))
    if not rest:
        ctx.leaves_below(node, branches, Outcome.NO_REDUNDANT_COLUMN, shape=_shape(M), k=1)
        return
    # Branches on which the whole matrix is rank deficient first: they are the
    # largest components, and everything inside them is pruned afterwards.
    pending = []
    for child in branches:
        cpts = ctx.sampler.points(child)
        crank = ctx.rank(ctx.substitute(M, child), child, cpts) if cpts else n
        if crank < n:
            cnode = ctx.add_node(node, child, k=n - crank)
            ctx.leaf(child, cnode, Outcome.BEYOND_REDUNDANCY)
        else:
            pending.append(child)
    for child in pending:
        ctx.tick()
        _reduce(ctx, M, cols, rest, child, node, level)


def _reduce(ctx: Context, M, cols, rest, branch, parent, level):
    """On a branch of det J_sq = 0: null vectors, J-dagger, recursion."""
    n = len(M)
    node = ctx.add_node(parent, branch)
    pts = ctx.open_branch(branch, node)
    if pts is None:
        return
    Mb = ctx.substitute(M, branch)
    Jsq = [[row[c] for c in cols] for row in Mb]
    Jr = [[row[c] for c in rest] for row in Mb]
    r = ctx.rank(Jsq, branch, pts)
    k = n - r
    if k == 0:
        # the factor has real points but J_sq is regular there: not a branch
        ctx.annotate(node, outcome=Outcome.EMPTY, k=0)
        return
    if k > len(rest):
        ctx.annotate(node, k=k)
        ctx.leaf(branch, node, Outcome.BEYOND_REDUNDANCY)
        return
    U, d = left_null_vectors(ctx, Jsq, r, pts, branch=branch)
    zero = ctx.ring.ctx.constant(0)
    Jdag = [[ctx.ring.normal(sum((u[j] * Jr[j][c] for j in range(n)
                                  if not u[j].is_zero() and not Jr[j][c].is_zero()), zero))
             for c in range(len(rest))] for u in U]
    ctx.annotate(node, k=k, outcome=Outcome.REFINED, shape=f"{k}x{len(rest)}",
                 columns=[c + 1 for c in cols])
    # The null vectors U prove rank deficiency only where d != 0: the levels
    # below live on that open set.  Where d = 0 they prove nothing; there the
    # matrix of this level is rank deficient exactly where all its maximal
    # minors vanish, which is decided on its own sub-branch.
    degenerate = []
    if not d.is_constant():
        for g in ctx.factors(branch.reduce(d, ctx.ring)):
            if ctx.parameter_only(g):
                ctx.special_parameters(g, f"null vectors at branch {node}")
            else:
                degenerate.append(g)
    below = branch
    for g in degenerate:
        below = below.excluding(g)
    _svm(ctx, Jdag, below, node, level + 1)
    seen = set()
    for g in degenerate:
        for child in distinct(children(ctx, branch, g), seen):
            if prune.known(ctx, child):
                continue
            sub = ctx.add_node(node, child, outcome=Outcome.REFINED, note="null vectors degenerate")
            _minor_branch(ctx, M, child, sub)


def _minor_branch(ctx: Context, M, branch, parent):
    """Split ``branch`` on one non-vanishing maximal minor at a time.

    All maximal minors vanish on a branch exactly when the numeric rank of
    the matrix at its generic points is below full, so the minors need not
    all be formed: one minor that does not vanish on the branch (the
    determinant of a regular block) must vanish on every singular point,
    and its factors split the branch.
    """
    pts = ctx.open_branch(branch, parent)
    if pts is None:
        return
    Mb = ctx.substitute(M, branch)
    if len(Mb) > len(Mb[0]):
        Mb = transpose(Mb)
    if ctx.rank(Mb, branch, pts) < len(Mb):
        ctx.leaf(branch, parent, Outcome.ALL_MINORS_VANISH)
        return
    cols, D = _nonvanishing_minor(ctx, Mb, branch, pts)
    ctx.annotate(parent, columns=[c + 1 for c in cols])
    ctx.split(branch, parent, D, "a minor on a branch",
              lambda child, node: _minor_branch(ctx, M, child, node))


def _nonvanishing_minor(ctx: Context, Mb, branch, pts):
    """Columns of a maximal minor of ``Mb`` that does not vanish on ``branch``, and the minor.

    A block is taken as regular on the branch from its rank at the branch's
    points; on nearly degenerate geometry a sample point can be close
    enough to the branch's equations (1e-15 of their term size) and still
    far enough from their zeros for a block singular on the whole branch to
    look regular there (tiago's arm).  Such a minor has an equation of the
    branch among its factors: it splits nothing, and the next block is
    taken.  When every candidate does so the last one stands, and the
    branch is analysed again below it.
    """
    skip, vanishing = [], None
    while True:
        try:
            cols, D = choose_columns(ctx, Mb, pts, candidates=MINOR_CANDIDATES, branch=branch,
                                     skip=skip)
        except LocusError:
            if vanishing is None:
                raise
            return vanishing
        if not any(f == e or f == -e for f in ctx.factors(D) for e in branch.implicit):
            return cols, D
        skip.append(cols)
        vanishing = cols, D
