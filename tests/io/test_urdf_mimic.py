"""Tests of URDF mimic joints (rankloci.io.urdf).

A mimic joint moves by ``multiplier * q + offset`` of the joint it follows and
has no variable of its own.  The imported model is checked against a numpy
composition of the URDF written here, with the coupling applied by hand: its
forward kinematics, finite differences of that composition, and the Jacobian
of the same chain without the ``<mimic>`` elements times the coupling matrix
``d q_all / d q`` (the chain rule).  A real gripper from example-robot-data is
checked the same way and against Pinocchio's own mimic joints.
"""

from __future__ import annotations

import math
import re

import defusedxml.ElementTree as SafeET
import numpy as np
import pytest
import sympy as sp

from rankloci.errors import ModelError
from rankloci.io.urdf import parse_urdf, read_urdf
from rankloci.kinematics import forward_kinematics, geometric_jacobian
from rankloci.model import Mimic
from rankloci.tolerances import URDF_ROTATION_ATOL
from urdf_reference import rot, snapped, snapped_length

SEED = 20240612

# Poses are O(1 m) from ~20 double-precision products: agreement to ~1e-15.
FK_ATOL = 1e-12
# A rotation or mimic offset that does not snap to a multiple of pi/12 is read as a short exact
# rational rotation within URDF_ROTATION_ATOL rad; these documents have fewer than 10 of them
# (origins, offsets and axes), with lever arms below 1 m.
READ_ATOL = FK_ATOL + 10 * URDF_ROTATION_ATOL
# Central differences: truncation FD_STEP**2/6 * |p'''| ~ 1e-13 at reach ~1 m,
# rounding eps * |p| / FD_STEP ~ 1e-10; FD_ATOL leaves a factor 100.
FD_STEP = 1e-6
FD_ATOL = 1e-8


# --- documents ----------------------------------------------------------------

def _joint(name, jtype, parent, child, extra=""):
    return (f'<joint name="{name}" type="{jtype}"><parent link="{parent}"/>'
            f'<child link="{child}"/>{extra}</joint>')


def _urdf(*joints: str) -> str:
    links = sorted({link for j in joints for link in re.findall(r'link="([^"]+)"', j)})
    return ('<robot name="r">' + "".join(f'<link name="{n}"/>' for n in links)
            + "".join(joints) + "</robot>")


def _mimic(leader, multiplier=None, offset=None) -> str:
    attrs = f'joint="{leader}"'
    attrs += "" if multiplier is None else f' multiplier="{multiplier}"'
    attrs += "" if offset is None else f' offset="{offset}"'
    return f"<mimic {attrs}/>"


TIP = _joint("flange", "fixed", "d", "e", '<origin xyz="0.05 0 0.02" rpy="0 0.3 0"/>')
LIMITS = '<limit lower="-0.5" upper="0.7" effort="1" velocity="1"/>'

