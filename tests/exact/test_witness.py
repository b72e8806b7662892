"""The certificate: witness points modulo a prime prove a locus complete and sound, or refuse it.

Each wrong locus below is wrong in one way that the numeric probes of earlier versions let
through (a missing half, an exclusion that hides part of the set, a wrong rank drop, a wrong
solved value); each must be refused, and the right one must pass.
"""

from __future__ import annotations

import dataclasses
import json

import pytest
import sympy as sp

import rankloci
from rankloci.certify import certify_locus
from rankloci.cli import main
from rankloci.exact.witness import Certificate, certify_components
from rankloci.jacobians import task_matrix
from rankloci.loci import Component

q1, q2, q3, q4 = sp.symbols("q1 q2 q3 q4", real=True)
x, y, t = sp.symbols("x y t", real=True)

#: planar2r with unit links: det J = sin(q2).
PLANAR2R = sp.Matrix([[-sp.sin(q1) - sp.sin(q1 + q2), -sp.sin(q1 + q2)],
                      [sp.cos(q1) + sp.cos(q1 + q2), sp.cos(q1 + q2)]])


def _certify(components, matrix=PLANAR2R, variables=(q1, q2), angles=(q1, q2)):
    return certify_components(matrix, variables, angles, components, seed=3)


def test_the_right_locus_passes_with_its_witness_points_and_bound():
    cert = _certify([Component((sp.sin(q2),), dimension=1)])
    assert cert.verdict == "passed"
    assert cert.witness_points == {1: 2}           # q2 = 0 and q2 = pi on a random line
    assert 0 < cert.error_bound < 1e-12
    assert 2 ** 61 <= cert.prime < 2 ** 62


def test_a_missing_half_is_found():
    cert = _certify([Component((sp.cos(q2 / 2),), dimension=1)])      # only q2 = pi
    assert cert.verdict == "failed"
    assert any("1 of the 2 witness points" in f and "missing" in f for f in cert.findings)


def test_an_exclusion_that_hides_half_the_set_is_refused():
    hidden = Component((sp.sin(q2),), dimension=1, excluding=(sp.cos(q2) - 1,))
    cert = _certify([hidden])
    assert cert.verdict == "failed"
    assert any("lie on no reported component" in f for f in cert.findings)


def test_a_component_with_regular_points_is_refused():
    cert = _certify([Component((sp.sin(q2),), dimension=1),
                     Component((sp.cos(q1),), dimension=1)])
    assert cert.verdict == "failed"
    assert any(f.startswith("component 2:") and "regular" in f for f in cert.findings)


def test_a_wrong_rank_drop_is_refused():
    cert = _certify([Component((sp.sin(q2),), dimension=1, rank_drop=2)])
    assert cert.verdict == "failed"
    assert any("has rank 1, not 0" in f for f in cert.findings)


def test_a_wrong_dimension_is_refused():
    cert = _certify([Component((sp.sin(q2),), dimension=0)])
    assert cert.verdict == "failed"


def test_a_wrong_solved_value_is_refused():
    """planar4r's locus is q2, q3, q4 in {0, pi}: a component of codimension 3, checked at a
    random point of each of its pieces."""
    tm = task_matrix(rankloci.load_model("planar4r"), numeric=True)
    q = tm.variables
    good = Component((sp.sin(q[1]), sp.sin(q[2]), sp.sin(q[3])), dimension=1, free=(q[0],),
                     solved={q[1]: (0, sp.pi), q[2]: (0, sp.pi), q[3]: (0, sp.pi)})
    assert certify_components(tm.matrix, q, tm.angles, [good]).verdict == "passed"
    bad = dataclasses.replace(good, solved={q[1]: (0, sp.pi / 2), q[2]: (0, sp.pi),
                                            q[3]: (0, sp.pi)})
    cert = certify_components(tm.matrix, q, tm.angles, [good, bad])
    assert cert.verdict == "failed"
    assert any("solved values do not satisfy" in f for f in cert.findings)


def _planar4r():
    tm = task_matrix(rankloci.load_model("planar4r"), numeric=True)
    q = tm.variables
    whole = Component((sp.sin(q[1]), sp.sin(q[2]), sp.sin(q[3])), dimension=1, free=(q[0],))
    return tm, q, whole


