"""Rank-deficiency loci: published loci, overdetermined matrices, representation edge cases,
soundness and completeness against the numeric SVD, method agreement, the branch tree.

Loci are computed once per (model, numeric parameters, method, seed) and shared between tests
(``locus_helpers.locus_of``).  Random configurations come from ``numpy.random.default_rng``
with the seeds below, printed in the test ids or failure messages.
"""

from __future__ import annotations

import math
import types

import networkx as nx
import numpy as np
import pytest
import sympy as sp

import locus_helpers as H
from rankloci.io import load_model
from rankloci.jacobians import task_matrix
from rankloci.methods import compute_locus
from rankloci.tolerances import RANK_RTOL, ZERO_RTOL

#: sigma_min/sigma_max at points solved onto a component.  Points solved to ROOT_RESIDUAL (~1e-11
#: scaled, in practice ~1e-15) give ratios ~1e-12..1e-15, since sigma_min is Lipschitz in q with a
#: constant ~sigma_max; RANK_RTOL itself therefore leaves >= 3 orders of margin, and a component
#: on which J is not rank deficient by the package's own threshold is a wrong component.
ON_LOCUS_RTOL = RANK_RTOL

#: An equation "vanishes" at a point when |e| / (sum of |coefficients| of e) <= EQ_RTOL: the
#: package's ZERO_RTOL, one order above what points accurate to ROOT_XTOL (1e-10) give.
EQ_RTOL = ZERO_RTOL

#: Completeness: a point with sigma_min/sigma_max <= RANK_RTOL found by minimisation lies within
#: ~ratio/|grad ratio| (~1e-8 rad) of the locus where it is smooth, but near places where
#: components meet tangentially the ratio is flat and minimisers stop ~1e-6 rad away (observed on
#: ssrms: scaled residual 2e-8 at ratio 2e-15); the scaled equations change by at most their
#: trig degree (<= 8 here) per radian, so 1e-6 accepts points ~1e-7 rad off a component while a
#: missing component leaves residuals of 1e-2 or more at a random point of it.
COVER_RTOL = 1e-6

SEED = 20240611

FAST_MODELS = ["planar2r", "planar3r", "planar3r_orient", "planar4r", "puma560", "ur5"]
# Measured on this 2-core machine (numeric parameters, svm): pa10 4-15 s, ssrms_lock3 2-5 s,
# ssrms 8-20 s, mobile10 30-50 s.
SLOW_MODELS = ["pa10", "ssrms_lock3", "ssrms", "mobile10"]


def _model_params(symbolic_too: bool):
    out = [pytest.param(m, True, id=f"{m}-numeric") for m in FAST_MODELS]
    out += [pytest.param(m, True, id=f"{m}-numeric", marks=pytest.mark.slow) for m in SLOW_MODELS]
    if symbolic_too:
        out += [pytest.param(m, False, id=f"{m}-symbolic") for m in FAST_MODELS]
    return out


# --- raw matrices -------------------------------------------------------------------------

SIN_PLUS_COS = 'variables = ["x"]\nmatrix = [["sin(x) + cos(x)"]]\n'
ONE_PLUS_COS = 'variables = ["x"]\nmatrix = [["1 + cos(x)"]]\n'
DIAGONAL = 'variables = ["x", "y"]\nmatrix = [["sin(x)", "0"], ["0", "sin(y)"]]\n'
TALL = 'variables = ["x", "y"]\nmatrix = [["cos(x)", "0"], ["sin(x)", "sin(y)"], ["0", "cos(y)"]]\n'
RAW = {"sin+cos": SIN_PLUS_COS, "1+cos": ONE_PLUS_COS, "diagonal": DIAGONAL, "tall3x2": TALL}


def _eqs(tm, comp, params=None):
    return H.ComponentEquations(comp, tm, params)


def _equation_set(*exprs):
    return types.SimpleNamespace(equations=tuple(exprs))


def _points_of(comp, tm, rng, n=4, params=None):
    """The component's sample and n more points solved onto its equations."""
    eqs = _eqs(tm, comp, params)
    pts = [H.sample_point(comp, tm)] + H.points_on(eqs, tm, rng, n)
    return eqs, pts


