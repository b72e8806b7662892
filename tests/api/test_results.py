"""Locus and Component in a notebook: reprs, contains, lambdify, pickling, dict round trips."""

from __future__ import annotations

import json
import pickle

import numpy as np
import pytest
import sympy as sp

import rankloci
from rankloci.errors import ModelError
from rankloci.loci import Component, Locus

X, Y = sp.symbols("x y", real=True)


@pytest.fixture(scope="module")
def puma():
    """PUMA 560 with symbolic lengths: three components and one special (a2 = 0)."""
    return rankloci.locus("puma560")


@pytest.fixture(scope="module")
def augmented():
    return rankloci.locus("planar3r_orient")


def test_reprs_are_short_and_name_the_equations(puma):
    assert repr(puma) == "<Locus 'puma560': 6x6, determinant, 3 components (+1 special), " \
                         f"{puma.seconds:.2f} s>"
    assert repr(puma.components[2]) == "<Component sin(q5) = 0: dimension 5, rank drop 1>"
    model = rankloci.load_model("puma560")
    assert repr(model) == "<RobotModel 'puma560': 6 revolute joints, standard DH, " \
                          "parameters a2, a3, d3, d4>"
    assert "Matrix" not in repr(model) and len(repr(model)) < 100
    assert repr(model.joints[2]) == "<Joint 'joint3': revolute about (0, 0, 1), dh a=a3 " \
                                    "alpha=-pi/2 d=d3 theta=0>"
    m = rankloci.load_model(sp.Matrix([[sp.cos(X), 2]]))
    assert repr(m) == "<MatrixModel 'matrix': 1x2 in x>"


def test_latex_and_html_show_every_component(puma, augmented):
    latex = puma._repr_latex_()
    assert latex.startswith("$\\displaystyle \\begin{array}") and latex.endswith("$")
    assert latex.count("= 0") == 3 and r"\sin{\left(q_{5} \right)} = 0" in latex
    assert puma.components[2]._repr_latex_() == r"$\displaystyle \sin{\left(q_{5} \right)} = 0$"
    html = puma._repr_html_()
    assert html.count("<tr>") == 4 and "sin(q5) = 0" in html and "q5 &isin; {0, pi}" in html
    assert "(+1 for special parameter values)" in html
    assert "<th>kind</th>" not in html      # only an augmented locus has kinds
    assert "<th>kind</th>" in augmented._repr_html_() and "<td>mixed</td>" in augmented._repr_html_()
    excl = Component((X * Y,), excluding=(X,))
    assert excl._repr_latex_() == r"$\displaystyle x y = 0,\quad x \neq 0$"
    assert "x*y = 0 where x != 0" in excl._repr_html_()


def test_html_escapes_text():
    L = Locus("<script>", (X,), {}, (1, 1), "determinant", (Component((sp.sin(X),)),))
    assert "<script>" not in L._repr_html_() and "&lt;script&gt;" in L._repr_html_()


def test_contains_respects_excluding():
    """{x y = 0, x != 0} is the line y = 0 without the origin; its closure holds the origin
    but not the points of x = 0 away from it."""
    L = Locus("m", (X, Y), {}, (2, 2), "svm", (Component((X * Y,), excluding=(X,)),))
    assert L.contains([1.0, 0.0])
    assert L.contains([0.0, 0.0])          # in the closure
    assert not L.contains([0.0, 1.0])      # x y = 0 there, but only where x = 0 is excluded
    assert not L.contains([1.0, 0.5])
    whole = Locus("m", (X, Y), {}, (2, 2), "svm", (Component((X,), excluding=(Y,)),))
    assert whole.contains([0.0, 0.0]) and whole.contains([0.0, 2.0])


def test_contains_with_symbolic_parameters_uses_their_values(puma):
    a2, a3, d4 = 0.4318, 0.0203, 0.4318
    q3 = 2 * np.arctan((a3 - np.sqrt(a3**2 + d4**2)) / d4)     # a3 sin q3 + d4 cos q3 = 0
    assert abs(a3 * np.sin(q3) + d4 * np.cos(q3)) < 1e-15
    assert puma.contains([0.1, 0.2, q3, 0.4, 0.5, 0.6])
    assert puma.contains([0.1, 0.2, 0.3, 0.4, 0.0, 0.6])
    assert not puma.contains([0.1, 0.2, 0.3, 0.4, 0.5, 0.6])
    assert a2 > 0   # the special component a2 = 0 is not the model's: not used
    assert rankloci.is_singular("puma560", [0.1, 0.2, 0.3, 0.4, 0.0, 0.6], locus=puma)


