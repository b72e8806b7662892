"""Covering: the branches of ``branch`` intersected with new conditions.

Solving a condition can lose points (a substitution a*C + b*S = 0 ->
(C, S) ~ (b, -a) misses a = b = 0), can make earlier equations simpler
(they are reduced again and split into factors), and can leave an equation
whose real points are all critical points of it (a sum of squares), which
no root finder reaches: those are replaced by the branches of the gradient.
The functions here return branches that together cover exactly the real
points asked for.
"""

from __future__ import annotations

from fractions import Fraction
from typing import TYPE_CHECKING

import sympy as sp

from ..tolerances import NEAR_MISS_RTOL, SIGN_STEP
from .branch import Branch

if TYPE_CHECKING:
    from .context import Context

__all__ = ["children", "cover", "distinct", "reduced_exclusion"]

#: An exclusion is replaced by its difference with a multiple of an equation of the branch
#: when the difference's coefficients sum to at most this fraction of its own.
EXCLUSION_REDUCTION = Fraction(1, 10)


def children(ctx: "Context", branch: Branch, f) -> list[Branch]:
    """Branches covering ``branch`` intersected with {f = 0}.

    A child whose equation has real points only where its gradient
    vanishes too (a sum of squares, say) is replaced by the branches
    of those critical points, which the sampler can reach.
    """
    out = []
    for child in cover(ctx, branch, [f]):
        if child.implicit and _critical_only(ctx, child):
            if ctx.reporting:
                # the equation can have thousands of terms: written out only when read
                ctx.progress(f"real points of {sp.sstr(ctx.ring.to_sympy(child.implicit[-1]))} "
                             "= 0 only where its gradient vanishes: adding the gradient")
            out.extend(_critical_branches(ctx, child))
        else:
            out.append(child)
    return distinct(out)


def distinct(branches, seen: set | None = None) -> list[Branch]:
    """``branches`` without repeats (equal :attr:`Branch.key`), in their order.

    The points where a substitution fails are covered case by case, and two
    cases can end in the same branch (q1 = 0 then q4 = 0, or q4 = 0 then
    q1 = 0): on tiago's arm one split gave 38 children, 14 of them
    distinct.  ``seen`` carries the keys of branches already taken across
    calls.
    """
    seen = set() if seen is None else seen
    out = []
    for b in branches:
        if b.key not in seen:
            seen.add(b.key)
            out.append(b)
    return out

def _critical_branches(ctx: "Context", child: Branch) -> list[Branch]:
    """``child`` and the gradient of its last equation, split on the gradient's factors."""
    branches = [child]
    for d in ctx.ring.gradient(child.implicit[-1]):
        nxt = []
        for b in branches:
            dr = b.reduce(d, ctx.ring)
            if dr.is_zero():
                nxt.append(b)
                continue
            for g in ctx.factors(dr):
                nxt.extend(c for c in cover(ctx, b, [g]) if ctx.sampler.points(c))
        branches = nxt
    return branches

def _critical_only(ctx: "Context", child: Branch) -> bool:
    """Are the real points of the child's last equation critical points of it?

    Either the sampler came close without converging (see
    BranchSampler.near_miss), or every sample point has a gradient that
    vanishes relative to the size of its terms (NEAR_MISS_RTOL) and the
    equation keeps one sign around every sample point (SIGN_STEP).
    """
    pts = ctx.sampler.points(child)
    if not pts:
        return ctx.sampler.near_miss(child)
    f = child.implicit[-1]
    if not ctx.probe.gradient_vanishes(f, pts, NEAR_MISS_RTOL):
        return False
    # a gradient small against the size of its terms can also come from terms that nearly
    # cancel (near-degenerate geometry: coefficients 512000000 and -511999200): a regular
    # zero still has f changing sign across it, a critical one does not
    angles, others, _ = ctx.sampler.unknowns(child)
    return not ctx.probe.changes_sign(f, pts, angles, others, ctx.rng, step=SIGN_STEP)


