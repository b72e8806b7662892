"""The examples of every --help name input files that exist in the source tree."""

import argparse
import shlex
from pathlib import Path

import pytest

from rankloci.cli.parser import build_parser

ROOT = Path(__file__).resolve().parents[2]
#: Options whose value a command writes (or a shell redirection): not inputs.
OUTPUTS = {">", "-o", "--output", "--tree", "--plot"}
SUFFIXES = (".toml", ".urdf", ".csv", ".json", ".txt", ".dot")


def _epilogs():
    parser = build_parser()
    yield "rankloci", parser.epilog
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                yield name, sub.epilog or ""


def input_paths(epilog: str) -> list[str]:
    """Files the example lines read: arguments ending in a file suffix, except those that
    an option or redirection writes, and files an earlier example line wrote."""
    written, read = set(), []
    for line in epilog.splitlines():
        if not line.startswith("  rankloci "):
            continue
        words = shlex.split(line.split("  #", 1)[0])
        for prev, word in zip(words, words[1:]):
            if prev in OUTPUTS:
                written.add(word)
            elif word.endswith(SUFFIXES) and word not in written:
                read.append(word)
    return read


def test_input_paths_reads_examples_as_meant():
    epilog = ("examples:\n  rankloci locus a.toml --format json > a.json   # a comment x.toml\n"
              "  rankloci check a.toml --locus a.json --tree t.dot\n"
              "  rankloci ik m --path w.csv -o r.json\nnot an example: b.toml\n")
    assert input_paths(epilog) == ["a.toml", "a.toml", "w.csv"]


@pytest.mark.parametrize("command, epilog", list(_epilogs()), ids=lambda v: str(v)[:20])
def test_every_file_an_example_reads_exists(command, epilog):
    missing = [p for p in input_paths(epilog) if not (ROOT / p).is_file()]
    assert missing == [], f"rankloci {command} --help names files that are not shipped: {missing}"


def test_the_examples_name_files_at_all():
    """The check above has something to check: the examples read shipped files."""
    named = {p for _, epilog in _epilogs() for p in input_paths(epilog)}
    assert {"examples/my_matrix.toml", "examples/waypoints.csv", "examples/sweeps/designs.toml",
            "examples/arm.urdf"} <= named



@pytest.mark.slow
def test_the_check_example_runs_as_written(capsys, tmp_path, monkeypatch):
    """`rankloci check --help`'s URDF lines, run from the source tree: the locus file of
    examples/arm.urdf (six joints: shoulder, elbow and wrist singularities) checks."""
    from rankloci.cli import main

    monkeypatch.chdir(ROOT)
    arm = ["examples/arm.urdf", "--tip", "tool0"]
    assert main(["locus", *arm, "--format", "json", "--quiet"]) == 0
    (tmp_path / "arm.json").write_text(capsys.readouterr().out)
    assert main(["check", *arm, "--locus", str(tmp_path / "arm.json"), "--quiet"]) == 0
    assert "result: PASS" in capsys.readouterr().out


def test_a_locus_of_another_task_is_refused_by_check(capsys, tmp_path):
    """A locus computed with --task is not the model's own: check says so in one line."""
    from rankloci.cli import main

    assert main(["locus", "planar3r", "--task", "0,1,5", "--format", "json", "--quiet"]) == 0
    (tmp_path / "l.json").write_text(capsys.readouterr().out)
    assert main(["check", "planar3r", "--locus", str(tmp_path / "l.json"), "--quiet"]) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1
    assert "the locus is of a 3x3 matrix and planar3r's task matrix is 2x3" in err
