"""What every locus method shares: the ring, numeric probes, the tree, the result.

The methods only decide *which* polynomial conditions to branch on.  This
module turns the leaves of their branch trees into a :class:`Locus`:
readable equations, solved forms, dimensions, rank drops, lost directions,
duplicates and contained components removed.
"""

from __future__ import annotations

import itertools
import math

import networkx as nx
import numpy as np
import sympy as sp

from ..algebra import PolyRing, abs_poly, irreducible_factors, laplace_det
from ..branch import Branch, BranchSampler, apply_substitution
from ..errors import LocusError
from ..kinematics import trig_normal
from ..locus import Component
from ..tolerances import RANK_RTOL, ZERO_RTOL

__all__ = ["Context", "LocusTimeout", "finalize"]


class LocusTimeout(LocusError):
    """The computation was stopped because its time budget ran out."""


class Context:
    """State of one locus computation."""

    def __init__(self, tm, *, method, rng=None, progress=None, should_stop=None):
        self.tm = tm
        self.method = method
        angles = tuple(tm.angles)
        others = tuple(v for v in tm.variables if v not in angles)
        used = set().union(*(e.free_symbols for e in tm.matrix)) if len(tm.matrix) else set()
        params = tuple(sorted((p for p in tm.parameters if p in used), key=lambda s: s.name))
        unknown = used - set(tm.variables) - set(params)
        if unknown:
            raise LocusError(f"the matrix uses symbols that are neither variables nor parameters: "
                             f"{', '.join(sorted(map(str, unknown)))}")
        self.ring = PolyRing(angles, others, params)
        self.M = self.ring.from_sympy_rows(sp.Matrix(tm.matrix))
        self.shape = tm.matrix.shape
        self.rng = rng if rng is not None else np.random.default_rng(0)
        actual = {p: float(tm.parameters[p]) for p in params}
        # Zero tests in the tree use generic parameter values, so that a
        # polynomial is "zero" only when it is zero for all parameters; the
        # model's own values are used for the samples reported to the user.
        generic = {p: _generic_value(v, self.rng) for p, v in actual.items()}
        self.model_sampler = BranchSampler(self.ring, actual, self.rng) if params else None
        self.sampler = BranchSampler(self.ring, generic, self.rng, fallback=self.model_sampler)
        if self.model_sampler is None:
            self.model_sampler = self.sampler
        self.tree = nx.DiGraph()
        self.leaves: list[tuple[Branch, int]] = []
        self.notes: list[str] = []
        self._actual = actual
        self.progress = progress or (lambda msg: None)
        self.should_stop = should_stop or (lambda: False)
        self._compiled = {}
        self._vanish_cache = {}
        self._reduced = {}

    # --- bookkeeping --------------------------------------------------------

    def tick(self):
        if self.should_stop():
            raise LocusTimeout(
                f"the {self.method} computation did not finish within its time budget "
                f"({self.tree.number_of_nodes()} branches explored)")

    def add_node(self, parent, branch: Branch, **attrs) -> int:
        node = self.tree.number_of_nodes()
        cond = branch.conditions[-1] if branch.conditions else None
        label = sp.sstr(self.ring.to_sympy(cond)) if cond is not None else "(all configurations)"
        self.tree.add_node(node, condition=label, depth=len(branch.conditions), **attrs)
        if parent is not None:
            self.tree.add_edge(parent, node)
        return node

    def leaf(self, branch: Branch, node: int, outcome: str):
        """Record a terminal branch, if the whole matrix really loses rank on it.

        A branch of J-dagger where the chosen null vectors vanish is no
        component: J has full rank at its generic points, and those points
        are covered by the sub-branch on which the null vectors degenerate.
        """
        pts = self.sampler.points(branch)
        full = min(len(self.M), len(self.M[0]))
        if self.known(branch):
            self.tree.nodes[node]["outcome"] = "inside a component already found"
            return
        if pts and self.generic_rank(self.M, pts) == full:
            self.tree.nodes[node]["outcome"] = "null vectors vanish (covered by its own branch)"
            return
        self.tree.nodes[node]["outcome"] = outcome
        self.leaves.append((branch, node))
        self.progress(f"component found at branch {node} ({outcome}): "
                      f"{', '.join(sp.sstr(self.ring.to_sympy(c)) for c in branch.conditions)}")

    # --- numeric probes -----------------------------------------------------

    def numeric(self, M, g, *, scale=False) -> np.ndarray:
        """Values of the entries at ``g`` (or, with ``scale``, the size of their terms)."""
        flat = [p for row in M for p in row]
        key = (scale,) + tuple(id(p) for p in flat)
        got = self._compiled.get(key)
        # the cached entry keeps its polynomials alive, so their ids cannot be reused
        if got is None or any(a is not b for a, b in zip(got[0], flat)):
            polys = [abs_poly(p, self.ring) for p in flat] if scale else flat
            got = (flat, self.ring.compile(polys))
            if len(self._compiled) > 512:
                self._compiled.clear()
            self._compiled[key] = got
        x = np.abs(g) if scale else g
        return got[1](x).reshape(len(M), len(M[0]))

    def reduce_matrix(self, M, branch: Branch):
        """``M`` with the substitutions of ``branch`` applied (memoised by prefix).

        Sibling branches share their parent's substitutions, so each entry is
        reduced by the newest substitution only.
        """
        return self._reduced_by(M, branch.substitutions)

    def _reduced_by(self, M, subs):
        if not subs:
            return M
        key = (id(M),) + tuple(id(s) for s in subs)
        got = self._reduced.get(key)
        # the entry keeps M and the substitutions alive, so their ids cannot be reused
        if got is None or got[0] is not M or any(a is not b for a, b in zip(got[1], subs)):
            prev = self._reduced_by(M, subs[:-1])
            last = subs[-1]
            got = (M, subs, [[apply_substitution(p, last, self.ring) for p in row] for row in prev])
            if len(self._reduced) > 4096:
                self._reduced.clear()
            self._reduced[key] = got
        return got[2]

    def rank_at(self, M, g) -> int:
        """Numeric rank of ``M`` at ``g``; see :func:`numeric_rank`."""
        return numeric_rank(self.numeric(M, g), self.numeric(M, g, scale=True))

    def generic_rank(self, M, points) -> int:
        return max(self.rank_at(M, g) for g in points)

    def vanishes(self, p, points) -> bool:
        """Does ``p`` vanish at every point (relative to the size of its terms)?"""
        if p.is_zero():
            return True
        got = self._vanish_cache.get(id(p))
        # the cached entry keeps p alive, so its id cannot be reused
        if got is None or got[0] is not p:
            if len(self._vanish_cache) > 4096:
                self._vanish_cache.clear()
            got = (p, self.ring.compile([p]), self.ring.compile([abs_poly(p, self.ring)]))
            self._vanish_cache[id(p)] = got
        _, val, scale = got
        G = np.asarray(points, dtype=float)
        return bool(np.all(np.abs(val(G)[:, 0]) <= ZERO_RTOL * np.maximum(scale(np.abs(G))[:, 0], 1e-300)))

    def children(self, branch: Branch, f) -> list[Branch]:
        """Branches covering ``branch`` intersected with {f = 0}.

        A child whose equation has real points only where its gradient
        vanishes too (a sum of squares, say) is replaced by the branches
        of those critical points, which the sampler can reach.
        """
        out = []
        for child in self._cover(branch, [f]):
            if child.implicit and self._critical_only(child):
                self.progress(f"real points of {sp.sstr(self.ring.to_sympy(child.implicit[-1]))} "
                              "= 0 only where its gradient vanishes: adding the gradient")
                out.extend(self._critical_branches(child))
            else:
                out.append(child)
        return out

    def _critical_branches(self, child: Branch) -> list[Branch]:
        """``child`` and the gradient of its last equation, split on the gradient's factors."""
        branches = [child]
        for d in self.ring.gradient(child.implicit[-1]):
            nxt = []
            for b in branches:
                dr = b.reduce(d, self.ring)
                if dr.is_zero():
                    nxt.append(b)
                    continue
                for g in self.factors(dr):
                    nxt.extend(c for c in self._cover(b, [g]) if self.sampler.points(c))
            branches = nxt
        return branches

    def _critical_only(self, child: Branch) -> bool:
        """Are the real points of the child's last equation critical points of it?

        Either the sampler came close without converging (see
        BranchSampler.near_miss), or every sample point has a gradient that
        vanishes relative to the size of its terms (NEAR_MISS_RTOL): points
        of a genuine hypersurface have gradients of order one.
        """
        from ..tolerances import NEAR_MISS_RTOL

        pts = self.sampler.points(child)
        if not pts:
            return self.sampler.near_miss(child)
        grad = [d for d in self.ring.gradient(child.implicit[-1]) if not d.is_zero()]
        if not grad:
            return False
        val = self.ring.compile(grad)
        size = self.ring.compile([abs_poly(d, self.ring) for d in grad])
        G = np.asarray(pts, dtype=float)
        return bool(np.all(np.abs(val(G)) <= NEAR_MISS_RTOL * np.maximum(size(np.abs(G)), 1e-300)))

    def _cover(self, branch: Branch, conditions) -> list[Branch]:
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
        c = branch.reduce(conditions[0], self.ring)
        rest = list(conditions[1:])
        if c.is_zero():
            return self._cover(branch, rest)
        if c.is_constant():
            return []
        if c != conditions[0]:
            fs = self.factors(c)
            if len(fs) != 1 or fs[0] != c:
                return [b for f in fs for b in self._cover(branch, [f] + rest)]
        child, exceptional = branch.with_condition(c, self.ring)
        out = [b for settled in self._settle(branch, child) for b in self._cover(settled, rest)]
        for extra in exceptional:
            split = [[]]
            for e in extra:
                e = branch.reduce(e, self.ring)
                if e.is_zero():
                    continue
                split = [s + [f] for s in split for f in self.factors(e)]
            for conds in split:
                out += self._cover(branch, conds + rest)
        return out

    def _settle(self, parent: Branch, child: Branch) -> list[Branch]:
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
            return [child]
        ring = self.ring
        nonzero = []
        for e in child.nonzero:
            r = child.reduce(e, ring)
            if r.is_zero():
                return []
            if not r.is_constant():
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
            if r.is_constant():
                return []
            fs = []
            for f in self.factors(r):
                if self.parameter_only(f):
                    self.special_parameters(f, "an equation reduced on a branch")
                else:
                    fs.append(f)
            out = [b for o in out for f in fs for b in self._cover(o, [f])]
        return out

    def factors(self, p):
        return irreducible_factors(p, self.ring)

    def parameter_only(self, f) -> bool:
        """Does ``f`` involve parameters only (no joint variable)?"""
        joint = 2 * self.ring.n_angles + len(self.ring.others)
        return all(i >= joint for i in self.ring.variable_indices(f))

    def special_parameters(self, f, where: str):
        """Note a parameter-only factor that is not analysed further."""
        text = sp.sstr(self.ring.to_sympy(f))
        vals = np.array([0.0] * len(self.ring.names))
        base = 2 * self.ring.n_angles + len(self.ring.others)
        for j, p in enumerate(self.ring.params):
            vals[base + j] = self._actual[p]
        if any(n.startswith((f"the model's parameter values satisfy {text} = 0",
                             f"for parameters with {text} = 0")) for n in self.notes):
            return
        if self.vanishes(f, [vals]):
            note = (f"the model's parameter values satisfy {text} = 0, a special case of the "
                    f"symbolic analysis ({where}); rerun with --numeric-parameters")
        else:
            note = f"for parameters with {text} = 0 the analysis differs ({where}); not pursued"
        if note not in self.notes:
            self.notes.append(note)

    def open_branch(self, branch: Branch, node: int):
        """Sample points of ``branch``, or None after marking ``node`` empty or known."""
        self.tick()
        if self._known_symbolically(branch):
            self.tree.nodes[node]["outcome"] = "inside a component already found"
            return None
        pts = self.sampler.points(branch)
        if not pts:
            self.tree.nodes[node]["outcome"] = "empty"
            return None
        if self.known(branch):
            self.tree.nodes[node]["outcome"] = "inside a component already found"
            return None
        return pts

    def _known_symbolically(self, branch: Branch) -> bool:
        """Does ``branch`` carry every condition of a component found (without exclusions)?

        Then the numeric test below would find all of its points on that
        component; this decides it without sampling the branch.
        """
        if not self.leaves or not branch.conditions:
            return False
        have = set(branch.key[0])
        for leaf, _ in self.leaves:
            if leaf is branch or not leaf.conditions or not self._dense(leaf):
                continue
            if len(leaf.conditions) <= len(branch.conditions) and \
                    all(c in have for c in leaf.key[0]):
                return True
        return False

    def known(self, branch: Branch) -> bool:
        """Is every sample point of ``branch`` on a component already found?"""
        if not self.leaves:
            return False
        if self._known_symbolically(branch):
            return True
        pts = self.sampler.points(branch)
        if not pts:
            return False
        for leaf, _ in self.leaves:
            if leaf is branch or not leaf.conditions:
                continue
            if len(leaf.conditions) > len(branch.conditions):
                continue
            if all(self.vanishes(c, pts) for c in leaf.conditions) and (
                    self._dense(leaf)
                    or not any(self.vanishes(e, [g]) for e in leaf.nonzero for g in pts)):
                return True
        return False

    def _dense(self, leaf: Branch) -> bool:
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
        return bool(self.sampler.points(leaf))

    def choose_columns(self, M, points, candidates: int = 12):
        """n columns whose square block is regular at the points, and its determinant.

        Among up to ``candidates`` regular blocks (smallest entries first) the
        one with the fewest determinant terms wins: its factors, and so the
        branches below it, are the simplest.
        """
        n, m = len(M), len(M[0])
        size = [sum(len(M[i][j]) for i in range(n)) for j in range(m)]
        combos = itertools.combinations(range(m), n)
        if math.comb(m, n) > 5000:
            combos = itertools.islice(combos, 5000)
        ranked = sorted(combos, key=lambda cs: sum(size[c] for c in cs))
        best = None
        tried = 0
        # a block is regular on the branch if it is regular at one of its points
        # where the whole matrix has full rank (a sample point may happen to lie
        # on a smaller subset where more is singular)
        evaluated = [(self.numeric(M, g), self.numeric(M, g, scale=True)) for g in points]
        evaluated = [(A, S) for A, S in evaluated if numeric_rank(A, S) == n]
        for cols in ranked:
            cl = list(cols)
            if not any(numeric_rank(A[:, cl], S[:, cl]) == n for A, S in evaluated):
                continue
            sub = [[row[c] for c in cols] for row in M]
            self.tick()
            D = laplace_det(sub)
            if best is None or len(D) < len(best[1]):
                best = (list(cols), D)
            tried += 1
            if tried >= candidates:
                break
        if best is None:
            raise LocusError("no regular square block found although the matrix has full rank")
        return best

    def choose_block(self, A, r, points, candidates: int = 24):
        """Rows and columns of an r x r block of ``A`` regular at the points.

        The null vectors built from the block's cofactors are independent
        wherever its determinant d is nonzero, and the points where d
        vanishes need sub-branches of their own, one per factor of d.
        Pivoted QR at the first point proposes a block; a regular block
        (among up to ``candidates``, smallest entries first) whose d has
        fewer factors in the joint variables, and no more terms, replaces it.
        """
        n, m = len(A), len(A[0])
        N = self.numeric(A, points[0])
        norms = np.linalg.norm(N, axis=1)
        N = N / np.where(norms > 0, norms, 1.0)[:, None]
        cols = sorted(_pivots(N, r))
        rows = sorted(_pivots(N[:, cols].T, r))
        if r == 0 or math.comb(n, r) * math.comb(m, r) > 400:
            return rows, cols

        def score(rl, cl, most=None):
            d = laplace_det([[A[i][j] for j in cl] for i in rl])
            if most is not None and len(d) > most:
                return None
            if d.is_constant() or self.parameter_only(d):
                return 0, len(d)
            return len([f for f in self.factors(d) if not self.parameter_only(f)]), len(d)

        best = (score(rows, cols), rows, cols)
        if best[0][0] == 0:
            return rows, cols
        evaluated = [(self.numeric(A, g), self.numeric(A, g, scale=True)) for g in points]
        evaluated = [(E, S) for E, S in evaluated if numeric_rank(E, S) == r]
        size = [[len(p) for p in row] for row in A]
        blocks = sorted(((rs, cs) for rs in itertools.combinations(range(n), r)
                         for cs in itertools.combinations(range(m), r)),
                        key=lambda rc: sum(size[i][j] for i in rc[0] for j in rc[1]))
        tried = 0
        for rs, cs in blocks:
            if tried >= candidates or not evaluated:
                break
            rl, cl = list(rs), list(cs)
            if (rl, cl) == (rows, cols) or not any(
                    numeric_rank(E[np.ix_(rl, cl)], S[np.ix_(rl, cl)]) == r for E, S in evaluated):
                continue
            tried += 1
            self.tick()
            sc = score(rl, cl, most=best[0][1])
            if sc is not None and sc[0] < best[0][0]:
                best = (sc, rl, cl)
                if sc[0] == 0:
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


