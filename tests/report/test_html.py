"""The HTML report: one self-contained page with the summary, every component's equations and
an arm view whose data put each component's sample on the locus.

The page in a real browser is tested in test_html_browser.py.
"""

from __future__ import annotations

import html
import json
import re

import numpy as np
import pytest
import sympy as sp

from rankloci.io import load_model
from rankloci.reporting import FORMATS, build_report, write_report
from rankloci.reporting.html import KATEX_VERSION, blocks_html, render_html, view_data
from rankloci.reporting.mathfmt import latex
from rankloci.tolerances import VIEW_ON_LOCUS_RTOL

pytest.importorskip("matplotlib")


@pytest.fixture(scope="module")
def planar3r():
    """A report on planar3r and its page (building it takes several seconds: slow tests)."""
    report = build_report(load_model("planar3r"), samples=2, exact=False)
    return report, render_html(report, timings=False)


def _data(page: str) -> dict:
    m = re.search(r'<script id="rankloci-data" type="application/json">(.*?)</script>', page,
                  re.S)
    assert m, "the page holds no view data"
    return json.loads(m[1])


def _tags(page: str) -> list:
    """(tag, attributes) of every element of ``page``, as the browser's parser sees them."""
    from html.parser import HTMLParser

    found = []

    class Tags(HTMLParser):
        def handle_starttag(self, tag, attrs):
            found.append((tag, dict(attrs)))

    Tags().feed(page)
    return found


def _fetches(page: str) -> list:
    """The elements of ``page`` that would load anything from outside it."""
    return [(tag, attrs) for tag, attrs in _tags(page)
            if tag in ("link", "iframe", "img", "object", "embed", "base")
            or any(k in ("src", "href", "data", "srcset", "action")
                   and not (v or "").startswith("#") for k, v in attrs.items())]


def test_the_check_for_fetches_sees_them():
    assert _fetches('<a href="#x">x</a><p>src=https://a</p><script>"<img src=x>"</script>') == []
    for markup in ('<script src="https://a/k.js"></script>', '<link rel="stylesheet" href="k">',
                   '<img src="data:,">', '<a href="https://a">a</a>', '<iframe></iframe>'):
        assert _fetches(markup), markup


def test_html_is_a_format():
    assert "html" in FORMATS


@pytest.mark.slow
def test_page_is_self_contained(planar3r):
    _, page = planar3r
    # nothing is fetched: no element refers to anything outside the page (links within it
    # only), no style sheet imports one
    tags = _tags(page)
    assert [t for t, _ in tags if t == "script"] and _fetches(page) == []
    assert any(t == "a" for t, _ in tags)          # the summary's links, to the page's headings
    assert not re.search(r"@import|url\(", page[page.index("<style>"):page.index("</style>")])
    # the math renderer is inside: KaTeX's own code, not a reference to it
    assert "katex.render(" in page and f'version:"{KATEX_VERSION}"' in page


@pytest.mark.slow
def test_page_holds_the_summary_and_every_components_equations(planar3r):
    report, page = planar3r
    assert "<table>" in page and ">no.</th>" in page      # the summary table
    for view in report.components:
        c = view.component
        # each component's subsection, with the anchor the summary links to ...
        anchor = f'id="rankloci-{report.name}-component-{view.index}"'
        assert anchor in page, anchor
        section = page[page.index(anchor):]
        section = section[:section.index("<h", 1)]
        # ... shows its equations: displayed (LaTeX that the page renders to MathML), in the
        # notation of J or written out, each one there in some form
        assert '<div class="math display">' in section, view.index
        for k, e in enumerate(c.equations):
            forms = [latex(e), html.escape(str(e))]
            if view.folded:
                forms.append(latex(view.folded[k]))
            assert any(html.escape(f) in section or f in section for f in forms), (view.index, e)


def test_math_and_text_are_escaped():
    from rankloci.reporting.blocks import Para, Table
    from rankloci.reporting.escape import literal

    page = blocks_html([Para("a <b> & " + literal("<script>alert(1)</script>") + " $x < 1$"),
                        Table(("h<",), (("$q_1 & 2$",),))])
    assert "<script>" not in page and "<b>" not in page
    assert '<span class="math">x &lt; 1</span>' in page
    assert "&lt;script&gt;" in page


@pytest.mark.slow
def test_view_data_put_each_sample_on_its_component(planar3r):
    report, page = planar3r
    data = _data(page)
    assert data == json.loads(json.dumps(view_data(report)))
    chain = data["chain"]
    assert chain["variables"] == [v.name for v in report.model.variables]
    assert chain["rtol"] == VIEW_ON_LOCUS_RTOL
    shown = {c["index"] for c in data["components"]}
    assert shown == {v.index for v in report.components if not v.special}
    for comp in data["components"]:
        q = np.array(comp["sample"])
        assert report.locus.contains(q), comp["index"]
        # the equations as the page evaluates them vanish there (scaled)
        for code, scale in zip(comp["equations"], comp["scales"]):
            value = eval(code, {"Math": _Math, "q": q})    # the code is checked plain arithmetic
            assert abs(value) / scale <= 1e-9
        # as many sliders as the component's dimension, the rest follow or are solved
        followers = set(comp["moving"]) | {v for v, _ in comp["solved"]}
        assert set(comp["sliders"]).isdisjoint(followers)
        assert len(comp["sliders"]) + len(followers) == len(chain["variables"])


