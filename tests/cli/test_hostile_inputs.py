"""Hostile and extreme input, command by command: one line on stderr and exit 2, never a traceback.

Each case writes its files into a fresh folder, runs ``main([...])`` and checks the exit code,
that stderr names the reason, that no traceback escaped and that nothing was written beside the
input files.  Limits are kept small so that each case takes well under a second of algebra.

At the end: the JSON that ``jacobian`` and ``locus`` print for the built-in models is strict
JSON (no NaN or Infinity, which Python's ``json`` would write and other parsers refuse).
"""

from __future__ import annotations

import json

import pytest

from rankloci.cli import main

PLANAR = """name = "{name}"
convention = "dh"
task = "planar"
[parameters]
l1 = {l1}
l2 = 1.0
[[joint]]
a = "{a}"
[[joint]]
a = "l2"
"""


def _planar(name, a="l1", l1="1.0"):
    return PLANAR.format(name=name, a=a, l1=l1)


def _raw(name, matrix, variables=("x",)):
    rows = ", ".join("[" + ", ".join(json.dumps(e) for e in row) + "]" for row in matrix)
    return f'name = "{name}"\nvariables = {json.dumps(list(variables))}\nmatrix = [{rows}]\n'


def _locus_file(equations=("sin(q2)",), rank_drop=1, raw=None):
    if raw is not None:
        return raw
    return json.dumps({"schema": "rankloci.locus/1", "model": "planar2r",
                       "variables": ["q1", "q2"],
                       "components": [{"equations": list(equations), "rank_drop": rank_drop}]})