def _angle_distance(a, b):
    """Largest distance between angle vectors a and b on the circle (modulo 2 pi)."""
    d = np.remainder(np.asarray(a, dtype=float) - np.asarray(b, dtype=float) + np.pi, 2 * np.pi) - np.pi
    return float(np.max(np.abs(d)))


# --- 1. published loci ----------------------------------------------------------------------

def _published(name):
    """Published singular sets, as tuples of equations in the model's symbols.

    planar2r: det J = l1 l2 sin q2 (B. Siciliano, L. Sciavicco, L. Villani, G. Oriolo,
      "Robotics: Modelling, Planning and Control", Springer 2009, Sec. 3.3, two-link arm).
    planar3r_orient: the three-link arm of Sec. 2.9.1 with the orientation row; subtracting the
      last column from the others leaves l1 l2 sin q2 as the determinant (link 3 drops out).
    planar3r / planar4r with the 2-row position task: each column is the tip velocity of one
      joint, perpendicular to the line from that joint to the tip, so J loses rank iff those
      lines are all parallel, i.e. all links collinear (ibid. Sec. 3.3 for the 2R case):
      sin q2 = sin q3 (= sin q4) = 0.
    puma560 (standard DH of Corke's mdl_puma560, task point = wrist centre): the singularities
      decouple into wrist and arm singularities (ibid. Sec. 3.3.1-3.3.2): the wrist one s5 = 0,
      the elbow one d4 c3 + a3 s3 = 0 (arm stretched or folded: wrist centre in line with the
      elbow's common normal) and the shoulder one a2 c2 + a3 c23 - d4 s23 = 0 (wrist centre on
      the plane through axis 1 parallel to axis 2), written in this model's parametrisation.
    """
    tm = H.model_tm(name, False)
    S = {s.name: s for s in tm.variables} | {p.name: p for p in tm.parameters}
    sin, cos = sp.sin, sp.cos
    if name == "planar2r":
        return [(sin(S["q2"]),)]
    if name == "planar3r_orient":
        return [(sin(S["q2"]),)]
    if name == "planar3r":
        return [(sin(S["q2"]), sin(S["q3"]))]
    if name == "planar4r":
        return [(sin(S["q2"]), sin(S["q3"]), sin(S["q4"]))]
    if name == "puma560":
        q2, q3, q5 = S["q2"], S["q3"], S["q5"]
        a2, a3, d4 = S["a2"], S["a3"], S["d4"]
        return [(sin(q5),),
                (d4 * cos(q3) + a3 * sin(q3),),
                (a2 * cos(q2) + a3 * cos(q2 + q3) - d4 * sin(q2 + q3),)]
    raise KeyError(name)


@pytest.mark.parametrize("numeric", [False, True], ids=["symbolic", "numeric"])
@pytest.mark.parametrize("name", ["planar2r", "planar3r_orient", "planar3r", "planar4r", "puma560"])
def test_published_loci(name, numeric):
    """Every point of a published singular set is on a model component, and every model
    component lies inside a published set (its sample and points solved onto it)."""
    tm, locus = H.locus_of(name, numeric)
    values = H.model_tm(name, False).parameters
    comps = H.model_components(locus)
    assert comps, f"{name}: no component for the model's parameters"
    comp_eqs = [_eqs(tm, c, values) for c in comps]
    published = [_eqs(tm, _equation_set(*s), values) for s in _published(name)]
    rng = np.random.default_rng(SEED)
    for pub in published:
        pts = H.points_on(pub, tm, rng, 6)
        assert len(pts) == 6, f"could not sample the published set {pub.exprs} (seed {SEED})"
        for q in pts:
            best = min(e.residual(q) for e in comp_eqs)
            assert best <= EQ_RTOL, (
                f"{name}: point {H.fmt(q, tm.variables)} of the published set {pub.exprs} = 0 "
                f"is on no component (smallest scaled residual {best:.2e}; seed {SEED}); "
                f"components: {[H.describe(c) for c in comps]}")
    for comp, eqs in zip(comps, comp_eqs):
        pts = [H.sample_point(comp, tm)] + H.points_on(eqs, tm, rng, 4)
        for q in pts:
            best = min(p.residual(q) for p in published)
            assert best <= EQ_RTOL, (
                f"{name}: component {H.describe(comp)} has the point {H.fmt(q, tm.variables)} "
                f"outside every published set (smallest scaled residual {best:.2e}; seed {SEED})")


