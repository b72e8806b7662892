"""TOML model files: what they parse to, and the located error each malformed file gives."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from rankloci.errors import ModelError
from rankloci.io import builtin_models, load_model, models_dir
from rankloci.io.toml_model import MAX_FILE_BYTES, parse_model, read_model
from rankloci.kinematics import forward_kinematics, geometric_jacobian, trig_normal
from rankloci.model import MatrixModel, RobotModel
from rankloci.tolerances import RANK_RTOL

SEED = 7

ARM = """\
name = "arm"
title = "test arm"
source = "written for the tests"
convention = "dh"
task = "full"
frame = "base"

[parameters]
l1 = 0.4318
l2 = 0.25

[[joint]]
kind = "revolute"
a = "l1"
alpha = "pi/2"

[[joint]]
a = "l2"
d = 0

[[joint]]
kind = "prismatic"
alpha = "-pi/2"
"""

MATRIX = """\
name = "m"
variables = ["x", "y"]
matrix = [
  ["x", "k*y"],
  ["sin(x)", "cos(y)"],
  [1, 0.5],
]

[parameters]
k = 2
"""


def _edit(text: str, old: str, new: str) -> str:
    assert old in text, old
    return text.replace(old, new, 1)


# --- valid files -------------------------------------------------------------------------

def test_valid_robot_file():
    model = parse_model(ARM, file="arm.toml")
    assert isinstance(model, RobotModel)
    assert model.name == "arm" and model.dof == 3
    assert [j.kind for j in model.joints] == ["revolute", "revolute", "prismatic"]
    assert [v.name for v in model.variables] == ["q1", "q2", "q3"]
    assert all(v.is_real for v in model.variables)
    p = {s.name: v for s, v in model.parameters.items()}
    assert p == {"l1": sp.Rational(2159, 5000), "l2": sp.Rational(1, 4)}  # exact, not floats
    assert model.joints[0].dh.alpha == sp.pi / 2 and model.joints[2].dh.alpha == -sp.pi / 2
    assert model.task == (0, 1, 2, 3, 4, 5) and model.frame == "base" and model.convention == "dh"


def test_prismatic_joint_translates_along_its_z_axis():
    model = parse_model('name = "slider"\n[[joint]]\nkind = "prismatic"\nd = 2\n')
    (q1,) = model.variables
    assert forward_kinematics(model)[:3, 3] == sp.Matrix([0, 0, q1 + 2])
    assert geometric_jacobian(model) == sp.Matrix([0, 0, 1, 0, 0, 0])


def test_task_rows_frame_and_augment_fields():
    text = _edit(ARM, 'task = "full"\n', 'rows = [5, 0, 1]\n')
    text = _edit(text, 'frame = "base"', 'frame = "tool"')
    text += '[[augment]]\nexpr = "q1 + q3"\n[[augment]]\nname = "lock"\nexpr = "q2"\n'
    model = parse_model(text)
    q1, q2, q3 = model.variables
    assert model.task == (5, 0, 1)
    assert model.frame == "tool"
    assert model.augment == (("g1", q1 + q3), ("lock", q2))


def test_matrix_file_with_more_rows_than_columns():
    model = parse_model(MATRIX, file="m.toml")
    assert isinstance(model, MatrixModel)
    assert model.matrix.shape == (3, 2)
    x, y = model.variables
    (k,) = model.parameters
    assert model.matrix == sp.ImmutableMatrix([[x, k * y], [sp.sin(x), sp.cos(y)], [1, sp.Rational(1, 2)]])
    assert model.parameters[k] == 2


def test_a_number_named_like_a_top_level_key_is_a_parameter():
    """Only a key that its table cannot hold is taken for a misplaced top-level key."""
    model = parse_model(_edit(MATRIX, "k = 2", "k = 2\ntitle = 3"), file="m.toml")
    assert sorted(s.name for s in model.parameters) == ["k", "title"]
    assert model.title == "m"


ROOT = Path(__file__).resolve().parents[2]


def _documented_raw_matrix_example() -> str:
    """The TOML block under **Raw matrices.** in the user guide's page on input formats."""
    import re

    page = (ROOT / "docs" / "guide" / "input-formats.md").read_text(encoding="utf-8")
    section = page.split("**Raw matrices.**", 1)[1]
    return re.search(r"```toml\n(.*?)```", section, re.S).group(1)


