"""Tests of URDF import (rankloci.io.urdf).

The forward kinematics of imported models is checked against an independent
numeric composition of the URDF transforms (plain numpy, written here), the
Jacobian against finite differences, and the UR5 URDF against the UR5 DH
model file: the two describe the same arm with the *same joint zero* (no
joint offsets, same joint directions); only the base frames differ, by a
rotation of pi about the base z axis (T_urdf(q) = Rz(pi) T_dh(q), both ending
at the flange frame ``tool0``), which the test measures rather than assumes.
"""

from __future__ import annotations

import math
from pathlib import Path

import defusedxml.ElementTree as SafeET
import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from rankloci.errors import ModelError
from rankloci.io.toml_model import read_model
from rankloci.io.urdf import parse_urdf, read_urdf
from rankloci.kinematics import forward_kinematics, geometric_jacobian
from rankloci.tolerances import RANK_RTOL, URDF_ANGLE_SNAP_ATOL, URDF_ROTATION_ATOL
from urdf_reference import rot, snapped, snapped_length

SEED = 20240611
REPO = Path(__file__).resolve().parents[2]

# FK entries are O(1 m) and come from ~20 double-precision products, so the
# lambdified symbolic FK and the numpy composition agree to ~1e-15.
FK_ATOL = 1e-12
# Central differences with step H: truncation H**2/6 * |p'''| <= ~1e-13 (reach
# ~1 m), rounding ~eps * |p| / H ~ 1e-10; 1e-8 leaves a factor 100.
FD_STEP = 1e-6
FD_ATOL = 1e-8


# --- example-robot-data -----------------------------------------------------


# name, file, base link, tip link, expected DOF, expected title
ROBOTS = {
    "ur5": ("ur_description/urdf/ur5_robot.urdf", "base_link", "tool0", 6, "ur5"),
    "panda": ("panda_description/urdf/panda.urdf", "panda_link0", "panda_hand_tcp", 7, "panda"),
    "panda_link8": ("panda_description/urdf/panda.urdf", "panda_link0", "panda_link8", 7,
                    "panda"),
    "kinova": ("kinova_description/robots/kinova.urdf", None, "j2s6s200_end_effector", 6,
               "kinova"),
    "kinova_finger": ("kinova_description/robots/kinova.urdf", None,
                      "j2s6s200_link_finger_tip_1", 6, "kinova"),
    "xarm7": ("xarm_description/urdf/xarm7.urdf", None, None, 7, "UF_ROBOT"),
}

_model_cache: dict[str, object] = {}


def load(robots: Path, key: str):
    if key not in _model_cache:
        file, base, tip, _, _ = ROBOTS[key]
        _model_cache[key] = read_urdf(robots / file, base_link=base, tip=tip)
    return _model_cache[key]


# --- an independent numeric reading of a URDF -------------------------------


class NumericChain:
    """The chain base -> tip of a URDF file, composed in float64 with numpy."""

    def __init__(self, path: Path, base: str | None, tip: str | None, *, snap: bool):
        root = SafeET.parse(path).getroot()
        by_child = {j.find("child").get("link"): j for j in root.findall("joint")}
        links = [link.get("name") for link in root.findall("link")]
        if base is None:
            base = next(link for link in links if link not in by_child)
        if tip is None:
            parents = {j.find("parent").get("link") for j in root.findall("joint")}
            leaves = [link for link in links if link not in parents]
            assert len(leaves) == 1
            tip = leaves[0]
        chain, link = [], tip
        while link != base:
            j = by_child[link]
            chain.append(j)
            link = j.find("parent").get("link")
        self.steps = []   # (origin 4x4, type, axis)
        self.angle_error = 0.0  # sum of |snapped - file| angles on the chain
        self.length = 0.0       # sum of |xyz| on the chain: a bound on every lever arm
        self.length_error = 0.0  # sum of |snapped - file| lengths on the chain
        # rotations read as short exact rational ones, each within URDF_ROTATION_ATOL rad:
        # rpy angles that do not snap, and joint axes (one rotation by up to pi about an axis
        # moved by URDF_ROTATION_ATOL moves a point by at most pi times that per lever arm)
        self.rotation_error = 0.0
        for j in reversed(chain):
            o = j.find("origin")
            xyz = [float(v) for v in (o.get("xyz", "0 0 0") if o is not None else "0 0 0").split()]
            rpy = [float(v) for v in (o.get("rpy", "0 0 0") if o is not None else "0 0 0").split()]
            if snap:
                self.angle_error += sum(abs(snapped(t) - t) for t in rpy)
                rpy = [snapped(t) for t in rpy]
                self.length_error += sum(abs(snapped_length(x) - x) for x in xyz)
                xyz = [snapped_length(x) for x in xyz]
                self.rotation_error += URDF_ROTATION_ATOL * (
                    sum(t != 0 and snapped(t) == t for t in rpy) + math.pi)
            self.length += float(np.linalg.norm(xyz))
            T = np.eye(4)
            T[:3, :3] = rot((0, 0, 1), rpy[2]) @ rot((0, 1, 0), rpy[1]) @ rot((1, 0, 0), rpy[0])
            T[:3, 3] = xyz
            a = j.find("axis")
            axis = [float(v) for v in (a.get("xyz") if a is not None else "1 0 0").split()]
            self.steps.append((T, j.get("type"), axis))

    @property
    def dof(self) -> int:
        return sum(t != "fixed" for _, t, _ in self.steps)

    def fk(self, q) -> np.ndarray:
        T = np.eye(4)
        q = iter(q)
        for origin, jtype, axis in self.steps:
            T = T @ origin
            if jtype in ("revolute", "continuous"):
                M = np.eye(4)
                M[:3, :3] = rot(axis, next(q))
                T = T @ M
            elif jtype == "prismatic":
                M = np.eye(4)
                M[:3, 3] = np.asarray(axis, float) / np.linalg.norm(axis) * next(q)
                T = T @ M
        return T


