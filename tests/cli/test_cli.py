"""The command line, called as ``main([...])``: output formats, one-line errors, exit codes."""

from __future__ import annotations

import json
import re
import subprocess
import sys

import pytest
import sympy as sp

from rankloci.cli import main
from rankloci.cli.commands import COMMANDS
from rankloci.errors import ModelError
from rankloci.expr import parse_expression
from rankloci.io import builtin_models, load_model
from rankloci.io.toml_model import parse_model
from rankloci.kinematics import geometric_jacobian

PLANAR = """\
name = "arm"
source = "test"
task = "planar"
[parameters]
l1 = 1.0
l2 = 0.5
[[joint]]
a = "l1"
[[joint]]
a = "l2"
"""


def run(capsys, *argv):
    """main(argv) -> (exit code, stdout, stderr)."""
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def assert_one_line_error(code, out, err):
    assert code == 2
    assert out == ""
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("rankloci: error: ")
    assert "Traceback" not in err


# --- models --------------------------------------------------------------------------------

def test_models_lists_every_builtin_model(capsys):
    code, out, err = run(capsys, "models")
    assert code == 0 and err == ""
    names = builtin_models()
    assert names, "there are built-in models"
    listed = [line.split()[0] for line in out.splitlines()[1:]]
    assert listed == names


def test_models_json(capsys):
    code, out, _ = run(capsys, "models", "--format", "json")
    assert code == 0
    rows = json.loads(out)
    assert [r["name"] for r in rows] == builtin_models()
    by_name = {r["name"]: r for r in rows}
    if "puma560" in by_name:
        assert by_name["puma560"]["shape"] == "6x6" and by_name["puma560"]["joints"] == "6"
    if "planar2r" in by_name:
        assert by_name["planar2r"]["shape"] == "2x2"


# --- jacobian -----------------------------------------------------------------------------

def _planar2r_names():
    model = load_model("planar2r")
    names = {v.name: v for v in model.variables} | {p.name: p for p in model.parameters}
    return model, names


def test_jacobian_text(capsys):
    code, out, err = run(capsys, "jacobian", "planar2r")
    assert code == 0 and err == ""
    lines = out.splitlines()
    assert lines[0] == "# planar2r: 2x2 matrix in q1, q2"
    model, names = _planar2r_names()
    J = geometric_jacobian(model)
    entries = {}
    for line in lines:
        if line.startswith("J["):
            lhs, rhs = line.split(" = ")
            entries[lhs] = parse_expression(rhs, names)
    assert set(entries) == {f"J[{r}, {q}]" for r in ("vx", "vy") for q in ("q1", "q2")}
    for i, r in enumerate(("vx", "vy")):
        for j, q in enumerate(("q1", "q2")):
            assert sp.expand(entries[f"J[{r}, {q}]"] - J[i, j]) == 0  # printed text round-trips


def test_jacobian_json(capsys):
    code, out, err = run(capsys, "jacobian", "planar2r", "--format", "json")
    assert code == 0 and err == ""
    data = json.loads(out)
    assert data["schema"] == "rankloci.jacobian/1"
    assert data["model"] == "planar2r"
    assert data["variables"] == ["q1", "q2"]
    assert data["rows"] == ["vx", "vy"]
    assert data["parameters"] == {"l1": 1.0, "l2": 1.0}
    assert data["notes"] == []  # a TOML model: nothing was snapped
    matrix = data["matrix"]
    assert len(matrix) == 2 and all(len(row) == 2 for row in matrix)
    model, names = _planar2r_names()
    J = geometric_jacobian(model)
    parsed = sp.Matrix([[parse_expression(e, names) for e in row] for row in matrix])
    assert (parsed - J).applyfunc(sp.expand) == sp.zeros(2, 2)


def test_jacobian_latex(capsys):
    code, out, err = run(capsys, "jacobian", "planar2r", "--format", "latex")
    assert code == 0 and err == ""
    lines = out.strip().splitlines()
    assert lines[0] == r"\begin{bmatrix}" and lines[-1] == r"\end{bmatrix}"
    body = lines[1:-1]
    assert len(body) == 2
    assert all(row.count("&") == 1 for row in body)
    assert body[0].endswith(r"\\") and not body[1].endswith(r"\\")
    assert r"\sin" in out and "l_{1}" in out