# --- 2. overdetermined: more rows than columns ----------------------------------------------

PLANAR2R_ORIENT = """\
name = "p2o"
source = "test"
task = "planar"
[parameters]
l1 = 1.0
l2 = 0.7
[[joint]]
a = "l1"
[[joint]]
a = "l2"
[[augment]]
name = "phi"
expr = "q1 + q2"
"""

PLANAR3R_FULL = """\
name = "p3full"
source = "test"
task = "full"
[parameters]
l1 = 1.0
l2 = 0.8
l3 = 0.5
[[joint]]
a = "l1"
[[joint]]
a = "l2"
[[joint]]
a = "l3"
"""


@pytest.mark.parametrize("method", ["svm", "subdeterminant"])
def test_tall_raw_matrix_has_four_isolated_points(method, write_file):
    """J = [[cos x, 0], [sin x, sin y], [0, cos y]] (3x2).

    Derivation: rank J < 2 iff its three 2x2 minors vanish: cos x sin y = 0, cos x cos y = 0,
    sin x cos y = 0.  sin y and cos y never vanish together, so the first two give cos x = 0;
    then sin x = +-1 and the third gives cos y = 0.  The locus is the four points
    (x, y) = (+-pi/2, +-pi/2), each with rank 1 (the first column is nonzero there).
    """
    tm = task_matrix(load_model(str(write_file("tall.toml", TALL))), frame="auto")
    assert tm.shape == (3, 2)
    locus = compute_locus(tm, method, rng=np.random.default_rng(SEED))
    expected = [np.array([sx * np.pi / 2, sy * np.pi / 2]) for sx in (1, -1) for sy in (1, -1)]
    assert not locus.degenerate
    comps = list(locus.components)
    # the four points, as four components or joined (cos x = 0, cos y = 0)
    assert 1 <= len(comps) <= 4, [H.describe(c) for c in comps]
    comp_eqs = [_eqs(tm, c) for c in comps]
    for p in expected:
        assert min(e.residual(p) for e in comp_eqs) <= EQ_RTOL, f"{p} is on no component"
    rng = np.random.default_rng(SEED)
    for c in comps:
        assert c.dimension == 0 and c.rank_drop == 1, H.describe(c)
        _, pts = _points_of(c, tm, rng)
        for q in pts:
            assert min(_angle_distance(q, p) for p in expected) <= 1e-9, (H.describe(c), q)


@pytest.mark.parametrize("method", ["svm", "subdeterminant"])
def test_planar2r_with_orientation_row_is_never_singular(method, write_file):
    """2R arm, rows (vx, vy, d(q1 + q2)): a 3x2 matrix of rank 2 everywhere.

    Derivation: columns c1 = (-l1 s1 - l2 s12, l1 c1 + l2 c12, 1), c2 = (-l2 s12, l2 c12, 1).
    c1 - c2 = l1 (-s1, c1, 0) has norm l1 != 0 and last entry 0, while c2 has last entry 1, so
    c2 is no multiple of c1 - c2: the columns are independent at every q.  The locus is empty.
    """
    tm = task_matrix(load_model(str(write_file("p2o.toml", PLANAR2R_ORIENT))), frame="auto",
                     numeric=True)
    assert tm.shape == (3, 2)
    locus = compute_locus(tm, method, rng=np.random.default_rng(SEED))
    assert not locus.degenerate
    assert locus.components == (), [H.describe(c) for c in locus.components]


