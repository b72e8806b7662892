"""cross_check: passes on computed loci, fails on wrong ones (the checks can fail).

Seeds are fixed (SEED below) and appear in every report.
"""

from __future__ import annotations

import dataclasses
import functools

import numpy as np
import pytest
import sympy as sp

from rankloci.io import load_model
from rankloci.loci import Component
from rankloci.jacobians import task_matrix
from rankloci.methods import compute_locus
from rankloci.numeric.crosscheck import cross_check, parse_locus, render_check_text
from rankloci.numeric.minors import relative_max_minor
from rankloci.numeric.svd import numeric_rank_drop, sigma_ratio
from rankloci.errors import ModelError

SEED = 20240611
SAMPLES = 6


@functools.lru_cache(maxsize=None)
def _setup(name):
    model = load_model(name)
    tm = task_matrix(model, frame="auto", numeric=True)
    locus = compute_locus(tm, rng=np.random.default_rng(SEED))
    return model, locus, task_matrix(model)


def _check(name, locus=None):
    model, computed, J = _setup(name)
    return cross_check(computed if locus is None else locus, J.matrix, J.variables,
                       angles=J.angles, parameters=J.parameters, samples=SAMPLES,
                       rng=np.random.default_rng(SEED), seed=SEED)


def _with(locus, components):
    return dataclasses.replace(locus, components=tuple(components))


def _sym(name, var):
    return {v.name: v for v in _setup(name)[0].variables}[var]


@pytest.mark.parametrize("name", ["planar2r", "planar3r", "puma560"])
def test_computed_locus_passes(name):
    report = _check(name)
    assert report.ok, render_check_text(report)
    assert all(len(c.points) == SAMPLES for c in report.components)
    assert len(report.off_locus) == SAMPLES
    assert report.probe_singular >= 1
    d = report.to_dict()
    assert d["schema"] == "rankloci.check/1" and d["seed"] == SEED and d["ok"]


def test_missing_component_fails_completeness():
    """Dropping the PUMA wrist component s5 = 0 leaves singular minima on no component."""
    _, locus, _ = _setup("puma560")
    q5 = _sym("puma560", "q5")
    kept = [c for c in locus.components if c.equations != (sp.sin(q5),)]
    assert len(kept) == len(locus.components) - 1
    report = _check("puma560", _with(locus, kept))
    assert not report.ok and report.uncovered, render_check_text(report)
    assert all(c.ok for c in report.components)


def test_spurious_component_fails_on_locus():
    _, locus, _ = _setup("puma560")
    bogus = Component(equations=(_sym("puma560", "q1"),))
    report = _check("puma560", _with(locus, list(locus.components) + [bogus]))
    assert not report.ok
    assert [c.ok for c in report.components] == [True] * len(locus.components) + [False]


def test_typo_in_equation_fails():
    """sin(q4) instead of sin(q5): J is regular on it and the wrist singularity is uncovered."""
    _, locus, _ = _setup("puma560")
    q4, q5 = _sym("puma560", "q4"), _sym("puma560", "q5")
    comps = [dataclasses.replace(c, equations=(sp.sin(q4),)) if c.equations == (sp.sin(q5),) else c
             for c in locus.components]
    report = _check("puma560", _with(locus, comps))
    assert not report.ok
    assert sum(not c.ok for c in report.components) == 1


def test_an_earlier_check_is_reused_for_the_components_it_passed():
    """A locus recomputed after a failed check differs in a few components: the others keep
    their points and verdict.  Here the earlier check passed PUMA's components but the
    bogus q1 = 0; checked again with it, the correct locus samples no component anew,
    while the bogus one, failed before, is sampled again and fails again."""
    _, locus, J = _setup("puma560")
    bogus = Component(equations=(_sym("puma560", "q1"),))
    first = _check("puma560", _with(locus, [bogus] + list(locus.components)))
    assert [c.ok for c in first.components] == [False] + [True] * len(locus.components)

    def again(loc):
        return cross_check(loc, J.matrix, J.variables, angles=J.angles,
                           parameters=J.parameters, samples=SAMPLES,
                           rng=np.random.default_rng(SEED + 1), earlier=first)

    second = again(locus)
    assert second.ok
    assert [c.points for c in second.components] == [c.points for c in first.components[1:]]
    assert [c.index for c in second.components] == list(range(1, len(locus.components) + 1))
    # the q1 = 0 component failed before: not taken from the earlier check
    third = again(_with(locus, [bogus]))
    assert not third.components[0].ok
    assert third.components[0].points != first.components[0].points
    # the same equations with another rank drop are another component: sampled anew
    changed = dataclasses.replace(locus.components[0], rank_drop=2)
    fourth = again(_with(locus, [changed]))
    assert fourth.components[0].points != first.components[1].points