def _numeric(model):
    """Float functions q -> FK (4x4) and q -> geometric Jacobian (6xn), base frame."""
    subs = dict(model.parameters)
    fk = sp.lambdify(model.variables, forward_kinematics(model).subs(subs), "numpy")
    jac = sp.lambdify(model.variables, geometric_jacobian(model, frame="base", point="tool",
                                                          task="full").subs(subs), "numpy")
    return (lambda q: np.array(fk(*q), dtype=float)), (lambda q: np.array(jac(*q), dtype=float))


def _no_floats(m) -> bool:
    return not sp.ImmutableMatrix(m).atoms(sp.Float)


# --- real robots ------------------------------------------------------------

@pytest.mark.parametrize("key", list(ROBOTS))
def test_dof_title_and_structure(robots, key):
    file, base, tip, dof, title = ROBOTS[key]
    m = load(robots, key)
    assert m.dof == dof
    assert m.title == title
    assert m.name == Path(file).stem
    assert m.convention == "urdf" and m.frame == "base" and m.task == (0, 1, 2, 3, 4, 5)
    assert m.parameters == {}
    assert m.variables == tuple(sp.Symbol(f"q{i}", real=True) for i in range(1, dof + 1))
    assert m.base == sp.eye(4)
    assert m.path == str(robots / file)


@pytest.mark.parametrize("key", list(ROBOTS))
def test_transforms_are_exact_rigid_motions(robots, key):
    m = load(robots, key)
    for T in [j.pre for j in m.joints] + [j.post for j in m.joints] + [m.tool]:
        assert _no_floats(T)
        assert not any(isinstance(a, (sp.cos, sp.sin)) for a in sp.ImmutableMatrix(T).atoms(
            sp.Function))
        R = sp.Matrix(T)[:3, :3]
        assert (R.T * R).applyfunc(sp.expand) == sp.eye(3)
        assert sp.expand(R.det()) == 1
        assert list(sp.Matrix(T)[3, :]) == [0, 0, 0, 1]
    for j in m.joints:
        assert all(isinstance(c, sp.Expr) and c.is_number for c in j.axis)
        assert sp.expand(sum(c**2 for c in j.axis)) == 1


def test_joint_names_kinds_and_limits(robots):
    ur5 = load(robots, "ur5")
    assert [j.name for j in ur5.joints] == ["shoulder_pan_joint", "shoulder_lift_joint",
                                            "elbow_joint", "wrist_1_joint", "wrist_2_joint",
                                            "wrist_3_joint"]
    assert all(j.kind == "revolute" for j in ur5.joints)
    assert ur5.joints[2].limits == (-3.14159265359, 3.14159265359)
    assert ur5.joints[1].axis == (0, 1, 0)
    kinova = load(robots, "kinova")
    # continuous joints have no limits (URDF ignores them); revolute ones keep theirs
    assert kinova.joints[0].limits is None
    assert kinova.joints[1].limits == (0.820304748437, 5.46288055874)


