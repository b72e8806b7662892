"""From the leaves of a branch tree to the components of a :class:`~rankloci.loci.Locus`.

Each component leaf becomes a :class:`~rankloci.loci.Component`: its
equations in readable form (:mod:`.readable`), its dimension (the rank of
the equations' gradient at a sample point), its rank drop and lost
directions there, and the exclusions it needs.  Then leaves q = 0 and q = pi
that agree otherwise are joined into sin q = 0, duplicates and components
inside another are dropped, and lost directions are added as expressions
where they are small.
"""

from __future__ import annotations

import dataclasses
import functools
import operator
from dataclasses import dataclass

import numpy as np
import sympy as sp

from ..algebra import TermLimit, transpose
from ..loci import Component, Outcome
from ..numeric.equations import dimension_from_gradient, normalised
from ..numeric.closure import near_admitted
from ..tolerances import (CONTAINED_EXCLUSION_RTOL, CONTAINED_RTOL, DIMENSION_STEP,
                          MAX_DIRECTION_COFACTOR_TERMS, MAX_DIRECTION_MATRIX_TERMS,
                          MAX_DIRECTION_TERMS, NEAR_ADMITTED_EXCLUSION_RTOL)
from ..tree import prune
from ..tree.branch import Branch, apply_substitution
from ..tree.context import Context
from ..tree.modular import evaluate
from ..tree.cover import children
from ..tree.reducible import special_points
from .null_vectors import left_null_vectors
from .readable import readable_equations
from ..numeric.functions import numpy_function

__all__ = ["finalize"]


def _equation_functions(ring, equations, tm):
    """Numeric functions of (q, params) for sympy equations (each divided by its largest
    coefficient, so that none overflows a float)."""
    syms = list(tm.variables) + list(ring.params)
    return numpy_function(syms, [normalised(e) for e in equations]), syms


@dataclass(frozen=True, eq=False)
class _Candidate:
    """A component being formed, with the branch it came from and that branch's points.

    ``branch`` is None for a component merged from two leaves (q = 0 and q = pi).
    """

    comp: Component
    branch: Branch | None
    points: tuple

    def replace(self, **changes) -> "_Candidate":
        return dataclasses.replace(self, comp=dataclasses.replace(self.comp, **changes))


def finalize(ctx: Context) -> list[Component]:
    """Components from the leaves: readable, deduplicated, none inside another."""
    ring = ctx.ring
    for node, data in ctx.tree.nodes(data=True):
        # a refined branch whose every factor was decided symbolically (a constant, or
        # parameters only) has no child: no real point for generic parameters
        if data.get("outcome") == Outcome.REFINED and ctx.tree.out_degree(node) == 0:
            data["outcome"] = Outcome.EMPTY
    raw = []
    for branch, node in ctx.leaves:
        pts = ctx.sampler.points(branch)
        if not pts:
            ctx.annotate(node, outcome=Outcome.NO_REAL_POINT)
            continue
        eqs = []
        for c in _without_excluded_factors(ctx, branch):
            e = ring.to_sympy(c)
            if e != 0 and e not in eqs and -e not in eqs:
                eqs.append(e)
        raw.append((eqs, branch, pts, node))
    if ctx.sampler.fell_back:
        k = len(ctx.sampler.fell_back)
        ctx.note(f"{k} {'branch has' if k == 1 else 'branches have'} real points for the "
                         "model's parameter values but none were found for random nearby values: "
                         "the components found there may exist only in a range of parameters")
    cands = [_component(ctx, eqs, branch, pts) for eqs, branch, pts, _ in raw]
    cands = [_with_exclusions(ctx, c) for c in cands]
    cands = _merge_zero_pi(cands)
    cands = _remove_contained(ctx, cands)
    comps = [_with_direction(ctx, c) for c in cands]
    comps.sort(key=lambda c: (len(c.parameter_conditions) > 0, -c.dimension, c.rank_drop,
                              [sp.sstr(e) for e in c.equations]))
    return comps