# case -> (document, tip link, number of variables, expected joint coordinates as strings)
DOCS = {
    "finger follows an earlier joint, with offset": (
        _urdf(_joint("j1", "revolute", "a", "b", '<origin xyz="0 0 0.3"/><axis xyz="0 0 1"/>'),
              _joint("j2", "revolute", "b", "c",
                     '<origin xyz="0.4 0 0" rpy="0.2 0 0"/><axis xyz="0 1 0"/>'),
              _joint("j3", "revolute", "c", "d",
                     '<origin xyz="0.3 0.1 0"/><axis xyz="0 0.6 0.8"/>' + _mimic("j1", -1, 0.3)),
              TIP),
        "e", 2, ["q1", "q2", "-q1"]),
    "joint follows a later joint, integer multiplier": (
        _urdf(_joint("j1", "revolute", "a", "b",
                     '<origin xyz="0 0 0.3"/><axis xyz="1 1 0"/>' + _mimic("j3", 2, -0.2)),
              _joint("j2", "prismatic", "b", "c", '<origin xyz="0.2 0 0"/><axis xyz="0 0 1"/>'),
              _joint("j3", "continuous", "c", "d",
                     '<origin xyz="0 0.3 0" rpy="0 0.4 0"/><axis xyz="0 1 0"/>'),
              TIP),
        "e", 2, ["2*q2", "q1", "q2"]),
    "prismatic fingers, fractional multiplier": (
        _urdf(_joint("j1", "revolute", "a", "b", '<origin xyz="0 0 0.3"/><axis xyz="0 0 1"/>'),
              _joint("j2", "prismatic", "b", "c", '<origin xyz="0.2 0 0"/><axis xyz="0 1 0"/>'),
              _joint("j3", "prismatic", "c", "d",
                     '<origin xyz="0.1 0 0" rpy="0.7 0 0"/><axis xyz="0 -1 0"/>'
                     + _mimic("j2", 0.5, 0.01)),
              TIP),
        "e", 2, ["q1", "q2", "q2/2"]),
    "mimic of a mimic off the chain": (
        _urdf(_joint("j1", "revolute", "a", "b", '<origin xyz="0 0 0.3"/><axis xyz="0 0 1"/>'),
              _joint("side", "revolute", "b", "x", '<axis xyz="0 0 1"/>' + _mimic("j1", -1, 0.1)),
              _joint("j2", "revolute", "b", "c",
                     '<origin xyz="0.4 0 0"/><axis xyz="0 1 0"/>' + _mimic("side", -1, 0.25)),
              _joint("j3", "revolute", "c", "d", '<origin xyz="0.3 0 0"/><axis xyz="1 0 0"/>'),
              TIP),
        "e", 2, ["q1", "q1", "q2"]),
    "composed multiplier is an integer": (
        _urdf(_joint("j1", "revolute", "a", "b", '<axis xyz="0 0 1"/>'),
              _joint("j2", "revolute", "b", "c",
                     '<origin xyz="0.4 0 0"/><axis xyz="0 0 1"/>' + _mimic("j3", 0.5)),
              _joint("j3", "revolute", "c", "d",
                     '<origin xyz="0.3 0 0"/><axis xyz="0 0 1"/>' + _mimic("j1", 2)),
              TIP),
        "e", 1, ["q1", "q1", "2*q1"]),
    "two fingers follow a leader off the chain": (
        _urdf(_joint("j1", "revolute", "a", "b", '<origin xyz="0 0 0.3"/><axis xyz="0 0 1"/>'),
              _joint("s1", "revolute", "b", "x", '<axis xyz="0 1 0"/>' + LIMITS),
              _joint("j2", "revolute", "b", "c",
                     '<origin xyz="0.4 0 0"/><axis xyz="0 1 0"/>' + _mimic("s1", -1, 0.2)),
              _joint("j3", "revolute", "c", "d",
                     '<origin xyz="0.3 0 0"/><axis xyz="1 0 0"/>' + _mimic("s1", 2, -0.1)),
              TIP),
        "e", 2, ["q1", "q2", "2*q2"]),
    "the second follower of a leader off the chain carries its variable": (
        _urdf(_joint("j1", "revolute", "a", "b", '<origin xyz="0 0 0.3"/><axis xyz="0 0 1"/>'),
              _joint("s1", "prismatic", "b", "x", '<axis xyz="0 1 0"/>' + LIMITS),
              _joint("j2", "prismatic", "b", "c",
                     '<origin xyz="0.4 0 0"/><axis xyz="0 1 0"/>' + _mimic("s1", 0.5, 0.01)),
              _joint("j3", "prismatic", "c", "d",
                     '<origin xyz="0.3 0 0" rpy="0.3 0 0"/><axis xyz="0 0 1"/>'
                     + _mimic("s1", -1, -0.02)),
              TIP),
        "e", 2, ["q1", "q2/2", "q2"]),
}


def _model(case):
    text, tip, _, _ = DOCS[case]
    return parse_urdf(text, name="m", tip=tip)