@pytest.mark.parametrize("method", ["svm", "subdeterminant"])
def test_planar3r_full_task_6x3_is_singular_iff_sin_q2(method, write_file):
    """Planar 3R with the full 6-row task: a 6x3 matrix.

    Derivation: all axes are parallel to z, so the rows vz, wx, wy are identically zero and
    wz = (1, 1, 1) (a change of frame or reference point multiplies J by an invertible matrix).
    The rank is that of the 3x3 [J_xy; 1 1 1], whose determinant is l1 l2 sin q2 (subtract
    column 3 from columns 1 and 2: the last row becomes (0, 0, 1) and the 2x2 block left is the
    2R Jacobian of links 1-2 rotated by q3).  So the locus is {sin q2 = 0} (dimension 2: q1, q3
    free), with rank drop 1 (the columns of links 2 and 3 stay independent).
    """
    tm = task_matrix(load_model(str(write_file("p3full.toml", PLANAR3R_FULL))), frame="auto",
                     numeric=True)
    assert tm.shape == (6, 3)
    locus = compute_locus(tm, method, rng=np.random.default_rng(SEED))
    comps = H.model_components(locus)
    assert len(comps) == 1, [H.describe(c) for c in comps]
    (comp,) = comps
    assert comp.dimension == 2 and comp.rank_drop == 1, H.describe(comp)
    q2 = tm.variables[1]
    expected = _eqs(tm, _equation_set(sp.sin(q2)))
    got = _eqs(tm, comp)
    rng = np.random.default_rng(SEED)
    for q in H.points_on(expected, tm, rng, 6):
        assert got.residual(q) <= EQ_RTOL, f"{H.fmt(q, tm.variables)} (sin q2 = 0) not on {H.describe(comp)}"
    for q in [H.sample_point(comp, tm)] + H.points_on(got, tm, rng, 6):
        assert abs(np.sin(q[1])) <= EQ_RTOL, f"{H.fmt(q, tm.variables)} on {H.describe(comp)} has sin q2 != 0"


# --- 3. representation edge cases ----------------------------------------------------------

SQUARE_METHODS = ["svm", "subdeterminant", "determinant"]


@pytest.mark.parametrize("method", SQUARE_METHODS)
@pytest.mark.parametrize("text, roots", [
    pytest.param(SIN_PLUS_COS, (-sp.pi / 4, 3 * sp.pi / 4), id="sin+cos"),
    pytest.param(ONE_PLUS_COS, (sp.pi,), id="1+cos"),
])
def test_one_by_one_roots(text, roots, method):
    """[[sin x + cos x]] vanishes at x = -pi/4 and 3pi/4 (two roots of one irreducible
    half-angle quadratic); [[1 + cos x]] = 2 cos^2(x/2) vanishes only at x = pi, a root that the
    plain substitution t = tan(x/2) sends to infinity.  Each root must be a 0-dimensional
    component of rank drop 1, and no other component may appear."""
    tm, locus = H.raw_locus(text, method)
    comps = list(locus.components)
    expected = [np.array([float(r)]) for r in roots]
    comp_eqs = [_eqs(tm, c) for c in comps]
    for r, p in zip(roots, expected):
        covered = [c for c, e in zip(comps, comp_eqs) if e.residual(p) <= EQ_RTOL]
        assert covered, (f"root x = {r} of {tm.matrix[0]} is missing; components: "
                         f"{[H.describe(c) for c in comps]}; tree outcomes: "
                         f"{[d.get('outcome') for _, d in locus.tree.nodes(data=True)]}")
    for c in comps:
        assert c.dimension == 0 and c.rank_drop == 1, H.describe(c)
        x = H.sample_point(c, tm)
        assert min(_angle_distance(x, [float(r)]) for r in roots) <= 1e-9, (H.describe(c), x)
        for v in c.solved.get(tm.variables[0], ()):
            assert any(sp.simplify(v - r) == 0 or sp.simplify(v - r - 2 * sp.pi) == 0
                       or sp.simplify(v - r + 2 * sp.pi) == 0 for r in roots), (H.describe(c), c.solved)


@pytest.mark.parametrize("method", SQUARE_METHODS)
def test_diagonal_sines_two_components_no_intersection_listed(method):
    """diag(sin x, sin y): the locus is {sin x = 0} and {sin y = 0}, each of dimension 1 and rank
    drop 1.  Their intersection (sin x = sin y = 0, rank drop 2) lies in both and must not be
    listed as a component of its own."""
    tm, locus = H.raw_locus(DIAGONAL, method)
    comps = list(locus.components)
    assert len(comps) == 2, [H.describe(c) for c in comps]
    x, y = tm.variables
    rng = np.random.default_rng(SEED)
    want = {x: _eqs(tm, _equation_set(sp.sin(x))), y: _eqs(tm, _equation_set(sp.sin(y)))}
    matched = set()
    for c in comps:
        assert c.rank_drop == 1 and c.dimension == 1, H.describe(c)
        eqs, pts = _points_of(c, tm, rng)
        hits = [v for v, w in want.items() if all(w.residual(q) <= EQ_RTOL for q in pts)]
        assert len(hits) == 1, f"{H.describe(c)} is not exactly one of sin x = 0, sin y = 0"
        for q in H.points_on(want[hits[0]], tm, rng, 4):
            assert eqs.residual(q) <= EQ_RTOL, f"{H.describe(c)} misses {H.fmt(q, tm.variables)}"
        matched.add(hits[0])
    assert matched == {x, y}


