"""A computation with hints resumes from the tree its first computation grew.

The self-check's hints (configurations where a component was found regular) change only the
leaves of a grown tree (:func:`~rankloci.tree.reducible.repair_leaves`), so that
``locus_and_tree`` returns the grown tree as a value, and ``compute_locus(..., grown=...)``
takes it up again for the hints without changing it.
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
from rankloci.methods import compute_locus, locus_and_tree, singular_vector

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


def _tree_edges(locus):
    return sorted(locus.tree.edges)


def test_hints_resume_the_grown_tree(counted):
    tm, grown = counted
    first, tree = locus_and_tree(tm, "svm", rng=np.random.default_rng(3))
    edges = _tree_edges(first)
    notes = tree.context.notes
    exclusions = {k: [str(p) for p in v] for k, v in tree.context.exceptional_exclusions.items()}
    again, repaired = locus_and_tree(tm, "svm", hints=HINTS, grown=tree)
    assert len(grown) == 1
    # the same hints once more, from the tree they repaired, as a second round of the
    # self-check brings them: nothing more to repair, the same locus
    twice = compute_locus(tm, "svm", hints=HINTS, grown=repaired)
    assert len(grown) == 1
    fresh = compute_locus(tm, "svm", rng=np.random.default_rng(3), hints=HINTS)
    assert len(grown) == 2
    assert _equations(again) == _equations(twice) == _equations(fresh)
    assert _equations(first)
    for locus in (again, twice):
        assert sum("of the leaves were split" in n for n in locus.notes) == 1
    # the value passed in is not changed: the first locus keeps its tree, and resuming from
    # it again gives the same locus and tree
    assert _tree_edges(first) == edges
    assert tree.context.notes == notes
    assert {k: [str(p) for p in v]
            for k, v in tree.context.exceptional_exclusions.items()} == exclusions
    assert repaired.context is not tree.context
    other = compute_locus(tm, "svm", hints=HINTS, grown=tree)
    assert _equations(other) == _equations(again)
    assert _tree_edges(other) == _tree_edges(again)
    assert [n for n in other.notes] == [n for n in again.notes]


def test_a_tree_is_taken_up_only_for_its_own_matrix_and_method(counted):
    tm, grown = counted
    _, tree = locus_and_tree(tm, "svm", rng=np.random.default_rng(3))
    with pytest.raises(ValueError, match="grown"):
        compute_locus(tm, "subdeterminant", hints=HINTS, grown=tree)
    other = task_matrix(parse_model(RAW.replace("sin(x)\"]", "cos(x)\"]"), name="other"),
                        frame="auto")
    with pytest.raises(ValueError, match="grown"):
        compute_locus(other, "svm", hints=HINTS, grown=tree)
    assert len(grown) == 1