def numeric_rank(A, sizes) -> int:
    """Rank of the evaluated matrix ``A`` whose entries have term sizes ``sizes``.

    Rows are scaled to unit norm first (row scaling keeps the rank and
    removes the arbitrary powers of C**2 + S**2); a row whose entries all
    vanish relative to the size of their terms (ZERO_RTOL) is a zero row.
    """
    norms = np.linalg.norm(A, axis=1)
    nz = norms > ZERO_RTOL * np.linalg.norm(sizes, axis=1)
    if not np.any(nz):
        return 0
    B = A[nz] / norms[nz, None]
    s = np.linalg.svd(B, compute_uv=False)
    return int(np.sum(s > RANK_RTOL * s[0]))


def _generic_value(value: float, rng) -> float:
    """A random value near ``value`` that satisfies no special relation."""
    scale = abs(value) if value else 1.0
    return float(np.sign(value or 1.0) * scale * rng.uniform(0.6, 1.4))


def transpose(M):
    return [list(col) for col in zip(*M)]


def left_null_vectors(ctx: Context, A, rank, points):
    """Left null vectors of ``A`` (n x n, rank ``rank`` on the branch), fraction free.

    Returns the vectors and the polynomial ``d`` (the determinant of the
    regular block used): the vectors are independent wherever d != 0.
    """
    n = len(A)
    rows, cols = ctx.choose_block(A, rank, points)
    block = [[A[i][j] for j in cols] for i in rows]
    d = laplace_det(block) if rank else ctx.ring.ctx.constant(1)
    vectors = []
    zero = ctx.ring.ctx.constant(0)
    for i in range(n):
        if i in rows:
            continue
        order = rows + [i]
        u = [zero] * n
        for t, r in enumerate(order):
            rest = [order[s] for s in range(len(order)) if s != t]
            if rest:
                minor = laplace_det([[A[x][j] for j in cols] for x in rest])
            else:
                minor = ctx.ring.ctx.constant(1)
            u[r] = minor if t % 2 == 0 else -minor
        vectors.append(u)
    return vectors, d


