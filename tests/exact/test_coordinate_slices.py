"""Codimension 3 on coordinate slices (three variables free, the others at random values).

The elimination projects along coordinates there, which is not generic: several witness
points share coordinates, a curve of the slice can sit over the projection of an isolated
point, and an equation without the variable eliminated first puts a curve at infinity under
every resultant.  Each case is built here with known zeros over GF(P)."""

from __future__ import annotations

import dataclasses

import flint
import numpy as np
import pytest
import sympy as sp

import rankloci
from rankloci.certify import certify_locus
from rankloci.exact import witness
from rankloci.jacobians import task_matrix
from rankloci.loci import Component

P = 2305843009213693951          # 2**61 - 1


def _ring():
    ctx = flint.nmod_mpoly_ctx.get(("u0", "u1", "u2"), modulus=P)
    return ctx.gens()


def _points(polys):
    """The isolated zeros found, as sorted tuples (GF(P) points) and the orbit sizes."""
    found = witness._isolated_in_some_order(polys, 3, P, np.random.default_rng(0))
    rational = sorted(tuple(int(x) for x in pt) for F, pt, d in found if F.degree() == 1)
    return rational, sorted(d for _, _, d in found)


def test_a_point_behind_a_line_is_found():
    """The line u0 = u2 = 0 projects (along u2) onto the line u0 = 0 of the (u0, u1) plane,
    and so does the isolated point (0, 5, 7): dividing the line out of the resultants would
    lose the point; it is found in the plane u0 = 0."""
    u0, u1, u2 = _ring()
    polys = [u0, u2 * (u1 - 5), u2 * (u2 - 7), u0 + 3 * u2 * (u1 - 5)]
    assert _points(polys) == ([(0, 5, 7)], [1])


def test_points_that_share_coordinates_are_all_lifted():
    """Eight points of a product {0, 1} x {2, 3} x {4, 5}: every projection along a
    coordinate maps two of them to one."""
    u0, u1, u2 = _ring()
    polys = [u0 * (u0 - 1), (u1 - 2) * (u1 - 3), (u2 - 4) * (u2 - 5),
             u0 * (u0 - 1) + (u2 - 4) * (u2 - 5)]
    expected = sorted((a, b, c) for a in (0, 1) for b in (2, 3) for c in (4, 5))
    assert _points(polys) == (expected, [1] * 8)