@pytest.mark.parametrize("source", ["documented", "examples/my_matrix.toml"])
def test_the_raw_matrix_example_parses(source):
    """The documented example, and the example file that --help names, are the same matrix."""
    if source == "documented":
        text, file = _documented_raw_matrix_example(), "example.toml"
    else:
        text, file = (ROOT / source).read_text(encoding="utf-8"), Path(source).name
    assert "matrix = " in text
    model = parse_model(text, file=file)
    assert isinstance(model, MatrixModel)
    x, y = model.variables
    (k,) = model.parameters
    assert model.matrix == sp.ImmutableMatrix([[sp.cos(x), k * y], [sp.sin(x), 1], [0, y]])
    assert model.parameters[k] == 2


def test_same_text_gives_equal_models_and_a_change_does_not():
    a, b = parse_model(ARM), parse_model(ARM)
    assert a == b and hash(a) == hash(b)
    c = parse_model(_edit(ARM, "l2 = 0.25", "l2 = 0.26"))
    assert a != c


@pytest.mark.parametrize("name", builtin_models())
def test_builtin_model_files_load(name):
    model = load_model(name)
    assert model.name == name
    assert model.source.strip(), "a built-in model cites its source"
    assert model.path.endswith(f"{name}.toml")
    assert all(not v.atoms(sp.Float) for v in model.parameters.values())
    assert read_model(models_dir() / f"{name}.toml") == model


# --- dh vs mdh ------------------------------------------------------------------------------

PLANAR_DH = """\
name = "p2"
convention = "dh"
[parameters]
l1 = 0.7
l2 = 0.3
[[joint]]
a = "l1"
[[joint]]
a = "l2"
"""

PLANAR_MDH = """\
name = "p2"
convention = "mdh"
[parameters]
l1 = 0.7
l2 = 0.3
[tool]
xyz = ["l2", 0, 0]
[[joint]]
a = 0
[[joint]]
a = "l1"
"""


def _numeric_rank(J):
    s = np.linalg.svd(J, compute_uv=False)
    return int(np.linalg.matrix_rank(J, tol=RANK_RTOL * s[0]))


def test_planar2r_written_in_dh_and_mdh_is_the_same_arm():
    dh, mdh = parse_model(PLANAR_DH), parse_model(PLANAR_MDH)
    assert (dh.convention, mdh.convention) == ("dh", "mdh")
    assert dh.variables == mdh.variables
    # exact equality of the tool position (and orientation), with symbolic l1, l2
    diff = (forward_kinematics(dh) - forward_kinematics(mdh)).applyfunc(trig_normal)
    assert diff == sp.zeros(4, 4)
    assert forward_kinematics(dh)[0, 3] != forward_kinematics(dh)[1, 3]  # not trivially equal
    J_dh = geometric_jacobian(dh, task="full").subs(dh.parameters)
    J_mdh = geometric_jacobian(mdh, task="full").subs(mdh.parameters)
    f = sp.lambdify(dh.variables, [J_dh, J_mdh], "numpy")
    rng = np.random.default_rng(SEED)
    for q1 in rng.uniform(-math.pi, math.pi, 5):
        for q2 in (*rng.uniform(-math.pi, math.pi, 2), 0.0, math.pi):
            A, B = (np.asarray(J, float) for J in f(q1, q2))
            assert _numeric_rank(A) == _numeric_rank(B)
            assert _numeric_rank(A[:2]) == _numeric_rank(B[:2]) == (1 if q2 in (0.0, math.pi) else 2)


