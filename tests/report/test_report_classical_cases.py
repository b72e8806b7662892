"""Classical cases named from the geometry on arms the readings were not written for.

The Stanford arm (a prismatic boom), the KUKA iiwa 7 R800 (d3 = d5: the wrist centre can
reach the shoulder centre), the SSRMS (shoulder and wrist at once) and the SSRMS with joint 3
locked (no tautology about dependent columns); the PUMA elbow's q3, fixed once a3 and d4 have
values, is printed with its exact values.
"""

from __future__ import annotations

import pytest
import sympy as sp

from rankloci.augmented import augmented_locus
from rankloci.io import load_model
from rankloci.jacobians import task_matrix
from rankloci.methods import method_for
from rankloci.methods.readable import solved_at_values
from rankloci.reporting.build import component_views

SEED = 0


def _views(name):
    model = load_model(name)
    tm = task_matrix(model, frame="auto")
    locus = augmented_locus(model, tm, method_for(tm.shape), seed=SEED)
    views = [v for v in component_views(model, locus, seed=SEED) if not v.special]
    return {tuple(sorted(map(str, v.component.equations))): v for v in views}


def test_stanford_boom_shoulder_and_wrist():
    views = _views("stanford")
    boom = views[("q3",)].readings[0]
    assert boom.startswith("Boom singularity (the boom, joint 3, at zero extension)"), boom
    shoulder = views[("sin(q2)",)].readings[0]
    assert shoulder.startswith("Shoulder singularity: the prismatic joint 3 slides parallel "
                               "to axis 1"), shoulder
    wrist = views[("sin(q5)",)].readings[0]
    assert wrist.startswith("Wrist singularity: axes 4 and 6 are collinear"), wrist


def test_stanford_boom_at_zero_is_outside_the_stroke_exactly():
    from rankloci.limits import within_limits

    model = load_model("stanford")
    tm = task_matrix(model, frame="auto")
    locus = augmented_locus(model, tm, method_for(tm.shape), seed=SEED)
    checks = within_limits(locus, model)
    boom = next(c for c, comp in zip(checks, locus.components)
                if [str(e) for e in comp.equations] == ["q3"])
    assert boom.meets is False and boom.how == "exact"


def test_iiwa_wrist_centre_on_the_shoulder_has_its_own_reading():
    views = _views("iiwa")
    stretched = views[("sin(q4/2)",)]
    folded = views[("cos(q4/2)",)]
    assert folded.component.rank_drop == 2
    assert stretched.readings[0] != folded.readings[0]
    text = folded.readings[0]
    assert text.startswith("Wrist centre on the shoulder: the point where axes 5, 6 and 7 meet "
                           "coincides with the point where axes 1, 2 and 3 meet"), text
    # d3 = d5 = 0.4: both centres are as far from the elbow axis, which is why they can meet
    assert "Both points lie 0.4 length units from axis 4" in text
    assert "rank of J is at most 4" in text
    assert stretched.readings[0].startswith("Elbow singularity")


@pytest.mark.slow
def test_ssrms_component_with_c2_and_c6_is_shoulder_and_wrist_at_once():
    views = _views("ssrms")
    both = views[("cos(q2)", "cos(q6)")].readings[0]
    assert both.startswith("Shoulder and wrist singularities at once"), both


def test_ssrms_lock3_states_no_tautology():
    views = _views("ssrms_lock3")
    for v in views.values():
        text = " ".join(v.readings)
        assert "columns of joints 1, 2, 4, 5, 6 and 7" not in text, text
        # what is said instead: no smaller set of joints, no axis fact
        assert text.startswith("No fact about the axes holds at all"), text
        assert "no set of fewer than 6 joints has dependent columns" in text


def test_puma_elbow_angle_is_solved_at_the_parameter_values():
    model = load_model("puma560")
    named = {str(k): k for k in model.parameters}
    a3, d4, q3 = named["a3"], named["d4"], model.variables[2]
    found = solved_at_values([a3 * sp.sin(q3) + d4 * sp.cos(q3)], [q3], model.parameters)
    values = sorted(float(v) for v in found[q3])
    a, d = float(model.parameters[a3]), float(model.parameters[d4])
    assert len(values) == 2 and values[1] - values[0] == pytest.approx(float(sp.pi))
    for v in values:    # each value is a root, not a rounded guess
        assert abs(a * sp.sin(v) + d * sp.cos(v)) < 1e-12


def test_report_prints_the_values_solved_at_the_parameter_values():
    from types import SimpleNamespace

    from rankloci.reporting.findings import _solved_at_values

    model = load_model("puma560")
    named = {str(k): k for k in model.parameters}
    q3 = model.variables[2]
    elbow = SimpleNamespace(equations=(named["a3"] * sp.sin(q3) + named["d4"] * sp.cos(q3),))
    report = SimpleNamespace(locus=SimpleNamespace(parameters=model.parameters),
                             tm=SimpleNamespace(variables=model.variables))
    text = _solved_at_values(report, elbow)
    assert text.startswith("$q_{3} \\in \\lbrace") and "\\approx -1.52382" in text, text
    assert "\\approx 1.61777" in text
