"""A 7R arm with 0.5 mm joint offsets (as KUKA's LBR descriptions carry): near-degenerate geometry.

The offsets make the straight-elbow configurations nearly, not exactly, singular: on
800 sin q4 + cos q4 = 0 the maximal minors are ~4e-8 of their size, and sigma_min/sigma_max
has positive local minima down to ~1e-12 nearby.  Decisions that rest on a numeric tolerance
alone miss components there; the locus must still pass its own self-check.
"""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest
import sympy as sp

from rankloci.io import load_model
from rankloci.jacobians import task_matrix

JOINT = ('<joint name="j{k}" type="revolute"><parent link="link_{p}"/><child link="link_{k}"/>'
         '<origin rpy="0 0 0" xyz="{xyz}"/><axis xyz="{axis}"/>'
         '<limit lower="-3" upper="3" effort="1" velocity="1"/></joint>')
#: origin and axis of joints 1 to 7
JOINTS = [("0 0 0", "0 0 1"), ("-0.0005 0 0.34", "0 1 0"), ("0 0 0", "0 0 1"),
          ("0.0005 0 0.4", "0 -1 0"), ("0 0 0", "0 0 1"), ("0 0 0.4", "0 1 0"), ("0 0 0", "0 0 1")]


def urdf_text() -> str:
    links = "".join(f'<link name="link_{k}"/>' for k in range(8))
    joints = "".join(JOINT.format(k=k + 1, p=k, xyz=xyz, axis=axis)
                     for k, (xyz, axis) in enumerate(JOINTS))
    return f'<?xml version="1.0"?><robot name="iiwa_offsets">{links}{joints}</robot>'


@pytest.fixture(scope="module")
def urdf(tmp_path_factory):
    path = tmp_path_factory.mktemp("offsets") / "iiwa_offsets.urdf"
    path.write_text(urdf_text())
    return path