def _component(ctx: Context, eqs, branch, pts) -> _Candidate:
    ring, tm = ctx.ring, ctx.tm
    model_pts = ctx.model_sampler.points(branch) if ctx.model_sampler is not ctx.sampler else pts
    # the samplers solve for parameters that only parameter conditions constrain: the
    # component is the model's when those conditions hold at the model's own values
    at_model = [ctx.model_point()]
    for_model = bool(model_pts) and all(ctx.probe.vanishes(c, at_model)
                                        for c in branch.conditions if ctx.parameter_only(c))
    g = model_pts[0] if model_pts else pts[0]
    qv = ring.joint_values(g)
    pv = ring.parameter_values(g)
    joint = set(tm.variables)
    param_conds = tuple(e for e in eqs if not (e.free_symbols & joint))
    eqs_j = tuple(e for e in eqs if e.free_symbols & joint)
    used = set().union(*(e.free_symbols for e in eqs_j)) if eqs_j else set()
    free = tuple(v for v in tm.variables if v not in used)
    eqs_j, solved = readable_equations(eqs_j, tm.variables)
    eqs_j = tuple(eqs_j)
    used = set().union(*(e.free_symbols for e in eqs_j)) if eqs_j else set()
    free = tuple(v for v in tm.variables if v not in used)
    # dimension: joint variables minus the rank of the equations' gradient, exactly where
    # the branch has points modulo a prime, else numerically at the sample point
    dim = len(tm.variables)
    exact = ctx.modular.dimension(branch) if eqs_j else None
    if exact is not None:
        dim = exact
    if eqs_j and (exact is None or exact < len(tm.variables) - len(eqs_j)):
        # numerically at the sample point; also where the count modulo a prime is below the
        # number of the component's own equations, which counts conditions of the branch
        # that its equations no longer hold: where their gradients are independent at the
        # (real) sample point, the zero set of the equations is a manifold of dimension
        # N - k there, and that is the set reported (an 8-joint arm whose component at
        # q7 = pi came out one dimension short, and was then dropped as inside larger ones)
        numeric = _gradient_dimension(ring, eqs_j, tm, qv, pv)
        if exact is None or numeric == len(tm.variables) - len(eqs_j):
            dim = numeric
    # rank drop and lost directions at the sample point
    A = ctx.probe.values(ctx.M, g)
    n, m = A.shape
    U, s, Vt = np.linalg.svd(A)
    rank = ctx.probe.rank_at(ctx.M, g)
    drop = min(n, m) - rank
    if n <= m:
        dirs = tuple(tuple(float(x) for x in U[:, rank + i]) for i in range(drop))
    else:
        dirs = tuple(tuple(float(x) for x in Vt[rank + i, :]) for i in range(drop))
    sample = {str(v): float(qv[v]) for v in tm.variables}
    for p in ring.params:
        if any(p in e.free_symbols for e in param_conds):
            sample[str(p)] = float(pv[p])
    comp = Component(equations=eqs_j + param_conds,
                     solved=solved, free=free, dimension=dim, rank_drop=drop,
                     direction=(), direction_at_sample=dirs, sample=sample,
                     parameter_conditions=param_conds, for_model=for_model)
    return _Candidate(comp, branch, tuple(model_pts or pts))


def _gradient_dimension(ring, eqs_j, tm, qv, pv) -> int:
    """The local dimension of the zero set of ``eqs_j`` at the point (qv, pv), from the rank
    of their gradient by central differences."""
    f, _ = _equation_functions(ring, eqs_j, tm)
    x0 = np.array([qv[v] for v in tm.variables] + [pv[p] for p in ring.params], dtype=float)
    h = DIMENSION_STEP
    grads = []
    for j in range(len(tm.variables)):
        xp, xm = x0.copy(), x0.copy()
        xp[j] += h
        xm[j] -= h
        grads.append((np.array(f(*xp), dtype=float) - np.array(f(*xm), dtype=float)) / (2 * h))
    return dimension_from_gradient(np.array(grads).T)


