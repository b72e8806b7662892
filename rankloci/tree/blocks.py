"""Block choice: which square block of a matrix to take the determinant of.

The singular vector method splits a branch on the factors of the
determinant of an n x n block (:func:`choose_columns`), and builds null
vectors from the cofactors of an r x r block (:func:`choose_block`).  Any
block regular on the branch is correct; these choose one whose determinant
is small and has few factors, so that the branches below stay simple.
"""

from __future__ import annotations

import itertools
import math
from typing import TYPE_CHECKING

import numpy as np

from ..errors import LocusError
from .modular import block_rank
from .probe import numeric_rank
from ..tolerances import MAX_COLUMN_SETS, CANDIDATE_MAX_TERMS, MAX_BLOCKS

if TYPE_CHECKING:
    from .context import Context

__all__ = ["choose_columns", "choose_block"]


def _regular(ctx: "Context", M, points, size: int, branch):
    """A test ``(rows, cols) -> bool``: is that block of ``M`` regular on the branch?

    Regular at a point where ``M`` itself has rank ``size`` (a sample point
    may lie on a smaller subset where more is singular): exactly at the
    branch's points modulo a prime, where it has them, or numerically at its
    real points (which can lie on pieces the former miss, see Context.rank).
    """
    exact = ctx.modular.values(M, branch) if branch is not None else None
    exact = [E for E in exact if E.rank() == size] if exact is not None else []
    evaluated = [ctx.probe.evaluated(M, g) for g in points]
    evaluated = [(A, S) for A, S in evaluated if numeric_rank(A, S) == size]

    def regular(rl, cl):
        if any(block_rank(E, rl, cl) == size for E in exact):
            return True
        return any(numeric_rank(A[np.ix_(rl, cl)], S[np.ix_(rl, cl)]) == size
                   for A, S in evaluated)
    return regular


def choose_columns(ctx: "Context", M, points, candidates: int = 12, *, branch=None,
                   skip=()):
    """n columns whose square block is regular at the points, and its determinant.

    Among up to ``candidates`` regular blocks (smallest entries first) the
    one with the fewest determinant terms wins: its factors, and so the
    branches below it, are the simplest.  Column sets in ``skip`` are not
    taken.
    """
    n, m = len(M), len(M[0])
    size = [sum(len(M[i][j]) for i in range(n)) for j in range(m)]
    combos = itertools.combinations(range(m), n)
    if math.comb(m, n) > MAX_COLUMN_SETS:
        combos = itertools.islice(combos, MAX_COLUMN_SETS)
    ranked = sorted(combos, key=lambda cs: sum(size[c] for c in cs))
    best = None
    tried = 0
    regular = _regular(ctx, M, points, n, branch)
    rows = list(range(n))
    for cols in ranked:
        if list(cols) in skip or not regular(rows, list(cols)):
            continue
        sub = [[row[c] for c in cols] for row in M]
        ctx.tick()
        D = ctx.det(sub)
        if best is None or len(D) < len(best[1]):
            best = (list(cols), D)
        tried += 1
        if tried >= candidates or len(D) > CANDIDATE_MAX_TERMS:
            break
    if best is None:
        raise LocusError("no regular square block found although the matrix has full rank")
    return best

def choose_block(ctx: "Context", A, r, points, candidates: int = 24, *, branch=None):
    """Rows and columns of an r x r block of ``A`` regular at the points.

    The null vectors built from the block's cofactors are independent
    wherever its determinant d is nonzero, and the points where d
    vanishes need sub-branches of their own, one per factor of d.
    Pivoted QR at the first point proposes a block; a regular block
    (among up to ``candidates``, smallest entries first) whose d has
    fewer factors in the joint variables, and no more terms, replaces it.
    """
    n, m = len(A), len(A[0])
    N = ctx.probe.values(A, points[0])
    big = np.max(np.abs(N), axis=1, keepdims=True)      # first: huge rows would overflow norms
    N = N / np.where(big > 0, big, 1.0)
    norms = np.linalg.norm(N, axis=1)
    N = N / np.where(norms > 0, norms, 1.0)[:, None]
    cols = sorted(_pivots(N, r))
    rows = sorted(_pivots(N[:, cols].T, r))
    if r == 0:
        return rows, cols
    regular = _regular(ctx, A, points, r, branch)
    if not regular(rows, cols):
        # the numeric proposal is singular on the branch: the first regular block instead
        rows, cols = next(((list(rs), list(cs)) for rs in itertools.combinations(range(n), r)
                           for cs in itertools.combinations(range(m), r)
                           if regular(list(rs), list(cs))), (rows, cols))
    if candidates == 0 or math.comb(n, r) * math.comb(m, r) > MAX_BLOCKS:
        return rows, cols

    sizes: list[int] = []           # terms of every determinant scored

    def score(rl, cl, most=None):
        """(factors in the joint variables, terms) of the block's determinant; None when it
        has more than ``most`` terms."""
        d = ctx.det([[A[i][j] for j in cl] for i in rl])
        sizes.append(len(d))
        if most is not None and len(d) > most:
            return None
        if d.is_constant() or ctx.parameter_only(d):
            return 0, len(d)
        return len([f for f in ctx.factors(d) if not ctx.parameter_only(f)]), len(d)

    best = (score(rows, cols), rows, cols)
    if best[0][0] == 0 or best[0][1] > CANDIDATE_MAX_TERMS:
        # no search past a determinant that large: on talos' 9-joint arm the null-vector
        # level's 3 x 3 blocks (entries of 3000 to 6500 terms) have 0.9 to 1 million terms
        # and take 50 to 66 s each
        return rows, cols
    size = [[len(p) for p in row] for row in A]
    blocks = sorted(((rs, cs) for rs in itertools.combinations(range(n), r)
                     for cs in itertools.combinations(range(m), r)),
                    key=lambda rc: sum(size[i][j] for i in rc[0] for j in rc[1]))
    tried = 0
    for rs, cs in blocks:
        if tried >= candidates:
            break
        rl, cl = list(rs), list(cs)
        if (rl, cl) == (rows, cols) or not regular(rl, cl):
            continue
        tried += 1
        ctx.tick()
        sc = score(rl, cl, most=best[0][1])
        if sc is not None and sc[0] < best[0][0]:
            best = (sc, rl, cl)
            if sc[0] == 0:
                break
        if sizes[-1] > CANDIDATE_MAX_TERMS:
            break
    return best[1], best[2]


def _pivots(N, r):
    """Indices of r columns of N chosen greedily by largest remaining norm (pivoted QR)."""
    R = N.astype(float).copy()
    chosen = []
    for _ in range(r):
        norms = np.linalg.norm(R, axis=0)
        norms[chosen] = -1.0
        j = int(np.argmax(norms))
        chosen.append(j)
        v = R[:, j] / max(np.linalg.norm(R[:, j]), 1e-300)
        R = R - np.outer(v, v @ R)
    return chosen