def test_puma560_rewritten_in_mdh_has_the_same_forward_kinematics():
    """Standard -> modified DH: joint i takes (a, alpha) of row i-1; the last row's go into the tool."""
    puma = load_model("puma560")
    lines = ['name = "puma560"\nconvention = "mdh"\nsource = "test"\n[parameters]']
    lines += [f"{s.name} = {float(v)!r}" for s, v in puma.parameters.items()]
    last = puma.joints[-1].dh
    lines += [f'[tool]\nxyz = ["{last.a}", 0, 0]\nrpy = ["{last.alpha}", 0, 0]']
    prev_a, prev_alpha = 0, 0
    for joint in puma.joints:
        dh = joint.dh
        lines += [f'[[joint]]\na = "{prev_a}"\nalpha = "{prev_alpha}"\nd = "{dh.d}"\ntheta = "{dh.theta}"']
        prev_a, prev_alpha = dh.a, dh.alpha
    mdh = parse_model("\n".join(lines) + "\n")
    diff = (forward_kinematics(puma) - forward_kinematics(mdh)).applyfunc(trig_normal)
    assert diff == sp.zeros(4, 4)


# --- malformed files: "<file>: joint <i>: field '<f>': <message>" ------------------------------

BAD = [
    # id, file name, text, (joint, field), exact message prefix
    ("bad-toml-syntax", "arm.toml", _edit(ARM, "[[joint]]\nkind", "[[joint]\nkind"), (None, None),
     "arm.toml: invalid TOML: "),
    ("unknown-top-level-key", "arm.toml", "colour = 'red'\n" + ARM, (None, None),
     "arm.toml: unknown top-level key(s) ['colour']; allowed: "),
    ("unknown-joint-key", "arm.toml", _edit(ARM, 'a = "l2"', 'a = "l2"\nlength = 3'), (2, None),
     "arm.toml: joint 2: unknown key(s) ['length']; allowed: "),
    ("bad-kind", "arm.toml", _edit(ARM, '"prismatic"', '"spherical"'), (3, "kind"),
     "arm.toml: joint 3: field 'kind': 'spherical' is not 'revolute' or 'prismatic'"),
    ("name-stem-mismatch", "other.toml", ARM, (None, "name"),
     "other.toml: field 'name': name 'arm' does not match the file stem 'other'"),
    ("bad-name", "arm.toml", _edit(ARM, 'name = "arm"', 'name = "Arm 1"'), (None, "name"),
     "arm.toml: field 'name': 'Arm 1' is not a valid model name"),
    ("name-with-newline", "", _edit(ARM, 'name = "arm"', 'name = "arm\\n"'), (None, "name"),
     "field 'name': 'arm\\n' is not a valid model name"),
    ("unknown-symbol", "arm.toml", _edit(ARM, 'a = "l2"', 'a = "l3"'), (2, "a"),
     "arm.toml: joint 2: field 'a': cannot parse 'l3': unknown name 'l3'"),
    ("joint-variable-in-dh-field", "arm.toml", _edit(ARM, 'a = "l2"', 'a = "q1"'), (2, "a"),
     "arm.toml: joint 2: field 'a': cannot parse 'q1': unknown name 'q1'"),
    ("floor-division", "arm.toml", _edit(ARM, '"-pi/2"', '"pi//2"'), (3, "alpha"),
     "arm.toml: joint 3: field 'alpha': cannot parse 'pi//2': operator FloorDiv is not allowed"),
    ("boolean-field", "arm.toml", _edit(ARM, "d = 0", "d = true"), (2, "d"),
     "arm.toml: joint 2: field 'd': expected a number or an expression string, got True"),
    ("non-number-parameter", "arm.toml", _edit(ARM, "l2 = 0.25", 'l2 = "abc"'), (None, "parameters.l2"),
     "arm.toml: field 'parameters.l2': value 'abc' is not a number"),
    ("expression-parameter", "arm.toml", _edit(ARM, "l2 = 0.25", 'l2 = "pi/2"'), (None, "parameters.l2"),
     "arm.toml: field 'parameters.l2': value 'pi/2' is not a number"),
    ("nan-parameter", "arm.toml", _edit(ARM, "l2 = 0.25", "l2 = nan"), (None, "parameters.l2"),
     "arm.toml: field 'parameters.l2': number is not finite"),
    ("reserved-parameter-q1", "arm.toml", _edit(ARM, "l2 = 0.25", "l2 = 0.25\nq1 = 1"), (None, "parameters.q1"),
     "arm.toml: field 'parameters.q1': 'q1' is not a usable parameter name"),
    ("reserved-parameter-sin", "arm.toml", _edit(ARM, "l2 = 0.25", "l2 = 0.25\nsin = 1"), (None, "parameters.sin"),
     "arm.toml: field 'parameters.sin': 'sin' is not a usable parameter name"),
    ("reserved-parameter-pi", "arm.toml", _edit(ARM, "l2 = 0.25", "l2 = 0.25\npi = 3"), (None, "parameters.pi"),
     "arm.toml: field 'parameters.pi': 'pi' is not a usable parameter name"),
    ("bad-task", "arm.toml", _edit(ARM, 'task = "full"', 'task = "sideways"'), (None, "task"),
     "arm.toml: field 'task': task 'sideways' is not one of ['full', 'orientation', 'planar', 'position']"),
    ("bad-rows-out-of-range", "arm.toml", _edit(ARM, 'task = "full"', "rows = [0, 6]"), (None, "rows"),
     "arm.toml: field 'rows': task row 6 is not an integer in 0..5"),
    ("bad-rows-repeat", "arm.toml", _edit(ARM, 'task = "full"', "rows = [1, 1]"), (None, "rows"),
     "arm.toml: field 'rows': task rows [1, 1] repeat a row"),
    ("bad-rows-empty", "arm.toml", _edit(ARM, 'task = "full"', "rows = []"), (None, "rows"),
     "arm.toml: field 'rows': task row list is empty"),
    ("bad-rows-type", "arm.toml", _edit(ARM, 'task = "full"', "rows = 3"), (None, "rows"),
     "arm.toml: field 'rows': 3 is not a task name or a list of rows"),
    ("task-and-rows", "arm.toml", _edit(ARM, 'task = "full"', 'task = "full"\nrows = [0]'), (None, "rows"),
     "arm.toml: field 'rows': give either 'task' or 'rows', not both"),
    ("bad-frame", "arm.toml", _edit(ARM, 'frame = "base"', 'frame = "middle"'), (None, "frame"),
     "arm.toml: field 'frame': 'middle' is not one of ['base', 'tool']"),
    ("bad-convention", "arm.toml", _edit(ARM, 'convention = "dh"', 'convention = "craig"'), (None, "convention"),
     "arm.toml: field 'convention': 'craig' is not one of ['dh', 'mdh']"),
    ("nan-angle", "arm.toml", _edit(ARM, 'a = "l2"', 'a = "l2"\ntheta = nan'), (2, "theta"),
     "arm.toml: joint 2: field 'theta': cannot parse 'nan': number is not finite"),
    ("inf-rpy", "arm.toml", ARM + "[base]\nrpy = [0, -inf, 0]\n", (None, "base.rpy"),
     "arm.toml: field 'base.rpy': cannot parse '-inf': number is not finite"),
    ("bad-limits", "arm.toml", _edit(ARM, 'a = "l2"', 'a = "l2"\nlimits = [1, -1]'), (2, "limits"),
     "arm.toml: joint 2: field 'limits': must be [lower, upper] with lower < upper"),
    ("symbolic-limits", "arm.toml", _edit(ARM, 'a = "l2"', 'a = "l2"\nlimits = ["l1", 1]'),
     (2, "limits"), "arm.toml: joint 2: field 'limits': cannot parse 'l1': unknown name 'l1' "
     "(a limit is a number or a constant such as '-8*pi/9')"),
    ("bad-base-rpy", "arm.toml", ARM + "[base]\nrpy = [0, 1]\n", (None, "base.rpy"),
     "arm.toml: field 'base.rpy': must be a list of three numbers or expressions"),
    ("bad-tool-expression", "arm.toml", ARM + '[tool]\nxyz = [0, 0, "l1 +"]\n', (None, "tool.xyz"),
     "arm.toml: field 'tool.xyz': cannot parse 'l1 +': invalid syntax"),
    ("empty-joint-list", "arm.toml", 'name = "arm"\njoint = []\n', (None, "joint"),
     "arm.toml: field 'joint': a robot model needs at least one [[joint]] table"),
    ("no-joints-no-matrix", "arm.toml", 'name = "arm"\n', (None, "joint"),
     "arm.toml: field 'joint': a robot model needs at least one [[joint]] table"),
    ("joint-not-a-table", "arm.toml", 'name = "arm"\njoint = [1]\n', (1, None),
     "arm.toml: joint 1: must be a table"),
    ("augment-without-expr", "arm.toml", ARM + '[[augment]]\nname = "lock"\n', (None, "augment"),
     "arm.toml: field 'augment': entry 1 needs an 'expr'"),
    ("augment-unknown-name", "arm.toml", ARM + '[[augment]]\nexpr = "q4"\n', (None, "augment[1].expr"),
     "arm.toml: field 'augment[1].expr': cannot parse 'q4': unknown name 'q4'"),
    ("matrix-ragged-rows", "m.toml", _edit(MATRIX, "[1, 0.5]", "[1]"), (None, "matrix"),
     "m.toml: field 'matrix': rows have different lengths [2, 2, 1]"),
    ("matrix-unknown-variable", "m.toml", _edit(MATRIX, '"cos(y)"', '"cos(z)"'), (None, "matrix[1][1]"),
     "m.toml: field 'matrix[1][1]': cannot parse 'cos(z)': unknown name 'z'"),
    ("matrix-empty", "m.toml", 'name = "m"\nvariables = ["x"]\nmatrix = []\n', (None, "matrix"),
     "m.toml: field 'matrix': must be a non-empty list of rows"),
    ("matrix-variable-is-parameter", "m.toml", _edit(MATRIX, "k = 2", "x = 2"), (None, "variables"),
     "m.toml: field 'variables': ['x'] are both variables and parameters"),
    ("matrix-repeated-variable", "m.toml", _edit(MATRIX, '["x", "y"]', '["x", "x"]'), (None, "variables"),
     "m.toml: field 'variables': variable names repeat"),
    ("matrix-reserved-variable", "m.toml", _edit(MATRIX, '["x", "y"]', '["x", "pi"]'), (None, "variables"),
     "m.toml: field 'variables': 'pi' is not a usable variable name"),
    ("matrix-robot-key", "m.toml", "frame = 'tool'\n" + MATRIX, (None, None),
     "m.toml: unknown top-level key(s) ['frame']"),
    ("too-many-joints", "arm.toml", 'name = "arm"\n' + "[[joint]]\n" * 65, (None, "joint"),
     "arm.toml: field 'joint': more than 64 joints"),
    ("matrix-below-parameters", "m.toml",
     'name = "m"\nvariables = ["x"]\n[parameters]\nk = 2.0\nmatrix = [["k*x"]]\n', (None, None),
     "m.toml: 'matrix' is inside [parameters]; top-level keys must come before the first [table]"),
    ("variables-below-parameters", "m.toml",
     'name = "m"\nmatrix = [["k*x"]]\n[parameters]\nk = 2.0\nvariables = ["x"]\n', (None, None),
     "m.toml: 'variables' is inside [parameters]; top-level keys must come before"),
    ("task-below-the-last-joint", "arm.toml", _edit(ARM, 'task = "full"\n', "") + 'task = "planar"\n',
     (None, None), "arm.toml: 'task' is inside [[joint]] number 3; top-level keys must come before"),
    ("source-below-base", "arm.toml",
     _edit(ARM, 'source = "written for the tests"\n', "") + '[base]\nxyz = [0, 0, 1]\nsource = "x"\n',
     (None, None), "arm.toml: 'source' is inside [base]; top-level keys must come before"),
    ("title-below-the-only-augment", "m.toml", MATRIX + '[[augment]]\nexpr = "x"\ntitle = "m"\n',
     (None, None), "m.toml: 'title' is inside [[augment]]; top-level keys must come before"),
]


