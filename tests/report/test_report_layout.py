"""Layout of the written reports: figures stay in their sections, the branch tree page is
legible, commands copied from the PDF work, the appendix holds J, the tree and the timings.

Two small reports are built with their PDF (puma560 and planar3r_orient, seed 3, 2 samples);
the PDF checks need latexmk and poppler (pdftotext, pdfimages, pdftoppm).  The committed
reports in reports/ are checked for the same properties where they are cheap to check.
"""

from __future__ import annotations

import contextlib
import io
import re
import shutil
import subprocess
from pathlib import Path

import pytest

import report_helpers as RH
from rankloci.cli import main

SEED = 3
REPORTS = Path(__file__).resolve().parents[2] / "reports"
PDF_TOOLS = all(shutil.which(t) for t in ("latexmk", "pdftotext", "pdfimages", "pdftoppm"))
needs_pdf = pytest.mark.skipif(not PDF_TOOLS, reason="latexmk or poppler is not installed")

#: Smallest legible text in a PDF, in points (a footnote is 8 pt; 6 pt still reads on paper).
LEGIBLE_PT = 6.0


def _report(directory: Path, model: str, *extra) -> Path:
    err = io.StringIO()
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err):
        code = main(["report", model, "-o", str(directory), "--samples", "2", "--seed",
                     str(SEED), "--quiet", *extra])
    assert code == 0, err.getvalue()
    return directory


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """Model name -> directory with its report (md, tex, pdf when LaTeX is there)."""
    root = tmp_path_factory.mktemp("layout")
    return {m: _report(root / m, m) for m in ("puma560", "planar3r_orient")}


def _pdf_text(pdf: Path) -> list[str]:
    """The text of each page of ``pdf``."""
    text = subprocess.run(["pdftotext", "-layout", str(pdf), "-"], capture_output=True,
                          check=True, text=True).stdout
    return text.split("\f")


def _tex_sequence(tex: str) -> list[tuple[str, str]]:
    """(kind, text) of the section headings and figures of the LaTeX source, in order.

    Figures float within their section (placeins): subsection headings are not barriers.
    """
    out = []
    for m in re.finditer(r"\\section\{([^}]*)\}|\\begin\{figure\}", tex):
        out.append(("heading", m.group(1)) if m.group(1) is not None else ("figure", ""))
    return out


def test_every_figure_floats_within_its_section(built):
    tex = (built["puma560"] / "puma560.tex").read_text()
    figures = re.findall(r"\\begin\{figure\}(\[[^\]]*\])?", tex)
    assert figures and all(f in ("[htbp]", "[p]") for f in figures), figures
    assert "\\usepackage[section]{placeins}" in tex


@needs_pdf
@pytest.mark.parametrize("model", ["puma560", "planar3r_orient"])
def test_each_figure_appears_in_its_own_section(built, model):
    """In the PDF, figure k comes after the heading that precedes it in the source and before
    the next heading: no figure floats into another section or past the last one."""
    tex = (built[model] / f"{model}.tex").read_text()
    text = "\n".join(_pdf_text(built[model] / f"{model}.pdf"))
    flat = re.sub(r"\s+", " ", text)
    seq = _tex_sequence(tex)
    # walking the source in order, each heading and each figure caption must be found after
    # the one before: a figure that floated past the next heading breaks the chain there
    pos, k, previous = 0, 0, None
    for kind, title in seq:
        if kind == "heading":
            plain = re.sub(r"\\[a-z]+\{|[{}$\\]", "", title).strip()
            at = flat.find(plain, pos)
            assert at >= 0, f"heading {plain!r} is not after the figure or heading before it"
            pos, previous = at, plain
        else:
            k += 1
            at = flat.find(f"Figure {k}:", pos)
            assert at >= 0, f"Figure {k} is not after the heading {previous!r}"
            pos = at
    assert k == len(re.findall(r"\\begin\{figure\}", tex))