def test_codimension_three_refuses_a_missing_or_halved_component():
    """planar4r (2 x 4): its only component has codimension 3, 8 witness points on a random
    3-dimensional subspace (q2, q3, q4 each 0 or pi).  Without it, or with q4 = pi only, the
    witness points of codimension 3 are not covered."""
    tm, q, whole = _planar4r()
    cert = certify_components(tm.matrix, q, tm.angles, [whole], seed=5)
    assert cert.verdict == "passed"
    assert cert.witness_points == {1: 0, 2: 0, 3: 8}
    cert = certify_components(tm.matrix, q, tm.angles, [], seed=5)
    assert cert.verdict == "failed"
    assert any("8 of the 8 witness points of codimension 3" in f for f in cert.findings)
    halved = dataclasses.replace(whole, equations=(sp.sin(q[1]), sp.sin(q[2]), sp.cos(q[3] / 2)))
    cert = certify_components(tm.matrix, q, tm.angles, [halved], seed=5)
    assert cert.verdict == "failed"
    assert any("4 of the 8 witness points of codimension 3" in f for f in cert.findings)


def test_a_certificate_computed_again_reuses_its_planes_and_is_the_same(monkeypatch):
    """A second certificate of the same matrix and seed (as when components are added to a
    locus that failed) reuses the planes, determinants and witness points of the first: the
    same verdict, counts and findings, and none of them recomputed."""
    import rankloci.exact.witness as witness

    tm, q, whole = _planar4r()
    monkeypatch.setattr(witness, "_MEMO", {})
    first = certify_components(tm.matrix, q, tm.angles, [], seed=5)
    kept = dict(witness._MEMO)
    assert {k[0][:2] for k in kept} >= {("plane", 1), ("points", 3)}
    calls = []
    monkeypatch.setattr(witness, "_compressions", lambda *a: calls.append(a))
    monkeypatch.setattr(witness, "_isolated_points",
                        lambda *a, **k: calls.append(a) or ([], None))
    again = certify_components(tm.matrix, q, tm.angles, [], seed=5)
    assert calls == [] and witness._MEMO == kept
    assert dataclasses.replace(again, seconds=0) == dataclasses.replace(first, seconds=0)
    assert again.verdict == "failed" and again.witness_points == {1: 0, 2: 0, 3: 8}


def test_a_codimension_beyond_the_elimination_budget_is_undecided(monkeypatch):
    """Where the eliminations of codimension 3 would exceed their budget (long chains:
    mobile10, the 9R snake), the verdict is undecided and says which codimension and why,
    never passed."""
    import rankloci.exact.witness as witness

    tm, q, whole = _planar4r()
    monkeypatch.setattr(witness, "MAX_ELIMINATION_TERMS", 10)
    cert = certify_components(tm.matrix, q, tm.angles, [whole], seed=5)
    assert cert.verdict == "undecided"
    assert 3 not in cert.witness_points
    assert any(f.startswith("codimension 3 components are not certified") for f in cert.findings)


def test_a_certificate_reads_back_from_its_json():
    cert = _certify([Component((sp.sin(q2),), dimension=1)])
    assert Certificate.from_dict(json.loads(json.dumps(cert.to_dict()))).to_dict() == \
        cert.to_dict()
    with pytest.raises(ValueError, match="verdict"):
        Certificate.from_dict({**cert.to_dict(), "verdict": "maybe"})


@pytest.mark.parametrize("name", ["planar2r", "planar3r", "planar3r_orient", "planar4r",
                                  "puma560", "ur5", "pa10", "ssrms_lock3"])
def test_built_in_models_carry_a_passing_certificate(name):
    locus = rankloci.locus(name)
    assert locus.complete is True, locus.notes
    assert locus.certificate.verdict == "passed"
    assert locus.to_dict()["certificate"]["verdict"] == "passed"


@pytest.mark.slow
@pytest.mark.parametrize("name", ["ssrms", "kinematics_models/extra/jaco2.toml",
                                  "kinematics_models/extra/baxter_dh.toml"])
def test_larger_models_carry_a_passing_certificate(name):
    locus = rankloci.locus(name)
    assert locus.complete is True, locus.notes


