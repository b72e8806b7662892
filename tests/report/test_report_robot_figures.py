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

    from rankloci.geometry import plane_through_axis

    pose = _pose("puma560")
    corners = plane_through_axis(pose, 1)
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


#: A sample point is on its component to about 1e-12 relative; the axes it makes collinear
#: (and the point it puts on an axis) are so to a few orders of magnitude above it, not more.
ON_LINE_REL = 1e-8


def _named_line_figure(name, equations):
    """The singular panel of ``name``'s component with ``equations`` (as strings, sorted),
    drawn with the lines its reading names, and the pose and the lines."""
    from matplotlib.colors import to_hex

    from rankloci.augmented import augmented_locus
    from rankloci.jacobians import task_matrix
    from rankloci.methods import method_for
    from rankloci.reporting.build import component_views
    from rankloci.reporting.figure_files import reading_lines
    from rankloci.reporting.figures import READING_LINE_COLOUR

    model = load_model(name)
    tm = task_matrix(model, frame="auto")
    locus = augmented_locus(model, tm, method_for(tm.shape), seed=0)
    view = next(v for v in component_views(model, locus, seed=0)
                if tuple(sorted(map(str, v.component.equations))) == equations)
    named = reading_lines(view.readings)
    pose = robot_pose(model, {k: float(v) for k, v in view.component.sample.items()})
    ax = robot_figure(pose, pose, lines=tuple((g[0], label) for g, label, _ in named))[0]
    drawn = {ln.get_label(): ln for ln in ax.get_lines()
             if to_hex(ln.get_color()) == READING_LINE_COLOUR}
    return pose, named, drawn, ax


def _check_line(pose, joints, line):
    ends = np.asarray(line.get_data_3d(), dtype=float).T
    u = ends[1] - ends[0]
    length = float(np.linalg.norm(u))
    u /= length
    # extended through the arm: it reaches past every point of the chain along its direction
    s = (np.asarray(pose.chain) - ends[0]) @ u
    assert s.min() > 0 and s.max() < length and length >= 0.4 * pose.scale
    for k in joints:
        p = np.asarray(pose.axis_points[k - 1])
        d = np.asarray(pose.axis_directions[k - 1])
        off = (p - ends[0]) - ((p - ends[0]) @ u) * u    # the joint origin is on the line
        assert np.linalg.norm(off) <= ON_LINE_REL * pose.scale, (k, off)
        assert np.linalg.norm(np.cross(u, d)) <= ON_LINE_REL, (k, d, u)  # parallel to its axis


def test_the_collinear_axes_a_reading_names_are_drawn_as_one_line():
    pose, named, drawn, ax = _named_line_figure("puma560", ("sin(q5)",))
    assert [g for g, _, _ in named] == [(4, 6)]
    assert list(drawn) == ["axes 4 and 6 (collinear)"]
    _check_line(pose, (4, 6), drawn["axes 4 and 6 (collinear)"])
    assert "axes 4 and 6 (collinear)" in [t.get_text() for t in ax.figure.legends[0].get_texts()]
    # the other joints' axes are not on that line: the check can fail
    with pytest.raises(AssertionError):
        _check_line(pose, (1,), drawn["axes 4 and 6 (collinear)"])


def test_an_axis_a_point_lies_on_is_drawn_as_a_line():
    # the Stanford arm's boom at zero extension: the wrist centre lies on axis 2
    pose, named, drawn, _ = _named_line_figure("stanford", ("q3",))
    assert [g for g, _, _ in named] == [(2,)]
    _check_line(pose, (2,), drawn["axis 2 (a point on it)"])
    centre = np.asarray(pose.axis_points[3])   # axes 4, 5 and 6 meet at the wrist centre
    ends = np.asarray(drawn["axis 2 (a point on it)"].get_data_3d(), dtype=float).T
    u = (ends[1] - ends[0]) / np.linalg.norm(ends[1] - ends[0])
    off = (centre - ends[0]) - ((centre - ends[0]) @ u) * u
    assert np.linalg.norm(off) <= ON_LINE_REL * pose.scale


def test_each_line_a_reading_names_is_taken_once():
    # pa10's shoulder and wrist at once: two groups, each named once
    from rankloci.reporting.figure_files import reading_lines

    named = reading_lines(["Shoulder and wrist singularities at once: where $s_{2} = 0$, axes 1 "
                           "and 3 are collinear; the point where axes 3, 4 and 5 meet lies on "
                           "axis 1; where $s_{6} = 0$, axes 5 and 7 are collinear; the task point "
                           "lies on axis 5"])
    assert [g for g, _, _ in named] == [(1, 3), (5, 7)]
