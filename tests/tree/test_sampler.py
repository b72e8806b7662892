"""Generator rows of a branch's points: substitutions applied in order, constants set directly."""

from __future__ import annotations

import numpy as np
import sympy as sp

from rankloci.algebra import PolyRing
from rankloci.tree.branch import Branch
from rankloci.tree.sampler import BranchSampler

q, r, s = sp.symbols("q r s")
u = sp.Symbol("u")
RING = PolyRing((q, r, s), (u,), ())
Cq, Sq, Cr, Sr, Cs, Ss, U = RING.gens


def _branch(*conditions):
    branch = Branch()
    for f in conditions:
        branch, _ = branch.with_condition(f, RING)
    return branch


def test_constant_substitutions_set_the_values_the_evaluators_give():
    """q = pi, s = 0 and u = 3/2 are set as constants; r solved from C_r*(u - 1) + S_r*C_q
    (a pair in the later-solved q and u) is evaluated after them.  Each row equals the one the
    compiled evaluators of the substitutions' values give, bit for bit, and the rows lie on
    the branch."""
    branch = _branch(Sr * Cq + Cr * (U - 1) + Sr * Sq, Cq, Ss, 2 * U - 3)
    kinds = [sub.kind for sub in branch.substitutions]
    assert kinds == ["pair", "pi", "zero", "linear"]
    sampler = BranchSampler(RING, {}, np.random.default_rng(0))
    angles, others, params = sampler.unknowns(branch)
    assert (angles, others, params) == ([], [], [])
    G = sampler.generators_batch(branch, angles, others, params, np.zeros((3, 0)))

    want = np.zeros((3, len(RING.names)))
    for sub in reversed(branch.substitutions):
        vals = RING.compile(list(sub.values))(want)
        if sub.kind == "linear":
            want[:, sub.index] = vals[:, 0]
        else:
            norm = np.hypot(vals[:, 0], vals[:, 1])
            want[:, 2 * sub.index], want[:, 2 * sub.index + 1] = vals[:, 0] / norm, vals[:, 1] / norm
    assert np.array_equal(G, want)
    assert G[0, 0] == 0.0 and abs(G[0, 1]) == 1.0                     # q = pi
    assert G[0, 4] == 1.0 and G[0, 5] == 0.0 and G[0, 6] == 1.5       # s = 0, u = 3/2
    residuals = RING.compile(list(branch.conditions))(G)
    assert np.max(np.abs(residuals)) < 1e-15


def test_coefficient_scaled_solves_reach_a_piece_where_every_term_vanishes():
    """The Whitney umbrella Sq**2 - Sr**2 * u: on its handle Sq = Sr = 0 every term vanishes on
    its own, and where u < 0 no other point of the surface is near.  There the equation over
    the size of its terms is 1 however close a point comes, so the sampler's solves never
    accept such a point; solved with the equation over its coefficients, some reach it."""
    branch = _branch(Sq**2 - Sr**2 * U)
    assert branch.implicit and not branch.substitutions
    sampler = BranchSampler(RING, {}, np.random.default_rng(0))
    plain = sampler.points(branch, count=12)
    assert len(plain) == 12 and all(g[6] >= 0 for g in plain)   # u >= 0: the sheets only
    scaled = sampler.coefficient_scaled_points(branch, starts=24)
    handle = [g for g in scaled if g[6] < -1e-3]
    assert handle
    for g in handle:
        assert abs(g[1]) < 1e-5 and abs(g[3]) < 1e-5             # Sq = Sr = 0: q = r = 0
        assert abs(g[1] ** 2 - g[3] ** 2 * g[6]) <= 1e-10
