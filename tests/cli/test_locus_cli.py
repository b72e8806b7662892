"""The ``locus`` command, called as ``main([...])``: JSON schema, formats, errors, timeout, tree files."""

from __future__ import annotations

import json

import numpy as np
import pytest
import sympy as sp

from rankloci.cli import main
from rankloci.tolerances import ZERO_RTOL

#: An equation string "vanishes" at a component's sample when |e| / (sum of |coefficients|) is
#: at most the package's ZERO_RTOL (samples are accurate to ROOT_XTOL = 1e-10).
EQ_RTOL = ZERO_RTOL

DEGENERATE = 'variables = ["x", "y"]\nmatrix = [["x", "x"], ["y", "y"]]\n'


def run(capsys, *argv):
    """main(argv) -> (exit code, stdout, stderr)."""
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def locus_json(capsys, *argv):
    code, out, err = run(capsys, "locus", *argv, "--format", "json", "--quiet")
    assert code == 0, err
    assert err == "", "--quiet must keep stderr empty"
    return json.loads(out)


def scaled_value(expr, params: dict, values: dict) -> float:
    """|expr(values)| / (sum of |coefficients| of expr with the parameters substituted)."""
    e = sp.expand(expr.subs(params))
    scale = sum(abs(float(t.as_coeff_Mul()[0])) for t in sp.Add.make_args(e))
    return abs(float(expr.subs(values))) / (scale if scale > 0 else 1.0)


# --- JSON ---------------------------------------------------------------------------------

def test_planar2r_json_schema_and_equations(capsys):
    data = locus_json(capsys, "planar2r")
    assert data["schema"] == "rankloci.locus/2"
    assert data["model"] == "planar2r"
    assert data["variables"] == ["q1", "q2"]
    assert data["parameters"] == {"l1": 1.0, "l2": 1.0}
    assert data["matrix"] == {"rows": 2, "cols": 2}
    assert data["method"] in ("svm", "subdeterminant", "determinant")
    assert data["degenerate"] is False
    assert isinstance(data["seconds"], (int, float)) and data["seconds"] >= 0
    assert data["components"], "planar2r has a singular locus"
    names = {n: sp.Symbol(n, real=True) for n in data["variables"] + list(data["parameters"])}
    for comp in data["components"]:
        for key, kind in (("equations", list), ("solved", dict), ("free", list), ("dimension", int),
                          ("rank_drop", int), ("direction", list)):
            assert isinstance(comp[key], kind), (key, comp)
        assert set(comp["free"]) <= set(data["variables"])
        assert 0 <= comp["dimension"] <= 2 and comp["rank_drop"] >= 1
        # the sample holds the variables and, for special components, their parameter values
        params = {names[k]: v for k, v in data["parameters"].items()}
        params |= {names[k]: v for k, v in comp["sample"].items() if k in data["parameters"]}
        values = params | {names[k]: v for k, v in comp["sample"].items()}
        assert set(comp["sample"]) >= set(data["variables"]), comp["sample"]
        for text in comp["equations"]:
            expr = sp.sympify(text, locals=names)
            assert expr.free_symbols <= set(names.values()), (text, expr.free_symbols)
            value = scaled_value(expr, params, values)
            assert value <= EQ_RTOL, f"equation {text!r}: scaled {value:.2e} at the sample {comp['sample']}"
    main_comps = [c for c in data["components"] if not c["parameter_conditions"] and c["for_model"]]
    assert main_comps and all(c["rank_drop"] == 1 for c in main_comps)
    # the model's own locus is sin(q2) = 0 (det J = l1 l2 sin q2): q2 = 0 and pi, not q2 = 1
    q1, q2 = names["q1"], names["q2"]
    for q2_value, on in ((0.0, True), (np.pi, True), (1.0, False)):
        vals = {q1: 0.3, q2: q2_value, names["l1"]: 1.0, names["l2"]: 1.0}
        zero = any(all(abs(float(sp.sympify(t, locals=names).subs(vals))) <= 1e-12
                       for t in c["equations"]) for c in main_comps)
        assert zero == on, (q2_value, [c["equations"] for c in main_comps])


def test_json_agrees_with_seed_and_is_reproducible(capsys):
    a = locus_json(capsys, "puma560", "--numeric", "--seed", "3")
    b = locus_json(capsys, "puma560", "--numeric", "--seed", "3")
    assert a["seed"] == 3
    a.pop("seconds"), b.pop("seconds")
    a["certificate"].pop("seconds"), b["certificate"].pop("seconds")
    assert a == b
    assert a["certificate"]["verdict"] == "passed" and a["certificate"]["seed"] == 3
    assert a["matrix"] == {"rows": 6, "cols": 6} and a["parameters"] == {}
    # shoulder, elbow and wrist singularities: at least three pieces, all of dimension 5
    assert len(a["components"]) >= 3, [c["equations"] for c in a["components"]]
    assert all(c["dimension"] == 5 and c["rank_drop"] == 1 for c in a["components"])


