"""`rankloci report`: the files it writes, their content, LaTeX and PDF, determinism, errors.

Reports are built once per model (module fixtures) for the small models planar2r, planar3r
and puma560 with 3 cross-check samples and seed 3.
"""

from __future__ import annotations

import re
import shutil
import subprocess

import pytest
import sympy as sp

import report_helpers as RH
from rankloci.cli import main
from rankloci.reporting.figures import DPI, HEATMAP_SIZE, PATH_SIZE

SEED = 3
SAMPLES = 3
MODELS = ("planar2r", "planar3r", "puma560")


def _flat(text: str) -> str:
    """LaTeX without line breaks, alignment marks, indentation and spaces."""
    return re.sub(r"\s+|&|\\\\|\\quad", "", text)


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    """Model name -> directory with its report (md, tex and, when LaTeX is there, pdf)."""
    import contextlib
    import io

    dirs = {}
    for name in MODELS:
        d = tmp_path_factory.mktemp("reports") / name
        err = io.StringIO()
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err):
            code = main(["report", name, "-o", str(d), "--samples", str(SAMPLES),
                         "--seed", str(SEED), "--quiet"])
        assert code == 0, err.getvalue()
        dirs[name] = d
    return dirs


@pytest.fixture(scope="module")
def loci():
    """Model name -> the locus the report is built from (same method, seed and frame)."""
    import numpy as np

    from rankloci.io import load_model
    from rankloci.jacobians import task_matrix
    from rankloci.methods import compute_locus

    out = {}
    for name in MODELS:
        tm = task_matrix(load_model(name), frame="auto")
        method = "determinant" if tm.shape[0] == tm.shape[1] else "svm"
        out[name] = compute_locus(tm, method, rng=np.random.default_rng(SEED))
    return out


# --- the Markdown -------------------------------------------------------------------------------

@pytest.mark.parametrize("name", MODELS)
def test_every_component_appears_in_the_markdown(written, loci, name):
    md = (written[name] / f"{name}.md").read_text(encoding="utf-8")
    assert loci[name].components, f"{name}: expected a non-empty locus"
    for i, comp in enumerate(loci[name].components, start=1):
        assert f"### Component {i}" in md, f"{name}: component {i} has no section"
        plain = ",  ".join(f"{sp.sstr(e)} = 0" for e in comp.equations)
        assert md.splitlines().count(plain) == 1, f"{name}: component {i}: plain equations " \
            f"{plain!r} missing or repeated"
        section = md.split(f"### Component {i}\n", 1)[1].split("\n#", 1)[0]
        assert section.count("$$") == 2, f"{name}: component {i}: not one display"


@pytest.mark.parametrize("name", MODELS)
def test_markdown_math_is_dollar_delimited_and_balanced(written, name):
    md = (written[name] / f"{name}.md").read_text(encoding="utf-8")
    prose = re.sub(r"```.*?```", "", md, flags=re.S)
    assert prose.count("$$") % 2 == 0
    inline = re.sub(r"\$\$.*?\$\$", "", prose, flags=re.S)
    assert inline.count("$") % 2 == 0, f"{name}: unbalanced inline $"
    assert "\\(" not in inline and "\\[" not in inline, "use $...$, not \\( \\) or \\[ \\]"
    for fig in re.findall(r"!\[[^\]]*\]\(([^)]+)\)", md):
        assert "/" not in fig and (written[name] / fig).is_file(), f"figure link {fig}"


def test_markdown_sections(written):
    md = (written["puma560"] / "puma560.md").read_text(encoding="utf-8")
    for heading in ("The model", "Denavit-Hartenberg table", "The symbolic Jacobian",
                    "The singularity locus", "Singularity maps", "Branch tree",
                    "Numeric cross-check", "Method comparison", "Timings"):
        assert heading in md, heading
    assert "Corke" in md, "the source citation"
    assert "wrist singularity: axes 4 and 6 are collinear" in md.lower()
    assert f"--seed {SEED}" in md and "Result: PASS" in md
    assert "determinant method is the only one" in md


def test_method_comparison_of_a_redundant_arm(written):
    md = (written["planar3r"] / "planar3r.md").read_text(encoding="utf-8")
    section = md.split("Method comparison", 1)[1]
    assert "| svm |" in section and "| subdeterminant |" in section
    assert "same components" in section or "describe the same set" in section


def test_no_absolute_paths_or_dates_in_the_text(written, tmp_path_factory):
    for name, d in written.items():
        for suffix in (".md", ".tex"):
            text = (d / f"{name}{suffix}").read_text(encoding="utf-8")
            assert str(d) not in text and "/tmp" not in text
            assert not re.search(r"\b20\d\d-\d\d-\d\d\b", text), f"{name}{suffix} has a date"


# --- figures ------------------------------------------------------------------------------------

