"""Where the two methods' loci differ, the report gives the SVD's verdict and its reason."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import sympy as sp

from rankloci.io import load_model
from rankloci.jacobians import task_matrix
from rankloci.methods import compute_locus
from rankloci.numeric.equations import NumericMatrix
from rankloci.reporting import build_report
from rankloci.numeric.landscape import sigma_ratios
from rankloci.compare import compare_loci
from rankloci.reporting.markdown import render_markdown
from rankloci.tolerances import RANK_RTOL

SEED = 5


@pytest.fixture(scope="module")
def planar3r():
    tm = task_matrix(load_model("planar3r"), frame="auto", numeric=True)
    a = compute_locus(tm, "svm", rng=np.random.default_rng(SEED))
    b = compute_locus(tm, "subdeterminant", rng=np.random.default_rng(SEED))
    nm = NumericMatrix(tm.matrix, tm.variables, tm.angles)
    return a, b, nm


def _spurious(locus, nm):
    """``locus`` with one more component, q1 = 0, which holds regular configurations."""
    q1 = nm.variables[0]
    sample = {v.name: 0.7 + 0.3 * k for k, v in enumerate(nm.variables)}
    sample[q1.name] = 0.0
    fake = dataclasses.replace(locus.components[0], equations=(sp.sin(q1),), solved={},
                               excluding=(), sample=sample)
    return dataclasses.replace(locus, components=locus.components + (fake,))


def test_a_missing_component_is_decided_for_the_method_that_has_it(planar3r):
    a, b, nm = planar3r
    cmp = compare_loci(a, dataclasses.replace(b, components=()), nm, {},
                       np.random.default_rng(SEED))
    assert not cmp.agree and cmp.disagreements
    assert cmp.right == ("svm",)
    for d in cmp.disagreements:
        assert (d.method, d.other) == ("svm", "subdeterminant")
        assert max(d.ratios) <= RANK_RTOL and d.right == ("svm",)
        assert np.allclose(sigma_ratios(nm.batch(np.array(d.points))), d.ratios)


def test_a_component_with_regular_points_is_decided_against_it(planar3r):
    a, b, nm = planar3r
    cmp = compare_loci(a, _spurious(b, nm), nm, {}, np.random.default_rng(SEED))
    assert not cmp.agree and cmp.right == ("svm",)
    (d,) = cmp.disagreements
    assert (d.method, d.index) == ("subdeterminant", len(b.components) + 1)
    assert min(d.ratios) > RANK_RTOL and d.right == ("svm",)


def test_the_report_says_which_method_is_right_and_why(planar3r):
    a, b, nm = planar3r
    report = build_report(load_model("planar3r"), seed=SEED, samples=2, exact=False)
    cmp = compare_loci(report.locus, _spurious(report.second, nm), nm, {},
                       np.random.default_rng(SEED))
    md = render_markdown(dataclasses.replace(report, comparison=cmp))
    summary = md.split("## 1.", 1)[0]
    assert "sides with the svm locus" in summary
    section = md.split("Method comparison", 1)[1]
    (d,) = cmp.disagreements
    assert (f"The subdeterminant component {d.index} contains regular points: sigma ratio "
            in section)
    assert "the svm locus is the right one there" in section
    assert "sin(q1) = 0" in section, "the equations of the other method's component"
