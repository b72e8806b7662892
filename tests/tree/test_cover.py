"""How a branch is cut by a new condition: substitutions, re-reduced equations, split factors.

These are the algebraic steps below every locus method.  The expected branches are derived by
hand in each docstring, in the half-angle coordinates C = cos(q/2), S = sin(q/2) of
rankloci.algebra (sin q = 2*C*S, cos q = C**2 - S**2, C**2 + S**2 = 1).
"""

from __future__ import annotations

import numpy as np
import sympy as sp

from rankloci.tree.branch import Branch
from rankloci.io.toml_model import parse_model
from rankloci.jacobians import task_matrix
from rankloci.tree.context import Context
from rankloci.tree.cover import cover

RAW = 'variables = ["x", "y"]\nmatrix = [["sin(x)*cos(y) + sin(y)", "cos(x)"]]\n'


def _context():
    tm = task_matrix(parse_model(RAW, name="raw"), frame="auto")
    return Context(tm, method="svm", rng=np.random.default_rng(0))


def _angles(ctx, g):
    """(x, y) in (-pi, pi] of a generator vector."""
    return tuple(float(np.remainder(2 * np.arctan2(g[2 * i + 1], g[2 * i]) + np.pi, 2 * np.pi)
                       - np.pi) for i in range(ctx.ring.n_angles))


def test_implicit_equation_is_reduced_by_a_later_substitution():
    """E = sin x cos y + sin y is quadratic in both angle pairs, so {E = 0} is carried as an
    implicit equation.  Adding sin(y/2) = 0 (y = 0) substitutes y, and E becomes
    sin x = 2 C_x S_x, whose factors S_x (x = 0) and C_x (x = pi) are solvable.  The branch
    {E = 0, y = 0} must therefore come out as the two points (0, 0) and (pi, 0), each with both
    angles substituted and no implicit equation left for the root finder."""
    ctx = _context()
    x, y = ctx.tm.variables
    E = ctx.ring.from_sympy(sp.sin(x) * sp.cos(y) + sp.sin(y))
    (b,) = cover(ctx, Branch(), [E])
    assert b.implicit, "E should not be solvable for one angle"
    out = cover(ctx, b, [ctx.ring.S(1)])
    assert len(out) == 2, [[str(c) for c in o.conditions] for o in out]
    seen = set()
    for o in out:
        assert not o.implicit, [str(c) for c in o.implicit]
        assert {s.index for s in o.substitutions} == {0, 1}
        (g,) = ctx.sampler.points(o, count=1)
        qx, qy = _angles(ctx, g)
        assert abs(qy) <= 1e-12
        seen.add(round(abs(qx) / np.pi))
    assert seen == {0, 1}


def test_reduced_equation_that_becomes_constant_empties_the_branch():
    """E3 = sin x sin y + cos y + 3 is quadratic in both angle pairs, so it is implicit.  With
    y = 0 substituted it becomes 4, a nonzero constant: {E3 = 0, y = 0} is empty, and that is
    decided without any root finding."""
    ctx = _context()
    x, y = ctx.tm.variables
    E3 = ctx.ring.from_sympy(sp.sin(x) * sp.sin(y) + sp.cos(y) + 3)
    (b,) = cover(ctx, Branch(), [E3])
    assert b.implicit
    assert cover(ctx, b, [ctx.ring.S(1)]) == []


def test_exceptional_piece_never_carries_a_circle_factor():
    """f = a*C_x + b*S_x with a = C_y**2 + S_y**2 (which is 1 on the circle) and b = S_y.  The
    substitution (C_x, S_x) ~ (b, -a) misses the points where a = b = 0; a has no real zero, so
    that exceptional piece is empty, and no branch may carry the condition C_y**2 + S_y**2."""
    ctx = _context()
    C, S = ctx.ring.C, ctx.ring.S
    a = C(1) * C(1) + S(1) * S(1)
    f = a * C(0) + S(1) * S(0)
    out = cover(ctx, Branch(), [f])
    circle = str(a)
    for o in out:
        assert all(str(c) != circle for c in o.conditions), [str(c) for c in o.conditions]
    assert len(out) == 1


def test_distinct_keeps_the_first_of_equal_branches_across_calls():
    """Branches with the same conditions and exclusions are the same set: ``distinct`` keeps the
    first, in order, and with a shared ``seen`` also drops those taken by an earlier call."""
    from rankloci.tree.cover import distinct

    ctx = _context()
    Cx, Sx, Cy, Sy = ctx.ring.gens
    a, b, c = (Branch((Sx,), (), (Sx,)), Branch((Cy,), (), (Cy,)), Branch((Sx,), (), (Sx,)))
    assert distinct([a, b, c]) == [a, b]
    seen: set = set()
    assert distinct([b], seen) == [b]
    assert distinct([a, c, b], seen) == [a]


def test_a_minor_vanishing_on_its_branch_is_passed_over(monkeypatch):
    """On the branch {E = 0}, a minor with E among its factors splits nothing: it vanishes on
    the whole branch.  ``_nonvanishing_minor`` passes over its columns and takes the next
    block; when no other block is left the last one stands."""
    from rankloci.errors import LocusError
    from rankloci.methods import singular_vector

    ctx = _context()
    Cx, Sx, Cy, Sy = ctx.ring.gens
    E = Cx * Sy - Sx * Cy                      # sin((y - x)/2): irreducible
    branch = Branch((E,), (), (E,))
    offered = {(): ([0, 1], E * (Cx + 2 * Sy)), ((0, 1),): ([1, 2], Cx + 3 * Sy)}
    calls = []

    def choose(ctx, M, pts, *, candidates, branch, skip):
        calls.append([tuple(s) for s in skip])
        key = tuple(tuple(s) for s in skip)
        if key not in offered:
            raise LocusError("no regular square block found")
        return offered[key]

    monkeypatch.setattr(singular_vector, "choose_columns", choose)
    cols, D = singular_vector._nonvanishing_minor(ctx, None, branch, [])
    assert (cols, D) == ([1, 2], Cx + 3 * Sy) and calls == [[], [(0, 1)]]
    # only the vanishing minor on offer: it stands
    offered.pop(((0, 1),))
    cols, D = singular_vector._nonvanishing_minor(ctx, None, branch, [])
    assert (cols, D) == ([0, 1], E * (Cx + 2 * Sy))
