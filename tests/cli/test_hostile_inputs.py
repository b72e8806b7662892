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
     ["locus", "m.toml", "--numeric", "--quiet"], 2, "40 digits"),
    ("60-digit-integer-parameter", {"m.toml": _planar("m", l1="1" + "0" * 60)},
     ["jacobian", "m.toml"], 2, "40 digits"),
    ("float-parameter-near-overflow", {"m.toml": _planar("m", l1="1.7e308")},
     ["locus", "m.toml", "--numeric", "--quiet"], 2, "magnitude"),
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
    # limits beyond what the system's waits and address-space limits take
    ("timeout-past-the-system-timers", {}, ["locus", "planar2r", "--timeout", "2147483"], 2,
     "--timeout: '2147483' is more than 1000000 seconds"),
    ("timeout-past-the-system-timers-check", {},
     ["check", "planar2r", "--timeout", "1e300"], 2, "--timeout"),
    ("timeout-past-the-system-timers-manipulability", {},
     ["manipulability", "planar2r", "--q", "0 1", "--timeout", "3000000"], 2, "--timeout"),
    ("memory-past-64-bits", {}, ["locus", "planar2r", "--memory", "99999999999999"], 2,
     "--memory: '99999999999999' is more than"),
    ("sweep-timeout-past-the-system-timers",
     {"s.toml": 'models = ["planar2r"]\ntimeout = 2147483\n'},
     ["sweep", "s.toml", "-o", "out", "--serial", "--quiet"], 2, "timeout"),
    ("sweep-memory-past-64-bits", {"s.toml": 'models = ["planar2r"]\nmemory = 99999999999999\n'},
     ["sweep", "s.toml", "-o", "out", "--serial", "--quiet"], 2, "memory"),
    # names longer than the file system takes
    ("model-name-of-300-characters", {}, ["locus", "x" * 300, "--quiet"], 2, "File name too long"),
    ("model-file-name-of-300-characters", {}, ["check", "x" * 300 + ".toml", "--quiet"], 2,
     "File name too long"),
    # locus files whose equations have no value at some configurations
    ("square-root-of-a-sine-in-a-locus-file", {"l.json": _locus_file(["sqrt(sin(q2))"])},
     ["check", "planar2r", "--locus", "l.json", "--quiet", "--samples", "2"], 2,
     "sqrt(sin(q2)) is not defined at every configuration"),
    ("arc-cosine-in-a-locus-file", {"l.json": _locus_file(["acos(q2)"])},
     ["check", "planar2r", "--locus", "l.json", "--quiet", "--samples", "2"], 2,
     "acos(q2) is not defined"),
    ("division-in-a-locus-file-exclusion", {"l.json": _locus_file(raw=json.dumps({
        "schema": "rankloci.locus/2", "model": "planar2r", "variables": ["q1", "q2"],
        "components": [{"equations": ["sin(q2)"], "excluding": ["1/q1"]}]}))},
     ["check", "planar2r", "--locus", "l.json", "--quiet", "--samples", "2"], 2,
     "1/q1 is not defined"),
    # scheduler addresses Dask cannot use: refused before anything runs
    ("scheduler-port-not-a-number", {"s.toml": 'models = ["planar2r", "planar3r"]\n'},
     ["sweep", "s.toml", "-o", "out", "--scheduler", "tcp://127.0.0.1:notaport"], 2,
     "--scheduler 'tcp://127.0.0.1:notaport'"),
    ("scheduler-in-process", {"s.toml": 'models = ["planar2r", "planar3r"]\n'},
     ["sweep", "s.toml", "-o", "out", "--scheduler", "inproc://x"], 2, "tcp://HOST:8786"),
    ("scheduler-unclosed-bracket", {"s.toml": 'models = ["planar2r", "planar3r"]\n'},
     ["sweep", "s.toml", "-o", "out", "--scheduler", "tcp://[::1"], 2, "Invalid IPv6 URL"),
    ("scheduler-without-port-one-case", {"s.toml": 'models = ["planar2r"]\n'},
     ["sweep", "s.toml", "-o", "out", "--scheduler", "tcp://localhost"], 2, "--scheduler"),
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


