"""The parts of a report: readings, math layout, analysis, the timeout and augmented cases, and
the all-or-nothing writing."""

from __future__ import annotations

import dataclasses
import itertools
import time

import numpy as np
import pytest
import sympy as sp

import report_helpers as RH
from rankloci.io import load_model
from rankloci.loci import Outcome
from rankloci.reporting import ReportError, build_report, write_report
from rankloci.compare import compare_loci
from rankloci.reporting.tree_summary import tree_summary
from rankloci.reporting.markdown import render_markdown
from rankloci.reporting.mathfmt import LINE_WIDTH, broken_lines, latex, math_width
from rankloci.reporting.matrixfmt import jacobian_display
from rankloci.reporting.interpret import component_reading
from rankloci.reporting.reading import direction_readings

SEED = 5


# --- readings -----------------------------------------------------------------------------------

_Q0 = {"q1": 0.3, "q2": 0.2, "q3": -0.4, "q4": 0.5, "q5": 0.0, "q6": 0.1}
_Q1 = {"q1": 0.3, "q2": 0.7, "q3": 0.2, "q4": 0.5, "q5": 0.9, "q6": 0.1}


def test_puma_wrist_and_elbow_readings():
    puma = load_model("puma560")
    rng = np.random.default_rng(SEED)
    wrist = component_reading(puma, [sp.sin(sp.Symbol("q5"))], ["$s_5 = 0$"],
                              [_Q0], [[]], rng)
    assert wrist.text == "Wrist singularity: axes 4 and 6 are collinear"
    # elbow: a3 sin q3 + d4 cos q3 = 0
    q3 = float(sp.atan2(-0.4318, 0.0203))
    elbow = component_reading(puma, [sp.Symbol("e")], ["$e = 0$"],
                              [dict(_Q1, q3=q3)], [[]], rng)
    # axes 2 and 3 are parallel at every pose: the reading does not repeat it
    assert elbow.text == ("Elbow singularity (the arm is stretched out or folded back): the task "
                          "point lies in the plane of axes 2 and 3")


def test_no_geometric_claim_at_a_regular_configuration():
    puma = load_model("puma560")
    assert component_reading(puma, [sp.Symbol("e")], ["$e = 0$"],
                             [_Q1], [[]],
                             np.random.default_rng(SEED)) is None


def test_direction_reading_needs_a_real_null_vector():
    J = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 0.0]])
    labels = ["vx", "vy", "wz"]
    assert direction_readings(J, [0, 0, 1], labels) == [
        "the end-effector cannot rotate about [+1.000] over (z) in the base frame"]
    assert direction_readings(J, [1, 0, 0], labels) == []       # not a left null vector
    J2 = np.array([[1.0, 2.0], [2.0, 4.0]])
    text = direction_readings(J2, [2, -1], ["vx", "vy"])
    assert len(text) == 1 and "cannot translate along [+0.894, -0.447]" in text[0]


