"""Random small matrices: the certified locus agrees with an independent exact computation.

The independent computation is sympy's Groebner bases (no code of rankloci's algebra), in
half-angle coordinates C = cos(a/2), S = sin(a/2) with C**2 + S**2 = 1 for the angle a:

- sound: every maximal minor g vanishes on each component off its exclusions,
  1 in <C**2 + S**2 - 1, equations, 1 - z * g * (product of exclusions)>;
- complete: every product of one generator of each component's closure (its equations
  saturated by its exclusions) vanishes on the zero set of the minors,
  1 in <C**2 + S**2 - 1, minors, 1 - w * product>.

Both are statements about complex points, as the certificate's are.  A locus called complete
must pass both; a locus whose certificate failed must fail one.
"""

from __future__ import annotations

import itertools

import pytest
import sympy as sp
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import rankloci
from rankloci.loci import Component

a, x = sp.symbols("a x", real=True)
C, S, z, w = sp.symbols("C S z w")
#: monomials an entry is built from: sines and cosines of the angle a, and the variable x
BASIS = (sp.Integer(1), x, sp.cos(a), sp.sin(a), x * sp.cos(a), x * x)
#: the largest number of products the completeness test may need
MAX_PRODUCTS = 64


def _half(e):
    """An expression in a (and a/2) and x as a polynomial in C, S and x."""
    h = sp.Symbol("h")
    e = sp.expand_trig(sp.sympify(e, strict=True).subs(a, 2 * h))
    e = e.subs({sp.cos(h): C, sp.sin(h): S})
    return sp.expand(e)


def _is_one(polys, gens):
    return list(sp.groebner(polys, *gens, order="grevlex").exprs) == [1]


def _saturation(eqs, excl, gens):
    """Generators of the closure of V(eqs) minus V(product of excl)."""
    if not excl:
        return eqs
    u = sp.Symbol("u")
    G = sp.groebner(eqs + [1 - u * sp.Mul(*excl)], u, *gens, order="lex")
    return [g for g in G.exprs if not g.has(u)]


def independent_verdict(M, components) -> bool:
    gens = (C, S, x)
    circle = C ** 2 + S ** 2 - 1
    if M.rows > M.cols:
        M = M.T
    n = M.rows
    minors = [_half(M.extract(list(range(n)), list(cols)).det())
              for cols in itertools.combinations(range(M.cols), n)]
    minors = [g for g in minors if g != 0]
    for c in components:
        eqs = [_half(e) for e in c.equations]
        excl = [_half(e) for e in c.excluding]
        for g in minors:
            if not _is_one([circle, *eqs, 1 - z * g * sp.Mul(*excl)], (z, *gens)):
                return False
    closures = [_saturation([circle] + [_half(e) for e in c.equations],
                            [_half(e) for e in c.excluding], gens) for c in components]
    choices = list(itertools.islice(itertools.product(*closures), MAX_PRODUCTS + 1))
    assume(len(choices) <= MAX_PRODUCTS)
    if not minors:
        # rank deficient everywhere: some component must be the whole space
        return any(not [e for e in c.equations if e != 0] for c in components)
    for prod in choices:
        if not _is_one([circle, *minors, 1 - w * sp.Mul(*prod)], (w, *gens)):
            return False
    return True


@st.composite
def small_matrices(draw):
    rows = draw(st.integers(1, 2))
    cols = draw(st.integers(rows, 3))
    coeff = st.integers(-2, 2)
    entries = []
    for _ in range(rows * cols):
        terms = draw(st.lists(st.tuples(coeff, st.sampled_from(BASIS)), min_size=1,
                              max_size=2))
        entries.append(sp.Add(*[k * m for k, m in terms]))
    return sp.Matrix(rows, cols, entries)


@pytest.mark.slow
@settings(max_examples=25, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(small_matrices())
def test_certified_loci_agree_with_groebner_bases(M):
    assume(any(e.has(a) for e in M) and any(e.has(x) for e in M))
    locus = rankloci.locus(M, variables=(a, x), timeout=60)
    assume(locus.certificate is not None and locus.certificate.verdict != "undecided")
    # components of the complex locus without real points, which the certificate proved so
    complex_only = [Component(tuple(eqs)) for eqs in locus.certificate.complex_components]
    # and the complex components whose real points are reported as components of their own
    complex_only += [Component(tuple(c.real_points_of)) for c in locus.components
                     if c.real_points_of]
    verdict = independent_verdict(M, list(locus.components) + complex_only)
    if locus.complete is True:
        assert verdict, [c.equations for c in locus.components]
    else:
        assert not verdict, [c.equations for c in locus.components]


def test_the_independent_verdict_can_say_no():
    """It refuses a locus with half of it missing, and accepts the whole one."""
    M = sp.Matrix([[x, sp.sin(a)]])
    whole = rankloci.locus(M, variables=(a, x))
    assert whole.complete is True
    assert independent_verdict(M, whole.components)
    half = [Component((x, sp.cos(a / 2)), dimension=0)]      # only a = pi of sin(a) = 0
    assert not independent_verdict(M, half)