def test_jacobian_options(capsys, write_file):
    code, out, _ = run(capsys, "jacobian", "planar2r", "--numeric", "--format", "json")
    assert code == 0
    data = json.loads(out)
    assert data["parameters"] == {}
    assert not any("l1" in e or "l2" in e for row in data["matrix"] for e in row)

    code, out, _ = run(capsys, "jacobian", "puma560", "--task", "0,1,5", "--frame", "tool", "--point", "3",
                       "--format", "json")
    assert code == 0
    data = json.loads(out)
    assert data["rows"] == ["vx", "vy", "wz"] and len(data["matrix"]) == 3

    code, out, _ = run(capsys, "jacobian", "planar2r", "--augment", "q1 + q2", "--format", "json")
    assert code == 0
    data = json.loads(out)
    assert data["rows"] == ["vx", "vy", "q1 + q2"] and data["matrix"][2] == ["1", "1"]

    path = write_file("arm.toml", PLANAR)
    code, out, _ = run(capsys, "jacobian", str(path), "--format", "json")
    assert code == 0 and json.loads(out)["model"] == "arm"


def test_float_angle_in_a_file_prints_one_warning_line(capsys, write_file):
    path = write_file("arm.toml", PLANAR.replace('a = "l2"', 'a = "l2"\nalpha = 3.141592653589793'))
    code, out, err = run(capsys, "jacobian", str(path))
    assert code == 0 and out
    warning_lines = [line for line in err.splitlines() if line]
    assert len(warning_lines) == 1, err
    assert warning_lines[0].startswith("rankloci: warning: ")
    assert "joint 2" in warning_lines[0] and "'alpha'" in warning_lines[0] and "pi" in warning_lines[0]


# --- bad input: one line on stderr, exit code 2 ---------------------------------------------

def _bad_cases(tmp_path):
    malformed = tmp_path / "broken.toml"
    malformed.write_text(PLANAR.replace('a = "l2"', 'a = "pi//2"').replace('"arm"', '"broken"'), encoding="utf-8")
    bad_toml = tmp_path / "syntax.toml"
    bad_toml.write_text('name = "syntax"\n[[joint]\n', encoding="utf-8")
    latin1 = tmp_path / "latin.toml"
    latin1.write_bytes(b'name = "latin"\n# caf\xe9\n')
    return {
        "nonexistent-file": (["jacobian", str(tmp_path / "missing.toml")], "missing.toml: no such file"),
        "directory": (["jacobian", str(tmp_path)], "no such file"),
        "unknown-model": (["jacobian", "nosuchrobot"], "no built-in model or file 'nosuchrobot'"),
        "bad-task-name": (["jacobian", "planar2r", "--task", "sideways"], "argument --task"),
        "bad-task-row": (["jacobian", "planar2r", "--task", "0,9"], "task row 9"),
        "bad-frame-word": (["jacobian", "planar2r", "--frame", "world"], "argument --frame"),
        "bad-frame-index": (["jacobian", "planar2r", "--frame", "9"], "--frame 9: planar2r has no link frame 9"),
        "bad-point-index": (["jacobian", "planar2r", "--point", "-1"], "--point -1: planar2r has no link frame -1"),
        "negative-seed": (["locus", "planar2r", "--seed", "-1"], "argument --seed: '-1' is not an integer 0 or above"),
        "bad-augment-syntax": (["jacobian", "planar2r", "--augment", "q1 +"], "--augment: cannot parse 'q1 +'"),
        "bad-augment-name": (["jacobian", "planar2r", "--augment", "q3"], "unknown name 'q3'"),
        "bad-augment-code": (["jacobian", "planar2r", "--augment", "__import__('os').getcwd()"], "--augment"),
        "malformed-file": (["jacobian", str(malformed)],
                           "broken.toml: joint 2: field 'a': cannot parse 'pi//2': operator FloorDiv is not allowed"),
        "toml-syntax": (["jacobian", str(bad_toml)], "syntax.toml: invalid TOML"),
        "not-utf8": (["jacobian", str(latin1)], "latin.toml: not UTF-8 text"),
        "unknown-command": (["frobnicate"], "argument COMMAND"),
        "bad-format": (["jacobian", "planar2r", "--format", "xml"], "argument --format"),
        "missing-model": (["jacobian"], "required"),
        "unknown-option": (["models", "--colour"], "unrecognized arguments"),
    }


