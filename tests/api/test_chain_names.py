"""One name per option: every call that takes a model takes ``tip=`` and ``base_link=``."""

from __future__ import annotations

import inspect

import numpy as np
import pytest

import rankloci
from rankloci.errors import ArgumentError
from small_urdfs import ARM3

#: An arm with two tools hanging off its last link: no single leaf.
FORK = ARM3.replace("</robot>", """  <link name="camera"/>
  <joint name="camera_mount" type="fixed"><parent link="l3"/><child link="camera"/></joint>
</robot>
""")

TAKE_A_MODEL = ["load_model", "jacobian", "locus", "check", "report", "manipulability",
                "joint_rates", "nearest_component"]


@pytest.fixture
def urdf(tmp_path):
    (tmp_path / "arm3.urdf").write_text(ARM3)
    (tmp_path / "fork.urdf").write_text(FORK)
    return tmp_path


@pytest.mark.parametrize("name", TAKE_A_MODEL)
def test_every_call_that_takes_a_model_spells_the_chain_tip_and_base_link(name):
    parameters = inspect.signature(getattr(rankloci, name)).parameters
    assert "tip" in parameters and "base_link" in parameters
    assert "tip_link" not in parameters


def test_locus_and_jacobian_take_a_base_link_and_a_tip(urdf):
    path = urdf / "arm3.urdf"
    L = rankloci.locus(path, base_link="l1", tip="l3", task=[0, 2])
    assert len(L.variables) == 2 and L.joint_names == ("shoulder_lift", "elbow")
    J = rankloci.jacobian(path, base_link="l1", tip="l3")
    assert J.shape[1] == 2
    assert rankloci.is_singular(path, {"shoulder_lift": 0.3, "elbow": 0.0}, base_link="l1",
                                tip="l3", task=[0, 2])
    m = rankloci.manipulability(path, [0.1, 0.2], base_link="l1", tip="l3")
    assert m.J.shape[1] == 2 and np.isfinite(m.ellipsoid.w)


def test_chain_errors_name_the_arguments_not_the_flags(urdf):
    with pytest.raises(ArgumentError, match=r"^tip=: tip link 'nope' is not a link") as info:
        rankloci.locus(urdf / "arm3.urdf", tip="nope")
    assert info.value.argument == "tip"
    with pytest.raises(ArgumentError, match="^base_link=: base link 'nope'"):
        rankloci.jacobian(urdf / "arm3.urdf", base_link="nope")
    with pytest.raises(ArgumentError, match="choose the tip link with tip=") as info:
        rankloci.load_model(urdf / "fork.urdf")
    assert "--" not in str(info.value)
    assert rankloci.load_model(urdf / "fork.urdf", tip="tool").dof == 3