SUM_OF_SQUARES = 'variables = ["y", "z"]\nmatrix = [["cos(y)", "-cos(z)"], ["cos(z)", "cos(y)"]]\n'


@pytest.mark.parametrize("method", ["svm", "subdeterminant", "determinant"])
def test_determinant_with_isolated_real_zeros(method):
    """det = cos(y)**2 + cos(z)**2 is irreducible over Q and vanishes on the reals only at the
    four points cos y = cos z = 0, where its gradient vanishes too (the matrix is zero there:
    rank drop 2).  Gauss-Newton reaches such points only to the square root of its tolerance,
    where the matrix still looks regular; the locus must find them all the same."""
    tm, locus = H.raw_locus(SUM_OF_SQUARES, method)
    y, z = tm.variables
    comps = list(locus.components)
    assert comps, "the four points cos y = cos z = 0 were lost"
    rng = np.random.default_rng(SEED)
    want = _eqs(tm, _equation_set(sp.cos(y), sp.cos(z)))
    for c in comps:
        assert c.rank_drop == 2 and c.dimension == 0, H.describe(c)
        _, pts = _points_of(c, tm, rng)
        assert all(want.residual(q) <= EQ_RTOL for q in pts), H.describe(c)
    for qy in (-np.pi / 2, np.pi / 2):
        for qz in (-np.pi / 2, np.pi / 2):
            assert any(_eqs(tm, c).residual(np.array([qy, qz])) <= EQ_RTOL for c in comps), (qy, qz)


PIVOT = 'variables = ["x", "y"]\nmatrix = [["1", "cos(x)", "cos(y)"], ["0", "sin(x)", "sin(y)"]]\n'


@pytest.mark.parametrize("method", ["svm", "subdeterminant"])
def test_constant_pivot_column_is_taken_out(method):
    """J = [[1, cos x, cos y], [0, sin x, sin y]]: the first column is a constant pivot, so
    rank J = 1 + rank [sin x, sin y], and J is singular exactly where sin x = sin y = 0.  A
    left null vector u has u1 = 0 (first column), so the lost direction is (0, +-1)."""
    tm, locus = H.raw_locus(PIVOT, method)
    x, y = tm.variables
    assert any("pivoted out" in n for n in locus.notes), locus.notes
    comps = list(locus.components)
    assert comps
    rng = np.random.default_rng(SEED)
    want = _eqs(tm, _equation_set(sp.sin(x), sp.sin(y)))
    for c in comps:
        _, pts = _points_of(c, tm, rng)
        assert all(want.residual(q) <= EQ_RTOL for q in pts), H.describe(c)
        (d,) = c.direction_at_sample
        assert abs(d[0]) <= 1e-12 and abs(abs(d[1]) - 1) <= 1e-12, d
    for qx in (0.0, np.pi):
        for qy in (0.0, np.pi):
            assert any(_eqs(tm, c).residual(np.array([qx, qy])) <= EQ_RTOL for c in comps)


# --- 4. soundness -------------------------------------------------------------------------

