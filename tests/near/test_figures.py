"""The figures draw into the axes they are given and return their Figure."""

from __future__ import annotations

import numpy as np
import pytest
from matplotlib.figure import Figure

from rankloci.io import load_model
from rankloci.near.figures import (path_figure, plot_distance, plot_indices, plot_joint_rates,
                                   plot_manipulability)
from rankloci.near.path import Kinematics, joint_rates_along


@pytest.fixture(scope="module")
def path():
    kin = Kinematics(load_model("planar4r"))
    q0 = np.array([0.62, 0.23, 1.0, 0.46])
    x0 = kin.position(q0)
    return joint_rates_along(kin, q0, [x0, x0 - [0.5, 0.0]], steps=20)


def test_path_plots_use_the_given_axes(path):
    fig = Figure()
    axes = fig.subplots(3, 1)
    assert plot_joint_rates(path, ax=axes[0]) is fig
    assert plot_indices(path, ax=axes[1]) is fig
    assert plot_distance(path.t, np.linspace(1, 0.5, len(path.t)), ["c1"], ax=axes[2]) is fig
    assert len(axes[0].lines) == 4 and len(axes[1].lines) == 5 and len(axes[2].lines) == 1
    np.testing.assert_allclose(axes[0].lines[2].get_ydata(), path.rates[:, 2])


def test_path_figure_has_a_panel_per_quantity(path):
    assert len(path_figure(path).axes) == 2
    assert len(path_figure(path, np.ones((len(path.t), 2)), ["a", "b"]).axes) == 3


def test_manipulability_plots_in_2d_and_3d():
    fig = Figure()
    ax = fig.add_subplot()
    assert plot_manipulability([[-1.7, -1.0], [0.7, 0.0]], ax=ax) is fig
    assert len(ax.lines) == 2, "the ellipse and the polygon"
    fig3 = plot_manipulability(np.eye(3)[:, [0, 1, 2, 0]])
    assert fig3.axes[0].name == "3d"
    with pytest.raises(ValueError, match="2 or 3 rows"):
        plot_manipulability(np.eye(4))