# --- output files: never replace what is not a regular file; respect the umask ------------------

IK = ["ik", "planar4r", "--q0", "0.62 0.23 1.0 0.46", "--line",
      "0.524572,3.032596 -> -1.475428,3.032596", "--steps", "5", "--quiet"]


def _one_error_line(capsys, code):
    err = capsys.readouterr().err
    assert "Traceback" not in err
    assert code == 2, err
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("rankloci: error: "), err
    return lines[0]


@pytest.mark.parametrize("argv, option", [(IK + ["-o", "{}"], "-o"),
                                          (IK + ["--plot", "{}.png"], "--plot"),
                                          (["locus", "planar2r", "--quiet", "--tree", "{}.json"],
                                           "--tree")])
def test_output_onto_a_fifo_is_refused_and_the_fifo_stays(tmp_path, monkeypatch, capsys, argv,
                                                          option):
    import os
    import stat

    monkeypatch.chdir(tmp_path)
    name = [a for a in argv if "{}" in a][0].format("fifo")
    os.mkfifo(name)
    line = _one_error_line(capsys, main([a.format("fifo") for a in argv]))
    assert f"{option} '{name}' is not a regular file" in line
    assert stat.S_ISFIFO(os.lstat(name).st_mode)
    assert sorted(p.name for p in tmp_path.iterdir()) == [name]


@pytest.mark.parametrize("argv", [IK + ["-o", "null.csv"],
                                  ["locus", "planar2r", "--quiet", "--tree", "null.json"]])
def test_output_through_a_link_to_a_device_is_refused(tmp_path, monkeypatch, capsys, argv):
    """``-o /dev/null`` as root would replace the system's /dev/null: a link to it must not."""
    import os
    import stat

    monkeypatch.chdir(tmp_path)
    link = argv[-1]
    os.symlink("/dev/null", link)
    line = _one_error_line(capsys, main(argv))
    assert "is not a regular file" in line
    assert os.readlink(link) == "/dev/null"
    assert stat.S_ISCHR(os.stat("/dev/null").st_mode)


def test_output_through_a_link_to_a_file_writes_the_file(tmp_path, monkeypatch, capsys):
    import os

    monkeypatch.chdir(tmp_path)
    (tmp_path / "real.csv").write_text("old\n")
    os.symlink("real.csv", "link.csv")
    assert main(IK + ["-o", "link.csv"]) == 0
    assert os.readlink("link.csv") == "real.csv"
    assert (tmp_path / "real.csv").read_text().startswith("t,q1,q2,q3,q4,")


@pytest.fixture
def umask_022():
    import os

    old = os.umask(0o022)
    yield
    os.umask(old)


def _modes(root):
    import stat

    return {str(p.relative_to(root)): oct(stat.S_IMODE(p.stat().st_mode))
            for p in sorted(root.rglob("*")) if p.is_file()}


def test_output_files_respect_the_umask(tmp_path, monkeypatch, capsys, umask_022):
    monkeypatch.chdir(tmp_path)
    assert main(IK + ["-o", "path.csv", "--plot", "path.png"]) == 0
    assert main(["locus", "planar2r", "--quiet", "--tree", "tree.json"]) == 0
    assert main(["report", "planar2r", "-o", "rep", "--format", "md", "--quiet", "--samples",
                 "2"]) == 0
    modes = _modes(tmp_path)
    assert {"path.csv", "path.png", "tree.json", "rep/planar2r.md"} <= set(modes)
    assert set(modes.values()) == {"0o644"}, modes


def test_a_replaced_output_keeps_its_permission_bits(tmp_path, monkeypatch, capsys, umask_022):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "tree.json").write_text("old")
    (tmp_path / "tree.json").chmod(0o640)
    assert main(["locus", "planar2r", "--quiet", "--tree", "tree.json"]) == 0
    assert _modes(tmp_path) == {"tree.json": "0o640"}
    assert "nodes" in (tmp_path / "tree.json").read_text()


