"""The certificate and the self-check that run before a locus is shown (rankloci.verify)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import sympy as sp

from rankloci.io import load_model
from rankloci.jacobians import task_matrix
from rankloci.methods import compute_locus, method_for
from rankloci.verify import dimension_bound, dimension_findings, verified_locus


def _compute(t, seed, hints=(), method=None):
    return compute_locus(t, method or method_for(t.shape), rng=np.random.default_rng(seed),
                         hints=hints)


def _planar3r():
    model = load_model("planar3r")
    return task_matrix(model, frame="auto"), task_matrix(model)


@pytest.mark.parametrize("shape, nvars, drop, bound", [
    ((2, 3), 3, 1, 1), ((6, 6), 6, 1, 5), ((6, 7), 7, 1, 5), ((6, 10), 10, 1, 5),
    ((6, 6), 6, 2, 2), ((7, 6), 6, 1, 4), ((2, 4), 4, 2, 0)])
def test_dimension_bound_is_the_eagon_northcott_codimension(shape, nvars, drop, bound):
    """codim <= k (m - n + k) for rank n - k of an n x m matrix, n <= m."""
    assert dimension_bound(shape, nvars, drop) == bound


def test_a_correct_locus_passes_at_the_first_attempt():
    """The certificate proves it: the numeric self-check, which could only add a
    recomputation to a locus that fails, is not run."""
    tm, ref = _planar3r()
    said = []
    locus, v = verified_locus(_compute, tm, ref, seed=0, progress=said.append)
    assert v.complete and locus.complete is True
    assert v.attempts == ("as computed: certificate passed",)
    assert locus.certificate.verdict == "passed"
    assert not dimension_findings(locus)
    assert not [m for m in said if m.startswith("self-check")]


def _too_large(t, seed, hints=(), method=None):
    """A locus whose component sin q3 = 0 leaves q2 free, where the planar arm's position is
    singular only where sin q2 = 0 too: the certificate fails it, whatever the hints."""
    locus = _compute(t, seed)
    q2, q3 = t.variables[1], t.variables[2]
    (c,) = locus.components
    return dataclasses.replace(locus, components=(dataclasses.replace(
        c, equations=(sp.sin(q3),), solved=(), free=(q2,)),))


def test_the_self_check_reports_its_progress():
    """Refining points in extended precision can take seconds each on long chains: the
    self-check of a locus that the certificate does not prove says which part it is at."""
    tm, ref = _planar3r()
    said = []
    verified_locus(_too_large, tm, ref, seed=0, progress=said.append)
    checks = [m for m in said if m.startswith("self-check")]
    assert "self-check: component 1 of 1" in checks
    assert checks[-2:] == ["self-check: random configurations off the locus",
                           "self-check: singular points found by minimising sigma_min/sigma_max"]
    assert said.index("certificate: witness points of the locus, modulo a prime") \
        < said.index(checks[-1])


def test_a_locus_missing_its_component_is_recomputed():
    """The first computation loses the component (sin q2 = 0 ...); the check sees singular points
    on no component and the next attempt, correct, is returned with a note."""
    tm, ref = _planar3r()
    calls = []

    def flaky(t, seed, hints=(), method=None):
        calls.append(seed)
        locus = _compute(t, seed)
        return dataclasses.replace(locus, components=()) if len(calls) == 1 else locus

    locus, v = verified_locus(flaky, tm, ref, seed=0)
    # q2, q3 in {0, pi}: the certificate's witness points give the component directly
    assert len(calls) == 1
    assert v.complete and locus.complete is True
    (c,) = locus.components
    assert set(c.solved) == set(tm.variables[1:]) and c.dimension == 1
    assert any("found from the witness points" in n for n in locus.notes)


def test_regular_points_found_by_the_check_go_back_as_hints():
    """The first locus reports sin q3 = 0 with q2 free, where the planar arm's position is
    singular only where sin q2 = 0 too.  The check finds it regular at its points, and the
    next computation gets those configurations."""
    tm, ref = _planar3r()
    q2, q3 = tm.variables[1], tm.variables[2]
    got = []

    def computed(t, seed, hints=(), method=None):
        got.append(hints)
        locus = _compute(t, seed)
        if hints:
            return locus
        (c,) = locus.components
        return dataclasses.replace(locus, components=(dataclasses.replace(
            c, equations=(sp.sin(q3),), solved=(), free=(q2,)),))

    locus, v = verified_locus(computed, tm, ref, seed=0)
    assert got[0] == () and len(got) == 2 and got[1]
    for q in got[1]:
        assert set(q) == {"q1", "q2", "q3"}
        assert abs(np.sin(q["q3"])) < 1e-6 and abs(np.sin(q["q2"])) > 1e-3
    assert v.complete and v.attempts[0] == "as computed: certificate failed, numeric check failed"
    assert v.attempts[1].startswith(f"as computed, with the {len(got[1])} configuration")
    assert v.attempts[1].endswith("certificate passed, numeric check passed")


def test_a_locus_that_never_passes_is_marked_incomplete():
    tm, ref = _planar3r()

    q1 = tm.variables[0]

    def broken(t, seed, hints=(), method=None):
        # a component that is regular at its points, whatever the hints
        c = dataclasses.replace(_compute(t, seed).components[0], equations=(sp.sin(q1),),
                                solved={}, free=tm.variables[1:], dimension=2)
        return dataclasses.replace(_compute(t, seed), components=(c,))

    locus, v = verified_locus(broken, tm, ref, seed=0)
    assert not v.complete and locus.complete is False
    assert len(v.attempts) >= 3 and all("certificate failed" in a for a in v.attempts)
    assert any("regular" in p for p in v.problems)
    assert any(n.startswith("INCOMPLETE") for n in locus.notes)
    assert locus.to_dict()["complete"] is False


def test_a_component_below_the_bound_is_reported():
    tm, ref = _planar3r()
    locus = _compute(tm, 0)
    low = dataclasses.replace(locus, components=tuple(
        dataclasses.replace(c, dimension=0) for c in locus.components))
    (finding,) = dimension_findings(low)
    assert "below the bound 1" in finding


@pytest.mark.slow
def test_the_base_locus_certificate_knows_components_without_real_points(robots):
    """The Panda with its elbow height as a constraint row: the witness points of J's own locus
    that lie on no component lie on 17 sin q6 + 22 = 0, which has no real point.  The
    certificate of J's locus counts them there, as the certificate of J_aug's does, and the
    locus, unchanged, is certified."""
    import rankloci

    locus = rankloci.locus(robots / "panda_description/urdf/panda.urdf", base_link="panda_link0",
                           tip="panda_link8", augment=["position(4, z)"], jobs=1)
    assert locus.complete is True and locus.base.complete is True
    assert locus.base.certificate.complex_components
    assert len(locus.base.components) == 5
    assert any("without real points" in n and "17*sin(q6) + 22" in n for n in locus.base.notes)


@pytest.mark.parametrize("findings, numeric_ok, expected", [
    # witness points of codimension 3 (coordinate slices) on no component, nothing else: the
    # complex locus has more, the real one is undecided
    (("8 of the 176 witness points of codimension 3 lie on no reported component: a "
      "component of dimension 5 is missing",), True, None),
    (("8 of the 176 witness points of codimension 3 lie on no reported component: a "
      "component of dimension 5 is missing",
      "component 1 (dimension 5) is not certified: its witness points need too large an "
      "elimination, and it is not given in solved form"), True, None),
    # ... but not when the numeric check found the locus wrong
    (("8 of the 176 witness points of codimension 3 lie on no reported component: a "
      "component of dimension 5 is missing",), False, False),
    # of codimension 1 or 2 they refuse the locus, as does any unsound component
    (("2 of the 8 witness points of codimension 2 lie on no reported component: a "
      "component of dimension 4 is missing",), True, False),
    (("8 of the 176 witness points of codimension 3 lie on no reported component: a "
      "component of dimension 5 is missing",
      "component 13: the matrix is regular at a witness point of the component"), True, False),
])
def test_points_of_codimension_three_on_no_component_leave_the_real_locus_undecided(
        findings, numeric_ok, expected):
    from rankloci.exact.certificate import Certificate
    from rankloci.verify import _complete

    cert = Certificate("failed", prime=2305843009213693951, seed=0, codimensions=(1, 2, 3),
                       findings=findings)
    assert _complete(cert, numeric_ok) is expected
    assert _complete(dataclasses.replace(cert, verdict="passed", findings=()), True) is True
