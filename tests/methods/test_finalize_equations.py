"""A component's equations do not keep factors that its branch excludes."""

from __future__ import annotations

import sympy as sp

import locus_helpers as H
from rankloci.methods.finalize import _without_excluded_factors
from rankloci.tree.branch import Branch, Substitution

RAW = ('variables = ["x", "y", "z"]\n'
       'matrix = [["cos(z)", "sin(z)", "0"], ["0", "sin(x)", "sin(y)"]]\n')


def test_an_excluded_factor_that_appears_once_an_angle_is_fixed_is_divided_out():
    """cos(y/2) cos(z/2) + cos(x/2) sin(z/2), stored before x = pi, is cos(y/2) cos(z/2) on
    the branch; with cos(z/2) excluded the branch lies on cos(y/2) = 0, and a component
    written with the product would also hold on the whole of {z = pi}."""
    ctx, ix = H.raw_context(RAW)
    ring = ctx.ring
    C, S = ring.C, ring.S
    x, y, z = ix["x"], ix["y"], ix["z"]
    cond = C(y) * C(z) + C(x) * S(z)
    pi_x = Substitution("pi", x, (ring.ctx.constant(0), ring.ctx.constant(1)))
    branch = Branch(conditions=(C(x), cond), substitutions=(pi_x,), nonzero=(C(z),))
    first, got = _without_excluded_factors(ctx, branch)
    half_y = sp.cos(ring.angles[y] / 2)
    assert first == C(x) and ring.to_sympy(got) in (half_y, -half_y)
    # without that exclusion nothing is divided out, and the condition stays as it was stored
    assert _without_excluded_factors(ctx, Branch((C(x), cond), (pi_x,)))[1] == cond
    assert _without_excluded_factors(ctx, Branch((C(x), cond), (pi_x,), (), (S(z),)))[1] == cond