def test_angles_are_snapped_exactly(robots):
    xarm = load(robots, "xarm7")  # rpy written "1.5708": pi/2 to 3.7e-6
    R = sp.Matrix(xarm.joints[1].pre)[:3, :3]
    assert R == sp.Matrix([[1, 0, 0], [0, 0, 1], [0, -1, 0]])  # Rx(-1.5708) taken as Rx(-pi/2)
    panda = load(robots, "panda")  # hand yaw -0.7853981633974483 = -pi/4
    assert sp.Matrix(panda.tool)[0, 0] == sp.sqrt(2) / 2


@pytest.mark.parametrize("key", list(ROBOTS))
def test_fk_matches_numeric_composition(robots, key):
    file, base, tip, dof, _ = ROBOTS[key]
    m = load(robots, key)
    fk, _ = _numeric(m)
    ideal = NumericChain(robots / file, base, tip, snap=True)
    raw = NumericChain(robots / file, base, tip, snap=False)
    assert ideal.dof == raw.dof == m.dof
    # Snapping moves each angle by at most URDF_ANGLE_SNAP_ATOL; to first order an
    # angle error d moves every later point by <= d * (sum of link lengths).
    # A snapped length moves every later point by its own size.
    snap_bound = ideal.angle_error * (1 + ideal.length) + ideal.length_error + FK_ATOL
    assert ideal.angle_error <= 6 * dof * URDF_ANGLE_SNAP_ATOL
    rng = np.random.default_rng(SEED)
    for _ in range(8):
        q = rng.uniform(-np.pi, np.pi, m.dof)
        T = fk(q)
        np.testing.assert_allclose(T, ideal.fk(q), rtol=0,
                                   atol=ideal.rotation_error * (1 + ideal.length) + FK_ATOL)
        np.testing.assert_allclose(T, raw.fk(q), rtol=0, atol=snap_bound)


@pytest.mark.parametrize("key", ["ur5", "panda", "kinova", "xarm7"])
def test_jacobian_matches_finite_differences(robots, key):
    m = load(robots, key)
    fk, jac = _numeric(m)
    rng = np.random.default_rng(SEED + 1)
    for _ in range(4):
        q = rng.uniform(-np.pi, np.pi, m.dof)
        J = jac(q)
        R = fk(q)[:3, :3]
        for i in range(m.dof):
            dq = np.zeros(m.dof)
            dq[i] = FD_STEP
            Tp, Tm = fk(q + dq), fk(q - dq)
            np.testing.assert_allclose(J[:3, i], (Tp[:3, 3] - Tm[:3, 3]) / (2 * FD_STEP),
                                       rtol=0, atol=FD_ATOL)
            W = (Tp[:3, :3] - Tm[:3, :3]) / (2 * FD_STEP) @ R.T  # skew(omega)
            np.testing.assert_allclose(J[3:, i], [W[2, 1], W[0, 2], W[1, 0]],
                                       rtol=0, atol=FD_ATOL)


# --- UR5: URDF against the DH model file -------------------------------------

# UR5 DH values (kinematics_models/ur5.toml), for building singular configurations.
UR5_A2, UR5_A3, UR5_D5 = -0.425, -0.39225, 0.09465


def _rank(J: np.ndarray) -> int:
    s = np.linalg.svd(J, compute_uv=False)
    return int(np.linalg.matrix_rank(J, tol=RANK_RTOL * s[0]))


def _shoulder_singular(q: np.ndarray) -> np.ndarray:
    """q with q2 chosen so that a2 c2 + a3 c23 + d5 s234 = 0.

    That is the shoulder singularity: the wrist point (where axes 5 and 6 meet)
    lies in the plane through axis 1 spanned by axis 1 and axis 2, i.e. on axis
    1 up to the constant shoulder offset d4 along axis 2.
    """
    q = q.copy()
    q3, q4 = q[2], q[3]
    a = UR5_A2 + UR5_A3 * math.cos(q3) + UR5_D5 * math.sin(q3 + q4)   # coefficient of c2
    b = -UR5_A3 * math.sin(q3) + UR5_D5 * math.cos(q3 + q4)           # coefficient of s2
    q[1] = math.atan2(-a, b)
    return q


@pytest.fixture(scope="module")
def ur5_pair(robots):
    urdf = load(robots, "ur5")
    dh = read_model(REPO / "kinematics_models" / "ur5.toml")
    assert urdf.dof == dh.dof == 6
    return _numeric(urdf), _numeric(dh)


