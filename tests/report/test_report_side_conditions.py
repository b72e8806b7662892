"""Side conditions of a component (``Component.excluding``) in every form the report gives it.

ssrms component 1 is the closure of {equations = 0, excluding != 0}: where its excluded
expression vanishes, its two equations also hold on a set of regular configurations.  The
report must carry the side condition into the displays, the plain text and the summary, and
must not draw, sample or read the component on that set.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from rankloci.io import load_model
from rankloci.jacobians import task_matrix
from rankloci.methods import compute_locus
from rankloci.numeric.equations import NumericMatrix
from rankloci.render_text import locus_latex, locus_text
from rankloci.numeric import landscape as A
from rankloci.compare import compare_loci
from rankloci.tolerances import ON_LOCUS_RTOL

SEED = 0

#: A point drawn on the overlay as a dot is refined onto the component's equations to a
#: residual of 1e-10 (relative to the size of their coefficients), so J there is singular
#: to within a few orders of that; regular configurations of ssrms have ratios of 1e-3 and up.
OVERLAY_DOT_RTOL = 1e-7


@pytest.fixture(scope="module")
def ssrms():
    """(locus by svm as the report computes it, J in the model's frame as numbers, parameters)."""
    model = load_model("ssrms")
    tm = task_matrix(model, frame="auto")
    model_tm = task_matrix(model)
    params = dict(model_tm.parameters)
    nm = NumericMatrix(sp.Matrix(model_tm.matrix).subs(params), model_tm.variables,
                       model_tm.angles)
    locus = compute_locus(tm, "svm", rng=np.random.default_rng(SEED))
    return locus, nm, params


def _excluded(locus):
    return [(i, c) for i, c in A.model_components(locus) if c.excluding]


def test_ssrms_has_a_component_with_a_side_condition(ssrms):
    locus, _, _ = ssrms
    assert [i for i, _ in _excluded(locus)] == [1]


def test_points_solved_onto_an_excluded_component_are_singular(ssrms):
    locus, nm, params = ssrms
    for i, comp in _excluded(locus):
        pts = A.component_points(comp, nm, params, np.random.default_rng(SEED), 8)
        assert len(pts) == 9
        ratios = A.sigma_ratios(nm.batch(np.array(pts)))
        assert np.all(ratios <= ON_LOCUS_RTOL), (i, ratios)


def _slices(locus, nm):
    """A slice through the sample point of each component, on the joints the report picks."""
    for idx, comp in A.model_components(locus):
        point = np.array([comp.sample[v.name] for v in nm.variables], dtype=float)
        weights = A.equation_weights([(idx, comp)], nm.variables)
        yield idx, A.slice_joints(nm, point, weights), point


def test_overlay_of_an_excluded_component_is_singular_and_admitted(ssrms):
    locus, nm, params = ssrms
    comps = _excluded(locus)
    dots = 0
    for idx, axes, point in _slices(locus, nm):
        data = A.slice_grid(nm, comps, params, axes, point, through=idx, n=91)
        for i, lines, pts in data.curves:
            eqs = A.component_equations(dict(comps)[i], nm, params)

            def at(xy, point=point, axes=axes):
                q = point.copy()
                q[axes[0]], q[axes[1]] = xy
                return q

            for xy in list(pts) + [p for seg in lines for p in seg]:
                assert eqs.admits(at(xy)), f"slice {idx}: overlay point {xy} is excluded"
            if len(pts):
                ratios = A.sigma_ratios(nm.batch(np.array([at(xy) for xy in pts])))
                assert np.all(ratios <= OVERLAY_DOT_RTOL), f"slice {idx}: ratios {ratios}"
                dots += len(pts)
    assert dots, "no overlay dot of component 1 was tested"


def test_text_renderings_of_the_locus_keep_the_side_condition(ssrms):
    locus, _, _ = ssrms
    (i, comp), = _excluded(locus)
    text = locus_text(locus)
    for e in comp.excluding:
        assert f"{sp.sstr(e)} != 0" in text
        assert sp.latex(e) + r" &\neq 0" in locus_latex(locus)


@pytest.fixture(scope="module")
def ssrms_report():
    from rankloci.reporting import build_report

    return build_report(load_model("ssrms"), seed=SEED, samples=2, exact=False)


def _component_section(text: str, index: int, heading: str) -> str:
    start = text.index(f"{heading}Component {index}")
    end = text.find(f"{heading}Component {index + 1}", start)
    return text[start:end if end > 0 else None]


@pytest.mark.slow
def test_every_display_of_an_excluded_component_states_its_side_condition(ssrms_report):
    from rankloci.reporting.latex import render_latex
    from rankloci.reporting.markdown import render_markdown

    views = [v for v in ssrms_report.components if v.component.excluding]
    assert views
    md, tex = render_markdown(ssrms_report), render_latex(ssrms_report)
    for v in views:
        c = v.component
        section = _component_section(md, v.index, "### ")
        for e in c.excluding:
            assert f"{sp.sstr(e)} != 0" in section, "plain text"
        for f in v.folded_excluding or c.excluding:
            assert sp.latex(f) + r" &\neq 0" in section, "compact display"
        displays = section.split("$$")[1::2]
        assert displays and all(r"\neq 0" in d for d in displays), "a display without it"
        tsec = _component_section(tex, v.index, "section{")
        assert "!=" in tsec and r"\neq 0" in tsec
        row = next(ln for ln in md.split("\n## ", 1)[0].splitlines()
                   if ln.startswith(f"| [{v.index}](#component-{v.index}) |"))
        for f in v.folded_excluding or c.excluding:
            assert sp.latex(f) + r" \neq 0" in row, "summary table"


@pytest.mark.slow
def test_methods_agree_on_ssrms_once_the_side_condition_is_kept(ssrms):
    """The subdeterminant method cuts component 1 out with a third equation where svm has a
    side condition; points of svm's component 1 outside its excluded set are on it."""
    locus, nm, params = ssrms
    tm = task_matrix(load_model("ssrms"), frame="auto")
    other = compute_locus(tm, "subdeterminant", rng=np.random.default_rng(SEED))
    cmp = compare_loci(locus, other, nm, params, np.random.default_rng(SEED))
    assert cmp.agree, cmp.differences