# (case id, files {name: text}, argv, expected exit code, text stderr must contain)
CASES = [
    ("exp-tower", {"m.toml": _planar("m", a="exp(exp(exp(100)))")},
     ["jacobian", "m.toml"], 2, "larger than"),
    ("imaginary-length", {"m.toml": _planar("m", a="sqrt(-1)")},
     ["jacobian", "m.toml"], 2, "not a real number"),
    ("fullwidth-name", {"m.toml": _planar("m", a="\uff4c1")},
     ["jacobian", "m.toml"], 2, "non-ASCII"),
    ("huge-integer-parameter", {"m.toml": _planar("m", l1="1" + "0" * 4000)},
     ["locus", "m.toml", "--numeric-parameters", "--quiet"], 2, "40 digits"),
    ("60-digit-integer-parameter", {"m.toml": _planar("m", l1="1" + "0" * 60)},
     ["jacobian", "m.toml"], 2, "40 digits"),
    ("float-parameter-near-overflow", {"m.toml": _planar("m", l1="1.7e308")},
     ["locus", "m.toml", "--numeric-parameters", "--quiet"], 2, "magnitude"),
    ("negative-timeout", {}, ["locus", "planar2r", "--timeout", "-5"], 2, "--timeout"),
    ("nan-timeout", {}, ["locus", "planar2r", "--timeout", "nan"], 2, "--timeout"),
    ("nan-timeout-check", {}, ["check", "planar2r", "--timeout", "nan"], 2, "--timeout"),
    ("negative-memory", {}, ["locus", "planar2r", "--memory", "-1"], 2, "--memory"),
    ("angle-multiple-augment", {}, ["locus", "planar2r", "--augment", "cos(1000*q1)", "--quiet"],
     2, "multiple of q1"),
    ("angle-multiple-raw", {"r.toml": _raw("r", [["cos(1000*x)"]])},
     ["locus", "r.toml", "--quiet"], 2, "multiple of x"),
    ("row-of-30-angles", {"r.toml": _raw("r", [[f"cos(x{i})" for i in range(30)]],
                                         [f"x{i}" for i in range(30)])},
     ["locus", "r.toml", "--quiet"], 2, "too large"),
    ("imaginary-equation-in-locus-file", {"l.json": _locus_file(["sqrt(-1)*sin(q2)"])},
     ["check", "planar2r", "--locus", "l.json", "--quiet", "--samples", "2"], 2, "not a real"),
    ("negative-rank-drop", {"l.json": _locus_file(rank_drop=-5)},
     ["check", "planar2r", "--locus", "l.json", "--quiet", "--samples", "2"], 2, "rank_drop"),
    ("huge-rank-drop", {"l.json": _locus_file(rank_drop=10 ** 30)},
     ["check", "planar2r", "--locus", "l.json", "--quiet", "--samples", "2"], 2, "rank_drop"),
    ("boolean-rank-drop", {"l.json": _locus_file(rank_drop=True)},
     ["check", "planar2r", "--locus", "l.json", "--quiet", "--samples", "2"], 2, "rank_drop"),
    ("locus-file-with-5000-components",
     {"l.json": _locus_file(raw=json.dumps({
         "schema": "rankloci.locus/2", "model": "planar2r", "variables": ["q1", "q2"],
         "components": [{"equations": ["sin(q2)"]}] * 5000}))},
     ["check", "planar2r", "--locus", "l.json", "--quiet", "--samples", "2"], 2,
     "more than 1000 components"),
    ("deeply-nested-locus-file", {"l.json": _locus_file(raw="[" * 100000)},
     ["check", "planar2r", "--locus", "l.json", "--quiet", "--samples", "2"], 2, "l.json"),
    ("matrix-below-parameters", {"r.toml": 'variables = ["x"]\n[parameters]\nk = 2.0\n'
                                           'matrix = [["k*x"]]\n'},
     ["jacobian", "r.toml"], 2, "r.toml: 'matrix' is inside [parameters]; top-level keys"),
    ("tip-on-a-toml-model", {"m.toml": _planar("m")}, ["jacobian", "m.toml", "--tip", "l2"],
     2, "--tip applies to URDF files only; 'm.toml' is not a .urdf file"),
    ("base-link-on-a-builtin-model", {}, ["locus", "planar2r", "--base-link", "base", "--quiet"],
     2, "--base-link applies to URDF files only; 'planar2r' is a built-in model"),
    ("chain-options-on-a-report", {"m.toml": _planar("m")},
     ["report", "m.toml", "--base-link", "a", "--tip", "b", "-o", "out", "--quiet"],
     2, "--base-link and --tip apply to URDF files only"),
    ("chain-options-on-all", {}, ["report", "all", "--tip", "b", "-o", "out", "--quiet"],
     2, "'all' is the built-in models"),
    ("non-polynomial-entry-locus", {"r.toml": _raw("r", [["tan(x)"]])},
     ["locus", "r.toml", "--quiet"], 2, "r.toml: entry tan(x) is not a polynomial"),
    ("non-polynomial-entry-check", {"r.toml": _raw("r", [["tan(x)"]])},
     ["check", "r.toml", "--quiet", "--samples", "2"], 2, "r.toml: entry tan(x) is not a"),
    ("non-polynomial-entry-report", {"r.toml": _raw("r", [["tan(x)"]])},
     ["report", "r.toml", "-o", "out", "--format", "md", "--quiet"], 2,
     "r.toml: entry tan(x) is not a polynomial"),
    ("jacobian-past-its-time-limit",
     {"m.toml": 'name = "m"\nconvention = "dh"\n' + "".join(
         f'[[joint]]\na = 0.1\nalpha = "{"pi/2" if k % 2 else "-pi/2"}"\nd = 0.2\n'
         for k in range(20))},
     ["jacobian", "m.toml", "--timeout", "1"], 1, "did not finish within 1 s"),
    ("urdf-chain-of-600-joints",
     {"c.urdf": "<robot name='c'>" + "".join(f"<link name='l{k}'/>" for k in range(601))
      + "".join(f"<joint name='j{k}' type='fixed'><parent link='l{k}'/>"
                f"<child link='l{k + 1}'/></joint>" for k in range(599))
      + "<joint name='a' type='revolute'><parent link='l599'/><child link='l600'/>"
        "<axis xyz='0 0 1'/><limit lower='-1' upper='1' effort='1' velocity='1'/></joint>"
      + "</robot>"},
     ["jacobian", "c.urdf"], 2, "more than 500"),
    ("report-into-a-regular-file", {"afile": "not a folder"},
     ["report", "planar2r", "-o", "afile/sub", "--format", "md", "--quiet"], 2,
     "is not a directory"),
    ("tree-onto-a-directory", {"D.json/keep": "x"},
     ["locus", "planar2r", "--tree", "D.json", "--quiet"], 2, "is a directory"),
    ("non-polynomial-entry-given-as-a-path", {"r.toml": _raw("r", [["x", "1/x"]], ["x"])},
     ["locus", "./r.toml", "--quiet"], 2, "r.toml: entry"),
]