@pytest.mark.slow
def test_view_data_carry_the_rows_that_augment_j():
    from rankloci.jacobians import task_matrix
    from rankloci.numeric.equations import NumericMatrix

    model = load_model("planar3r_orient")           # J is [vx; vy; grad(q1 + q2 + q3)]
    assert model.augment
    data = view_data(build_report(model, samples=2, exact=False))
    tm = task_matrix(model)
    nm = NumericMatrix(sp.Matrix(tm.matrix).subs(dict(tm.parameters)), tm.variables, tm.angles)
    rows = data["chain"]["augment"]
    assert len(rows) == len(model.augment) and data["chain"]["task"] == list(model.task)
    q = np.array(data["components"][0]["sample"]) + 0.3
    page_rows = [[eval(code, {"Math": _Math, "q": q}) for code in row] for row in rows]
    np.testing.assert_allclose(page_rows, nm(q)[len(model.task):], rtol=0, atol=1e-15)


class _Math:
    sin, cos, tan, sqrt, atan2, pow = np.sin, np.cos, np.tan, np.sqrt, np.arctan2, np.power
    PI = np.pi


@pytest.mark.slow
def test_a_matrix_model_gets_the_page_without_an_arm():
    from pathlib import Path

    path = Path(__file__).parents[2] / "examples" / "my_matrix.toml"
    report = build_report(load_model(str(path)), samples=2, exact=False)
    page = render_html(report, timings=False)
    assert view_data(report) == {}
    assert '<script id="rankloci-data"' not in page and "<canvas" not in page
    assert 'class="math display"' in page and "katex.render(" in page


HOSTILE = ("Arm <script>alert(1)</script> <img src=https://example.com/x.png> "
           "$\\input{/etc/passwd}$ `tick` & </p>")


@pytest.mark.slow
def test_model_text_is_text_in_the_page():
    from rankloci.io.toml_model import parse_model

    text = (f'name = "hostile"\nvariables = ["x", "y"]\n'
            f'matrix = [["cos(x)", "y"], ["sin(x)", "1"]]\n'
            f"title = {json.dumps(HOSTILE)}\nsource = {json.dumps(HOSTILE)}\n")
    report = build_report(parse_model(text), samples=2, exact=False, model_notes=HOSTILE)
    page = render_html(report, timings=False)
    body = page[page.index("<body>"):]
    assert body.count("<script>") == 2           # KaTeX and the call that renders the math
    assert _fetches(page) == [] and "example.com/x.png" in page
    escaped = html.escape(HOSTILE)
    assert page.count(escaped) >= 2               # the title and the source, as text
    # the model's dollars are not math: no span holds the model's LaTeX
    assert '<span class="math">\\input' not in page


def test_code_for_the_page_is_only_arithmetic_in_the_joints():
    from rankloci.loci import Component
    from rankloci.reporting.html import _component_code

    q1, q2, evil = sp.symbols("q1 q2 alert")
    ok = Component(equations=(sp.sin(q1) + sp.Rational(1, 2) * sp.cos(q2),), free=(q2,))
    solved, eqs = _component_code(ok, [q1, q2], {}, [0.0, 0.0])
    assert eqs == ["Math.sin(q[0]) + 0.5*Math.cos(q[1])"] and solved == []
    # a name that is neither a joint nor a parameter with a value: no code, the view leaves
    # the component out
    bad = Component(equations=(sp.sin(q1) + evil,), free=(q2,))
    assert _component_code(bad, [q1, q2], {}, [0.0, 0.0]) is None


@pytest.mark.slow
def test_write_report_writes_one_html_file(planar3r, tmp_path):
    report, _ = planar3r
    paths = write_report(report, tmp_path, formats=("html",), timings=False)
    pages = [p for p in paths if p.suffix == ".html"]
    assert [p.name for p in pages] == ["planar3r.html"]
    assert not [p for p in paths if p.suffix in (".md", ".tex", ".pdf")]
    assert pages[0].read_text(encoding="utf-8") == render_html(report, timings=False)


@pytest.mark.slow
def test_cli_writes_the_page(tmp_path, capsys):
    from rankloci.cli import main

    out = tmp_path / "out"
    assert main(["report", "planar2r", "-o", str(out), "--format", "html", "--quiet"]) == 0
    printed = capsys.readouterr().out.split()
    assert printed == [str(out / "planar2r.html")]
    page = (out / "planar2r.html").read_text(encoding="utf-8")
    assert page.startswith("<!DOCTYPE html>") and page.rstrip().endswith("</html>")
    assert not (out / "planar2r.md").exists()


def test_cli_rejects_an_unknown_format_before_writing(tmp_path, capsys):
    from rankloci.cli import main

    out = tmp_path / "out"
    assert main(["report", "planar2r", "-o", str(out), "--format", "html,htm"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "html" in err[0] and "htm'" in err[0]
    assert not out.exists()
