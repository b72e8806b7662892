"""The numeric checks' rank threshold as an option: ``rank_rtol=`` and ``--rank-rtol``.

The matrix [[cos x, -sin x], [sin x / 10^7, cos x / 10^7]] is a rotation with its second row
scaled down: its singular values are 1 and 1e-7 at every x, so it never loses rank (its
determinant is 1e-7) and its locus is empty, but it is nearly singular everywhere.  At the
default threshold (RANK_RTOL = 1e-8) the check finds it regular; at 1e-6 it finds it singular
at every configuration off the (empty) locus, and fails.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
import sympy as sp

import rankloci
from rankloci.api.calls import certified_locus
from rankloci.cli import main
from rankloci.errors import ArgumentError
from rankloci.io import load_model
from rankloci.tolerances import RANK_RTOL

NEAR = ('variables = ["x"]\n'
        'matrix = [["cos(x)", "-sin(x)"], ["sin(x)/10000000", "cos(x)/10000000"]]\n')


@pytest.fixture(scope="module")
def near(tmp_path_factory):
    path = tmp_path_factory.mktemp("near") / "near.toml"
    path.write_text(NEAR)
    return path


def test_the_matrix_is_nearly_singular_everywhere(near):
    tm = rankloci.jacobian(str(near))
    f = sp.lambdify(tm.variables, tm.matrix, "numpy")
    for x in np.random.default_rng(1).uniform(-np.pi, np.pi, 5):
        s = np.linalg.svd(np.asarray(f(x), dtype=float), compute_uv=False)
        assert s[-1] / s[0] == pytest.approx(1e-7, rel=1e-6)


def test_the_threshold_decides_the_check(near):
    default = rankloci.check(str(near), samples=3, jobs=1)
    tight = rankloci.check(str(near), samples=3, jobs=1, rank_rtol=1e-9)
    loose = rankloci.check(str(near), samples=3, jobs=1, rank_rtol=1e-6)
    assert default.ok and tight.ok
    assert not loose.ok
    assert loose.numeric.off_locus_failures
    assert all(p.rank_drop == 1 for p in loose.numeric.off_locus_failures)
    # the threshold used is recorded
    assert default.to_dict()["thresholds"]["RANK_RTOL"] == RANK_RTOL
    assert loose.to_dict()["thresholds"]["RANK_RTOL"] == 1e-6


def test_the_default_is_the_package_threshold(near):
    """The default gives what RANK_RTOL given explicitly gives: the same locus, the same check."""
    a = rankloci.check(str(near), samples=3, jobs=1)
    b = rankloci.check(str(near), samples=3, jobs=1, rank_rtol=RANK_RTOL)
    assert a.to_dict() == b.to_dict()
    m = load_model("planar2r")
    assert certified_locus(m, jobs=1)[0] is certified_locus(m, jobs=1, rank_rtol=RANK_RTOL)[0]


def test_the_threshold_is_part_of_the_pipeline_key():
    m = load_model("planar2r")
    first = certified_locus(m, jobs=1)[0]
    other = certified_locus(m, jobs=1, rank_rtol=1e-6)[0]
    assert other is not first
    assert [c.equations for c in other.components] == [c.equations for c in first.components]


@pytest.mark.parametrize("bad", [0, 1, -1e-8, 2.0, float("nan"), float("inf"), "1e-6", True,
                                 None])
def test_bad_values_are_refused_before_any_work(bad):
    with pytest.raises(ArgumentError, match="rank_rtol="):
        rankloci.locus("planar2r", rank_rtol=bad)
    with pytest.raises(ArgumentError, match="rank_rtol="):
        rankloci.check("planar2r", rank_rtol=bad)


def test_the_command_line_takes_it_and_records_it(near, capsys):
    assert main(["check", str(near), "--samples", "3", "--quiet", "--jobs", "1"]) == 0
    capsys.readouterr()
    code = main(["check", str(near), "--samples", "3", "--quiet", "--jobs", "1",
                 "--rank-rtol", "1e-6", "--format", "json"])
    data = json.loads(capsys.readouterr().out)
    assert code == 1 and data["ok"] is False
    assert data["thresholds"]["RANK_RTOL"] == 1e-6
    assert main(["locus", "planar2r", "--quiet", "--jobs", "1", "--format", "json",
                 "--rank-rtol", "1e-7"]) == 0
    assert json.loads(capsys.readouterr().out)["tolerances"] == {"rank_rtol": 1e-7}
    assert main(["locus", "planar2r", "--quiet", "--jobs", "1", "--format", "json"]) == 0
    assert json.loads(capsys.readouterr().out)["tolerances"] == {"rank_rtol": RANK_RTOL}


@pytest.mark.parametrize("command", ["locus", "check", "report"])
@pytest.mark.parametrize("bad", ["0", "1", "-1e-8", "nan", "inf", "small"])
def test_the_command_line_refuses_bad_values(command, bad, capsys, tmp_path):
    extra = ["-o", str(tmp_path / "out")] if command == "report" else []
    code = main([command, "planar2r", "--rank-rtol", bad, *extra])
    err = capsys.readouterr().err
    assert code == 2
    assert len(err.strip().splitlines()) == 1 and "--rank-rtol" in err
    assert not (tmp_path / "out").exists()


def test_is_singular_takes_the_containment_tolerance():
    """q2 = 1e-6 is 1e-6 from the component sin q2 = 0 of planar2r (scaled residual ~1e-6):
    off it at the default (1e-9), on it at rtol=1e-5."""
    assert not rankloci.is_singular("planar2r", [0.3, 1e-6])
    assert rankloci.is_singular("planar2r", [0.3, 1e-6], rtol=1e-5)
    for bad in (0, -1.0, float("nan"), "1e-5"):
        with pytest.raises(ArgumentError, match="rtol="):
            rankloci.is_singular("planar2r", [0.3, 0.0], rtol=bad)