# --- from leaves to components ---------------------------------------------

def _q_values(ring: PolyRing, g) -> dict:
    out = {}
    for i, q in enumerate(ring.angles):
        v = 2.0 * math.atan2(g[2 * i + 1], g[2 * i])
        out[q] = math.remainder(v, 2 * math.pi)
    for j, x in enumerate(ring.others):
        out[x] = g[2 * ring.n_angles + j]
    return out


def _param_values(ring: PolyRing, g) -> dict:
    base = 2 * ring.n_angles + len(ring.others)
    return {p: g[base + j] for j, p in enumerate(ring.params)}


def _solved_value(e, q):
    """Values of q on {e = 0} when e depends on q alone and is a half-angle line."""
    if e.free_symbols != {q}:
        return None
    C, S = sp.Dummy("C"), sp.Dummy("S")
    h = e.subs({sp.cos(q / 2): C, sp.sin(q / 2): S})
    if h.has(q):
        # full angles: sin(q), cos(q) in the equation
        h2 = sp.expand(e.subs({sp.cos(q): C ** 2 - S ** 2, sp.sin(q): 2 * C * S}))
        if h2.has(q):
            return None
        h = h2
    try:
        poly = sp.Poly(h, C, S)
    except sp.PolynomialError:
        return None
    if not poly.is_homogeneous:
        return None
    vals = []
    d = poly.total_degree()
    ht = sp.Poly(h.subs(C, 1), S)
    if ht.degree() < d:
        vals.append(sp.pi)            # C = 0 is a root: q = pi
    if ht.degree() > 0:
        try:
            found = sp.roots(ht, filter="R")
        except (sp.PolynomialError, NotImplementedError):
            return None
        real_count = sum(1 for r in sp.Poly(ht, S).nroots() if abs(sp.im(r)) < 1e-12)
        if sum(found.values()) < real_count:
            return None
        for t in found:
            v = 2 * sp.atan(t)
            if v.has(sp.atan) and len(sp.sstr(v)) > 40:
                return None
            vals.append(v)
    return tuple(sorted(set(vals), key=lambda x: float(x))) if vals else None