def test_sweep_outputs_respect_the_umask(tmp_path, monkeypatch, capsys, umask_022):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "s.toml").write_text('models = ["planar2r"]\n')
    assert main(["sweep", "s.toml", "-o", "out", "--serial", "--quiet"]) == 0
    modes = _modes(tmp_path / "out")
    assert "summary.md" in modes and any(k.startswith("cases/") for k in modes)
    assert set(modes.values()) == {"0o644"}, modes


@pytest.mark.parametrize("argv", [IK + ["-o", "/proc/rankloci-path.csv"],
                                  IK + ["--plot", "/proc/rankloci-path.png"],
                                  ["locus", "planar2r", "--quiet", "--tree",
                                   "/proc/rankloci-tree.json"]])
def test_unwritable_output_is_refused_before_computing(tmp_path, monkeypatch, capsys, argv):
    """/proc takes no new files, even from root: refused at once, not after the work."""
    import time

    monkeypatch.chdir(tmp_path)
    t0 = time.monotonic()
    line = _one_error_line(capsys, main(argv))
    assert "cannot write in '/proc'" in line
    assert time.monotonic() - t0 < 1.5


@pytest.mark.parametrize("argv", [IK + ["-o", "x" * 300 + ".csv"],
                                  ["locus", "planar2r", "--quiet", "--tree", "x" * 300 + ".json"],
                                  ["report", "planar2r", "--quiet", "-o", "x" * 300]])
def test_output_name_longer_than_the_file_system_takes(tmp_path, monkeypatch, capsys, argv):
    monkeypatch.chdir(tmp_path)
    line = _one_error_line(capsys, main(argv))
    assert "longer than 255 bytes" in line
    assert list(tmp_path.iterdir()) == []


# --- reports: nothing outside -o, nothing half-moved -------------------------------------------

REPORT = ["report", "planar2r", "--format", "md", "--quiet", "--samples", "2"]


