"""Any combination of command-line options: an exit code of 0, 1 or 2, never a traceback.

Options are drawn with valid and invalid values alike.  Exit code 2 (bad input) must come with
exactly one line on stderr.  The models are the two cheapest built-ins, so each example costs
about a second.
"""

from __future__ import annotations

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rankloci.cli import main

VALUES = {
    "--method": ["svm", "subdeterminant", "determinant", "bogus", ""],
    "--format": ["text", "json", "latex", "xml"],
    "--seed": ["0", "3", "-1", "x", "99999999999999999999"],
    "--timeout": ["60", "0", "-5", "nan", "inf", "abc", "1e-9"],
    "--memory": ["0", "4096", "-1", "lots"],
    "--task": ["full", "position", "planar", "xyz", "1,2", "9", ""],
    "--frame": ["base", "tool", "1", "9", "-1", "auto", "x"],
    "--point": ["tool", "base", "1", "7", "q"],
    "--augment": ["q1", "q1 + q2", "cos(q1)", "q9", "import os", "sin(", "cos(100*q1)"],
    "--samples": ["1", "2", "0", "-3", "many"],
    "--tip": ["tool0"],
    "--base-link": ["base"],
    "--jobs": ["1", "2", "0", "x"],
}
FLAGS = ["--quiet", "--numeric-parameters", "--numeric", "--no-verify", "--show-tree"]
OPTIONS = {
    "jacobian": ["--task", "--frame", "--point", "--augment", "--format", "--tip", "--base-link",
                 "--numeric"],
    "locus": ["--method", "--format", "--seed", "--timeout", "--memory", "--task", "--frame",
              "--augment", "--tip", "--numeric-parameters", "--no-verify", "--show-tree",
              "--quiet", "--jobs"],
    "check": ["--format", "--seed", "--timeout", "--memory", "--samples",
              "--numeric-parameters", "--quiet", "--jobs"],
}


@st.composite
def command_lines(draw):
    command = draw(st.sampled_from(sorted(OPTIONS)))
    model = draw(st.sampled_from(["planar2r", "planar3r", "nonexistent_model"]))
    argv = [command, model]
    for option in draw(st.lists(st.sampled_from(OPTIONS[command]), max_size=4, unique=True)):
        argv.append(option)
        if option not in FLAGS:
            argv.append(draw(st.sampled_from(VALUES[option])))
    if command == "check" and "--samples" not in argv:
        argv += ["--samples", "2"]
    return argv


@settings(max_examples=80, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(argv=command_lines())
def test_any_options_give_an_exit_code_and_no_traceback(capsys, argv):
    code = main(argv)
    err = capsys.readouterr().err
    assert code in (0, 1, 2), (argv, code)
    assert "Traceback" not in err, (argv, err)
    if code == 2:
        lines = [line for line in err.splitlines() if line.strip()]
        assert len(lines) == 1 and lines[0].startswith("rankloci: error: "), (argv, err)
