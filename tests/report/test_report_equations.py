"""Equations a paper can cite: shorter forms at equal parameter values, long integers rounded
for display with the rounding stated, exact values kept in the plain text."""

from __future__ import annotations

import re

import pytest
import sympy as sp

from rankloci.io import load_model
from rankloci.reporting.build import equal_parameter_forms
from rankloci.reporting.mathfmt import (LONG_INTEGER_DIGITS, SHOWN_DIGITS, has_long_integers,
                                     latex)


def test_equal_parameters_shorten_only_where_terms_cancel():
    puma = load_model("puma560")
    named = {p.name: p for p in puma.parameters}
    q3 = puma.variables[2]
    # a2 = d4 = 0.4318 in this model, but the elbow equation has no a2: nothing to show
    elbow = named["a3"] * sp.sin(q3) + named["d4"] * sp.cos(q3)
    assert equal_parameter_forms([elbow], puma.parameters) == ()
    # where the equal parameters meet with opposite signs, the terms go
    e = named["a2"] * sp.cos(q3) - named["d4"] * sp.cos(q3) + named["d4"] * sp.sin(q3)
    (f,) = equal_parameter_forms([e], puma.parameters)
    assert f.equalities == ((named["d4"], named["a2"]),) and f.terms == (3, 1)
    assert sp.simplify(f.form - named["a2"] * sp.sin(q3)) == 0


@pytest.mark.slow
def test_ssrms_loses_four_of_twelve_terms_at_a3_equal_a4():
    import rankloci

    model = load_model("ssrms")
    locus = rankloci.locus("ssrms")
    comp = next(c for c in locus.components if "cos(q4/2)" in map(str, c.equations))
    (f,) = equal_parameter_forms(comp.equations, model.parameters)
    names = {(p.name, r.name) for p, r in f.equalities}
    assert names == {("a4", "a3")} and f.terms == (12, 8)


def test_long_integers_are_displayed_rounded_and_the_value_kept():
    n = 1234567890123456789
    q = sp.Symbol("q1")
    e = n * sp.cos(q) - 7
    assert has_long_integers(e) and not has_long_integers(12 * sp.cos(q))
    text = latex(e)
    assert not re.search(r"\d{%d}" % (LONG_INTEGER_DIGITS + 1), text), text
    m = re.search(r"(\d\.\d+) \\cdot 10\^\{(\d+)\}", text)
    assert m and len(m.group(1)) == SHOWN_DIGITS + 1
    shown = float(m.group(1)) * 10 ** int(m.group(2))
    assert abs(shown - n) <= 0.5 * 10 ** (int(m.group(2)) - SHOWN_DIGITS + 1)
    assert str(n) in sp.sstr(e)    # the plain text keeps it exact
