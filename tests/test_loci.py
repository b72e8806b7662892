"""The Locus is immutable: asking it questions changes nothing in it, and it splits its own
components into the model's and the special ones."""

from __future__ import annotations

import pickle

import sympy as sp

from rankloci.loci import Component, Locus

q1, q2, a = sp.symbols("q1 q2 a", real=True)


def _locus(**kw) -> Locus:
    return Locus("m", (q1, q2), {a: 1}, (2, 2), "determinant",
                 (Component((sp.sin(q2),)), Component((sp.cos(q1),), excluding=(sp.sin(q2),))),
                 **kw)


def test_contains_leaves_the_locus_as_it_was():
    L = _locus()
    before = dict(vars(L))
    assert L.contains([0.4, 0.0]) and not L.contains([0.4, 1.0])
    assert L.contains([[0.4, 0.0], [1.5707963267948966, 1.0]]).tolist() == [True, True]
    assert vars(L) == before
    again = pickle.loads(pickle.dumps(L))
    assert again == L and again.contains([0.4, 0.0])


def test_components_for_other_parameter_values_go_to_special_whoever_builds_the_locus():
    other = Component((a - 2,), parameter_conditions=(a - 2,), for_model=False)
    L = Locus("m", (q1, q2), {a: 1}, (2, 2), "determinant",
              (Component((sp.sin(q2),)), other))
    assert L.components == (Component((sp.sin(q2),)),) and L.special == (other,)
    assert L.all_components == (Component((sp.sin(q2),)), other)
    assert not L.contains([0.4, 1.0])
    # a locus built with the split already made is the same locus
    assert Locus("m", (q1, q2), {a: 1}, (2, 2), "determinant", (Component((sp.sin(q2),)),),
                 special=(other,)) == L


def test_exists_for_model_is_the_old_name_of_for_model():
    import pytest

    for flag in (True, False):
        c = Component((a - 2,), for_model=flag)
        with pytest.warns(DeprecationWarning, match="for_model"):
            assert c.exists_for_model is flag