@pytest.mark.parametrize("name, numeric", _model_params(symbolic_too=True))
def test_components_are_rank_deficient(name, numeric):
    """At points solved onto each model component, sigma_min/sigma_max <= ON_LOCUS_RTOL and the
    number of singular values below RANK_RTOL * sigma_max is the component's rank drop."""
    tm, locus = H.locus_of(name, numeric)
    values = H.model_tm(name, False).parameters
    nj = H.numeric_j(H.model_tm(name, True))
    rng = np.random.default_rng(SEED)
    comps = H.model_components(locus)
    assert comps or locus.degenerate, f"{name}: empty locus"
    for comp in comps:
        eqs, pts = _points_of(comp, tm, rng, n=5, params=values)
        assert len(pts) >= 4, f"{name}: could not solve onto {H.describe(comp)} (seed {SEED})"
        for q in pts:
            J = nj(q)
            ratio = H.sigma_ratio(J)
            assert ratio <= ON_LOCUS_RTOL, (
                f"{name}: J is regular on {H.describe(comp)}: sigma_min/sigma_max = {ratio:.2e} "
                f"at {H.fmt(q, tm.variables)} (equation residual {eqs.residual(q):.1e}, seed {SEED})")
            drop = H.numeric_rank_drop(J)
            assert drop == comp.rank_drop, (
                f"{name}: rank drop {drop} at {H.fmt(q, tm.variables)}, component says "
                f"{comp.rank_drop}: {H.describe(comp)} (seed {SEED})")


@pytest.mark.parametrize("name, numeric", [
    pytest.param("puma560", True, id="puma560-numeric"),
    pytest.param("puma560", False, id="puma560-symbolic"),
    pytest.param("ur5", True, id="ur5-numeric"),
    pytest.param("ur5", False, id="ur5-symbolic"),
    pytest.param("ssrms", True, id="ssrms-numeric", marks=pytest.mark.slow),
])
def test_symbolic_directions_are_null_vectors(name, numeric):
    """Where a component's lost direction is given as expressions, they are a null vector of J
    (left for a wide J, right for a tall one) at points solved onto the component: each entry
    keeps its own scale and sign (PUMA 560's elbow lost its direction when an entry's content
    was cleared on its own).  These are the built-in models whose loci show such directions."""
    tm, locus = H.locus_of(name, numeric)
    values = H.model_tm(name, False).parameters
    nj = H.numeric_j(H.model_tm(name, True))
    rng = np.random.default_rng(SEED)
    syms = list(tm.variables)
    checked = 0
    for comp in H.model_components(locus):
        for vec in comp.direction:
            u_of = sp.lambdify(syms, [sp.sympify(x).subs(values) for x in vec], modules="numpy")
            _, pts = _points_of(comp, tm, rng, n=3, params=values)
            for q in pts:
                J = nj(q)
                u = np.array([np.broadcast_to(x, ()) for x in u_of(*q)], dtype=float)
                if np.linalg.norm(u) == 0:
                    continue        # a point where the expressions all vanish: no direction there
                r = u @ J if J.shape[0] <= J.shape[1] else J @ u
                rel = np.linalg.norm(r) / (np.linalg.norm(u) * H.singular_values(J)[0])
                assert rel <= ON_LOCUS_RTOL, (
                    f"{name}: the direction of {H.describe(comp)} is no null vector at "
                    f"{H.fmt(q, tm.variables)}: |u J| / (|u| sigma_max) = {rel:.1e} (seed {SEED})")
                checked += 1
    assert checked >= 4, f"{name}: only {checked} points with a symbolic direction checked"


# --- 5. completeness ----------------------------------------------------------------------

N_STARTS = 24


def _check_completeness(tm, locus, label, seed, n_starts=N_STARTS):
    nj = H.numeric_j(tm)
    comps = H.model_components(locus)
    comp_eqs = [_eqs(tm, c) for c in comps]
    rng = np.random.default_rng(seed)
    singular, uncovered = 0, []
    for _ in range(n_starts):
        q, ratio = H.minimise_sigma_ratio(nj, H.random_q(tm, rng))
        if ratio > RANK_RTOL:
            continue
        singular += 1
        res = [e.residual(q) for e in comp_eqs]
        best = min(res) if res else np.inf
        if best > COVER_RTOL:
            near = H.describe(comps[int(np.argmin(res))]) if res else "(no component)"
            uncovered.append(f"{H.fmt(q, tm.variables)}: sigma ratio {ratio:.1e}, nearest "
                             f"component {near} at scaled residual {best:.1e}")
    # sigma_min/sigma_max has minimum 0 on the locus; most starts must reach it
    assert singular >= n_starts // 4, f"{label}: only {singular}/{n_starts} starts reached a singular point"
    assert not uncovered, (f"{label} (seed {seed}): {len(uncovered)} singular point(s) on no "
                           "component:\n  " + "\n  ".join(uncovered))