@needs_pdf
def test_no_figure_between_the_last_section_and_the_appendix(built):
    pages = _pdf_text(built["puma560"] / "puma560.pdf")
    flat = re.sub(r"\s+", " ", "\n".join(pages))
    start = flat.index("Reproducing this report")
    end = flat.index("The symbolic Jacobian", start)
    assert not re.search(r"Figure \d+:", flat[start:end])
    # J, the tree and the timings are in the appendix, after the last numbered section
    for title in ("Branch tree", "Timings"):
        assert flat.find(title, end) > end, title


@needs_pdf
def test_reproduce_command_survives_copying_from_the_pdf(built):
    flat = " ".join(_pdf_text(built["planar3r_orient"] / "planar3r_orient.pdf"))
    assert f"rankloci report planar3r_orient --seed {SEED} --samples 2" in flat


def test_reproduce_command_names_a_model_file_by_its_path(tmp_path):
    from rankloci.io import models_dir

    model = tmp_path / "arm.toml"
    text = (models_dir() / "planar2r.toml").read_text().replace('name = "planar2r"',
                                                                'name = "arm"')
    model.write_text(text)
    out = _report(tmp_path / "out", str(model), "--format", "md")
    md = (out / "arm.md").read_text()
    assert f"rankloci report {model} --seed {SEED}" in md


def _tree_legibility(pdf: Path, png: Path) -> tuple[float, float]:
    """(grey-level spread of the tree's page, smallest text size in pt on that page)."""
    from rankloci.reporting.figures import DPI

    pages = _pdf_text(pdf)
    page = next(k for k, p in enumerate(pages, start=1) if "Branch tree of the" in p)
    listing = subprocess.run(["pdfimages", "-list", "-f", str(page), "-l", str(page), str(pdf)],
                             capture_output=True, check=True, text=True).stdout
    width, _ = RH.png_size(png)
    ppi = [float(row.split()[12]) for row in listing.splitlines()[2:]
           if row.split()[2] == "image" and int(row.split()[3]) == width]
    assert ppi, f"the tree image is not on page {page}"
    # graphviz draws 12 pt text at 110 dpi, matplotlib 8 pt at DPI
    font, dpi = (12.0, 110.0) if shutil.which("dot") else (8.0, float(DPI))
    subprocess.run(["pdftoppm", "-png", "-r", "40", "-f", str(page), "-l", str(page),
                    str(pdf), str(pdf.with_name("treepage"))], check=True)
    shot = next(pdf.parent.glob("treepage*.png"))
    return RH.grey_std(shot), font * dpi / ppi[0]


@needs_pdf
def test_tree_page_is_not_blank_and_legible(built):
    d = built["puma560"]
    spread, size = _tree_legibility(d / "puma560.pdf", d / "puma560-tree.png")
    assert spread > RH.BLANK_STD
    assert size >= LEGIBLE_PT, f"tree text is {size:.1f} pt"


# --- the committed reports ------------------------------------------------------------------

def _committed():
    return sorted(p for p in REPORTS.glob("*/*.md") if p.stem == p.parent.name)


def _summary_rows(md: str) -> list[list[str]]:
    head = md.split("\n## ", 1)[0]
    rows = [ln for ln in head.splitlines() if ln.startswith("| [")]
    return [[c.strip() for c in ln.strip("|").split(" | ")] for ln in rows]


def test_committed_reports_have_one_distinct_reading_per_component():
    reports = _committed()
    assert len(reports) >= 10
    for md_path in reports:
        md = md_path.read_text()
        rows = _summary_rows(md)
        assert rows, md_path.name
        readings = [r[2] for r in rows]
        assert all(r and r != "-" for r in readings), (md_path.name, readings)
        assert len(set(readings)) == len(readings), (md_path.name, readings)
        sections = md.split("### Component ")[1:]
        full = [s.split("**Reading.**", 1)[1].split("\n- ", 1)[1].split("\n")[0]
                for s in sections if "**Reading.**" in s]
        assert len(set(full)) == len(full), (md_path.name, "duplicated readings")


