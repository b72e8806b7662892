"""`rankloci check`: exit 0 on computed loci, 1 on wrong loci, 2 on bad input."""

from __future__ import annotations

import json

import pytest

from rankloci.cli import main


@pytest.fixture(scope="module")
def puma_json(tmp_path_factory):
    import contextlib
    import io

    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(["locus", "puma560", "--numeric", "--format", "json", "--quiet"]) == 0
    return json.loads(out.getvalue())


def _write(tmp_path, data):
    path = tmp_path / "locus.json"
    path.write_text(json.dumps(data) if not isinstance(data, str) else data, encoding="utf-8")
    return str(path)


def _check(capsys, *argv):
    code = main(["check", *argv, "--samples", "6", "--seed", "7", "--quiet"])
    return code, capsys.readouterr()


@pytest.mark.parametrize("name", ["planar2r", "planar3r", "puma560"])
def test_check_passes(capsys, name):
    code, out = _check(capsys, name, "--numeric")
    assert code == 0, out.out
    assert "seed 7" in out.out and "PASS" in out.out


def test_check_json_report(capsys):
    code, out = _check(capsys, "planar2r", "--numeric", "--format", "json")
    report = json.loads(out.out)
    assert code == 0 and report["schema"] == "rankloci.check/1" and report["seed"] == 7
    assert report["ok"] and report["on_locus"][0]["n_points"] == 6


def test_check_of_the_locus_file_passes(capsys, tmp_path, puma_json):
    code, out = _check(capsys, "puma560", "--locus", _write(tmp_path, puma_json))
    assert code == 0, out.out


def test_missing_wrist_component_fails(capsys, tmp_path, puma_json):
    data = dict(puma_json, components=[c for c in puma_json["components"]
                                       if c["equations"] != ["sin(q5)"]])
    assert len(data["components"]) == len(puma_json["components"]) - 1
    code, out = _check(capsys, "puma560", "--locus", _write(tmp_path, data))
    assert code == 1, out.out
    assert "FAIL" in out.out


def test_spurious_component_fails(capsys, tmp_path, puma_json):
    data = dict(puma_json, components=puma_json["components"] + [{"equations": ["q1"]}])
    code, out = _check(capsys, "puma560", "--locus", _write(tmp_path, data))
    assert code == 1, out.out


def test_typo_in_equation_fails(capsys, tmp_path, puma_json):
    comps = [dict(c, equations=["sin(q4)"]) if c["equations"] == ["sin(q5)"] else c
             for c in puma_json["components"]]
    code, out = _check(capsys, "puma560", "--locus", _write(tmp_path, dict(puma_json, components=comps)))
    assert code == 1, out.out


@pytest.mark.parametrize("bad", [
    "{not json",
    {"schema": "rankloci.jacobian/1"},
    {"schema": "rankloci.locus/1", "variables": ["q1", "q2"], "components": []},
    {"schema": "rankloci.locus/1", "variables": ["q1", "q2", "q3", "q4", "q5", "q6"],
     "components": [{"equations": ["sin(q5"]}]},
    {"schema": "rankloci.locus/1", "variables": ["q1", "q2", "q3", "q4", "q5", "q6"],
     "components": [{"equations": ["sin(x)"]}]},
], ids=["syntax", "schema", "variables", "equation-syntax", "unknown-name"])
def test_malformed_locus_file_is_exit_2(capsys, tmp_path, bad):
    code, out = _check(capsys, "puma560", "--locus", _write(tmp_path, bad))
    assert code == 2
    assert out.out == ""
    lines = out.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("rankloci: error: ")


def test_missing_locus_file_is_exit_2(capsys, tmp_path):
    code, out = _check(capsys, "planar2r", "--locus", str(tmp_path / "nope.json"))
    assert code == 2 and len(out.err.strip().splitlines()) == 1


def test_check_takes_the_chain_of_a_urdf(capsys, robots):
    """`check` reads the same chain as `locus`: --base-link and --tip."""
    urdf = str(robots / "anymal_b_simple_description/robots/anymal.urdf")
    code, out = _check(capsys, urdf, "--tip", "LF_SHANK")
    assert code == 0, out.out + out.err
    assert "PASS" in out.out
    code, out = _check(capsys, urdf, "--tip", "no_such_link")
    assert code == 2 and "no_such_link" in out.err
