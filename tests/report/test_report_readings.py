"""Readings of the components: one per component, covering every equation, never duplicated,
named after the classical case only where the geometry says so, and checked numerically.

The loci are computed as the report computes them (model's method, seed 0); the readings
with :func:`rankloci.reporting.build.component_views`.
"""

from __future__ import annotations

import numpy as np
import pytest

from rankloci.augmented import augmented_locus
from rankloci.io import load_model
from rankloci.jacobians import task_matrix
from rankloci.methods import method_for
from rankloci.reporting.build import component_views
from rankloci.geometry import dependent_joints, facts_at
from rankloci.reporting.mathfmt import latex as mlatex

SEED = 0


def _views(name):
    model = load_model(name)
    tm = task_matrix(model, frame="auto")
    locus = augmented_locus(model, tm, method_for(tm.shape), seed=SEED)
    return model, [v for v in component_views(model, locus, seed=SEED) if not v.special]


@pytest.fixture(scope="module")
def puma():
    return _views("puma560")


@pytest.fixture(scope="module")
def pa10():
    return _views("pa10")


def _check_complete_and_distinct(views):
    readings = [v.readings[0] if v.readings else "" for v in views]
    assert all(readings), f"a component without a reading: {readings}"
    assert len(set(readings)) == len(readings), f"duplicated readings: {readings}"
    summaries = [v.summary for v in views]
    assert all(summaries) and len(set(summaries)) == len(summaries), summaries
    ordinals = ("first", "second", "third", "fourth", "fifth", "sixth")
    for v, text in zip(views, readings):
        eqs = v.component.equations
        if len(eqs) > 1:
            # each equation is named in the reading: as math, or by its order
            forms = list(v.folded) if len(v.folded) == len(eqs) else list(eqs)
            for k, f in enumerate(forms):
                assert f"${mlatex(f)} = 0$" in text or f"the {ordinals[k]} equation" in text, \
                    (v.index, k, text)


def test_puma560_readings_name_shoulder_elbow_and_wrist(puma):
    _, views = puma
    _check_complete_and_distinct(views)
    names = [v.readings[0].split(":")[0] for v in views]
    assert names == ["Shoulder singularity", "Elbow singularity (the arm is stretched out or "
                     "folded back)", "Wrist singularity"]
    shoulder = views[0].readings[0]
    # d3 != 0: the plane through axis 1 is the general form of "wrist centre on axis 1"
    assert "plane through axis 1 parallel to axes 2 and 3" in shoulder
    assert "general form" in shoulder and "0.15 length units" in shoulder
    # the wrist says which rotation it loses
    wrist = " ".join(views[2].readings)
    assert "cannot rotate the end-effector about the common normal" in wrist
    assert views[2].axes == (4, 6) and len(views[2].lost_axis) == 3


def test_lost_wrist_rotation_is_orthogonal_to_the_wrist_axes(puma):
    """The rotation the wrist loses is normal to the directions of axes 4, 5 and 6 there."""
    from rankloci.geometry import axis_lines

    model, views = puma
    c = views[2].component
    lines, _ = axis_lines(model, c.sample)
    n = np.array(views[2].lost_axis)
    assert abs(np.linalg.norm(n) - 1) < 1e-9
    for j in (4, 5, 6):
        assert abs(lines[j - 1].direction @ n) < 1e-7


def test_facts_hold_on_the_component_and_not_off_it(puma):
    """The fact behind the wrist reading is checked: it holds at q5 = 0 and not at q5 = 0.3."""
    model, _ = puma
    q = {"q1": 0.3, "q2": 0.2, "q3": -0.4, "q4": 0.5, "q5": 0.0, "q6": 0.1}
    assert ("collinear", 4, 6) in facts_at(model, q, None)
    assert ("collinear", 4, 6) not in facts_at(model, dict(q, q5=0.3), None)


@pytest.mark.slow
def test_pa10_readings_are_distinct_and_cover_every_factor(pa10):
    _, views = pa10
    _check_complete_and_distinct(views)
    by_eqs = {tuple(sorted(map(str, v.component.equations))): v for v in views}
    both = by_eqs[("sin(q2)", "sin(q6)")].readings[0]
    assert both.startswith("Shoulder and wrist singularities at once")
    assert "axes 1 and 3 are collinear" in both and "axes 5 and 7 are collinear" in both


@pytest.mark.parametrize("name, expected", [
    ("planar4r", "All links aligned"),
    ("planar2r", "All links aligned"),
    ("ur5", "Shoulder singularity: the point where axes 5 and 6 meet lies in the plane "
            "through axis 1"),
])
def test_classical_names(name, expected):
    _, views = _views(name)
    _check_complete_and_distinct(views)
    assert any(v.readings[0].startswith(expected) for v in views), \
        [v.readings[0] for v in views]
    assert any(v.summary.startswith(expected.split(":")[0]) for v in views)


def test_dependent_joints_finds_the_smallest_dependent_set():
    J = np.array([[1.0, 0.0, 2.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]])
    assert dependent_joints([J], ["1", "2", "3", "4"]) == ("1", "3")
    assert dependent_joints([np.eye(3)], ["a", "b", "c"]) == ()


def test_facts_true_at_every_pose_are_not_stated_as_the_components(puma):
    _, views = puma
    # axes 2 and 3 of the PUMA are parallel at every pose: the elbow reading names the plane
    elbow = views[1].readings[0]
    assert elbow.endswith("the task point lies in the plane of axes 2 and 3")
    assert "are parallel" not in elbow
    # UR5: axes 2, 3 and 4 are always parallel; what the component adds is 4 || 6
    _, ur5 = _views("ur5")
    texts = [v.readings[0] for v in ur5]
    assert any(t.startswith("Wrist singularity: axes 4 and 6 are parallel") for t in texts), texts
    assert not any("axes 2, 3, 4 and 6" in t for t in texts), texts


def test_a_lost_direction_with_force_and_moment_is_labelled_a_wrench(puma):
    _, views = puma
    wrist = views[2].motions[0]
    assert wrist.startswith("no motion with a.v + b.w != 0; as a wrench, force a = [")
    assert "moment b = [" in wrist and "needs no joint torque" in wrist
    assert views[1].motions[0].startswith("no translation along [")
    assert not any(x in m for v in views for m in v.motions for x in ("+0.00", "-0.00"))