BAD_IDS = ["nonexistent-file", "directory", "unknown-model", "bad-task-name", "bad-task-row",
           "bad-frame-word", "bad-frame-index", "bad-point-index", "negative-seed", "bad-augment-syntax",
           "bad-augment-name", "bad-augment-code", "malformed-file", "toml-syntax", "not-utf8",
           "unknown-command", "bad-format", "missing-model", "unknown-option"]


@pytest.mark.parametrize("case", BAD_IDS)
def test_bad_input_gives_one_error_line_and_exit_2(capsys, tmp_path, case):
    argv, expected = _bad_cases(tmp_path)[case]
    code, out, err = run(capsys, *argv)
    assert_one_line_error(code, out, err)
    assert expected in err, err


def test_bad_case_ids_cover_every_case(tmp_path):
    assert sorted(BAD_IDS) == sorted(_bad_cases(tmp_path))


def test_a_bug_is_a_traceback_not_bad_input(monkeypatch):
    """Only bad input (a RanklociError or a usage error) is exit 2; any other error propagates."""
    import rankloci.cli.commands

    def broken(args):
        raise ValueError("a bug")

    monkeypatch.setitem(rankloci.cli.commands.COMMANDS, "models", broken)
    with pytest.raises(ValueError, match="a bug"):
        main(["models"])


def test_huge_exact_number_is_an_error_line_not_a_traceback(capsys, write_file):
    """A 5000-digit integer (more than Python prints by default) is refused by the expression
    parser, which caps the digits of an exact number: bad input, before anything is printed."""
    path = write_file("big.toml", 'name = "big"\nvariables = ["x"]\nmatrix = [["(10**40)**64 * (10**40)**64 * x"]]\n')
    code, out, err = run(capsys, "jacobian", str(path))
    assert_one_line_error(code, out, err)
    assert "big.toml: field 'matrix[0][0]': cannot parse " in err and "digits" in err, err


def test_main_leaves_the_warning_settings_as_it_found_them(capsys):
    import warnings

    before, filters = warnings.showwarning, list(warnings.filters)
    assert main(["models", "--format", "json"]) == 0
    assert warnings.showwarning is before
    assert warnings.filters == filters


def test_a_warning_is_one_line_on_stderr(capsys, monkeypatch):
    import warnings

    import rankloci.cli.commands

    def warns(args):
        warnings.warn("the matrix has a suspicious entry", UserWarning, stacklevel=1)
        return 0

    monkeypatch.setitem(rankloci.cli.commands.COMMANDS, "models", warns)
    code, out, err = run(capsys, "models")
    assert code == 0 and out == ""
    assert err == "rankloci: warning: the matrix has a suspicious entry\n"


def test_no_command_prints_help_and_exits_2(capsys):
    code, out, err = run(capsys)
    assert code == 2
    assert "examples:" in out


def _subcommands():
    return sorted(COMMANDS)


def test_help_lists_exactly_the_commands_main_runs(capsys):
    with pytest.raises(SystemExit):
        main(["--help"])
    listed = re.findall(r"^    (\w+)  ", capsys.readouterr().out, re.MULTILINE)
    assert sorted(listed) == _subcommands()


@pytest.mark.parametrize("command", [None, *_subcommands()])
def test_help_exits_0_with_examples(capsys, command):
    argv = ["--help"] if command is None else [command, "--help"]
    with pytest.raises(SystemExit) as info:
        main(argv)
    assert info.value.code == 0
    out, err = capsys.readouterr()
    assert "examples:" in out and err == ""