@pytest.mark.parametrize("blocker", ["directory", "fifo", "symlink"])
def test_report_onto_a_non_file_moves_nothing(tmp_path, monkeypatch, capsys, blocker):
    import os

    monkeypatch.chdir(tmp_path)
    (tmp_path / "out").mkdir()
    target = tmp_path / "out" / "planar2r.md"
    {"directory": target.mkdir, "fifo": lambda: os.mkfifo(target),
     "symlink": lambda: os.symlink("/dev/null", target)}[blocker]()
    line = _one_error_line(capsys, main(REPORT + ["-o", "out"]))
    assert "'out/planar2r.md' is not a regular file" in line
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["planar2r.md"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_report_figure_name_taken_by_a_directory_moves_nothing(tmp_path, monkeypatch, capsys):
    """Figure names are known only once the report is built: checked before any move."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "out" / "planar2r-sigma-1.png").mkdir(parents=True)
    line = _one_error_line(capsys, main(REPORT + ["-o", "out"]))
    assert "planar2r-sigma-1.png is a directory; nothing was written" in line
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["planar2r-sigma-1.png"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_report_into_a_dot_dot_path_creates_only_the_target(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(REPORT + ["-o", "a/../b"]) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["b"]
    assert (tmp_path / "b" / "planar2r.md").is_file()


def test_report_into_a_directory_whose_parent_takes_no_files(tmp_path, monkeypatch, capsys):
    """The build folder goes inside an existing -o, not beside it: /proc/self/fd is not
    writable, and a report into a writable folder must not need its parent."""
    import os

    monkeypatch.chdir(tmp_path)
    out = tmp_path / "ro" / "out"
    out.mkdir(parents=True)
    made = []
    real_mkdtemp = __import__("tempfile").mkdtemp

    def mkdtemp(*args, dir=None, **kw):
        made.append(os.path.realpath(dir))
        if os.path.realpath(dir) != str(out):
            raise PermissionError(13, "Permission denied")
        return real_mkdtemp(*args, dir=dir, **kw)

    monkeypatch.setattr("tempfile.mkdtemp", mkdtemp)
    assert main(REPORT + ["-o", str(out)]) == 0, capsys.readouterr().err
    assert made == [str(out)]
    assert sorted(p.name for p in out.iterdir()) == sorted(
        p.name for p in out.iterdir() if not p.name.startswith("."))


@pytest.mark.parametrize("sig", ["SIGINT", "SIGTERM"])
def test_interrupted_report_leaves_no_build_folder(tmp_path, sig):
    import signal
    import subprocess
    import sys
    import time

    # mobile10: its locus alone takes seconds, so the signal comes while the child computes
    # (an SSRMS report could finish within the second waited below)
    # SIGINT at its default in the child: a shell that starts the tests in the background
    # ignores it, and an ignored SIGINT is inherited (Python then installs no handler)
    proc = subprocess.Popen([sys.executable, "-m", "rankloci", "report", "mobile10", "-o", "out",
                             "--format", "md", "--quiet"], cwd=tmp_path,
                            stderr=subprocess.PIPE, text=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    deadline = time.monotonic() + 60
    while not any(p.name.startswith(".out.tmp-") for p in tmp_path.iterdir()):
        assert proc.poll() is None and time.monotonic() < deadline, proc.stderr.read()
        time.sleep(0.05)
    time.sleep(1.0)                       # the child is computing
    proc.send_signal(getattr(signal, sig))
    _, err = proc.communicate(timeout=30)
    assert "Traceback" not in err
    assert proc.returncode == 130, err
    assert list(tmp_path.iterdir()) == []


# --- bounded reads: regular files only, a size limit, no blocking --------------------------------

def _special(tmp_path, name, kind):
    import os

    if kind == "fifo":
        os.mkfifo(tmp_path / name)
    else:
        os.symlink("/dev/zero", tmp_path / name)


@pytest.mark.parametrize("kind", ["fifo", "zero"])
@pytest.mark.parametrize("argv, name", [
    (["check", "planar2r", "--locus", "l.json", "--quiet", "--samples", "2"], "l.json"),
    (IK[:4] + ["--path", "p.txt", "--steps", "5", "--quiet"], "p.txt"),
    (["sweep", "s.toml", "-o", "out", "--serial", "--quiet"], "m.toml"),
])
def test_a_fifo_or_dev_zero_as_input_is_refused_at_once(tmp_path, monkeypatch, capsys, kind,
                                                        argv, name):
    """Before: a FIFO blocked forever, /dev/zero grew without bound."""
    import threading
    import time

    monkeypatch.chdir(tmp_path)
    (tmp_path / "s.toml").write_text('models = ["m.toml"]\n')
    _special(tmp_path, name, kind)
    got = []
    t0 = time.monotonic()
    runner = threading.Thread(target=lambda: got.append(main(argv)), daemon=True)
    runner.start()
    runner.join(20)
    if runner.is_alive():        # let the blocked open return, so that the thread ends
        with open(tmp_path / name, "w"):
            pass
        runner.join(5)
        pytest.fail(f"{name} ({kind}) blocked the command")
    line = _one_error_line(capsys, got[0])
    assert "not a regular file" in line and name in line
    assert time.monotonic() - t0 < 20
    assert not (tmp_path / "out").exists()


def test_a_large_locus_file_is_refused_and_read_under_the_limits(tmp_path, monkeypatch, capsys):
    from rankloci.cli import commands

    monkeypatch.chdir(tmp_path)
    (tmp_path / "l.json").write_text(_locus_file())
    monkeypatch.setattr(commands, "MAX_LOCUS_BYTES", 50)
    line = _one_error_line(capsys, main(["check", "planar2r", "--locus", "l.json", "--quiet",
                                         "--samples", "2"]))
    assert "l.json" in line and "larger than 50 bytes" in line


def test_a_locus_file_is_parsed_inside_the_time_limit(tmp_path, monkeypatch, capsys):
    """A locus file that takes long to parse ends at --timeout (exit 1), not after it."""
    import time

    from rankloci.cli import commands

    monkeypatch.chdir(tmp_path)
    (tmp_path / "l.json").write_text(_locus_file())

    def slow(*args):
        time.sleep(30)

    monkeypatch.setattr(commands, "_parsed_locus", slow)
    t0 = time.monotonic()
    code = main(["check", "planar2r", "--locus", "l.json", "--quiet", "--samples", "2",
                 "--timeout", "1"])
    err = capsys.readouterr().err
    assert code == 1 and "within 1 s" in err, err
    assert time.monotonic() - t0 < 10


@pytest.mark.parametrize("pattern", ["../*.toml", "/etc/*", "sub/../../*.toml", "**a"])
def test_sweep_pattern_outside_the_directory_is_refused(tmp_path, monkeypatch, capsys, pattern):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "d").mkdir()
    (tmp_path / "s.toml").write_text(f'[[model]]\npath = "d"\npattern = "{pattern}"\n')
    line = _one_error_line(capsys, main(["sweep", "s.toml", "-o", "out", "--serial",
                                         "--quiet"]))
    assert "pattern" in line and "s.toml" in line
    assert not (tmp_path / "out").exists()


def test_sweep_cleanup_removes_only_its_own_temporary_files(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "s.toml").write_text('models = ["planar2r"]\n')
    cases = tmp_path / "out" / "cases"
    cases.mkdir(parents=True)
    mine = cases / ".planar2r.json.abc123_z.rankloci-tmp"
    users = [cases / ".notes.json.bak", cases / ".x.json.1"]
    for p in [mine, *users]:
        p.write_text("x")
    assert main(["sweep", "s.toml", "-o", "out", "--serial", "--quiet"]) == 0
    assert not mine.exists()
    assert all(p.read_text() == "x" for p in users)


# --- sweeps: the scheduler named is used; case files edited by hand are recomputed --------------

def test_scheduler_named_for_one_case_is_not_ignored(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "s.toml").write_text('models = ["planar2r"]\n')
    line = _one_error_line(capsys, main(["sweep", "s.toml", "-o", "out", "--scheduler",
                                         "tcp://127.0.0.1:1", "--connect-timeout", "1",
                                         "--quiet"]))
    assert "cannot reach the Dask scheduler at tcp://127.0.0.1:1" in line
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("field, value", [("components", "many"), ("seconds", None),
                                          ("limits", [1, 2]), ("note", 7), ("hash", {})])
def test_case_file_edited_by_hand_is_computed_again(tmp_path, monkeypatch, capsys, field, value):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "s.toml").write_text('models = ["planar2r"]\n')
    argv = ["sweep", "s.toml", "-o", "out", "--serial", "--quiet"]
    assert main(argv) == 0
    [case] = (tmp_path / "out" / "cases").glob("*.json")
    data = json.loads(case.read_text())
    first = dict(data["sweep"])
    data["sweep"][field] = value
    case.write_text(json.dumps(data))
    capsys.readouterr()
    assert main(argv) == 0, capsys.readouterr().err
    again = json.loads(case.read_text())["sweep"]
    assert again[field] != value and type(again[field]) is type(first[field])
    measured = {"seconds", "peak_mib", "worker"}     # measurements of the run, not results
    assert {k: v for k, v in again.items() if k not in measured} == {
        k: v for k, v in first.items() if k not in measured}
    assert "| planar2r |" in (tmp_path / "out" / "summary.md").read_text()


# --- --timeout counts from the start of the process ----------------------------------------------

def _busy(progress):
    progress("a step that never returns")
    while True:
        pass


def test_the_kill_counts_from_the_given_start_not_from_the_childs():
    """Imports and building J came before the child's start and were not counted: the command
    ended up to 4.8 s past --timeout."""
    import time

    from rankloci.process_limits import KILL_GRACE, LimitExceeded, run_limited

    t0 = time.monotonic()
    with pytest.raises(LimitExceeded, match="did not finish within 4 s"):
        run_limited(_busy, timeout=4, memory_mb=0, started=t0 - 3.5)
    # killed at t0 + 0.5 + KILL_GRACE; counted from the child's start it would be t0 + 4.5
    assert time.monotonic() - t0 < 4 - 3.5 + KILL_GRACE + 2.0
    assert KILL_GRACE <= 0.5        # the kill, the error line and the exit within 1 s


def test_the_process_start_is_before_its_imports():
    import subprocess
    import sys

    code = ("import time; t = time.monotonic(); time.sleep(0.5)\n"
            "from rankloci.process_limits import process_started\n"
            "print(t - process_started(), time.monotonic() - process_started())")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=120, check=True).stdout.split()
    before_sleep, age = map(float, out)
    assert 0.0 <= before_sleep < 60 and age >= 0.5


def test_the_childs_deadline_counts_from_the_given_start(capsys, monkeypatch):
    """A start long ago leaves no time: the locus stops at once (at its first poll, or
    killed), exit 1 and one line."""
    import time

    t0 = time.monotonic()
    assert main(["locus", "planar3r", "--timeout", "600", "--quiet"],
                started=t0 - 601.0) == 1
    assert time.monotonic() - t0 < 10
    err = capsys.readouterr().err
    assert err.startswith("rankloci: error: ") and "did not finish" in err and "600 s" in err
    assert len(err.splitlines()) == 1


# --- degenerate models in reports ----------------------------------------------------------------

def _displays(tex):
    """The bodies of the numbered displays of a LaTeX report."""
    import re

    return re.findall(r"\\begin\{(align|equation)\}(.*?)\\end\{\1\}", tex, re.S)


def test_report_of_an_all_zero_matrix_has_no_empty_display(tmp_path, monkeypatch, capsys):
    """An empty align is a LaTeX error ("Paragraph ended before \\align* was complete")."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "zero.toml").write_text(_raw("zero", [["0", "0"], ["0", "0"]], ("x", "y")))
    assert main(["report", "zero.toml", "-o", "out", "--format", "md,tex", "--quiet"]) == 0
    tex = (tmp_path / "out" / "zero.tex").read_text()
    assert _displays(tex) and all(body.strip() for _, body in _displays(tex))
    assert "none (every configuration)" in tex and "No equation" in tex
    assert "none (every configuration)" in (tmp_path / "out" / "zero.md").read_text()


def test_report_of_a_zero_length_arm_says_no_nan(tmp_path, monkeypatch, capsys):
    import re

    monkeypatch.chdir(tmp_path)
    (tmp_path / "zl.toml").write_text('name = "zl"\nconvention = "dh"\ntask = "planar"\n'
                                      '[[joint]]\na = 0\n[[joint]]\na = 0\n')
    assert main(["report", "zl.toml", "-o", "out", "--format", "md,tex", "--quiet"]) == 0
    assert "warning" not in capsys.readouterr().err
    for name in ("zl.md", "zl.tex"):
        text = (tmp_path / "out" / name).read_text()
        assert not re.search(r"\bnan\b", text, re.I), name
        assert "no configuration is off the locus" in text


def test_a_correct_empty_locus_of_an_unbounded_variable_passes_its_check(tmp_path, monkeypatch,
                                                                       capsys):
    """det [[1, x], [0, 1]] = 1: never singular, but sigma_min/sigma_max ~ 1/x**2 tends to 0 as
    x runs off; the probe's minima out there were taken for singular points on no component."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "shear.toml").write_text(_raw("shear", [["1", "x"], ["0", "1"]]))
    assert main(["check", "shear.toml", "--quiet", "--format", "json"]) == 0
    got = json.loads(capsys.readouterr().out)
    assert got["ok"] and got["completeness"]["uncovered"] == []
    assert got["completeness"]["ran_off_to_infinity"] > 0


# --- what the error lines say --------------------------------------------------------------------

def _killed_from_outside(progress):
    import os
    import signal

    progress("computing")
    os.kill(os.getpid(), signal.SIGKILL)        # as `kill -9` from a shell would


def test_a_child_killed_from_outside_is_not_called_out_of_memory():
    from rankloci.process_limits import LimitExceeded, run_limited

    with pytest.raises(LimitExceeded) as err:
        run_limited(_killed_from_outside, timeout=60, memory_mb=4096)
    message = str(err.value)
    assert "killed by signal 9 (SIGKILL) from outside rankloci" in message
    assert "most likely out of memory" not in message and "last progress: computing" in message


def test_a_check_out_of_time_says_what_stopped_in_plain_words(capsys, monkeypatch):
    """It said "the check the svm computation did not finish ..."."""
    import itertools

    import rankloci.cli.running

    ticks = itertools.count(0.0, 1000.0)       # every budget is spent at the first poll
    monkeypatch.setattr(rankloci.cli.running, "deadline_clock", lambda: next(ticks))
    assert main(["check", "planar3r", "--timeout", "600", "--quiet"]) == 1
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and "Traceback" not in err
    assert err.startswith("rankloci: error: the check stopped: the ")
    assert "the check the" not in err and "raise --timeout (now 600 s)" in err


def _server(handler):
    """A TCP server on a free local port running ``handler(connection)`` in a thread."""
    import socket
    import threading

    listener = socket.create_server(("127.0.0.1", 0))
    kept = []

    def serve():
        while True:
            try:
                conn, _ = listener.accept()
            except OSError:
                return
            kept.append(conn)
            try:
                handler(conn)
            except OSError:          # the test closed the connection first
                pass

    threading.Thread(target=serve, daemon=True).start()
    return listener, kept


def _http_reply(conn):
    conn.recv(1 << 16)
    conn.sendall(b"HTTP/1.0 200 OK\r\nContent-Length: 2\r\n\r\nok")


@pytest.mark.parametrize("kind, handler", [("silent", lambda conn: None),
                                           ("http", _http_reply),
                                           ("ssh", lambda c: c.sendall(b"SSH-2.0-OpenSSH_9\r\n"))])
def test_scheduler_address_where_no_scheduler_greets(tmp_path, monkeypatch, capsys, kind,
                                                       handler):
    """A server that accepts and never answers, or answers HTTP: the client waited for ever."""
    import time

    from rankloci.sweep import execute

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(execute, "CONNECT_SECONDS", 1.0)
    listener, kept = _server(handler)
    address = "tcp://127.0.0.1:%d" % listener.getsockname()[1]
    (tmp_path / "s.toml").write_text('models = ["planar2r"]\n')
    t0 = time.monotonic()
    try:
        line = _one_error_line(capsys, main(["sweep", "s.toml", "-o", "out", "--scheduler",
                                             address, "--quiet"]))
    finally:
        listener.close()
        for conn in kept:
            conn.close()
    assert time.monotonic() - t0 < 30
    assert f"no Dask scheduler answers at {address}" in line
    assert not (tmp_path / "out").exists()


def test_an_interrupt_lost_inside_a_callback_still_stops_a_serial_sweep(tmp_path, monkeypatch,
                                                                        capsys):
    """Ctrl-C during the fork of a case's child raised inside logging's at-fork lock release,
    which ignores exceptions ("Exception ignored in _releaseLock"): the sweep went on to exit
    0.  Here the first case's interrupt is swallowed the same way."""
    import signal

    from rankloci.sweep import execute

    real = execute.run_case
    ran = []

    def run_case(case, *args, **kw):
        ran.append(case.id)
        try:
            signal.getsignal(signal.SIGINT)(signal.SIGINT, None)     # Ctrl-C ...
        except KeyboardInterrupt:
            pass                                                     # ... ignored
        return real(case, *args, **kw)

    monkeypatch.setattr(execute, "run_case", run_case)
    monkeypatch.chdir(tmp_path)
    (tmp_path / "s.toml").write_text('models = ["planar2r", "planar3r"]\n')
    assert main(["sweep", "s.toml", "-o", "out", "--serial", "--quiet"]) == 130
    assert len(ran) == 1 and "interrupted" in capsys.readouterr().err
    assert not (tmp_path / "out" / "summary.md").exists()
