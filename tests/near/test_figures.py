"""The figures start from what the public functions return, draw into the axes they are
given, and return those Axes."""

from __future__ import annotations

import numpy as np
import pytest
from matplotlib.figure import Figure

from rankloci.io import load_model
from rankloci.near.figures import (path_distances, path_figure, plot_distance, plot_indices,
                                   plot_joint_rates, plot_manipulability)
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
    assert plot_joint_rates(path, ax=axes[0]) is axes[0]
    assert plot_indices(path, ax=axes[1]) is axes[1]
    assert plot_distance(path.t, np.linspace(1, 0.5, len(path.t)), ["c1"], ax=axes[2]) is axes[2]
    assert len(axes[0].lines) == 4 and len(axes[1].lines) == 5 and len(axes[2].lines) == 1
    np.testing.assert_allclose(axes[0].lines[2].get_ydata(), path.rates[:, 2])


def test_path_figure_has_a_panel_per_quantity(path):
    assert len(path_figure(path)) == 2 and len(path_figure(path)[0].figure.axes) == 2
    three = path_figure(path, np.ones((len(path.t), 2)), ["a", "b"])
    assert len(three) == 3 and all(a.figure is three[0].figure for a in three)
    fig = Figure()
    given = fig.subplots(2, 1)
    assert list(path_figure(path, ax=given)) == list(given)


def test_the_distance_starts_from_a_locus(path):
    """planar4r's one component is sin q2 = sin q3 = sin q4 = 0: the distance to it is the
    norm of each of q2..q4's distance to the nearest multiple of pi."""
    import rankloci

    L = rankloci.locus("planar4r")
    D, labels = path_distances(path, L)
    wrapped = (path.q[:, 1:] + np.pi / 2) % np.pi - np.pi / 2
    np.testing.assert_allclose(D[:, 0], np.linalg.norm(wrapped, axis=1), atol=1e-8)
    ax = plot_distance(path, L)
    assert [ln.get_label() for ln in ax.lines] == labels
    np.testing.assert_allclose(ax.lines[0].get_ydata(), D[:, 0])
    assert len(path_figure(path, L)) == 3


def test_manipulability_plots_in_2d_and_3d():
    fig = Figure()
    ax = fig.add_subplot()
    assert plot_manipulability([[-1.7, -1.0], [0.7, 0.0]], ax=ax) is ax
    assert len(ax.lines) == 2, "the ellipse and the polygon"
    ax3 = plot_manipulability(np.eye(3)[:, [0, 1, 2, 0]])
    assert ax3.name == "3d" and ax3.figure.axes == [ax3]
    with pytest.raises(ValueError, match="2 or 3 rows"):
        plot_manipulability(np.eye(4))


def test_manipulability_plots_the_result_of_manipulability():
    import rankloci

    m = rankloci.manipulability("planar2r", [0.3, 1.1])
    ax = plot_manipulability(m)
    assert ax.name != "3d"
    np.testing.assert_allclose(ax.lines[0].get_xydata(),
                               plot_manipulability(m.J).lines[0].get_xydata())