def test_subcommands_include_models_and_jacobian():
    assert {"models", "jacobian"} <= set(_subcommands())


# --- hostile model files run no code ---------------------------------------------------------

PAYLOADS = [
    "__import__('os').system('touch {marker}')",
    "__import__('pathlib').Path('{marker}').touch()",
    "open('{marker}', 'w').write('x')",
    "eval(\"open('{marker}', 'w')\")",
    "exec(\"open('{marker}', 'w')\")",
    "(lambda: open('{marker}', 'w'))()",
    "q1.__class__.__init__.__globals__['os'].system('touch {marker}')",
    "().__class__.__base__.__subclasses__()[0]('{marker}')",
    "[open('{marker}', 'w') for _ in (1,)]",
    "sympy.sympify(\"open('{marker}', 'w')\")",
    "Symbol('x').__reduce__()",
]


def _hostile_model(field: str, payload: str, *, literal: str | None = None) -> str:
    """A planar model with ``payload`` as a TOML string (or the raw TOML ``literal``) in ``field``."""
    s = json.dumps(payload) if literal is None else literal  # a JSON string is a TOML basic string
    text = {
        "a": PLANAR.replace('a = "l2"', f"a = {s}"),
        "alpha": PLANAR.replace('a = "l2"', f'a = "l2"\nalpha = {s}'),
        "d": PLANAR.replace('a = "l2"', f'a = "l2"\nd = {s}'),
        "theta": PLANAR.replace('a = "l2"', f'a = "l2"\ntheta = {s}'),
        "augment": PLANAR + f"[[augment]]\nexpr = {s}\n",
        "base": PLANAR + f"[base]\nxyz = [0, {s}, 0]\n",
        "tool": PLANAR + f"[tool]\nrpy = [{s}, 0, 0]\n",
        "parameter": PLANAR.replace("l2 = 0.5", f"l2 = {s}"),
        "limits": PLANAR.replace('a = "l2"', f'a = "l2"\nlimits = [0, {s}]'),
        "task": PLANAR.replace('task = "planar"', f"task = {s}"),
        "matrix": f'name = "arm"\nvariables = ["q1"]\nmatrix = [["q1", {s}]]\n',
    }[field]
    return text


HOSTILE_FIELDS = ["a", "alpha", "d", "theta", "augment", "base", "tool", "parameter", "limits", "task", "matrix"]


@pytest.mark.parametrize("field", HOSTILE_FIELDS)
def test_hostile_model_file_runs_no_code(capsys, tmp_path, field):
    marker = tmp_path / "PWNED_x"
    path = tmp_path / "arm.toml"
    for payload in PAYLOADS:
        text = _hostile_model(field, payload.format(marker=marker))
        with pytest.raises(ModelError):
            parse_model(text, file="arm.toml")
        path.write_text(text, encoding="utf-8")
        code, out, err = run(capsys, "jacobian", str(path))
        assert_one_line_error(code, out, err)
        assert err.startswith("rankloci: error: arm.toml: ")
        assert not marker.exists(), f"{field}: {payload}"
    # the template with a harmless value is a valid model, so the payloads reach the parser
    harmless = {"task": '"planar"', "parameter": "1", "limits": "1"}.get(field, '"1"')
    assert parse_model(_hostile_model(field, "", literal=harmless), file="arm.toml")


def test_payload_in_free_text_fields_is_only_text(capsys, tmp_path):
    marker = tmp_path / "PWNED_x"
    payload = json.dumps(PAYLOADS[0].format(marker=marker))
    text = PLANAR.replace('source = "test"', f"source = {payload}\ntitle = {payload}\nnotes = {payload}")
    model = parse_model(text, file="arm.toml")
    assert model.source == PAYLOADS[0].format(marker=marker)
    path = tmp_path / "arm.toml"
    path.write_text(text, encoding="utf-8")
    code, _, _ = run(capsys, "jacobian", str(path))
    assert code == 0
    assert not marker.exists()