def test_degenerate_matrix_is_reported(capsys, write_file):
    path = write_file("degen.toml", DEGENERATE)
    for method in ("svm", "subdeterminant", "determinant"):
        data = locus_json(capsys, str(path), "--method", method)
        assert data["degenerate"] is True, method
        assert data["matrix"] == {"rows": 2, "cols": 2}


# --- other formats, progress, errors ------------------------------------------------------

def test_latex_format(capsys):
    code, out, err = run(capsys, "locus", "planar2r", "--format", "latex", "--quiet")
    assert code == 0 and err == ""
    assert "\\begin{align*}" in out and "\\end{align*}" in out
    assert out.count("\\begin{align*}") == out.count("\\end{align*}")


def test_text_format_lists_components(capsys):
    code, out, err = run(capsys, "locus", "puma560", "--numeric", "--quiet")
    assert code == 0 and err == ""
    lines = out.splitlines()
    assert lines[0].startswith("puma560: 6x6 matrix"), lines[0]
    counts = [line for line in lines
              if line.endswith(("component of the rank-deficiency locus:",
                                "components of the rank-deficiency locus:"))]
    assert len(counts) == 1 and int(counts[0].split()[0]) >= 3, out
    assert out.count("rank drop 1") == int(counts[0].split()[0]), out


def test_progress_goes_to_stderr_unless_quiet(capsys):
    code, out, err = run(capsys, "locus", "planar2r", "--format", "json")
    assert code == 0
    json.loads(out)  # stdout is only the JSON document
    lines = err.splitlines()
    assert lines, "progress messages expected on stderr"
    assert all(line.startswith("rankloci: ") for line in lines), err
    code, out_quiet, err_quiet = run(capsys, "locus", "planar2r", "--format", "json", "--quiet")
    assert code == 0 and err_quiet == ""


@pytest.mark.parametrize("quiet", [True, False], ids=["quiet", "progress"])
def test_determinant_method_needs_a_square_matrix(capsys, quiet):
    code, out, err = run(capsys, "locus", "planar3r", "--method", "determinant",
                         *(["--quiet"] if quiet else []))
    assert code == 2
    assert out == ""
    assert "Traceback" not in err
    errors = [line for line in err.splitlines() if line.startswith("rankloci: error: ")]
    assert len(errors) == 1, err
    assert errors == ["rankloci: error: --method determinant needs a square matrix; this one is 2x3"]
    if quiet:
        assert err.splitlines() == errors


@pytest.fixture
def jumping_clock(monkeypatch):
    """The --timeout clock moves 1000 s at every reading: the first poll after the start
    finds any budget under 1000 s spent, however fast the machine."""
    import itertools

    import rankloci.cli.running

    ticks = itertools.count(0.0, 1000.0)
    monkeypatch.setattr(rankloci.cli.running, "deadline_clock", lambda: next(ticks))


def test_timeout_exits_1(capsys, jumping_clock):
    code, out, err = run(capsys, "locus", "planar3r", "--timeout", "600", "--quiet")
    assert code == 1, (out, err)
    assert out == ""
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    assert err.startswith("rankloci: error: ") and "did not finish" in err
    assert "raise --timeout (now 600 s)" in err


def test_timeout_0_never_stops(capsys, jumping_clock):
    code, out, err = run(capsys, "locus", "planar3r", "--timeout", "0", "--quiet")
    assert (code, err) == (0, "")


# --- the branch tree files ----------------------------------------------------------------

def test_tree_files_are_written_and_parse(capsys, tmp_path):
    paths = {ext: tmp_path / f"tree.{ext}" for ext in ("json", "dot", "txt")}
    for path in paths.values():
        code, out, err = run(capsys, "locus", "planar3r", "--tree", str(path), "--quiet", "--seed", "1")
        assert code == 0, err
        assert path.is_file()
    with open(paths["json"], encoding="utf-8") as fh:
        data = json.load(fh)
    ids = {n["id"] for n in data["nodes"]}
    edges = data["edges"]
    assert 0 in ids
    assert all(e["source"] in ids and e["target"] in ids for e in edges)
    assert not any(e["target"] == 0 for e in edges), "node 0 is the root"
    parents = {e["source"] for e in edges}
    leaves = [n for n in data["nodes"] if n["id"] not in parents]
    assert leaves and all(n.get("outcome") for n in leaves), leaves
    dot = paths["dot"].read_text(encoding="utf-8")
    assert dot.startswith("digraph")
    assert dot.rstrip().endswith("}")
    assert dot.count("->") == len(edges)
    txt = paths["txt"].read_text(encoding="utf-8")
    assert txt.strip() and "0:" in txt.splitlines()[0]
    assert len(txt.strip().splitlines()) >= len(ids)


def test_tree_with_unknown_suffix_is_a_usage_error(capsys, tmp_path):
    code, out, err = run(capsys, "locus", "planar2r", "--tree", str(tmp_path / "tree.png"))
    assert code == 2 and out == "" and len(err.splitlines()) == 1


