"""Pinocchio models as a user has them: a RobotWrapper, a free-flyer root, a chain between any
two frames.  Each chain's Jacobian is checked against the one Pinocchio computes for the same
two frames (the tip's motion relative to the base, in the base's axes)."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import rankloci
from rankloci.adapters import from_pinocchio
from rankloci.errors import ModelError
from rankloci.tolerances import FOREIGN_JACOBIAN_RTOL

SEED = 20261207


def _se3(xyz, rx=0.0):
    """A placement: a rotation about x by ``rx`` (a multiple of pi/12: exact in rankloci)."""
    c, s = np.cos(rx), np.sin(rx)
    R = np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
    return pin.SE3(R, np.array(xyz, dtype=float))


@pytest.fixture(scope="module")
def two_arms():
    """A floating torso (free-flyer root) with two arms: l1 l2 l3 -> l_hand, r1 r2 -> r_hand."""
    m = pin.Model()
    m.name = "two_arms"
    root = m.addJoint(0, pin.JointModelFreeFlyer(), pin.SE3.Identity(), "root_joint")
    m.addFrame(pin.Frame("torso", root, pin.SE3.Identity(), pin.FrameType.BODY))
    l1 = m.addJoint(root, pin.JointModelRZ(), _se3([0.0, 0.2, 0.1]), "l1")
    m.addFrame(pin.Frame("upper_arm", l1, pin.SE3.Identity(), pin.FrameType.BODY))
    l2 = m.addJoint(l1, pin.JointModelRY(), _se3([0.3, 0.0, 0.0], np.pi / 2), "l2")
    l3 = m.addJoint(l2, pin.JointModelRY(), _se3([0.25, 0.0, 0.05]), "l3")
    m.addFrame(pin.Frame("l_hand", l3, _se3([0.2, 0.0, 0.0]), pin.FrameType.OP_FRAME))
    r1 = m.addJoint(root, pin.JointModelRZ(), _se3([0.0, -0.2, 0.1], -np.pi / 6), "r1")
    r2 = m.addJoint(r1, pin.JointModelPX(), _se3([0.3, 0.0, 0.0]), "r2")
    m.addFrame(pin.Frame("r_hand", r2, _se3([0.25, 0.0, 0.05]), pin.FrameType.OP_FRAME))
    return m


def _relative_jacobian(model, q, base, tip, joints):
    """Pinocchio's Jacobian of the tip's origin relative to the base frame, in the base's axes:
    linear rows R_b^T (J_t - J_b + [p_t - p_b]x w_b), angular rows R_b^T (w_t - w_b), the
    columns of ``joints`` (names) in order."""
    data = model.createData()
    pin.computeJointJacobians(model, data, q)
    pin.updateFramePlacements(model, data)
    fb, ft = model.getFrameId(base), model.getFrameId(tip)
    Jb = pin.getFrameJacobian(model, data, fb, pin.LOCAL_WORLD_ALIGNED)
    Jt = pin.getFrameJacobian(model, data, ft, pin.LOCAL_WORLD_ALIGNED)
    Rb = data.oMf[fb].rotation
    d = data.oMf[ft].translation - data.oMf[fb].translation
    cross = np.array([[0.0, -d[2], d[1]], [d[2], 0.0, -d[0]], [-d[1], d[0], 0.0]])
    lin = Rb.T @ (Jt[:3] - Jb[:3] + cross @ Jb[3:])
    ang = Rb.T @ (Jt[3:] - Jb[3:])
    cols = [model.joints[model.getJointId(n)].idx_v for n in joints]
    return np.vstack([lin, ang])[:, cols]


def _same_jacobian(model, robot, base, tip, trials=4):
    pin.seed(SEED)  # pinocchio's random configurations
    J = rankloci.jacobian(robot, numeric=True)
    names = [j.name for j in robot.joints]
    for _ in range(trials):
        q = pin.randomConfiguration(model, -np.ones(model.nq), np.ones(model.nq))
        chain = np.array([q[model.joints[model.getJointId(n)].idx_q] for n in names])
        theirs = _relative_jacobian(model, q, base, tip, names)
        mine = J.evaluate(chain)
        scale = np.linalg.svd(theirs, compute_uv=False)[0]
        assert np.abs(mine - theirs).max() <= FOREIGN_JACOBIAN_RTOL * scale, (base, tip, q)


def test_a_free_flyer_root_is_left_out_by_default(two_arms):
    robot = from_pinocchio(two_arms, tip="l_hand")
    assert [j.name for j in robot.joints] == ["l1", "l2", "l3"]
    # the chain starts in the body the free-flyer carries: the same Jacobian as from "torso"
    _same_jacobian(two_arms, robot, "torso", "l_hand")
    assert rankloci.jacobian(robot).matrix == rankloci.jacobian(
        from_pinocchio(two_arms, tip="l_hand", base_link="torso")).matrix


def test_a_chain_from_frame_to_frame_across_the_tree(two_arms):
    """From the left hand to the right hand: up through l3 l2 l1 (reversed), down r1 r2."""
    robot = from_pinocchio(two_arms, base_link="l_hand", tip="r_hand")
    assert [j.name for j in robot.joints] == ["l3", "l2", "l1", "r1", "r2"]
    assert [j.kind for j in robot.joints] == ["revolute"] * 4 + ["prismatic"]
    _same_jacobian(two_arms, robot, "l_hand", "r_hand")


def test_a_chain_that_starts_below_the_root(two_arms):
    robot = from_pinocchio(two_arms, base_link="l1", tip="l_hand")   # a joint's name: its frame
    assert [j.name for j in robot.joints] == ["l2", "l3"]
    _same_jacobian(two_arms, robot, "upper_arm", "l_hand")


def test_a_robot_wrapper_is_its_model(two_arms):
    wrapper = pin.RobotWrapper(two_arms)
    L = rankloci.locus(wrapper, tip="l_hand", task="position")
    assert L == rankloci.locus(two_arms, tip="l_hand", task="position")
    assert L.joint_names == ("l1", "l2", "l3") and len(L.components) > 0
    assert rankloci.load_model(wrapper, tip="r_hand", base_link="l_hand").dof == 5


def test_a_free_flyer_between_the_frames_is_refused(two_arms):
    with pytest.raises(ModelError, match="'root_joint' is a JointModelFreeFlyer.*base_link="):
        from_pinocchio(two_arms, base_link="universe", tip="l_hand")
    with pytest.raises(ModelError, match="no frame 'nowhere' in the model \\(base_link\\)"):
        from_pinocchio(two_arms, base_link="nowhere", tip="l_hand")
    with pytest.raises(ModelError, match="no joint between the base and the tip"):
        from_pinocchio(two_arms, base_link="l_hand", tip="l_hand")


def test_a_urdf_loaded_on_a_free_flyer_gives_the_fixed_arms_chain(robots):
    """example-robot-data's UR5 read by Pinocchio with a free-flyer root (as a mobile base or
    a humanoid is read): its chain to tool0 is the one of the fixed arm, free-flyer left out."""
    urdf = str(robots / "ur_description" / "urdf" / "ur5_robot.urdf")
    fixed = pin.buildModelFromUrdf(urdf)
    floating = pin.buildModelFromUrdf(urdf, pin.JointModelFreeFlyer())
    assert floating.joints[1].shortname() == "JointModelFreeFlyer"
    assert from_pinocchio(floating, tip="tool0") == from_pinocchio(fixed, tip="tool0")
    # a sub-chain between two links: the chain rankloci reads from the file between them (the
    # file's rounded angles are snapped to exact ones alike in both)
    wrist = from_pinocchio(floating, base_link="forearm_link", tip="tool0")
    assert [j.name for j in wrist.joints] == ["wrist_1_joint", "wrist_2_joint", "wrist_3_joint"]
    mine = rankloci.jacobian(wrist, numeric=True)
    read = rankloci.jacobian(urdf, base_link="forearm_link", tip="tool0", numeric=True)
    Q = np.random.default_rng(SEED).uniform(-np.pi, np.pi, (5, 3))
    A, B = mine.evaluate(Q), read.evaluate(Q)
    scale = np.linalg.svd(B, compute_uv=False)[:, 0]
    assert np.all(np.abs(A - B).max(axis=(1, 2)) <= FOREIGN_JACOBIAN_RTOL * scale)
