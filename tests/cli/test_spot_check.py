"""`rankloci check` on every built-in model: all on-locus points singular, all
off-locus points regular, no uncovered singular point."""

import json

import pytest

from rankloci.cli import main
from rankloci.io import builtin_models

SLOW = {"pa10", "ssrms", "ssrms_lock3", "mobile10"}
MODELS = [pytest.param(m, marks=pytest.mark.slow) if m in SLOW else m for m in builtin_models()]
SAMPLES = 3


@pytest.mark.parametrize("name", MODELS)
def test_check_passes_on_builtin_model(name, capsys):
    code = main(["check", name, "--numeric", "--quiet", "--samples", str(SAMPLES),
                 "--seed", "5", "--format", "json"])
    out, err = capsys.readouterr()
    assert err == ""
    report = json.loads(out)
    assert (code, report["ok"], report["model"]) == (0, True, name), out
    # every component of the locus is checked, each at SAMPLES singular points
    assert report["on_locus"] and report["skipped_components"] == []
    assert [(c["index"], c["ok"], c["n_points"]) for c in report["on_locus"]] == \
        [(k, True, SAMPLES) for k in range(1, len(report["on_locus"]) + 1)]
    # SAMPLES random configurations, all of full rank
    off = report["off_locus"]
    assert (off["ok"], off["n_points"], off["failures"]) == (True, SAMPLES, [])
    # every singular minimum found from SAMPLES starts lies on a component
    assert report["completeness"]["ok"] and report["completeness"]["starts"] == SAMPLES
    assert report["completeness"]["uncovered"] == []
    assert report["findings"] == []
    assert report["singular"]["status"] in ("agree", "skipped")
