"""The figures as a plotting API: from a Locus, Axes returned, ``ax=`` honoured, no backend
chosen."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

import report_helpers as RH
from rankloci.io import load_model
from rankloci.reporting import figures as F
from rankloci.numeric.landscape import PathData
from rankloci.geometry import robot_pose

PACKAGE = Path(F.__file__).resolve().parents[1]


def test_the_report_package_chooses_no_backend():
    offenders = [str(p.relative_to(PACKAGE)) for p in (PACKAGE / "report").rglob("*.py")
                 if re.search(r"matplotlib\.use\(|import matplotlib\.pyplot|from matplotlib "
                               r"import pyplot", p.read_text())]
    assert offenders == []


@pytest.fixture(scope="module")
def path():
    t = np.linspace(-1, 1, 41)
    w = np.abs(t) * (1.5 - t)
    return PathData(1, np.zeros(2), np.ones(2), t, w, w / 2, zeros=(0.0,))


def test_manipulability_path_draws_into_the_given_axes(path):
    from matplotlib.figure import Figure

    fig = Figure()
    ax = fig.add_subplot()
    assert F.plot_manipulability_path(path, ax=ax) is ax
    # the curve and one marker per crossing
    assert len(ax.lines) == 3
    own = F.plot_manipulability_path(path)
    assert isinstance(own.figure, Figure) and own.figure is not fig


def test_robot_picture(tmp_path):
    from matplotlib.figure import Figure

    arm = load_model("puma560")
    q = {"q1": 0.3, "q2": 0.2, "q3": -0.4, "q4": 0.5, "q5": 0.0, "q6": 0.1}
    pose = robot_pose(arm, q)
    assert pose.chain.shape[1] == 3 and len(pose.axis_points) == 6
    ax = F.plot_robot(pose, highlight=(4, 6), arrow=[0.0, 0.0, 1.0], arrow_label="lost",
                      Jv=np.eye(3)[:2])
    fig = ax.figure
    assert isinstance(fig, Figure) and ax.name == "3d" and fig.axes == [ax]
    out = tmp_path / "robot.png"
    out.write_bytes(F.figure_png(fig))
    assert RH.grey_std(out) > RH.BLANK_STD
    both = F.robot_figure(pose, robot_pose(arm, dict(q, q5=0.4)), highlight=(4, 6))
    assert len(both) == 2 and both[0].figure.axes == list(both)


def test_locus_lines_on_a_heat_map_are_thin_and_told_apart():
    from matplotlib.colors import to_hex

    from rankloci.numeric.landscape import SliceData

    xs = ys = np.linspace(-1.0, 1.0, 5)
    line = np.array([[-1.0, 0.0], [1.0, 0.0]])
    curves = tuple((k, (line + [0.0, 0.2 * k],), np.zeros((0, 2))) for k in (1, 2, 3, 4))
    data = SliceData((0, 1), xs, ys, np.full((5, 5), 0.5), np.zeros(2), None, curves)
    fig = F.plot_sigma_slice(data, ["q1", "q2"], [False, True], title="t").figure
    drawn = [ln for ln in fig.axes[0].lines if (ln.get_label() or "").startswith("component")]
    assert len(drawn) == 4
    looks = {(to_hex(ln.get_color()), ln.get_linestyle()) for ln in drawn}
    assert len({c for c, _ in looks}) == 4 and len({s for _, s in looks}) == 4
    assert all(ln.get_linewidth() == F.CURVE_WIDTH for ln in drawn)
    # thin: the colour and its dark edge together at most 1.2 pt, and the colour most of it
    # (an edge as wide as the colour hid it: the lines looked black or dark red)
    assert F.CURVE_WIDTH + F.CURVE_EDGE <= 1.2 and F.CURVE_EDGE <= F.CURVE_WIDTH / 2
    assert fig.axes[0].get_ylabel() == "q2 [m]" and fig.axes[0].get_xlabel() == "q1 [rad]"


def _task_point(ax):
    return next(ln for ln in ax.lines if ln.get_label() == "task point")


def test_the_robot_is_drawn_from_a_locus_or_from_a_model_and_q():
    import rankloci

    ax = F.plot_robot("planar2r", [0.0, 0.0])                  # a planar arm: in its plane
    assert ax.name == "rectilinear"
    x, y = (float(np.ravel(v)[0]) for v in _task_point(ax).get_data())
    assert (x, y) == (2.0, 0.0)                                # the arm stretched along x
    L = rankloci.locus("puma560", numeric=True)
    for k, comp in enumerate(L.components, start=1):
        ax = F.plot_robot(L, component=k)
        tool = robot_pose(load_model("puma560"), comp.sample).tool
        np.testing.assert_allclose(np.ravel(_task_point(ax).get_data_3d()), tool, atol=1e-12)
    pair = F.robot_figure(L, component=2)
    assert [a.name for a in pair] == ["3d", "3d"]
    with pytest.raises(rankloci.ArgumentError, match="q= must have 2 values"):
        F.plot_robot("planar2r", [0.1])
    with pytest.raises(rankloci.ArgumentError, match="component=7"):
        F.plot_robot(L, component=7)


def test_manipulability_paths_from_a_locus_cross_their_components():
    import rankloci

    L = rankloci.locus("puma560", numeric=True)
    axes = F.plot_manipulability_paths(L, units="m^3")
    assert len([a for a in axes if a.axison]) == len(L.components) == 3
    paths = F.manipulability_paths(L)
    for k, p in enumerate(paths, start=1):
        assert p.component == k and any(abs(t) < 1e-6 for t in p.zeros)   # t = 0 on it
        assert L.contains(p.point)
    one = F.plot_manipulability_path(L, component=2, seed=5)
    np.testing.assert_array_equal(one.lines[0].get_ydata(),
                                  F.manipulability_paths(L, components=[2], seed=5)[0].w)


def test_the_augmented_pair_starts_from_an_augmented_locus():
    import rankloci

    J = rankloci.jacobian("planar3r", augment=["q1 + q2 + q3"], numeric=True)
    L = rankloci.locus("planar3r", augment=["q1 + q2 + q3"], numeric=True)
    assert L.base is not None
    left, right = F.plot_augmented(L, jacobian=J)
    drawn = {a: sorted({ln.get_label() for ln in a.lines if "component" in ln.get_label()})
             for a in (left, right)}
    assert drawn[left] and all(lb.startswith("J's component") for lb in drawn[left])
    assert drawn[right] and all(lb.startswith("component") for lb in drawn[right])
    assert left.figure is right.figure
    with pytest.raises(rankloci.ArgumentError, match="not of an augmented matrix"):
        F.plot_augmented(rankloci.locus("planar3r"))
