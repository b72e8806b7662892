"""The ``ik`` and ``manipulability`` commands, called as ``main([...])``."""

from __future__ import annotations

import csv
import io
import json

import numpy as np
import pytest

from rankloci.cli import main
from rankloci.tolerances import RANK_RTOL

Q0 = "0.62 0.23 1.0 0.46"
LINE = "0.524572,3.032596 -> -1.475428,3.032596"   # the tool point of Q0, then 2 units in -x


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def is_png(path) -> bool:
    data = path.read_bytes()
    return data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 5000


def test_manipulability_planar2r_json_names_the_nearest_component(capsys, tmp_path):
    fig = tmp_path / "p.png"
    code, out, err = run(capsys, "manipulability", "planar2r", "--q", "pi/4 pi/4", "--format",
                         "json", "--plot", str(fig), "--quiet")
    assert code == 0 and err == ""
    r = json.loads(out)
    assert r["task"]["w"] == pytest.approx(np.sin(np.pi / 4), rel=1e-12)
    assert r["task"]["w_p"] == pytest.approx(4 * np.sin(np.pi / 4), rel=1e-12)
    assert r["task"]["polytope_vertices"] == 4 and r["task"]["polytope_flat"] is False
    near = r["nearest_component"]
    assert near["component"] == 1 and near["equations"] == "sin(q2) = 0"
    assert near["distance"] == pytest.approx(np.pi / 4, abs=1e-8)
    assert near["sigma_ratio_at_point"] <= RANK_RTOL
    assert is_png(fig)


def test_manipulability_pa10_text_has_task_and_position_rows_and_a_3d_figure(capsys, tmp_path):
    fig = tmp_path / "pa10.png"
    code, out, err = run(capsys, "manipulability", "pa10", "--q", "0 pi/4 0 pi/4 0 pi/4 0",
                         "--no-locus", "--plot", str(fig), "--quiet")
    assert code == 0, err
    assert "task rows (vx, vy, vz, wx, wy, wz)" in out and "position rows (vx, vy, vz)" in out
    assert "12 vertices, 8 facets" in out
    assert "nearest locus component" not in out
    assert is_png(fig)


def test_manipulability_on_the_locus_is_flat(capsys):
    code, out, _ = run(capsys, "manipulability", "planar2r", "--q", "0.3 0", "--format", "json",
                       "--quiet")
    r = json.loads(out)
    assert code == 0 and r["task"]["polytope_flat"] is True and r["task"]["w"] <= 1e-15
    assert r["nearest_component"]["distance"] <= 1e-12


def read_csv(text):
    rows = list(csv.reader(io.StringIO(text)))
    return rows[0], np.array(rows[1:], dtype=float)


def test_ik_planar4r_csv_table_and_figure(capsys, tmp_path):
    out_csv, fig = tmp_path / "rates.csv", tmp_path / "rates.png"
    code, out, err = run(capsys, "ik", "planar4r", "--q0", Q0, "--line", LINE, "--steps", "50",
                         "-o", str(out_csv), "--plot", str(fig), "--quiet")
    assert code == 0 and out == "" and err == ""
    header, data = read_csv(out_csv.read_text())
    assert header[:5] == ["t", "q1", "q2", "q3", "q4"]
    assert header[-2:] == ["distance", "nearest_component"]
    assert data.shape == (51, len(header))
    np.testing.assert_allclose(data[0, 1:5], [0.62, 0.23, 1.0, 0.46])
    rates = data[:, 5:9]
    inf_norm = np.abs(rates).max(axis=1)
    at_norm = np.abs(np.abs(rates) - inf_norm[:, None]) <= 1e-9 * inf_norm[:, None]
    saturated = np.sum(at_norm, axis=1)
    assert np.all(saturated >= 3), "n - m + 1 = 3 components at the infinity norm (theorem 3)"
    assert np.all(data[:, header.index("nearest_component")] == 1)
    assert np.all(data[:, header.index("distance")] > 0)
    assert is_png(fig)


