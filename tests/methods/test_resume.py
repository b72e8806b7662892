"""A computation with hints resumes from the tree its first computation grew.

The self-check's hints (configurations where a component was found regular) change only the
leaves of a grown tree (:func:`~rankloci.tree.reducible.repair_leaves`), so that
``compute_locus(..., trees=...)`` grows the tree once and takes it up again for the hints.
The hints here lie on the regular piece of a reducible set: the 1 x 2 matrix [sin x, sin y +
sin x cos z] loses rank where sin x = sin y = 0, and the equations sin x - sin y sin z =
sin y cos z = 0 also hold where cos z = 0 and sin x = sin y (see tests/tree/test_reducible.py).
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from rankloci.io.toml_model import parse_model
from rankloci.jacobians import task_matrix
from rankloci.methods import compute_locus, singular_vector

RAW = 'variables = ["x", "y", "z"]\nmatrix = [["sin(x)", "sin(y) + sin(x)*cos(z)"]]\n'
HINTS = ({"x": 0.7, "y": 0.7, "z": np.pi / 2}, {"x": -1.1, "y": -1.1, "z": -np.pi / 2})


def _equations(locus):
    return sorted(tuple(sp.sstr(e) for e in c.equations) + tuple(map(sp.sstr, c.excluding))
                  for c in locus.components)


@pytest.fixture
def counted(monkeypatch):
    """The matrix, and the list of contexts the singular vector method grows a tree in."""
    grown = []
    grow = singular_vector.singular_vector_tree
    monkeypatch.setattr(singular_vector, "singular_vector_tree",
                        lambda ctx: grown.append(ctx) or grow(ctx))
    return task_matrix(parse_model(RAW, name="raw"), frame="auto"), grown


def test_hints_resume_the_grown_tree(counted):
    tm, grown = counted
    trees = {}
    first = compute_locus(tm, "svm", rng=np.random.default_rng(3), trees=trees)
    again = compute_locus(tm, "svm", rng=np.random.default_rng(3), hints=HINTS, trees=trees)
    assert len(grown) == 1 and len(trees) == 1
    # the same hints once more, as a second round of the self-check brings them: nothing
    # more to repair, the same locus
    twice = compute_locus(tm, "svm", rng=np.random.default_rng(3), hints=HINTS, trees=trees)
    assert len(grown) == 1
    fresh = compute_locus(tm, "svm", rng=np.random.default_rng(3), hints=HINTS)
    assert len(grown) == 2
    assert _equations(again) == _equations(twice) == _equations(fresh)
    assert _equations(first)
    for locus in (again, twice):
        assert sum("of the leaves were split" in n for n in locus.notes) == 1


def test_another_seed_or_no_hints_grow_their_own_tree(counted):
    tm, grown = counted
    trees = {}
    compute_locus(tm, "svm", rng=np.random.default_rng(3), trees=trees)
    compute_locus(tm, "svm", rng=np.random.default_rng(4), hints=HINTS, trees=trees)
    compute_locus(tm, "svm", rng=np.random.default_rng(3), trees=trees)
    assert len(grown) == 3
