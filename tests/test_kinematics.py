"""Forward kinematics and the geometric Jacobian: finite differences, closed forms, invariants.

Every built-in robot model is checked; configurations come from
``numpy.random.default_rng(SEED)``.
"""

from __future__ import annotations

import functools
import math
import tomllib
from dataclasses import dataclass
from typing import Callable

import numpy as np
import pytest
import sympy as sp

from rankloci.io import builtin_models, load_model, models_dir
from rankloci.kinematics import (
    forward_kinematics,
    frame_position,
    geometric_jacobian,
    relative_transforms,
    trig_normal,
)
from rankloci.model import RobotModel
from rankloci.tolerances import RANK_RTOL

SEED = 20240611
N_CONFIGS = 5

#: Central-difference step.  Truncation error ~ FD_STEP**2 * |p'''| ~ 1e-12 L and
#: rounding ~ eps * L / FD_STEP ~ 2e-10 L (L = arm size), so FD_RTOL = 1e-7 of L
#: has three orders of margin yet catches any wrong entry.
FD_STEP = 1e-6
FD_RTOL = 1e-7

#: A determinant computed in double precision from an exactly singular matrix is
#: ~n * eps * (Hadamard bound) ~ 1e-15 of it; DET_ZERO_RTOL leaves 1000x margin.
#: A regular configuration must have |det| above RANK_RTOL times the bound.
DET_ZERO_RTOL = 1e-12

#: Models with this many joints or more take a few seconds to differentiate.
SLOW_DOF = 7


def _robot_params():
    """One pytest.param per built-in robot model (matrix models have no kinematics)."""
    out = []
    for name in builtin_models():
        try:
            data = tomllib.loads((models_dir() / f"{name}.toml").read_text(encoding="utf-8"))
        except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError):
            data = {}  # load_model inside the test reports the problem
        if "matrix" in data:
            continue
        slow = len(data.get("joint", [])) >= SLOW_DOF
        out.append(pytest.param(name, id=name, marks=[pytest.mark.slow] if slow else []))
    return out


ROBOTS = _robot_params()

#: Full-task rank at a random configuration, for the models we know.
GENERIC_RANK = {
    "planar2r": 2, "planar3r": 3, "planar3r_orient": 3, "planar4r": 3,
    "puma560": 6, "ur5": 6, "pa10": 6, "ssrms": 6, "ssrms_lock3": 6, "mobile10": 6,
}


def skew(w) -> np.ndarray:
    return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])


def numeric_rank(J: np.ndarray) -> int:
    s = np.linalg.svd(J, compute_uv=False)
    return int(np.linalg.matrix_rank(J, tol=RANK_RTOL * s[0]))


@dataclass(frozen=True)
class NumericRobot:
    """A built-in model with its poses and Jacobians lambdified once."""

    model: RobotModel
    mid: int  # a middle link
    frames: tuple
    _poses: Callable
    _jacobians: Callable

    @property
    def dof(self) -> int:
        return self.model.dof

    def poses(self, q) -> dict:
        """World (base-frame) pose of every frame in ``frames``."""
        return dict(zip(self.frames, (np.asarray(T, float) for T in self._poses(*q))))

    def jacobians(self, q) -> dict:
        """Full 6-row Jacobian for every (frame, point) pair of ``frames``."""
        pairs = [(f, p) for f in self.frames for p in self.frames]
        return dict(zip(pairs, (np.asarray(J, float) for J in self._jacobians(*q))))


