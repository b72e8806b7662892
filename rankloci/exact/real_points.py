"""Real points of complex components that have fewer real points than complex ones.

The rank-deficiency locus a robot meets is real.  A component of the complex
locus can have real points of lower dimension than its own: ``x**2 + y**2 = 0``
is a complex curve (the lines y = +-i x) with one real point, the origin.  The
engine's real sampling does not see such a component as a curve, and the
certificate's witness points (complex, on a random line) lie on it.

This module proves exactly where the real points of such a component are.  A
hypersurface component ``f = 0`` of the locus is a factor of the greatest common
divisor of the maximal minors.  When ``f`` is a sum of squares with positive
weights,

    f = d_1 * l_1**2 + ... + d_r * l_r**2,      d_k > 0,

found by an exact LDL factorisation of a Gram matrix on the monomials of half
its Newton polytope, its real zeros are exactly the common real zeros of the
``l_k``.  Those are solved exactly (sympy's Groebner-based solver, with
c**2 + s**2 = 1 for each angle), and each real point, or product of values per
variable, becomes a component of the real locus in solved form, with a note
naming the complex component it comes from.  A sum of squares whose ``l_k``
have no common real zero (``x**2 + y**2 + 1``) is a complex component without
real points.

Polynomials are in the variables that are not angles and in s = sin q,
c = cos q of each angle q.  A factor that is not such a sum of squares (in this
diagonal-first Gram matrix) is left alone: the locus then stays uncertified,
as before.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import sympy as sp

from ..tolerances import REAL_POINTS_MAX_ENTRY_TERMS as MAX_ENTRY_TERMS
from ..tolerances import REAL_POINTS_MAX_GRAM as MAX_GRAM
from ..tolerances import REAL_POINTS_MAX_MINORS as MAX_MINORS
from ..tolerances import REAL_POINTS_MAX_SIDE as MAX_SIDE

__all__ = ["RealPart", "definite_parts", "real_part_of", "without_real_points"]



@dataclass(frozen=True)
class RealPart:
    """The real points of one hypersurface component ``f = 0`` of the complex locus.

    Attributes
    ----------
    equation : sympy.Expr
        ``f``, in the variables and sines and cosines of the angles.
    squares : tuple of sympy.Expr
        The ``l_k`` of ``f = sum d_k l_k**2`` (d_k > 0): its real points are where all vanish.
    points : tuple of dict
        The real points: variable -> exact value, for the variables the ``l_k`` involve
        (the others are free).  Empty: no real point.
    free : tuple of sympy.Symbol
        The variables ``f`` leaves free.
    """

    equation: sp.Expr
    squares: tuple
    points: tuple
    free: tuple


class _Ring:
    """Polynomials in the non-angle variables and s, c of each angle."""

    def __init__(self, variables, angles):
        self.variables = tuple(variables)
        self.angles = tuple(v for v in variables if v in set(angles))
        self.s = {q: sp.Dummy(f"s_{q}") for q in self.angles}
        self.c = {q: sp.Dummy(f"c_{q}") for q in self.angles}
        self.others = tuple(v for v in variables if v not in set(angles))
        self.gens = (*self.others, *self.c.values(), *self.s.values())
        self._back = {**{d: sp.sin(q) for q, d in self.s.items()},
                      **{d: sp.cos(q) for q, d in self.c.items()}}

    def poly(self, expr, domain="QQ"):
        """``expr`` as a Poly over ``domain`` (None: the smallest that holds its coefficients,
        square roots included), or None when it is not a polynomial in the generators."""
        e = sp.expand(sp.expand_trig(sp.sympify(expr, strict=True)))
        rep = {}
        for a in e.atoms(sp.sin, sp.cos):
            q = a.args[0]
            if q not in self.s:
                return None
            rep[a] = (self.s if isinstance(a, sp.sin) else self.c)[q]
        e = e.xreplace(rep)
        if e.free_symbols - set(self.gens) or e.atoms(sp.Function):
            return None
        try:
            return sp.Poly(e, *self.gens, domain=domain)
        except (sp.PolynomialError, sp.polys.polyerrors.CoercionFailed):
            return None

    def expr(self, poly):
        """A Poly back as an expression in the variables, sines and cosines."""
        return poly.as_expr().xreplace(self._back)

    def circle_reduced(self, poly):
        """``poly`` with c**2 replaced by 1 - s**2 for every angle (the same function on the
        real torus)."""
        if not self.angles:
            return poly
        circles = [self.c[q] ** 2 + self.s[q] ** 2 - 1 for q in self.angles]
        rem = sp.reduced(poly.as_expr(), circles, *self.gens, order="lex")[1]
        return sp.Poly(rem, *self.gens, domain="QQ")


def sum_of_squares(poly):
    """Weights and polynomials ``(d_k, l_k)``, d_k > 0, with ``poly = sum d_k l_k**2``, or None.

    The Gram matrix G on the monomials m with m**2 in the support spreads each coefficient
    equally over the pairs of those monomials that give it; an exact LDL factorisation of G
    decides whether it is positive semidefinite.  None means "not proved", not "not a sum
    of squares".

    Examples
    --------
    >>> x, y = sp.symbols("x y")
    >>> [(d, l.as_expr()) for d, l in sum_of_squares(sp.Poly(x**2 + 2*x*y + 2*y**2, x, y))]
    [(1, x + y), (1, y)]
    >>> sum_of_squares(sp.Poly(x**2 - y**2, x, y)) is None
    True
    """
    terms = dict(poly.terms())
    if not terms or poly.total_degree() % 2:
        return None
    half = sorted({tuple(e // 2 for e in m) for m in terms if all(e % 2 == 0 for e in m)},
                  reverse=True)
    if not half or len(half) > MAX_GRAM:
        return None
    size = len(half)
    G = [[sp.Integer(0)] * size for _ in range(size)]
    pairs: dict = {}
    for i, j in itertools.product(range(size), repeat=2):
        pairs.setdefault(tuple(a + b for a, b in zip(half[i], half[j])), []).append((i, j))
    for m, coeff in terms.items():
        if m not in pairs:
            return None
        share = sp.Rational(coeff) / len(pairs[m])
        for i, j in pairs[m]:
            G[i][j] += share
    gens = poly.gens
    basis = [sp.Poly(sp.Mul(*[g ** e for g, e in zip(gens, m)]), *gens, domain="QQ")
             for m in half]
    out = []
    for k in range(size):
        d = G[k][k]
        if d < 0:
            return None
        if d == 0:
            if any(G[k][j] != 0 for j in range(k, size)):
                return None
            continue
        row = [G[k][j] / d for j in range(size)]
        out.append((d, sum((row[j] * basis[j] for j in range(k, size)),
                           sp.Poly(0, *gens, domain="QQ"))))
        for i in range(k, size):
            for j in range(k, size):
                G[i][j] -= d * row[i] * row[j]
    return out


def _hypersurface_factors(ring, matrix):
    """The irreducible factors (Polys) of the gcd of the maximal minors, or None when the
    matrix is beyond the budget or not polynomial in the ring."""
    M = sp.Matrix(matrix)
    if M.rows > M.cols:
        M = M.T
    n, m = M.shape
    if n == 0 or n > MAX_SIDE or sp.binomial(m, n) > MAX_MINORS:
        return None
    if sum(len(sp.Add.make_args(sp.expand(e))) for e in M) > MAX_ENTRY_TERMS:
        return None
    entries = [[ring.poly(M[i, j]) for j in range(m)] for i in range(n)]
    if any(e is None for row in entries for e in row):
        return None
    g = None
    for cols in itertools.combinations(range(m), n):
        sub = sp.Matrix([[entries[i][j].as_expr() for j in cols] for i in range(n)])
        minor = sp.Poly(sub.det(method="berkowitz"), *ring.gens, domain="QQ")
        if minor.is_zero:
            continue
        g = minor if g is None else g.gcd(minor)
        if g.is_ground:
            return []
    if g is None:
        return []
    return [f for f, _ in g.factor_list()[1] if not f.is_ground]


def _angle(s0, c0):
    """The angle with sine s0 and cosine c0, exactly: 0, pi, or 2 atan(s0 / (1 + c0))."""
    if sp.simplify(c0 + 1) == 0:
        return sp.pi
    return sp.simplify(2 * sp.atan(sp.radsimp(s0 / (1 + c0))))


def _real_points(ring, squares):
    """The common real zeros of ``squares`` (Polys), as dicts over the variables they
    involve, or None when they are not finitely many or not found exactly."""
    if any(p.is_ground for p in squares):
        return (), ()
    used = set().union(*(p.free_symbols for p in squares))
    involved_angles = [q for q in ring.angles if ring.s[q] in used or ring.c[q] in used]
    involved = [x for x in ring.others if x in used]
    unknowns = [*involved, *(ring.c[q] for q in involved_angles),
                *(ring.s[q] for q in involved_angles)]
    system = [p.as_expr() for p in squares] + [ring.c[q] ** 2 + ring.s[q] ** 2 - 1
                                               for q in involved_angles]
    try:
        solutions = sp.solve(system, unknowns, dict=True)
    except (NotImplementedError, sp.PolynomialError):
        return None
    points = []
    for sol in solutions:
        if set(sol) != set(unknowns) or any(v.free_symbols for v in sol.values()):
            return None         # not finitely many: a parametric solution
        if any(v.is_real is False for v in sol.values()):
            continue
        if any(v.is_real is not True for v in sol.values()):
            return None
        point = {x: sol[x] for x in involved}
        for q in involved_angles:
            point[q] = _angle(sol[ring.s[q]], sol[ring.c[q]])
        points.append(point)
    free = tuple(v for v in ring.variables if v not in set(involved) | set(involved_angles))
    return tuple(points), free


def real_part_of(equation, variables, angles):
    """The :class:`RealPart` of the hypersurface ``equation = 0``, or None when it is not
    proved to have real points of lower dimension (not a sum of squares here, or its real
    points not solved exactly).

    Examples
    --------
    >>> x, y = sp.symbols("x y", real=True)
    >>> part = real_part_of(sp.sin(x)**2 + sp.sin(y)**2, (x, y), (x, y))
    >>> sorted(tuple(p.values()) for p in part.points)
    [(0, 0), (0, pi), (pi, 0), (pi, pi)]
    >>> real_part_of(x**2 + y**2 + 1, (x, y), ()).points
    ()
    """
    ring = _Ring(variables, angles)
    f = ring.poly(equation)
    if f is None or f.is_ground:
        return None
    candidates = [f, -f]
    if ring.angles:
        g = ring.circle_reduced(f)
        candidates += [g, -g]
    for p in candidates:
        sos = sum_of_squares(p)
        if sos is None:
            continue
        squares = [sp.Poly(sp.sqf_part(sq.as_expr()), *ring.gens, domain="QQ")
                   if not sq.is_ground else sq for _, sq in sos]
        found = _real_points(ring, squares)
        if found is None:
            return None
        points, free = found
        return RealPart(sp.sympify(equation, strict=True), tuple(ring.expr(s) for s in squares), points,
                        free)
    return None


def definite_parts(matrix, variables, angles):
    """The :class:`RealPart` of every hypersurface component of the complex locus of
    ``matrix`` that is a sum of squares (real points of lower dimension, or none).

    ``matrix`` has its parameters substituted.  Empty when there is none, or when the matrix
    is beyond the budget of the symbolic expansion (:data:`MAX_SIDE`, :data:`MAX_MINORS`).

    Examples
    --------
    >>> x, y = sp.symbols("x y", real=True)
    >>> [(p.equation, p.points) for p in definite_parts(sp.Matrix([[x, -y], [y, x]]),
    ...                                                 (x, y), ())]
    [(x**2 + y**2, ({x: 0, y: 0},))]
    """
    ring = _Ring(variables, angles)
    factors = _hypersurface_factors(ring, matrix)
    out = []
    for f in factors or ():
        part = real_part_of(ring.expr(f), variables, angles)
        if part is not None:
            out.append(part)
    return out


def _fixed_equation(var, values, is_angle):
    """One equation of ``var`` that vanishes, over the complex numbers too, exactly at
    ``values`` (an angle's in its half angle, so that no other angle is a zero)."""
    vals = set(values)
    if not is_angle:
        return sp.expand(sp.Mul(*[var - v for v in values]))
    if vals == {sp.S.Zero, sp.pi}:
        return sp.sin(var)
    if vals == {sp.pi / 2, -sp.pi / 2}:
        return sp.cos(var)
    factors = []
    for v in values:
        if v == sp.pi:
            factors.append(sp.cos(var / 2))
        else:
            factors.append(sp.sin(var / 2) - sp.radsimp(sp.tan(v / 2)) * sp.cos(var / 2))
    return sp.expand(sp.Mul(*factors))


def _rank_drop(matrix, point, free, angles, rng):
    """min(rows, cols) minus the exact rank of ``matrix`` at ``point``, the free variables at
    random rationals (an angle at a random rational half-angle tangent)."""
    subs = dict(point)
    for v in free:
        t = sp.Rational(int(rng.integers(1, 10 ** 6)), int(rng.integers(1, 10 ** 6)))
        subs[v] = 2 * sp.atan(t) if v in set(angles) else t
    A = sp.Matrix(matrix).applyfunc(lambda e: sp.radsimp(sp.expand_trig(e.subs(subs))))
    return min(A.shape) - A.rank(simplify=True)


def real_point_components(part, matrix, variables, angles, rng):
    """The components of the real locus that hold the real points of ``part``: one per set of
    points with the same rank drop that is a product of values per variable, else one per
    point; each in solved form, its ``real_points_of`` the complex component's equation."""
    from ..loci import Component

    angles = set(angles)
    drops: dict = {}
    for p in part.points:
        drops.setdefault(_rank_drop(matrix, p, part.free, angles, rng), []).append(p)
    out = []
    for drop, points in sorted(drops.items(), key=lambda kv: -kv[0]):
        if drop < 1:
            continue        # not singular there: cannot happen on a factor of the minors
        fixed = [v for v in variables if v in points[0]]
        per_var = {v: sorted(dict.fromkeys(p[v] for p in points), key=float) for v in fixed}
        product = 1
        for vals in per_var.values():
            product *= len(vals)
        groups = [per_var] if product == len(points) else [
            {v: [p[v]] for v in fixed} for p in points]
        for g in groups:
            out.append(Component(
                tuple(_fixed_equation(v, g[v], v in angles) for v in fixed),
                solved={v: tuple(g[v]) for v in fixed}, free=part.free,
                dimension=len(part.free), rank_drop=drop, real_points_of=(part.equation,)))
    return out


def without_real_points(equations, variables, angles) -> bool:
    """Is it proved that ``equations`` have no common real zero?  True when one of them has
    none: a polynomial in one variable, or in the sine and cosine of one angle, without real
    solutions, or a weighted sum of squares without a common real zero (``x**2 + y**2 + 1``).
    False means "not proved".

    Examples
    --------
    >>> x, q = sp.symbols("x q", real=True)
    >>> without_real_points([sp.sin(q) - 3 - sp.sqrt(2)], (q, x), (q,))
    True
    >>> without_real_points([sp.sin(q) - sp.Rational(1, 2)], (q, x), (q,))
    False
    """
    ring = _Ring(variables, angles)
    for e in equations:
        p = ring.poly(e, domain=None)
        if p is None or p.is_ground:
            if p is not None and not p.is_zero:
                return True
            continue
        used = p.free_symbols
        if len({ring.s.get(q) for q in ring.angles if ring.s[q] in used or ring.c[q] in used}
               | {x for x in ring.others if x in used}) == 1:
            found = _real_points(ring, [p])
            if found is not None and not found[0]:
                return True
        part = real_part_of(e, variables, angles)
        if part is not None and not part.points:
            return True
    return False