def test_ur5_urdf_and_dh_share_the_joint_zero(ur5_pair):
    """T_urdf(q) = B T_dh(q) E with constant B, E for the same q: no joint offsets.

    B and E are measured at q = 0 and checked elsewhere; they come out as
    B = Rz(pi) (URDF base_link is the DH base turned half a turn) and E = I
    (URDF tool0 is the DH flange frame).
    """
    (fk_u, _), (fk_d, _) = ur5_pair
    q0 = np.zeros(6)
    B = np.diag([-1.0, -1.0, 1.0, 1.0])
    E = np.linalg.inv(B @ fk_d(q0)) @ fk_u(q0)
    np.testing.assert_allclose(E, np.eye(4), rtol=0, atol=FK_ATOL)
    rng = np.random.default_rng(SEED + 2)
    for _ in range(8):
        q = rng.uniform(-np.pi, np.pi, 6)
        np.testing.assert_allclose(fk_u(q), B @ fk_d(q) @ E, rtol=0, atol=FK_ATOL)


def _ur5_configurations():
    rng = np.random.default_rng(SEED + 3)
    out = [("random", rng.uniform(-np.pi, np.pi, 6), 6) for _ in range(6)]
    for _ in range(3):
        q = rng.uniform(-np.pi, np.pi, 6)
        wrist, elbow = q.copy(), q.copy()
        wrist[4] = 0.0
        elbow[2] = 0.0
        out += [("wrist q5=0", wrist, 5), ("elbow q3=0", elbow, 5),
                ("shoulder", _shoulder_singular(q), 5)]
    # two of the conditions at once: the two lost directions coincide, rank stays 5
    q = rng.uniform(-np.pi, np.pi, 6)
    q[4] = 0.0
    out.append(("wrist and shoulder", _shoulder_singular(q), 5))
    q = rng.uniform(-np.pi, np.pi, 6)
    q[2] = q[4] = 0.0
    out.append(("elbow and wrist", q, 5))
    return out


@pytest.mark.parametrize("case, q, expected", _ur5_configurations(),
                         ids=lambda v: v if isinstance(v, str) else "")
def test_ur5_urdf_and_dh_jacobians_have_equal_rank(ur5_pair, case, q, expected):
    (_, jac_u), (_, jac_d) = ur5_pair
    assert _rank(jac_u(q)) == _rank(jac_d(q)) == expected


# --- small documents ----------------------------------------------------------

def _urdf(joints: str, links=("a", "b", "c"), name="r") -> str:
    link_xml = "".join(f'<link name="{n}"/>' for n in links)
    return f'<robot name="{name}">{link_xml}{joints}</robot>'


def _joint(name, jtype, parent, child, extra=""):
    return (f'<joint name="{name}" type="{jtype}"><parent link="{parent}"/>'
            f'<child link="{child}"/>{extra}</joint>')


TWO_R = _urdf(_joint("j1", "revolute", "a", "b", '<origin xyz="0 0 0.5"/><axis xyz="0 0 1"/>')
              + _joint("j2", "continuous", "b", "c", '<origin xyz="1 0 0"/><axis xyz="0 0 1"/>'))


def test_small_chain_and_defaults():
    m = parse_urdf(TWO_R, name="two", file="two.urdf")
    assert m.dof == 2 and m.name == "two" and m.title == "r" and m.path == ""
    assert m.joints[0].pre == sp.Matrix(4, 4, [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, sp.Rational(1, 2),
                                               0, 0, 0, 1])
    assert m.joints[0].post == sp.eye(4) and m.tool == sp.eye(4)
    # no <axis>: the URDF default 1 0 0; no <origin>: identity
    m = parse_urdf(_urdf(_joint("j", "prismatic", "a", "b"), links=("a", "b")), name="p")
    assert m.joints[0].kind == "prismatic" and m.joints[0].axis == (1, 0, 0)
    assert m.joints[0].pre == sp.eye(4)


def test_fixed_joints_fold_into_pre_and_tool():
    doc = _urdf(_joint("f0", "fixed", "a", "b", '<origin xyz="0 0 1"/>')
                + _joint("j", "revolute", "b", "c", '<origin xyz="2 0 0"/><axis xyz="0 0 1"/>')
                + _joint("f1", "fixed", "c", "d", '<origin xyz="0 3 0" rpy="0 0 1.5708"/>'),
                links=("a", "b", "c", "d"))
    m = parse_urdf(doc, name="f")
    assert m.dof == 1
    assert list(sp.Matrix(m.joints[0].pre)[:3, 3]) == [2, 0, 1]
    assert m.tool == sp.ImmutableMatrix([[0, -1, 0, 0], [1, 0, 0, 3], [0, 0, 1, 0],
                                         [0, 0, 0, 1]])