@functools.lru_cache(maxsize=None)
def numeric_robot(name: str) -> NumericRobot:
    model = load_model(name)
    assert isinstance(model, RobotModel)
    mid = max(1, model.dof // 2)
    frames = ("base", "tool", mid)
    world = relative_transforms(model, "base")
    poses = [sp.Matrix(world[frame_position(model, f)]).subs(model.parameters) for f in frames]
    jacs = [geometric_jacobian(model, task="full", frame=f, point=p).subs(model.parameters)
            for f in frames for p in frames]
    q = model.variables
    return NumericRobot(model, mid, frames, sp.lambdify(q, poses, "numpy", cse=True),
                        sp.lambdify(q, jacs, "numpy", cse=True))


def random_configs(rng, dof, n=N_CONFIGS):
    return rng.uniform(-np.pi, np.pi, size=(n, dof))


# --- 1. Jacobian = derivative of the forward kinematics ------------------------------

@pytest.mark.parametrize("name", ROBOTS)
def test_jacobian_matches_finite_differences(name):
    """Linear rows = d(point fixed to the tool)/dq; angular rows: skew(w) = dR/dq R^T.

    Checked in the base frame (point tool), the tool frame (point tool) and a
    middle link's frame with that link's origin as the point; velocities in
    frame F are R_F^T times the world ones.
    """
    robot = numeric_robot(name)
    rng = np.random.default_rng(SEED)
    k = robot.mid
    cases = [("base", "tool"), ("tool", "tool"), (k, k)]
    for q0 in random_configs(rng, robot.dof):
        poses = robot.poses(q0)
        jacs = robot.jacobians(q0)
        T_tool = poses["tool"]
        scale = max(1.0, float(np.abs(T_tool[:3, 3]).max()), *(np.abs(jacs[c]).max() for c in cases))
        # d/dq_i of the world tool pose, by central differences
        dT = []
        for i in range(robot.dof):
            step = np.zeros(robot.dof)
            step[i] = FD_STEP
            dT.append((robot.poses(q0 + step)["tool"] - robot.poses(q0 - step)["tool"]) / (2 * FD_STEP))
        for frame, point in cases:
            J = jacs[(frame, point)]
            assert J.shape == (6, robot.dof)
            R_F = poses[frame][:3, :3]
            body_point = np.linalg.solve(T_tool, poses[point][:, 3])  # the point, fixed to the tool
            for i in range(robot.dof):
                v_world = (dT[i] @ body_point)[:3]
                W_world = dT[i][:3, :3] @ T_tool[:3, :3].T
                np.testing.assert_allclose(J[:3, i], R_F.T @ v_world, rtol=0, atol=FD_RTOL * scale,
                                           err_msg=f"{name} frame={frame} point={point} column {i + 1} (linear)")
                np.testing.assert_allclose(skew(J[3:, i]), R_F.T @ W_world @ R_F, rtol=0, atol=FD_RTOL * scale,
                                           err_msg=f"{name} frame={frame} point={point} column {i + 1} (angular)")


def _dh_step(convention, kind, a, alpha, d, theta, q):
    """Textbook link transform, written independently of rankloci.model."""
    def rz(t):
        c, s = math.cos(t), math.sin(t)
        return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])

    def rx(t):
        c, s = math.cos(t), math.sin(t)
        return np.array([[1.0, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1]])

    def tz(x):
        T = np.eye(4)
        T[2, 3] = x
        return T

    def tx(x):
        T = np.eye(4)
        T[0, 3] = x
        return T

    if kind == "revolute":
        theta = theta + q
    else:
        d = d + q
    if convention == "dh":
        return rz(theta) @ tz(d) @ tx(a) @ rx(alpha)
    return rx(alpha) @ tx(a) @ rz(theta) @ tz(d)


@pytest.mark.parametrize("name", ROBOTS)
def test_forward_kinematics_is_the_dh_product(name):
    """Tool pose = base * prod(DH link transforms) * tool; frame k = the first k factors (standard DH)."""
    robot = numeric_robot(name)
    model = robot.model
    subs = model.parameters

    def num(e):
        return float(sp.sympify(e).subs(subs))

    base = np.array(sp.Matrix(model.base).subs(subs), dtype=float)
    tool = np.array(sp.Matrix(model.tool).subs(subs), dtype=float)
    rng = np.random.default_rng(SEED + 1)
    for q0 in random_configs(rng, robot.dof):
        poses = robot.poses(q0)
        T = base
        for i, (joint, qi) in enumerate(zip(model.joints, q0), 1):
            dh = joint.dh
            assert dh is not None, f"{name}: a TOML robot keeps its DH fields"
            T = T @ _dh_step(dh.convention, joint.kind, num(dh.a), num(dh.alpha), num(dh.d), num(dh.theta), qi)
            if i == robot.mid and dh.convention == "dh":  # frame k is the DH frame k
                np.testing.assert_allclose(poses[robot.mid], T, rtol=0, atol=1e-12 * max(1.0, np.abs(T).max()))
        T = T @ tool
        np.testing.assert_allclose(poses["tool"], T, rtol=0, atol=1e-12 * max(1.0, np.abs(T).max()))