@pytest.mark.slow
def test_offset_arm_locus_is_certified_complete_with_the_offset_component(urdf, tmp_path):
    """tan q2 = 1/1600 and tan q4 = 1/800 give a 5-dimensional component (singular whatever
    q1, q3, q5, q6 and q7 are) that the branch tree does not find.  The certificate's witness
    points show it missing; on the slice of q4 they fix, the sine of q2 is fixed at a number of
    Q(sqrt(71111)), and the component is found and certified.  The mirror slice holds a
    component without real points (sin q2 = 800 + 3 sqrt(71111)), listed as complex only."""
    # a process of its own, as a user runs it
    run = subprocess.run([sys.executable, "-m", "rankloci", "locus", str(urdf), "--tip", "link_7",
                          "--format", "json", "--quiet"], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    out = json.loads(run.stdout)
    assert out["complete"] is True
    assert out["certificate"]["verdict"] == "passed", out["certificate"]["findings"]
    assert any("sqrt(71111)" in e for eqs in out["certificate"]["complex_components"]
               for e in eqs)
    # the elbow of the offset arm, near straight: 800 sin q4 + cos q4 = 0, found and kept
    equations = [e for c in out["components"] for e in c["equations"]]
    assert any("800*sin(q4)" in e and "cos(q4)" in e for e in equations), equations
    # Pinocchio-free check: points of the offset component, q2 = atan(1/1600) and
    # q4 = atan(1/800) whatever the other joints, are singular and on the locus; with either
    # sign flipped they are regular and off it
    from rankloci.loci import parse_locus_dict

    model = load_model(str(urdf), tip="link_7")
    locus = parse_locus_dict(out, model)
    tm = task_matrix(model, numeric=True)
    f = sp.lambdify(tm.variables, tm.matrix, "numpy")
    rng = np.random.default_rng(2)
    for s2, s4 in ((1, 1), (1, 1), (-1, 1), (1, -1)):
        q = rng.uniform(-np.pi, np.pi, 7)
        q[1], q[3] = np.arctan2(s2, 1600.0), np.arctan2(s4, 800.0)
        s = np.linalg.svd(np.array(f(*q), dtype=float), compute_uv=False)
        on = s2 == s4 == 1
        assert (s[-1] / s[0] < 1e-12) == on
        assert locus.contains(q) == on
    # the locus file is certified again by check
    saved = tmp_path / "iiwa.json"
    saved.write_text(run.stdout, encoding="utf-8")
    from rankloci.cli import main

    assert main(["check", str(urdf), "--tip", "link_7", "--locus", str(saved), "--quiet",
                 "--samples", "2"]) == 0


def test_the_straight_elbow_alone_is_not_singular(urdf):
    # sigma_min/sigma_max ~1e-7 on 800 sin q4 + cos q4 = 0: near the tolerance, but regular
    tm = task_matrix(load_model(str(urdf), tip="link_7"), numeric=True)
    f = sp.lambdify(tm.variables, tm.matrix, "numpy")
    rng = np.random.default_rng(1)
    q4 = -np.arctan2(1.0, 800.0)                  # tan q4 = -1/800
    assert abs(800 * np.sin(q4) + np.cos(q4)) < 1e-12
    for _ in range(5):
        q = rng.uniform(-np.pi, np.pi, 7)
        q[3] = q4
        s = np.linalg.svd(np.array(f(*q), dtype=float), compute_uv=False)
        assert 1e-9 < s[-1] / s[0] < 1e-5


def _straight_elbow(tm):
    """800 sin q4 + cos q4 = 0 and tan q6 = B/A there: the straight elbow of the offset arm
    widened by one equation, a 5-dimensional set on which J is regular but nearly singular
    (sigma_min/sigma_max 1e-10 to 1e-13 when evaluated in 60 digits)."""
    q = {v.name: v for v in tm.variables}
    s = {k: sp.sin(q[f"q{k}"]) for k in range(1, 8)}
    c = {k: sp.cos(q[f"q{k}"]) for k in range(1, 8)}
    big = (1280000 * s[2] * s[4] * c[4] * c[5] - 511999200 * s[2] * c[4]**2 * c[5]
           + 512000000 * s[2] * c[5] + 800 * s[3] * s[4] * s[5] * c[3] - s[3] * s[5] * c[3]
           - 800 * s[4] * c[4] * c[5] + 640000 * c[4]**2 * c[5] - 640000 * c[5])
    other = (511999200 * s[2] * s[4] * c[4] + 512000000 * s[2] * s[4] + 1280000 * s[2] * c[4]**2
             + 640000 * s[2] * c[4] - 640000 * s[2] + 640000 * s[4] * c[3]**2
             - 640000 * s[4] * c[4] - 640000 * s[4] - 800 * c[3]**2 - 800 * c[4]**2 + 800)
    return (800 * s[4] + c[4], sp.expand(s[6] * other - c[6] * big))


def test_the_check_rejects_a_nearly_singular_component(urdf):
    """Double precision calls the widened straight elbow singular; 50 and 100 digits do not."""
    from rankloci.loci import Component, Locus
    from rankloci.numeric.crosscheck import cross_check, render_check_text
    from rankloci.tolerances import ON_LOCUS_RTOL

    tm = task_matrix(load_model(str(urdf), tip="link_7"), numeric=True)
    q = {v.name: v for v in tm.variables}
    # a component of the offset arm's locus: singular, though double precision shows 1e-11
    flipped = (sp.cos(q["q3"] / 2), 800 * sp.sin(q["q4"]) - 1,
               800 * sp.sin(q["q2"]) * sp.sin(q["q4"]) + sp.sin(q["q2"]) * sp.cos(q["q4"])
               - sp.sin(q["q4"]))
    locus = Locus(model="iiwa_offsets", variables=tuple(tm.variables), parameters={},
                  shape=tuple(tm.matrix.shape), method="svm",
                  components=(Component(equations=_straight_elbow(tm), dimension=5),
                              Component(equations=flipped, dimension=4)))
    report = cross_check(locus, tm.matrix, tm.variables, angles=tm.angles, samples=6,
                         rng=np.random.default_rng(0))
    comp, singular = report.components
    assert singular.ok, singular.message
    assert any(p.precise == "singular" and p.sigma_ratio > 1e-14 for p in singular.points)
    assert "decided singular in 100 digits" in render_check_text(report).splitlines()[3]
    assert not comp.ok, comp.message
    regular = [p for p in comp.points if p.precise == "regular"]
    assert regular
    # the failure is the extended-precision verdict's: in double precision these points
    # look singular
    assert all(p.sigma_ratio <= ON_LOCUS_RTOL for p in regular)
    assert all(p.precise_ratio > 1e-16 for p in regular)
