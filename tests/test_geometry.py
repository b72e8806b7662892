"""The geometry of a pose and of a component (rankloci.geometry, rankloci.directions).

Invariants, not printed decimals: a fact of the pose holds where the arm is
singular and at no random configuration; the lost direction is a null vector
of J and is read by what it moves; the API call agrees with the library.
"""

from __future__ import annotations

import numpy as np
import pytest

import rankloci
from rankloci.directions import lost_direction
from rankloci.geometry import (axis_lines, columns_fill_rows, component_facts, design_facts,
                               facts_at, lost_rotation_axis, robot_pose)
from rankloci.io import load_model

SEED = 20261207
PUMA_WRIST = [0.3, 0.2, -0.4, 0.5, 0.0, 0.1]


def test_axis_lines_are_unit_and_pass_through_the_frames():
    arm = load_model("planar2r")
    lines, tool = axis_lines(arm, {"q1": 0.0, "q2": np.pi / 2})
    assert [ln.joint for ln in lines] == [1, 2]
    for ln in lines:
        assert np.linalg.norm(ln.direction) == pytest.approx(1.0)
        assert abs(ln.direction[2]) == pytest.approx(1.0)     # about z, the plane's normal
    np.testing.assert_allclose(tool, [1.0, 1.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(robot_pose(arm, {"q1": 0.0, "q2": np.pi / 2}).tool, tool)


def test_a_fact_of_a_singular_pose_is_at_no_random_configuration():
    arm = load_model("puma560")
    rng = np.random.default_rng(SEED)
    meets, design = design_facts(arm, None, rng)
    q = {f"q{k + 1}": x for k, x in enumerate(PUMA_WRIST)}
    assert ("collinear", 4, 6) in facts_at(arm, q, None, meets)
    assert ("collinear", 4, 6) not in design
    assert ("collinear", 4, 6) not in facts_at(arm, dict(q, q5=0.7), None, meets)


def test_component_facts_keep_what_holds_at_every_point():
    arm = load_model("puma560")
    q = {f"q{k + 1}": x for k, x in enumerate(PUMA_WRIST)}
    pts = [q, dict(q, q1=1.0, q4=-1.2), dict(q, q2=-0.7, q6=2.0)]
    f = component_facts(arm, pts, rng=np.random.default_rng(SEED))
    assert ("collinear", 4, 6) in f.whole and f.points == 3 and f.factors == ()
    assert not f.whole & f.design
    # a point off the wrist singularity takes the collinearity away
    g = component_facts(arm, pts + [dict(q, q5=0.4)], rng=np.random.default_rng(SEED))
    assert ("collinear", 4, 6) not in g.whole
    with pytest.raises(ValueError, match="rng"):
        component_facts(arm, pts)


def test_the_lost_rotation_axis_is_normal_to_the_wrist_axes():
    arm = load_model("puma560")
    q = {f"q{k + 1}": x for k, x in enumerate(PUMA_WRIST)}
    n = np.array(lost_rotation_axis(arm, q, None, [4, 5, 6]))
    lines, _ = axis_lines(arm, q)
    assert np.linalg.norm(n) == pytest.approx(1.0)
    for j in (4, 5, 6):
        assert abs(float(n @ lines[j - 1].direction)) < 1e-9
    assert lost_rotation_axis(arm, dict(q, q5=0.4), None, [4, 5, 6]) == ()


def test_columns_fill_rows_only_when_the_others_miss_those_rows():
    locked = np.array([[1.0, 2.0, 0.0], [2.0, 4.0, 0.0], [0.0, 0.0, 1.0]])
    assert columns_fill_rows([locked], [0, 1])
    assert not columns_fill_rows([locked + [[0, 0, 1.0], [0, 0, 0], [0, 0, 0]]], [2])


@pytest.mark.parametrize("u, rows, kind", [
    ([1.0, 0.0, 0.0], ("vx", "vy", "wz"), "translation"),
    ([0.0, 0.0, 1.0], ("vx", "vy", "wz"), "rotation"),
    ([1.0, 0.0, -1.0], ("vx", "vy", "wz"), "wrench"),
    ([1.0, 0.0, -1.0], ("vx", "vy", "phi"), "mixed"),
])
def test_lost_direction_reads_the_parts_of_a_null_vector(u, rows, kind):
    u = np.asarray(u) / np.linalg.norm(u)
    # a 3x3 J whose left null space is spanned by u
    rng = np.random.default_rng(SEED)
    J = rng.normal(size=(3, 3))
    J -= np.outer(u, u @ J)
    d = lost_direction(J, u, rows)
    assert d.kind == kind
    assert np.linalg.norm(d.vector @ J) <= 1e-12 * np.linalg.norm(J)
    assert lost_direction(J, J[:, 0], rows) is None            # not a null vector


def test_pose_geometry_at_a_regular_and_a_singular_pose():
    g = rankloci.pose_geometry("planar2r", [0.3, 0.0])            # stretched out
    assert g.rank_drop == 1 and ("parallel", 1, 2) in g.design
    (d,) = g.lost
    assert d.kind == "translation"
    # the task point cannot move along the arm
    along = np.array([np.cos(0.3), np.sin(0.3)])
    assert abs(abs(float(np.array([x for _, x in d.present(("vx", "vy"))]) @ along)) - 1) < 1e-9
    r = rankloci.pose_geometry("planar2r", [0.3, 1.1])
    assert r.rank_drop == 0 and r.lost == () and not r.special


def test_pose_geometry_refuses_what_is_not_a_pose_of_a_robot():
    with pytest.raises(ValueError, match="2 values"):
        rankloci.pose_geometry("planar2r", [0.1, 0.2, 0.3])
    with pytest.raises(ValueError, match="finite"):
        rankloci.pose_geometry("planar2r", [0.1, np.nan])
    with pytest.raises(ValueError, match="robot model"):
        rankloci.pose_geometry(rankloci.api.matrix_model([["cos(x)", "1"]], variables=["x"]),
                               [0.1])


@pytest.fixture(scope="module")
def puma_locus():
    return rankloci.locus("puma560", numeric=True)


def test_component_geometry_reads_the_puma_560s_three_singularities(puma_locus):
    facts = {i: rankloci.component_geometry("puma560", puma_locus, i, seed=SEED)
             for i in range(1, len(puma_locus.components) + 1)}
    by_equation = {str(c.equations[0]): i for i, c in enumerate(puma_locus.components, 1)}
    wrist = facts[by_equation["sin(q5)"]]
    assert ("collinear", 4, 6) in wrist.facts.whole and wrist.facts.points == 4
    shoulder = [g for g in facts.values() if ("in-plane", "P", 1, 2) in g.facts.whole]
    elbow = [g for g in facts.values() if ("coplanar", "P", frozenset({2, 3})) in g.facts.whole]
    assert len(shoulder) == 1 and len(elbow) == 1 and shoulder[0] is not elbow[0]
    # each lost direction is a left null vector of J at the sample point
    for g in facts.values():
        assert len(g.lost) == puma_locus.components[g.index - 1].rank_drop
        assert not g.facts.whole & g.facts.design


def test_component_geometry_refuses_a_bad_index_or_another_models_locus(puma_locus):
    for index in (0, 4, True, 1.0):
        with pytest.raises(ValueError, match="index"):
            rankloci.component_geometry("puma560", puma_locus, index)
    with pytest.raises(ValueError, match="not a locus of planar2r"):
        rankloci.component_geometry("planar2r", puma_locus, 1)
    with pytest.raises(ValueError, match="must be a Locus"):
        rankloci.component_geometry("puma560", "sin(q5)", 1)