@pytest.mark.parametrize("case, files, argv, code, reason", CASES, ids=[c[0] for c in CASES])
def test_hostile_input_is_refused_in_one_line(tmp_path, monkeypatch, capsys, case, files, argv,
                                              code, reason):
    for name, text in files.items():
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_text(text, encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    got = main(argv)
    err = capsys.readouterr().err
    assert "Traceback" not in err
    assert got == code, err
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1, err
    assert reason in lines[0], lines[0]
    assert lines[0].startswith("rankloci: error: "), lines[0]
    written = sorted(str(p.relative_to(tmp_path)) for p in tmp_path.rglob("*") if p.is_file())
    assert written == sorted(files), "something was written"


def test_flat_sum_of_many_terms_is_accepted(tmp_path, monkeypatch, capsys):
    """A 52-term sum is flat, not nested: only nesting depth is limited."""
    sum52 = " + ".join(f"{k}*x" for k in range(1, 53))
    (tmp_path / "r.toml").write_text(_raw("r", [[sum52]]), encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    assert main(["jacobian", "r.toml"]) == 0
    assert "1378*x" in capsys.readouterr().out      # 1 + 2 + ... + 52 = 1378


# --- JSON output --------------------------------------------------------------------------------

def _strict_json(text):
    """``json.loads`` that refuses NaN, Infinity and -Infinity (which are not JSON)."""
    def refuse(constant):
        raise ValueError(f"{constant} in the JSON output")

    return json.loads(text, parse_constant=refuse)


def test_strict_json_refuses_what_python_would_write():
    with pytest.raises(ValueError, match="NaN"):
        _strict_json(json.dumps({"x": float("nan")}))
    with pytest.raises(ValueError, match="Infinity"):
        _strict_json(json.dumps([1.0, -float("inf")]))


_SLOW_LOCI = {"pa10", "ssrms", "ssrms_lock3", "mobile10"}


def _builtin_models():
    from rankloci.io import builtin_models

    return builtin_models()


@pytest.mark.parametrize("name", _builtin_models())
def test_jacobian_json_of_builtin_models_is_strict_json(name, capsys):
    assert main(["jacobian", name, "--format", "json"]) == 0
    data = _strict_json(capsys.readouterr().out)
    assert data["model"] == name and data["matrix"]


@pytest.mark.parametrize("name", [pytest.param(m, marks=pytest.mark.slow) if m in _SLOW_LOCI
                                  else m for m in _builtin_models()])
def test_locus_json_of_builtin_models_is_strict_json(name, capsys):
    assert main(["locus", name, "--format", "json", "--quiet"]) == 0
    data = _strict_json(capsys.readouterr().out)
    assert data["model"] == name and data["components"]


def test_report_where_nothing_can_be_created_is_one_line(tmp_path, monkeypatch, capsys):
    """/proc takes no new folders: the error names -o, and nothing is left behind."""
    monkeypatch.chdir(tmp_path)
    code = main(["report", "planar2r", "-o", "/proc/rankloci-test/out", "--format", "md",
                 "--quiet", "--samples", "2"])
    err = capsys.readouterr().err
    assert code == 2 and "Traceback" not in err
    assert err.strip().count("\n") == 0 and "-o '/proc/rankloci-test/out'" in err


def test_fifty_fixed_rotations_stay_short(tmp_path, monkeypatch, capsys):
    """Fixed joints at rpy 0.3 0.2 0.1 compose exact rational rotations whose digits would
    grow without bound (past Python's 4300-digit conversion limit); they are kept short."""
    links = "".join(f'<link name="l{i}"/>' for i in range(53))
    joints = "".join(
        f'<joint name="f{i}" type="fixed"><parent link="l{i}"/><child link="l{i + 1}"/>'
        f'<origin rpy="0.3 0.2 0.1" xyz="0 0 0.1"/></joint>' for i in range(50))
    moving = ('<joint name="a" type="revolute"><parent link="l50"/><child link="l51"/>'
              '<axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>'
              '<joint name="b" type="revolute"><parent link="l51"/><child link="l52"/>'
              '<origin xyz="0.1 0 0"/><axis xyz="0 1 0"/>'
              '<limit lower="-3" upper="3" effort="1" velocity="1"/></joint>')
    (tmp_path / "f.urdf").write_text(f'<robot name="f">{links}{joints}{moving}</robot>',
                                     encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    assert main(["jacobian", "f.urdf"]) == 0
    out = capsys.readouterr().out
    assert max(len(word) for word in out.replace("*", " ").replace("/", " ").split()) < 200