def test_contains_agrees_with_the_svd_at_component_samples(puma):
    from rankloci.numeric.svd import sigma_ratio
    from rankloci.tolerances import RANK_RTOL

    J = rankloci.jacobian("puma560", numeric=True)
    f = sp.lambdify(J.variables, J.matrix, "numpy")
    for c in puma.components:
        q = [c.sample[str(v)] for v in puma.variables]
        assert puma.contains(q)
        assert sigma_ratio(np.array(f(*q), dtype=float)) <= RANK_RTOL


def test_lambdify(puma):
    comp = puma.components[1]                   # a3 sin q3 + d4 cos q3
    f = comp.lambdify(puma.variables, puma.parameters)
    q = np.zeros((6, 5))
    q[2] = np.linspace(-1, 1, 5)
    values = np.asarray(f(*q))
    assert values.shape == (1, 5)
    assert np.allclose(values[0], 0.0203 * np.sin(q[2]) + 0.4318 * np.cos(q[2]), atol=1e-15)
    g = comp.lambdify()                         # default: a3, d4, q3 (natural name order)
    assert g(1.0, 2.0, 0.5) == [pytest.approx(1.0 * np.sin(0.5) + 2.0 * np.cos(0.5))]


@pytest.mark.parametrize("which", ["puma", "augmented"])
def test_pickle_round_trip(which, request):
    L = request.getfixturevalue(which)
    L.contains([0.0] * len(L.variables))       # fills the cache of numeric equations
    back = pickle.loads(pickle.dumps(L))
    assert back.to_dict() == L.to_dict()
    assert back.components == L.components and back.special == L.special
    assert back.contains([c for c in L.components[0].sample.values()][:len(L.variables)])


@pytest.mark.parametrize("which", ["puma", "augmented"])
def test_dict_round_trip(which, request):
    L = request.getfixturevalue(which)
    data = json.loads(json.dumps(L.to_dict()))
    back = Locus.from_dict(data)
    assert back.to_dict() == data
    assert [c.equations for c in back.components] == [c.equations for c in L.components]
    assert back.parameters == L.parameters
    with_model = Locus.from_dict(data, rankloci.load_model(L.model))
    assert with_model.to_dict() == data
    assert with_model.variables == L.variables


@pytest.mark.parametrize("change, field", [
    ({"schema": "rankloci.locus/9"}, "schema"),
    ({"variables": "q1"}, "variables"),
    ({"parameters": {"a2": "big"}}, "parameters.a2"),
    ({"components": [{"equations": ["sin(q1)"], "rank_drop": 0}]}, "components[1].rank_drop"),
    ({"components": [{"equations": ["__import__('os')"]}]}, "components[1].equations"),
    ({"components": [{"equations": ["q1"], "solved": {"zz": ["0"]}}]}, "components[1].solved"),
    ({"components": [{"equations": ["q1"], "kind": "odd"}]}, "components[1].kind"),
    ({"components": [{"equations": ["q1"], "sample": {"q1": "x"}}]}, "components[1].sample"),
    ({"matrix": {"rows": -1, "cols": 2}}, "matrix"),
    ({"complete": "yes"}, "complete"),
    ({"base_locus": {"schema": "rankloci.locus/2", "variables": ["q1"], "components": [],
                     "base_locus": {}}}, "base_locus"),
])
def test_from_dict_names_the_bad_field(puma, change, field):
    data = puma.to_dict() | change
    with pytest.raises(ModelError) as err:
        Locus.from_dict(data)
    assert err.value.field == field


def test_from_dict_bounds_directions(puma):
    data = puma.to_dict()
    data["components"][0] = data["components"][0] | {"direction": [["1"] * 1001]}
    with pytest.raises(ModelError, match="at most 100 lists of at most 1000 entries"):
        Locus.from_dict(data)
