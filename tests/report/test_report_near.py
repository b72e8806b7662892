"""The report's section on motion near the locus: manipulability and minimum infinity-norm rates."""

from __future__ import annotations

import re
import shutil

import numpy as np
import pytest

import report_helpers as RH
from rankloci.api.near import manipulability
from rankloci.numeric.landscape import model_components
from rankloci.reporting.content import report_blocks
from rankloci.reporting.near_section import NEAR_OFFSET

SEED = 1
MODELS = ("planar3r", "puma560")


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """Model name -> (directory with md and tex, the Report)."""
    from rankloci.io import load_model
    from rankloci.reporting.build import build_report
    from rankloci.reporting.write import write_report

    out = {}
    for name in MODELS:
        d = tmp_path_factory.mktemp("near") / name
        report = build_report(load_model(name), seed=SEED, samples=2, exact=False)
        write_report(report, d, formats=("md", "tex"))
        out[name] = (d, report)
    return out


@pytest.mark.parametrize("name", MODELS)
def test_section_and_figures_are_in_markdown_and_latex(built, name):
    d, report = built[name]
    md = (d / f"{name}.md").read_text(encoding="utf-8")
    tex = (d / f"{name}.tex").read_text(encoding="utf-8")
    assert "Motion near the locus" in md and "Motion near the locus" in tex
    for kind in ("near-manipulability", "near-path"):
        f = f"{name}-{kind}.png"
        assert (d / f).is_file() and RH.grey_std(d / f) > RH.BLANK_STD
        assert f"]({f})" in md and f"{{{f}}}" in tex


@pytest.mark.parametrize("name", MODELS)
def test_w_is_smaller_near_every_component_than_at_the_regular_pose(built, name):
    near = built[name][1].near
    regular, *close = near.poses
    assert regular.component == 0 and len(close) == len(model_components(built[name][1].locus))
    for p in close:
        assert p.w < regular.w and p.sigma_ratio < regular.sigma_ratio
        assert p.distance == pytest.approx(NEAR_OFFSET, rel=0.5)


@pytest.mark.parametrize("name", MODELS)
def test_numbers_in_the_text_are_those_of_the_functions(built, name):
    """The table's w, semi-axes and volume are manipulability()'s at the pose the report names."""
    d, report = built[name]
    md = (d / f"{name}.md").read_text(encoding="utf-8")
    for p in report.near.poses:
        m = manipulability(report.model, p.q)
        assert p.w == m.ellipsoid.w and p.volume == m.polytope.volume
        assert np.array_equal(p.radii, m.ellipsoid.radii)
        assert f"| {p.w:.4g} |" in md
    path = report.near.path
    assert f"the largest joint rate is {path.rate_max:.4g}" in md
    assert f"discontinuity index is {path.index:.3g}" in md


def test_the_rates_grow_toward_the_stretched_planar_arm(built):
    """planar3r: the minimum infinity-norm rates grow toward the workspace boundary."""
    path = built["planar3r"][1].near.path
    assert path.sigma_ratio < 0.1 and path.rate_max > 3 * path.rate_max_start


def test_a_matrix_model_has_no_such_section():
    import sympy as sp

    import rankloci
    from rankloci.reporting.build import build_report

    x = sp.Symbol("x")
    report = build_report(rankloci.load_model(sp.Matrix([[sp.cos(x), 2], [1, sp.sin(x)]])),
                          samples=2, exact=False)
    assert report.near is None and not report.figure("near-path")
    assert not [b for b in report_blocks(report) if "Motion near" in getattr(b, "text", "")]


def test_tex_compiles(built, tmp_path):
    if RH.LATEXMK is None:
        pytest.skip("latexmk is not installed (Debian: latexmk, texlive-latex-extra)")
    name = "planar3r"
    work = tmp_path / name
    shutil.copytree(built[name][0], work)
    code, log = RH.latexmk(work, name)
    assert code == 0, log[-2000:]
    overfull = [float(x) for x in re.findall(r"Overfull \\hbox \(([\d.]+)pt too wide\)", log)]
    assert not [x for x in overfull if x > 1.0], overfull
