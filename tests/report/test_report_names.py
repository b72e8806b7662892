"""Reports on models with hostile names and texts: files stay in their folder, only a report's
own files are replaced or removed, and what goes into LaTeX and Markdown is escaped.

The model name of a URDF file is its file stem, which may be anything a file system allows
(``*``, ``..``, ``my robot$%\\x``); titles, sources and joint names are free text.
"""

from __future__ import annotations

import dataclasses
import re

import pytest

import report_helpers as RH
from rankloci.cli import main
from rankloci.io import load_model
from rankloci.io.toml_model import parse_model
from rankloci.reporting import build_report, file_stem, write_report
from rankloci.reporting.escape import literal, rich_md, rich_tex
from rankloci.reporting.latex import render_latex
from rankloci.reporting.markdown import render_markdown

SEED = 4

#: A planar two-link arm as URDF: two revolute joints about z, links of 1 m.
URDF_2R = """<robot name="{robot}">
  <link name="base"/><link name="l1"/><link name="l2"/><link name="tool"/>
  <joint name="{joint}" type="revolute"><parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0"/><axis xyz="0 0 1"/><limit lower="-3" upper="3"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
    <origin xyz="1 0 0"/><axis xyz="0 0 1"/><limit lower="-3" upper="3"/></joint>
  <joint name="flange" type="fixed"><parent link="l2"/><child link="tool"/>
    <origin xyz="1 0 0"/></joint>
</robot>
"""


def _urdf(path, robot="arm", joint="j1"):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(URDF_2R.format(robot=robot, joint=joint), encoding="utf-8")
    return path


def _report(capsys, *argv):
    code = main(["report", *argv, "--samples", "2", "--seed", str(SEED), "--quiet"])
    out, err = capsys.readouterr()
    assert code == 0, err
    return out


def _tree(root):
    """Every file under ``root`` with its bytes, by path relative to ``root``."""
    return {p.relative_to(root).as_posix(): p.read_bytes()
            for p in sorted(root.rglob("*")) if p.is_file()}


# --- file names ---------------------------------------------------------------------------------

@pytest.mark.parametrize("name, stem", [
    ("puma560", "puma560"), ("ssrms_lock3", "ssrms_lock3"), ("lock-q3", "lock-q3"),
    ("*", "model"), ("..", "model"), (".", "model"), ("", "model"),
    ("my robot$%\\x", "my_robot_x"), ("-rf", "rf"), ("a/../../b", "a_b"),
    ("r\u00f6bot", "r_bot"), ("x" * 200, "x" * 64),
])
def test_file_stem_is_a_plain_file_name(name, stem):
    assert file_stem(name) == stem
    assert re.fullmatch(r"[A-Za-z0-9][A-Za-z0-9_-]{0,63}", file_stem(name))


def test_a_glob_in_the_model_name_leaves_another_report_in_the_folder_alone(tmp_path, capsys,
                                                                           monkeypatch):
    """``rankloci report 'g/*.urdf' -o shared`` beside planar2r's report deletes none of it."""
    monkeypatch.chdir(tmp_path)
    _report(capsys, "planar2r", "-o", "shared", "--format", "md")
    before = _tree(tmp_path / "shared")
    assert any(n.startswith("planar2r-sigma-") for n in before)
    _urdf(tmp_path / "g" / "*.urdf")
    out = _report(capsys, "g/*.urdf", "-o", "shared", "--format", "md")
    after = _tree(tmp_path / "shared")
    assert {n: b for n, b in after.items() if n in before} == before, "planar2r's files changed"
    new = set(after) - set(before)
    assert new and all(n.startswith("model") for n in new), new
    assert out.strip() == "shared/model.md"