def _without_mimic(text: str) -> str:
    return re.sub(r"<mimic [^>]*/>", "", text)


# --- an independent numeric reading, coupling applied by hand --------------------


def _floats(el, attr, default):
    return [float(v) for v in (el.get(attr, default) if el is not None else default).split()]


class CoupledChain:
    """The chain base -> tip of a URDF in float64; mimic joints take ``m * q + o``."""

    def __init__(self, text: str, base: str | None, tip: str):
        root = SafeET.fromstring(text)
        self.joints = {j.get("name"): j for j in root.findall("joint")}
        by_child = {j.find("child").get("link"): j for j in root.findall("joint")}
        if base is None:
            base = next(link.get("name") for link in root.findall("link")
                        if link.get("name") not in by_child)
        chain, link = [], tip
        while link != base:
            chain.append(by_child[link])
            link = chain[-1].find("parent").get("link")
        self.chain = chain[::-1]
        # the variables: joints without a mimic, and each leader off the chain in the place of
        # its first follower with multiplier 1 or -1
        names = [j.get("name") for j in self.chain]
        self.free = []
        for name in names:
            leader, multiplier = name, 1.0
            while (m := self.joints[leader].find("mimic")) is not None:
                leader, multiplier = m.get("joint"), multiplier * float(m.get("multiplier", "1"))
            if self.joints[name].get("type") != "fixed" and (leader == name or (
                    leader not in names and leader not in self.free and abs(multiplier) == 1)):
                self.free.append(leader)

    def _value(self, name: str, q: dict) -> float:
        if name in q:
            return q[name]
        m = self.joints[name].find("mimic")
        leader = self._value(m.get("joint"), q)
        return float(m.get("multiplier", "1")) * leader + float(m.get("offset", "0"))

    def fk(self, q) -> np.ndarray:
        free = dict(zip(self.free, q))
        T = np.eye(4)
        for j in self.chain:
            o = j.find("origin")
            xyz = [snapped_length(x) for x in _floats(o, "xyz", "0 0 0")]
            rpy = [snapped(t) for t in _floats(o, "rpy", "0 0 0")]
            origin = np.eye(4)
            origin[:3, :3] = rot((0, 0, 1), rpy[2]) @ rot((0, 1, 0), rpy[1]) @ rot((1, 0, 0), rpy[0])
            origin[:3, 3] = xyz
            T = T @ origin
            if j.get("type") == "fixed":
                continue
            axis = _floats(j.find("axis"), "xyz", "1 0 0")
            v = self._value(j.get("name"), free)
            M = np.eye(4)
            if j.get("type") == "prismatic":
                M[:3, 3] = np.asarray(axis) / np.linalg.norm(axis) * v
            else:
                M[:3, :3] = rot(axis, v)
            T = T @ M
        return T

    def jacobian_fd(self, q) -> np.ndarray:
        """Central differences of :meth:`fk`: linear, then angular velocity (base frame)."""
        q = np.asarray(q, float)
        R = self.fk(q)[:3, :3]
        cols = []
        for k in range(len(q)):
            dq = np.zeros_like(q)
            dq[k] = FD_STEP
            Tp, Tm = self.fk(q + dq), self.fk(q - dq)
            W = (Tp[:3, :3] - Tm[:3, :3]) / (2 * FD_STEP) @ R.T  # skew(omega)
            cols.append(np.r_[(Tp[:3, 3] - Tm[:3, 3]) / (2 * FD_STEP), W[2, 1], W[0, 2], W[1, 0]])
        return np.array(cols).T


def _numeric(model):
    fk = sp.lambdify(model.variables, forward_kinematics(model), "numpy")
    jac = sp.lambdify(model.variables, geometric_jacobian(model, frame="base", point="tool",
                                                          task="full"), "numpy")
    return (lambda q: np.array(fk(*q), dtype=float)), (lambda q: np.array(jac(*q), dtype=float))


