"""Exclusions decided by proof (rankloci.tree.certify) and reduced by a branch's equations.

Generators of the small ring below: C_q, S_q, C_r, S_r (half angles of q, r).  The last
tests compute the locus of romeo_laas_small's right elbow, where the null vectors' guard
is 1e-6 of its term size on a whole 3-dimensional component.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from rankloci.algebra import PolyRing
from rankloci.tree.branch import Branch
from rankloci.tree.certify import admitted_near, certified_point
from rankloci.tree.cover import reduced_exclusion

q, r = sp.symbols("q r")
RING = PolyRing((q, r), (), ())
Cq, Sq, Cr, Sr = RING.gens
ALL = [0, 1, 2, 3]
#: sin((q - r) / 2): its zero set is q = r
DIFF = Sq * Cr - Cq * Sr
#: cos((q - r) / 2), 1 on q = r
SUM = Cq * Cr + Sq * Sr


def generators(qv, rv):
    return np.array([np.cos(qv / 2), np.sin(qv / 2), np.cos(rv / 2), np.sin(rv / 2)])


def branch(equation, exclusion):
    b, _ = Branch().with_condition(equation, RING)
    if not b.implicit:
        b = Branch((equation,), (), (equation,), ())
    return b.excluding(exclusion)


def test_an_exclusion_tiny_on_the_branch_is_proved_nonzero():
    # on q = r the exclusion is 1e-9 of its term size: no threshold tells it from 0
    tiny = DIFF + SUM / 10 ** 9
    b = Branch((DIFF * DIFF + DIFF,), (), (DIFF * DIFF + DIFF,), (tiny,))
    g = generators(0.7, 0.7 + 1e-12)
    got = certified_point(RING, b, g, ALL)
    assert got is not None
    qv = 2 * np.arctan2(got[1], got[0])
    rv = 2 * np.arctan2(got[3], got[2])
    assert abs(qv - rv) < 1e-15 and abs(qv - 0.7) < 1e-9


def test_an_exclusion_that_vanishes_on_the_branch_is_never_proved_nonzero():
    b = Branch((DIFF * DIFF + DIFF,), (), (DIFF * DIFF + DIFF,), (DIFF * (Cq + Sr),))
    for x in (0.7, -2.0, 3.0):
        assert certified_point(RING, b, generators(x, x + 1e-12), ALL) is None


def test_a_point_off_the_equations_is_not_proved():
    b = Branch((DIFF * DIFF + DIFF,), (), (DIFF * DIFF + DIFF,), (SUM,))
    # Newton converges to q = r, but from 0.3 away the box does not hold the start
    got = certified_point(RING, b, generators(0.7, 1.0), ALL)
    assert got is None or abs(2 * np.arctan2(got[1], got[0]) - 2 * np.arctan2(got[3], got[2])) < 1e-15


def test_crossing_sheets_closure_decided_by_the_sheet_through_the_point():
    # {S_q * S_r = 0}: the sheets q = 0 and r = 0; the exclusion S_r vanishes on r = 0
    # identically and on q = 0 only where the sheets cross
    e = Sq * Sr
    b = Branch((e,), (), (e,), (Sr,))
    rng = np.random.default_rng(0)
    at_crossing = generators(0.0, 0.0)
    assert admitted_near(RING, b, at_crossing, ALL, rng, step=1e-3, radius=0.05)
    on_other_sheet = generators(1.1, 0.0)
    assert not admitted_near(RING, b, on_other_sheet, ALL, rng, step=1e-3, radius=0.05)


def test_exclusion_reduced_by_an_equation_of_the_branch():
    e = DIFF * SUM + 3 * Sq * Sr
    p = 5 * e + (Cq * Cr) / 1000
    assert reduced_exclusion(RING, p, e) == (Cq * Cr) / 1000
    # unrelated or of other degrees: kept
    assert reduced_exclusion(RING, Cq * Cr + Sq * Sr, e) == Cq * Cr + Sq * Sr
    assert reduced_exclusion(RING, Sq, e) == Sq


# --- romeo_laas_small's right elbow --------------------------------------------------------

ELBOW = ("romeo_description/urdf/romeo_laas_small.urdf", "RElbowYaw_link")


@pytest.fixture(scope="module")
def elbow():
    from rankloci.api import load_model
    from rankloci.io.urdf_chains import example_robot_data_dir

    robots = example_robot_data_dir()
    if robots is None:
        pytest.fail("example-robot-data is not installed; it is a declared test dependency")
    return load_model(str(robots / ELBOW[0]), tip=ELBOW[1], base_link="base_link")


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_elbow_component_with_a_tiny_exclusion_is_found_at_every_seed(elbow, seed):
    """Each seed's own computation (no recomputation) passes the numeric check: the
    3-dimensional component where both shoulder axes and both elbow axes share the upper
    arm's line is found, and no component lies inside another."""
    from rankloci.api import locus
    from rankloci.jacobians import task_matrix
    from rankloci.numeric.crosscheck import cross_check

    L = locus(elbow, numeric=True, seed=seed, verify=False)
    ref = task_matrix(elbow)
    report = cross_check(L, ref.matrix, ref.variables, angles=ref.angles,
                         parameters=ref.parameters, samples=10,
                         rng=np.random.default_rng(seed), seed=seed)
    assert all(c.ok for c in report.components), [c.message for c in report.components]
    assert not report.uncovered and report.probe_singular >= 1
    # rank drop 1 of a 6x5 matrix in 5 variables: every component has dimension >= 3
    assert L.components and all(c.dimension >= 3 for c in L.components)


