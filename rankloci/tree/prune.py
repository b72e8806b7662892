"""Pruning: is a branch inside a component already found?

A branch all of whose points lie on a component found before needs no
analysis: whatever it holds is already in the locus.  The leaves of the
tree are tried newest condition sets first; the test is symbolic where the
conditions decide it, numeric (at the branch's sample points) otherwise; a
point where an exclusion of the component vanishes is in its closure when
exact points of the component next to it are proved to keep every exclusion
nonzero (:mod:`.certify`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .branch import Branch
from .certify import admitted_near

if TYPE_CHECKING:
    from .context import Context

__all__ = ["known", "known_symbolically", "below_bound", "dense", "in_closure", "on_leaf"]

#: Whether branches below the determinantal dimension bound are left unanalysed
#: (:func:`below_bound`); the tests compare the loci with and without.
PRUNE_BELOW_BOUND = True


def known_symbolically(ctx: "Context", branch: Branch) -> bool:
    """Does ``branch`` carry every condition of a component found (without exclusions)?

    Then the numeric test of :func:`known` would find all of its points on
    that component; this decides it without sampling the branch.
    """
    if not ctx.leaves or not branch.conditions:
        return False
    have = set(branch.key[0])
    for leaf, _ in ctx.leaves:
        if leaf is branch or not leaf.conditions or not dense(ctx, leaf):
            continue
        if len(leaf.conditions) <= len(branch.conditions) and \
                all(c in have for c in leaf.key[0]):
            return True
    return False


def known(ctx: "Context", branch: Branch) -> bool:
    """Is every sample point of ``branch`` on a component already found?"""
    if not ctx.leaves:
        return False
    if known_symbolically(ctx, branch):
        return True
    pts = ctx.sampler.points(branch)
    if not pts:
        return False
    vanishing = ctx.probe.vanishing
    # leaves with more conditions than the branch are tried only when they have no
    # exclusion: the test is then one evaluation, and a leaf found deep in the tree holds
    # whole branches opened later (on tiago's 9-joint thumb chain the locus took 57 s
    # against 77 s without them); one with exclusions would ask for closure proofs
    leaves = [leaf for leaf, _ in ctx.leaves
              if leaf is not branch and leaf.conditions
              and (len(leaf.conditions) <= len(branch.conditions) or not leaf.nonzero)]
    # per leaf: is every condition zero at each point; is some exclusion zero there
    on = _on_equations(ctx, leaves, pts)
    excluded = {}

    def in_excluded(j):
        if j not in excluded:
            excluded[j] = vanishing(leaves[j].nonzero, pts).any(axis=1)
        return excluded[j]

    for j, leaf in enumerate(leaves):
        if on[j].all() and (dense(ctx, leaf) or not in_excluded(j).any()):
            return True

    # a reducible branch: each point on a component, in its closure where an exclusion
    # of that component vanishes.  The proofs of the latter are costly (a failed one about
    # 2 s on panda's finger chain): they come last, once every point has a candidate and
    # none is on a component without one.
    proofs = []
    for k, g in enumerate(pts):
        cands = [j for j in range(len(leaves)) if on[j, k]]
        if not cands:
            return False
        if not any(dense(ctx, leaves[j]) or not in_excluded(j)[k] for j in cands):
            proofs.append((k, g, [leaves[j] for j in cands]))
    return all(any(in_closure(ctx, leaf, g, k) for leaf in cands) for k, g, cands in proofs)


def _on_equations(ctx: "Context", leaves, pts) -> np.ndarray:
    """Booleans, one row per leaf of ``leaves``: is every condition of it zero at each point.

    The smallest condition of each leaf is evaluated first, and the others only where it
    vanishes: most leaves fail on it (an angle at 0 or pi), and a tree opens a branch against
    every leaf found so far (on PR2's finger chain these evaluations took 12 of 66 s).  The
    smallest conditions of all leaves go in one call: that list changes only when a leaf is
    added, so its evaluator is compiled once per leaf, not per branch (one call per leaf took a
    third of human's 8-joint chain).
    """
    vanishing = ctx.probe.vanishing
    everyone = [leaf for leaf, _ in ctx.leaves if leaf.conditions]
    smallest = [min(leaf.conditions, key=len) for leaf in everyone]
    at = dict(zip(map(id, everyone), vanishing(smallest, pts).T))
    on = np.zeros((len(leaves), len(pts)), dtype=bool)
    for j, leaf in enumerate(leaves):
        first = at[id(leaf)].copy()
        if first.any() and len(leaf.conditions) > 1:
            conds = sorted(leaf.conditions, key=len)
            first &= vanishing(conds[1:], pts).all(axis=1)
        on[j] = first
    return on


def below_bound(ctx: "Context", branch: Branch, pts) -> bool:
    """Is ``branch`` smaller than any component, with no singular point of its own to find?

    Every irreducible component of the complex set where an n x m matrix (n <= m) loses
    rank has codimension at most m - n + 1 in the joint space (the Eagon-Northcott bound
    for maximal minors), whatever its rank drop: its dimension is at least
    :func:`rankloci.verify.dimension_bound` for rank drop 1.  So a component's generic
    points never lie in a branch of smaller dimension; they lie in larger branches, which
    the tree analyses, and the closures of the components found there hold every singular
    point of the small branch that is a limit of singular points of a larger piece.  Such a
    branch is not analysed when its dimension at each sample point is below the bound
    (the joint variables minus the rank of its conditions' gradient there; a singular point
    of the branch's equations can only raise this figure) and each sample point is either
    regular for the whole matrix or on the equations of a leaf already found.

    What the bound does not cover are real singular points where the locus has a smaller
    real than complex dimension (the real points of x**2 + y**2 = 0): a singular sample
    point on no leaf found may be one, and its branch is analysed.  On tiago's 9-joint
    thumb chain 835 of the 3088 branches were pruned here, most of which had been found
    inside a component by closure proofs before; the locus (13 components) is the same,
    in 24 s instead of 69 s.  Models with symbolic parameters are left out: at special
    parameter values a branch can be larger than at the generic values its points have.
    """
    if not PRUNE_BELOW_BOUND or not branch.conditions or not pts or ctx.ring.params:
        return False
    bound = ctx.dimension_bound
    if any(ctx.local_dimension(branch, g) >= bound for g in pts):
        return False
    singular = [g for g in pts if ctx.probe.rank_at(ctx.M, g) < ctx.full_rank]
    if not singular:
        return True
    leaves = [leaf for leaf, _ in ctx.leaves if leaf.conditions and leaf is not branch]
    return bool(leaves) and bool(_on_equations(ctx, leaves, singular).any(axis=0).all())


def in_closure(ctx: "Context", leaf: Branch, g, k: int = 0) -> bool:
    """Is the point ``g`` of ``leaf``'s equations in the closure of ``leaf``?

    Decided by proof where it can be (:func:`.certify.admitted_near`): exact
    points of the leaf with every exclusion nonzero next to ``g``.  An
    exclusion that vanishes at ``g`` can be tiny on the whole component
    through it (near-degenerate geometry), where no threshold on its value
    tells that component from one on which it vanishes identically.  The
    random moves use their own fixed stream (seed ``k``), not the
    computation's.
    """
    from ..tolerances import NEAR_ADMITTED_RADIUS, NEAR_ADMITTED_STEP

    cache = ctx.closure_cache(leaf)
    # the same point is asked about again (a branch's points are tested when it opens and
    # when the tree is refined): the verdict, a function of the leaf, the point and k, is kept
    key = ("verdict", np.asarray(g, dtype=float).tobytes(), k)
    if key not in cache:
        angles, others, params = ctx.sampler.unknowns(leaf)
        movable = [j for i in angles for j in (2 * i, 2 * i + 1)] + list(others) + list(params)
        cache[key] = admitted_near(ctx.ring, leaf, g, movable, np.random.default_rng(k),
                                   step=NEAR_ADMITTED_STEP, radius=NEAR_ADMITTED_RADIUS,
                                   cache=cache)
    return cache[key]


def dense(ctx: "Context", leaf: Branch) -> bool:
    """Is ``leaf``, its exclusions left out, dense in the zero set of its conditions?

    Then every point of that zero set is a limit of rank-deficient points,
    so it is rank deficient itself, and a branch inside it needs no
    analysis of its own.  It holds when every condition was solved by
    fixing an angle at 0 or pi or a generator at a polynomial value: the
    zero set is then a graph over the free variables (a connected
    manifold), the excluded set is the zero set of polynomials that do not
    vanish at the leaf's sample points, and the complement of such a set
    in a connected manifold is dense.
    """
    if not leaf.nonzero:
        return True
    if leaf.implicit or any(s.kind == "pair" for s in leaf.substitutions):
        return False
    return bool(ctx.sampler.points(leaf))


def on_leaf(ctx: "Context", leaf: Branch, x, k: int = 0) -> bool:
    """Is the configuration ``x`` in the closure of ``leaf``, by proof?

    ``x`` holds the values of the matrix's variables, then of the ring's
    parameters.  True when the leaf's conditions vanish at ``x`` (CONTAINED_RTOL of the
    size of their terms, each cosine and sine of a half angle at 1) and exact
    points of the leaf with every exclusion nonzero are proved next to it
    (:func:`in_closure`); False where that is not proved.
    """
    ring = ctx.ring
    names = list(ctx.tm.variables)
    g = ctx.model_point()
    for i, q in enumerate(ring.angles):
        v = float(x[names.index(q)])
        g[2 * i], g[2 * i + 1] = np.cos(v / 2), np.sin(v / 2)
    base = 2 * ring.n_angles
    for j, v in enumerate(ring.others):
        g[base + j] = float(x[names.index(v)])
    for j in range(len(ring.params)):
        g[base + len(ring.others) + j] = float(x[len(names) + j])
    # each condition against the size of its terms with every cos and sin of a half angle
    # at 1, the scale of the caller's test (CONTAINED_RTOL): against the terms at ``g`` a
    # single-term condition never vanishes where its angle is pi, as the cosine of
    # float(pi) / 2 is 6e-17, not 0
    from ..tolerances import CONTAINED_RTOL

    conds = list(leaf.conditions)
    top = np.abs(g)
    top[:2 * ring.n_angles] = 1.0
    values = ring.compile(conds)(g)
    sizes = ring.compile(conds, absolute=True)(top)
    if not np.all(np.abs(values) <= CONTAINED_RTOL * np.maximum(sizes, 1e-300)):
        return False
    return in_closure(ctx, leaf, g, k)
