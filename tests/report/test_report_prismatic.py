"""Prismatic joints are lengths: sampled and plotted in metres within their stroke, never in rad."""

from __future__ import annotations

import re

import numpy as np
import pytest
import sympy as sp

from rankloci.io.toml_model import parse_model
from rankloci.limits import DEFAULT_STROKE
from rankloci.numeric.equations import NumericMatrix
from rankloci.numeric import landscape as A
from rankloci.reporting import build_report
from rankloci.reporting.markdown import render_markdown

#: A polar arm: joint 1 turns, joint 2 slides radially; J loses rank where q2 = 0.
POLAR = """\
name = "polar"
title = "RP polar arm"
source = "written for the tests"
convention = "dh"
task = "planar"

[[joint]]
alpha = "pi/2"

[[joint]]
kind = "prismatic"
{limits}
"""


def polar(limits: str = ""):
    return parse_model(POLAR.format(limits=limits), file="polar.toml")


@pytest.fixture(scope="module")
def report():
    return build_report(polar("limits = [-0.5, 0.8]"), seed=2, samples=2, exact=False)


def test_no_prismatic_coordinate_is_given_in_rad(report):
    md = render_markdown(report)
    # no value of the length q2 in rad, and no joint-space distance in rad alone
    assert not re.search(r"q2 = \S+ rad", md)
    assert not re.search(r"\d rad (from|across)", md)
    assert "0.05 joint-space units (rad for revolute, m for prismatic joints)" in md
    # the sample point gives each coordinate its unit, and no signed zero
    line = next(x for x in md.splitlines() if x.startswith("- Sample point:"))
    assert re.fullmatch(r"- Sample point: q1 = [+-]\d\.\d{4} rad, q2 = 0 m\.", line), line


def test_heat_map_of_a_length_spans_its_stroke():
    arm = polar("limits = [-0.5, 0.8]")
    from rankloci.jacobians import task_matrix

    tm = task_matrix(arm)
    nm = NumericMatrix(sp.Matrix(tm.matrix), tm.variables, tm.angles)
    q2 = tm.variables[1]
    point = np.array([0.3, 0.0])
    unbounded = A.slice_grid(nm, [], {}, (0, 1), point)
    assert unbounded.ys[0] == -1.0 and unbounded.ys[-1] == 1.0    # the old +-max(1, 2|q|)
    nm.strokes = {q2: (-0.5, 0.8)}
    data = A.slice_grid(nm, [], {}, (0, 1), point)
    assert (data.ys[0], data.ys[-1]) == (-0.5, 0.8)
    assert data.xs[-1] - data.xs[0] == pytest.approx(2 * np.pi)    # the angle keeps a full turn


def test_samples_and_figures_stay_within_the_stroke(report):
    comp = report.locus.components[0]
    assert -0.5 <= comp.sample["q2"] <= 0.8
    assert "Sample points are taken within the joint limits." in report.notes
    # without limits a length is sampled within the default stroke, and the report says so
    free = build_report(polar(), seed=2, samples=2, exact=False)
    lo, hi = DEFAULT_STROKE
    assert lo <= free.locus.components[0].sample["q2"] <= hi
    assert (f"prismatic joints without limits within [{lo:g}, {hi:g}] m") in " ".join(free.notes)
