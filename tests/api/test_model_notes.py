"""What a locus takes from its model: a word on an empty full-task locus, URDF joint names."""

from __future__ import annotations

import json
import logging

import numpy as np
import pytest

import rankloci
from rankloci.errors import ArgumentError
from small_urdfs import ARM3

NAMES = ("shoulder_pan", "shoulder_lift", "elbow")


@pytest.fixture
def arm3(tmp_path):
    path = tmp_path / "arm3.urdf"
    path.write_text(ARM3)
    return path


def test_an_empty_full_task_locus_says_why_and_what_to_try(arm3, caplog):
    with caplog.at_level(logging.WARNING, logger="rankloci"):
        L = rankloci.locus(arm3)
    assert L.shape == (6, 3) and L.components == ()
    note = [n for n in L.notes if n.startswith("the task has 6 rows")]
    assert len(note) == 1 and "3 joints" in note[0] and 'task="position"' in note[0]
    warned = [r for r in caplog.records if r.name == "rankloci" and r.levelno == logging.WARNING]
    assert len(warned) == 1 and 'task="position"' in warned[0].getMessage()


def test_the_suggested_task_finds_the_arms_singularities_without_the_note(arm3, caplog):
    with caplog.at_level(logging.WARNING, logger="rankloci"):
        L = rankloci.locus(arm3, task="position")
    assert len(L.components) == 2                       # elbow straight, wrist on the pan axis
    assert not any(n.startswith("the task has") for n in L.notes)
    assert not [r for r in caplog.records if r.levelno == logging.WARNING]


def test_a_task_that_fits_the_joints_gets_no_note():
    assert not any(n.startswith("the task has") for n in rankloci.locus("planar2r").notes)


def test_urdf_variables_are_named_after_their_joints(arm3):
    L = rankloci.locus(arm3, task="position")
    assert [str(v) for v in L.variables] == ["q1", "q2", "q3"]
    assert L.joint_names == NAMES
    assert "joint variables of the URDF joints: q1 = shoulder_pan, q2 = shoulder_lift, " \
           "q3 = elbow" in L.notes
    assert "joint_names" not in L.to_dict()              # the schema stays as it was
    assert rankloci.locus("puma560", numeric=True).joint_names == ()


def test_contains_takes_urdf_joint_names(arm3):
    L = rankloci.locus(arm3, task="position")
    rng = np.random.default_rng(11)
    points = np.vstack([rng.uniform(-3, 3, size=(4, 3)), [[0.2, -0.7, 0.0]]])
    for q in points:
        by_joint = dict(zip(NAMES, q))
        assert L.contains(by_joint) == L.contains(q)
    assert L.contains({"shoulder_pan": 0.2, "shoulder_lift": -0.7, "elbow": 0.0})
    assert L.contains({"q1": 0.2, "shoulder_lift": -0.7, "elbow": 0.0})   # names may mix
    with pytest.raises(ArgumentError, match="'wrist' is not a variable or joint name"):
        L.contains({"shoulder_pan": 0.2, "shoulder_lift": -0.7, "wrist": 0.0})
    with pytest.raises(ArgumentError, match="twice"):
        L.contains({"q3": 0.0, "elbow": 0.0, "q1": 0.0, "q2": 0.0})


def test_the_json_of_rankloci_locus_maps_variables_to_joints(arm3, capsys):
    from rankloci.cli import main

    assert main(["locus", str(arm3), "--task", "position", "--format", "json", "--quiet"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["joint_names"] == dict(zip(("q1", "q2", "q3"), NAMES))
    back = rankloci.Locus.from_dict(data)
    assert back.joint_names == NAMES and back.contains({"elbow": 0.0, "shoulder_pan": 0.2,
                                                          "shoulder_lift": -0.7})
    assert main(["locus", "planar2r", "--format", "json", "--quiet"]) == 0
    assert "joint_names" not in json.loads(capsys.readouterr().out)


def test_the_command_line_prints_the_note_of_an_empty_full_task_locus(arm3, capsys):
    from rankloci.cli import main

    main(["locus", str(arm3), "--quiet"])
    out = capsys.readouterr().out
    assert "note: the task has 6 rows" in out and "--task position" in out