def _readable_equations(eqs, variables):
    """Substitute each solved variable into the other equations; return eqs and solved."""
    solved = {}
    eqs = list(eqs)
    changed = True
    while changed:
        changed = False
        for i, e in enumerate(eqs):
            for q in variables:
                if q in solved:
                    continue
                vals = _solved_value(e, q)
                if vals is None or len(vals) != 1:
                    continue
                solved[q] = vals
                rest = []
                for j, f in enumerate(eqs):
                    if j == i:
                        continue
                    g = trig_normal(f.subs(q, vals[0]))
                    if g != 0:
                        rest.append(g)
                eqs = [e] + rest
                changed = True
                break
            if changed:
                break
    out = []
    for e in eqs:
        if e.is_number:
            continue
        if e.could_extract_minus_sign():
            e = -e
        if e not in out:
            out.append(e)
    for q in variables:
        if q not in solved:
            for e in out:
                vals = _solved_value(e, q)
                if vals:
                    solved[q] = vals
    return out, solved


def _equation_functions(ring, equations, tm):
    """Numeric functions of (q, params) for sympy equations."""
    syms = list(tm.variables) + list(ring.params)
    return sp.lambdify(syms, list(equations), modules="numpy"), syms


def finalize(ctx: Context) -> list[Component]:
    """Components from the leaves: readable, deduplicated, none inside another."""
    ring = ctx.ring
    for node, data in ctx.tree.nodes(data=True):
        # a refined branch whose every factor was decided symbolically (a constant, or
        # parameters only) has no child: no real point for generic parameters
        if data.get("outcome") == "refined" and ctx.tree.out_degree(node) == 0:
            data["outcome"] = "empty"
    raw = []
    for branch, node in ctx.leaves:
        pts = ctx.sampler.points(branch)
        if not pts:
            ctx.tree.nodes[node]["outcome"] += " (no real point)"
            continue
        eqs = []
        for c in branch.conditions:
            e = ring.to_sympy(c)
            if e != 0 and e not in eqs and -e not in eqs:
                eqs.append(e)
        raw.append((eqs, branch, pts, node))
    if ctx.sampler.fell_back:
        ctx.notes.append(f"{len(ctx.sampler.fell_back)} branch(es) have real points for the "
                         "model's parameter values but none were found for random nearby values: "
                         "the components found there may exist only in a range of parameters")
    comps = [_component(ctx, eqs, branch, pts) for eqs, branch, pts, _ in raw]
    comps = [_with_exclusions(ctx, c) for c in comps]
    comps = _merge_zero_pi(comps)
    comps = _remove_contained(ctx, comps)
    comps = [_with_direction(ctx, c) for c in comps]
    comps.sort(key=lambda c: (len(c.parameter_conditions) > 0, -c.dimension, c.rank_drop,
                              [sp.sstr(e) for e in c.equations]))
    return comps


