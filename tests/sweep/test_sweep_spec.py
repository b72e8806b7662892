"""The sweep spec: TOML read as data, every problem one error naming the file and the key."""

from __future__ import annotations

from pathlib import Path

import pytest

from rankloci.sweep.cases import expand
from rankloci.sweep.spec import MAX_CASES, SpecError, parse_spec, read_spec


def test_lists_ranges_and_expressions_become_exact_values():
    spec = parse_spec('models = ["planar3r"]\n[grid.parameters]\n'
                      'l2 = [0.5, 2, "3/2", "pi/4"]\n'
                      'l3 = { start = 0.25, stop = 1, step = 0.25 }\n', file="s.toml")
    (name2, v2), (name3, v3) = spec.entries[0].grid.parameters
    assert name2 == "l2" and [str(v) for _, v in v2] == ["1/2", "2", "3/2", "pi/4"]
    assert name3 == "l3" and [t for t, _ in v3] == ["0.25", "0.5", "0.75", "1"]
    assert spec.entries[0].grid.size == 16


def test_defaults_are_those_of_rankloci_locus_with_parameters_substituted():
    spec = parse_spec('models = ["planar2r"]\n')
    assert (spec.method, spec.task, spec.seed, spec.verify, spec.numeric) == (
        None, None, 0, True, True)
    assert spec.timeout == 600 and spec.memory == 8192


def test_numeric_is_the_key_and_numeric_parameters_its_old_name():
    """One name, as on the command line (--numeric); the old key still works, with a warning
    the command line shows (a FutureWarning: the spec is the user's file)."""
    assert parse_spec('models = ["planar2r"]\nnumeric = false\n').numeric is False
    with pytest.warns(FutureWarning, match="s.toml: numeric_parameters is deprecated; use numeric"):
        old = parse_spec('models = ["planar2r"]\nnumeric_parameters = false\n', file="s.toml")
    assert old == parse_spec('models = ["planar2r"]\nnumeric = false\n', file="s.toml")
    with pytest.raises(SpecError, match="give numeric only"):
        parse_spec('models = ["planar2r"]\nnumeric = true\nnumeric_parameters = true\n')


@pytest.mark.parametrize("text, key", [
    ('models = ["planar2r"]\nfoo = 1\n', "foo"),
    ('models = ["planar2r"]\nmethod = "newton"\n', "method"),
    ('models = ["planar2r"]\ntimeout = -1\n', "timeout"),
    ('models = ["planar2r"]\ntimeout = nan\n', "timeout"),
    ('models = ["planar2r"]\nseed = 1.5\n', "seed"),
    ('models = ["planar2r"]\ntask = "sideways"\n', "task"),
    ('models = ["planar2r"]\n[grid.parameters]\nl1 = []\n', "grid.parameters.l1"),
    ('models = ["planar2r"]\n[grid.parameters]\nl1 = [1, 1.0]\n', "grid.parameters.l1"),
    ('models = ["planar2r"]\n[grid.parameters]\nl1 = { start = 0, stop = 1 }\n',
     "grid.parameters.l1"),
    ('models = ["planar2r"]\n[grid.parameters]\nl1 = { start = 0, stop = 1, step = -1 }\n',
     "grid.parameters.l1.step"),
    ('models = ["planar2r"]\n[grid.parameters]\nl1 = ["__import__(\'os\').system(\'x\')"]\n',
     "grid.parameters.l1[0]"),
    ('models = ["planar2r"]\n[grid.parameters]\nl1 = ["q1 + 1"]\n', "grid.parameters.l1[0]"),
    ('models = ["planar2r"]\n[grid]\naugment = [3]\n', "grid.augment[0]"),
    ('[[model]]\nname = "planar2r"\nchains = "all"\n', "model[0]"),
    ('[[model]]\nname = "planar2r"\npath = "x.toml"\n', "model[0]"),
    ('[[model]]\npath = "missing.urdf"\n', "model[0].path"),
    ('[[model]]\nname = "planar2r"\nmin_joints = 2\n', "model[0].min_joints"),
    ("models = 3\n", "models"),
    ("", "models"),
])
def test_a_bad_spec_names_the_file_and_the_key(text, key):
    with pytest.raises(SpecError) as err:
        parse_spec(text, file="s.toml")
    assert err.value.file == "s.toml" and err.value.field == key
    assert str(err.value).startswith(f"s.toml: field {key!r}: ")


