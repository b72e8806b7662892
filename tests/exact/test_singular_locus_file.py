"""`rankloci check --locus FILE` with Singular: a locus read back from JSON has no samples.

The exact cross-check compares each component with the minimal primes of the maximal-minor
ideal at a point of the component.  A locus written by `rankloci locus --format json` and read
back carries equations but no sample point, so the check must find points itself.
"""

from __future__ import annotations

import json

import pytest

from rankloci.cli import main
from rankloci.exact.singular import singular_available

pytestmark = pytest.mark.skipif(not singular_available(),
                                reason="Singular is not installed (Debian package 'singular')")


@pytest.mark.parametrize("name", ["planar2r", "planar3r"])
def test_check_reads_its_own_locus_json(tmp_path, capsys, name):
    assert main(["locus", name, "--quiet", "--format", "json"]) == 0
    path = tmp_path / f"{name}.json"
    path.write_text(capsys.readouterr().out, encoding="utf-8")
    code = main(["check", name, "--locus", str(path), "--quiet", "--format", "json"])
    out = capsys.readouterr()
    assert code == 0, out.err
    report = json.loads(out.out)
    singular = report["singular"]
    assert singular["status"] == "agree", singular


def test_equations_that_name_parameters_get_the_models_values(tmp_path, capsys):
    """l1*sin(q2) = 0 is planar2r's locus at l1 = 1; the exact check substitutes the value."""
    path = tmp_path / "l.json"
    path.write_text(json.dumps({"schema": "rankloci.locus/2", "model": "planar2r",
                                "variables": ["q1", "q2"],
                                "components": [{"equations": ["l1*sin(q2)"]}]}), encoding="utf-8")
    code = main(["check", "planar2r", "--locus", str(path), "--quiet", "--format", "json"])
    out = capsys.readouterr()
    assert code == 0, out.err
    assert json.loads(out.out)["singular"]["status"] == "agree"