def test_points_over_an_extension_are_lifted_over_a_tower():
    """u2**2 = r for a non-residue r: over each of u0 in {0, 1} a pair of conjugate points,
    one orbit of 2 each, in GF(P**2)."""
    u0, u1, u2 = _ring()
    r = next(k for k in range(2, 100) if pow(k, (P - 1) // 2, P) == P - 1)
    polys = [u0 * (u0 - 1), u1 - 3, u2 * u2 - r, u0 * (u0 - 1) + u1 - 3]
    found = witness._isolated_in_some_order(polys, 3, P, np.random.default_rng(0))
    assert sorted(d for _, _, d in found) == [2, 2]
    for F, pt, _ in found:
        assert pt[2] * pt[2] == F(r) and pt[1] == F(3) and (pt[0] == F(0) or pt[0] == F(1))


def test_a_triangular_system_is_eliminated_in_an_order_that_works():
    """Only the last equation contains u2: along u2 every resultant has the curve at infinity
    over the zeros of its leading coefficient (u0 u1 + 1) as a factor, which is no line; the
    order that eliminates u0 first finds the four points."""
    u0, u1, u2 = _ring()
    e1 = (u0 - 2) * (u0 - 3)
    e2 = (u1 - u0) * (u1 + 1)
    e3 = (u0 * u1 + 1) * u2 - 1
    polys = [e1, e2, e3, e1 + 5 * e2 + 7 * e3]
    want = []
    for a in (2, 3):
        for b in (a, P - 1):
            want.append((a, b, pow((a * b + 1) % P, -1, P)))
    assert _points(polys) == (sorted(want), [1] * 4)


def test_a_curve_in_no_coordinate_plane_leaves_the_slice_undecided():
    """A twisted cubic (t, t**2, t**3) projects onto a curve that is no line along every
    coordinate: no order takes it apart, and the slice is not decided."""
    u0, u1, u2 = _ring()
    polys = [u1 - u0 * u0, u2 - u0 * u1, u0 * u2 - u1 * u1, u1 - u0 * u0 + u2 - u0 * u1]
    with pytest.raises(witness._Curves):
        witness._isolated_in_some_order(polys, 3, P, np.random.default_rng(0))


def _planar4r():
    tm = task_matrix(rankloci.load_model("planar4r"), numeric=True)
    q = tm.variables
    whole = Component((sp.sin(q[1]), sp.sin(q[2]), sp.sin(q[3])), dimension=1, free=(q[0],))
    return tm, q, whole


def test_slices_certify_planar4r_and_refuse_what_a_subspace_refuses(monkeypatch):
    """planar4r (2 x 4): its only component has codimension 3.  Decided on coordinate slices
    instead of a random subspace, the verdicts are those of the subspace: its locus passes,
    a locus without it or with half of it fails, and a component where J is regular fails."""
    tm, q, whole = _planar4r()
    half = Component((sp.sin(q[1]), sp.sin(q[2]), sp.cos(q[3] / 2)), dimension=1, free=(q[0],))
    regular = Component((sp.cos(q[1]), sp.sin(q[2]), sp.sin(q[3])), dimension=1, free=(q[0],))
    cases = {"whole": [whole], "none": [], "half": [half], "regular": [whole, regular]}
    generic = {k: witness.certify_components(tm.matrix, q, tm.angles, v, seed=5)
               for k, v in cases.items()}
    monkeypatch.setattr(witness, "_SLICES_FIRST", True)
    sliced = {k: witness.certify_components(tm.matrix, q, tm.angles, v, seed=5)
              for k, v in cases.items()}
    assert {k: c.verdict for k, c in generic.items()} == \
        {"whole": "passed", "none": "failed", "half": "failed", "regular": "failed"}
    assert {k: c.verdict for k, c in sliced.items()} == {k: c.verdict for k, c in generic.items()}
    # the slices' witness points of codimension 3: 8 points on each slice that meets the
    # component, q2, q3, q4 in {0, pi}; the other slices hold q1 free (no isolated point)
    assert sliced["whole"].witness_points[3] == 8
    assert any("lie on no reported component" in f for f in sliced["half"].findings)
    assert any("is regular at a witness point" in f for f in sliced["regular"].findings)


@pytest.mark.slow
def test_an_eight_joint_arm_is_certified_and_a_missing_component_refused(robots):
    """pr2's left arm from its torso (6 x 8, a prismatic lift and seven revolute joints): codim
    3 is beyond a random subspace's budget and decided on coordinate slices; the locus
    `rankloci locus` shows is certified, and the same locus without one of its components of
    codimension 3 is refused."""
    path = robots / "pr2_description/urdf/pr2.urdf"
    locus = rankloci.locus(path, base_link="base_footprint", tip="l_wrist_roll_link")
    assert locus.complete is True, locus.certificate.findings
    assert locus.certificate.witness_points[3] > 0
    complex_only = [Component(tuple(eqs)) for eqs in locus.certificate.complex_components]
    tm = task_matrix(rankloci.load_model(path, base_link="base_footprint",
                                         tip="l_wrist_roll_link"))
    for k, comp in enumerate(locus.components):
        if len(locus.variables) - comp.dimension != 3:
            continue
        rest = locus.components[:k] + locus.components[k + 1:]
        without = dataclasses.replace(locus, components=rest)
        cert = certify_locus(without, tm, complex_only=complex_only)
        assert cert.verdict == "failed", (comp.equations, cert.findings)
        assert any("lie on no reported component" in f for f in cert.findings)
        break
    else:
        pytest.fail("no component of codimension 3")


def test_a_slice_gives_the_points_of_a_random_subspace_of_it():
    """planar4r's slice where q2, q3, q4 vary: the elimination along its coordinates finds the
    witness points that the random subspace's own elimination finds after a random change of
    coordinates inside the slice (generic projections), 8 (q2, q3, q4 in {0, pi})."""
    tm, _, _ = _planar4r()
    forms = witness._Forms(tuple(tm.angles), (), [])
    rows = forms.homogeneous_rows(sp.Matrix(tm.matrix))
    rng = np.random.default_rng(0)
    P, roots = witness._random_prime(rng, [])
    found = {}
    for mixed in (False, True):
        plane = witness._CoordinatePlane(forms, P, roots, (1, 2, 3), rng, mixed=mixed)
        Mp = [[plane.restrict(x) for x in row] for row in rows]
        points, _ = witness._isolated_points(witness._compressions(Mp, 2, 4, 4, P, rng), plane,
                                             rng)
        # the points as tan(q / 2) of the free angles, "pi" where cos(q / 2) = 0 (the charts'
        # coordinates differ between the two)
        na = len(forms.angles)

        def half_tangent(pt, i, plane=plane, na=na):
            C, S = pt.value(plane.images[i]), pt.value(plane.images[na + i])
            return "pi" if C.is_zero() else str(int(S / C))

        found[mixed] = sorted(tuple(half_tangent(pt, i) for i in (1, 2, 3)) for pt in points)
    assert len(found[False]) == 8
    assert found[False] == found[True]