@pytest.mark.parametrize("name, numeric", _model_params(symbolic_too=False))
def test_every_singular_point_is_on_a_component(name, numeric):
    """Minimise sigma_min/sigma_max from random starts; every point where J is numerically rank
    deficient must satisfy the equations of some component."""
    tm, locus = H.locus_of(name, numeric)
    _check_completeness(tm, locus, name, SEED)


@pytest.mark.slow
@pytest.mark.parametrize("seed", [1, 2, SEED + 1])
def test_ssrms_locus_is_complete_for_other_engine_seeds(seed):
    """The engine's random probes must not decide what is found.

    Regression: on the SSRMS the implicit pair of the position singularity (the two factors in
    q3, q4, q5 of the subdeterminant locus) was missed for every engine seed, because the sample
    points of its leaf all fell where the level's null vectors vanish (a regular piece of the
    same equations), and the leaf was discarded.  Probed with 32 starts and another seed.
    """
    tm = H.model_tm("ssrms", True)
    locus = compute_locus(tm, "svm", rng=np.random.default_rng(seed))
    _check_completeness(tm, locus, f"ssrms, engine seed {seed}", 7, n_starts=32)


@pytest.mark.parametrize("raw", ["diagonal", "tall3x2"])
def test_every_singular_point_of_a_raw_matrix_is_on_a_component(raw):
    tm, locus = H.raw_locus(RAW[raw])
    _check_completeness(tm, locus, raw, SEED)


def test_sigma_ratio_is_not_small_at_random_configurations():
    """Control for the soundness test: off the locus the ratio is far above ON_LOCUS_RTOL."""
    rng = np.random.default_rng(SEED)
    for name in FAST_MODELS:
        nj = H.numeric_j(H.model_tm(name, True))
        ratios = [H.sigma_ratio(nj(H.random_q(nj.tm, rng))) for _ in range(20)]
        assert np.median(ratios) > 1e4 * ON_LOCUS_RTOL, (name, ratios)


# --- 6. method agreement ------------------------------------------------------------------

def _outside(tm, comp, others, rng, params=None):
    """Points of ``comp`` (its sample and points solved onto it) on no component of ``others``."""
    _, pts = _points_of(comp, tm, rng, n=6, params=params)
    eqs = [_eqs(tm, o, params) for o in others]
    return [q for q in pts if not any(e.residual(q) <= EQ_RTOL for e in eqs)]


def _check_agreement(tm, a, b, label, params=None):
    """Same locus: every point of every component of one is on a component of the other.

    Tested point by point, not component by component: a method may list {q2 = 0} and
    {q2 = pi} where the other lists their union {sin q2 = 0}, which is the same locus.
    """
    rng = np.random.default_rng(SEED)
    ca, cb = H.model_components(a), H.model_components(b)
    assert a.degenerate == b.degenerate, label
    for x, y, xs, ys in ((a, b, ca, cb), (b, a, cb, ca)):
        for comp in xs:
            bad = _outside(tm, comp, ys, rng, params)
            assert not bad, (
                f"{label}: {x.method} component {H.describe(comp)} has points on no {y.method} "
                f"component, e.g. {H.fmt(bad[0], tm.variables)}; {y.method} components: "
                f"{[H.describe(c) for c in ys]} (seed {SEED})")


@pytest.mark.parametrize("name, numeric", [
    pytest.param("planar3r", False, id="planar3r-symbolic"),
    pytest.param("planar3r", True, id="planar3r-numeric"),
    pytest.param("planar4r", False, id="planar4r-symbolic"),
    pytest.param("planar4r", True, id="planar4r-numeric"),
    pytest.param("puma560", True, id="puma560-numeric"),
    pytest.param("ur5", True, id="ur5-numeric"),
    pytest.param("pa10", True, id="pa10-numeric", marks=pytest.mark.slow),
    pytest.param("ssrms", True, id="ssrms-numeric", marks=pytest.mark.slow),
    pytest.param("mobile10", True, id="mobile10-numeric", marks=pytest.mark.slow),
])
def test_svm_and_subdeterminant_agree_on_models(name, numeric):
    tm, a = H.locus_of(name, numeric, "svm")
    _, b = H.locus_of(name, numeric, "subdeterminant")
    _check_agreement(tm, a, b, f"{name} ({'numeric' if numeric else 'symbolic'})",
                     H.model_tm(name, False).parameters)