def test_ik_json_with_a_restricted_joint_and_a_waypoint_file(capsys, tmp_path):
    path = tmp_path / "waypoints.txt"
    path.write_text("# x, y\n0.524572, 3.032596\n0.3 2.8\n\n-0.2, 2.9  # last\n")
    code, out, err = run(capsys, "ik", "planar4r", "--q0", Q0, "--path", str(path), "--norm",
                         "mixed", "--restrict", "1", "--steps", "40", "--format", "json",
                         "--no-locus", "--quiet")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["norm"] == "mixed" and doc["restricted"] == [1] and doc["stopped"] is None
    rows = np.array(doc["rows"], dtype=float)
    cols = doc["columns"]
    assert "distance" not in cols
    np.testing.assert_array_equal(rows[:, cols.index("rate_q1")], 0.0)
    # with the correction gain 1/(4 dt) the tool lags the path by less than one step's length
    pts = np.array([[0.524572, 3.032596], [0.3, 2.8], [-0.2, 2.9]])
    step = np.linalg.norm(np.diff(pts, axis=0), axis=1).sum() / 40
    assert rows[:, cols.index("tracking_error")].max() < step


def test_ik_start_solved_from_the_first_point(capsys):
    code, out, err = run(capsys, "ik", "pa10", "--line", "0.4,0.1,0.8 -> 0.45,0.0,0.75",
                         "--steps", "20", "--no-locus", "--format", "json", "--quiet")
    assert code == 0, err
    doc = json.loads(out)
    assert len(doc["rows"]) == 21 and max(r[doc["columns"].index("tracking_error")]
                                          for r in doc["rows"]) < 1e-3


BAD = [
    (["manipulability", "planar2r", "--q", "1 2 3"], "expected 2 values"),
    (["manipulability", "planar2r", "--q", "1 foo"], "not a number or an expression in pi"),
    (["manipulability", "planar2r", "--q", "1 inf"], "not"),
    (["manipulability", "planar2r", "--q", "1 2", "--plot", "x.txt"], "must end in"),
    (["ik", "planar4r", "--q0", Q0, "--line", "1,2"], "X0 -> X1"),
    (["ik", "planar4r", "--q0", Q0, "--line", "1,2,3 -> 1,2"], "expected 2 values"),
    (["ik", "planar4r", "--q0", Q0, "--line", "1,2 -> 3,4"], "--q0 puts the tool at"),
    (["ik", "planar4r", "--line", "9,9 -> 3,4"], "out of reach"),
    (["ik", "planar4r", "--q0", Q0, "--line", LINE, "--restrict", "9"], "--restrict 9"),
    (["ik", "planar4r", "--q0", Q0, "--line", LINE, "--restrict", "1", "2", "3"],
     "leaves 1 joint for"),
    (["ik", "planar4r", "--q0", Q0, "--line", LINE, "--steps", "0"], "--steps"),
    (["ik", "planar4r", "--q0", Q0, "--line", LINE, "--gain", "-1"], "--gain"),
    (["ik", "planar4r", "--q0", Q0, "--path", "/nonexistent/w.csv"], "cannot read"),
    (["ik", "planar4r", "--q0", Q0, "--line", LINE, "--path", "w.csv"], "not allowed"),
    (["ik", "planar4r", "--q0", Q0], "one of the arguments"),
    (["ik", "planar4r", "--q0", "0 0 0 0", "--line", "4,0 -> 3,0"], "is singular"),
    (["ik", "planar4r", "--q0", Q0, "--line", LINE, "-o", "/nonexistent/dir/r.csv"],
     "does not exist"),
]


@pytest.mark.parametrize("argv, message", BAD)
def test_bad_input_is_one_line_and_exit_2(capsys, tmp_path, monkeypatch, argv, message):
    monkeypatch.chdir(tmp_path)
    code, out, err = run(capsys, *argv)
    assert code == 2
    assert out == ""
    assert err.count("\n") == 1 and err.startswith("rankloci: error: ") and message in err
    assert list(tmp_path.iterdir()) == [], "nothing is written"


def test_raw_matrix_model_is_refused(capsys, tmp_path):
    model = tmp_path / "m.toml"
    model.write_text('name = "m"\nvariables = ["x"]\nmatrix = [["cos(x)", "1"]]\n')
    code, _, err = run(capsys, "manipulability", str(model), "--q", "0")
    assert code == 2 and "needs a robot model" in err


def test_waypoint_file_errors_name_the_line(capsys, tmp_path):
    path = tmp_path / "w.csv"
    path.write_text("0.524572, 3.032596\n1, 2, 3\n")
    code, _, err = run(capsys, "ik", "planar4r", "--q0", Q0, "--path", str(path))
    assert code == 2 and "line 2" in err and "expected 2 values" in err
    path.write_text("0.524572, 3.032596\n")
    code, _, err = run(capsys, "ik", "planar4r", "--q0", Q0, "--path", str(path))
    assert code == 2 and "at least 2 waypoints" in err
