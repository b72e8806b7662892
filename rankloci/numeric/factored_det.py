"""det J of a square matrix as the product of its components' equations.

For a square J the components of the locus are the factors of det J.  Their
product, with multiplicities and a constant, is det J itself:
:func:`factored_determinant` finds the multiplicities and the constant from J at
random configurations (least squares on the logarithms), rounds the
multiplicities to whole numbers, and keeps the result only when the ratio det J
over the product is one constant at every point, to
:data:`~rankloci.tolerances.DET_FACTOR_RTOL`.  The constant is given exactly when
it is a small rational multiple of a product of parameters, else as a number.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np
import sympy as sp

from ..tolerances import DET_FACTOR_RTOL, DET_POINTS, MAX_MINORS, MINOR_MAX_TERMS

__all__ = ["FactoredDeterminant", "factored_determinant", "MinorGcd", "maximal_minor_gcd",
           "MAX_MINORS", "MINOR_MAX_TERMS"]

#: Rational multipliers tried for an exact constant (half-angle factors bring powers of 2).
_MULTIPLIERS = (1, 2, 4, 8, sp.Rational(1, 2), sp.Rational(1, 4), sp.Rational(1, 8))


@dataclass(frozen=True)
class FactoredDeterminant:
    """``det J = constant * prod(factor ** power)``, checked at ``points`` configurations."""

    constant: sp.Expr         # exact (in the parameters) or a Float
    factors: tuple            # sympy expressions, the components' equations
    powers: tuple             # whole numbers >= 1
    exact_constant: bool
    points: int


def _exact_constant(kappas, param_sets):
    """``c * prod(p**e)`` (c in _MULTIPLIERS, e in 0..2) equal to ``kappas[k]`` at each
    ``param_sets[k]``, the one of least degree; or None."""
    names = sorted(param_sets[0], key=str)
    if len(names) > 8:
        return None
    for degree in range(2 * len(names) + 1):
        for exps in itertools.product(range(3), repeat=len(names)):
            if sum(exps) != degree:
                continue
            monos = [float(np.prod([float(ps[p]) ** e for p, e in zip(names, exps)]))
                     for ps in param_sets]
            for c in _MULTIPLIERS:
                for sign in (1, -1):
                    if all(abs(sign * float(c) * m - k) <= DET_FACTOR_RTOL * abs(k)
                           for m, k in zip(monos, kappas)):
                        return sign * c * sp.Mul(*[p ** e for p, e in zip(names, exps)])
    return None


def _constant(J, variables, kinds, funcs, values, powers, rng):
    """det J / prod(f**m) at DET_POINTS random configurations, if it is one number."""
    Q = np.column_stack([rng.uniform(-np.pi, np.pi, DET_POINTS) if k == "revolute"
                         else rng.uniform(-1.0, 1.0, DET_POINTS) for k in kinds])
    args = [values[p] for p in sorted(values, key=str)]
    dets = np.array([np.linalg.det(np.asarray(J(*q, *args), dtype=float)) for q in Q])
    vals = np.array([[float(f(*q, *args)) for f in funcs] for q in Q])
    if np.any(dets == 0.0) or np.any(vals == 0.0):
        return None, None
    if powers is None:
        X = np.column_stack([np.ones(len(Q)), np.log(np.abs(vals))])
        coef, *_ = np.linalg.lstsq(X, np.log(np.abs(dets)), rcond=None)
        powers = tuple(int(round(m)) for m in coef[1:])
        if any(m < 1 for m in powers):
            return None, None
    ratios = dets / np.prod(vals ** np.array(powers), axis=1)
    kappa = float(np.median(ratios))
    if kappa == 0.0 or np.max(np.abs(ratios - kappa)) > DET_FACTOR_RTOL * abs(kappa):
        return None, None
    return kappa, powers


def factored_determinant(jacobian, variables, kinds, factors, params, rng):
    """det J as the product of ``factors``, or None when they do not make it up.

    Parameters
    ----------
    jacobian : sympy.Matrix
        The square matrix J, in the joint variables and the parameters.
    variables : sequence of sympy.Symbol
        The joint variables.
    kinds : sequence of str
        ``"revolute"`` or ``"prismatic"`` per variable (angles drawn in [-pi, pi],
        lengths in [-1, 1]).
    factors : sequence of sympy.Expr
        The equations of the components (one each).
    params : dict
        Parameter symbol -> value.  The constant is fitted at these values and at two
        random multiples of them (each value times 0.5 to 2), so that an exact constant
        is one in the parameters, not a coincidence of their values.
    rng : numpy.random.Generator

    Examples
    --------
    >>> import numpy as np, sympy as sp
    >>> q1, q2, a = sp.symbols("q1 q2 a")
    >>> J = sp.Matrix([[a * sp.sin(q2), 0], [q1, 2]])
    >>> d = factored_determinant(J, [q1, q2], ["revolute"] * 2, [sp.sin(q2)], {a: 0.5},
    ...                          np.random.default_rng(0))
    >>> d.constant, d.powers
    (2*a, (1,))
    """
    if not factors:
        return None
    names = sorted(params, key=str)
    J = sp.lambdify(list(variables) + names, sp.Matrix(jacobian), "numpy")
    funcs = [sp.lambdify(list(variables) + names, sp.sympify(f, strict=True), "numpy") for f in factors]
    base = {p: float(params[p]) for p in names}
    kappa, powers = _constant(J, variables, kinds, funcs, base, None, rng)
    if kappa is None:
        return None
    kappas, sets = [kappa], [base]
    for _ in range(2 if names else 0):
        other = {p: v * float(rng.uniform(0.5, 2.0)) for p, v in base.items()}
        k, _ = _constant(J, variables, kinds, funcs, other, powers, rng)
        if k is None:
            break
        kappas.append(k)
        sets.append(other)
    exact = _exact_constant(kappas, sets) if len(kappas) == len(sets) == (3 if names else 1) \
        else None
    constant = exact if exact is not None else sp.Float(kappa, 6)
    return FactoredDeterminant(constant, tuple(factors), powers, exact is not None,
                               DET_POINTS * len(kappas))


@dataclass(frozen=True)
class MinorGcd:
    """The gcd of the maximal minors of a wide or tall J, factored, or why it is not given.

    ``factors`` (in the joint variables) and ``powers`` are empty when the gcd is a constant
    (or ``skipped`` says why it was not computed); ``minors`` is how many maximal minors J
    has; ``parameter_factor`` is the product of the factors in the parameters alone (zero
    only at special parameter values).
    """

    shape: tuple
    minors: int
    factors: tuple = ()
    powers: tuple = ()
    skipped: str = ""
    parameter_factor: sp.Expr = sp.Integer(1)  # the factors in the parameters alone


def maximal_minor_gcd(matrix, variables, angles, *, max_minors: int = MAX_MINORS,
                      max_terms: int = MINOR_MAX_TERMS) -> MinorGcd:
    """The gcd of the maximal minors of a wide or tall ``matrix``, factored, computed exactly.

    The minors are polynomials in the half-angle cosines and sines of ``angles``, the other
    variables and the parameters (FLINT, over the rationals); their gcd, with the circles
    ``cos(q/2)**2 + sin(q/2)**2`` and constants dropped, vanishes exactly where every maximal
    minor does because of one common factor: a hypersurface where J loses rank.  A gcd of 1
    says the locus has codimension 2 or more.

    Parameters
    ----------
    matrix : sympy.Matrix
        J, not square.
    variables : sequence of sympy.Symbol
        The joint variables.
    angles : sequence of sympy.Symbol
        Those of ``variables`` that enter through sin and cos.
    max_minors, max_terms : int
        Bounds: more minors than ``max_minors``, or a minor over ``max_terms`` terms, and
        the result is ``skipped`` with the reason.

    Examples
    --------
    >>> import sympy as sp
    >>> q1, q2, x = sp.symbols("q1 q2 x")
    >>> J = sp.Matrix([[sp.sin(q2), 0, sp.cos(q1) * sp.sin(q2)], [x, 1, 0]])
    >>> g = maximal_minor_gcd(J, [q1, q2, x], [q1, q2])
    >>> g.minors, g.factors, g.powers
    (3, (sin(q2),), (1,))
    """
    from ..algebra.polys import TermLimit, circle_free_det, common_factor
    from ..algebra.ring import PolyRing, square_root_primes

    M = sp.Matrix(matrix)
    m, n = M.shape
    if m == n:
        raise ValueError(f"matrix: a wide or tall J has maximal minors of interest, this one "
                         f"is square ({m} x {n})")
    small = min(m, n)
    count = math.comb(max(m, n), small)
    if count > max_minors:
        return MinorGcd((m, n), count, skipped=f"J has {count} maximal minors, more than the "
                                                f"{max_minors} computed")
    angles = tuple(angles)
    others = tuple(v for v in variables if v not in angles)
    known = set(variables)
    params = tuple(sorted({s for e in M for s in e.free_symbols if s not in known},
                          key=lambda s: s.name))
    ring = PolyRing(angles, others, params, square_root_primes(M))
    rows = ring.from_sympy_rows(M if m < n else M.T)
    minors = []
    for cols in itertools.combinations(range(max(m, n)), small):
        sub = [[row[c] for c in cols] for row in rows]
        try:
            minors.append(circle_free_det(sub, ring, max_terms=max_terms))
        except TermLimit:
            return MinorGcd((m, n), count, skipped=f"a maximal minor has more than {max_terms} "
                                                   "terms")
    g = common_factor(minors)
    if g is None or ring.is_number(g):
        return MinorGcd((m, n), count)
    circles = [ring.C(i) * ring.C(i) + ring.S(i) * ring.S(i) for i in range(ring.n_angles)]
    joints = set(range(2 * len(angles) + len(others)))
    found, parameters = {}, []
    for f, k in g.factor()[1]:
        if f.is_constant() or any(f == c for c in circles) or ring.is_number(f):
            continue
        if ring.variable_indices(f) & joints:
            e = ring.to_sympy(f)
            found[e] = found.get(e, 0) + int(k)
        else:
            parameters.append(ring.to_sympy(f) ** int(k))
    # the half angles of the ring joined again: sin(q/2) cos(q/2) is sin(q)/2, and
    # (cos(q/2) - sin(q/2)) (cos(q/2) + sin(q/2)) is cos(q)
    for q in angles:
        s, c = sp.sin(q / 2), sp.cos(q / 2)
        for pair, whole in (((s, c), sp.sin(q)), ((c - s, c + s), sp.cos(q))):
            k = min(found.get(pair[0], 0), found.get(pair[1], 0))
            if k:
                for h in pair:
                    found[h] -= k
                found[whole] = found.get(whole, 0) + k
    kept = [(e, k) for e, k in found.items() if k]
    return MinorGcd((m, n), count, tuple(e for e, _ in kept), tuple(k for _, k in kept),
                    parameter_factor=sp.Mul(*parameters))