def test_components_are_the_models_own_and_special_ones_are_kept_apart(capsys):
    """planar2r (l1 = l2 = 1): det J = l1 l2 sin q2.  The model's locus is sin q2 = 0; l1 = 0
    and l2 = 0 hold only for other link lengths and are listed under special_components."""
    data = locus_json(capsys, "planar2r")
    assert [c["equations"] for c in data["components"]] == [["sin(q2)"]]
    assert all(c["for_model"] and not c["parameter_conditions"] for c in data["components"])
    special = sorted(c["parameter_conditions"] for c in data["special_components"])
    assert special == [["l1"], ["l2"]]
    assert not any(c["for_model"] for c in data["special_components"])


def test_schema_1_files_are_read_with_special_components_kept_apart(tmp_path, capsys):
    """A rankloci.locus/1 file listed special-parameter components among the others."""
    path = tmp_path / "old.json"
    path.write_text(json.dumps({
        "schema": "rankloci.locus/1", "model": "planar2r", "variables": ["q1", "q2"],
        "components": [{"equations": ["sin(q2)"], "parameter_conditions": [], "for_model": True},
                       {"equations": ["l1"], "parameter_conditions": ["l1"],
                        "for_model": True}]}), encoding="utf-8")
    code = main(["check", "planar2r", "--locus", str(path), "--quiet", "--format", "json"])
    out = capsys.readouterr()
    assert code == 0, out.err
    report = json.loads(out.out)
    assert report["ok"]
    assert [c["equations"] for c in report["on_locus"]] == [["sin(q2)"]]
    assert report["skipped_components"] == [["l1"]]


def test_a_locus_its_self_check_rejects_is_printed_incomplete_with_exit_1(monkeypatch, capsys):
    """Never a locus that the tool's own check rejects, shown as if it passed."""
    import dataclasses

    import rankloci.augmented as augmented

    real = augmented.augmented_locus_and_tree

    def losing(*args, **kwargs):
        # sin q1 = 0 with q2, q3 free: regular at its points, whatever else is found
        locus, tree = real(*args, **kwargs)
        q1, *rest = locus.variables
        wrong = dataclasses.replace(locus.components[0], equations=(sp.sin(q1),), solved={},
                                    free=tuple(rest), dimension=len(rest))
        return dataclasses.replace(locus, components=(wrong,)), tree

    monkeypatch.setattr(augmented, "augmented_locus_and_tree", losing)
    code = main(["locus", "planar3r", "--format", "json", "--quiet"])
    out = capsys.readouterr()
    assert code == 1
    data = json.loads(out.out)
    assert data["complete"] is False
    assert any(n.startswith("INCOMPLETE") for n in data["notes"])
    assert "incomplete" in out.err
    assert main(["locus", "planar3r", "--format", "json", "--quiet", "--no-verify"]) == 0
    assert json.loads(capsys.readouterr().out)["complete"] is None


# --- joint limits -------------------------------------------------------------------------

def _planar2r_with_elbow_limits(tmp_path, lo, hi):
    from pathlib import Path

    text = (Path(__file__).parents[2] / "kinematics_models" / "planar2r.toml").read_text()
    head, sep, tail = text.rpartition('a = "l2"')
    path = tmp_path / "planar2r.toml"
    path.write_text(head + sep + f"\nlimits = [{lo}, {hi}]" + tail)
    return str(path)


def test_json_says_per_component_whether_it_meets_the_joint_limits(capsys, tmp_path):
    free = locus_json(capsys, "planar2r")["components"][0]["within_limits"]
    assert free["meets"] is True and free["how"] == "no joint limits"
    # sin(q2) = 0 fixes the elbow at 0 or pi: limits (0.5, 2.5) miss both
    bent = locus_json(capsys, _planar2r_with_elbow_limits(tmp_path, 0.5, 2.5))
    entry = bent["components"][0]["within_limits"]
    assert (entry["meets"], entry["how"], entry["sample"]) == (False, "exact", None)
    # limits (-0.5, 2.5) hold q2 = 0: a point inside them, on the component
    wide = locus_json(capsys, _planar2r_with_elbow_limits(tmp_path, -0.5, 2.5))
    entry = wide["components"][0]["within_limits"]
    assert entry["meets"] is True
    assert -0.5 <= entry["sample"]["q2"] <= 2.5 and abs(np.sin(entry["sample"]["q2"])) < 1e-9


def test_text_output_has_a_joint_limits_line(capsys, tmp_path):
    code, out, _ = run(capsys, "locus", _planar2r_with_elbow_limits(tmp_path, 0.5, 2.5), "--quiet")
    assert code == 0
    line = next(x.strip() for x in out.splitlines() if "joint limits" in x)
    assert line.startswith("within the joint limits: no (exact: q2 is fixed at 0, pi")