@pytest.mark.parametrize("matrix, variables", [
    (sp.Matrix([[sp.cos(x), y]]), (x, y)),
    (sp.Matrix([[sp.sin(t) - sp.Rational(1, 2)]]), (t,)),
])
def test_one_row_matrices_are_certified(matrix, variables):
    locus = rankloci.locus(matrix, variables=variables)
    assert locus.complete is True, locus.notes
    assert locus.contains([sp.pi / 2 if len(variables) == 2 else sp.pi / 6, 0][:len(variables)])


def test_a_five_bar_linkage_gets_a_certified_locus():
    """The singular vector method's locus of this constraint Jacobian has a component that is
    regular at most of its points; the certificate refuses it and the subdeterminant method's
    locus is certified instead."""
    th1, th2 = sp.symbols("th1 th2", real=True)
    M = sp.Matrix([[2 * x - sp.cos(th1) / 2 + sp.Rational(1, 5), 2 * y - sp.sin(th1) / 2,
                    x * sp.sin(th1) / 2 - y * sp.cos(th1) / 2 + sp.sin(th1) / 20, 0],
                   [2 * x - sp.cos(th2) / 2 - sp.Rational(1, 5), 2 * y - sp.sin(th2) / 2, 0,
                    x * sp.sin(th2) / 2 - y * sp.cos(th2) / 2 - sp.sin(th2) / 20]])
    locus = rankloci.locus(M, variables=(x, y, th1, th2))
    assert locus.complete is True, locus.notes
    assert not locus.contains([0.5, 0, 0, 1])          # sigma_min / sigma_max = 0.37 there


def test_a_complex_component_with_one_real_point_is_reported():
    """[[x, -y], [y, x]] is singular only at the origin, the one real point of x**2 + y**2 = 0:
    without it the certificate fails; with it (tests/exact/test_real_points.py) it passes."""
    assert _certify([], sp.Matrix([[x, -y], [y, x]]), (x, y), ()).verdict == "failed"
    locus = rankloci.locus(sp.Matrix([[x, -y], [y, x]]), variables=(x, y))
    assert locus.complete is True
    assert [c.real_points_of for c in locus.components] == [(x ** 2 + y ** 2,)]


def test_irrational_twists_are_made_exact_and_certified(tmp_path):
    path = tmp_path / "twist.toml"
    path.write_text('''name = "twist"
title = "three joints with irrational twists"
convention = "dh"
task = "position"

[[joint]]
kind = "revolute"
a = 1
alpha = "0.3"
d = 0
theta = "0"

[[joint]]
kind = "revolute"
a = 1
alpha = "2*pi/7"
d = "0.2"
theta = "0"

[[joint]]
kind = "revolute"
a = "0.5"
alpha = "0"
d = 0
theta = "0"
''', encoding="utf-8")
    locus = rankloci.locus(str(path))
    assert locus.complete is True, locus.notes
    rotations = [n for n in locus.notes if "constant angle" in n]
    assert len(rotations) == 2 and all("rad from it" in n for n in rotations)


