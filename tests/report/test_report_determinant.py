"""det J of a square J, factored into the components' equations, and checked."""

from __future__ import annotations

import numpy as np
import pytest
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


def _gcd(name):
    from rankloci.numeric.factored_det import maximal_minor_gcd

    model = load_model(name)
    tm = task_matrix(model, frame="auto")
    return model, tm, maximal_minor_gcd(tm.matrix, tm.variables, tm.angles)


def test_a_common_factor_of_the_maximal_minors_is_found_with_its_power():
    from rankloci.numeric.factored_det import maximal_minor_gcd

    q1, q2, q3, x, a = sp.symbols("q1 q2 q3 x a")
    f = sp.sin(q2) ** 2 * sp.cos(q3)
    J = sp.Matrix([[f, 0, a * sp.cos(q1) * f], [x, 1, sp.sin(q3)]])
    g = maximal_minor_gcd(J, [q1, q2, q3, x], [q1, q2, q3])
    assert g.minors == 3 and not g.skipped
    got = sp.Mul(*[e ** k for e, k in zip(g.factors, g.powers)])
    # the same product up to a constant: the ratio has no joint variable left
    assert sp.simplify(got / f).free_symbols <= {a}
    assert sorted(g.powers) == [1, 2]
    # tall: the transpose has the same maximal minors
    assert maximal_minor_gcd(J.T, [q1, q2, q3, x], [q1, q2, q3]).factors == g.factors


def test_pa10_gcd_is_its_elbow_the_one_component_of_codimension_one():
    model, tm, g = _gcd("pa10")
    assert tm.matrix.shape == (6, 7) and g.minors == 7
    q4 = tm.variables[3]
    assert g.factors == (sp.sin(q4),) and g.powers == (1,)
    assert {s.name for s in g.parameter_factor.free_symbols} == {"d3", "d5"}
    # the locus, computed by its own method, agrees: its components of dimension n - 1 are
    # exactly the zeros of the gcd
    n = len(tm.variables)
    locus = rankloci.locus("pa10")
    hyper = [c for c in locus.components if c.dimension == n - 1]
    assert [tuple(map(str, c.equations)) for c in hyper] == [("sin(q4)",)]


@pytest.mark.parametrize("name", ["planar3r", "ssrms"])
def test_gcd_one_means_every_component_has_codimension_two_or_more(name):
    model, tm, g = _gcd(name)
    assert tm.matrix.shape[0] < tm.matrix.shape[1]
    assert not g.skipped and g.factors == () and g.parameter_factor == 1
    n = len(tm.variables)
    locus = rankloci.locus(name)
    assert locus.components and all(c.dimension <= n - 2 for c in locus.components)


def test_the_gcd_is_skipped_with_its_reason_past_its_bounds():
    from rankloci.numeric.factored_det import maximal_minor_gcd

    _, tm, _ = _gcd("pa10")
    many = maximal_minor_gcd(tm.matrix, tm.variables, tm.angles, max_minors=6)
    assert many.skipped == "J has 7 maximal minors, more than the 6 computed"
    big = maximal_minor_gcd(tm.matrix, tm.variables, tm.angles, max_terms=3)
    assert big.skipped == "a maximal minor has more than 3 terms" and big.factors == ()


def test_a_square_matrix_is_refused():
    from rankloci.numeric.factored_det import maximal_minor_gcd

    q = sp.Symbol("q")
    with pytest.raises(ValueError, match="square"):
        maximal_minor_gcd(sp.Matrix([[sp.sin(q)]]), [q], [q])


def test_the_report_prints_the_gcd_of_the_maximal_minors():
    from rankloci.reporting import build_report
    from rankloci.reporting.markdown import render_markdown

    md = render_markdown(build_report(load_model("planar3r"), seed=0, samples=2, exact=False))
    assert "all its 3 maximal (2 $\\times$ 2) minors vanish" in md
    assert "greatest common divisor is 1" in md
