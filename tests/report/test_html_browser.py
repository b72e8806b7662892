"""The HTML report in a real browser (headless Chromium driven by Selenium).

The page loads without console errors, renders every formula, and its sliders
move the arm along each component of the locus (of the PUMA 560, of the Stanford arm,
whose boom is a prismatic joint, and of a 6R arm read from a URDF file) while the ratio
sigma_min/sigma_max the page computes (from the joint chain, not from the
locus) stays at most VIEW_ON_LOCUS_RTOL; the poses it reaches are on the locus
by :meth:`Locus.contains`.  With every joint free, the ratio the page shows is
the one numpy gives for the tool's own Jacobian.

Needs Debian's ``chromium`` and ``chromium-driver`` (``.ci/run`` installs them)
and ``selenium`` (the ``test`` extra).  Without them the tests are skipped with
the reason, unless ``RANKLOCI_REQUIRE_BROWSER`` is set (as ``.ci/run`` sets it
when it installed them): then they fail.
"""

from __future__ import annotations

import json
import os
import shutil

import numpy as np
import pytest
import sympy as sp

from rankloci.io import load_model
from rankloci.jacobians import task_matrix
from rankloci.numeric.equations import NumericMatrix
from rankloci.tolerances import REGULAR_MIN_RATIO, VIEW_ON_LOCUS_RTOL

pytestmark = pytest.mark.slow

#: Steps in which a slider is dragged (each an input event, as a hand on the slider gives).
DRAG_STEPS = 6

#: How far a slider is dragged, as a fraction of its range.
DRAG = 0.2

#: Relative agreement of the page's sigma_min/sigma_max with numpy's at a regular pose: both
#: are double precision from the same chain; a ratio of 1e-2 or more carries ~1e-14.
AGREE_RTOL = 1e-9


def _chromium():
    """(chromium, chromedriver) paths, or a skip (a failure when a browser is required)."""
    required = bool(os.environ.get("RANKLOCI_REQUIRE_BROWSER"))
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    driver = shutil.which("chromedriver")
    try:
        import selenium  # noqa: F401
    except ImportError:
        selenium_missing = True
    else:
        selenium_missing = False
    missing = [name for name, ok in (("chromium", browser), ("chromedriver", driver),
                                     ("selenium", not selenium_missing)) if not ok]
    if missing:
        why = (f"the browser test needs {', '.join(missing)} (apt-get install chromium "
               "chromium-driver; pip install -e '.[test]')")
        if required:
            pytest.fail(why + "; RANKLOCI_REQUIRE_BROWSER is set")
        pytest.skip(why)
    return browser, driver


#: A 6R arm from a URDF file (yaw, shoulder and elbow pitch, a roll-pitch-roll wrist, with
#: limits): the page is built from a URDF model as from a model file.
URDF_6R = """<?xml version="1.0"?>
<robot name="arm6r">
  <link name="base"/><link name="l1"/><link name="l2"/><link name="l3"/><link name="l4"/>
  <link name="l5"/><link name="l6"/><link name="tool"/>
  <joint name="yaw" type="revolute"><parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0" rpy="0 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-2.9" upper="2.9" effort="1" velocity="1"/></joint>
  <joint name="shoulder" type="revolute"><parent link="l1"/><child link="l2"/>
    <origin xyz="0 0 0.3" rpy="0 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-2.0" upper="2.0" effort="1" velocity="1"/></joint>
  <joint name="elbow" type="revolute"><parent link="l2"/><child link="l3"/>
    <origin xyz="0.4 0 0" rpy="0 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-2.5" upper="2.5" effort="1" velocity="1"/></joint>
  <joint name="roll1" type="revolute"><parent link="l3"/><child link="l4"/>
    <origin xyz="0.35 0 0" rpy="0 0 0"/><axis xyz="1 0 0"/>
    <limit lower="-3.0" upper="3.0" effort="1" velocity="1"/></joint>
  <joint name="pitch" type="revolute"><parent link="l4"/><child link="l5"/>
    <origin xyz="0 0 0" rpy="0 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-2.0" upper="2.0" effort="1" velocity="1"/></joint>
  <joint name="roll2" type="revolute"><parent link="l5"/><child link="l6"/>
    <origin xyz="0 0 0" rpy="0 0 0"/><axis xyz="1 0 0"/>
    <limit lower="-3.0" upper="3.0" effort="1" velocity="1"/></joint>
  <joint name="flange" type="fixed"><parent link="l6"/><child link="tool"/>
    <origin xyz="0.1 0 0" rpy="0 0 0"/></joint>
</robot>
"""

#: The PUMA 560, a prismatic arm (the Stanford arm: its boom slides) and a URDF model.
PAGES = ("puma560", "stanford", "arm6r.urdf")


@pytest.fixture(scope="module", params=PAGES)
def page(request, tmp_path_factory):
    pytest.importorskip("matplotlib")
    from rankloci.reporting import build_report
    from rankloci.reporting.html import render_html

    d = tmp_path_factory.mktemp("html")
    name = request.param
    if name.endswith(".urdf"):
        (d / name).write_text(URDF_6R, encoding="utf-8")
        name = str(d / name)
    report = build_report(load_model(name), samples=2, exact=False)
    path = d / "page.html"
    path.write_text(render_html(report, timings=False), encoding="utf-8")
    return report, path