def test_base_and_tip_choose_a_sub_chain():
    doc = _urdf(_joint("j1", "revolute", "a", "b") + _joint("j2", "revolute", "b", "c")
                + _joint("j3", "prismatic", "c", "d"), links=("a", "b", "c", "d"))
    m = parse_urdf(doc, name="s", base_link="b", tip="c")
    assert [j.name for j in m.joints] == ["j2"]


@settings(max_examples=200, deadline=None)
@given(st.tuples(*[st.floats(-7, 7, allow_nan=False)] * 3))
def test_origin_rotation_is_exact_orthogonal_and_close(rpy):
    doc = _urdf(_joint("j", "revolute", "a", "b",
                       f'<origin rpy="{rpy[0]!r} {rpy[1]!r} {rpy[2]!r}"/>'), links=("a", "b"))
    R = sp.Matrix(parse_urdf(doc, name="x").joints[0].pre)[:3, :3]
    assert _no_floats(R)
    assert (R.T * R).applyfunc(sp.expand) == sp.eye(3)
    Rn = rot((0, 0, 1), rpy[2]) @ rot((0, 1, 0), rpy[1]) @ rot((1, 0, 0), rpy[0])
    # each angle moves by at most the snap tolerance, and the rotation with it
    np.testing.assert_allclose(np.array(R.evalf(), float), Rn, rtol=0,
                               atol=3 * URDF_ANGLE_SNAP_ATOL + FK_ATOL)
    ideal = [snapped(t) for t in rpy]
    Rs = rot((0, 0, 1), ideal[2]) @ rot((0, 1, 0), ideal[1]) @ rot((1, 0, 0), ideal[0])
    # an angle that does not snap is read as a short rational rotation within URDF_ROTATION_ATOL
    approx = sum(t != 0 and snapped(t) == t for t in rpy)
    np.testing.assert_allclose(np.array(R.evalf(), float), Rs, rtol=0,
                               atol=approx * URDF_ROTATION_ATOL + FK_ATOL)


@settings(max_examples=200, deadline=None)
@given(st.tuples(*[st.floats(-2, 2, allow_nan=False)] * 3).filter(
    lambda v: math.hypot(*v) > 1e-3))
def test_axis_is_exact_unit_and_close(v):
    doc = _urdf(_joint("j", "revolute", "a", "b", f'<axis xyz="{v[0]!r} {v[1]!r} {v[2]!r}"/>'),
                links=("a", "b"))
    axis = parse_urdf(doc, name="x").joints[0].axis
    assert sp.expand(sum(c**2 for c in axis)) == 1
    assert not sp.Tuple(*axis).atoms(sp.Float)
    u = np.asarray(v) / np.linalg.norm(v)
    # each component moves by at most the snap tolerance
    assert np.linalg.norm(np.array([float(c) for c in axis]) - u) <= 2 * URDF_ANGLE_SNAP_ATOL


def test_axis_snaps_near_unit_values():
    doc = _urdf(_joint("j", "revolute", "a", "b", '<axis xyz="0 0.9999999 1e-7"/>'),
                links=("a", "b"))
    assert parse_urdf(doc, name="x").joints[0].axis == (0, 1, 0)
    doc = _urdf(_joint("j", "revolute", "a", "b", '<axis xyz="0 -0.7071068 0.7071068"/>'),
                links=("a", "b"))
    assert parse_urdf(doc, name="x").joints[0].axis == (0, -sp.sqrt(2) / 2, sp.sqrt(2) / 2)


