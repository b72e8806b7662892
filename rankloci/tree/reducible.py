"""Leaves whose zero set is reducible: a regular piece next to a singular one.

A branch is a component when the whole matrix loses rank at its points.
The rank is decided at a few sample points, and the equations of a branch
can have several irreducible pieces of the same dimension: on PR2's arm,
``4 cos q3 + 1 = sin q4 cos q5 cos q6 + sin q6 cos q4 = ...`` holds both on
a singular piece and on ``cos q4 = cos q6 = 0``, where J has full rank.  A
leaf is therefore sampled again, more widely (``LEAF_POINTS``), before it
is recorded.  When some of those points are regular, the branch is split on
a maximal minor that is nonzero at one of them: every singular point of the
branch is a zero of that minor, so the pieces below hold all of them, and
the recursion goes on until every piece is singular at all of its points
or has none.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..algebra import transpose
from ..loci import Outcome
from .probe import numeric_rank, scaled_ratio
from ..tolerances import (BISECT_LEVELS, LEAF_POINTS, MINOR_CANDIDATES, SCAN_GRID,
                          SPECIAL_PARTIAL_ROWS, SPECIAL_POINTS, SPECIAL_SOLVES, SPECIAL_SOLVE_ROWS,
                          SPECIAL_STARTS)

if TYPE_CHECKING:
    from .branch import Branch
    from .context import Context

__all__ = ["LEAF_POINTS", "ranked_points", "refine_leaves", "repair_leaves", "special_points",
           "special_solved_points", "split_on_minor"]


def ranked_points(ctx: "Context", branch: "Branch") -> tuple[list, list, bool]:
    """Points of ``branch`` where the matrix has full rank, points where it has not, and
    whether every point found lies where a pair substitution of the branch is undefined.

    Its first sample points, ``LEAF_POINTS`` solved from uniform random starts, and the exact
    points among ``SPECIAL_STARTS`` starts with random angles at multiples of pi/2 (a regular
    piece of a robot's leaf is often a coordinate one, like cos q4 = cos q6 = 0, which the
    solves from uniform starts seldom reach).

    The points where a substitution (C, S) ~ (b, -a) is undefined (:func:`_degenerate_pairs`)
    are ranked neither way.  When all of them are such points, the branch has no real point
    found where its substitutions hold: its equations are real only on the exceptional sets
    a = b = 0, which are branches of their own (:func:`~rankloci.tree.cover.cover`).  On a
    9R snake, a leaf q4 = q5 = pi, E1 = E2 = 0 has its 19 points found (3 sample points, 12
    wider ones, 4 special ones) where q6 = pi and q3 + q7 = pi: E2 is real only where it is
    critical, and there the substitution for q2 is undefined; reported, the leaf was a
    component of no real point of its own, regular where q6 = 0 and q3 + q7 = 0.
    """
    full = ctx.full_rank
    # the wider sample draws from its own stream, so that the computation's random choices
    # (and with them its tree) stay those of a computation without it
    sampler = ctx.sampler
    stream, sampler.rng = sampler.rng, np.random.default_rng(len(branch.conditions))
    try:
        wider = list(sampler.points(branch, count=LEAF_POINTS))
    finally:
        sampler.rng = stream
    special = special_points(ctx, branch)
    pts = list(sampler.points(branch)) + wider + _scan_points(ctx, branch) + special
    from ..tolerances import LEAF_REGULAR_RTOL

    regular, singular = [], []
    degenerate = _degenerate_pairs(ctx, branch, pts)
    excl = _exceptional_exclusions(ctx, branch, pts, degenerate)
    if excl:
        ctx.set_exclusions(branch, excl)
    # the sampled points (not the exact special ones) that double precision does not show
    # regular are decided in extended precision, where the branch is small enough
    precise = ctx.precise.affordable(branch)
    n_sampled = len(pts) - len(special)
    for k, (g, bad) in enumerate(zip(pts, degenerate)):
        if bad.any():
            continue
        A, S = ctx.probe.evaluated(ctx.M, g)
        ratio = scaled_ratio(A, S)
        if ratio > LEAF_REGULAR_RTOL and numeric_rank(A, S) == full:
            regular.append(g)
            continue
        verdict = ctx.real_verdict(branch, g, ratio) if precise and k < n_sampled else None
        if verdict is False:
            regular.append(g)
        elif verdict or numeric_rank(A, S) < full:
            singular.append(g)
    exceptional = bool(len(pts)) and bool(degenerate.any(axis=1).all())
    return regular, singular, exceptional


def _degenerate_pairs(ctx: "Context", branch: "Branch", pts) -> np.ndarray:
    """Which substitutions (C, S) ~ (b, -a) of ``branch`` are undefined at each point.

    A boolean array, one row per point, one column per pair substitution.  Where a and b
    are both below EXCLUSION_RTOL of their terms, the sampler normalised rounding noise into
    (C, S): such a point lies in the exceptional set {a = b = 0}, which is a branch of its
    own, and the matrix's rank there says nothing about this branch (on tiago's arm a whole
    branch lies in it, with |a|, |b| near 1e-6 of their terms).
    """
    from ..tolerances import EXCLUSION_RTOL

    pairs = [s for s in branch.substitutions if s.kind == "pair"]
    if not pairs or not pts:
        return np.zeros((len(pts), len(pairs)), dtype=bool)
    ring = ctx.ring
    G = np.array(pts, dtype=float)
    V, S = ring.compile([v for s in pairs for v in s.values], sized=True)(G)
    V, S = V.reshape(len(G), len(pairs), 2), S.reshape(len(G), len(pairs), 2)
    return ~(np.hypot(V[..., 0], V[..., 1]) > EXCLUSION_RTOL * np.hypot(S[..., 0], S[..., 1]))


def _exceptional_exclusions(ctx: "Context", branch: "Branch", pts, degenerate) -> list:
    """Exclusions for a leaf whose equations hold, with J regular, on a degenerate substitution.

    ``pts`` satisfy the leaf's conditions; ``degenerate`` (:func:`_degenerate_pairs`) says at
    which of them each pair substitution (C, S) ~ (b, -a) is undefined, in its exceptional set
    {a = b = 0}.  The branch leaves that set to another branch, but the component's equations
    admit it: where J is regular at such a point, the component is reported without the zero
    set of the factors of the shorter of a and b that vanish there (nonzero on the branch
    itself, whose closure is unchanged; the other factors can hold the branch's real points,
    as sin(q6/2) cos(q6/2) cos(q7/2) on a 9R snake whose leaf is real only where q6 = pi).
    tiago_dual's left arm: q3 = 0, q4 = -pi/2, q5 = pi.
    """
    from ..tolerances import EXCLUSION_RTOL, LEAF_REGULAR_RTOL

    pairs = [s for s in branch.substitutions if s.kind == "pair"]
    out = []
    for g, bad in zip(pts, degenerate):
        if not bad.any():
            continue
        A, S = ctx.probe.evaluated(ctx.M, g)
        if numeric_rank(A, S) < ctx.full_rank or not scaled_ratio(A, S) > LEAF_REGULAR_RTOL:
            continue
        for sub in (p for p, b in zip(pairs, bad) if b):
            p = min((v for v in sub.values if not v.is_constant()), key=len, default=None)
            if p is None:
                continue
            # the factors small at g, scaled by their coefficients (the generators of angles
            # lie on the unit circle; a value scaled by its own terms is 1 for any single
            # term, such as sin(q6/2)); where none is, the whole of p
            factors = [f for f in ctx.factors(p) if not f.is_constant()]
            values = ctx.ring.compile(factors)(np.array([g]))[0] if factors else []
            small = [f for f, v in zip(factors, values)
                     if abs(v) <= EXCLUSION_RTOL * sum(abs(float(c)) for c in f.coeffs())]
            for f in small or [p]:
                if not any(f == q for q in out):
                    out.append(f)
    return out


def _scan_points(ctx: "Context", branch: "Branch") -> list:
    """Points of ``branch`` found by solving its implicit equations one at a time, on lines.

    Each equation in turn is solved for one free unknown it depends on (chosen at random),
    the other unknowns at random values or at the values solved so far: the sign changes
    of the equation along ``SCAN_GRID`` values of that unknown, one of them bisected to
    rounding.  A line crosses every piece of the zero set that it meets, where Newton's
    method from a random start goes to the nearest piece.  On the 7R arm with 0.5 mm
    offsets, ``800 sin q4 + cos q4 = P = 0`` holds on ``sin q3 = 0`` (singular) and on a
    regular piece; every one of 15 solves from random starts went to the first.
    """
    if not branch.implicit:
        return []
    angles, others, params = ctx.sampler.unknowns(branch)
    if not len(angles) + len(others):
        return []
    # the lines run through angles of +-pi, where a half-angle tangent is infinite: such
    # values are nan and skipped, and numpy need not warn of them
    with np.errstate(all="ignore"):
        return _scan(ctx, branch, angles, others, params)


def _scan(ctx, branch, angles, others, params) -> list:
    """The search of :func:`_scan_points`."""
    from ..tolerances import EXCLUSION_CERTIFY_RTOL, ROOT_XTOL

    sampler, ring = ctx.sampler, ctx.ring
    na, no = len(angles), len(others)
    rng = np.random.default_rng(len(branch.conditions) + 1)
    fixed = sampler._fixed
    eqs = list(branch.implicit)
    evaluators = [ring.compile([f], sized=True) for f in eqs]
    unknown_gens = [[2 * i, 2 * i + 1] for i in angles] + [[j] for j in others]
    out = []
    for _ in range(LEAF_POINTS):
        x = np.concatenate([rng.uniform(-np.pi, np.pi, na), rng.uniform(-2.0, 2.0, no),
                            fixed[list(params)] if params else np.zeros(0)])
        solved = set()
        for f, ev in zip(eqs, evaluators):
            degs = f.degrees()
            cands = [k for k in range(na + no) if k not in solved
                     and any(degs[g] for g in unknown_gens[k])]
            if not cands:
                continue
            k = int(rng.choice(cands))
            x = _solve_on_line(sampler, branch, angles, others, params, ev, x, k, k < na, rng)
            if x is None:
                break
            solved.add(k)
        if x is None:
            continue
        G = sampler.generators_batch(branch, angles, others, params, x[None, :])
        if np.isnan(G).any():
            continue
        R, size = ring.compile(eqs, sized=True)(G)
        if not np.max(np.abs(R) / np.maximum(size, 1e-300)) <= ROOT_XTOL:
            continue
        nz = list(branch.nonzero)
        if nz:
            # a regular point here only chooses the minor a split is made on, which is sound
            # at any regular point of the equations: the exclusions need only be nonzero
            V, size = ring.compile(nz, sized=True)(G)
            if not np.min(np.abs(V) / np.maximum(size, 1e-300)) > EXCLUSION_CERTIFY_RTOL:
                continue
        out.append(G[0])
    return out


def _solve_on_line(sampler, branch, angles, others, params, ev, x, k, is_angle, rng):
    """``x`` with unknown ``k`` moved to a random sign change of the equation along its line."""
    lo, hi = (-np.pi, np.pi) if is_angle else (-2.0, 2.0)
    t = np.linspace(lo, hi, SCAN_GRID + 1)
    X = np.repeat(x[None, :], len(t), axis=0)
    X[:, k] = t
    G = sampler.generators_batch(branch, angles, others, params, X)
    v = ev(G)[0][:, 0]
    ok = ~np.isnan(v)
    sign = np.sign(v)
    cross = np.flatnonzero(ok[:-1] & ok[1:] & (sign[:-1] * sign[1:] < 0))
    if not len(cross):
        return None
    j = int(rng.choice(cross))
    a, b, fa = t[j], t[j + 1], v[j]
    # bisection to rounding, BISECT_LEVELS steps a call: every midpoint those steps can take
    # is evaluated together (a call costs about as much for seven points as for one), each
    # computed as the step would compute it
    steps = 0
    while steps < 60:
        levels = min(BISECT_LEVELS, 60 - steps)
        nodes, mids = [(a, b)], []
        for i in range(2 ** levels - 1):
            lo_, hi_ = nodes[i]
            m = 0.5 * (lo_ + hi_)
            mids.append(m)
            nodes += [(lo_, m), (m, hi_)]
        X1 = np.repeat(x[None, :], len(mids), axis=0)
        X1[:, k] = mids
        fs = ev(sampler.generators_batch(branch, angles, others, params, X1))[0][:, 0]
        i, done = 0, False
        for _ in range(levels):
            m, fm = mids[i], fs[i]
            if fm == 0 or not np.isfinite(fm):
                a = b = m
                done = True
                break
            if np.sign(fm) == np.sign(fa):
                a, fa, i = m, fm, 2 * i + 2
            else:
                b, i = m, 2 * i + 1
        steps += levels
        if done:
            break
    out = x.copy()
    out[k] = 0.5 * (a + b)
    return out


def special_points(ctx: "Context", branch: "Branch") -> list:
    """Points of ``branch`` (within ROOT_XTOL, exclusions above EXCLUSION_RTOL) among random
    starts with each free angle at a random multiple of pi/2 with probability one half."""
    from ..tolerances import EXCLUSION_RTOL, ROOT_XTOL

    if not branch.implicit:
        return []
    sampler, ring = ctx.sampler, ctx.ring
    (angles, others, params), X, _ = _special_starts(ctx, branch)
    G = sampler.generators_batch(branch, angles, others, params, X)
    ok = ~np.isnan(G).any(axis=1)
    G = G[ok]
    hit = np.max(np.abs(_relative(ring.compile(list(branch.implicit), sized=True), G)),
                 axis=1) <= ROOT_XTOL
    if branch.nonzero and hit.any():
        V = _relative(ring.compile(list(branch.nonzero), sized=True), G)
        hit &= np.min(np.abs(V), axis=1) > EXCLUSION_RTOL
    return list(G[hit][:SPECIAL_POINTS])


def _relative(evaluate, G) -> np.ndarray:
    """Values of a sized evaluator (``PolyRing.compile(..., sized=True)``) at the rows ``G``,
    each over the size of its terms."""
    V, S = evaluate(G)
    return V / np.maximum(S, 1e-300)


def _special_starts(ctx: "Context", branch: "Branch"):
    """The starts of :func:`special_points`: unknown rows, and which angles are snapped."""
    angles, others, params = ctx.sampler.unknowns(branch)
    rng = np.random.default_rng(len(branch.conditions))
    X = np.concatenate([rng.uniform(-np.pi, np.pi, (SPECIAL_STARTS, len(angles))),
                        rng.uniform(-2.0, 2.0, (SPECIAL_STARTS, len(others) + len(params)))],
                       axis=1)
    snap = rng.random((SPECIAL_STARTS, len(angles))) < 0.5
    X[:, :len(angles)][snap] = rng.integers(-1, 3, int(snap.sum())) * (np.pi / 2)
    return (angles, others, params), X, snap


def refine_leaves(ctx: "Context") -> None:
    """Split the leaves on which :func:`special_solved_points` finds regular points.

    Run once the tree is grown, on the leaves whose sample points do not all lie on other
    leaves (:func:`.prune.known`): a leaf inside others is dropped by finalize whatever its
    pieces.  On PR2's 9-joint finger chains the special solves found regular points on four
    leaves of that kind; split during the tree, their pieces made it grow from 41 s to
    50-57 s, with the same locus.  A split's new leaves are checked in turn.
    """
    from ..tolerances import LEAF_REGULAR_RTOL
    from . import prune

    checked = set()
    while True:
        todo = [(b, n) for b, n in ctx.leaves if b.key not in checked]
        if not todo:
            return
        for branch, node in todo:
            checked.add(branch.key)
            if prune.known(ctx, branch):
                continue
            regular = []
            for g in special_solved_points(ctx, branch):
                A, S = ctx.probe.evaluated(ctx.M, g)
                if scaled_ratio(A, S) > LEAF_REGULAR_RTOL and numeric_rank(A, S) == ctx.full_rank:
                    regular.append(g)
            if regular:
                _split_leaf(ctx, branch, node, regular)
            else:
                _keep_exceptional_exclusions(ctx, branch)


def exceptional_branch(ctx: "Context", branch: "Branch", sub) -> "Branch | None":
    """Where the conditions of ``branch`` hold and its pair substitution ``sub`` is undefined.

    ``sub`` is (C, S) ~ (b, -a), solving a condition a*C + b*S = 0.  The conditions are
    taken again in their order, that one replaced by a = 0 and b = 0, so that the pair is
    free: the later conditions were reduced by ``sub`` and hold wherever they still do at
    a = b = 0 (a condition homogeneous in the pair becomes one that vanishes there).  None
    when a or b is a nonzero constant (the substitution is defined everywhere).
    """
    from .branch import Branch

    ring = ctx.ring
    a, b = -sub.values[1], sub.values[0]
    if any(f.is_constant() and not f.is_zero() for f in (a, b)):
        return None
    out = Branch()
    replaced = False
    for c in branch.conditions:
        c = out.reduce(c, ring)
        if c.is_zero():
            continue
        nxt, _ = out.with_condition(c, ring)
        got = nxt.substitutions[len(out.substitutions):]
        if not replaced and got and got[0].kind == "pair" and got[0].index == sub.index \
                and got[0].values == sub.values:
            replaced = True
            for f in (a, b):
                f = out.reduce(f, ring)
                if not f.is_zero():
                    out, _ = out.with_condition(f, ring)
            continue
        out = nxt
    return out if replaced else None


def _keep_exceptional_exclusions(ctx: "Context", branch: "Branch") -> None:
    """Exclusions for the pieces where the leaf's equations hold with a pair substitution
    undefined and the matrix regular (see :func:`_exceptional_exclusions`).

    The self-check's hints find such pieces after the fact (:func:`repair_leaves`); here
    each pair substitution's :func:`exceptional_branch` is sampled before the locus is
    shown.  On a 9R snake the first computation's check found components regular at 9
    configurations, each on such a piece or inside an exclusion; with this, at 2, and the
    self-checked run took 70 s instead of 85 s.  A factor kept must be nonzero at every
    sample point of the leaf, so that no piece of the leaf itself is excluded.
    """
    pts = []
    for sub in branch.substitutions:
        piece = exceptional_branch(ctx, branch, sub) if sub.kind == "pair" else None
        if piece is not None:
            pts += ctx.sampler.points(piece)
    if not pts:
        return
    # _exceptional_exclusions looks only at the points where the matrix is regular
    found = _exceptional_exclusions(ctx, branch, pts, _degenerate_pairs(ctx, branch, pts))
    own = ctx.sampler.points(branch)
    fresh = []
    for f in found:
        if not ctx.probe.vanishing([f], own).any() and not any(f == k for k in fresh):
            fresh.append(f)
    ctx.add_exclusions(branch, fresh)


def _split_leaf(ctx: "Context", branch: "Branch", node: int, regular) -> bool:
    """Replace the recorded leaf ``branch`` by its pieces (:func:`split_on_minor` at the
    ``regular`` points); it stays, in its place, when the minor vanishes on it."""
    return ctx.replace_leaf(branch, node, lambda: split_on_minor(
        ctx, branch, node, regular, ctx.tree.nodes[node]["outcome"]))


def repair_leaves(ctx: "Context", hints) -> int:
    """Leaves whose equations hold at a configuration of ``hints`` where the matrix is regular.

    ``hints`` are configurations (dicts from variable names to values) at which a check
    found a component regular: real points of the leaf's equations that no sample reached (on
    romeo's 8-joint arm, a regular piece inside an exclusion's zero set: 48 of 48 of the
    sampler's solves from uniform starts, residuals scaled by term sizes, land on the
    singular piece, least squares on the equations scaled by their largest coefficient lands
    on the regular one from 4 of 8 starts).  At each such point that the leaf excludes (an
    exclusion vanishes there), the vanishing factors of the exclusion stay in the component,
    which :func:`~rankloci.methods.finalize` would otherwise have dropped.  At a point where
    a pair substitution (C, S) ~ (b, -a) of the leaf is undefined (a = b = 0), the leaf keeps
    the exclusion :func:`_exceptional_exclusions` gives there: the point lies in the
    substitution's exceptional set, a branch of its own, and no minor reduced on the leaf can
    be nonzero at it (on a 9R snake, q3 = q4 = pi with E1 = E2 = 0 holds on a singular piece
    and, where q6 = 0, on a regular one where q2's substitution degenerates).  At any other
    point of the leaf, the leaf is split on a minor nonzero there.  Returns how many leaves
    changed.
    """
    changed = 0
    full = ctx.full_rank
    for q in hints:
        g = ctx.point_at(q)
        if g is None:
            continue
        A, S = ctx.probe.evaluated(ctx.M, g)
        if numeric_rank(A, S) < full:
            continue
        for branch, node in list(ctx.leaves):
            if not all(ctx.probe.vanishes(c, [g]) for c in branch.conditions):
                continue
            vanishing = [f for p in branch.nonzero if ctx.probe.vanishes(p, [g])
                         for f in ctx.factors(p) if ctx.probe.vanishes(f, [g])]
            degenerate = _degenerate_pairs(ctx, branch, [g])
            if not vanishing and degenerate.any():
                vanishing = _exceptional_exclusions(ctx, branch, [g], degenerate)
            if vanishing:
                changed += bool(ctx.add_exclusions(branch, vanishing))
                continue
            if not degenerate.any():
                changed += _split_leaf(ctx, branch, node, [g])
    return changed


def special_solved_points(ctx: "Context", branch: "Branch") -> list:
    """Points of ``branch`` solved from special starts at which some of its equations vanish.

    A leaf's equations can hold on its singular piece and on a smaller piece of their own
    that fixes some angles at multiples of pi/2 and is cut out by the other equations there:
    on tiago's 9-joint thumb chain, a leaf of three equations (dimension 5 in 7 unknowns)
    whose first two vanish wherever q4 = 0 and q6 = 3 pi/2, the third cutting a regular piece
    of dimension 4 out of that.  Neither random solves (they go to the larger piece) nor the
    exact special points (the third equation is not solved by angles at multiples of pi/2)
    reach it.  Here the starts of :func:`special_points` at which some equations vanish
    exactly, and not all, are grouped by which do and by their snapped angles; those angles
    are held and the rest solved (Gauss-Newton), for up to SPECIAL_SOLVES groups, round
    robin over the patterns of vanishing equations.  The points found are no exact points:
    they are accepted as the sampler accepts its own (ROOT_XTOL, EXCLUSION_RTOL).
    """
    from ..numeric.gauss_newton import gauss_newton_rows
    from ..tolerances import EXCLUSION_RTOL, ROOT_XTOL

    # the equations hold on a piece smaller than the branch only when they are no complete
    # intersection: k equations cut every piece of their zero set to at least (unknowns - k)
    # dimensions (decided exactly, ModularProbe.complete_intersection; undecided: they may)
    if len(branch.implicit) < 2 or ctx.modular.complete_intersection(branch):
        return []
    sampler, ring = ctx.sampler, ctx.ring
    (angles, others, params), X, snap = _special_starts(ctx, branch)
    G = sampler.generators_batch(branch, angles, others, params, X)
    ok = ~np.isnan(G).any(axis=1)
    eqs = list(branch.implicit)
    sized = ring.compile(eqs, sized=True)
    zero = np.zeros((len(X), len(eqs)), dtype=bool)
    zero[ok] = np.abs(_relative(sized, G[ok])) <= ROOT_XTOL
    chosen = _held_groups(ctx, branch, (angles, others, params), X, snap, zero, sized)
    nz_sized = ring.compile(list(branch.nonzero), sized=True) if branch.nonzero else None
    found = []
    with np.errstate(all="ignore"):
        for held, rows in chosen:
            free = np.setdiff1d(np.arange(X.shape[1]), held)
            if not len(free):
                continue
            # the starts of a group differ only in their free columns
            base = rows[0]

            def residual(Y, base=base, free=free):
                Z = np.repeat(base[None, :], len(Y), axis=0)
                Z[:, free] = Y
                Gz = sampler.generators_batch(branch, angles, others, params, Z)
                V = _relative(sized, Gz)
                V[np.isnan(Gz).any(axis=1)] = 1e3
                return V

            Y = gauss_newton_rows(residual, np.array(rows[:SPECIAL_SOLVE_ROWS])[:, free])
            Z = np.repeat(base[None, :], len(Y), axis=0)
            Z[:, free] = Y
            Gz = sampler.generators_batch(branch, angles, others, params, Z)
            ok = ~np.isnan(Gz).any(axis=1) & (np.max(np.abs(residual(Y)), axis=1) <= ROOT_XTOL)
            if nz_sized is not None:
                ok &= np.min(np.abs(_relative(nz_sized, Gz)), axis=1) > EXCLUSION_RTOL
            found.extend(Gz[ok])
    return found


def _held_groups(ctx: "Context", branch: "Branch", unknowns, X, snap, zero, sized) -> list:
    """(held columns, starts) to solve for :func:`special_solved_points`.

    The starts at which some equations vanish (``zero``, a row per start) and not all, each
    with only the snapped angles those equations need held, grouped by which equations vanish
    and which angles are held at which values: up to SPECIAL_SOLVES groups, taken round robin
    over the patterns of vanishing equations.
    """
    from ..tolerances import ROOT_XTOL

    angles, others, params = unknowns
    sampler = ctx.sampler
    partial = np.flatnonzero(zero.any(axis=1) & ~zero.all(axis=1))[:SPECIAL_PARTIAL_ROWS]
    rng = np.random.default_rng(len(branch.conditions) + 2)
    groups: dict = {}
    for r in partial:
        # the snapped angles that the vanishing equations need: each is let go in turn (a
        # random value) and stays so when those equations still vanish; an angle held at a
        # special value for nothing would keep the solved point special (a multiple of pi/2
        # at which the matrix drops rank for reasons of its own)
        base, held = X[r].copy(), []
        for j in np.flatnonzero(snap[r]):
            trial = base.copy()
            trial[j] = rng.uniform(-np.pi, np.pi)
            Gt = sampler.generators_batch(branch, angles, others, params, trial[None, :])
            if np.isnan(Gt).any():
                held.append(j)
                continue
            if (np.abs(_relative(sized, Gt)[0]) <= ROOT_XTOL)[zero[r]].all():
                base = trial
            else:
                held.append(j)
        key = (tuple(zero[r]), tuple(held), tuple(np.round(base[held] / (np.pi / 2)).astype(int)))
        groups.setdefault(key, []).append(base)
    by_pattern: dict = {}
    for key, rows in groups.items():
        by_pattern.setdefault(key[0], []).append((key[1], rows))
    chosen = []
    queues = list(by_pattern.values())
    while queues and len(chosen) < SPECIAL_SOLVES:
        queues = [q for q in queues if q]
        for q in queues:
            if len(chosen) < SPECIAL_SOLVES:
                chosen.append(q.pop(0))
    return chosen


def split_on_minor(ctx: "Context", branch: "Branch", node: int, regular, outcome: Outcome) -> bool:
    """Split ``branch`` on a maximal minor nonzero at the ``regular`` points; recurse below.

    Returns False, and splits nothing, when that minor vanishes identically on the branch:
    then the regular points are no exact points of it (a substitution (C, S) ~ (b, -a)
    whose a and b vanish on the whole branch, where the sampler normalises rounding noise),
    and the branch is taken as its singular points say.
    """
    # a minor of the matrix itself (memoised across the tree: entries substituted for a
    # branch can have a thousand terms each), reduced on the branch
    M = ctx.M if len(ctx.M) <= len(ctx.M[0]) else transpose(ctx.M)
    ctx.progress(f"branch {node}: regular points next to singular ones, split on a minor")
    D = branch.reduce(_minor(ctx, branch, M, regular), ctx.ring)
    if D.is_zero():
        return False
    ctx.annotate(node, outcome=Outcome.REFINED,
                 note="regular points on the branch: split on a maximal minor")
    ctx.split(branch, node, D, "a minor on a reducible branch",
              lambda child, sub: _below(ctx, child, sub, outcome))
    return True


def _below(ctx: "Context", branch: "Branch", node: int, outcome: Outcome):
    """A piece of a reducible branch: a leaf where the matrix is singular, else split again."""
    pts = ctx.open_branch(branch, node)
    if pts is None:
        return
    full = ctx.full_rank
    regular = [g for g in pts if ctx.probe.rank_at(ctx.M, g) == full]
    if not (regular and split_on_minor(ctx, branch, node, regular, outcome)):
        ctx.leaf(branch, node, outcome)


def _minor(ctx: "Context", branch: "Branch", M, points):
    """The determinant of an n x n block of the n x m matrix ``M`` regular at one of ``points``.

    The block choice of the singular vector method, among its first ``MINOR_CANDIDATES``
    regular blocks (smallest entries first, the fewest determinant terms wins).
    """
    from ..errors import LocusError
    from .blocks import choose_columns

    try:
        return choose_columns(ctx, M, points, MINOR_CANDIDATES)[1]
    except LocusError:
        # regular in extended precision only (nearly degenerate geometry): the block is
        # chosen at the refined point
        cols = ctx.precise.regular_columns(branch, M, points)
        if cols is None:
            raise
        return ctx.det([[row[c] for c in cols] for row in M])