@pytest.mark.parametrize("raw", sorted(RAW))
def test_svm_and_subdeterminant_agree_on_raw_matrices(raw):
    tm, a = H.raw_locus(RAW[raw], "svm")
    _, b = H.raw_locus(RAW[raw], "subdeterminant")
    _check_agreement(tm, a, b, raw)


# --- 7. the branch tree -------------------------------------------------------------------

@pytest.mark.parametrize("case", [
    ("planar2r", True, "svm"), ("planar3r", False, "svm"), ("planar3r", False, "subdeterminant"),
    ("puma560", True, "svm"), ("puma560", True, "determinant"), ("planar4r", True, "svm"),
    pytest.param(("mobile10", True, "svm"), marks=pytest.mark.slow),
    pytest.param(("pa10", False, "svm"), marks=pytest.mark.slow),
], ids=lambda c: f"{c[0]}-{'numeric' if c[1] else 'symbolic'}-{c[2]}")
def test_branch_tree_is_a_rooted_tree_with_outcomes(case):
    name, numeric, method = case
    _, locus = H.locus_of(name, numeric, method)
    _check_tree(locus)


@pytest.mark.parametrize("raw", sorted(RAW))
def test_branch_tree_of_raw_matrices(raw):
    _, locus = H.raw_locus(RAW[raw])
    _check_tree(locus)


def _check_tree(locus):
    tree = locus.tree
    assert isinstance(tree, nx.DiGraph)
    assert 0 in tree and tree.in_degree(0) == 0
    assert nx.is_arborescence(tree), "the branch tree is not a tree rooted at node 0"
    assert set(nx.descendants(tree, 0)) | {0} == set(tree)
    leaves = [n for n in tree if tree.out_degree(n) == 0]
    no_outcome = [n for n in leaves if not tree.nodes[n].get("outcome")]
    assert not no_outcome, f"leaves without an outcome: {no_outcome}"
    unfinished = [n for n in leaves if tree.nodes[n]["outcome"] == "refined"]
    assert not unfinished, f"leaves marked 'refined' (a stop reason is missing): {unfinished}"
    assert len(leaves) >= len(locus.components) or locus.degenerate


@pytest.mark.parametrize("name, most", [
    ("pa10", 0),
    pytest.param("mobile10", 0, marks=pytest.mark.slow),
    pytest.param("ssrms", 0, marks=pytest.mark.slow),
])
def test_pair_conditions_left_implicit_give_the_same_locus(name, most, monkeypatch):
    """A condition a*C + b*S with large a and b stays an implicit equation instead of being
    substituted (rankloci.tree.branch.PAIR_MAX_TERMS).  With every pair condition of more than
    ``most`` terms implicit, the locus is the same set, point by point in both directions, as
    with the substitutions.

    Regression (SSRMS, every pair implicit): a leaf {q2 = -pi/2, f = 0} whose f, not reduced by
    the implicit q2 = -pi/2, vanishes there on cos q3 = 0 too, where J is regular; that piece lay
    in an excluded set of the leaf, and the exclusion was dropped because no sample point of the
    excluded part was regular.  Its exact points at multiples of pi/2 are now tested as well."""
    import rankloci.tree.branch as branch

    tm, substituted = H.locus_of(name, True)
    monkeypatch.setattr(branch, "PAIR_MAX_TERMS", most)
    declined = []
    solve = branch.solve_condition

    def counting(f, ring):
        got = solve(f, ring)
        if got[0] is None:
            # declined by the bound alone: without it, the same condition is a pair
            branch.PAIR_MAX_TERMS = math.inf
            if solve(f, ring)[0] is not None:
                declined.append(f)
            branch.PAIR_MAX_TERMS = most
        return got

    monkeypatch.setattr(branch, "solve_condition", counting)
    implicit = compute_locus(tm, "svm", rng=np.random.default_rng(0))
    assert declined, f"{name}: no pair condition was left implicit: the test exercises nothing"
    _check_agreement(tm, substituted, implicit, f"{name}, pair conditions implicit")