def _without_excluded_factors(ctx: Context, branch) -> list:
    """The conditions of ``branch``, each with every factor the branch excludes divided out.

    A condition stored before a later substitution can become a product once angles are
    fixed: on a 9R snake, with q4 = pi, a condition became cos(q6/2) cos(q5/2) cos(q3/2 -
    q5/2) (up to a constant), where cos(q6/2) and cos(q5/2) are nonzero on the branch.  The
    branch lies on the remaining factor; the product also vanishes on the whole of
    {q6 = pi} and {q5 = pi}, where J is regular, and a component written with it is unsound
    there.  The factors are those of the conditions and of the exclusions with the branch's
    constant substitutions (angles at 0 or pi, variables at numbers) applied; a condition
    with no excluded factor is kept as it is.
    """
    if not branch.nonzero:
        return list(branch.conditions)
    ring = ctx.ring
    constant = [s for s in branch.substitutions if all(v.is_constant() for v in s.values)]

    def fixed(p):
        for s in constant:
            p = apply_substitution(p, s, ring)
        return None if p.is_zero() or ring.is_number(p) else p

    excluded = [f for p in branch.nonzero if (pf := fixed(p)) is not None for f in ctx.factors(pf)]
    out = []
    for c in branch.conditions:
        cf = fixed(c)
        factors = ctx.factors(cf) if cf is not None else []
        kept = [f for f in factors if not any(f == x for x in excluded)]
        out.append(functools.reduce(operator.mul, kept) if 0 < len(kept) < len(factors) else c)
    return out


def _with_exclusions(ctx: Context, cand: _Candidate) -> _Candidate:
    """Keep the excluded sets of a leaf that the equations alone would let in.

    A leaf below a null-vector level lives where the block determinant d of
    that level is nonzero.  Where the equations of the leaf and a factor g
    of d vanish together at points where J has full rank, the equations
    alone would describe too much: g != 0 becomes part of the component.
    Full rank is tested at the sample points of each part of {g = 0}, at
    its exact points with angles at multiples of pi/2 (a coordinate piece
    like cos q3 = 0, which the root finder's random starts can all miss),
    and, when all of those are singular, at points solved with residuals
    scaled by coefficients
    (:meth:`~rankloci.tree.sampler.BranchSampler.coefficient_scaled_points`).
    """
    branch = cand.branch
    keep = []
    for p in ctx.exceptional_exclusions.get(branch.key, ()):
        expr = ctx.ring.to_sympy(p)
        keep.append(-expr if expr.could_extract_minus_sign() else expr)
    if not branch.nonzero or prune.dense(ctx, branch):
        # dense: the whole zero set of the equations is singular (see tree.prune.dense)
        return cand.replace(excluding=tuple(keep)) if keep else cand
    full = ctx.full_rank
    closure = branch.closure()
    for e in branch.nonzero:
        for g in ctx.factors(closure.reduce(e, ctx.ring)):
            if ctx.parameter_only(g):
                continue
            for part in children(ctx, closure, g):
                pts = list(ctx.sampler.points(part)) + special_points(ctx, part)
                regular = any(ctx.probe.rank_at(ctx.M, x) == full for x in pts)
                if not regular:
                    # the sampler's residuals, scaled by the size of their terms, can miss a
                    # regular piece of {g = 0}: solved again, scaled by coefficients
                    regular = any(ctx.probe.rank_at(ctx.M, x) == full
                                  for x in ctx.sampler.coefficient_scaled_points(part))
                if regular:
                    expr = ctx.ring.to_sympy(g)
                    if expr.could_extract_minus_sign():
                        expr = -expr
                    if expr not in keep:
                        keep.append(expr)
                    break
    return cand.replace(excluding=tuple(keep)) if keep else cand