def test_rewriting_removes_only_figures_of_the_same_stem(tmp_path):
    """Stale figures are those whose whole name is one a report on this stem writes."""
    report = build_report(load_model("planar2r"), seed=SEED, samples=2, exact=False)
    mine = ["planar2r-sigma-9.png", "planar2r-augmented.png"]
    others = ["planar2r-sigma-x.png", "planar2r-sigma-1-old.png", "planar2r-notes.png",
              "planar2rb-tree.png", "xplanar2r-tree.png", "planar2r-tree.png.bak",
              "planar2r.txt", "notes.png"]
    for n in mine + others:
        (tmp_path / n).write_bytes(b"old")
    write_report(report, tmp_path, formats=("md",))
    assert not any((tmp_path / n).exists() for n in mine)
    assert all((tmp_path / n).read_bytes() == b"old" for n in others)
    assert (tmp_path / "planar2r-tree.png").read_bytes() != b"old"


def test_a_model_named_dot_dot_writes_into_its_own_folder(tmp_path, capsys, monkeypatch):
    """A URDF named ``...urdf`` has the model name ``..``; its report is not written into
    the parent of the reports folder."""
    (tmp_path / "work").mkdir()
    monkeypatch.chdir(tmp_path / "work")
    _urdf(tmp_path / "work" / "...urdf")
    out = _report(capsys, "...urdf", "--format", "md")
    assert out.strip() == "reports/model/model.md"
    assert sorted(_tree(tmp_path)) == sorted(
        ["work/...urdf"] + [f"work/reports/model/{n}"
                            for n in _tree(tmp_path / "work" / "reports" / "model")])
    assert all(n.startswith("model") for n in _tree(tmp_path / "work" / "reports" / "model"))


def test_write_report_refuses_a_file_name_that_leaves_the_folder(tmp_path):
    report = build_report(load_model("planar2r"), seed=SEED, samples=2, exact=False)
    fig = dataclasses.replace(report.figures[0], name="../escaped.png")
    bad = dataclasses.replace(report, figures=(fig,) + report.figures[1:])
    with pytest.raises(ValueError, match="escaped.png"):
        write_report(bad, tmp_path / "out", formats=("md",))
    assert list(tmp_path.iterdir()) == []


def test_special_characters_in_the_file_name_give_plain_file_names_and_latex(tmp_path, capsys,
                                                                            monkeypatch):
    r"""``my robot$%\x.urdf``: file names from the sanitised stem; the LaTeX compiles."""
    monkeypatch.chdir(tmp_path)
    _urdf(tmp_path / "my robot$%\\x.urdf")
    formats = "md,tex,pdf" if RH.LATEXMK else "md,tex"
    _report(capsys, "my robot$%\\x.urdf", "-o", "out", "--format", formats)
    names = sorted(_tree(tmp_path / "out"))
    assert "my_robot_x.md" in names and "my_robot_x.tex" in names
    assert all(re.fullmatch(r"my_robot_x(-[a-z0-9-]+)?\.(md|tex|pdf|png)", n) for n in names), names
    tex = (tmp_path / "out" / "my_robot_x.tex").read_text(encoding="utf-8")
    graphics = re.findall(r"\\includegraphics\[[^]]*\]\{([^}]*)\}", tex)
    assert graphics and all(re.fullmatch(r"my_robot_x-[a-z0-9-]+\.png", g) for g in graphics)
    labels = re.findall(r"\\label\{([^}]*)\}", tex)
    assert labels and all(re.fullmatch(r"rankloci:my_robot_x(:[A-Za-z0-9_-]+)*", x)
                          for x in labels), labels
    if RH.LATEXMK:
        assert "my_robot_x.pdf" in names


# --- text from the model file -------------------------------------------------------------------

HOSTILE_TITLE = ("Arm ![pwned](https://example.com/x.png) [link](https://example.com) "
                 "$\\input{/etc/passwd}$ `tick` 50% #1 <b>bold</b> a_b *c*\n\n# not a heading")
HOSTILE_SOURCE = "Paper | with ![img](y.png) and $x$ \\def\\a{b} ~ ^"

