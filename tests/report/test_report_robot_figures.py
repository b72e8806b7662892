"""Pictures of the arm: planar arms in their plane, 3-D arms on a base and floor with the
end-effector frame, prismatic joints as boxes."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from rankloci.io import load_model
from rankloci.reporting.figures import plot_robot, robot_figure
from rankloci.geometry import robot_pose


#: Points computed in one plane leave a third singular value of their differences at the
#: round-off of double precision on coordinates of about one metre.
COPLANAR_REL = 1e-12


def _pose(name, **q):
    model = load_model(name)
    values = {str(v): 0.3 for v in model.variables}
    values.update(q)
    return robot_pose(model, values)


@pytest.mark.parametrize("name", ["planar2r", "planar3r", "planar4r"])
def test_planar_arms_are_drawn_in_two_dimensions(name):
    pose = _pose(name)
    assert pose.planar
    fig = robot_figure(pose, pose, highlight=(1,), arrow=np.array([1.0, 0.0, 0.0]))[0].figure
    assert [ax.name for ax in fig.axes] == ["rectilinear", "rectilinear"]
    # the arm fills its panel: every point of the chain is inside the limits
    ax = fig.axes[0]
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    for x, y, _ in pose.chain:
        assert x0 < x < x1 and y0 < y < y1


def test_spatial_arms_stay_three_dimensional_with_floor_base_and_tool_frame():
    pose = _pose("puma560")
    assert not pose.planar
    R = pose.tool_frame
    assert R.shape == (3, 3) and np.allclose(R.T @ R, np.eye(3), atol=1e-12)
    fig = robot_figure(pose, pose)[0].figure
    ax = fig.axes[0]
    assert ax.name == "3d"
    kinds = [type(c).__name__ for c in ax.collections]
    assert "Poly3DCollection" in kinds                   # the floor
    assert kinds.count("Line3DCollection") >= 3          # x, y and z of the end-effector


def test_prismatic_joints_are_drawn_as_boxes():
    pose = _pose("stanford", q3=0.8)
    as_revolute = dataclasses.replace(pose, kinds=tuple("revolute" for _ in pose.kinds))
    with_box = plot_robot(pose)
    without = plot_robot(as_revolute)
    assert len(with_box.lines) - len(without.lines) == 12     # the edges of one box


def test_the_plane_through_axis_1_and_the_task_point_is_drawn():
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    from rankloci.reporting.figures import _plane_corners

    pose = _pose("puma560")
    corners = _plane_corners(pose, 1)
    assert corners.shape == (4, 3)
    # the four corners, a point of axis 1, a second point along it and the task point all lie
    # in one plane: the matrix of their differences has rank 2
    p, d = np.asarray(pose.axis_points[0]), np.asarray(pose.axis_directions[0])
    pts = np.vstack([corners, p, p + d, pose.tool]) - corners[0]
    s = np.linalg.svd(pts, compute_uv=False)
    assert s[2] <= COPLANAR_REL * s[0] and s[1] > 0.1 * s[0]
    with_plane = plot_robot(pose, plane=1)
    without = plot_robot(pose)
    count = lambda ax: sum(isinstance(c, Poly3DCollection) for c in ax.collections)  # noqa: E731
    assert count(with_plane) == count(without) + 1
    assert "plane through axis 1" in [t.get_text() for t in with_plane.get_legend().get_texts()]