def test_figures_are_non_blank_pngs_of_the_expected_size(written):
    heat = (round(HEATMAP_SIZE[0] * DPI), round(HEATMAP_SIZE[1] * DPI))
    path = (round(PATH_SIZE[0] * DPI), round(PATH_SIZE[1] * DPI))
    for name, d in written.items():
        sigma = sorted(d.glob(f"{name}-sigma-*.png"))
        assert sigma, f"{name}: no heat map"
        for f in sigma:
            assert RH.png_size(f) == heat, f
            assert RH.grey_std(f) > RH.BLANK_STD, f"{f} is blank"
        man = d / f"{name}-manipulability.png"
        assert RH.png_size(man) == path
        assert RH.grey_std(man) > RH.BLANK_STD
        tree = d / f"{name}-tree.png"
        w, h = RH.png_size(tree)
        assert w > 100 and h > 50
        assert RH.grey_std(tree) > RH.BLANK_STD


def test_puma_heat_maps_cover_every_component(written):
    md = (written["puma560"] / "puma560.md").read_text(encoding="utf-8")
    shown = set()
    for caption in re.findall(r"where components? ([\d, and]+?) meets? the slice", md):
        shown |= {int(x) for x in re.findall(r"\d+", caption)}
    assert shown >= {1, 2, 3}


# --- LaTeX and PDF ------------------------------------------------------------------------------

def test_tex_uses_amsmath_and_relative_figures(written):
    tex = (written["puma560"] / "puma560.tex").read_text(encoding="utf-8")
    assert "\\usepackage{amsmath,amssymb}" in tex and "\\documentclass" in tex
    assert "breqn" not in tex
    for fig in re.findall(r"\\includegraphics\[[^\]]*\]\{([^}]+)\}", tex):
        assert "/" not in fig and (written["puma560"] / fig).is_file()


@pytest.mark.parametrize("name", MODELS)
def test_tex_compiles_without_overfull_lines(written, name, tmp_path):
    if RH.LATEXMK is None:
        pytest.skip("latexmk is not installed (Debian: latexmk, texlive-latex-extra)")
    work = tmp_path / name
    shutil.copytree(written[name], work)
    code, log = RH.latexmk(work, name)
    assert code == 0, log[-2000:]
    overfull = [float(x) for x in re.findall(r"Overfull \\hbox \(([\d.]+)pt too wide\)", log)]
    assert not [x for x in overfull if x > 1.0], f"{name}: overfull boxes {overfull}"
    assert "LaTeX Error" not in log and "Undefined control sequence" not in log


def test_pdf_written_and_its_first_page_is_not_blank(written, tmp_path):
    pdf = written["puma560"] / "puma560.pdf"
    if RH.LATEXMK is None and shutil.which("pdflatex") is None:
        assert not pdf.exists()
        pytest.skip("neither latexmk nor pdflatex is installed: no PDF to render")
    assert pdf.read_bytes().startswith(b"%PDF")
    if RH.PDFTOPPM is None:
        pytest.skip("pdftoppm is not installed (Debian: poppler-utils)")
    subprocess.run([RH.PDFTOPPM, "-png", "-r", "50", "-f", "1", "-l", "1", str(pdf),
                    str(tmp_path / "page")], check=True, timeout=120)
    page = next(tmp_path.glob("page*.png"))
    w, h = RH.png_size(page)
    assert w > 300 and h > 400
    assert RH.grey_std(page) > RH.BLANK_STD, "page 1 of the PDF is blank"


def test_pdf_is_reproducible(written, tmp_path, capsys):
    if RH.LATEXMK is None:
        pytest.skip("latexmk is not installed")
    out = tmp_path / "again"
    code, _, err = run(capsys, "report", "planar2r", "-o", str(out), "--samples", str(SAMPLES),
                       "--seed", str(SEED), "--quiet", "--format", "pdf", "--no-timings")
    assert code == 0, err
    first = (out / "planar2r.pdf").read_bytes()
    code, _, err = run(capsys, "report", "planar2r", "-o", str(out), "--samples", str(SAMPLES),
                       "--seed", str(SEED), "--quiet", "--format", "pdf", "--no-timings")
    assert (out / "planar2r.pdf").read_bytes() == first


# --- options, determinism, errors ---------------------------------------------------------------

def test_fragment_has_no_preamble(tmp_path, capsys):
    code, out, err = run(capsys, "report", "planar2r", "-o", str(tmp_path), "--format", "tex",
                         "--fragment", "--samples", "2", "--quiet")
    assert code == 0, err
    tex = (tmp_path / "planar2r.tex").read_text(encoding="utf-8")
    assert "\\documentclass" not in tex and "\\begin{document}" not in tex
    assert "\\usepackage" not in tex.replace("% Needs \\usepackage", "")
    assert tex.lstrip().startswith("%") and "\\section{" in tex
    assert not (tmp_path / "planar2r.md").exists() and not (tmp_path / "planar2r.pdf").exists()
    assert str(tmp_path / "planar2r.tex") in out


