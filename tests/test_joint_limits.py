"""Which components meet the joint-limit box: exact where a variable is solved, else searched."""

import dataclasses
import math

import numpy as np
import pytest

import rankloci
from rankloci.limits import (DEFAULT_STROKE, LIMIT_SEARCH_STARTS, joint_kinds, joint_strokes,
                             within_limits)

DEG = math.pi / 180
#: Corke's mdl_puma560 limits, as in kinematics_models/puma560.toml.
PUMA_LIMITS = [(-160 * DEG, 160 * DEG), (-45 * DEG, 225 * DEG), (-225 * DEG, 45 * DEG),
               (-110 * DEG, 170 * DEG), (-100 * DEG, 100 * DEG), (-266 * DEG, 266 * DEG)]


def limited(model, limits):
    return dataclasses.replace(model, joints=tuple(
        dataclasses.replace(j, limits=lim) for j, lim in zip(model.joints, limits)))


@pytest.fixture(scope="module")
def puma():
    arm = rankloci.load_model("puma560")
    return arm, rankloci.locus(arm, numeric=True)


def inside(sample, names, limits):
    return all(lim is None or lim[0] <= sample[n] <= lim[1] for n, lim in zip(names, limits))


def test_without_limits_every_component_meets_the_box_at_its_sample(puma):
    arm, L = puma
    free = limited(arm, [None] * 6)
    checks = within_limits(L, free)
    assert [c.meets for c in checks] == [True] * len(L.components)
    assert all(c.how == "no joint limits" for c in checks)
    assert [c.sample for c in checks] == [dict(c.sample) for c in L.components]


def test_samples_inside_the_limits_are_points_of_the_locus(puma):
    arm, L = puma
    names = [str(v) for v in L.variables]
    checks = within_limits(L, limited(arm, PUMA_LIMITS), rng=np.random.default_rng(1))
    assert [c.component for c in checks] == list(range(1, len(L.components) + 1))
    for c in checks:
        assert c.meets is True, c
        assert inside(c.sample, names, PUMA_LIMITS)
        assert L.contains(c.sample)


def test_a_solved_value_outside_the_limits_is_decided_exactly(puma):
    arm, L = puma
    # the wrist component fixes q5 at 0 or pi (and their turns); keep q5 away from both
    limits = list(PUMA_LIMITS)
    limits[4] = (10 * DEG, 100 * DEG)
    checks = within_limits(L, limited(arm, limits))
    wrist = next(c for c, comp in zip(checks, L.components)
                 if [str(v) for v in comp.solved] == ["q5"])
    assert (wrist.meets, wrist.how, wrist.sample) == (False, "exact", None)
    assert "q5 is fixed at 0, pi" in wrist.reason


def test_the_numeric_search_finds_points_away_from_the_sample(puma):
    arm, L = puma
    names = [str(v) for v in L.variables]
    # q1 is free on every component; a narrow range of it excludes the engine's samples
    limits = [(2.0, 2.05)] + [None] * 5
    for comp, check in zip(L.components, within_limits(L, limited(arm, limits))):
        assert not 2.0 <= comp.sample["q1"] <= 2.05
        assert check.meets is True and check.how == "numeric search"
        assert inside(check.sample, names, limits) and L.contains(check.sample)


def test_a_component_the_search_does_not_reach_is_left_undecided(puma):
    arm, L = puma
    # near q2 = q3 = 0 the wrist centre is far from axis 1: the shoulder component is not there
    limits = [None, (0.1, 0.2), (-0.1, 0.1), None, None, None]
    shoulder = within_limits(L, limited(arm, limits))[0]
    assert not L.components[0].solved
    assert (shoulder.meets, shoulder.sample, shoulder.how) == (None, None, "numeric search")
    assert f"{LIMIT_SEARCH_STARTS} starts" in shoulder.reason
    assert shoulder.to_dict() == {"meets": None, "sample": None, "how": "numeric search",
                                  "reason": shoulder.reason}


def test_strokes_are_the_limits_else_a_turn_or_the_default_stroke():
    arm = rankloci.load_model("planar2r")
    slide = dataclasses.replace(arm.joints[1], kind="prismatic")
    model = dataclasses.replace(arm, joints=(arm.joints[0], slide))
    assert joint_kinds(model) == ("revolute", "prismatic")
    assert joint_strokes(model) == ((-math.pi, math.pi), DEFAULT_STROKE)
    assert joint_strokes(limited(model, [(0.0, 1.0), (0.1, 0.3)])) == ((0.0, 1.0), (0.1, 0.3))


def test_a_locus_of_another_model_is_refused(puma):
    _, L = puma
    with pytest.raises(ValueError, match="not a locus of this model"):
        within_limits(L, rankloci.load_model("planar2r"))