def test_mixed_direction_is_read_as_a_relation():
    J = np.array([[1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])   # rows vx, vy, wz
    text = direction_readings(J, [1.0, 1.0, -1.0], ["vx", "vy", "wz"])
    assert len(text) == 1 and "a.v + b.w = 0" in text[0] and "no joint torque" in text[0]


# --- math layout --------------------------------------------------------------------------------

def test_long_equations_are_broken_within_the_line_width():
    xs = sp.symbols("q1:9")
    long = sum(sp.Symbol(f"a{k}") * sp.sin(x) * sp.cos(y)
               for k, (x, y) in enumerate(itertools.combinations(xs, 2)))
    lines = broken_lines(long, tail=" = 0")
    assert len(lines) > 3
    assert all(math_width(ln) <= LINE_WIDTH for ln in lines)
    n_terms = len(sp.Add.make_args(long))
    joined = " ".join(lines)
    assert joined.count("\\sin") == n_terms, "every term is printed once"


@pytest.mark.parametrize("name", ["planar3r", "puma560", "ssrms", "mobile10"])
def test_jacobian_display_is_equal_to_the_jacobian(name):
    from rankloci.jacobians import task_matrix

    tm = task_matrix(load_model(name), frame="auto")
    jd = jacobian_display(tm.matrix, tm.variables, tm.parameters)
    back = {s: f for s, f in jd.abbreviations}
    subs = dict(jd.definitions)
    rng = np.random.default_rng(SEED)
    values = {v: rng.uniform(-3, 3) for v in tm.variables}
    values |= {p: float(val) for p, val in tm.parameters.items()}
    for i, j in itertools.product(range(tm.shape[0]), range(tm.shape[1])):
        e = jd.entries[i][j]
        for _ in range(len(subs) + 1):
            e = e.xreplace(subs)
        e = e.xreplace(back)
        assert abs(float((e - tm.matrix[i, j]).subs(values))) < 1e-9, (i, j)


def test_wide_jacobian_is_laid_out_in_columns_that_fit():
    from rankloci.jacobians import task_matrix
    from rankloci.reporting.content import matrix_blocks

    tm = task_matrix(load_model("ssrms"), frame="auto")
    jd = jacobian_display(tm.matrix, tm.variables, tm.parameters)
    assert jd.layout == "columns"
    for block in matrix_blocks(jd):
        for line in getattr(block, "lines", ()):
            # a column vector's width is its widest entry, not the sum of its rows
            rows = line.split(r",\quad ")
            width = sum(max(math_width(r) for r in col.split(r" \\ ")) for col in rows)
            assert width <= LINE_WIDTH + 6 * len(rows), line


# --- analysis -----------------------------------------------------------------------------------

def test_tree_summary_keeps_paths_to_components():
    import networkx as nx

    tree = nx.DiGraph()
    tree.add_node(0, condition="(all configurations)", outcome=Outcome.REFINED)
    for k in range(1, 80):
        tree.add_node(k, condition=f"f{k}", outcome=Outcome.EMPTY)
        tree.add_edge(0, k)
    tree.add_node(80, condition="sin(q2/2)", outcome=Outcome.NO_REDUNDANT_COLUMN)
    tree.add_edge(3, 80)
    tree.nodes[3]["outcome"] = Outcome.REFINED
    s = tree_summary(tree, max_nodes=20)
    assert s.total_nodes == 81 and s.graph.number_of_nodes() < 10
    roles = nx.get_node_attributes(s.graph, "role")
    assert roles[80] == "component" and "summary" in roles.values()
    label = [d["label"] for n, d in s.graph.nodes(data=True) if d["role"] == "summary"][0]
    assert "78 more branches" in label and "78 x empty" in label


def test_only_component_outcomes_make_component_leaves():
    import networkx as nx

    tree = nx.DiGraph()
    tree.add_node(0, condition="(all configurations)", outcome=Outcome.REFINED)
    tree.add_node(1, condition="f1", outcome=Outcome.NO_REAL_POINT)
    tree.add_node(2, condition="f2", outcome=Outcome.ALL_MINORS_VANISH)
    tree.add_node(3, condition="f3")                    # no outcome recorded
    tree.add_edges_from([(0, 1), (0, 2), (0, 3)])
    s = tree_summary(tree)
    assert nx.get_node_attributes(s.graph, "role") == {0: "inner", 1: "leaf", 2: "component",
                                                       3: "leaf"}
    assert s.outcomes == {str(Outcome.NO_REAL_POINT): 1, str(Outcome.ALL_MINORS_VANISH): 1, "": 1}
    assert f"[{Outcome.NO_REAL_POINT}]" in s.graph.nodes[1]["label"]


def test_compare_loci_sees_a_missing_component():
    from rankloci.jacobians import task_matrix
    from rankloci.methods import compute_locus
    from rankloci.numeric.equations import NumericMatrix

    model = load_model("planar3r")
    tm = task_matrix(model, frame="auto", numeric=True)
    a = compute_locus(tm, "svm", rng=np.random.default_rng(SEED))
    b = compute_locus(tm, "subdeterminant", rng=np.random.default_rng(SEED))
    nm = NumericMatrix(tm.matrix, tm.variables, tm.angles)
    assert compare_loci(a, b, nm, {}, np.random.default_rng(SEED)).agree
    empty = dataclasses.replace(b, components=())
    cmp = compare_loci(a, empty, nm, {}, np.random.default_rng(SEED))
    assert not cmp.agree and not cmp.identical and "on no subdeterminant component" in \
        cmp.differences[0]


# --- the timeout --------------------------------------------------------------------------------

def test_a_locus_that_does_not_finish_still_gives_a_report(tmp_path, monkeypatch):
    # a locus kept from an earlier computation in this process would be shown at once
    monkeypatch.setattr("rankloci.api.calls._PIPELINE", {})
    ticks = itertools.count()
    clock = lambda: float(next(ticks))  # noqa: E731 - every call is one "second" later
    report = build_report(load_model("planar3r"), seed=SEED, samples=2, timeout=0.5, clock=clock)
    assert report.locus is None and report.check is None
    md = render_markdown(report)
    assert "did not finish within 0.5 s" in md
    assert "J = \\begin{bmatrix}" in md and "Denavit-Hartenberg" in md
    assert report.figure("sigma"), "the heat map is drawn without the locus"
    paths = write_report(report, tmp_path / "out", formats=("md",))
    assert {p.name for p in paths} >= {"planar3r.md", "planar3r-sigma-1.png"}
    assert RH.grey_std(tmp_path / "out" / "planar3r-sigma-1.png") > RH.BLANK_STD


# --- augmented Jacobians ------------------------------------------------------------------------

def test_algorithmic_section_of_an_augmented_model(tmp_path):
    """planar3r_orient stacks the orientation row under J: its locus has a base and kinds."""
    report = build_report(load_model("planar3r_orient"), seed=SEED, samples=2, exact=False)
    assert report.augmented and getattr(report.locus, "base", None) is not None
    md = render_markdown(report)
    assert "Algorithmic singularities" in md
    kinds = {v.kind for v in report.augmented if not v.special}
    assert kinds and kinds <= {"kinematic", "algorithmic", "mixed"}
    assert "without the constraint rows" in md
    assert len(report.figure("augmented")) == 1
    paths = write_report(report, tmp_path, formats=("md",))
    png = tmp_path / "planar3r_orient-augmented.png"
    assert png in paths and RH.grey_std(png) > RH.BLANK_STD
    from rankloci.reporting.figures import AUGMENTED_SIZE, DPI

    assert RH.png_size(png) == (round(AUGMENTED_SIZE[0] * DPI), round(AUGMENTED_SIZE[1] * DPI))


def test_no_algorithmic_section_without_constraint_rows():
    report = build_report(load_model("planar2r"), seed=SEED, samples=2, exact=False)
    assert not report.augmented and not report.figure("augmented")
    assert "Algorithmic singularities" not in render_markdown(report)


# --- all or nothing -----------------------------------------------------------------------------

def test_a_failing_pdf_build_writes_nothing(tmp_path):
    report = build_report(load_model("planar2r"), seed=SEED, samples=2, exact=False)
    target = tmp_path / "new" / "out"
    with pytest.raises(ReportError):
        write_report(report, target, latex=("pdflatex", "/bin/false"))
    assert list(tmp_path.iterdir()) == [], "a failed write left files or directories"
    (tmp_path / "old").mkdir()
    (tmp_path / "old" / "planar2r.md").write_text("previous", encoding="utf-8")
    with pytest.raises(ReportError):
        write_report(report, tmp_path / "old", latex=("pdflatex", "/bin/false"))
    assert [p.name for p in (tmp_path / "old").iterdir()] == ["planar2r.md"]
    assert (tmp_path / "old" / "planar2r.md").read_text(encoding="utf-8") == "previous"


def test_rewriting_removes_figures_the_report_no_longer_has(tmp_path):
    report = build_report(load_model("planar2r"), seed=SEED, samples=2, exact=False)
    (tmp_path / "planar2r-sigma-9.png").write_bytes(b"old")
    (tmp_path / "notes.png").write_bytes(b"mine")
    write_report(report, tmp_path, formats=("md",))
    assert not (tmp_path / "planar2r-sigma-9.png").exists()
    assert (tmp_path / "notes.png").read_bytes() == b"mine"


def test_build_report_does_not_read_the_clock_without_one(monkeypatch):
    # the locus pipeline times itself (Locus.seconds, the certificate's seconds): its locus is
    # computed first, so that what is tested is the report's own building and figures
    from rankloci.api.calls import certified_locus

    certified_locus(load_model("planar2r"), seed=SEED)
    monkeypatch.setattr(time, "perf_counter", lambda: pytest.fail("clock read"))
    monkeypatch.setattr(time, "monotonic", lambda: pytest.fail("clock read"))
    report = build_report(load_model("planar2r"), seed=SEED, samples=2, exact=False)
    assert all(sec == 0.0 for _, sec in report.timings)


def test_latex_of_equations_matches_sympy():
    q5 = sp.Symbol("q5", real=True)
    assert latex(sp.sin(q5)) == sp.latex(sp.sin(q5))