def cover(ctx: "Context", branch: Branch, conditions) -> list[Branch]:
    """Branches covering ``branch`` and all of ``conditions``.

    A substitution a*C + b*S -> (C, S) ~ (b, -a) misses the points where
    a = b = 0; those points satisfy the condition and are covered by
    their own branches, recursively.  A condition that the branch's
    substitutions changed, and a and b above, are split into their
    irreducible factors first, so that a factor like C**2 + S**2, which
    has no real zero, never becomes a branch.
    """
    if not conditions:
        return [branch]
    c = branch.reduce(conditions[0], ctx.ring)
    rest = list(conditions[1:])
    if c.is_zero():
        return cover(ctx, branch, rest)
    if ctx.ring.is_number(c):
        return []
    if c != conditions[0]:
        fs = ctx.factors(c)
        if len(fs) != 1 or fs[0] != c:
            return [b for f in fs for b in cover(ctx, branch, [f] + rest)]
    child, exceptional = branch.with_condition(c, ctx.ring)
    out = [b for settled in _settle(ctx, branch, child) for b in cover(ctx, settled, rest)]
    for extra in exceptional:
        split = [[]]
        for e in extra:
            e = branch.reduce(e, ctx.ring)
            if e.is_zero():
                continue
            split = [s + [f] for s in split for f in ctx.factors(e)]
        for conds in split:
            out += cover(ctx, branch, conds + rest)
    return distinct(out)

def _settle(ctx: "Context", parent: Branch, child: Branch) -> list[Branch]:
    """``child`` with its earlier equations reduced by its newest substitution.

    An implicit equation stays as it was when it was added; a later
    substitution can turn it into a constant (the branch is empty), into
    zero (it is implied), or into a product of simpler factors, each of
    which may be solvable.  Left alone, the root finder would have to
    find the zeros of something like ``C*S*d3`` through a residual that
    is almost constant away from them.  An excluded polynomial that the
    substitution makes zero empties the branch; one it makes a nonzero
    constant excludes nothing.
    """
    if len(child.substitutions) == len(parent.substitutions):
        if len(child.implicit) == len(parent.implicit) or not child.nonzero:
            return [child]
        nonzero = []
        for e in child.nonzero:
            r = reduced_exclusion(ctx.ring, e, child.implicit[-1])
            if r.is_zero():
                return []
            if not ctx.ring.is_number(r):
                nonzero.append(r)
        return [Branch(child.conditions, child.substitutions, child.implicit, tuple(nonzero))]
    ring = ctx.ring
    nonzero = []
    for e in child.nonzero:
        r = child.reduce(e, ring)
        if r.is_zero():
            return []
        if not ctx.ring.is_number(r):
            nonzero.append(r)
    stale, reduced = [], []
    for e in child.implicit:
        r = child.reduce(e, ring)
        if r != e:
            stale.append(e)
            reduced.append(r)
    if not stale and len(nonzero) == len(child.nonzero):
        return [child]
    base = Branch(tuple(c for c in child.conditions if not any(c is e for e in stale)),
                  child.substitutions,
                  tuple(e for e in child.implicit if not any(e is x for x in stale)),
                  tuple(nonzero))
    out = [base]
    for r in reduced:
        if r.is_zero():
            continue
        if ctx.ring.is_number(r):
            return []
        fs = []
        for f in ctx.factors(r):
            if ctx.parameter_only(f):
                ctx.special_parameters(f, "an equation reduced on a branch")
            else:
                fs.append(f)
        out = [b for o in out for f in fs for b in cover(ctx, o, [f])]
    return out


def reduced_exclusion(ring, p, e):
    """``p`` or ``p - c*e`` (``c`` rational), whichever has the smaller coefficients.

    On a branch where ``e`` vanishes both exclude the same points, exactly.
    On near-degenerate geometry the determinant that guards a level's null
    vectors can agree with an equation of the branch to one part in 1e4
    (romeo_laas_small's elbow): on the component it is then 1e-6 of the
    size of its terms, too small for the numeric tests of exclusions
    (EXCLUSION_RTOL and those of rankloci.methods.finalize), while the
    difference is of the order of its own terms.  ``c`` cancels the term of
    ``e`` with the largest coefficient; both must have the same degree in
    each angle pair (homogeneous polynomials of the same degrees).
    """
    if e.is_zero() or ring.pair_degrees(p) != ring.pair_degrees(e):
        return p
    mons = e.monoms()
    coeffs = e.coeffs()
    k = max(range(len(coeffs)), key=lambda i: abs(coeffs[i]))
    c = dict(zip(p.monoms(), p.coeffs())).get(mons[k], 0)
    if c == 0:
        return p
    r = ring.normal(p - (c / coeffs[k]) * e)
    if _coefficient_sum(r) * EXCLUSION_REDUCTION.denominator <= EXCLUSION_REDUCTION.numerator * _coefficient_sum(p):
        return r
    return p


def _coefficient_sum(p):
    return sum((abs(c) for c in p.coeffs()), 0)
