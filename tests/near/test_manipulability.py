"""Manipulability ellipsoid and polytope: Kilic's three arms, pycapacity, and the locus.

Kilic's thesis reports its results as figures (lost in the text we have) and statements; each
statement is checked here with our built-in models, and the numbers are derived in closed form
where one exists:

- 2-link planar arm, unit links, q1 = q2 = pi/4 (planar2r): the polytope is a parallelogram whose
  edges are tangent to the ellipse, and it narrows to a segment as q2 -> 0.  w = |sin q2|, and
  for a square J the polytope's area is 2^2 |det J| = 4 w.
- PA10 at q = (0, pi/4, 0, pi/4, 0, pi/4, 0), translational rows (pa10): "the polytope is in shape
  of extrusion of an improper hexagon and ellipsoid covers a smaller volume while orientations
  of the polytope and ellipsoid are equal".
- PUMA 560 at q = pi/4 for every joint, translational rows (puma560): the polytope covers a wider
  set than the ellipsoid.  The task point is the wrist centre, so joints 4-6 add no linear
  velocity: the polytope is a parallelepiped, tangent to the ellipsoid, and the volume ratio
  is 8 |det| / (4 pi / 3 |det|) = 6 / pi.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from locus_helpers import locus_of, model_components

from rankloci.io import load_model
from rankloci.near.manipulability import ellipsoid, polytope, support, zonotope_volume
from rankloci.near.path import Kinematics
from rankloci.numeric.equations import Equations, NumericMatrix, points_on
from rankloci.tolerances import FLAT_RTOL, RANK_RTOL

PI4 = np.pi / 4


def translational(name, q):
    J = Kinematics(load_model(name)).jacobian(q)
    return J[:3] if J.shape[0] == 6 else J


def facet_vertex_counts(P):
    return sorted(int(np.sum(np.abs(P.vertices @ n - b) <= 1e-9 * (1 + abs(b))))
                  for n, b in zip(P.normals, P.offsets))


def test_planar2r_parallelogram_tangent_to_the_ellipse():
    J = translational("planar2r", [PI4, PI4])
    E, P = ellipsoid(J), polytope(J)
    assert E.w == pytest.approx(np.sin(PI4), rel=1e-12)
    np.testing.assert_allclose(np.prod(E.radii), E.w, rtol=1e-12)
    assert len(P.vertices) == 4 and len(P.normals) == 4
    assert P.w_p == pytest.approx(4 * E.w, rel=1e-12) and P.volume == pytest.approx(4 * E.w)
    # each edge touches the ellipse: the ellipse's support value along its normal is its offset
    np.testing.assert_allclose(np.linalg.norm(J.T @ P.normals.T, axis=0), P.offsets, rtol=1e-10)


def test_planar2r_polytope_narrows_to_a_segment_as_q2_goes_to_zero():
    q2s = np.linspace(PI4, 0.0, 9)
    areas = [polytope(translational("planar2r", [PI4, q2])).w_p for q2 in q2s]
    assert all(a > b for a, b in zip(areas, areas[1:-1]))
    np.testing.assert_allclose(areas, 4 * np.abs(np.sin(q2s)), atol=1e-12)
    flat = polytope(translational("planar2r", [PI4, 0.0]))
    assert flat.flat and flat.rank == 1 and flat.volume == 0.0 and len(flat.vertices) == 2


def test_pa10_polytope_is_a_hexagonal_prism_aligned_with_the_ellipsoid():
    J = translational("pa10", [0, PI4, 0, PI4, 0, PI4, 0])
    E, P = ellipsoid(J), polytope(J)
    assert len(P.vertices) == 12 and len(P.normals) == 8
    assert facet_vertex_counts(P) == [4] * 6 + [6, 6], "6 parallelograms and 2 hexagons"
    # the extrusion direction: the columns of joints 1, 3 and 5 are parallel to it
    axis = J[:, 0] / np.linalg.norm(J[:, 0])
    for j in (2, 4):
        assert abs(abs(axis @ J[:, j]) - np.linalg.norm(J[:, j])) <= 1e-12
    # the two hexagons are the facets normal to that direction ...
    caps = [n for n in P.normals if abs(abs(n @ axis) - 1) <= 1e-9]
    assert len(caps) == 2
    # ... and that direction is a principal axis of the ellipsoid: equal orientations
    assert max(abs(E.axes.T @ axis)) == pytest.approx(1.0, abs=1e-12)
    # the ellipsoid lies inside the polytope and covers a smaller volume
    assert np.all(np.linalg.norm(J.T @ P.normals.T, axis=0) <= P.offsets * (1 + 1e-12))
    assert E.volume < P.volume
    # the numbers: w = 0.182698, semi-axes 1.02102, 0.942685, 0.189816, polytope volume 2.75174
    np.testing.assert_allclose([E.w, *E.radii, P.volume],
                               [0.182698, 1.02102, 0.942685, 0.189816, 2.75174], rtol=5e-6)


def test_puma560_polytope_covers_more_than_the_ellipsoid():
    J = translational("puma560", [PI4] * 6)
    E, P = ellipsoid(J), polytope(J)
    np.testing.assert_allclose(J[:, 3:], 0, atol=1e-15)
    assert len(P.vertices) == 8 and len(P.normals) == 6 and facet_vertex_counts(P) == [4] * 6
    np.testing.assert_allclose(np.linalg.norm(J.T @ P.normals.T, axis=0), P.offsets, rtol=1e-10)
    assert P.volume / E.volume == pytest.approx(6 / np.pi, rel=1e-10)
    assert E.w == pytest.approx(abs(np.linalg.det(J[:, :3])), rel=1e-10)


@pytest.mark.filterwarnings("ignore:Importing from numpy.matlib:PendingDeprecationWarning")
@pytest.mark.parametrize("m, n", [(2, 2), (2, 4), (2, 7), (3, 3), (3, 5), (3, 7)])
def test_polytope_matches_pycapacity_on_random_jacobians(m, n):
    from pycapacity.robot import velocity_polytope

    rng = np.random.default_rng(100 * m + n)
    for _ in range(5):
        J = rng.normal(size=(m, n))
        P = polytope(J)
        theirs = velocity_polytope(J, np.ones(n), -np.ones(n)).vertices.T
        theirs = theirs[np.unique(np.round(theirs, 9), axis=0, return_index=True)[1]]
        assert len(theirs) == len(P.vertices)
        gap = np.linalg.norm(P.vertices[:, None, :] - theirs[None, :, :], axis=2)
        scale = np.abs(J).sum()
        assert gap.min(axis=1).max() <= 1e-9 * scale and gap.min(axis=0).max() <= 1e-9 * scale


@pytest.mark.parametrize("m, n", [(2, 3), (3, 4), (3, 6), (4, 6), (6, 7)])
def test_cone_cell_index_is_the_volume_and_the_zonotope_formula(m, n):
    rng = np.random.default_rng(10 * m + n)
    J = rng.normal(size=(m, n))
    P = polytope(J)
    assert P.w_p == pytest.approx(P.volume, rel=1e-10)
    assert P.w_p == pytest.approx(zonotope_volume(J), rel=1e-10)
    assert not P.flat and P.rank == m
    # every vertex is a sign vector's image, and the support along each normal is ||J'n||_1
    np.testing.assert_allclose([support(J, nrm) for nrm in P.normals], P.offsets, rtol=1e-10)


def test_bad_jacobians_are_refused():
    with pytest.raises(ValueError, match="at most 16"):
        polytope(np.ones((2, 17)))
    with pytest.raises(ValueError, match="finite"):
        ellipsoid([[1.0, np.inf]])


LOCUS_MODELS = ["planar2r", "planar3r", "planar4r", "puma560", "pa10"]


@pytest.mark.parametrize("name", LOCUS_MODELS)
def test_both_measures_vanish_on_every_component_of_the_locus(name):
    """rankloci's own locus: its sample point and 3 more points on each component."""
    tm, locus = locus_of(name)
    comps = model_components(locus)
    assert comps
    kin = Kinematics(load_model(name))
    nm = NumericMatrix(tm.matrix, tm.variables, tm.angles)
    rng = np.random.default_rng(0)
    for comp in comps:
        sample = np.array([comp.sample[v.name] for v in tm.variables])
        eqs = Equations(comp.equations, tm.variables, tm.parameters, comp.excluding)
        points = [sample] + points_on(eqs, nm, rng, 3)
        assert len(points) >= 2
        for q in points:
            J = kin.jacobian(q)
            E, P = ellipsoid(J), polytope(J)
            m = J.shape[0]
            assert E.w <= RANK_RTOL * E.radii[0] ** m, (comp.equations, q)
            assert P.flat and P.flatness <= FLAT_RTOL and P.volume == 0.0 and P.w_p == 0.0
            assert P.rank < m
    # and neither vanishes at random configurations
    for q in nm.random_q(rng, 3):
        J = kin.jacobian(q)
        assert ellipsoid(J).sigma_ratio > 1e-4 and not polytope(J).flat


def test_zonotope_formula_counts_every_column_subset():
    J = np.array([[1.0, 0.0, 1.0], [0.0, 1.0, 1.0]])
    dets = [abs(np.linalg.det(J[:, list(S)])) for S in itertools.combinations(range(3), 2)]
    assert zonotope_volume(J) == pytest.approx(4 * sum(dets)) == pytest.approx(12.0)


def test_cone_cell_index_of_the_full_pa10_jacobian():
    """6-D, 7 columns: facets with many vertices, where Qhull's triangulated output overlaps;
    the facet-by-facet cone cells give the volume (15.519)."""
    J = Kinematics(load_model("pa10")).jacobian([0, PI4, 0, PI4, 0, PI4, 0])
    P = polytope(J)
    assert P.w_p == pytest.approx(P.volume, rel=1e-10)
    assert P.w_p == pytest.approx(zonotope_volume(J), rel=1e-10)
    assert P.w_p == pytest.approx(15.51895, rel=1e-6)