def test_component_without_real_points_fails():
    _, locus, _ = _setup("planar2r")
    q2 = _sym("planar2r", "q2")
    report = _check("planar2r", _with(locus, list(locus.components)
                                      + [Component(equations=(sp.cos(q2) + 2,))]))
    assert not report.ok
    assert report.components[-1].points == () and "no point" in report.components[-1].message


def test_parse_locus_round_trip_and_errors():
    model, locus, _ = _setup("puma560")
    data = locus.to_dict()
    parsed = parse_locus(data, model)
    assert [c.equations for c in parsed.components] == [c.equations for c in locus.components]
    with pytest.raises(ModelError, match="schema"):
        parse_locus(data | {"schema": "nope"}, model)
    with pytest.raises(ModelError, match="variables"):
        parse_locus(data | {"variables": ["x"]}, model)
    with pytest.raises(ModelError, match="cannot parse"):
        parse_locus(data | {"components": [{"equations": ["sin(q7)"]}]}, model)


def test_svd_and_minors_agree_on_simple_matrices():
    singular = np.array([[1.0, 2.0, 3.0], [2.0, 4.0, 6.0]])
    regular = np.array([[1.0, 0.0, 0.0], [0.0, 1e3, 0.0]])
    assert sigma_ratio(singular) < 1e-15 and int(numeric_rank_drop(singular)) == 1
    assert relative_max_minor(singular) < 1e-15
    # scale-free: a row in millimetres instead of metres gives the same value
    assert relative_max_minor(regular) == pytest.approx(1.0)
    assert relative_max_minor(regular.T) == pytest.approx(1.0)
    batch = np.stack([singular, regular])
    assert sigma_ratio(batch).shape == (2,)


def test_excluded_sets_are_respected():
    """{sin q2 cos q1 = 0} holds the regular line cos q1 = 0 too; with cos q1 excluded the
    component is the closure of {sin q2 = 0, cos q1 != 0}, the planar 2R locus itself."""
    model, locus, _ = _setup("planar2r")
    q1, q2 = _sym("planar2r", "q1"), _sym("planar2r", "q2")
    wide = Component(equations=(sp.sin(q2) * sp.cos(q1),))
    assert not _check("planar2r", _with(locus, [wide])).ok
    closed = dataclasses.replace(wide, excluding=(sp.cos(q1),))
    report = _check("planar2r", _with(locus, [closed]))
    assert report.ok, render_check_text(report)
    assert all(abs(np.cos(p.q[0])) > 1e-4 for p in report.components[0].points)
    data = _with(locus, [closed]).to_dict()
    assert data["components"][0]["excluding"] == ["cos(q1)"]
    assert parse_locus(data, model).components[0].excluding == (sp.cos(q1),)


def test_points_near_a_multiple_root_are_refined(monkeypatch):
    """sin(q2)**3 = 0 is the planar 2R locus with a triple root: double-precision least squares
    stops with |sin q2| ~ 1e-5 (scaled residual 1e-15), where J's sigma ratio is ~1e-5.  The
    check refines such points onto the equations before it calls them regular."""
    from rankloci.numeric.equations import Equations

    _, locus, _ = _setup("planar2r")
    q2 = _sym("planar2r", "q2")
    cubed = _with(locus, [Component(equations=(sp.sin(q2) ** 3,))])
    report = _check("planar2r", cubed)
    assert report.ok, render_check_text(report)
    assert all(abs(np.sin(p.q[1])) < 1e-12 for p in report.components[0].points)
    # without the refinement the extended-precision decision still finds them singular ...
    monkeypatch.setattr(Equations, "refined", lambda self, q: np.asarray(q, dtype=float))
    report = _check("planar2r", cubed)
    assert report.ok and any(p.precise == "singular" for p in report.components[0].points)
    # ... and without either the same points are regular beyond RANK_RTOL: the check needs one
    monkeypatch.setattr(Equations, "precise", lambda self, q, digits: None)
    assert not _check("planar2r", cubed).ok