@needs_pdf
def test_committed_tree_pages_are_legible(tmp_path):
    for md_path in _committed():
        name = md_path.stem
        pdf, png = md_path.with_suffix(".pdf"), md_path.with_name(f"{name}-tree.png")
        if not png.exists():
            continue
        work = tmp_path / name
        work.mkdir()
        shutil.copy(pdf, work / pdf.name)
        spread, size = _tree_legibility(work / pdf.name, png)
        assert spread > RH.BLANK_STD, name
        assert size >= LEGIBLE_PT, f"{name}: tree text is {size:.1f} pt"


@needs_pdf
def test_committed_pdf_keeps_side_conditions():
    """ssrms component 1 holds only away from an excluded set: the PDF says so wherever it
    gives the component's equations (summary table, display, plain text)."""
    # pdftotext writes the slashed equals sign as a combining slash and "="
    text = " ".join(_pdf_text(REPORTS / "ssrms" / "ssrms.pdf")).replace("\u0338=", "≠")
    flat = re.sub(r"\s+", " ", text)
    summary = flat[:flat.index("1 The model")]
    assert "≠ 0" in summary
    comp = flat[flat.index("Component 1"):flat.index("Component 2", flat.index("Component 1"))]
    assert comp.count("≠ 0") >= 2 and "!= 0" in comp


#: A page is "half blank" when more than this share of its text block, below its last line of
#: ink, is empty (the page number excluded).  The last page may end anywhere.
MAX_BLANK_SHARE = 0.5


def _blank_shares(pdf: Path, tmp: Path) -> list[float]:
    """For each page of ``pdf``: the share of the text block below its last ink, empty."""
    import numpy as np
    from matplotlib.image import imread

    subprocess.run(["pdftoppm", "-r", "30", "-gray", "-png", str(pdf), str(tmp / "page")],
                   check=True, capture_output=True)
    shares = []
    for png in sorted(tmp.glob("page-*.png")):
        grey = imread(str(png))
        grey = grey[..., 0] if grey.ndim == 3 else grey
        h = grey.shape[0]
        body = grey[int(0.08 * h):int(0.90 * h)]    # margins and the page number left out
        ink = np.flatnonzero((body < 0.9).any(axis=1))
        shares.append(1.0 if ink.size == 0 else (len(body) - 1 - ink[-1]) / len(body))
    return shares


def _float_only(text: str) -> bool:
    """Is a page's text only a figure's caption (a page of its own for a figure)?"""
    lines = [ln.strip() for ln in text.splitlines() if ln.strip() and not ln.strip().isdigit()]
    return bool(lines) and lines[0].startswith("Figure ")


def _check_pages(pdf: Path, tmp: Path):
    shares = _blank_shares(pdf, tmp)
    pages = _pdf_text(pdf)[:len(shares)]
    # the last page of text may end anywhere, and so may a page of its own for a figure
    last_text = max(k for k, p in enumerate(pages) if p.strip() and not _float_only(p))
    half = [(k + 1, round(x, 2)) for k, x in enumerate(shares)
            if k < last_text and not _float_only(pages[k]) and x > MAX_BLANK_SHARE]
    assert not half, f"{pdf.name}: half-blank pages (page, blank share) {half}"
    # the summary table starts on page 1, under the title
    assert re.search(r"no\.\s+equations\s+reading", pages[0]), pages[0][:400]
    # the last page holds more than the timings
    last = [p for p in pages if p.strip()][-1]
    assert "Timings" not in last or "Notes of the analysis" in last or "Branch tree" in last


@needs_pdf
def test_no_half_blank_page_and_the_summary_on_page_one(built, tmp_path):
    _check_pages(built["puma560"] / "puma560.pdf", tmp_path)


@needs_pdf
@pytest.mark.slow
def test_a_long_summary_table_starts_on_page_one(tmp_path):
    """The iiwa's summary table (five components, long readings) runs onto page 2."""
    out = _report(tmp_path / "iiwa", "iiwa")
    (tmp_path / "pages").mkdir()
    _check_pages(out / "iiwa.pdf", tmp_path / "pages")


@needs_pdf
@pytest.mark.parametrize("pdf", sorted(REPORTS.glob("*/*.pdf")), ids=lambda p: p.stem)
def test_committed_reports_have_no_half_blank_page(pdf, tmp_path):
    _check_pages(pdf, tmp_path)