def _with_direction(ctx: Context, cand: _Candidate) -> Component:
    """The component, with its lost direction as expressions where they are small.

    Kept per leaf by ``ctx.symbolic_direction``: a computation resumed for the self-check's hints
    (:func:`~rankloci.methods.compute_locus`, ``grown``) finalises the same leaves again, and
    on a 9R snake the directions took half of each finalisation.
    """
    if cand.branch is None:
        return cand.comp
    key = (cand.branch.key, cand.comp.rank_drop)
    direction = ctx.symbolic_direction(
        key, lambda: _symbolic_direction(ctx, cand.branch, list(cand.points), cand.comp.rank_drop))
    return dataclasses.replace(cand.comp, direction=direction)


def _symbolic_direction(ctx, branch, pts, drop):
    """Null vectors of the whole matrix on the branch as expressions, if small."""
    if drop != 1:
        return ()
    try:
        M = ctx.substitute(ctx.M, branch, max_terms=MAX_DIRECTION_MATRIX_TERMS)
    except TermLimit:
        return ()
    if len(M) > len(M[0]):
        M = transpose(M)
    n = len(M)
    # the cofactors of any block regular on the branch give a null vector there: the block
    # is not searched for a determinant with few factors, which matters only for the tree's
    # sub-branches (on centauro's arm that search took 0.6 s, for directions then too large
    # to show)
    vecs, _ = left_null_vectors(ctx, M, n - 1, pts, max_terms=MAX_DIRECTION_COFACTOR_TERMS,
                                candidates=0)
    if not vecs:
        return ()
    u = vecs[0]
    if sum(len(p) for p in u) > MAX_DIRECTION_TERMS:
        return ()
    if all(p.is_zero() for p in u):
        return ()
    # each entry exactly (an equation's content may be cleared, a vector entry's may not),
    # then the content common to all entries divided out, so that the vector reads with
    # integer coefficients
    exprs = [ctx.ring.to_sympy(p, exact=True) if not p.is_zero() else sp.Integer(0) for p in u]
    contents = [e.as_content_primitive()[0] for e in exprs if e != 0]
    num = functools.reduce(sp.igcd, [c.p for c in contents])
    den = functools.reduce(sp.ilcm, [c.q for c in contents])
    return (tuple(sp.expand(e * den / num) for e in exprs),)


def _merge_zero_pi(cands: list[_Candidate]) -> list[_Candidate]:
    """Join q = 0 and q = pi into sin(q) = 0, and q = pi/2 and q = -pi/2 into cos(q) = 0.

    Only components that agree in everything else are joined.
    """
    pairs = {sp.Integer(0): (0, sp.sin), sp.pi: (0, sp.sin),
             sp.pi / 2: (1, sp.cos), -sp.pi / 2: (1, sp.cos)}
    texts = {}

    def text(cand):
        got = texts.get(cand)
        if got is None:
            c = cand.comp
            got = ([(e.free_symbols, sp.sstr(e)) for e in c.equations],
                   [(k, (str(k), tuple(map(str, v)))) for k, v in c.solved.items()],
                   (c.rank_drop, tuple(map(str, c.parameter_conditions)),
                    tuple(map(sp.sstr, c.excluding))))
            texts[cand] = got
        return got

    def key_without(cand, q):
        eqs, solved, other = text(cand)
        rest = tuple(sorted(t for free, t in eqs if q not in free))
        return (str(q), rest, tuple(sorted(t for k, t in solved if k != q))) + other

    changed = True
    while changed:
        changed = False
        groups = {}
        for i, cand in enumerate(cands):
            for q, vals in cand.comp.solved.items():
                if len(vals) == 1 and vals[0] in pairs:
                    which, _ = pairs[vals[0]]
                    groups.setdefault(key_without(cand, q) + (which,), {}).setdefault(vals[0], i)
        # join every pair found in this pass whose components are still unjoined
        used, merged_all = set(), []
        for key, by_value in groups.items():
            if len(by_value) != 2:
                continue
            (va, a), (vb, b) = sorted(by_value.items(), key=lambda kv: float(kv[0]))
            if a in used or b in used:
                continue
            used |= {a, b}
            A, B = cands[a].comp, cands[b].comp
            q = next(k for k in A.solved if str(k) == key[0])
            solved = dict(A.solved)
            solved[q] = (va, vb)
            func = pairs[va][1]
            merged = dataclasses.replace(
                A, equations=(func(q),) + tuple(e for e in A.equations if q not in e.free_symbols),
                solved=solved, for_model=A.for_model or B.for_model)
            merged_all.append(_Candidate(merged, None, cands[a].points + cands[b].points))
        if merged_all:
            cands = [c for i, c in enumerate(cands) if i not in used] + merged_all
            changed = True
    return cands


