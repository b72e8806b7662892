"""The report's standard sentences say only what holds for the model at hand, in good English."""

from __future__ import annotations

import dataclasses
import re

import networkx as nx
import pytest

from rankloci.io import load_model
from rankloci.loci import Outcome
from rankloci.reporting import build_report
from rankloci.reporting.tree_summary import tree_summary
from rankloci.reporting.markdown import render_markdown

SEED = 2


@pytest.fixture(scope="module")
def reports():
    """Model name -> Markdown of its report, for two small models."""
    return {name: render_markdown(build_report(load_model(name), seed=SEED, samples=2,
                                               exact=False))
            for name in ("planar2r", "planar3r_orient")}


def _section(md: str, heading: str) -> str:
    start = md.index(heading)
    end = md.find("\n#", start + len(heading))
    return md[start:end if end > 0 else None]


def test_unit_links_are_claimed_only_for_a_model_with_unit_links(reports):
    from rankloci.reporting.content import _units_sentence

    assert "(unit links)" in _section(reports["planar2r"], "### Parameters")
    for name in ("puma560", "ssrms", "mobile10"):
        model = load_model(name)
        assert any(float(v) != 1.0 for v in model.parameters.values())
        assert "unit" not in _units_sentence(model), name


def test_rows_of_an_augmented_planar_task_are_named_as_they_are(reports):
    section = _section(reports["planar3r_orient"], "### Task, frame and constraint rows")
    assert "`vx`, `vy` are the x and y components of the linear velocity" in section
    for row in ("vz", "wx", "wy", "wz"):
        assert f"`{row}`" not in section, row
    assert "Constraint row `orientation`" in section


@pytest.mark.parametrize("name", ["planar2r", "planar3r_orient"])
def test_no_plural_placeholders(reports, name):
    md = reports[name]
    notes = md.find("### Notes of the analysis")   # notes of the locus methods, quoted as given
    text = md if notes < 0 else md[:notes] + md[md.find("\n#", notes + 5):]
    assert not re.search(r"\w\((s|es)\)", text), re.search(r".{40}\w\((s|es)\).{10}", text)
    assert not re.search(r"\b1 (components|nodes|findings|more branches)\b", text)


def test_tree_summary_counts_one_branch_and_one_leaf_in_the_singular():
    tree = nx.DiGraph()
    tree.add_node(0, condition="(all configurations)", outcome=Outcome.REFINED)
    tree.add_node(1, condition="f1", outcome=Outcome.ALL_MINORS_VANISH)
    tree.add_node(2, condition="f2", outcome=Outcome.REFINED)
    tree.add_node(3, condition="f3", outcome=Outcome.REFINED)
    tree.add_node(4, condition="f4", outcome=Outcome.ALL_MINORS_VANISH)
    tree.add_node(5, condition="f5", outcome=Outcome.EMPTY)
    tree.add_edges_from([(0, 1), (0, 2), (2, 3), (3, 4), (0, 5)])
    labels = [d["label"] for _, d in tree_summary(tree, max_nodes=5).graph.nodes(data=True)
              if d["role"] == "summary"]
    heads = sorted(label.splitlines()[0] for label in labels)
    assert heads == ["1 more branch", "2 more branches, 1 component leaf"]


def test_fsp_finding_is_explained(reports):
    report = build_report(load_model("planar2r"), seed=SEED, samples=2, exact=False)
    finding = "component 1: SVD rank deficient (ratio 1.0e-16) but FSP finds no dependent row"
    check = dataclasses.replace(report.check, findings=(finding,))
    md = render_markdown(dataclasses.replace(report, check=check))
    # the finding is told in the appendix's second opinions, and named on the first page
    section = _section(md, "Second opinions")
    assert "1 finding where the FSP reducer" in section
    assert "Full Space Parameterization" in section and "it is not an error" in section
    assert "1 finding" not in _section(md, "Numeric cross-check")
    front = md[:md.index("## 1.")]
    assert "**Caveats.**" in front and "the FSP reducer or the largest maximal minor" in front


def test_model_notes_state_the_model_not_how_the_file_was_written():
    import tomllib

    from rankloci.io import models_dir

    for path in sorted(models_dir().glob("*.toml")):
        notes = tomllib.loads(path.read_text()).get("notes", "")
        for phrase in ("while writing", "could not be", "CHOICE", "project seeds",
                       "should be re-checked"):
            assert phrase not in notes, (path.name, phrase)


def test_timings_come_before_the_tree():
    from rankloci.io import load_model
    from rankloci.reporting import build_report
    from rankloci.reporting.markdown import render_markdown

    md = render_markdown(build_report(load_model("planar2r"), samples=2, exact=False,
                                      clock=iter(range(10**6)).__next__))
    titles = [h.lstrip("# ") for h in md.splitlines() if h.startswith("#")]
    timings = next(i for i, t in enumerate(titles) if t.endswith("Timings"))
    assert titles[-1] != titles[timings]
    assert any(t.endswith("Branch tree") for t in titles[timings + 1:]), titles