def test_tiny_lengths_snap_to_zero_and_every_snap_is_noted():
    # an exporter's float noise (icub writes 4.33681e-19 m) is taken as 0; 0.5 mm is kept
    doc = _urdf(_joint("j1", "revolute", "a", "b",
                       '<origin xyz="4.33681e-19 0.0005 0.3" rpy="1.5708 0 0"/>'
                       '<axis xyz="0 0.9999999 1e-7"/>')
                + _joint("j2", "revolute", "b", "c", '<origin xyz="-7.45058e-09 0 0"/>'),
                links=("a", "b", "c"))
    m = parse_urdf(doc, name="n")
    assert list(sp.Matrix(m.joints[0].pre)[:3, 3]) == [0, sp.Rational(1, 2000), sp.Rational(3, 10)]
    assert sp.Matrix(m.joints[1].pre)[0, 3] == 0
    assert m.notes == (
        "reading the URDF snapped 1 rpy angle to an exact multiple of pi/12 (largest change "
        "3.7e-06 rad), 2 axis components to exact values (largest change 1e-07) and 2 lengths "
        "to 0 (largest 7.5e-09 m); results are for the snapped model",)
    # values that are exact already change nothing
    exact = _urdf(_joint("j", "revolute", "a", "b",
                         f'<origin xyz="0 0 0.5" rpy="{math.pi / 2!r} 0 0"/><axis xyz="0 1 0"/>'),
                  links=("a", "b"))
    assert parse_urdf(exact, name="e").notes == ()


def test_other_rotations_are_short_exact_rationals():
    # alex's 40-degree rotation and a romeo axis written with 6 digits: exact, orthogonal,
    # within URDF_ROTATION_ATOL of the file, and with short denominators (a float's shortest
    # decimal would give 17 to 34 digits)
    doc = _urdf(_joint("j", "revolute", "a", "b", '<origin rpy="0.698132 0 0"/>'
                       '<axis xyz="0.417025 0.895055 -0.15801"/>'), links=("a", "b"))
    m = parse_urdf(doc, name="r")
    R = sp.Matrix(m.joints[0].pre)[:3, :3]
    assert (R.T * R).applyfunc(sp.expand) == sp.eye(3)
    assert max(x.q for x in R) < 10**10
    np.testing.assert_allclose(np.array(R.evalf(), float), rot((1, 0, 0), 0.698132), rtol=0,
                               atol=URDF_ROTATION_ATOL)
    axis = m.joints[0].axis
    # one common denominator of about 7 digits for both stereographic coordinates
    assert sp.expand(sum(c**2 for c in axis)) == 1 and max(c.q for c in axis) < 10**14
    u = np.array([0.417025, 0.895055, -0.15801])
    assert np.linalg.norm(np.array([float(c) for c in axis]) - u / np.linalg.norm(u)) <= \
        URDF_ROTATION_ATOL
    assert "2 other rotations and axes to short exact rational ones" in m.notes[0]


def test_common_denominator_search_is_bounded(monkeypatch):
    from fractions import Fraction

    import rankloci.io.urdf_exact as urdf_exact

    xs = [0.41702512345, 0.8950551234]
    common = urdf_exact._common_denominator(xs, 2.5e-10)
    assert common[0].q == common[1].q
    # past the largest denominator searched, each number gets its own short rational
    monkeypatch.setattr(urdf_exact, "_DENOMINATOR_MAX", 1 << 20)
    own = urdf_exact._common_denominator(xs, 2.5e-10)
    assert own[0].q != own[1].q
    for got in (common, own):
        assert all(abs(Fraction(int(g.p), int(g.q)) - Fraction(x)) <= Fraction(2.5e-10)
                   for g, x in zip(got, xs))


def test_a_locus_carries_the_snapping_note():
    from rankloci.api import locus

    doc = _urdf(_joint("j1", "revolute", "a", "b", '<origin xyz="0 0 0.5"/><axis xyz="0 0 1"/>')
                + _joint("j2", "revolute", "b", "c", '<origin xyz="1 1e-12 0" rpy="0 0 1.5708"/>'
                         '<axis xyz="0 0 1"/>')
                + _joint("f", "fixed", "c", "d", '<origin xyz="1 0 0"/>'),
                links=("a", "b", "c", "d"))
    result = locus(parse_urdf(doc, name="planar"), task="position")
    assert result.notes[0].startswith("reading the URDF snapped 1 rpy angle") and \
        "1 length to 0" in result.notes[0]


# --- malformed input ----------------------------------------------------------

BILLION_LAUGHS = """<?xml version="1.0"?>
<!DOCTYPE robot [
 <!ENTITY lol "lol">
 <!ENTITY lol2 "&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;">
 <!ENTITY lol3 "&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;">
 <!ENTITY lol4 "&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;">
 <!ENTITY lol5 "&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;">
 <!ENTITY lol6 "&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;">
 <!ENTITY lol7 "&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;">
 <!ENTITY lol8 "&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;">
 <!ENTITY lol9 "&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;">
]>
<robot name="&lol9;"><link name="a"/></robot>
"""