def _admitted(funcs, x, nvars: int, rng, *, solve: bool = True) -> bool:
    """Is ``x``, a point of the equations' zero set, in the component whose numeric functions
    are ``funcs``?

    It is where no exclusion vanishes (``CONTAINED_EXCLUSION_RTOL``).  A point
    where an exclusion vanishes too may still be in the closure of the
    component: it is, when points of the equations' zero set with the
    exclusions nonzero lie arbitrarily near (tested by projecting small
    perturbations back onto the equations); without ``solve``, such a point is not
    admitted.
    """
    _, g, gscale = funcs
    if g is not None and np.any(np.abs(np.array(g(*x), dtype=float))
                                <= CONTAINED_EXCLUSION_RTOL * gscale):
        return solve and _near_admitted(*funcs, x, nvars, rng)
    return True


def _near_admitted(f_rows, g, gscale, x, nvars, rng) -> bool:
    """Are there points of {f = 0} with g != 0 within NEAR_ADMITTED_RADIUS of ``x``?

    ``f_rows`` maps rows of configurations (variables, then parameters) to rows of
    equation values; the variables move, the parameters stay at their values in ``x``.
    """
    def rows(Y):
        return f_rows(np.concatenate([Y, np.broadcast_to(x[nvars:], (len(Y), len(x) - nvars))],
                                     axis=1))

    def admits(y):
        vals = np.abs(np.array(g(*np.concatenate([y, x[nvars:]])), dtype=float))
        return bool(np.all(vals > NEAR_ADMITTED_EXCLUSION_RTOL * gscale))

    return near_admitted(rows, lambda Y: np.max(np.abs(rows(Y)), axis=1) <= CONTAINED_RTOL,
                         admits, x[:nvars], rng)


def _coefficient_size(e):
    """Sum of the absolute values of the coefficients of ``e`` (1 for a zero sum), as a sympy
    number: it may be beyond the range of a float."""
    total = sp.Add(*[abs(t.as_coeff_Mul()[0]) for t in sp.Add.make_args(e)])
    return total if total != 0 else sp.Integer(1)


def _inside_exactly(ctx: Context, cand: _Candidate, others) -> bool:
    """Is every point of ``cand``'s branch modulo a prime on one of ``others``' branches?

    Exact where both branches are known and the other has no excluded set
    (a component's zero set is then its closure); False where undecided.
    Near-degenerate geometry makes the numeric test below undecidable: an
    equation of the larger component can stay 1e-6 of its coefficients' size
    on the smaller one although it vanishes there exactly.
    """
    if cand.branch is None:
        return False
    got = ctx.modular.points(cand.branch)
    if got is None:
        return False
    P, pts = got
    hosts = [k.branch for k in others if k.branch is not None and not k.branch.nonzero]
    return bool(hosts) and all(
        any(all(evaluate(c, g, P) == 0 for c in h.conditions) for h in hosts) for g in pts)