@pytest.mark.parametrize("file, text, where, prefix", [c[1:] for c in BAD], ids=[c[0] for c in BAD])
def test_malformed_text_names_file_joint_and_field(file, text, where, prefix):
    with pytest.raises(ModelError) as info:
        parse_model(text, file=file)
    err = info.value
    assert str(err).startswith(prefix), str(err)
    assert "\n" not in str(err).replace("\\n", "")  # one line, for the CLI
    assert (err.joint, err.field) == where
    assert err.file == (file or None)


@pytest.mark.parametrize("file, text, where, prefix", [c[1:] for c in BAD if c[1]], ids=[c[0] for c in BAD if c[1]])
def test_malformed_file_names_the_file_not_its_directory(tmp_path, file, text, where, prefix):
    path = tmp_path / file
    path.write_text(text, encoding="utf-8")
    with pytest.raises(ModelError) as info:
        read_model(path)
    assert str(info.value).startswith(prefix), str(info.value)
    assert str(tmp_path) not in str(info.value)


def test_file_not_utf8(write_file):
    path = write_file("arm.toml", b'name = "arm"\n# caf\xe9\n[[joint]]\n')
    with pytest.raises(ModelError) as info:
        read_model(path)
    assert str(info.value) == "arm.toml: not UTF-8 text"
    assert info.value.file == "arm.toml"


