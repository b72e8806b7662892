"""Augmented Jacobians: loci of J and J_aug, and each J_aug component classified.

Each expected answer is derived by hand in the test's docstring, independently of the engine.
Numeric checks use the test helpers' own J(q) (lambdified from the model, not the engine's
polynomial ring), the SVD, and the FSP reducer.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
import sympy as sp

import locus_helpers as H
from rankloci.augmented import augmented_locus, expand_preset, parse_augment
from rankloci.cli import main
from rankloci.errors import ModelError
from rankloci.io import load_model
from rankloci.jacobians import task_matrix
from rankloci.numeric.fsp import dependent_rows
from rankloci.tolerances import RANK_RTOL

SEED = 20241122

#: A configuration is "regular" for J when sigma_min/sigma_max is above this.  At points of an
#: algorithmic component that are generic (solved from random starts) the ratio of J is of
#: order 1e-2 and up; RANK_RTOL (1e-8) is where the package calls a matrix singular, and this
#: leaves five orders of margin on the regular side.
REGULAR_RATIO = 1e3 * RANK_RTOL


def _loci(name, augment=(), numeric=True):
    model = load_model(name)
    tm = task_matrix(model, frame="auto", augment=parse_augment(model, augment), numeric=numeric)
    return model, tm, augmented_locus(model, tm, seed=SEED)


def _main_components(locus):
    return [c for c in locus.components if c.for_model]


def _on(comp, tm, q, tol=1e-9):
    return H.ComponentEquations(comp, tm).residual(q) <= tol


def _points(comp, tm, rng, n=5):
    eqs = H.ComponentEquations(comp, tm)
    return [H.sample_point(comp, tm)] + H.points_on(eqs, tm, rng, n)


def _same_set(comps, expected, tm, rng):
    """The union of ``comps`` is the set where ``expected`` vanish: every point of a component
    satisfies the expected equations, and every point of the expected set lies on a component."""
    comps = comps if isinstance(comps, list) else [comps]
    want = H.ComponentEquations(type("E", (), {"equations": expected})(), tm)
    for comp in comps:
        for q in _points(comp, tm, rng):
            assert want.residual(q) <= 1e-9, (H.describe(comp), H.fmt(q, tm.variables))
    for q in H.points_on(want, tm, rng, 6):
        assert any(_on(c, tm, q) for c in comps), ([H.describe(c) for c in comps],
                                                  H.fmt(q, tm.variables))


# --- presets --------------------------------------------------------------------------------

def test_presets_expand_to_plain_expressions():
    m = load_model("pa10")
    q = m.variables
    assert expand_preset(m, "lock(q3)") == ("lock(q3)", q[2])
    assert expand_preset(m, "sum(q1, q2, q3)")[1] == q[0] + q[1] + q[2]
    # elbow of the PA10 = origin of frame 3: d1 + d3 cos q2 above the base at any q1
    d1, d3 = sp.Symbol("d1", real=True), sp.Symbol("d3", real=True)
    z = expand_preset(m, "elbow(z)")[1]
    assert sp.simplify(z - (d1 + d3 * sp.cos(q[1]))) == 0
    assert expand_preset(m, "q1 + q2") is None       # not a preset: a plain expression
    assert expand_preset(m, "position(5, x)")[1] == expand_preset(m, "wrist(x)")[1]


@pytest.mark.parametrize("text, message", [
    ("lock(q9)", "not a joint variable"),
    ("lock(q1, q2)", "takes one joint variable"),
    ("position(3, w)", "is not x, y or z"),
    ("position(12, x)", "link frame 12 is not in"),
    ("shoulder(z)", None),
])
def test_bad_presets_are_model_errors(text, message):
    m = load_model("pa10")
    if message is None:
        # an unknown call is not a preset; as an expression it names an unknown function
        with pytest.raises(ModelError):
            parse_augment(m, [text])
        return
    with pytest.raises(ModelError, match=message):
        expand_preset(m, text)


def test_bad_preset_on_the_command_line_exits_2(capsys):
    assert main(["locus", "planar3r", "--augment", "lock(q7)", "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "q7" in err[0]


# --- published / derived cases --------------------------------------------------------------

def test_planar3r_with_orientation_row_is_one_mixed_component():
    """Planar 3R, task (x, y), constraint q1 + q2 + q3 (the end-effector orientation).

    Derivation: with v the tip velocity and w = q1' + q2' + q3', the velocity of joint 3's
    position is v3 = v - w z x (p - p3).  This row operation turns J_aug into
    [[J3, 0], [1 1, 1]] with J3 the 2x2 position Jacobian of the two-link arm (links 1, 2) to
    joint 3, so det J_aug = det J3 = l1 l2 sin q2.  The locus of J_aug is {sin q2 = 0}.
    J itself (2x3) loses rank only when all three links are collinear: {sin q2 = sin q3 = 0}
    (Siciliano et al., Robotics, Springer 2009, Sec. 3.3).  On {sin q2 = 0} J has full rank at
    generic q3, so the component is not kinematic; it contains J's locus, so it is mixed, and
    it meets J's only component.
    """
    model, tm, locus = _loci("planar3r_orient")
    rng = np.random.default_rng(SEED)
    q1, q2, q3 = tm.variables
    comps = _main_components(locus)
    assert len(comps) == 1, [H.describe(c) for c in comps]
    _same_set(comps[0], (sp.sin(q2),), tm, rng)
    assert comps[0].kind == "mixed"
    base = _main_components(locus.base)
    assert 1 <= len(base) <= 2, [H.describe(c) for c in base]
    _same_set(base, (sp.sin(q2), sp.sin(q3)), tm, rng)
    assert sorted(m["base_component"] for m in comps[0].meets) == list(range(1, len(base) + 1))


def test_planar4r_with_orientation_constraint():
    """Planar 4R (Ha & Lee's arm), task (x, y), constraint q1 + q2 + q3 + q4.

    Derivation as for the 3R: the row operation v4 = v - w z x (p - p4) leaves
    [[J4, 0], [1 1 1, 1]] with J4 the 2x3 position Jacobian of the three-link arm to joint 4.
    J_aug (3x4) loses rank exactly where J4 does: links 1, 2, 3 collinear,
    {sin q2 = sin q3 = 0}, with q1 and q4 free (dimension 2).  J loses rank where all four
    links are collinear, {sin q2 = sin q3 = sin q4 = 0} (dimension 1).  At generic q4 J is
    regular on the J_aug component, which contains J's locus: mixed.
    """
    model, tm, locus = _loci("planar4r", ["sum(q1, q2, q3, q4)"])
    rng = np.random.default_rng(SEED)
    q1, q2, q3, q4 = tm.variables
    comps = _main_components(locus)
    assert len(comps) == 1, [H.describe(c) for c in comps]
    _same_set(comps[0], (sp.sin(q2), sp.sin(q3)), tm, rng)
    assert comps[0].dimension == 2 and comps[0].kind == "mixed"
    # J's locus may come as one component or as its q2 = 0 and q2 = pi halves
    base = _main_components(locus.base)
    assert 1 <= len(base) <= 2, [H.describe(c) for c in base]
    _same_set(base, (sp.sin(q2), sp.sin(q3), sp.sin(q4)), tm, rng)


def test_joint_function_constraint_adds_algorithmic_components():
    """Planar 3R, task (x, y), constraint g = sin q2, gradient (0, cos q2, 0).

    Derivation: det [J; grad g] = -cos q2 * (minor of J without column 2)
    = -cos q2 * (l1 l3 sin(q2 + q3) + l2 l3 sin q3).  On {cos q2 = 0} the constraint row is
    zero, and J (whose locus needs sin q2 = 0) is regular: an algorithmic component.  The other
    factor vanishes at q2 = q3 = 0, where J is singular, and is regular elsewhere: mixed.  With
    the model's equal lengths l1 = l2 it splits, sin(q2 + q3) + sin q3
    = 2 sin(q2/2 + q3) cos(q2/2), so the mixed part may come as two components; their union is
    what is checked.
    """
    model, tm, locus = _loci("planar3r", ["sin(q2)"])
    rng = np.random.default_rng(SEED)
    q1, q2, q3 = tm.variables
    l1, l2 = (sp.Symbol(n, real=True) for n in ("l1", "l2"))
    comps = _main_components(locus)
    by_kind = {k: [c for c in comps if c.kind == k] for k in ("kinematic", "algorithmic", "mixed")}
    assert not by_kind["kinematic"], [H.describe(c) for c in comps]
    assert len(by_kind["algorithmic"]) == 1 and by_kind["mixed"], [H.describe(c) for c in comps]
    _same_set(by_kind["algorithmic"], (sp.cos(q2),), tm, rng)
    values = H.model_tm("planar3r", False).parameters
    mixed = (l1 * sp.sin(q2 + q3) + l2 * sp.sin(q3)).subs(values)
    _same_set(by_kind["mixed"], (mixed,), tm, rng)


def test_algorithmic_points_numerically():
    """At points of each algorithmic component: J_aug singular, J regular, and the FSP
    reducer names a constraint row among the dependent rows of J_aug."""
    model, tm, locus = _loci("planar3r", ["sin(q2)"])
    rng = np.random.default_rng(SEED)
    nj_aug = H.numeric_j(tm)
    nj = H.numeric_j(task_matrix(model, frame="auto", numeric=True))
    n_task = tm.shape[0] - tm.n_constraint_rows
    algorithmic = [c for c in _main_components(locus) if c.kind == "algorithmic"]
    assert algorithmic
    for comp in algorithmic:
        pts = _points(comp, tm, rng, n=6)
        assert len(pts) >= 5
        for q in pts:
            J_aug, J = nj_aug(q), nj(q)
            assert H.sigma_ratio(J_aug) <= RANK_RTOL, H.fmt(q, tm.variables)
            assert H.sigma_ratio(J) >= REGULAR_RATIO, H.fmt(q, tm.variables)
            dep = dependent_rows(J_aug)
            assert any(i >= n_task for i in dep), (dep, H.fmt(q, tm.variables))


def test_tall_augmented_matrix_has_only_kinematic_components():
    """PUMA 560 with joint 1 locked: J_aug is 7x6.

    Derivation: a tall J_aug loses rank (below 6) only where J does, since its rows include
    J's; so no component can be algorithmic or mixed.  J_aug is singular on a component of J
    exactly when the joint-space null motion of J there does not move joint 1: at the wrist
    singularity (s5 = 0) the null motion is q4' = -q6' (axes 4 and 6 aligned), at the elbow
    singularity (d4 c3 + a3 s3 = 0 in this model's DH convention, as in test_locus) it involves
    joints 2..6 only, while at the shoulder singularity (wrist centre on axis 1) the null motion
    turns joint 1.  So the locus of J_aug
    is the wrist and the elbow singularity, both kinematic.
    """
    model, tm, locus = _loci("puma560", ["lock(q1)"])
    rng = np.random.default_rng(SEED)
    q = tm.variables
    values = H.model_tm("puma560", False).parameters
    a3, d4 = (sp.Symbol(n, real=True) for n in ("a3", "d4"))
    comps = _main_components(locus)
    assert {c.kind for c in comps} == {"kinematic"}
    assert len(comps) == 2, [H.describe(c) for c in comps]
    wrist = [c for c in comps if c.solved.get(q[4])]
    elbow = [c for c in comps if not c.solved.get(q[4])]
    assert len(wrist) == 1 and len(elbow) == 1
    _same_set(wrist[0], (sp.sin(q[4]),), tm, rng)
    _same_set(elbow[0], ((d4 * sp.cos(q[2]) + a3 * sp.sin(q[2])).subs(values),), tm, rng)


RAW_NO_ALGORITHMIC = ('name = "raw"\nvariables = ["x", "y", "z"]\n'
                      'matrix = [["1", "0", "0"], ["0", "cos(z)", "-cos(y)"]]\n')


def test_constraint_that_adds_no_algorithmic_singularity(write_file):
    """J = [[1, 0, 0], [0, cos z, -cos y]] with g = sin y + sin z, gradient (0, cos y, cos z).

    Derivation: J loses rank exactly where its second row vanishes, cos y = cos z = 0.
    det J_aug = cos(z)**2 + cos(y)**2, whose real zeros are the same four lines (x free):
    the constraint adds no singularity, and the only component is kinematic.  There the
    constraint row vanishes too, so J_aug has rank 1: a rank drop of 2.  (The determinant
    has real zeros only where its gradient vanishes as well; the locus must still find them.)
    """
    path = write_file("raw.toml", RAW_NO_ALGORITHMIC)
    model = load_model(str(path))
    tm = task_matrix(model, augment=parse_augment(model, ["sin(y) + sin(z)"]))
    locus = augmented_locus(model, tm, seed=SEED)
    rng = np.random.default_rng(SEED)
    x, y, z = tm.variables
    comps = _main_components(locus)
    assert comps and {c.kind for c in comps} == {"kinematic"}, [H.describe(c) for c in comps]
    assert all(c.rank_drop == 2 and c.dimension == 1 for c in comps)
    _same_set(comps, (sp.cos(y), sp.cos(z)), tm, rng)


@pytest.mark.slow
def test_ssrms_with_joint_3_locked():
    """SSRMS, full 6x7 task, joint 3 locked (the model ssrms_lock3): J_aug is 7x7.

    Derivation: expanding det J_aug along the constraint row e3 gives
    det J_aug = +-det J_(-3), the 6x6 Jacobian of the arm without joint 3, so the locus of
    J_aug is the hypersurface {det J_(-3) = 0} (dimension 6; checked here numerically with the
    helpers' own J).  J loses rank on sets of dimension 5 (a 6x7 matrix drops rank in
    codimension 2 generically, and every SSRMS component found has dimension 5), so no J_aug
    component lies inside J's locus: none is kinematic.  Every configuration where J is
    singular makes J_aug singular (J's rows are rows of J_aug), so each component of J's locus
    lies in a component of J_aug, which is therefore mixed, and every J component is met.
    """
    model, tm, locus = _loci("ssrms_lock3")
    rng = np.random.default_rng(SEED)
    base_tm = task_matrix(model, frame="auto", numeric=True, use_model_augment=False)
    nj = H.numeric_j(base_tm)
    comps = _main_components(locus)
    assert comps and {c.kind for c in comps} == {"mixed"}
    assert all(c.dimension == 6 for c in comps)

    def scaled_minor(q):
        Jm = np.delete(nj(q), 2, axis=1)
        return abs(np.linalg.det(Jm)) / np.prod(np.linalg.norm(Jm, axis=0))

    for comp in comps:
        for q in _points(comp, tm, rng, n=4):
            assert scaled_minor(q) <= 1e-9, H.fmt(q, tm.variables)
    # completeness: singular points of J_aug from random starts lie on a component
    nj_aug = H.numeric_j(tm)
    found = 0
    for _ in range(12):
        q, ratio = H.minimise_sigma_ratio(nj_aug, H.random_q(tm, rng))
        if ratio <= RANK_RTOL:
            found += 1
            assert any(_on(c, tm, q, 1e-6) for c in comps), H.fmt(q, tm.variables)
    assert found >= 6
    met = {m["base_component"] for c in comps for m in c.meets}
    n_base = len(_main_components(locus.base))
    assert n_base >= 1 and met == set(range(1, n_base + 1))


# --- output -------------------------------------------------------------------------------

def test_json_has_kind_per_component_and_the_base_locus(capsys):
    assert main(["locus", "planar3r", "--augment", "sin(q2)", "--format", "json", "--quiet"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["base_locus"]["schema"] == "rankloci.locus/2"
    assert data["base_locus"]["matrix"] == {"rows": 2, "cols": 3}
    assert all(c["for_model"] for c in data["components"])
    kinds = [c["kind"] for c in data["components"]]
    assert sorted(set(kinds)) == ["algorithmic", "mixed"]
    assert all("kind" in c and "meets" in c for c in data["components"])


def test_unaugmented_json_has_no_kind(capsys):
    assert main(["locus", "planar2r", "--format", "json", "--quiet"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert "base_locus" not in data and all("kind" not in c for c in data["components"])


def test_text_output_names_the_kinds(capsys):
    assert main(["locus", "planar3r_orient", "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "kind: mixed" in out and "classification: 0 kinematic, 0 algorithmic, 1 mixed" in out
    assert "locus of J without the constraint rows" in out


# --- certificate of the base locus -----------------------------------------------------------

#: planar3r's position Jacobian (2x3) loses rank where the arm is stretched or folded:
#: sin q2 = sin q3 = 0.  Augmented with the orientation q1 + q2 + q3, J_aug is square.
ORIENTATION = ("q1 + q2 + q3",)


def _augmented_reference():
    from rankloci.jacobians import task_matrix as tm_of

    model = load_model("planar3r")
    return tm_of(model, augment=parse_augment(model, ORIENTATION))


def _base_reference(tm):
    import dataclasses

    rows = tm.shape[0] - tm.n_constraint_rows
    return dataclasses.replace(tm, matrix=tm.matrix[:rows, :], n_constraint_rows=0)


def test_the_base_locus_of_an_augmented_matrix_carries_a_passing_certificate():
    import rankloci
    from rankloci.certify import certify_locus

    locus = rankloci.locus("planar3r", augment=list(ORIENTATION))
    assert locus.complete is True and locus.certificate.verdict == "passed"
    assert locus.base.complete is True and locus.base.certificate.verdict == "passed"
    assert locus.to_dict()["base_locus"]["certificate"]["verdict"] == "passed"
    # the base certificate is of J alone: its locus proves complete for J, not for J_aug
    tm = _augmented_reference()
    base_ref = _base_reference(tm)
    assert certify_locus(locus.base, base_ref).verdict == "passed"
    assert certify_locus(locus.base, tm).verdict == "failed"


def test_a_wrong_base_locus_fails_the_augmented_locus():
    """The augmented components are right, but the base locus reports only q3 = pi of
    sin q3 = 0: the certificate of the base refuses it, and the augmented locus is not
    called complete."""
    import dataclasses

    import rankloci
    from rankloci.certify import certify_locus
    from rankloci.loci import Component
    from rankloci.verify import verified_locus

    locus = rankloci.locus("planar3r", augment=list(ORIENTATION))
    q1, q2, q3 = locus.variables
    half = Component((sp.sin(q2), sp.cos(q3 / 2)), solved={q2: (0, sp.pi), q3: (sp.pi,)},
                     free=(q1,), dimension=1)
    wrong_base = dataclasses.replace(locus.base, components=(half,), certificate=None,
                                     complete=None)
    tm = _augmented_reference()
    cert = certify_locus(wrong_base, _base_reference(tm))
    assert cert.verdict == "failed"
    assert any("lie on no reported component" in f for f in cert.findings)

    wrong = dataclasses.replace(locus, base=wrong_base, certificate=None, complete=None)
    shown, verification = verified_locus(lambda t, s, **options: wrong, tm, tm, samples=2)
    assert shown.complete is False and not verification.complete
    assert shown.certificate.verdict == "failed"
    assert any(f.startswith("the locus of J without the constraint rows:")
               for f in shown.certificate.findings)
    assert shown.base.certificate.verdict == "failed" and shown.base.complete is False