EXTERNAL_ENTITY = """<?xml version="1.0"?>
<!DOCTYPE robot [<!ENTITY x SYSTEM "file:///etc/passwd">]>
<robot name="&x;"><link name="a"/></robot>
"""

CHAIN3 = ("a", "b", "c", "d")

# case id -> (document, kwargs, words the message must contain, joint, field)
MALFORMED = {
    "invalid xml": ("<robot name='r'><link name='a'></robot>", {}, ["invalid XML"], None, None),
    "not xml": ("this is not a URDF", {}, ["invalid XML"], None, None),
    "empty": ("", {}, ["invalid XML"], None, None),
    "billion laughs": (BILLION_LAUGHS, {}, ["entity"], None, None),
    "external entity": (EXTERNAL_ENTITY, {}, ["entity"], None, None),
    "wrong root": ("<sdf/>", {}, ["<sdf>", "<robot>"], None, None),
    "xacro": ('<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="r">'
              '<xacro:macro name="m"/><link name="a"/></robot>', {}, ["xacro"], None, None),
    "no links": ("<robot name='r'/>", {}, ["no <link>"], None, None),
    "origin xyz two values": (
        _urdf(_joint("j1", "revolute", "a", "b") + _joint("j2", "revolute", "b", "c",
                                                          '<origin xyz="0 0"/>')),
        {}, ["'j2'", "3 finite decimal numbers", "got 2 values in '0 0'"], 2, "origin xyz"),
    "origin rpy empty": (
        _urdf(_joint("j1", "revolute", "a", "b", '<origin rpy=""/>') + _joint(
            "j2", "revolute", "b", "c")), {}, ["'j1'", "origin rpy"], 1, "origin rpy"),
    "non-numeric xyz": (
        _urdf(_joint("j1", "revolute", "a", "b", '<origin xyz="0 zero 0"/>')
              + _joint("j2", "revolute", "b", "c")), {}, ["'j1'", "number"], 1, "origin xyz"),
    "nan xyz": (
        _urdf(_joint("j1", "revolute", "a", "b", '<origin xyz="0 nan 0"/>')
              + _joint("j2", "revolute", "b", "c")), {}, ["'j1'", "number"], 1, "origin xyz"),
    "underscore number": (
        _urdf(_joint("j1", "revolute", "a", "b", '<origin xyz="0 1_0 0"/>')
              + _joint("j2", "revolute", "b", "c")), {}, ["'j1'", "number"], 1, "origin xyz"),
    "bad fixed origin": (
        _urdf(_joint("f", "fixed", "a", "b", '<origin xyz="1 2 x"/>')
              + _joint("j", "revolute", "b", "c")), {}, ["'f'", "origin xyz"], None, "origin xyz"),
    "zero axis": (
        _urdf(_joint("j1", "revolute", "a", "b") + _joint("j2", "prismatic", "b", "c",
                                                          '<axis xyz="0 0 0"/>')),
        {}, ["'j2'", "zero"], 2, "axis xyz"),
    "bad limit": (
        _urdf(_joint("j1", "revolute", "a", "b", '<limit lower="-1" upper="one"/>')
              + _joint("j2", "revolute", "b", "c")), {}, ["'j1'", "limit upper"], 1,
        "limit upper"),
    "inverted limits": (
        _urdf(_joint("j1", "revolute", "a", "b", '<limit lower="1" upper="-1"/>')
              + _joint("j2", "revolute", "b", "c")), {}, ["'j1'", "above"], 1, "limit lower"),
    "unknown joint type": (
        _urdf(_joint("j1", "hinge", "a", "b") + _joint("j2", "revolute", "b", "c")),
        {}, ["'j1'", "unknown type 'hinge'"], None, "type"),
    "missing type": (
        _urdf('<joint name="j1"><parent link="a"/><child link="b"/></joint>'),
        {}, ["'j1'", "'type'"], None, "type"),
    "floating": (
        _urdf(_joint("j1", "floating", "a", "b") + _joint("j2", "revolute", "b", "c")),
        {}, ["'j1'", "floating", "supported"], None, "type"),
    "planar": (
        _urdf(_joint("j1", "revolute", "a", "b") + _joint("j2", "planar", "b", "c")),
        {}, ["'j2'", "planar", "supported"], None, "type"),
    "mimic of an unknown joint": (
        _urdf(_joint("j1", "revolute", "a", "b") + _joint("j2", "revolute", "b", "c",
                                                          '<mimic joint="j0"/>')),
        {}, ["'j2'", "'j0'", "not a joint"], 2, "mimic"),
    "missing link": (
        _urdf(_joint("j1", "revolute", "a", "b") + _joint("j2", "revolute", "b", "zz")),
        {}, ["'j2'", "'zz'", "not defined"], None, "child"),
    "missing child": (
        _urdf('<joint name="j1" type="fixed"><parent link="a"/></joint>'),
        {}, ["'j1'", "<child>"], None, "child"),
    "two parents": (
        _urdf(_joint("j1", "revolute", "a", "c") + _joint("j2", "revolute", "b", "c")),
        {}, ["'c'", "'j1'", "'j2'", "tree"], None, "child"),
    "cycle": (
        _urdf(_joint("j1", "revolute", "a", "b") + _joint("j2", "revolute", "b", "c")
              + _joint("j3", "revolute", "c", "a")), {}, ["cycle", "a -> b -> c -> a"], None, None),
    "cycle beside a tree": (
        _urdf(_joint("j1", "revolute", "a", "b") + _joint("j2", "revolute", "c", "d")
              + _joint("j3", "revolute", "d", "c"), links=CHAIN3), {}, ["cycle", "c -> d"],
        None, None),
    "disconnected": (
        _urdf(_joint("j1", "revolute", "a", "b") + _joint("j2", "revolute", "c", "d"),
              links=CHAIN3), {}, ["not connected", "'a'", "'c'"], None, None),
    "self joint": (_urdf(_joint("j1", "revolute", "a", "a")), {}, ["itself"], None, "child"),
    "duplicate link": (_urdf("", links=("a", "a")), {}, ["'a'", "twice"], None, "link name"),
    "duplicate joint": (
        _urdf(_joint("j", "revolute", "a", "b") + _joint("j", "revolute", "b", "c")),
        {}, ["'j'", "twice"], None, "joint name"),
    "two leaves": (
        _urdf(_joint("j1", "revolute", "a", "b") + _joint("j2", "revolute", "a", "c")),
        {}, ["'b'", "'c'", "--tip"], None, "tip_link"),
    "unknown tip": (TWO_R, {"tip": "nope"}, ["'nope'"], None, "tip_link"),
    "unknown base": (TWO_R, {"base_link": "nope"}, ["'nope'"], None, "base_link"),
    "tip not below base": (TWO_R, {"base_link": "c", "tip": "a"}, ["not below"], None,
                           "tip_link"),
    "no movable joint": (
        _urdf(_joint("f", "fixed", "a", "b"), links=("a", "b")), {}, ["no revolute"], None,
        None),
}


