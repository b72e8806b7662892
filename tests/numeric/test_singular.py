"""The optional Singular cross-check: agrees on planar arms, catches a missing
component, skips ideals too big for it, and says it is skipped when Singular is absent.

The comparisons need Singular on PATH (Debian package ``singular``, installed in CI); without
it they are reported as skipped by pytest, not passed.
"""

import dataclasses

import numpy as np
import pytest

from rankloci.exact import singular
from rankloci.exact.singular import MAX_ANGLES, singular_available, singular_cross_check
from rankloci.io import load_model
from rankloci.jacobians import task_matrix
from rankloci.methods import compute_locus

SEED = 4

requires_singular = pytest.mark.skipif(
    not singular_available(), reason="Singular is not on PATH (Debian package 'singular')")


def _case(name):
    tm = task_matrix(load_model(name), frame="auto", numeric=True)
    return tm, compute_locus(tm, rng=np.random.default_rng(SEED))


@requires_singular
@pytest.mark.parametrize("name, n_primes", [("planar2r", 2), ("planar3r", 4), ("planar4r", 8)])
def test_primes_agree_with_locus(name, n_primes):
    # published: the arm is singular iff all links are collinear, i.e. every
    # relative joint angle is 0 or pi: 2**(n-1) real points of the circles
    tm, locus = _case(name)
    result = singular_cross_check(tm, locus, rng=np.random.default_rng(SEED))
    assert result.status == "agree", result.findings
    assert len(result.primes) == n_primes


@requires_singular
def test_missing_component_disagrees():
    tm, locus = _case("planar3r")
    wrong = dataclasses.replace(locus, components=())
    result = singular_cross_check(tm, wrong, rng=np.random.default_rng(SEED))
    assert result.status == "disagree"
    assert any("on no component" in f for f in result.findings)


@requires_singular
def test_large_models_are_skipped_with_a_reason():
    tm, locus = _case("puma560")
    result = singular_cross_check(tm, locus, rng=np.random.default_rng(SEED))
    assert result.status == "skipped"
    assert f"more than {MAX_ANGLES} joint variables" in result.reason


def test_absent_singular_reports_itself_skipped(monkeypatch):
    """Runs everywhere: with Singular hidden from PATH the check is skipped, with the reason."""
    monkeypatch.setattr(singular.shutil, "which", lambda name, *args, **kwargs: None)
    assert not singular_available()
    tm, locus = _case("planar2r")
    result = singular_cross_check(tm, locus, rng=np.random.default_rng(SEED))
    assert result.status == "skipped"
    assert "not installed" in result.reason
    assert result.primes == () and result.findings == ()
