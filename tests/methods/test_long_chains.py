"""A chain of nine joints outside the built-in models: a spatial 9R snake
(kinematics_models/extra/snake9.toml).

Equal links, no offsets and twists alternating between +pi/2 and -pi/2 make a locus of many
components (95 with numeric parameters).  Its lost directions once asked FLINT for 6.4 GB
(a cofactor product of 25258 by 174532 terms) and ended the process.  The locus here is the
one ``rankloci locus`` shows: computed, checked numerically, and computed again with the
configurations where the check found a component regular as hints
(:func:`~rankloci.verify.verified_locus`; one round, taken up from the tree grown first).  Before hints reached
their leaves (angles at float multiples of pi, substitutions undefined at the hint, see
:func:`~rankloci.tree.reducible.repair_leaves`), the self-check rejected this locus.  Each
component's sample point is checked to be singular here too, and singular points found by
minimising sigma_min/sigma_max from random starts to lie on a component.  A minimum counts as
singular as in ``rankloci check``, where Newton steps on the ratio bring it to
PROBE_DESCENT_RTOL.  (One start here ends at 9.4e-11, a minimum that neither those steps nor
bounded searches within 0.01 rad bring lower, 1.7e-3 (scaled) off the component {q4 = pi,
q6 = 0, q8 = pi, ...}: nearly, not exactly, singular by that rule.)
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import least_squares

import locus_helpers as H
from rankloci.io.toml_model import read_model
from rankloci.jacobians import task_matrix
from rankloci.methods import locus_and_tree
from rankloci.numeric.equations import NumericMatrix, descend_to_singular
from rankloci.tolerances import COVER_DISTANCE, COVER_RESIDUAL, PROBE_DESCENT_RTOL, RANK_RTOL
from rankloci.verify import verified_locus


SNAKE = Path(__file__).resolve().parents[2] / "kinematics_models" / "extra" / "snake9.toml"


def _covers(eqs, q, nj) -> bool:
    """Is the singular point ``q`` on ``eqs``, or next to it (COVER_DISTANCE)?"""
    if eqs.residual(q) <= COVER_RESIDUAL:
        return True
    p = least_squares(eqs, q, method="trf", xtol=1e-15, ftol=1e-15, gtol=1e-15).x
    return (eqs.residual(p) <= COVER_RESIDUAL and np.linalg.norm(p - q) <= COVER_DISTANCE
            and H.sigma_ratio(nj(p)) <= RANK_RTOL)


@pytest.fixture(scope="module")
def snake():
    model = read_model(SNAKE)
    tm = task_matrix(model, frame="auto", numeric=True)
    reference = task_matrix(model, frame=tm.frame, point=tm.point)

    def compute(t, seed, hints=(), grown=None):
        return locus_and_tree(t, "svm", rng=np.random.default_rng(seed), hints=hints,
                              grown=grown)

    locus, verification = verified_locus(compute, tm, reference)
    return tm, locus, verification


@pytest.mark.slow
def test_nine_joint_snake_passes_its_self_check(snake):
    """A 6 x 9 matrix: components of codimension 3 and 4 are beyond the certificate's
    elimination, so the locus is not certified (complete is null), but nothing disproves it and
    the numeric self-check of the locus shown passes."""
    _, locus, verification = snake
    assert locus.complete is None
    assert locus.certificate.verdict == "undecided"
    assert verification.problems and all(p.startswith("certificate:")
                                         for p in verification.problems), verification.problems


@pytest.mark.slow
def test_nine_joint_snake_sample_points_are_singular(snake):
    tm, locus, _ = snake
    comps = H.model_components(locus)
    assert len(comps) >= 9
    nj = H.numeric_j(tm)
    for comp in comps:
        q = H.sample_point(comp, tm)
        assert H.sigma_ratio(nj(q)) <= RANK_RTOL, H.describe(comp)


@pytest.mark.slow
def test_nine_joint_snake_singular_points_lie_on_components(snake):
    tm, locus, _ = snake
    nj = H.numeric_j(tm)
    nm = NumericMatrix(tm.matrix, tm.variables, tm.angles)
    eqs = [H.ComponentEquations(c, tm, None) for c in H.model_components(locus)]
    rng = np.random.default_rng(7)
    singular = 0
    for _ in range(12):
        q, ratio = H.minimise_sigma_ratio(nj, H.random_q(tm, rng))
        if ratio > RANK_RTOL:
            continue
        q, ratio = descend_to_singular(nm, q)
        if ratio > PROBE_DESCENT_RTOL:
            continue
        singular += 1
        assert any(_covers(e, q, nj) for e in sorted(eqs, key=lambda e: e.residual(q))), \
            f"singular point {H.fmt(q, tm.variables)} on no component"
    assert singular >= 3