def _component(ctx: Context, eqs, branch, pts) -> Component:
    ring, tm = ctx.ring, ctx.tm
    model_pts = ctx.model_sampler.points(branch) if ctx.model_sampler is not ctx.sampler else pts
    for_model = bool(model_pts)
    g = model_pts[0] if model_pts else pts[0]
    qv = _q_values(ring, g)
    pv = _param_values(ring, g)
    joint = set(tm.variables)
    param_conds = tuple(e for e in eqs if not (e.free_symbols & joint))
    eqs_j = tuple(e for e in eqs if e.free_symbols & joint)
    used = set().union(*(e.free_symbols for e in eqs_j)) if eqs_j else set()
    free = tuple(v for v in tm.variables if v not in used)
    eqs_j, solved = _readable_equations(eqs_j, tm.variables)
    eqs_j = tuple(eqs_j)
    used = set().union(*(e.free_symbols for e in eqs_j)) if eqs_j else set()
    free = tuple(v for v in tm.variables if v not in used)
    # dimension: joint variables minus the rank of the equations' gradient
    dim = len(tm.variables)
    if eqs_j:
        f, syms = _equation_functions(ring, eqs_j, tm)
        x0 = np.array([qv[v] for v in tm.variables] + [pv[p] for p in ring.params], dtype=float)
        h = 1e-6
        grads = []
        for j in range(len(tm.variables)):
            xp, xm = x0.copy(), x0.copy()
            xp[j] += h
            xm[j] -= h
            grads.append((np.array(f(*xp), dtype=float) - np.array(f(*xm), dtype=float)) / (2 * h))
        G = np.array(grads).T
        # equations differ in scale by orders of magnitude: compare directions
        norms = np.linalg.norm(G, axis=1)
        G = G[norms > 0] / norms[norms > 0, None]
        s = np.linalg.svd(G, compute_uv=False) if len(G) else np.zeros(1)
        dim = len(tm.variables) - int(np.sum(s > 1e-7 * max(s[0], 1e-300)))
    # rank drop and lost directions at the sample point
    A = ctx.numeric(ctx.M, g)
    n, m = A.shape
    U, s, Vt = np.linalg.svd(A)
    rank = ctx.rank_at(ctx.M, g)
    drop = min(n, m) - rank
    if n <= m:
        dirs = tuple(tuple(float(x) for x in U[:, rank + i]) for i in range(drop))
    else:
        dirs = tuple(tuple(float(x) for x in Vt[rank + i, :]) for i in range(drop))
    sample = {str(v): float(qv[v]) for v in tm.variables}
    for p in ring.params:
        if any(p in e.free_symbols for e in param_conds):
            sample[str(p)] = float(pv[p])
    return Component(equations=eqs_j + param_conds,
                     solved=solved, free=free, dimension=dim, rank_drop=drop,
                     direction=(), direction_at_sample=dirs, sample=sample,
                     parameter_conditions=param_conds, for_model=for_model,
                     _branch=(branch, model_pts or pts))


