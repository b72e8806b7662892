"""Models from Robotics Toolbox for Python and Pinocchio against rankloci's own readings.

The toolbox's DH models of the PUMA 560 and the UR5 must give the same locus as
kinematics_models/puma560.toml and ur5.toml (their names and lengths agree, except
d1, which moves every frame along axis 1 and so leaves the rank alone); its Panda
the same as example-robot-data's Panda URDF read by rankloci.  Each locus is also
checked with the other library's own Jacobian: singular at points of every
component, regular at random points off the locus.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
import roboticstoolbox as rtb
import sympy as sp

import rankloci
from rankloci.adapters import from_pinocchio, from_rtb
from rankloci.errors import ModelError
from rankloci.numeric.equations import normalised
from rankloci.numeric.svd import sigma_ratio
from rankloci.tolerances import RANK_RTOL, REGULAR_MIN_RATIO

SEED = 20261201


def _equation_sets(components):
    """Each component's equations, each divided by its largest coefficient, as sorted text."""
    return sorted(tuple(sorted(sp.sstr(normalised(sp.expand(e))) for e in c.equations))
                  for c in components)


def _agrees_with(locus, jacobian, rng, *, off: int = 20):
    """``jacobian(q)`` (another library's) is singular at every component's sample point and
    regular at random points that the locus does not contain."""
    for c in locus.components:
        q = np.array([c.sample[str(v)] for v in locus.variables])
        assert sigma_ratio(jacobian(q)) <= RANK_RTOL, (c, q)
    n = len(locus.variables)
    for q in rng.uniform(-np.pi, np.pi, (off, n)):
        assert not locus.contains(q)
        assert sigma_ratio(jacobian(q)) > REGULAR_MIN_RATIO, q


@pytest.mark.parametrize("rtb_name, own", [("Puma560", "puma560"), ("UR5", "ur5")])
def test_rtb_dh_models_give_the_loci_of_our_files(rtb_name, own):
    robot = getattr(rtb.models.DH, rtb_name)()
    mine = rankloci.locus(robot)                   # accepted directly, as from_rtb(robot)
    theirs = rankloci.locus(own)
    assert _equation_sets(mine.components) == _equation_sets(theirs.components)
    assert _equation_sets(mine.special) == _equation_sets(theirs.special)
    assert mine.variables == theirs.variables
    _agrees_with(mine, lambda q: np.asarray(robot.jacob0(q)), np.random.default_rng(SEED))


def test_rtb_model_keeps_base_tool_offsets_and_convention():
    panda = from_rtb(rtb.models.DH.Panda())
    assert panda.convention == "mdh" and panda.dof == 7
    assert panda.tool[2, 3] == sp.Rational(103, 1000)          # 0.103, not 0.10300000000000001
    assert panda.tool[0, 0] == sp.sqrt(2) / 2                 # the -pi/4 hand, exact
    assert sorted(p.name for p in panda.parameters) == ["a4", "a5", "a7", "d1", "d3", "d5", "d7"]
    numbers = from_rtb(rtb.models.DH.Puma560(), symbolic=False)
    assert numbers.parameters == {}
    q = np.random.default_rng(SEED).uniform(-np.pi, np.pi, 6)
    T = rankloci.kinematics.forward_kinematics(numbers)
    fk = np.array(T.subs(dict(zip(numbers.variables, q))).evalf(), dtype=float)
    assert np.allclose(fk, rtb.models.DH.Puma560().fkine(q).A, atol=1e-12)


@pytest.mark.slow
def test_rtb_panda_gives_the_locus_of_the_panda_urdf(robots):
    """7 joints: about 10 s a locus; both with numeric parameters, no self-check."""
    robot = rtb.models.DH.Panda()
    mine = rankloci.locus(robot, numeric=True, verify=False)
    urdf = robots / "panda_description" / "urdf" / "panda.urdf"
    theirs = rankloci.locus(urdf, tip="panda_link8", numeric=True, verify=False)
    assert len(mine.components) == 5
    assert _equation_sets(mine.components) == _equation_sets(theirs.components)
    model = pin.buildModelFromUrdf(str(urdf))
    data, frame = model.createData(), model.getFrameId("panda_link8")

    def pinocchio_jacobian(q):
        return pin.computeFrameJacobian(model, data, np.concatenate([q, [0.0, 0.0]]), frame,
                                        pin.LOCAL_WORLD_ALIGNED)[:, :7]

    _agrees_with(mine, pinocchio_jacobian, np.random.default_rng(SEED), off=10)
    _agrees_with(theirs, lambda q: np.asarray(robot.jacob0(q)), np.random.default_rng(SEED + 1),
                 off=10)


def test_pinocchio_ur5_gives_the_locus_of_its_urdf(robots):
    urdf = robots / "ur_description" / "urdf" / "ur5_robot.urdf"
    model = pin.buildModelFromUrdf(str(urdf))
    mine = rankloci.locus(model, tip="tool0", numeric=True)
    theirs = rankloci.locus(urdf, tip="tool0", numeric=True)
    assert len(mine.components) == 3
    assert _equation_sets(mine.components) == _equation_sets(theirs.components)
    data, frame = model.createData(), model.getFrameId("tool0")
    _agrees_with(mine, lambda q: pin.computeFrameJacobian(model, data, q, frame,
                                                          pin.LOCAL_WORLD_ALIGNED),
                 np.random.default_rng(SEED))


def test_refusals_name_the_problem():
    with pytest.raises(ModelError, match="from_rtb takes a roboticstoolbox DHRobot"):
        from_rtb(object())
    flipped = rtb.DHRobot([rtb.RevoluteDH(a=1.0, flip=True), rtb.RevoluteDH(a=0.5)])
    with pytest.raises(ModelError, match="link 1 is flipped"):
        from_rtb(flipped)
    # a twist without an exact radical cosine is made an exact rational rotation, as in a
    # DH file or a URDF, and the note says so
    odd = rtb.DHRobot([rtb.RevoluteDH(a=1.0, alpha=0.3), rtb.RevoluteDH(a=0.5)])
    locus = rankloci.locus(odd)
    assert locus.complete is True
    assert any("constant angle 3/10" in n for n in locus.notes)
    free = pin.Model()
    free.addJoint(0, pin.JointModelFreeFlyer(), pin.SE3.Identity(), "base")
    with pytest.raises(ModelError, match="below the root joint 'base', a JointModelFreeFlyer"):
        from_pinocchio(free)
    with pytest.raises(ModelError, match="no frame 'nowhere'"):
        from_pinocchio(free, tip="nowhere")
    with pytest.raises(ModelError, match="takes a pinocchio.Model"):
        from_pinocchio(object())
