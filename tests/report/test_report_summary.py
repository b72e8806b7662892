"""The summary table up front, cross-references to sections and figures, and each equation printed
once in the body."""

from __future__ import annotations

import re

import numpy as np
import pytest
import sympy as sp

from rankloci.io import load_model
from rankloci.reporting import build_report
from rankloci.reporting.escape import heading_anchor
from rankloci.reporting.latex import render_latex
from rankloci.reporting.markdown import render_markdown

SEED = 4
HEADER = "| no. | equations | reading | lost motion | figures | within limits |"


@pytest.fixture(scope="module")
def puma():
    return build_report(load_model("puma560"), seed=SEED, samples=2, exact=False)


def _summary_rows(md: str) -> list[list[str]]:
    head = md.split("\n## ", 1)[0]
    assert HEADER in head, "no summary table before the first section"
    lines = head.split(HEADER, 1)[1].strip().splitlines()[1:]
    return [[c.strip() for c in ln.strip("|").split(" | ")] for ln in lines if ln.startswith("|")]


def test_summary_table_has_a_row_per_component_up_front(puma):
    md = render_markdown(puma)
    rows = _summary_rows(md)
    main = [v for v in puma.components if not v.special]
    assert [r[0] for r in rows] == [f"[{v.index}](#component-{v.index})" for v in main]
    for row, v in zip(rows, main):
        assert row[1].count("= 0}$") >= 1, row
        assert row[2] == ("; ".join(v.geometry) or "-")
        assert row[3] != "-" and (row[3].startswith(("no translation", "no rotation"))
                                  or "as a wrench" in row[3]), row
        assert row[4] != "-", f"component {v.index} has no figure"


def test_links_go_to_headings_and_figures_that_exist(puma):
    md = render_markdown(puma)
    anchors = {heading_anchor(h) for h in re.findall(r"^#+ (.*)$", md, flags=re.M)}
    files = {f.name for f in puma.figures}
    links = re.findall(r"(?<!!)\[([^\]]*)\]\(([^)]*)\)", md)
    assert links
    for text, target in links:
        if target.startswith("#"):
            assert target[1:] in anchors, target
        else:
            assert target in files and re.fullmatch(r"(Figure|Fig\.) \d+", text), (text, target)
    numbers = [int(n) for n in re.findall(r"^\*Figure (\d+):", md, flags=re.M)]
    assert numbers == list(range(1, len(puma.figures) + 1))


def test_latex_refers_with_ref_and_hyperref(puma):
    tex = render_latex(puma)
    labels = set(re.findall(r"\\label\{([^}]+)\}", tex))
    refs = re.findall(r"\\(?:ref|hyperref)[\[{]([^\]}]+)[\]}]", tex)
    assert refs and set(refs) <= labels
    assert "\\usepackage[hidelinks]{hyperref}" in tex
    fragment = render_latex(puma, fragment=True)
    assert "\\providecommand{\\hyperref}[2][]{#2}" in fragment


def test_each_component_has_one_display_in_the_notation_of_j(puma):
    """The display is the compact form when there is one, and it equals the equations."""
    notation = {s: f for s, f in puma.notation}
    params = {p: float(v) for p, v in puma.model.parameters.items()}
    rng = np.random.default_rng(SEED)
    for v in puma.components:
        if not v.folded:
            continue
        c = v.component
        eqs = [e for e in c.equations if e not in c.parameter_conditions]
        assert len(v.folded) == len(eqs)
        for f, e in zip(v.folded, eqs):
            back = sp.sympify(f).xreplace(notation)
            for _ in range(3):
                q = {s: rng.uniform(-3, 3) for s in e.free_symbols | back.free_symbols
                     if s not in params}
                got = float(back.subs(params).subs(q))
                want = float(sp.sympify(e).subs(params).subs(q))
                assert abs(got - want) <= 1e-9 * (1 + abs(want)), (f, e)
    md = render_markdown(puma)
    for v in puma.components:
        section = md.split(f"### Component {v.index}\n", 1)[1].split("\n#", 1)[0]
        assert section.count("$$") == 2, f"component {v.index}: not one display"
        if v.folded:
            link = "[the Jacobian section](#appendix-a-the-symbolic-jacobian)"
            assert f"notation of {link}" in section


def test_summary_says_which_components_the_joint_limits_let_the_arm_reach(puma):
    md = render_markdown(puma)
    rows = _summary_rows(md)
    assert [r[5] for r in rows] == [c.word for c in puma.limits] == ["yes"] * len(rows)
    head = md.split("\n## ", 1)[0]
    assert "**Joint limits.** Components 1, 2 and 3 meet the joint-limit box" in head
    names = [str(v) for v in puma.locus.variables]
    limits = [j.limits for j in puma.model.joints]
    for check in puma.limits:
        assert all(lo <= check.sample[n] <= hi for n, (lo, hi) in zip(names, limits))
        assert puma.locus.contains(check.sample)
        section = md.split(f"### Component {check.component}", 1)[1].split("\n#", 1)[0]
        assert "Within the joint limits: yes, for example at q1 = " in section
    # the DH table gives the limits in degrees
    assert "| 2 | revolute | $q_{2}$ | $0$ | $a_{2}$ | $0$ | [-45, 225] deg |" in md


def test_a_model_without_limits_says_so():
    report = build_report(load_model("planar2r"), seed=SEED, samples=2, exact=False)
    md = render_markdown(report)
    assert "| within limits |" not in md
    assert "**Joint limits.** The model gives no joint limits" in md


def test_every_displayed_equation_is_numbered(puma):
    md = render_markdown(puma)
    displays = md.split("$$")[1::2]
    tags = [re.search(r"\\tag\{(\d+)\}\s*$", d) for d in displays]
    assert all(tags), [d for d, t in zip(displays, tags) if not t][:2]
    assert [int(t.group(1)) for t in tags] == list(range(1, len(displays) + 1))
    tex = render_latex(puma)
    assert "align*" not in tex and "\\[\n" not in tex
    numbered = tex.count("\\begin{equation}") + tex.count("\\begin{align}")
    assert numbered == len(displays)
    # an aligned display carries one number: every line but the last is \notag
    for body in re.findall(r"\\begin\{align\}\n(.*?)\n\\end\{align\}", tex, flags=re.S):
        lines = body.split(" \\\\\n")
        assert all(ln.endswith("\\notag") for ln in lines[:-1]) and "\\notag" not in lines[-1]


def test_special_components_are_headed_below_their_subsection(puma):
    headings = [h for h in render_markdown(puma).splitlines() if h.startswith("#")]
    at = next(i for i, h in enumerate(headings) if "special parameter values" in h)
    assert headings[at].startswith("### ")
    below = headings[at + 1]
    assert below.startswith("#### Component ")