@pytest.mark.parametrize("case", list(MALFORMED))
def test_malformed_documents_raise_model_error(case):
    text, kwargs, words, joint, field = MALFORMED[case]
    with pytest.raises(ModelError) as info:
        parse_urdf(text, name="bad", file="bad.urdf", **kwargs)
    e = info.value
    assert e.file == "bad.urdf"
    assert str(e).startswith("bad.urdf: ")
    for w in words:
        assert w in str(e), (w, str(e))
    assert e.joint == joint
    assert e.field == field


def test_read_urdf_errors_name_the_file(tmp_path):
    with pytest.raises(ModelError) as info:
        read_urdf(tmp_path / "missing.urdf")
    assert info.value.file == "missing.urdf"
    p = tmp_path / "latin.urdf"
    p.write_bytes(b'<robot name="\xe9"><link name="a"/></robot>')
    with pytest.raises(ModelError) as info:
        read_urdf(p)
    assert info.value.file == "latin.urdf" and "UTF-8" in str(info.value)
    p = tmp_path / "two.urdf"
    p.write_text(TWO_R, encoding="utf-8")
    m = read_urdf(p)
    assert m.name == "two" and m.path == str(p) and m.dof == 2


@settings(max_examples=300, deadline=None)
@given(st.data())
def test_mutated_documents_give_a_model_or_a_model_error(data):
    """Any edit of a valid document gives a RobotModel or a ModelError, nothing else."""
    text = TWO_R
    for _ in range(data.draw(st.integers(1, 4))):
        i = data.draw(st.integers(0, len(text)))
        j = data.draw(st.integers(i, min(len(text), i + 8)))
        text = text[:i] + data.draw(st.text(alphabet='<>/="& 0123456789.-abjxyz', max_size=6)) \
            + text[j:]
    try:
        parse_urdf(text, name="m", file="m.urdf")
    except ModelError as e:
        assert e.file == "m.urdf"