def _points_on(ctx: Context, xs, others, functions) -> bool:
    """Does each configuration of ``xs`` lie on one of the components ``others``?

    On one whose equations vanish there, or in the closure of one's branch by proof
    (:func:`.prune.on_leaf`, up to seconds a proof): the proofs come last, once every point
    that the equations alone place has been placed.
    """
    n = len(ctx.tm.variables)
    X = np.array(xs, dtype=float)
    vanish = {}

    def zero_set(k):
        # where the equations of k (scaled by their coefficient sizes) vanish
        # (CONTAINED_RTOL), at every point in one call; compiled only when first needed
        if k not in vanish:
            vanish[k] = (np.ones(len(X), dtype=bool) if not k.comp.equations else
                         ~np.any(np.abs(functions(k)[0](X)) > CONTAINED_RTOL, axis=1))
        return vanish[k]

    def placed(i, x):
        # on a component whose exclusions are all nonzero at x first: the test of a point
        # where an exclusion vanishes solves onto the equations nearby (on panda's finger
        # chain, 12% of the time went to such tests on points that another component held)
        on = [k for k in others if not k.comp.equations or zero_set(k)[i]]
        if any(not k.comp.equations or _admitted(functions(k), x, n, None, solve=False)
               for k in on):
            return True
        return any(_admitted(functions(k), x, n, ctx.rng) for k in on)

    rest = [x for i, x in enumerate(X) if not placed(i, x)]
    return all(any(k.branch is not None and prune.on_leaf(ctx, k.branch, x) for k in others)
               for x in rest)


def _remove_contained(ctx: Context, cands: list[_Candidate]) -> list[_Candidate]:
    """Drop duplicates and components contained in another one."""
    tm, ring = ctx.tm, ctx.ring
    syms = list(tm.variables) + list(ring.params)
    pvals = {p: float(tm.parameters[p]) for p in ring.params}

    def pts_of(cand):
        c = cand.comp
        x = [c.sample[str(v)] for v in tm.variables]
        x += [c.sample.get(str(p), pvals[p]) for p in ring.params]
        out = [np.array(x)]
        # the other sample points of the branch: one point may be special (on the
        # intersection with another component), independent points rarely all are
        for g in cand.points[1:]:
            qv, pv = ring.joint_values(g), ring.parameter_values(g)
            out.append(np.array([qv[v] for v in tm.variables] + [pv[p] for p in ring.params]))
        return out

    # more points per component: rotate the free variables
    def probe(cand):
        out = []
        for base in pts_of(cand):
            out.append(base)
            for k in range(1, 3):
                x = base.copy()
                for i, v in enumerate(tm.variables):
                    if v in cand.comp.free:
                        x[i] = ((base[i] + 1.3 * k + np.pi) % (2 * np.pi)) - np.pi
                out.append(x)
        return out

    compiled = {}

    def functions(k):
        if k not in compiled:
            c = k.comp
            # each equation over the size of its coefficients at the model's values, as an
            # exact (or high-exponent) number: the coefficients may be beyond a float's range
            # (a number divides each term of a sum: no second expansion is needed)
            scaled = [e / _coefficient_size(sp.expand(e.subs(pvals))) for e in c.equations]
            raw = numpy_function(syms, scaled)

            def f_rows(X, raw=raw):
                # one call for all rows: an equation's value is an array over the rows, or
                # a number where it does not depend on them
                return np.stack([np.broadcast_to(np.asarray(v, dtype=float), (len(X),))
                                 for v in raw(*X.T)], axis=1)

            excl = [e / _coefficient_size(sp.expand(e.subs(pvals))) for e in c.excluding]
            g = numpy_function(syms, excl) if excl else None
            gscale = np.ones(len(excl)) if excl else None
            compiled[k] = (f_rows, g, gscale)
        return compiled[k]

    keep = []
    order = sorted(range(len(cands)),
                   key=lambda i: (-cands[i].comp.dimension, len(cands[i].comp.equations)))
    for i in order:
        c = cands[i].comp
        # c is redundant when each of its points lies on some component kept so far (a
        # leaf may be reducible, its pieces inside different components)
        others = [k for k in keep
                  if not (k.comp.parameter_conditions and not c.parameter_conditions)]
        contained = bool(others) and (_inside_exactly(ctx, cands[i], others)
                                      or _points_on(ctx, probe(cands[i]), others, functions))
        if not contained:
            keep.append(cands[i])
    return keep
