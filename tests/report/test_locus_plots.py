"""Plotting starts from a Locus: ``plot_sigma_slice`` and ``plot_tree`` take one, draw into
``ax=`` and return the Axes; ``rankloci.reporting.figures`` is reachable from the top level."""

from __future__ import annotations

import numpy as np
import pytest

import rankloci
from rankloci.errors import ArgumentError


@pytest.fixture(scope="module")
def planar2r():
    return rankloci.locus("planar2r")


def test_the_documented_path_to_the_figures_is_reachable():
    from rankloci.reporting import figures

    assert rankloci.reporting.figures is figures
    assert rankloci.reporting.figures.plot_sigma_slice is figures.plot_sigma_slice
    assert callable(rankloci.report)
    with pytest.raises(AttributeError, match="no attribute 'nope'"):
        rankloci.reporting.nope  # noqa: B018


def test_sigma_slice_of_a_locus_returns_the_axes_it_drew_into(planar2r):
    from matplotlib.figure import Figure

    from rankloci.reporting.figures import plot_sigma_slice

    ax = Figure().add_subplot()
    assert plot_sigma_slice(planar2r, ax=ax, title="planar2r") is ax
    assert ax.get_title() == "planar2r"
    curves = [ln for ln in ax.lines if (ln.get_label() or "").startswith("component")]
    assert curves                                      # the locus sin(q2) = 0 is drawn
    q2 = np.concatenate([ln.get_ydata() for ln in curves])
    assert np.allclose(np.sin(q2), 0.0, atol=1e-6)
    own = plot_sigma_slice(planar2r)
    assert own.figure is not ax.figure and own.get_xlabel() == "q1 [rad]"


def test_sigma_slice_takes_the_jacobian_and_checks_its_arguments(planar2r):
    from rankloci.reporting.figures import plot_sigma_slice

    J = rankloci.jacobian("planar2r")
    assert plot_sigma_slice(planar2r, jacobian=J, axes=(1, 0)).get_xlabel() == "q2 [rad]"
    with pytest.raises(ArgumentError, match="component=9"):
        plot_sigma_slice(planar2r, component=9)
    with pytest.raises(ArgumentError, match="are not the locus's"):
        plot_sigma_slice(planar2r, jacobian="planar3r")


def test_tree_of_a_locus_returns_the_axes(planar2r):
    from matplotlib.figure import Figure

    from rankloci.reporting.figures import plot_tree

    ax = Figure().add_subplot()
    assert plot_tree(planar2r, ax=ax) is ax
    assert len(ax.texts) == planar2r.tree.number_of_nodes()
    with pytest.raises(ArgumentError, match="no branch tree"):
        plot_tree(rankloci.Locus.from_dict(planar2r.to_dict()))
