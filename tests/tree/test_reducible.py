"""Leaves whose equations hold on a singular piece and on a regular one.

The 1 x 2 matrix [sin x, sin y + sin x cos z] loses rank exactly where sin x = sin y = 0 (z
free).  The equations E1 = sin x - sin y sin z, E2 = sin y cos z hold on that curve family and
also on {cos z = 0, sin x = +-sin y}, where the matrix is regular at generic points: both pieces
have dimension 1.  A leaf with these equations must not become a component as it stands.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from rankloci.io.toml_model import parse_model
from rankloci.jacobians import task_matrix
from rankloci.loci import Outcome
from rankloci.tree import reducible
from rankloci.tree.branch import Branch
from rankloci.tree.context import Context
from rankloci.tree.cover import cover

RAW = 'variables = ["x", "y", "z"]\nmatrix = [["sin(x)", "sin(y) + sin(x)*cos(z)"]]\n'


def _reducible_leaf():
    tm = task_matrix(parse_model(RAW, name="raw"), frame="auto")
    ctx = Context(tm, method="svm", rng=np.random.default_rng(0))
    x, y, z = tm.variables
    E1 = ctx.ring.from_sympy(sp.sin(x) - sp.sin(y) * sp.sin(z))
    E2 = ctx.ring.from_sympy(sp.sin(y) * sp.cos(z))
    (branch,) = cover(ctx, Branch(), [E1, E2])
    return ctx, branch


def _recorded(ctx, branch):
    """``branch`` recorded as a leaf of the tree, as the tree records its components."""
    node = ctx.add_node(None, branch)
    ctx.annotate(node, outcome=Outcome.ALL_MINORS_VANISH)
    ctx.leaves.append((branch, node))
    return node


def _split_into_singular_leaves(ctx, branch, node):
    """Was ``branch`` (at ``node``) split, and is the matrix singular on every leaf now?"""
    assert ctx.tree.nodes[node]["outcome"] == Outcome.REFINED
    assert ctx.leaves and all(leaf is not branch for leaf, _ in ctx.leaves)
    for leaf, _ in ctx.leaves:
        pts = ctx.sampler.points(leaf, count=reducible.LEAF_POINTS)
        assert pts and all(ctx.probe.rank_at(ctx.M, g) == 0 for g in pts)


def _angles(ctx, g):
    return [float(2 * np.arctan2(g[2 * i + 1], g[2 * i])) for i in range(ctx.ring.n_angles)]


def test_both_pieces_are_seen_among_the_leaf_points():
    ctx, branch = _reducible_leaf()
    regular, singular, _ = reducible.ranked_points(ctx, branch)
    assert regular and singular
    for g in regular:
        x, y, z = _angles(ctx, g)
        assert abs(np.cos(z)) < 1e-8
        assert abs(abs(np.sin(x)) - abs(np.sin(y))) < 1e-8
    for g in singular:
        x, y, _ = _angles(ctx, g)
        assert abs(np.sin(x)) < 1e-8 and abs(np.sin(y)) < 1e-8


def test_special_starts_reach_the_coordinate_piece():
    """cos z = 0 fixes z at +-pi/2: starts with angles at multiples of pi/2 land on it exactly."""
    ctx, branch = _reducible_leaf()
    pts = reducible.special_points(ctx, branch)
    assert any(abs(np.cos(_angles(ctx, g)[2])) < 1e-12 for g in pts)


def test_reducible_leaf_is_split_into_singular_leaves_only():
    """The leaf's first sample points all on the singular piece (as on PR2's arm, where the
    regular piece attracts few random solves): the wider sample finds the regular one."""
    ctx, branch = _reducible_leaf()
    _, singular, _ = reducible.ranked_points(ctx, branch)
    ctx.sampler.cache[branch.key + (3,)] = singular[:3]
    node = ctx.add_node(None, branch)
    ctx.leaf(branch, node, Outcome.ALL_MINORS_VANISH)
    _split_into_singular_leaves(ctx, branch, node)
    # complete: points of the singular piece, z anywhere, lie on a recorded leaf
    rng = np.random.default_rng(1)
    for _ in range(20):
        # half-angle generators, exact at 0 (1, 0) and pi (0, 1)
        z = rng.uniform(-3, 3)
        g = np.array([*[(1.0, 0.0), (0.0, 1.0)][rng.integers(2)],
                      *[(1.0, 0.0), (0.0, 1.0)][rng.integers(2)], np.cos(z / 2), np.sin(z / 2)])
        assert any(all(ctx.probe.vanishes(c, [g]) for c in leaf.conditions)
                   for leaf, _ in ctx.leaves), g


def test_special_solves_reach_a_piece_cut_out_at_held_angles():
    """E1 = sin x cos z + sin y sin w, E2 = sin x sin w + sin y cos z, E3 = 2 sin x - sin y hold
    on sin x = sin y = 0 (z, w free: where [sin x, sin y (2 + cos z cos w)] loses rank) and on
    {cos z = 0, sin w = 0, sin y = 2 sin x}, a regular curve.  No start with angles at multiples
    of pi/2 is a point of that curve with sin x != 0 (sin x = sin y / 2 is no such multiple),
    but E1 and E2 vanish wherever z and w are held at such values: the special solves hold
    them, solve E3, and land on it."""
    RAW4 = ('variables = ["x", "y", "z", "w"]\n'
            'matrix = [["sin(x)", "sin(y)*(2 + cos(z)*cos(w))"]]\n')
    tm = task_matrix(parse_model(RAW4, name="raw"), frame="auto")
    ctx = Context(tm, method="svm", rng=np.random.default_rng(0))
    x, y, z, w = tm.variables
    E = [sp.sin(x) * sp.cos(z) + sp.sin(y) * sp.sin(w),
         sp.sin(x) * sp.sin(w) + sp.sin(y) * sp.cos(z), 2 * sp.sin(x) - sp.sin(y)]
    (branch,) = cover(ctx, Branch(), [ctx.ring.from_sympy(e) for e in E])
    assert len(branch.implicit) == 3
    exact = reducible.special_points(ctx, branch)
    assert exact and all(ctx.probe.rank_at(ctx.M, g) == 0 for g in exact)
    solved = reducible.special_solved_points(ctx, branch)
    regular = [g for g in solved if ctx.probe.rank_at(ctx.M, g) == 1]
    assert regular
    for g in regular:
        ax, ay, az, aw = _angles(ctx, g)
        assert abs(np.cos(az)) < 1e-12 and abs(np.sin(aw)) < 1e-12
        assert abs(2 * np.sin(ax) - np.sin(ay)) < 1e-10 and abs(np.sin(ax)) > 1e-3
    # the held angles are only those the vanishing equations need: x and y are solved free
    assert len({round(_angles(ctx, g)[0], 6) for g in regular}) == len(regular)
    # recorded as a leaf, the leaf is split once the tree is grown, into singular leaves only
    node = _recorded(ctx, branch)
    reducible.refine_leaves(ctx)
    _split_into_singular_leaves(ctx, branch, node)


def test_leaf_with_mixed_first_points_is_split():
    """First sample points on both pieces (PR2's finger chains): the singular piece has the
    determinantal dimension (1 for a 1 x 2 matrix in 3 joints), so the regular points do not
    make the leaf covered; it is split, and the singular piece is kept."""
    ctx, branch = _reducible_leaf()
    regular, singular, _ = reducible.ranked_points(ctx, branch)
    mixed = [regular[0]] + singular[:2]
    assert not ctx.regular_throughout(branch, mixed)
    ctx.sampler.cache[branch.key + (3,)] = mixed
    node = ctx.add_node(None, branch)
    ctx.leaf(branch, node, Outcome.ALL_MINORS_VANISH)
    _split_into_singular_leaves(ctx, branch, node)


#: Half-angle generators (cos q/2, sin q/2), exact at 0, pi/2 and pi.
_HALF = {0: (1.0, 0.0), 1: (np.sqrt(0.5), np.sqrt(0.5)), 2: (0.0, 1.0)}


def _half_angles(*quarters):
    """The point with angles quarters[i] * pi/2."""
    return np.array([x for k in quarters for x in _HALF[k]])


def test_mixed_points_below_the_dimension_bound_are_covered():
    """sin y = sin z = sin x cos x = 0 is a finite set of points.  The matrix is singular at
    those with sin x = 0 and regular at those with cos x = 0.  Points have dimension 0, below the
    bound 1, so the singular ones lie on a larger component (sin x = sin y = 0, z free), which
    has a branch of its own.  This branch counts as covered."""
    tm = task_matrix(parse_model(RAW, name="raw"), frame="auto")
    ctx = Context(tm, method="svm", rng=np.random.default_rng(0))
    x, y, z = tm.variables
    E = [sp.sin(y), sp.sin(z), sp.sin(x) * sp.cos(x)]
    branch = Branch(tuple(ctx.ring.from_sympy(e) for e in E))
    singular = _half_angles(0, 2, 0)
    regular = _half_angles(1, 0, 2)
    assert ctx.probe.rank_at(ctx.M, singular) == 0
    assert ctx.probe.rank_at(ctx.M, regular) == 1
    assert all(ctx.probe.vanishes(c, [singular, regular]) for c in branch.conditions)
    assert ctx.local_dimension(branch, singular) == 0
    assert ctx.regular_throughout(branch, [regular, singular])
    # the same points on the 1-dimensional branch sin y = sin z = 0 with x free are not
    wide = Branch(tuple(ctx.ring.from_sympy(e) for e in E[:2]))
    assert ctx.local_dimension(wide, singular) == 1
    assert not ctx.regular_throughout(wide, [regular, singular])


def test_a_hint_on_the_regular_piece_splits_the_leaf():
    """A check found the leaf regular at x = y = 0.7, z = pi/2 (a point of the regular piece):
    the leaf is split, and its pieces are singular."""
    ctx, branch = _reducible_leaf()
    node = _recorded(ctx, branch)
    assert reducible.repair_leaves(ctx, [{"x": 0.7, "y": 0.7, "z": np.pi / 2}]) == 1
    _split_into_singular_leaves(ctx, branch, node)


def test_a_hint_in_an_excluded_set_keeps_the_exclusion():
    """The same leaf with cos z excluded is singular at all its points; its equations alone
    also hold on the regular piece, inside {cos z = 0}.  A hint there keeps cos z != 0 in the
    component (as the factor that vanishes there); a singular hint, or one off the leaf,
    changes nothing."""
    ctx, branch = _reducible_leaf()
    z = ctx.tm.variables[2]
    branch = branch.excluding(ctx.ring.from_sympy(sp.cos(z)))
    node = _recorded(ctx, branch)
    singular = {"x": 0.0, "y": np.pi, "z": 0.4}
    off = {"x": 0.3, "y": 0.9, "z": 0.4}
    assert reducible.repair_leaves(ctx, [singular, off]) == 0
    assert branch.key not in ctx.exceptional_exclusions
    assert reducible.repair_leaves(ctx, [{"x": 0.7, "y": np.pi - 0.7, "z": np.pi / 2}]) == 1
    # the factor of cos z = (cos z/2 - sin z/2)(cos z/2 + sin z/2) that vanishes at z = pi/2
    (kept,) = ctx.exceptional_exclusions[branch.key]
    half = sp.cos(z / 2) - sp.sin(z / 2)
    assert ctx.ring.to_sympy(kept) in (half, -half)
    assert ctx.leaves == [(branch, node)]


def _leaf_with(ctx, *conditions):
    """A leaf of ``ctx`` with ``conditions`` (polynomials of its ring), solved as the tree
    solves them."""
    branch = Branch()
    for c in conditions:
        branch, _ = branch.with_condition(c, ctx.ring)
    return branch, _recorded(ctx, branch)


def test_a_hint_at_a_float_multiple_of_pi_reaches_the_leaf():
    """A hint at x = pi in floats (cos(x/2) = 6e-17, which is all of the term size of the
    single-term condition cos(x/2)) is on the leaf {x = pi, sin y cos z = 0}; where cos z = 0
    the matrix [0, sin y] is regular, and the leaf is split there."""
    tm = task_matrix(parse_model(RAW, name="raw"), frame="auto")
    ctx = Context(tm, method="svm", rng=np.random.default_rng(0))
    y, z = tm.variables[1:]
    C_x = ctx.ring.gens[0]
    branch, node = _leaf_with(ctx, C_x, ctx.ring.from_sympy(sp.sin(y) * sp.cos(z)))
    hint = {"x": float(np.pi), "y": 0.7, "z": float(np.pi / 2)}
    g = ctx.point_at(hint)
    assert g[0] == 0.0 and g[1] == 1.0
    assert all(ctx.probe.vanishes(c, [g]) for c in branch.conditions)
    assert reducible.repair_leaves(ctx, [hint]) == 1
    assert ctx.tree.nodes[node]["outcome"] == Outcome.REFINED


def test_a_hint_where_a_pair_substitution_degenerates_keeps_its_exclusion():
    """The leaf sin(y/2) cos(x/2) + sin(z/2) sin(x/2) = 0 solves (cos x/2, sin x/2) ~
    (sin z/2, -sin y/2), undefined where y = z = 0.  There the condition holds for every x,
    and the matrix is regular at x = 0.7; no minor reduced on the leaf can be nonzero at such
    a point, so the leaf keeps the shorter value of the substitution as an exclusion instead
    of being split."""
    tm = task_matrix(parse_model(RAW, name="raw"), frame="auto")
    ctx = Context(tm, method="svm", rng=np.random.default_rng(0))
    x, y, z = tm.variables
    C_x, S_x, _, S_y, _, S_z = ctx.ring.gens[:6]
    branch, node = _leaf_with(ctx, S_y * C_x + S_z * S_x)
    assert [s.kind for s in branch.substitutions] == ["pair"]
    assert reducible.repair_leaves(ctx, [{"x": 0.7, "y": 0.0, "z": 0.0}]) == 1
    (kept,) = ctx.exceptional_exclusions[branch.key]
    assert ctx.ring.to_sympy(kept) in (sp.sin(y / 2), -sp.sin(y / 2), sp.sin(z / 2),
                                       -sp.sin(z / 2))
    assert ctx.leaves == [(branch, node)]


@pytest.mark.parametrize("matrix, kept", [
    ('[["sin(x)", "sin(y) + sin(x)*cos(z)"]]', True),
    ('[["sin(y)", "sin(z)", "sin(x)*sin(y)"]]', False)])
def test_pieces_where_a_pair_substitution_is_undefined_are_sampled_before_any_hint(matrix, kept):
    """The leaf sin(y/2) cos(x/2) + sin(z/2) sin(x/2) = 0, whose pair substitution is undefined
    where y = z = 0, is checked on that piece, with x free, before the self-check has any
    hint: where the matrix is regular there (first matrix: [sin x, sin x]) the leaf keeps the
    shorter value of the substitution as an exclusion; where it is singular there (second:
    [0, 0, 0]), nothing."""
    tm = task_matrix(parse_model(f'variables = ["x", "y", "z"]\nmatrix = {matrix}\n',
                                 name="raw"), frame="auto")
    ctx = Context(tm, method="svm", rng=np.random.default_rng(0))
    x, y, z = tm.variables
    C_x, S_x, _, S_y, _, S_z = ctx.ring.gens[:6]
    branch, _ = _leaf_with(ctx, S_y * C_x + S_z * S_x)
    (sub,) = branch.substitutions
    piece = reducible.exceptional_branch(ctx, branch, sub)
    assert sorted(map(str, piece.conditions)) == ["S_y", "S_z"]
    reducible._keep_exceptional_exclusions(ctx, branch)
    got = ctx.exceptional_exclusions.get(branch.key, [])
    if kept:
        (p,) = got
        assert ctx.ring.to_sympy(p) in (sp.sin(y / 2), -sp.sin(y / 2), sp.sin(z / 2),
                                        -sp.sin(z / 2))
    else:
        assert got == []
