"""`rankloci check` on every built-in model: all on-locus points singular, all
off-locus points regular, no uncovered singular point."""

import pytest

from rankloci.cli import main
from rankloci.io import builtin_models

SLOW = {"pa10", "ssrms", "ssrms_lock3", "mobile10"}
MODELS = [pytest.param(m, marks=pytest.mark.slow) if m in SLOW else m for m in builtin_models()]


@pytest.mark.parametrize("name", MODELS)
def test_check_passes_on_builtin_model(name, capsys):
    code = main(["check", name, "--numeric-parameters", "--quiet", "--samples", "3", "--seed", "5"])
    out = capsys.readouterr().out
    assert code == 0, out
    assert "result: PASS" in out