def test_fragment_compiles_inside_a_paper(tmp_path, capsys):
    if RH.LATEXMK is None:
        pytest.skip("latexmk is not installed")
    code, _, err = run(capsys, "report", "planar2r", "-o", str(tmp_path / "planar2r"),
                       "--format", "tex", "--fragment", "--samples", "2", "--quiet")
    assert code == 0, err
    (tmp_path / "paper.tex").write_text(
        "\\documentclass{article}\n\\usepackage{amsmath,amssymb,graphicx,booktabs}\n"
        "\\graphicspath{{planar2r/}}\n\\begin{document}\n\\appendix\n"
        "\\input{planar2r/planar2r.tex}\n\\end{document}\n", encoding="utf-8")
    code, log = RH.latexmk(tmp_path, "paper")
    assert code == 0, log[-2000:]


def test_same_seed_gives_byte_identical_markdown(tmp_path, capsys):
    texts = []
    for k in range(2):
        d = tmp_path / f"run{k}"
        code, _, err = run(capsys, "report", "planar3r", "-o", str(d), "--format", "md",
                           "--samples", "2", "--seed", "11", "--no-timings", "--quiet")
        assert code == 0, err
        texts.append((d / "planar3r.md").read_bytes())
        texts.append(b"".join(p.read_bytes() for p in sorted(d.glob("*.png"))))
    assert texts[0] == texts[2], "the Markdown differs between two runs with the same seed"
    assert texts[1] == texts[3], "the figures differ between two runs with the same seed"
    assert b"Timings" not in texts[0]


def test_timings_are_fenced(written):
    md = (written["planar2r"] / "planar2r.md").read_text(encoding="utf-8")
    start = md.index("<!-- timings:")
    end = md.index("<!-- end of timings -->")
    assert start < end and "| total |" in md[start:end]
    assert "| total |" not in md[:start] + md[end:]


@pytest.mark.parametrize("argv, what", [
    (["report", "no_such_model"], "no built-in model"),
    (["report", "planar2r", "--format", "md,docx"], "--format"),
    (["report", "planar2r", "--samples", "0"], "--samples"),
    (["report", "planar2r", "--timeout", "-1"], "--timeout"),
    (["report", "planar2r", "--bogus"], "unrecognized"),
])
def test_bad_input_exits_2_with_one_line_and_writes_nothing(tmp_path, capsys, argv, what):
    out = tmp_path / "out"
    code, stdout, err = run(capsys, *argv, "-o", str(out), "--quiet")
    assert code == 2
    assert err.count("\n") == 1 and err.startswith("rankloci: error:") and what in err, err
    assert stdout == ""
    assert not out.exists() and list(tmp_path.iterdir()) == []


def test_bad_model_file_exits_2(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text('name = "bad"\n[[joint]]\nkind = "revolute"\na = "pi//2"\n', encoding="utf-8")
    code, stdout, err = run(capsys, "report", str(bad), "-o", str(tmp_path / "out"), "--quiet")
    assert code == 2 and err.count("\n") == 1 and "bad.toml" in err
    assert not (tmp_path / "out").exists()


def test_output_that_is_a_file_is_refused(tmp_path, capsys):
    f = tmp_path / "file"
    f.write_text("x", encoding="utf-8")
    code, _, err = run(capsys, "report", "planar2r", "-o", str(f), "--quiet")
    assert code == 2 and "not a directory" in err
    assert f.read_text(encoding="utf-8") == "x"


def test_all_writes_one_directory_per_builtin_model(tmp_path, capsys, monkeypatch):
    import rankloci.io

    monkeypatch.setattr(rankloci.io, "builtin_models", lambda: ["planar2r", "planar3r_orient"])
    code, out, err = run(capsys, "report", "all", "-o", str(tmp_path), "--format", "md",
                         "--samples", "2", "--quiet")
    assert code == 0, err
    for name in ("planar2r", "planar3r_orient"):
        assert (tmp_path / name / f"{name}.md").is_file()
        assert str(tmp_path / name / f"{name}.md") in out


def test_missing_latex_skips_the_pdf_and_says_so(tmp_path, capsys, monkeypatch):
    real = shutil.which
    monkeypatch.setattr(shutil, "which",
                        lambda cmd, *a, **k: None if cmd in ("latexmk", "pdflatex") else real(cmd))
    code, out, err = run(capsys, "report", "planar2r", "-o", str(tmp_path), "--samples", "2",
                         "--quiet")
    assert code == 0
    assert "PDF skipped" in err
    assert (tmp_path / "planar2r.md").is_file() and (tmp_path / "planar2r.tex").is_file()
    assert not (tmp_path / "planar2r.pdf").exists()


def test_timestamp_only_when_asked(tmp_path, capsys):
    code, _, err = run(capsys, "report", "planar2r", "-o", str(tmp_path), "--format", "md",
                       "--samples", "2", "--timestamp", "--quiet")
    assert code == 0, err
    md = (tmp_path / "planar2r.md").read_text(encoding="utf-8")
    assert re.search(r"Written 20\d\d-\d\d-\d\dT\d\d:\d\d:\d\d", md)