def test_points_are_refined_onto_equations_with_dependent_gradients():
    """x - y = 0 and 2 y - 2 x = 0: the gradients are dependent everywhere, as those of a
    component's equations are when there are more of them than its codimension (nine for a
    3-dimensional component in nine joints on romeo_laas_small's gripper chain, where the
    double-precision solves stop 1e-5 away from it, at sigma ratios up to 1e-5).  The
    least-norm Newton step must still move a point near the line onto it."""
    from rankloci.numeric.equations import Equations

    x, y = sp.symbols("x y")
    eqs = Equations([x - y, 2 * y - 2 * x], (x, y), {})
    q = np.array([0.3, 0.3 + 1e-4])
    p = eqs.refined(q)
    assert abs(p[0] - p[1]) <= 1e-15 and np.max(np.abs(p - q)) <= 1e-4
    assert eqs.settled(q) is not None


def test_extended_precision_separates_singular_from_nearly_singular():
    """Above PRECISE_CHECK_FLOOR the double ratio decides nothing; 50 and 100 digits do."""
    from rankloci.numeric.crosscheck import _decided, _point
    from rankloci.numeric.equations import Equations, NumericMatrix
    from rankloci.tolerances import ON_LOCUS_RTOL, PRECISE_CHECK_FLOOR

    x, y = sp.symbols("x y")
    # singular on x = 1, a double root of the equation: a point 1e-6 away shows 1e-6
    nm = NumericMatrix(sp.Matrix([[x - 1, 0], [0, 1 + y**2]]), (x, y))
    eqs = Equations([(x - 1)**2], (x, y), {})
    p = _point(nm, [1 + 1e-6, 0.3])
    assert PRECISE_CHECK_FLOOR < p.sigma_ratio and p.sigma_ratio > ON_LOCUS_RTOL
    d = _decided(nm, eqs, p)
    assert d.precise == "singular" and not d.regular and d.precise_ratio < 1e-40
    # regular on x = 1 by 1e-12: looks singular in double precision
    nm = NumericMatrix(sp.Matrix([[x - 1 + sp.Rational(1, 10**12), 0], [0, 1]]), (x, y))
    eqs = Equations([x - 1], (x, y), {})
    p = _point(nm, [1.0, 0.3])
    assert PRECISE_CHECK_FLOOR < p.sigma_ratio <= ON_LOCUS_RTOL
    d = _decided(nm, eqs, p)
    assert d.precise == "regular" and d.regular
    assert abs(d.precise_ratio - 1e-12) < 1e-20
    assert d.to_dict()["precise"]["verdict"] == "regular"


@pytest.mark.parametrize("matrix, component", [
    # J vanishes on the component; at its double-precision points only the rounding residue
    # (sin(pi) = 1.2e-16) is left, whose sigma ratio is 1
    ("sines", Component((sp.sin(sp.Symbol("x", real=True)), sp.sin(sp.Symbol("y", real=True))),
                        dimension=0, rank_drop=2)),
    ("one row", Component((sp.cos(sp.Symbol("x", real=True)), sp.Symbol("y", real=True)),
                          dimension=0, rank_drop=1)),
])
def test_a_matrix_that_vanishes_on_a_component_is_singular_there(matrix, component):
    from rankloci.loci import Locus

    x, y = sp.symbols("x y", real=True)
    M = {"sines": sp.Matrix([[sp.sin(x), -sp.sin(y)], [sp.sin(y), sp.sin(x)]]),
         "one row": sp.Matrix([[sp.cos(x), y]])}[matrix]
    locus = Locus("m", (x, y), {}, M.shape, "determinant", (component,))
    report = cross_check(locus, M, (x, y), angles=(x,) if matrix == "one row" else (x, y),
                         samples=SAMPLES, rng=np.random.default_rng(SEED), seed=SEED)
    assert report.components[0].ok and report.ok, render_check_text(report)
    # the same component shifted off the locus is still refused
    off = dataclasses.replace(component, equations=(component.equations[0] - sp.Rational(1, 2),
                                                    *component.equations[1:]))
    report = cross_check(dataclasses.replace(locus, components=(off,)), M, (x, y),
                         angles=(x,) if matrix == "one row" else (x, y), samples=SAMPLES,
                         rng=np.random.default_rng(SEED), seed=SEED)
    assert not report.components[0].ok