def _configurations(n, count=4, seed=SEED):
    rng = np.random.default_rng(seed)
    return [rng.uniform(-np.pi, np.pi, n) for _ in range(count)]


# --- small documents ------------------------------------------------------------

@pytest.mark.parametrize("case", list(DOCS))
def test_mimic_joints_have_no_variable_of_their_own(case):
    _, _, nvars, coords = DOCS[case]
    m = _model(case)
    assert m.dof == 3
    assert m.variables == tuple(sp.Symbol(f"q{i}", real=True) for i in range(1, nvars + 1))
    assert [str(c) for c in m.joint_coordinates] == coords
    free = [i for i, j in enumerate(m.joints) if j.mimic is None]
    assert [m.joint_coordinates[i] for i in free] == list(m.variables)
    for j, c in zip(m.joints, m.joint_coordinates):
        if j.mimic is not None:
            assert m.joints[j.mimic.joint].mimic is None
            assert c == j.mimic.multiplier * m.variables[free.index(j.mimic.joint)]
    assert geometric_jacobian(m, frame="base", task="full").shape == (6, nvars)


def test_mimic_fields_and_angle_variables():
    m = _model("finger follows an earlier joint, with offset")
    assert [j.mimic for j in m.joints] == [None, None, Mimic(joint=0, multiplier=-1)]
    assert m.angle_variables == m.variables
    m = _model("prismatic fingers, fractional multiplier")
    assert m.joints[2].mimic == Mimic(joint=1, multiplier=sp.Rational(1, 2))
    assert m.angle_variables == (sp.Symbol("q1", real=True),)


@pytest.mark.parametrize("case", list(DOCS))
def test_fk_matches_the_coupled_composition(case):
    text, tip, nvars, _ = DOCS[case]
    fk, _ = _numeric(_model(case))
    ref = CoupledChain(text, None, tip)
    for q in _configurations(nvars):
        np.testing.assert_allclose(fk(q), ref.fk(q), rtol=0, atol=READ_ATOL)


@pytest.mark.parametrize("case", list(DOCS))
def test_jacobian_matches_finite_differences_of_the_coupled_fk(case):
    text, tip, nvars, _ = DOCS[case]
    _, jac = _numeric(_model(case))
    ref = CoupledChain(text, None, tip)
    for q in _configurations(nvars, seed=SEED + 1):
        np.testing.assert_allclose(jac(q), ref.jacobian_fd(q), rtol=0, atol=FD_ATOL)


@pytest.mark.parametrize("case", list(DOCS))
def test_jacobian_is_the_uncoupled_jacobian_times_the_coupling(case):
    """J(q) = J_all(q_all(q)) @ d q_all / d q, with J_all the chain without <mimic>."""
    text, tip, nvars, _ = DOCS[case]
    m = _model(case)
    free = parse_urdf(_without_mimic(text), name="free", tip=tip)
    assert free.variables == free.joint_coordinates and len(free.variables) == m.dof
    _, jac = _numeric(m)
    _, jac_all = _numeric(free)
    ref = CoupledChain(text, None, tip)
    names = [j.name for j in m.joints]
    coupling = np.zeros((m.dof, nvars))  # d q_all / d q, by central differences (exact: linear)
    for k in range(nvars):
        e = np.zeros(nvars)
        e[k] = 1.0
        hi = [ref._value(n, dict(zip(ref.free, e))) for n in names]
        lo = [ref._value(n, dict(zip(ref.free, -e))) for n in names]
        coupling[:, k] = (np.array(hi) - np.array(lo)) / 2
    for q in _configurations(nvars, seed=SEED + 2):
        q_all = [ref._value(n, dict(zip(ref.free, q))) for n in names]
        np.testing.assert_allclose(jac(q), jac_all(q_all) @ coupling, rtol=0, atol=READ_ATOL)