def test_hostile_augment_on_command_line_runs_no_code(capsys, tmp_path):
    marker = tmp_path / "PWNED_x"
    for payload in PAYLOADS:
        code, out, err = run(capsys, "jacobian", "planar2r", "--augment", payload.format(marker=marker))
        assert_one_line_error(code, out, err)
        assert not marker.exists(), payload


# --- as a program ------------------------------------------------------------------------------

def test_python_m_rankloci_help():
    proc = subprocess.run([sys.executable, "-m", "rankloci", "--help"], capture_output=True, text=True,
                          timeout=60)
    assert proc.returncode == 0, proc.stderr
    assert "examples:" in proc.stdout and "jacobian" in proc.stdout


@pytest.mark.parametrize("argv", [["--help"], ["jacobian", "--help"], ["models", "--help"]])
def test_help_does_not_import_heavy_libraries(argv):
    """``-X importtime`` lists every module imported; --help must not pay for sympy or numpy."""
    proc = subprocess.run([sys.executable, "-X", "importtime", "-m", "rankloci", *argv],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    imported = {line.rsplit("|", 1)[-1].strip() for line in proc.stderr.splitlines() if line.startswith("import time:")}
    assert "rankloci.cli" in imported  # the listing works
    heavy = {m for m in imported if m.split(".")[0] in ("sympy", "numpy", "scipy", "networkx", "flint", "matplotlib")}
    assert not heavy, sorted(heavy)[:10]


def test_console_script_help_does_not_import_sympy():
    """The installed ``rankloci`` script itself (PYTHONPROFILEIMPORTTIME is ``-X importtime``)."""
    import os
    from pathlib import Path

    script = Path(sys.executable).with_name("rankloci")
    assert script.is_file(), f"{script}: the package is not installed with its console script"
    proc = subprocess.run([str(script), "--help"], capture_output=True, text=True, timeout=60,
                          env={**os.environ, "PYTHONPROFILEIMPORTTIME": "1"})
    assert proc.returncode == 0, proc.stderr
    assert "examples:" in proc.stdout
    imported = {line.rsplit("|", 1)[-1].strip() for line in proc.stderr.splitlines() if line.startswith("import time:")}
    assert "rankloci.cli" in imported
    assert not {m for m in imported if m.split(".")[0] == "sympy"}


def test_models_with_a_broken_builtin_file_is_one_error_line(capsys, tmp_path, monkeypatch):
    import rankloci.io

    (tmp_path / "good.toml").write_text(PLANAR.replace('"arm"', '"good"'), encoding="utf-8")
    (tmp_path / "broken.toml").write_text('name = "broken"\n[[joint]\n', encoding="utf-8")
    monkeypatch.setattr(rankloci.io, "models_dir", lambda: tmp_path)
    assert rankloci.io.builtin_models() == ["broken", "good"]
    code, out, err = run(capsys, "models")
    assert_one_line_error(code, out, err)
    code, out, err = run(capsys, "jacobian", "broken")
    assert_one_line_error(code, out, err)
    assert err.startswith("rankloci: error: broken.toml: invalid TOML")


def test_jacobian_notes_what_reading_a_urdf_changed(capsys, tmp_path):
    urdf = tmp_path / "two.urdf"
    urdf.write_text(
        '<robot name="two"><link name="a"/><link name="b"/><link name="c"/>'
        '<joint name="j1" type="revolute"><parent link="a"/><child link="b"/>'
        '<axis xyz="0 0 1"/></joint>'
        '<joint name="j2" type="revolute"><parent link="b"/><child link="c"/>'
        '<origin xyz="1 0 0" rpy="1.5708 0 0"/><axis xyz="0 0 1"/></joint></robot>')
    code, out, _ = run(capsys, "jacobian", str(urdf))
    assert code == 0
    assert "# note: reading the URDF snapped 1 rpy angle to an exact multiple of pi/12" in out
    code, out, _ = run(capsys, "jacobian", str(urdf), "--format", "json")
    assert json.loads(out)["notes"][0].startswith("reading the URDF snapped 1 rpy angle")