def test_invalid_toml_is_one_error():
    with pytest.raises(SpecError, match="invalid TOML"):
        parse_spec("models = [", file="s.toml")


@pytest.mark.parametrize("text, match", [
    ('models = ["planar9r"]\n', "no built-in model 'planar9r'"),
    ('models = ["planar2r"]\n[grid.parameters]\nd9 = [1, 2]\n', "no parameter 'd9'"),
    ('models = ["planar2r"]\n[grid]\naugment = ["lock(q7)"]\n', "lock"),
    ('models = ["planar2r"]\n[grid.parameters]\nl1 = { start = 1, stop = 2, num = 400 }\n'
     'l2 = { start = 1, stop = 2, num = 400 }\n', f"more than {MAX_CASES} cases"),
])
def test_models_and_grids_are_checked_before_anything_runs(text, match):
    with pytest.raises(SpecError, match=match):
        expand(parse_spec(text, file="s.toml"))


@pytest.mark.parametrize("payload", [
    "__import__('os').system('touch {marker}')",
    "open('{marker}', 'w').write('x')",
    "(lambda: open('{marker}', 'w'))()",
    "().__class__.__base__.__subclasses__()[0]('{marker}')",
])
@pytest.mark.parametrize("where", ["value", "augment"])
def test_expressions_in_a_spec_run_no_code(tmp_path, payload, where):
    marker = tmp_path / "marker"
    text = payload.format(marker=marker).replace("'", "\\u0027")
    body = (f'[grid.parameters]\nl1 = ["{text}"]\n' if where == "value"
            else f'[grid]\naugment = ["{text}"]\n')
    with pytest.raises(SpecError):
        expand(parse_spec('models = ["planar2r"]\n' + body, file="s.toml"))
    assert not marker.exists()


def test_a_missing_spec_file_is_one_error(tmp_path):
    from rankloci.sweep.spec import read_spec

    with pytest.raises(SpecError, match="nope.toml: cannot read"):
        read_spec(tmp_path / "nope.toml")


EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "sweeps"


@pytest.mark.parametrize("name, cases", [
    ("robots.toml", ["planar3r", "planar2r_long.toml", "scara.toml", "my_arm.toml",
                     "arm.urdf:base->l_fore", "arm.urdf:base->r_fore"]),
    ("designs.toml", [f"planar3r l2={a} l3={b}{c}" for a in ("0.5", "1") for b in
                      ("0.5", "1", "1.5") for c in ("", " + q1 + q2 + q3")]),
    ("augment.toml", ["planar4r", "planar4r + q1 + q2 + q3 + q4", "planar4r + lock(q2)",
                      "planar4r + lock(q1), lock(q4)"]),
])
def test_the_shipped_example_specs_read_as_documented(name, cases):

    got, _, skipped = expand(read_spec(EXAMPLES / name))
    assert [c.label for c in got] == cases and skipped == []
    assert all(not c.problem for c in got)


ROOT = EXAMPLES.parents[1]


@pytest.mark.parametrize("doc", ["README.md", "docs/guide/sweeps.md"])
def test_the_sweep_files_the_documentation_names_are_shipped(doc):
    import re

    named = set(re.findall(r"examples/sweeps/[\w./-]*\w", (ROOT / doc).read_text()))
    assert named and all((ROOT / p).exists() for p in named), named


def test_the_guide_shows_the_robot_collection_spec_as_shipped():
    import tomllib

    guide = (ROOT / "docs" / "guide" / "sweeps.md").read_text()
    block = guide.split("`robots.toml`, with the keys", 1)[1].split("```toml\n", 1)[1]
    shown = tomllib.loads(block.split("```", 1)[0])
    assert shown == tomllib.loads((EXAMPLES / "robots.toml").read_text())
    for name in ("arms", "my_arm.toml", "robots/arm.urdf"):  # what its entries name
        assert (EXAMPLES / name).exists()