def _with_exclusions(ctx, c: Component) -> Component:
    """Keep the excluded sets of a leaf that the equations alone would let in.

    A leaf below a null-vector level lives where the block determinant d of
    that level is nonzero.  Where the equations of the leaf and a factor g
    of d vanish together at points where J has full rank, the equations
    alone would describe too much: g != 0 becomes part of the component.
    """
    import dataclasses

    branch, _ = c._branch
    if not branch.nonzero or ctx._dense(branch):
        # dense: the whole zero set of the equations is singular (see Context._dense)
        return c
    full = min(len(ctx.M), len(ctx.M[0]))
    closure = branch.closure()
    keep = []
    for e in branch.nonzero:
        for g in ctx.factors(closure.reduce(e, ctx.ring)):
            if ctx.parameter_only(g):
                continue
            for part in ctx.children(closure, g):
                pts = ctx.sampler.points(part)
                if any(ctx.rank_at(ctx.M, x) == full for x in pts):
                    expr = ctx.ring.to_sympy(g)
                    if expr.could_extract_minus_sign():
                        expr = -expr
                    if expr not in keep:
                        keep.append(expr)
                    break
    return dataclasses.replace(c, excluding=tuple(keep)) if keep else c


MAX_DIRECTION_TERMS = 400


def _with_direction(ctx, c: Component) -> Component:
    import dataclasses

    if c._branch is None or c._branch[0] is None:
        return c
    branch, pts = c._branch
    return dataclasses.replace(c, direction=_symbolic_direction(ctx, branch, pts, c.rank_drop))


