"""The HTML report in a real browser (headless Chromium driven by Selenium).

The page loads without console errors, renders every formula, and its sliders
move the arm along each component of the PUMA 560's locus while the ratio
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


@pytest.fixture(scope="module")
def puma_page(tmp_path_factory):
    pytest.importorskip("matplotlib")
    from rankloci.reporting import build_report
    from rankloci.reporting.html import render_html

    report = build_report(load_model("puma560"), samples=2, exact=False)
    path = tmp_path_factory.mktemp("html") / "puma560.html"
    path.write_text(render_html(report, timings=False), encoding="utf-8")
    return report, path


@pytest.fixture(scope="module")
def browser(puma_page):
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
        chrome.get(puma_page[1].as_uri())
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


def test_sliders_move_the_arm_along_each_component(browser, puma_page):
    report, _ = puma_page
    locus = report.locus
    offered = browser.execute_script(
        "return [...document.querySelectorAll('#arm-component option')].map(o => +o.value)")
    components = [v.index for v in report.components if not v.special]
    assert offered == [0, *components]
    for index in components:
        _choose(browser, index)
        start = _joints(browser)
        assert _ratio(browser) <= VIEW_ON_LOCUS_RTOL, index
        # the report's sample point lies within the joint limits, and the page says so
        assert report.limit_check(index).meets
        outside = browser.find_element("id", "arm-pose").get_attribute("data-outside")
        assert json.loads(outside) == [], index
        sliders = browser.find_elements("css selector", "#arm-sliders input[type=range]")
        dimension = next(v.component.dimension for v in report.components if v.index == index)
        assert len(sliders) == dimension
        for slider in sliders:
            for _ in _drag(browser, slider, DRAG):
                ratio = _ratio(browser)
                assert ratio <= VIEW_ON_LOCUS_RTOL, (index, slider.get_attribute("id"), ratio)
            assert locus.contains(_pose(browser)), (index, slider.get_attribute("id"))
        moved = np.abs(np.array(_joints(browser)) - np.array(start)).max()
        assert moved > 1.0, (index, moved)       # pixels
    assert [e for e in browser.get_log("browser") if e["level"] == "SEVERE"] == []


def test_with_every_joint_free_the_ratio_is_numpys(browser, puma_page):
    report, _ = puma_page
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
    outside = [v.name for v, lim, x in zip(model.variables, limits, q)
               if lim is not None and not any(lim[0] <= x + 2 * np.pi * k <= lim[1]
                                              for k in (-1, 0, 1))]
    shown = browser.find_element("id", "arm-pose").get_attribute("data-outside")
    assert json.loads(shown) == outside
    s = np.linalg.svd(nm(q), compute_uv=False)
    expected = s[-1] / s[0]
    assert expected > REGULAR_MIN_RATIO       # an ordinary pose: the page must not call it on
    assert abs(_ratio(browser) - expected) <= AGREE_RTOL * expected
    assert not report.locus.contains(q)