def test_check_refuses_a_locus_file_whose_exclusion_hides_half_the_set(tmp_path, capsys):
    assert main(["locus", "planar2r", "--quiet", "--format", "json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["complete"] is True and doc["certificate"]["verdict"] == "passed"
    doc["components"][0]["excluding"] = ["cos(q2) - 1"]
    path = tmp_path / "hidden.json"
    path.write_text(json.dumps(doc), encoding="utf-8")
    assert main(["check", "planar2r", "--locus", str(path), "--quiet", "--format",
                 "json"]) == 1
    report = json.loads(capsys.readouterr().out)
    assert report["certificate"]["verdict"] == "failed" and report["ok"] is False


def test_check_refuses_a_wrong_rank_drop_in_a_locus_file(tmp_path, capsys):
    assert main(["locus", "planar2r", "--quiet", "--format", "json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    doc["components"][0]["rank_drop"] = 2
    path = tmp_path / "drop.json"
    path.write_text(json.dumps(doc), encoding="utf-8")
    assert main(["check", "planar2r", "--locus", str(path), "--quiet"]) == 1


def test_certify_locus_substitutes_the_models_parameter_values():
    """puma560's locus keeps a2, a3, d4 symbolic; the certificate is for the model's values."""
    model = rankloci.load_model("puma560")
    locus = rankloci.locus(model, verify=False)
    assert locus.complete is None
    cert = certify_locus(locus, task_matrix(model))
    assert cert.verdict == "passed" and cert.witness_points == {1: 8}


def test_every_command_shows_the_locus_rankloci_locus_certified():
    from rankloci.api.calls import certified_locus, check
    from rankloci.api.near import nearest_component

    model = rankloci.load_model("planar2r")
    shown = rankloci.locus(model)
    assert certified_locus(model)[0] is shown
    assert check(model, samples=2).certificate is shown.certificate
    assert nearest_component(model, [0.3, 0.5]).component == 1


@pytest.mark.parametrize("matrix, variables", [
    (sp.Matrix([[sp.sin(x) - 3 - sp.sqrt(2)]]), (x,)),
    (sp.Matrix([[sp.sin(x) - 3 - sp.sqrt(2), y]]), (x, y)),
])
def test_a_sine_fixed_beyond_one_is_a_complex_component_without_real_points(matrix, variables):
    """sin x = 3 + sqrt(2) holds at complex x only; tan(x/2) there has a minimal polynomial
    of degree 4 over Q, so the witness points show the sine fixed, not the half tangent.  With
    y = 0 it is found on the slice y = 0 and lifted."""
    locus = rankloci.locus(matrix, variables=variables)
    assert locus.complete is True and locus.components == ()
    (eqs,) = locus.certificate.complex_components
    assert sp.sin(x) - 3 - sp.sqrt(2) in eqs
    assert any("without real points" in n for n in locus.notes)


def test_check_counts_complex_components_of_a_locus_file_only_when_proved(tmp_path, capsys):
    """A locus file lists sin x = 3 + sqrt(2), y = 0 as a component without real points:
    check proves it again and passes.  The same claim for sin x = 1/2, y = 0, which has real
    points, is not proved, and the file is refused."""
    model = tmp_path / "complex.toml"
    model.write_text('variables = ["x", "y"]\nmatrix = [["sin(x) - 3 - sqrt(2)", "y"]]\n',
                     encoding="utf-8")
    assert main(["locus", str(model), "--quiet", "--format", "json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["components"] == [] and len(doc["certificate"]["complex_components"]) == 1
    saved = tmp_path / "complex.json"
    saved.write_text(json.dumps(doc), encoding="utf-8")
    assert main(["check", str(model), "--locus", str(saved), "--quiet"]) == 0
    capsys.readouterr()

    real = tmp_path / "real.toml"
    real.write_text('variables = ["x", "y"]\nmatrix = [["sin(x) - 1/2", "y"]]\n',
                    encoding="utf-8")
    doc["certificate"]["complex_components"] = [["y", "sin(x) - 1/2"]]
    saved.write_text(json.dumps(doc), encoding="utf-8")
    assert main(["check", str(real), "--locus", str(saved), "--quiet"]) == 1
    assert "lie on no reported component" in capsys.readouterr().out


def test_values_and_lifts_at_points_over_the_prime_field_agree_with_direct_sums():
    """Values of a polynomial at a point of GF(P) (flint's evaluation), and the polynomial in
    the last variable left once the others are fixed (flint's substitution), against sums of
    the terms computed by hand modulo P."""
    import random

    import flint

    from rankloci.exact.witness import _at, _value

    P = 2 ** 61 - 1
    F = flint.fq_default_ctx(P, 1)
    ctx = flint.nmod_mpoly_ctx.get(("u0", "u1", "u2"), modulus=P)
    rng = random.Random(7)
    for _ in range(20):
        terms = {(rng.randrange(4), rng.randrange(4), rng.randrange(3)): rng.randrange(P)
                 for _ in range(rng.randrange(1, 9))}
        p = ctx.from_dict(terms)
        point = [rng.randrange(P) for _ in range(3)]

        def by_hand(xs, terms=terms):
            return sum(c * pow(xs[0], a, P) * pow(xs[1], b, P) * pow(xs[2], e, P)
                       for (a, b, e), c in terms.items()) % P

        assert _value(p, [F(x) for x in point], F) == F(by_hand(point))
        lifted = _at(p, [F(x) for x in point[:2]], F, 2)
        assert lifted(F(point[2])) == F(by_hand(point))