def _symbolic_direction(ctx, branch, pts, drop):
    """Null vectors of the whole matrix on the branch as expressions, if small."""
    if drop != 1:
        return ()
    M = ctx.reduce_matrix(ctx.M, branch)
    if len(M) > len(M[0]):
        M = transpose(M)
    n = len(M)
    vecs, _ = left_null_vectors(ctx, M, n - 1, pts)
    if not vecs:
        return ()
    u = vecs[0]
    if sum(len(p) for p in u) > MAX_DIRECTION_TERMS:
        return ()
    nonzero = [p for p in u if not p.is_zero()]
    if not nonzero:
        return ()
    from functools import reduce
    common = reduce(lambda a, b: a.gcd(b), nonzero)
    if not common.is_constant():
        u = [p / common if not p.is_zero() else p for p in u]
    return (tuple(ctx.ring.to_sympy(p) if not p.is_zero() else sp.Integer(0) for p in u),)


def _branch_points(c: Component) -> list:
    return list(c._branch[1]) if c._branch is not None else []


def _merge_zero_pi(comps: list[Component]) -> list[Component]:
    """Join q = 0 and q = pi into sin(q) = 0, and q = pi/2 and q = -pi/2 into cos(q) = 0.

    Only components that agree in everything else are joined.
    """
    pairs = {sp.Integer(0): (0, sp.sin), sp.pi: (0, sp.sin),
             sp.pi / 2: (1, sp.cos), -sp.pi / 2: (1, sp.cos)}
    texts = {}

    def text(c):
        # keyed by id, holding the component: a merged component may reuse a freed id
        got = texts.get(id(c))
        if got is None or got[0] is not c:
            got = (c, [(e.free_symbols, sp.sstr(e)) for e in c.equations],
                   [(k, (str(k), tuple(map(str, v)))) for k, v in c.solved.items()],
                   (c.rank_drop, tuple(map(str, c.parameter_conditions)),
                    tuple(map(sp.sstr, c.excluding))))
            texts[id(c)] = got
        return got[1:]

    def key_without(c, q):
        eqs, solved, other = text(c)
        rest = tuple(sorted(t for free, t in eqs if q not in free))
        return (str(q), rest, tuple(sorted(t for k, t in solved if k != q))) + other

    changed = True
    while changed:
        changed = False
        groups = {}
        for i, c in enumerate(comps):
            for q, vals in c.solved.items():
                if len(vals) == 1 and vals[0] in pairs:
                    which, _ = pairs[vals[0]]
                    groups.setdefault(key_without(c, q) + (which,), {}).setdefault(vals[0], i)
        # join every pair found in this pass whose components are still unjoined
        used, merged_all = set(), []
        for key, by_value in groups.items():
            if len(by_value) != 2:
                continue
            (va, a), (vb, b) = sorted(by_value.items(), key=lambda kv: float(kv[0]))
            if a in used or b in used:
                continue
            used |= {a, b}
            A, B = comps[a], comps[b]
            q = next(k for k in A.solved if str(k) == key[0])
            solved = dict(A.solved)
            solved[q] = (va, vb)
            func = pairs[va][1]
            merged_all.append(Component(
                equations=(func(q),) + tuple(e for e in A.equations if q not in e.free_symbols),
                solved=solved, free=A.free, dimension=A.dimension, rank_drop=A.rank_drop,
                direction=A.direction, direction_at_sample=A.direction_at_sample,
                sample=A.sample, parameter_conditions=A.parameter_conditions,
                for_model=A.for_model or B.for_model, excluding=A.excluding,
                _branch=(None, _branch_points(A) + _branch_points(B))))
        if merged_all:
            comps = [c for i, c in enumerate(comps) if i not in used] + merged_all
            changed = True
    return comps


