"""One name per option: the command line's --numeric (its old --numeric-parameters still works,
with a note), the readers' tip= (tip_link= still works, with a DeprecationWarning), report()'s
formats= with the command's default, nearest_component numbered as the command numbers it."""

from __future__ import annotations

import inspect
import json
import warnings
from pathlib import Path

import numpy as np
import pytest

import rankloci
from rankloci.cli import main
from rankloci.cli.parser import build_parser
from rankloci.errors import ArgumentError
from rankloci.io import load_model
from rankloci.io.urdf import parse_urdf, read_urdf

ROOT = Path(__file__).resolve().parents[2]
IIWA = ROOT / "kinematics_models" / "extra" / "iiwa_offsets.urdf"


def _untimed(text):
    """A JSON document without its measured seconds (they differ from run to run)."""
    def drop(x):
        if isinstance(x, dict):
            return {k: drop(v) for k, v in x.items() if "seconds" not in k}
        return [drop(v) for v in x] if isinstance(x, list) else x
    return drop(json.loads(text))


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.parametrize("command", ["jacobian", "locus", "check", "report"])
def test_every_command_spells_it_numeric_and_hides_the_old_spelling(capsys, command):
    with pytest.raises(SystemExit):
        main([command, "--help"])
    out = capsys.readouterr().out
    assert "--numeric " in out or "--numeric\n" in out
    assert "--numeric-parameters" not in out
    args = build_parser().parse_args([command, "planar2r", "--numeric-parameters"])
    assert args.numeric is True and args.old_options == ["--numeric-parameters"]
    assert build_parser().parse_args([command, "planar2r"]).numeric is False


@pytest.mark.parametrize("argv", [["jacobian", "planar2r", "--format", "json"],
                                  ["locus", "planar2r", "--format", "json", "--quiet"]])
def test_the_old_spelling_gives_the_same_output_with_a_note(capsys, argv):
    code, new, err = run(capsys, *argv, "--numeric")
    assert code == 0 and err == ""
    code, old, err = run(capsys, *argv, "--numeric-parameters")
    assert code == 0 and _untimed(old) == _untimed(new)
    assert err == "rankloci: note: --numeric-parameters is deprecated; use --numeric\n"


def test_bad_input_with_the_old_spelling_is_still_one_line(capsys):
    code, out, err = run(capsys, "locus", "nowhere", "--numeric-parameters")
    assert code == 2 and out == "" and err.count("\n") == 1
    assert err.startswith("rankloci: error: no built-in model or file 'nowhere'")


def test_the_readers_take_tip_and_the_old_tip_link_with_a_warning():
    text = IIWA.read_text()
    new = read_urdf(IIWA, tip="link_7")
    with pytest.warns(DeprecationWarning, match="read_urdf: tip_link= is deprecated; use tip="):
        assert read_urdf(IIWA, tip_link="link_7") == new
    with pytest.warns(DeprecationWarning, match="load_model: tip_link="):
        assert load_model(str(IIWA), tip_link="link_7") == new
    with pytest.warns(DeprecationWarning, match="parse_urdf: tip_link="):
        old = parse_urdf(text, name="iiwa_offsets", file=IIWA.name, tip_link="link_7")
    assert old == parse_urdf(text, name="iiwa_offsets", file=IIWA.name, tip="link_7")
    with warnings.catch_warnings():
        warnings.simplefilter("error")            # the new name warns of nothing
        load_model(str(IIWA), tip="link_7")
    with pytest.raises(ArgumentError, match="give tip= only"):
        read_urdf(IIWA, tip="link_7", tip_link="link_7")
    for f in (parse_urdf, read_urdf, load_model):
        assert "tip" in inspect.signature(f).parameters


def test_report_writes_what_the_command_writes_by_default(tmp_path):
    default = inspect.signature(rankloci.report).parameters["formats"].default
    assert list(default) == build_parser().parse_args(["report", "planar2r"]).format.split(",")
    with pytest.raises(ArgumentError, match="'docx' is not one of"):
        rankloci.report("planar2r", tmp_path, formats="md,docx")
    built, paths = rankloci.report("planar2r", tmp_path / "out", formats="md,tex", samples=2,
                                   timings=False)
    assert sorted(p.name for p in paths if p.suffix in (".md", ".tex", ".pdf")) == [
        "planar2r.md", "planar2r.tex"]
    assert "Timings" not in (tmp_path / "out" / "planar2r.md").read_text()


def test_nearest_component_is_numbered_as_the_command_numbers_it(capsys):
    """puma560 has three components; the API's number is the command's, 1-based."""
    q = [0.3, 0.2, -1.5, 0.4, 0.6, 0.1]          # nearest: not the first component
    near = rankloci.nearest_component("puma560", q)
    code, out, _ = run(capsys, "manipulability", "puma560", "--q", " ".join(map(str, q)),
                       "--format", "json", "--quiet")
    shown = json.loads(out)["nearest_component"]
    assert code == 0 and near.component == shown["component"] and near.component >= 1
    L = rankloci.locus("puma560")
    chosen = L.components[near.component - 1]
    assert shown["equations"] == ", ".join(f"{e} = 0" for e in chosen.equations)
    assert near.distance == pytest.approx(min(near.distances))
    assert np.isclose(near.distances[near.component - 1], near.distance)