def test_offsets_are_exact_motions():
    m = _model("finger follows an earlier joint, with offset")
    pre = sp.Matrix(m.joints[2].pre)
    assert not pre.atoms(sp.Float)
    R = pre[:3, :3]
    assert (R.T * R).applyfunc(sp.expand) == sp.eye(3) and sp.expand(R.det()) == 1
    # an offset near a multiple of pi/12 is that multiple, like an rpy angle
    doc = _urdf(_joint("j1", "revolute", "a", "b", '<axis xyz="0 0 1"/>'),
                _joint("j2", "revolute", "b", "c", '<axis xyz="0 0 1"/>' + _mimic("j1", 1, 1.5708)))
    assert parse_urdf(doc, name="q").joints[1].pre == sp.ImmutableMatrix(
        [[0, -1, 0, 0], [1, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])
    # a prismatic offset is a rational translation along the axis
    m = _model("prismatic fingers, fractional multiplier")
    pre = sp.Matrix(m.joints[2].pre)
    assert not pre.atoms(sp.Float)
    assert sp.expand(pre[:3, 3] - sp.Matrix([sp.Rational(1, 10), 0, 0])
                     - pre[:3, :3] * sp.Matrix([0, -sp.Rational(1, 100), 0])) == sp.zeros(3, 1)


def test_integer_multiple_stays_polynomial_in_cos_and_sin_of_the_variable():
    m = _model("joint follows a later joint, integer multiplier")
    J = geometric_jacobian(m, frame="base", task="full")
    trig = J.atoms(sp.sin, sp.cos)
    assert trig and all(f.args[0] in m.variables for f in trig)


def test_content_key_sees_the_coupling():
    text, tip, _, _ = DOCS["finger follows an earlier joint, with offset"]
    m = parse_urdf(text, name="m", tip=tip)
    other = parse_urdf(text.replace('multiplier="-1"', 'multiplier="1"'), name="m", tip=tip)
    assert m != other and m.content_key() != other.content_key()
    assert m == parse_urdf(text, name="m", tip=tip)


# --- refused documents ----------------------------------------------------------

def _two(extra2, extra1="", t1="revolute", t2="revolute", *more):
    return _urdf(_joint("j1", t1, "a", "b", extra1), _joint("j2", t2, "b", "c", extra2), *more)


SIDE = _joint("s1", "revolute", "a", "x")

# case -> (document, tip link, words the message must contain, joint, field)
REFUSED = {
    "nan multiplier": (_two(_mimic("j1", "nan")), "c", ["'j2'", "finite"], 2, "mimic multiplier"),
    "inf offset": (_two(_mimic("j1", 1, "inf")), "c", ["'j2'", "finite"], 2, "mimic offset"),
    "empty multiplier": (_two(_mimic("j1", "")), "c", ["'j2'", "got 0 values"], 2,
                         "mimic multiplier"),
    "no joint attribute": (_two('<mimic multiplier="1"/>'), "c", ["'j2'", "'joint'"], 2, "mimic"),
    "unknown leader": (_two(_mimic("j9")), "c", ["'j2'", "'j9'", "not a joint of this robot"], 2,
                       "mimic"),
    "two followers of a leader off the chain, neither with multiplier +-1": (
        _two(_mimic("s1", 2), _mimic("s1", 3), "revolute", "revolute", SIDE), "c",
        ["'j1', 'j2'", "'s1'", "not on the chain a -> c", "multiplier 1 or -1", "--tip"], 2,
        "mimic"),
    "second follower of a leader off the chain, fractional multiplier": (
        _two(_mimic("s1", 0.5), _mimic("s1", -1), "revolute", "revolute", SIDE), "c",
        ["'j2'", "'s1'", "1/2", "integer"], 2, "mimic multiplier"),
    "leader is fixed": (_two(_mimic("j1"), "", "fixed"), "c", ["'j2'", "'j1'", "fixed"], 1,
                        "mimic"),
    "mimics itself": (_two(_mimic("j2")), "c", ["cycle", "'j2' -> 'j2'"], 2, "mimic"),
    "two joints mimic each other": (_two(_mimic("j1"), _mimic("j2")), "c",
                                    ["cycle", "'j1' -> 'j2' -> 'j1'"], 1, "mimic"),
    "cycle off the chain": (
        _two(_mimic("s1"), "", "revolute", "revolute",
             _joint("s1", "revolute", "a", "x", _mimic("s2")),
             _joint("s2", "revolute", "a", "y", _mimic("s1"))),
        "c", ["cycle", "'s1' -> 's2' -> 's1'"], 2, "mimic"),
    "prismatic follows revolute": (_two(_mimic("j1"), "", "revolute", "prismatic"), "c",
                                   ["'j2'", "prismatic", "'j1'", "revolute", "kind"], 2, "mimic"),
    "revolute with fractional multiplier": (
        _two(_mimic("j1", 1.05851325, 0.72349796)), "c",
        ["'j2'", "'j1'", "4234053/4000000", "integer"], 2, "mimic multiplier"),
    "fractional composed multiplier": (
        _two(_mimic("s1", 0.5), "", "revolute", "revolute",
             _joint("s1", "revolute", "a", "x", _mimic("j1", 3))),
        "c", ["'j2'", "'j1'", "3/2", "integer"], 2, "mimic multiplier"),
    "bad number off the chain": (
        _two("", "", "revolute", "revolute", _joint("s1", "revolute", "a", "x",
                                                    _mimic("j1", "1e"))),
        "c", ["'s1'", "mimic multiplier"], None, "mimic multiplier"),
}


@pytest.mark.parametrize("case", list(REFUSED))
def test_refused_mimics_raise_one_line_model_errors(case):
    text, tip, words, joint, field = REFUSED[case]
    with pytest.raises(ModelError) as info:
        parse_urdf(text, name="bad", file="bad.urdf", tip=tip)
    e = info.value
    assert str(e).startswith("bad.urdf: ") and "\n" not in str(e)
    for w in words:
        assert w in str(e), (w, str(e))
    assert e.joint == joint
    assert e.field == field


# --- a real gripper: the PR2's -------------------------------------------------------


PR2 = "pr2_description/urdf/pr2.urdf"
# wrist flex, wrist roll, left finger, and the left finger tip, which mimics the left finger
PR2_CHAIN = ("r_forearm_link", "r_gripper_l_finger_tip_link")


@pytest.fixture(scope="module")
def pr2(robots):
    return read_urdf(robots / PR2, base_link=PR2_CHAIN[0], tip=PR2_CHAIN[1])


def test_pr2_finger_tip_follows_the_finger(pr2):
    assert [j.name for j in pr2.joints] == ["r_wrist_flex_joint", "r_wrist_roll_joint",
                                            "r_gripper_l_finger_joint",
                                            "r_gripper_l_finger_tip_joint"]
    assert pr2.joints[3].mimic == Mimic(joint=2, multiplier=1)
    assert len(pr2.variables) == 3
    assert pr2.joint_coordinates[3] == pr2.variables[2]


def test_pr2_chain_matches_the_coupled_composition(robots, pr2):
    fk, jac = _numeric(pr2)
    ref = CoupledChain((robots / PR2).read_text(encoding="utf-8"), *PR2_CHAIN)
    assert ref.free == [j.name for j in pr2.joints if j.mimic is None]
    for q in _configurations(3, seed=SEED + 3):
        np.testing.assert_allclose(fk(q), ref.fk(q), rtol=0, atol=READ_ATOL)
        np.testing.assert_allclose(jac(q), ref.jacobian_fd(q), rtol=0, atol=FD_ATOL)


# the right finger tip follows the left finger, which is on the chain; on the chain to the
# right finger tip, the right finger and its tip both follow the left finger, off the chain
PR2_LEADERS = {
    "r_gripper_l_finger_tip_link": ("r_wrist_flex_joint", "r_wrist_roll_joint",
                                    "r_gripper_l_finger_joint"),
    "r_gripper_r_finger_tip_link": ("r_wrist_flex_joint", "r_wrist_roll_joint",
                                    "r_gripper_l_finger_joint"),
}


@pytest.mark.parametrize("tip", list(PR2_LEADERS))
def test_pr2_chain_matches_pinocchio_mimic_joints(robots, tip):
    """Pinocchio's own mimic joints give the column of each leader, on the chain or not."""
    pin = pytest.importorskip("pinocchio", reason="Pinocchio (PyPI package 'pin', in the test "
                                                  "extra) is the reference")
    pr2 = read_urdf(robots / PR2, base_link=PR2_CHAIN[0], tip=tip)
    model = pin.buildModelFromXML((robots / PR2).read_text(encoding="utf-8"), mimic=True)
    data = model.createData()
    leaders = PR2_LEADERS[tip]
    tip = model.getFrameId(tip, pin.FrameType.BODY)
    base = model.getFrameId(PR2_CHAIN[0], pin.FrameType.BODY)
    joints = [model.joints[model.getJointId(name)] for name in leaders]
    assert len(joints) == len(pr2.variables)
    _, jac = _numeric(pr2)
    for q in _configurations(3, seed=SEED + 4):
        x = pin.neutral(model)
        for jm, v in zip(joints, q):
            if jm.nq == 2:  # continuous: (cos, sin)
                x[jm.idx_q], x[jm.idx_q + 1] = math.cos(v), math.sin(v)
            else:
                x[jm.idx_q] = v
        pin.computeJointJacobians(model, data, x)
        pin.framesForwardKinematics(model, data, x)
        J = pin.getFrameJacobian(model, data, tip, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)
        J = J[:, [jm.idx_v for jm in joints]]
        Rb = data.oMf[base].rotation  # rankloci's base frame is the chain's first link
        np.testing.assert_allclose(jac(q), np.kron(np.eye(2), Rb.T) @ J, rtol=0, atol=FK_ATOL)


def test_pr2_right_finger_carries_the_left_fingers_variable(robots):
    """Both joints of the right finger follow the left finger, which is on another branch: the
    right finger moves by the left finger's variable, its tip follows the right finger."""
    pr2 = read_urdf(robots / PR2, base_link=PR2_CHAIN[0], tip="r_gripper_r_finger_tip_link")
    assert [j.name for j in pr2.joints] == ["r_wrist_flex_joint", "r_wrist_roll_joint",
                                            "r_gripper_r_finger_joint",
                                            "r_gripper_r_finger_tip_joint"]
    assert pr2.joints[2].mimic is None and pr2.joints[3].mimic == Mimic(joint=2, multiplier=1)
    assert len(pr2.variables) == 3
    leader = read_urdf(robots / PR2, base_link=PR2_CHAIN[0], tip=PR2_CHAIN[1])
    assert pr2.joints[2].limits == leader.joints[2].limits


def test_real_mimics_that_cannot_be_followed(robots):
    # the hand's mimic elements name joints the file does not define ("index_q1")
    with pytest.raises(ModelError, match="'index_q1', which is not a joint"):
        read_urdf(robots / "alex_description/urdf/alex_psyonic_hands.urdf",
                  base_link="Left_thumb_base", tip="Left_index_L2")


def test_the_one_follower_of_a_leader_off_the_chain_moves_as_a_joint_of_its_own():
    """j2 follows s1, which moves nothing else on the chain a -> c: q_j2 = m q_s1 + o is a change
    of variable that keeps the rank, so j2 gets a variable of its own (as Panda's right finger
    does on the chain to panda_rightfinger)."""
    from rankloci.io.urdf import parse_urdf

    model = parse_urdf(_two(_mimic("s1", 2, 0.1), "", "revolute", "revolute", SIDE),
                       name="m", tip="c")
    assert len(model.variables) == 2
    assert all(j.mimic is None for j in model.joints)