def test_elbow_locus_is_complete(elbow):
    from rankloci.api import locus

    L = locus(elbow, numeric=True, seed=0)
    assert L.complete is True, L.notes


def test_dyadic_evaluation_is_exact():
    """The integer (homogenised) evaluation of the ball arithmetic equals the rational one."""
    import flint

    from rankloci.tree.certify import at_dyadic

    p = DIFF * SUM ** 3 / 7 - 5 * Cq + flint.fmpq(7, 2)
    rng = np.random.default_rng(3)
    for _ in range(20):
        xs = [flint.fmpq(int(rng.integers(-2**60, 2**60)), 2 ** int(rng.integers(0, 300)))
              for _ in range(4)]
        assert at_dyadic(p, xs, {}) == p(*xs)
    # a denominator that is no power of two takes the rational route, with the same value
    xs = [flint.fmpq(1, 3), flint.fmpq(2), flint.fmpq(-5, 8), flint.fmpq(0)]
    assert at_dyadic(p, xs, {}) == p(*xs)


def test_a_zero_with_a_singular_jacobian_is_not_proved():
    """At a double root of the system (sin^2 of half the difference), the Jacobian at the
    refined zero is singular (FLOAT_SINGULAR_COND) or the refinement does not settle:
    nothing is proved."""
    import flint

    from rankloci.tree.certify import PRECISION_BITS, _krawczyk

    def jac(eq):
        return RING.compile([eq.derivative(1)])

    with flint.ctx.workprec(PRECISION_BITS):
        vals = [flint.arb(float(x)) for x in generators(0.4 + 1e-9, 0.4)]
        assert _krawczyk([DIFF ** 2], [1], vals, {}, jac(DIFF ** 2)) is None
        # the simple root next to it is proved: the box holds the exact zero of the pivot,
        # sin(q/2) = cos(q/2) sin(r/2) / cos(r/2) with the other generators as given
        box = _krawczyk([DIFF], [1], vals, {}, jac(DIFF))
        assert box is not None
        exact = vals[0] * vals[3] / vals[2]
        assert box[1].overlaps(exact) and box[1].rad() < 1e-25
        assert not box[1].overlaps(exact + flint.arb(2) ** -90)


def test_a_singular_jacobian_in_doubles_skips_the_ball_arithmetic(monkeypatch):
    """No ball arithmetic is started where the equations' Jacobian at the zero found in doubles
    has a condition number above FLOAT_SINGULAR_COND; a simple root stays far below it."""
    import rankloci.tree.certify as certify

    # two equations that both vanish on the curve q = r: their Jacobian is singular on it
    g = generators(0.4, 0.4)
    assert certify._float_condition(RING, [DIFF, DIFF * SUM], [1, 3], g, {}) > \
        certify.FLOAT_SINGULAR_COND
    assert certify._float_condition(RING, [DIFF, Sr], [1, 3], g, {}) < 1e3

    calls = []
    real = certify._krawczyk

    def counted(*args, **kwargs):
        calls.append(args)
        return real(*args, **kwargs)

    monkeypatch.setattr(certify, "_krawczyk", counted)
    simple = Branch((DIFF,), (), (DIFF,), (SUM,))
    start = generators(0.4 + 1e-9, 0.4)
    assert certified_point(RING, simple, start, ALL) is not None and len(calls) == 1
    # the same root with the threshold below its condition number (1): not attempted
    monkeypatch.setattr(certify, "FLOAT_SINGULAR_COND", 0.5)
    assert certified_point(RING, simple, start, ALL) is None and len(calls) == 1


def test_newton_in_doubles_stops_once_the_equations_are_at_rounding(monkeypatch):
    """From 1e-3 off a simple zero, Newton reaches rounding in a few steps and stops there,
    on the zero, instead of taking all FLOAT_NEWTON_STEPS."""
    import rankloci.tree.certify as certify

    cache = {}
    start = generators(0.4 + 1e-3, 0.4)
    solves = []
    real = np.linalg.solve

    def counted(A, b):
        solves.append(1)
        return real(A, b)

    monkeypatch.setattr(np.linalg, "solve", counted)
    got = certify._float_newton(RING, [DIFF], [1], start, cache)
    assert got is not None
    values, sizes = RING.compile([DIFF], sized=True)(got)
    assert abs(values[0]) <= certify.FLOAT_NEWTON_SETTLED * sizes[0]
    assert 0 < len(solves) < certify.FLOAT_NEWTON_STEPS
