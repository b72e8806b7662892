"""The optional Singular cross-check: agrees on planar arms, catches a missing
component, and says it is skipped when Singular is absent or the ideal is too big."""

import dataclasses

import numpy as np
import pytest

from rankloci.io import load_model
from rankloci.jacobian import task_matrix
from rankloci.methods import compute_locus
from rankloci.exact.singular import singular_available, singular_cross_check

SEED = 4


def _case(name):
    tm = task_matrix(load_model(name), frame="auto", numeric=True)
    return tm, compute_locus(tm, rng=np.random.default_rng(SEED))


@pytest.mark.parametrize("name, n_primes", [("planar2r", 2), ("planar3r", 4), ("planar4r", 8)])
def test_primes_agree_with_locus(name, n_primes):
    tm, locus = _case(name)
    result = singular_cross_check(tm, locus, rng=np.random.default_rng(SEED))
    if singular_available():
        # published: the arm is singular iff all links are collinear, i.e. every
        # relative joint angle is 0 or pi: 2**(n-1) real points of the circles
        assert result.status == "agree", result.findings
        assert len(result.primes) == n_primes
    else:
        assert result.status == "skipped" and "not installed" in result.reason


def test_missing_component_disagrees():
    tm, locus = _case("planar3r")
    wrong = dataclasses.replace(locus, components=())
    result = singular_cross_check(tm, wrong, rng=np.random.default_rng(SEED))
    if singular_available():
        assert result.status == "disagree"
        assert any("on no component" in f for f in result.findings)
    else:
        assert result.status == "skipped"


def test_large_models_are_skipped_with_a_reason():
    tm, locus = _case("puma560")
    result = singular_cross_check(tm, locus, rng=np.random.default_rng(SEED))
    assert result.status == "skipped"
    assert result.reason