def test_file_too_large(write_file):
    path = write_file("big.toml", "#" * (MAX_FILE_BYTES + 1))
    with pytest.raises(ModelError, match=r"^big\.toml: (cannot read: )?file larger than"):
        read_model(path)
    with pytest.raises(ModelError, match="file larger than"):
        parse_model("#" * (MAX_FILE_BYTES + 1))


def test_builtin_models_need_a_source(tmp_path, write_file):
    path = write_file("arm.toml", _edit(ARM, 'source = "written for the tests"\n', ""))
    assert read_model(path).source == ""
    with pytest.raises(ModelError, match=r"^arm\.toml: field 'source': a built-in model needs"):
        read_model(path, require_source=True)


def test_deeply_nested_toml_is_a_model_error():
    text = 'name = "arm"\nx = ' + "[" * 5000 + "]" * 5000 + "\n"
    with pytest.raises(ModelError):
        parse_model(text)


def test_load_model_resolves_paths_and_names(tmp_path, write_file):
    path = write_file("arm.toml", ARM)
    assert load_model(str(path)).name == "arm"
    with pytest.raises(ModelError, match=r"no such file"):
        load_model(str(tmp_path / "missing.toml"))
    with pytest.raises(ModelError, match=r"^no built-in model or file 'nosuch'; built-in models: .*puma560"):
        load_model("nosuch")
    other = write_file("arm.txt", ARM)
    with pytest.raises(ModelError, match=r"^arm\.txt: unknown file type"):
        load_model(str(other))


def test_joint_limits_are_numbers_or_constant_expressions():
    text = _edit(ARM, 'a = "l2"', 'a = "l2"\nlimits = ["-8*pi/9", 2.5]')
    m = parse_model(text, file="arm.toml")
    assert m.joints[1].limits == (pytest.approx(-8 * math.pi / 9, abs=1e-15), 2.5)
    assert m.joints[0].limits is None and m.joints[2].limits is None