def _vanish_at(funcs, points, nvars: int) -> bool:
    """Is every point in the component whose numeric functions are ``funcs``?

    The equations must vanish at each point.  A point where an exclusion
    vanishes too may still be in the closure of the component: it is, when
    points of the equations' zero set with the exclusions nonzero lie
    arbitrarily near (tested by projecting small perturbations back onto the
    equations).
    """
    f, g, gscale = funcs
    for x in points:
        if np.any(np.abs(np.array(f(*x), dtype=float)) > 1e-7):
            return False
        if g is not None and np.any(np.abs(np.array(g(*x), dtype=float)) <= 1e-7 * gscale):
            if not _near_admitted(f, g, gscale, x, nvars):
                return False
    return True


def _near_admitted(f, g, gscale, x, nvars, tries: int = 6) -> bool:
    from ..branch import gauss_newton

    rng = np.random.default_rng(0)

    def rows(Y):
        return np.array([np.array(f(*np.concatenate([y, x[nvars:]])), dtype=float).ravel()
                         for y in Y])

    for _ in range(tries):
        y0 = x[:nvars] + 1e-3 * rng.standard_normal(nvars)
        y = gauss_newton(rows, y0)
        if y is None or np.max(np.abs(rows(y[None, :])[0])) > 1e-7 or np.max(np.abs(y - x[:nvars])) > 0.05:
            continue
        vals = np.abs(np.array(g(*np.concatenate([y, x[nvars:]])), dtype=float))
        if np.all(vals > 1e-6 * gscale):
            return True
    return False


def _remove_contained(ctx: Context, comps: list[Component]) -> list[Component]:
    """Drop duplicates and components contained in another one."""
    tm, ring = ctx.tm, ctx.ring
    syms = list(tm.variables) + list(ring.params)
    pvals = {p: float(tm.parameters[p]) for p in ring.params}

    def pts_of(c):
        x = [c.sample[str(v)] for v in tm.variables]
        x += [c.sample.get(str(p), pvals[p]) for p in ring.params]
        out = [np.array(x)]
        # the other sample points of the branch: one point may be special (on the
        # intersection with another component), independent points rarely all are
        for g in (c._branch[1] if c._branch is not None else ())[1:]:
            qv, pv = _q_values(ring, g), _param_values(ring, g)
            out.append(np.array([qv[v] for v in tm.variables] + [pv[p] for p in ring.params]))
        return out

    # more points per component: rotate the free variables
    def probe(c):
        out = []
        for base in pts_of(c):
            out.append(base)
            for k in range(1, 3):
                x = base.copy()
                for i, v in enumerate(tm.variables):
                    if v in c.free:
                        x[i] = ((base[i] + 1.3 * k + np.pi) % (2 * np.pi)) - np.pi
                out.append(x)
        return out

    compiled = {}

    def functions(k):
        if id(k) not in compiled:
            f = sp.lambdify(syms, list(k.equations), modules="numpy")
            g = sp.lambdify(syms, list(k.excluding), modules="numpy") if k.excluding else None
            excl = [sp.expand(e.subs(pvals)) for e in k.excluding]
            gscale = np.array([sum(abs(float(t.as_coeff_Mul()[0])) for t in sp.Add.make_args(e))
                               for e in excl]) if excl else None
            compiled[id(k)] = (f, g, gscale)
        return compiled[id(k)]

    keep = []
    order = sorted(range(len(comps)), key=lambda i: (-comps[i].dimension, len(comps[i].equations)))
    for i in order:
        c = comps[i]
        # c is redundant when each of its points lies on some component kept so far (a
        # leaf may be reducible, its pieces inside different components)
        others = [k for k in keep if not (k.parameter_conditions and not c.parameter_conditions)]
        contained = bool(others) and all(
            any(_vanish_at(functions(k), [x], len(tm.variables)) if k.equations else True
                for k in others)
            for x in probe(c))
        if not contained:
            keep.append(c)
    return keep