@pytest.mark.parametrize("name", ["planar2r", "puma560"])
def test_forward_kinematics_in_a_frame_is_relative_pose(name):
    """forward_kinematics(frame=F) == inverse(world pose of F) * world pose of the tool."""
    model = load_model(name)
    world = relative_transforms(model, "base")
    for frame in ("tool", 0, 1, model.dof):
        T_F = sp.Matrix(world[frame_position(model, frame)])
        R, p = T_F[:3, :3], T_F[:3, 3]
        T_F_inv = sp.Matrix.vstack(sp.Matrix.hstack(R.T, -R.T * p), sp.Matrix([[0, 0, 0, 1]]))
        expected = T_F_inv * sp.Matrix(world[-1])
        diff = (forward_kinematics(model, frame=frame) - expected).applyfunc(lambda e: trig_normal(sp.expand_trig(e)))
        assert diff == sp.zeros(4, 4), f"frame {frame}"
    assert forward_kinematics(model, frame="tool") == sp.eye(4)


def test_frame_and_point_names_are_validated():
    model = load_model("planar2r")
    for bad in (-1, 3, "world", 1.0, True):
        with pytest.raises(ValueError, match="frame"):
            geometric_jacobian(model, frame=bad)
        with pytest.raises(ValueError, match="frame"):
            geometric_jacobian(model, point=bad)
    with pytest.raises(ValueError, match="frame"):
        geometric_jacobian(model, point=None)  # frame=None means the model's frame; a point is required
    with pytest.raises(ValueError, match="task"):
        geometric_jacobian(model, task="sideways")


# --- 2. closed forms -------------------------------------------------------------------

def test_planar2r_determinant_closed_form():
    model = load_model("planar2r")
    p = {s.name: s for s in model.parameters}
    q1, q2 = model.variables
    J = geometric_jacobian(model, task="planar")
    assert J.shape == (2, 2)
    assert sp.simplify(J.det() - p["l1"] * p["l2"] * sp.sin(q2)) == 0


def _puma_closed_form(model):
    """det J of this model's PUMA 560 parametrisation (Corke standard DH, wrist-centre point).

    det J = a2 * sin(q5) * (d4 cos q3 + a3 sin q3) * (a2 cos q2 - d4 sin(q2+q3) + a3 cos(q2+q3));
    the elbow factor has +a3 (not -a3 as with Craig's modified DH) because
    alpha3 = -pi/2 here.
    """
    p = {s.name: s for s in model.parameters}
    a2, a3, d4 = p["a2"], p["a3"], p["d4"]
    _, q2, q3, _, q5, _ = model.variables
    elbow = d4 * sp.cos(q3) + a3 * sp.sin(q3)
    shoulder = a2 * sp.cos(q2) - d4 * sp.sin(q2 + q3) + a3 * sp.cos(q2 + q3)
    return a2 * sp.sin(q5) * elbow * shoulder, elbow


def test_puma560_determinant_closed_form():
    """Exact: the symbolic determinant (frame 3, any point) equals the textbook product."""
    model = load_model("puma560")
    closed, _ = _puma_closed_form(model)
    det = geometric_jacobian(model, task="full", frame=3, point=3).det(method="berkowitz")
    assert trig_normal(sp.expand_trig(det - closed)) == 0


def test_puma560_determinant_vanishes_at_wrist_singularity():
    robot = numeric_robot("puma560")
    rng = np.random.default_rng(SEED + 2)
    for q0 in random_configs(rng, 6, n=10):
        J = robot.jacobians(q0)[("base", "tool")]
        hadamard = np.prod(np.linalg.norm(J, axis=0))
        assert abs(np.linalg.det(J)) > RANK_RTOL * hadamard, f"q = {q0}"
        q0[4] = 0.0
        J = robot.jacobians(q0)[("base", "tool")]
        hadamard = np.prod(np.linalg.norm(J, axis=0))
        assert abs(np.linalg.det(J)) <= DET_ZERO_RTOL * hadamard, f"q = {q0}"