@pytest.fixture(scope="module")
def browser(page):
    browser, driver = _chromium()
    from selenium import webdriver
    from selenium.webdriver.chrome.options import Options
    from selenium.webdriver.chrome.service import Service

    options = Options()
    for arg in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                "--disable-extensions", "--no-first-run"):
        options.add_argument(arg)
    options.binary_location = browser
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    chrome = webdriver.Chrome(service=Service(driver), options=options)
    try:
        chrome.get(page[1].as_uri())
        yield chrome
    finally:
        chrome.quit()


def _ratio(chrome) -> float:
    return float(chrome.find_element("id", "sigma-ratio").get_attribute("data-value"))


def _pose(chrome) -> np.ndarray:
    return np.array(json.loads(chrome.find_element("id", "arm-pose").get_attribute("data-value")))


def _joints(chrome) -> list:
    return json.loads(chrome.find_element("id", "arm-canvas").get_attribute("data-joints"))


def _choose(chrome, index: int) -> None:
    chrome.execute_script("const s = document.getElementById('arm-component');"
                          "s.value = String(arguments[0]); s.dispatchEvent(new Event('change'));",
                          index)


def _drag(chrome, slider, fraction: float):
    """Move ``slider`` by ``fraction`` of its range in DRAG_STEPS input events; yield after each."""
    lo, hi, x = (float(slider.get_attribute(a)) for a in ("min", "max", "value"))
    step = fraction * (hi - lo)
    if x + step > hi:
        step = -step
    for k in range(1, DRAG_STEPS + 1):
        chrome.execute_script("const s = arguments[0]; s.value = String(arguments[1]);"
                              "s.dispatchEvent(new Event('input'));", slider,
                              x + step * k / DRAG_STEPS)
        yield


def test_page_loads_without_console_errors_and_renders_every_formula(browser):
    errors = [e for e in browser.get_log("browser") if e["level"] == "SEVERE"]
    assert errors == []
    spans = browser.execute_script("return document.querySelectorAll('.math').length")
    rendered = browser.execute_script("return document.querySelectorAll('.math math').length")
    failed = browser.execute_script("return document.querySelectorAll('.katex-error').length")
    assert spans > 20 and rendered == spans and failed == 0


def test_sliders_move_the_arm_along_each_component(browser, page):
    report, _ = page
    locus = report.locus
    offered = browser.execute_script(
        "return [...document.querySelectorAll('#arm-component option')].map(o => +o.value)")
    components = [v.index for v in report.components if not v.special]
    assert offered == [0, *components]
    dragged = set()
    for index in components:
        _choose(browser, index)
        start = _joints(browser)
        assert _ratio(browser) <= VIEW_ON_LOCUS_RTOL, index
        # a sample point within the joint limits is shown so (the Stanford arm's boom at
        # zero extension is outside the boom's stroke: its sample is too)
        outside = browser.find_element("id", "arm-pose").get_attribute("data-outside")
        if report.limit_check(index).meets:
            assert json.loads(outside) == [], index
        sliders = browser.find_elements("css selector", "#arm-sliders input[type=range]")
        dimension = next(v.component.dimension for v in report.components if v.index == index)
        assert len(sliders) == dimension
        for slider in sliders:
            dragged.add(int(slider.get_attribute("data-variable")))
            for _ in _drag(browser, slider, DRAG):
                ratio = _ratio(browser)
                assert ratio <= VIEW_ON_LOCUS_RTOL, (index, slider.get_attribute("id"), ratio)
            assert locus.contains(_pose(browser)), (index, slider.get_attribute("id"))
        moved = np.abs(np.array(_joints(browser)) - np.array(start)).max()
        assert moved > 1.0, (index, moved)       # pixels
    # a prismatic joint (the Stanford arm's boom) is among the joints moved along the locus
    prismatic = {k for k, j in enumerate(report.model.joints) if j.kind == "prismatic"}
    assert not prismatic or prismatic & dragged, (prismatic, dragged)
    assert [e for e in browser.get_log("browser") if e["level"] == "SEVERE"] == []


def test_with_every_joint_free_the_ratio_is_numpys(browser, page):
    report, _ = page
    model = report.model
    tm = task_matrix(model)
    nm = NumericMatrix(sp.Matrix(tm.matrix).subs(dict(tm.parameters)), tm.variables, tm.angles)
    _choose(browser, 0)
    sliders = browser.find_elements("css selector", "#arm-sliders input[type=range]")
    assert len(sliders) == len(model.variables)
    for slider in sliders:
        for _ in _drag(browser, slider, 0.3):
            pass
    q = _pose(browser)
    # a joint moved out of its limits is named (the page's own test, against the model's)
    limits = [j.limits for j in model.joints]
    turns = [(-1, 0, 1) if j.kind == "revolute" else (0,) for j in model.joints]
    outside = [v.name for v, lim, x, ks in zip(model.variables, limits, q, turns)
               if lim is not None and not any(lim[0] <= x + 2 * np.pi * k <= lim[1]
                                              for k in ks)]
    shown = browser.find_element("id", "arm-pose").get_attribute("data-outside")
    assert json.loads(shown) == outside
    s = np.linalg.svd(nm(q), compute_uv=False)
    expected = s[-1] / s[0]
    assert expected > REGULAR_MIN_RATIO       # an ordinary pose: the page must not call it on
    assert abs(_ratio(browser) - expected) <= AGREE_RTOL * expected
    assert not report.locus.contains(q)
