"""The arm's geometry at one configuration, for drawing: :func:`robot_pose`.

The chain of frame origins (links), each joint axis as a point and a unit
direction, and the task point, all in the world frame, plus the size of the
arm for scaling what is drawn on it.  numpy only; the drawing is
:func:`~rankloci.reporting.figures.plot_robot`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["RobotPose", "robot_pose"]


@dataclass(frozen=True)
class RobotPose:
    """The arm at one configuration (world frame)."""

    chain: np.ndarray             # (k, 3): base, every frame origin along the chain, task point
    axis_points: tuple            # a point of each joint axis
    axis_directions: tuple        # the unit direction of each joint axis
    kinds: tuple                  # "revolute" or "prismatic" per joint
    tool: np.ndarray              # the task point
    scale: float                  # the largest distance between two points of the chain
    tool_frame: np.ndarray | None = None  # (3, 3): the last frame's axes as columns

    @property
    def planar(self) -> bool:
        """Does the arm lie in the plane z = 0 with every revolute axis along z?"""
        tol = 1e-9 * self.scale
        flat = bool(np.all(np.abs(np.asarray(self.chain)[:, 2]) <= tol))
        return flat and all(abs(abs(float(d[2])) - 1.0) <= 1e-9 if k == "revolute"
                            else abs(float(d[2])) <= 1e-9
                            for d, k in zip(self.axis_directions, self.kinds))


def robot_pose(model, q: dict, params=None) -> RobotPose:
    """The :class:`RobotPose` of ``model`` at ``q`` (variable name -> value).

    Examples
    --------
    >>> from rankloci.io import load_model
    >>> pose = robot_pose(load_model("planar2r"), {"q1": 0.0, "q2": 0.0})
    >>> [float(x) for x in pose.tool], pose.scale
    ([2.0, 0.0, 0.0], 2.0)
    """
    from ..kinematics import numeric_frames
    from .reading import axis_lines

    lines, tool = axis_lines(model, q, params)
    qs = {v: float(q[str(v)]) for v in model.variables}
    poses = numeric_frames(model, qs, dict(model.parameters if params is None else params))
    chain = [poses[0][:3, 3]]
    for T in poses[1:]:
        p = T[:3, 3]
        if np.linalg.norm(p - chain[-1]) > 1e-12:
            chain.append(p)
    if np.linalg.norm(tool - chain[-1]) > 1e-12:
        chain.append(tool)
    chain = np.array(chain)
    diffs = chain[:, None, :] - chain[None, :, :]
    scale = max(float(np.max(np.linalg.norm(diffs, axis=-1))), 1e-9)
    return RobotPose(chain, tuple(ln.point for ln in lines), tuple(ln.direction for ln in lines),
                     tuple(ln.kind for ln in lines), np.asarray(tool, dtype=float), scale,
                     np.array(poses[-1][:3, :3], dtype=float))