# --- 3. rank does not depend on frame or reference point ---------------------------------

def _puma_elbow_q3(model) -> float:
    """q3 on the elbow locus d4 cos(q3) + a3 sin(q3) = 0 of this parametrisation."""
    p = {s.name: float(v) for s, v in model.parameters.items()}
    return math.atan2(-p["d4"], p["a3"])


#: (model, label, set the singular joints on a random q, expected full-task rank)
SINGULAR_CASES = [
    ("puma560", "wrist q5=0", lambda q, m: q.__setitem__(4, 0.0), 5),
    ("puma560", "elbow", lambda q, m: q.__setitem__(2, _puma_elbow_q3(m)), 5),
    ("ur5", "wrist q5=0", lambda q, m: q.__setitem__(4, 0.0), 5),
    ("ur5", "elbow q3=0", lambda q, m: q.__setitem__(2, 0.0), 5),
    ("planar2r", "stretched q2=0", lambda q, m: q.__setitem__(1, 0.0), 2),
    ("planar2r", "folded q2=pi", lambda q, m: q.__setitem__(1, math.pi), 2),
]


def _assert_same_rank_everywhere(robot, q0, expected=None):
    ranks = {pair: numeric_rank(J) for pair, J in robot.jacobians(q0).items()}
    assert len(ranks) == 9
    assert len(set(ranks.values())) == 1, f"{robot.model.name} q={q0}: ranks {ranks}"
    if expected is not None:
        assert set(ranks.values()) == {expected}, f"{robot.model.name} q={q0}: ranks {ranks}"


@pytest.mark.parametrize("name", ROBOTS)
def test_rank_is_frame_and_point_invariant_at_random_configurations(name):
    robot = numeric_robot(name)
    rng = np.random.default_rng(SEED + 3)
    for q0 in random_configs(rng, robot.dof):
        _assert_same_rank_everywhere(robot, q0, GENERIC_RANK.get(name))


@pytest.mark.parametrize("name, label, make_singular, rank", SINGULAR_CASES,
                         ids=[f"{c[0]}-{c[1]}" for c in SINGULAR_CASES])
def test_rank_is_frame_and_point_invariant_at_singular_configurations(name, label, make_singular, rank):
    robot = numeric_robot(name)
    rng = np.random.default_rng(SEED + 4)
    for q0 in random_configs(rng, robot.dof):
        make_singular(q0, robot.model)
        _assert_same_rank_everywhere(robot, q0, rank)


def test_puma560_elbow_configuration_is_singular_symbolically():
    """The elbow q3 used above zeroes the closed-form determinant's elbow factor."""
    model = load_model("puma560")
    _, elbow = _puma_closed_form(model)
    value = elbow.subs(model.parameters).subs(model.variables[2], _puma_elbow_q3(model))
    assert abs(float(value)) < 1e-15  # double-precision atan2, |elbow| ~ 0.43


def test_planar2r_planar_task_loses_rank_in_every_frame():
    """Planar-task rank (x, y rows) drops at q2 = 0, pi in base, tool and link frames.

    Every frame of a planar arm differs from the base by a rotation about z, so
    the x, y rows transform among themselves.
    """
    model = load_model("planar2r")
    rng = np.random.default_rng(SEED + 5)
    f = sp.lambdify(model.variables,
                    [geometric_jacobian(model, task="planar", frame=fr).subs(model.parameters)
                     for fr in ("base", "tool", 1)], "numpy")
    for q0 in random_configs(rng, 2):
        assert [numeric_rank(np.asarray(J, float)) for J in f(*q0)] == [2, 2, 2]
        for q2 in (0.0, math.pi):
            assert [numeric_rank(np.asarray(J, float)) for J in f(q0[0], q2)] == [1, 1, 1]


def test_task_selects_rows_of_the_full_jacobian():
    model = load_model("puma560")
    full = geometric_jacobian(model, task="full")
    assert geometric_jacobian(model, task="position") == full[:3, :]
    assert geometric_jacobian(model, task="orientation") == full[3:, :]
    assert geometric_jacobian(model, task=[5, 0]) == full.extract([5, 0], list(range(6)))
    assert geometric_jacobian(model) == full  # the model's default task is full
