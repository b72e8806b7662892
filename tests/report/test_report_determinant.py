"""det J of a square J, factored into the components' equations, and checked."""

from __future__ import annotations

import numpy as np
import sympy as sp

import rankloci
from rankloci.io import load_model
from rankloci.jacobians import task_matrix
from rankloci.numeric.factored_det import factored_determinant


def _factored(name, drop=None):
    model = load_model(name)
    tm = task_matrix(model)
    locus = rankloci.locus(name)
    eqs = [c.equations[0] for c in locus.components]
    if drop is not None:
        eqs.pop(drop)
    kinds = [j.kind for j in model.joints]
    return model, factored_determinant(tm.matrix, tm.variables, kinds, eqs,
                                       dict(tm.parameters), np.random.default_rng(0))


def test_puma560_det_is_minus_a2_times_its_three_components():
    model, d = _factored("puma560")
    assert d is not None and d.exact_constant and d.powers == (1, 1, 1)
    a2 = next(p for p in model.parameters if p.name == "a2")
    assert d.constant == -a2


def test_stanford_boom_counts_twice():
    _, d = _factored("stanford")
    assert d is not None and d.constant == 1
    by_factor = {str(f): m for f, m in zip(d.factors, d.powers)}
    assert by_factor == {"q3": 2, "sin(q2)": 1, "sin(q5)": 1}


def test_a_missing_factor_is_refused():
    """Without the wrist factor the ratio det J / product varies: no factorisation is shown."""
    _, d = _factored("puma560", drop=2)
    assert d is None


def test_a_wrong_factor_is_refused():
    q1, q2 = sp.symbols("q1 q2")
    J = sp.Matrix([[sp.sin(q2), 0], [q1, 1]])
    d = factored_determinant(J, [q1, q2], ["revolute"] * 2, [sp.cos(q2)], {},
                             np.random.default_rng(0))
    assert d is None


def test_the_report_displays_the_factored_determinant():
    from rankloci.reporting import build_report
    from rankloci.reporting.markdown import render_markdown

    md = render_markdown(build_report(load_model("stanford"), seed=0, samples=2, exact=False))
    assert "\\det J = q_{3}^{2} s_{2} s_{5}" in md
    assert "the constant factor is $1$" in md
