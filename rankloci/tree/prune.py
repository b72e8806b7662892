"""Pruning: is a branch inside a component already found?

A branch all of whose points lie on a component found before needs no
analysis: whatever it holds is already in the locus.  The leaves of the
tree are tried newest condition sets first; the test is symbolic where the
conditions decide it, numeric (at the branch's sample points) otherwise.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from .branch import Branch

if TYPE_CHECKING:
    from .context import Context

__all__ = ["known", "known_symbolically", "dense"]


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
    vanishes = ctx.probe.vanishes
    for leaf, _ in ctx.leaves:
        if leaf is branch or not leaf.conditions:
            continue
        if len(leaf.conditions) > len(branch.conditions):
            continue
        if all(vanishes(c, pts) for c in leaf.conditions) and (
                dense(ctx, leaf)
                or not any(vanishes(e, [g]) for e in leaf.nonzero for g in pts)):
            return True
    return False


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