MATRIX_MODEL = """name = "hostile"
variables = ["x", "y"]
matrix = [["cos(x)", "y"], ["sin(x)", "1"]]
title = {title}
source = {source}
notes = {notes}
"""


@pytest.fixture(scope="module")
def hostile_report():
    import json

    text = MATRIX_MODEL.format(title=json.dumps(HOSTILE_TITLE), source=json.dumps(HOSTILE_SOURCE),
                               notes=json.dumps("see ![n](n.png)"))
    return build_report(parse_model(text), seed=SEED, samples=2, exact=False,
                        model_notes="see ![n](n.png) $y$")


def test_markdown_images_and_links_in_model_text_are_escaped(hostile_report):
    """Brackets and dollars of model text become character references (``\\[`` and ``\\(``
    start math in some renderers); the other specials are backslash-escaped."""
    md = render_markdown(hostile_report)
    assert "&#93;(https://example.com" in md  # the text is kept ...
    # ... but the only images are the report's own figures, and the only links go to them or
    # to the report's own headings
    figures = [f.name for f in hostile_report.figures]
    assert re.findall(r"!\[[^\]]*\]\(([^)]*)\)", md) == figures
    for target in re.findall(r"(?<!!)\[[^\]]*\]\(([^)]*)\)", md):
        assert target in figures or re.fullmatch(r"#[a-z0-9-]+", target), target
    title = md.splitlines()[0]
    assert title.startswith("# Singularity report: Arm !&#91;pwned&#93;(https://example.com/x.png)")
    assert "&#36;\\\\input{/etc/passwd}&#36;" in title and "\\`tick\\`" in title
    assert "\\<b\\>" in title and "a\\_b \\*c\\*" in title and "\\# not a heading" in title
    source = next(line for line in md.splitlines() if line.startswith("**Source.**"))
    assert "Paper \\| with !&#91;img&#93;(y.png) and &#36;x&#36;" in source
    notes = next(line for line in md.splitlines() if line.startswith("**Notes.**"))
    assert notes == "**Notes.** see !&#91;n&#93;(n.png) &#36;y&#36;"


def test_model_text_is_escaped_in_latex(hostile_report, tmp_path):
    tex = render_latex(hostile_report)
    assert "\\input{/etc/passwd}" not in tex
    assert "\\$\\textbackslash{}input\\{/etc/passwd\\}\\$" in tex
    assert "\\def\\a" not in tex and "50\\% \\#1" in tex
    if RH.LATEXMK:  # ReportError if LaTeX fails on it
        paths = write_report(hostile_report, tmp_path, formats=("tex", "pdf"),
                             latex=("latexmk", RH.LATEXMK))
        assert tmp_path / "hostile.pdf" in paths


def test_urdf_joint_names_are_escaped(tmp_path):
    from rankloci.io.urdf import read_urdf

    path = _urdf(tmp_path / "arm.urdf", robot="a $x$ ![r](r.png)", joint="j`1|$y$")
    report = build_report(read_urdf(path), seed=SEED, samples=2, exact=False)
    md = render_markdown(report)
    row = next(line for line in md.splitlines() if line.startswith("| 1 |"))
    assert "j\\`1\\|&#36;y&#36;" in row and row.count(" | ") == 6
    assert md.splitlines()[0] == "# Singularity report: a &#36;x&#36; !&#91;r&#93;(r.png) (`arm`)"
    assert "\\texttt{j`1\\textbar{}\\$y\\$}" in render_latex(report)


def test_literal_text_is_one_line_without_control_characters():
    marked = literal("a\nb\x00c\x0e\x0fd\t e")
    assert rich_md(marked) == "a b c d e" and rich_tex(marked) == "a b c d e"
    assert rich_md("x " + literal("q_1", code=True) + " $x_1$") == "x `q_1` $x_1$"
    assert rich_tex(literal("$") + "$x$" + literal("$")) == "\\$$x$\\$"
