"""The figures as a plotting API: Figures returned, ``ax=`` honoured, no backend chosen."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

import report_helpers as RH
from rankloci.io import load_model
from rankloci.reporting import figures as F
from rankloci.reporting.analysis import PathData
from rankloci.reporting.robot import robot_pose

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
    assert F.plot_manipulability_path(path, ax=ax) is fig
    # the curve and one marker per crossing
    assert len(ax.lines) == 3
    own = F.plot_manipulability_path(path)
    assert isinstance(own, Figure) and own is not fig


def test_robot_picture(tmp_path):
    from matplotlib.figure import Figure

    arm = load_model("puma560")
    q = {"q1": 0.3, "q2": 0.2, "q3": -0.4, "q4": 0.5, "q5": 0.0, "q6": 0.1}
    pose = robot_pose(arm, q)
    assert pose.chain.shape[1] == 3 and len(pose.axis_points) == 6
    fig = F.plot_robot(pose, highlight=(4, 6), arrow=[0.0, 0.0, 1.0], arrow_label="lost",
                       Jv=np.eye(3)[:2])
    assert isinstance(fig, Figure) and fig.axes[0].name == "3d"
    out = tmp_path / "robot.png"
    out.write_bytes(F.figure_png(fig))
    assert RH.grey_std(out) > RH.BLANK_STD
    both = F.robot_figure(pose, robot_pose(arm, dict(q, q5=0.4)), highlight=(4, 6))
    assert len(both.axes) == 2


def test_locus_lines_on_a_heat_map_are_thin_and_told_apart():
    from matplotlib.colors import to_hex

    from rankloci.reporting.analysis import SliceData

    xs = ys = np.linspace(-1.0, 1.0, 5)
    line = np.array([[-1.0, 0.0], [1.0, 0.0]])
    curves = tuple((k, (line + [0.0, 0.2 * k],), np.zeros((0, 2))) for k in (1, 2, 3, 4))
    data = SliceData((0, 1), xs, ys, np.full((5, 5), 0.5), np.zeros(2), None, curves)
    fig = F.plot_sigma_slice(data, ["q1", "q2"], [False, True], title="t").figure
    drawn = [ln for ln in fig.axes[0].lines if (ln.get_label() or "").startswith("component")]
    assert len(drawn) == 4
    looks = {(to_hex(ln.get_color()), ln.get_linestyle()) for ln in drawn}
    assert len({c for c, _ in looks}) == 4 and len({s for _, s in looks}) == 4
    assert all(ln.get_linewidth() <= 0.7 for ln in drawn)
    assert fig.axes[0].get_ylabel() == "q2 [m]" and fig.axes[0].get_xlabel() == "q1 [rad]"
