"""The certificate of a locus: witness points of every component, modulo a large prime.

What it proves
--------------
Let V be the set of complex configurations at which an n x m matrix J
(n <= m after transposing) has rank below n: the zero set of its maximal
minors, with c_i = cos q_i, s_i = sin q_i on the complex circles
c_i**2 + s_i**2 = 1.  By Eagon and Northcott, every irreducible component of
V has codimension at most m - n + 1.  A *witness set* of the components of
codimension c is their intersection with a random affine subspace of
dimension c: finitely many points, at least one on every such component,
each a generic point of its component (numerical algebraic geometry's
witness sets, as in Bertini).

The certificate computes, for each codimension c that can occur, the
witness points of V, and for each reported component of that codimension
its own witness points (its equations on the same subspace, minus its
exclusions), all exactly in a finite field GF(P^k), P a random prime near
2**61.  It then proves

- *completeness*: every witness point of V lies on a reported component of
  its codimension, with the component's exclusions nonzero there: every
  component of V, hence every singular configuration, real or complex, is
  covered;
- *soundness*: every witness point of every reported component is a point
  of V at which the rank drops by exactly the component's ``rank_drop``;
  the reported dimension is the dimension of the component's equations off
  their exclusions.

A robot's locus is real.  A reported component may hold the real points of
a hypersurface f = 0 of the complex locus that has fewer of them
(``real_points_of``, see :mod:`rankloci.exact.real_points`): the claim is
proved again here (f a weighted sum of squares, its real zeros on the
components that name it), and f = 0 then covers the witness points on it.
Components without real points (``complex_only``) cover witness points too.

Nothing here depends on the branch tree, on floating point or on a
tolerance.  The random choices (prime, chart, subspace, compressions) can
only make it *fail to prove* a true statement or, with a probability
bounded by the Schwartz-Zippel lemma, accept a false one: each decision is
the vanishing of a polynomial of degree D in the random choices, so a
wrong verdict has probability at most (sum of those degrees) / P; the bound
is computed from the degrees and stated in the result.

Coordinates
-----------
Each angle is written in half-angle coordinates C = cos(q/2), S = sin(q/2);
every entry, padded along its row with powers of C**2 + S**2 = 1, is a form
of one degree per angle.  On the chart q = psi + 2 atan(t), with a random
rotation psi, the form becomes a polynomial in t (the factor cos(t)**deg is
nonzero there); the only configurations outside the chart are
q = psi + pi, random values that a component hits only when it fixes q at
exactly that value.  The points t = +-i, where C**2 + S**2 vanishes, are the
circle's points at infinity and are removed.

Limits
------
Witness points are computed for codimensions 1 to ``MAX_CODIMENSION`` (4):
on a subspace of dimension c, c - 1 variables are eliminated with
resultants, one at a time, and each elimination squares the degrees.  A
codimension whose determinants or eliminations exceed the budgets
(``MAX_ELIMINATION_DEGREE``, ``MAX_ELIMINATION_TERMS``) is left undecided,
and so is a codimension above ``MAX_CODIMENSION``; the result names each one
and why.  In practice codimensions 3 and 4 are decided for small matrices
(planar4r, 2 x 4).  Where a subspace of dimension 3 is beyond the budgets and
no higher codimension can occur (6 x 8 chains), codimension 3 is decided on
coordinate slices instead (:class:`_CoordinatePlane`), which keep the minors'
low degree in each variable.  Codimension 4 stays undecided on long chains,
whose determinants on a subspace have degree 70 to 80 (mobile10, 6 x 10; the
9R snake, 6 x 9); a component of such a codimension given in solved form is
still checked for soundness at a point of each of its pieces.  Expressions must be
polynomials in sines and cosines of rational multiples of the angles (half
angles included), the other variables and square roots of integers.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
import threading
import time
from dataclasses import dataclass

import flint
import numpy as np
import sympy as sp

from ..errors import RanklociError
from .certificate import CERTIFICATE_KIND, Certificate
from ..tolerances import (MAX_CODIMENSION, MAX_ELIMINATION_DEGREE, MAX_ELIMINATION_TERMS,
                          MAX_FIXED_DEGREE, MAX_HEIGHT, MAX_RELATION_HEIGHT,
                          MAX_SLICE_CODIMENSION, PRIME_BITS,
                          WITNESS_RETRIES as RETRIES)

__all__ = ["Certificate", "NotCertifiable", "certify_components", "MAX_CODIMENSION",
           "CERTIFICATE_KIND"]


class NotCertifiable(RanklociError):
    """The certificate does not apply to this matrix or these equations (with the reason)."""


# --- sympy expressions -> half-angle forms over Q ------------------------------------------


class _Forms:
    """Expressions in the angles and other variables as forms in (C_i, S_i), x_j, r_p."""

    def __init__(self, angles, others, surds):
        self.angles = tuple(angles)
        self.others = tuple(others)
        self.surds = tuple(surds)
        names = [f"C{i}" for i in range(len(angles))] + [f"S{i}" for i in range(len(angles))]
        names += [f"x{j}" for j in range(len(others))] + [f"r{p}" for p in self.surds]
        self.ctx = flint.fmpq_mpoly_ctx.get(tuple(names), "degrevlex")
        g = self.ctx.gens()
        na = len(angles)
        self.C, self.S = g[:na], g[na:2 * na]
        self.X = g[2 * na:2 * na + len(others)]
        self.R = g[2 * na + len(others):]
        self._angle_index = {q: i for i, q in enumerate(self.angles)}
        self._other_index = {x: j for j, x in enumerate(self.others)}

    def _half_multiple(self, arg):
        """(angle index, k) when ``arg`` = k * q / 2 for an angle q and an integer k."""
        coeffs = arg.as_coefficients_dict()
        if len(coeffs) != 1:
            return None
        (sym, coeff), = coeffs.items()
        if sym not in self._angle_index or not coeff.is_Rational:
            return None
        k = 2 * coeff
        if not k.is_Integer:
            return None
        return self._angle_index[sym], int(k)

    def _trig(self, i, k, kind):
        C, S = self.C[i], self.S[i]
        re, im = self.ctx.constant(1), self.ctx.constant(0)
        for _ in range(abs(k)):
            re, im = re * C - im * S, re * S + im * C
        if kind is sp.cos:
            return re
        return im if k >= 0 else -im

    def form(self, expr):
        """``expr`` as a polynomial in the generators (not yet homogeneous)."""
        expr = sp.sympify(expr, strict=True)
        allowed = set(self.angles) | set(self.others)
        unknown = expr.free_symbols - allowed
        if unknown:
            raise NotCertifiable(f"{sp.sstr(expr)[:80]} has symbols without values: "
                                 f"{', '.join(sorted(map(str, unknown)))}")
        atoms = expr.atoms(sp.sin, sp.cos)
        if any(self._half_multiple(a.args[0]) is None for a in atoms):
            expr = sp.expand_trig(sp.expand(expr))
            atoms = expr.atoms(sp.sin, sp.cos)
        rep, images = {}, []
        for a in sorted(atoms, key=sp.default_sort_key):
            hm = self._half_multiple(a.args[0])
            if hm is None:
                raise NotCertifiable(f"{sp.sstr(a)} is not a sine or cosine of a rational "
                                     "multiple of one angle")
            d = sp.Dummy()
            rep[a] = d
            images.append((d, self._trig(hm[0], hm[1], type(a))))
        for a in expr.atoms(sp.Pow):
            if a.is_number:
                root = _integer_root(a)
                if root is None:
                    raise NotCertifiable(f"the constant {sp.sstr(a)} is not a square root of an "
                                         "integer")
                n, sign = root
                value = sp.Integer(1)
                for prime, mult in sp.factorint(n).items():
                    if prime not in self.surds:
                        raise NotCertifiable(f"sqrt({prime}) is not among the surds")
                    d = sp.Dummy()
                    images.append((d, self.R[self.surds.index(prime)]))
                    value *= d ** mult
                rep[a] = value if sign > 0 else value / n
        e = expr.xreplace(rep) if rep else expr
        for x, j in self._other_index.items():
            images.append((x, self.X[j]))
        gens = [d for d, _ in images]
        if not gens:
            try:
                value = sp.Rational(e)
            except TypeError:
                raise NotCertifiable(f"{sp.sstr(expr)[:80]} is not a rational constant") from None
            return self.ctx.constant(flint.fmpq(int(value.p), int(value.q)))
        try:
            poly = sp.Poly(e, *gens, domain="QQ")
        except (sp.PolynomialError, sp.polys.polyerrors.CoercionFailed) as exc:
            raise NotCertifiable(f"{sp.sstr(expr)[:80]} is not a polynomial in sines, cosines "
                                 f"and the variables: {exc}") from None
        aux = flint.fmpq_mpoly_ctx.get(tuple(f"g{k}" for k in range(len(gens))), "degrevlex")
        terms = {m: flint.fmpq(int(c.p), int(c.q)) for m, c in poly.terms()}
        return aux.from_dict(terms).compose(*[img for _, img in images], ctx=self.ctx)

    def number(self, x):
        """An exact number (rationals and square roots of integers) as a constant form."""
        p = self.form(sp.sympify(x, strict=True))
        if any(sum(m[:2 * len(self.angles) + len(self.others)]) for m in p.monoms()):
            raise NotCertifiable(f"{sp.sstr(x)} is not a number")
        return p

    def degrees(self, p):
        """Per angle: the set of degrees of the terms of ``p`` in (C_i, S_i)."""
        na = len(self.angles)
        out = [set() for _ in range(na)]
        for mon in p.monoms():
            for i in range(na):
                out[i].add(mon[i] + mon[na + i])
        return out

    def homogeneous(self, p, target):
        """``p`` padded with powers of C_i**2 + S_i**2 to degree ``target[i]`` in each pair."""
        na = len(self.angles)
        if not na or p.is_zero():
            return p
        parts: dict = {}
        for mon, coeff in zip(p.monoms(), p.coeffs()):
            key = tuple(mon[i] + mon[na + i] for i in range(na))
            parts.setdefault(key, []).append((mon, coeff))
        out = self.ctx.constant(0)
        for key, terms in parts.items():
            part = self.ctx.from_dict(dict(terms))
            for i, d in enumerate(key):
                pad = target[i] - d
                if pad % 2:
                    raise NotCertifiable(f"an expression mixes odd and even degrees in the "
                                         f"half angle of {self.angles[i]}: it is not a function "
                                         "on the circle")
                if pad:
                    part *= (self.C[i] ** 2 + self.S[i] ** 2) ** (pad // 2)
            out += part
        return out

    def homogeneous_form(self, expr):
        p = self.form(expr)
        target = [max(d) if d else 0 for d in self.degrees(p)]
        return self.homogeneous(p, target)

    def homogeneous_rows(self, M):
        rows = []
        for r in range(M.rows):
            entries = [self.form(M[r, k]) for k in range(M.cols)]
            target = [0] * len(self.angles)
            for e in entries:
                for i, d in enumerate(self.degrees(e)):
                    target[i] = max([target[i], *d])
            rows.append([self.homogeneous(e, target) for e in entries])
        return rows


def _integer_root(atom):
    if atom.base.is_Integer and atom.base > 0 and atom.exp in (sp.S.Half, -sp.S.Half):
        return int(atom.base), 1 if atom.exp > 0 else -1
    return None


# --- finite fields --------------------------------------------------------------------------


def _random_prime(rng, surds):
    """A prime P in [2**PRIME_BITS, 2**(PRIME_BITS+1)) with a square root of every surd."""
    from ..tree.modular import prime_with_roots

    while True:
        found = prime_with_roots(rng, surds, PRIME_BITS)
        if found is not None:
            return found


def _mod(q, P):
    den = int(q.q) % P
    if den == 0:
        raise ZeroDivisionError
    return int(q.p) * pow(den, -1, P) % P


def _chart(tau, P, rand):
    """The images of C_i and S_i (half-angle cosine and sine, up to a common factor) of the
    angles whose chart coordinates are ``tau``: q = psi + 2 atan(t), with a random rotation
    psi of each chart, (cos psi, sin psi) from a random tangent drawn by ``rand()``."""
    images_C, images_S = [], []
    for t in tau:
        w = rand()
        inv = pow(1 + w * w, -1, P)
        cp, sp_ = (1 - w * w) * inv % P, 2 * w * inv % P
        images_C.append(cp - sp_ * t)
        images_S.append(sp_ + cp * t)
    return images_C, images_S


class _Plane:
    """A random affine subspace of dimension c in the chart, and forms restricted to it."""

    def __init__(self, forms: _Forms, P: int, roots, c: int, rng):
        self.forms, self.P, self.c = forms, P, c
        self.ctx = flint.nmod_mpoly_ctx.get(tuple(f"u{k}" for k in range(c)), modulus=P)
        u = self.ctx.gens()
        self.u = u

        def rand():
            return int(rng.integers(1, P))

        def affine():
            return self.ctx.constant(rand()) + sum((rand() * uk for uk in u), self.ctx.constant(0))

        na = len(forms.angles)
        self.tau = [affine() for _ in range(na)]
        images_C, images_S = _chart(self.tau, P, rand)
        images = images_C + images_S + [affine() for _ in forms.others]
        images += [self.ctx.constant(r) for r in roots]
        self.images = images
        self.fctx = flint.nmod_mpoly_ctx.get(forms.ctx.names(), modulus=P)
        #: the circles' points at infinity: 1 + tau_i**2 = 0
        self.infinity = [1 + t * t for t in self.tau]

    def restrict(self, p):
        """A form over Q as a polynomial in the plane's coordinates over GF(P)."""
        P = self.P
        terms = {m: _mod(c, P) for m, c in zip(p.monoms(), p.coeffs())}
        if not terms:
            return self.ctx.constant(0)
        return self.fctx.from_dict(terms).compose(*self.images, ctx=self.ctx)


class _CoordinatePlane(_Plane):
    """A coordinate slice of the chart: the variables ``free`` (indices into the angles, then
    the other variables) are its coordinates, every other variable is fixed at a random value.

    A maximal minor of a chain's J has a low degree in each angle (at most 4 in the half
    angle, see docs/explanation/certificate.md): a slice keeps these degrees per coordinate,
    where a random subspace adds them over every angle.  Every component of codimension c
    meets the slices over some c free variables in isolated points, each a generic point of
    it (among its coordinates there is a transcendence basis of its function field; the fixed
    values are random).  Projections along coordinates are not generic:
    :func:`_isolated` lifts several points per fibre, and stops with :class:`_Curves` where
    a positive-dimensional part could hide a point."""

    def __init__(self, forms: _Forms, P: int, roots, free, rng, *, mixed=False):
        self.forms, self.P, self.c, self.free = forms, P, len(free), tuple(free)
        self.ctx = flint.nmod_mpoly_ctx.get(tuple(f"u{k}" for k in range(self.c)), modulus=P)
        u = self.ctx.gens()
        self.u = u
        #: ``mixed``: the free variables are random affine functions of the coordinates (a
        #: random subspace of the slice, where projections are generic, at a higher degree)
        self.mixed = mixed
        if mixed:
            where = {i: self.ctx.constant(int(rng.integers(1, P)))
                     + sum((int(rng.integers(1, P)) * x for x in u), self.ctx.constant(0))
                     for i in self.free}
        else:
            where = {i: u[k] for k, i in enumerate(self.free)}

        def value(i):
            return where[i] if i in where else self.ctx.constant(int(rng.integers(1, P)))

        na = len(forms.angles)
        self.tau = [value(i) for i in range(na)]
        images_C, images_S = _chart(self.tau, P, lambda: int(rng.integers(1, P)))
        self.images = (images_C + images_S + [value(na + j) for j in range(len(forms.others))]
                       + [self.ctx.constant(r) for r in roots])
        self.fctx = flint.nmod_mpoly_ctx.get(forms.ctx.names(), modulus=P)
        self.infinity = [1 + t * t for t in self.tau]

    def names(self) -> str:
        variables = list(self.forms.angles) + list(self.forms.others)
        return ", ".join(str(variables[i]) for i in self.free)

    def restrict(self, p):
        """A form over Q on the slice: the fixed variables are substituted first (flint's
        substitution of constants), which leaves few terms to compose."""
        cache = self.forms.__dict__.setdefault("_nmod", {})
        hit = cache.get((id(p), self.P))
        if hit is None or hit[0] is not p:
            terms = {m: _mod(c, self.P) for m, c in zip(p.monoms(), p.coeffs())}
            hit = (p, self.fctx.from_dict(terms) if terms else None)
            cache[(id(p), self.P)] = hit
        q = hit[1]
        if q is None:
            return self.ctx.constant(0)
        names = self.fctx.names()
        fixed = {names[g]: int(img.coeffs()[0]) if not img.is_zero() else 0
                 for g, img in enumerate(self.images)
                 if img.is_constant() and names[g] in q.context().names()}
        q = q.subs(fixed)
        return q.compose(*self.images, ctx=self.ctx)


# --- determinants and points ----------------------------------------------------------------


def _det(rows):
    """Determinant of a square matrix of nmod_mpoly (fraction-free Bareiss)."""
    a = [list(r) for r in rows]
    n = len(a)
    if n == 0:
        return None
    sign, prev = 1, None
    for k in range(n - 1):
        piv = next((i for i in range(k, n) if not a[i][k].is_zero()), None)
        if piv is None:
            return a[0][0] * 0
        if piv != k:
            a[k], a[piv] = a[piv], a[k]
            sign = -sign
        for i in range(k + 1, n):
            for j in range(k + 1, n):
                v = a[k][k] * a[i][j] - a[i][k] * a[k][j]
                a[i][j] = v if prev is None else v / prev
        prev = a[k][k]
    return a[n - 1][n - 1] * sign


def _compressions(M, n, m, count, P, rng):
    """``count`` determinants det(M R) for random m x n matrices R over GF(P)."""
    if n == m:
        return [_det(M)]
    out = []
    for _ in range(count):
        R = [[int(rng.integers(0, P)) for _ in range(n)] for _ in range(m)]
        MR = [[sum((M[r][j] * R[j][k] for j in range(m)), M[r][0] * 0) for k in range(n)]
              for r in range(n)]
        out.append(_det(MR))
    return out


def _to_poly(p, P):
    """A polynomial in one variable (nmod_mpoly) as an nmod_poly."""
    d = p.to_dict()
    if not d:
        return flint.nmod_poly([], P)
    deg = max(m[0] for m in d)
    coeffs = [0] * (deg + 1)
    for m, v in d.items():
        coeffs[m[0]] = int(v)
    return flint.nmod_poly(coeffs, P)


def _strip(f, g):
    """``f`` with every factor shared with ``g`` removed (both nmod_poly)."""
    while f.degree() > 0:
        h = f.gcd(g)
        if h.degree() <= 0:
            break
        f = f // h
    return f


class _Point:
    """A witness point: coordinates in GF(P)[z]/(f) for an irreducible f (one Galois orbit)."""

    def __init__(self, field_ctx, coords, degree):
        self.F = field_ctx
        self.coords = coords       # field elements, one per plane coordinate
        self.degree = degree       # points in its Galois orbit

    def value(self, p):
        """The value of an nmod_mpoly in the plane's coordinates at the point."""
        return _value(p, self.coords, self.F)

    def rank(self, M):
        """Rank of a matrix of nmod_mpoly at the point (Gaussian elimination over the field)."""
        a = [[self.value(x) for x in row] for row in M]
        rank, rows, cols = 0, len(a), len(a[0]) if a else 0
        for j in range(cols):
            piv = next((i for i in range(rank, rows) if not a[i][j].is_zero()), None)
            if piv is None:
                continue
            a[rank], a[piv] = a[piv], a[rank]
            inv = 1 / a[rank][j]
            for i in range(rows):
                if i != rank and not a[i][j].is_zero():
                    f = a[i][j] * inv
                    a[i] = [x - f * y for x, y in zip(a[i], a[rank])]
            rank += 1
        return rank


def _field(f, P):
    return flint.fq_default_ctx(modulus=flint.fmpz_mod_poly_ctx(P)([int(c) for c in f.coeffs()]))


class _Degenerate(RanklociError):
    """A random choice that does not separate points; retried with fresh choices."""


def _combinations(polys, count, P, rng):
    out = []
    for _ in range(count):
        out.append(sum((int(rng.integers(1, P)) * p for p in polys), polys[0] * 0))
    return out


class _TooLarge(RanklociError):
    """The elimination would exceed :data:`MAX_ELIMINATION_DEGREE`."""


class _Curves(RanklociError):
    """On a coordinate slice, the polynomials have a positive-dimensional common part below
    the hypersurface one: a projection along a coordinate could map an isolated point onto
    it, so the isolated points found are not proved to be all."""


def _embedding(F, E):
    """A map from the field F into the field E (whose degree is a multiple of F's): the
    image of F's generator is a root of F's defining polynomial in E."""
    if F.degree() == 1:
        return lambda x: E(int(x))
    ring = flint.fq_default_poly_ctx(E)
    modulus = ring([E(int(c)) for c in F.modulus().coeffs()])
    root = modulus.roots()[0][0]
    powers = [E(1)]
    for _ in range(F.degree() - 1):
        powers.append(powers[-1] * root)

    def image(x):
        total = E(0)
        for c, pw in zip(x.to_list(), powers):
            if int(c):
                total += E(int(c)) * pw
        return total

    return image


def _fibre_points(common, F, coords, d, P):
    """The points over ``coords`` (in F, an orbit of ``d`` points) where the squarefree
    polynomial ``common`` (over F) in the next coordinate vanishes: one point per
    irreducible factor, over an extension of F of the factor's degree."""
    out = []
    for fac, _ in common.factor()[1]:
        e = fac.degree()
        if e == 1:
            c = fac.coeffs()
            out.append((F, list(coords) + [-c[0] / c[1]], d))
            continue
        E = flint.fq_default_ctx(P, F.degree() * e)
        image = _embedding(F, E)
        ring = flint.fq_default_poly_ctx(E)
        root = ring([image(c) for c in fac.coeffs()]).roots()[0][0]
        out.append((E, [image(x) for x in coords] + [root], d * e))
    return out


def _univariate_points(f, P):
    """One representative point (a field element) per irreducible factor of ``f``."""
    out = []
    if f.degree() <= 0:
        return out
    for fac, _ in f.factor()[1]:
        if fac.degree() == 1:
            F = flint.fq_default_ctx(P, 1)
            out.append((F, F(int(-fac.coeffs()[0]) % P), 1))
        else:
            F = _field(fac, P)
            out.append((F, F.gen(), fac.degree()))
    return out


def _at(p, coords, F, k):
    """``p`` (nmod_mpoly in u0..) with u0..u_{k-1} = ``coords`` (in F): a polynomial in u_k over F."""
    if F.degree() == 1:
        # coordinates in GF(P) itself: flint substitutes their integers
        q = p.subs({f"u{j}": int(coords[j]) for j in range(k)}) if k else p
        terms = q.to_dict()
        out = [F(0)] * (max((m[k] for m in terms), default=0) + 1)
        for mon, coeff in terms.items():
            out[mon[k]] = F(int(coeff))
        return flint.fq_default_poly_ctx(F)(out)
    coeffs: dict = {}
    for mon, coeff in zip(p.monoms(), p.coeffs()):
        term = F(int(coeff))
        for j in range(k):
            if mon[j]:
                term *= coords[j] ** mon[j]
        coeffs[mon[k]] = coeffs.get(mon[k], F(0)) + term
    deg = max(coeffs) if coeffs else 0
    return flint.fq_default_poly_ctx(F)([coeffs.get(j, F(0)) for j in range(deg + 1)])


def _isolated(polys, k, P, rng, *, coordinate=False, top=True, infinity=frozenset()):
    """The isolated common zeros of ``polys`` in the variables u0 .. u_{k-1} (the others
    absent), off the hypersurface of their gcd: (field, coords, orbit size) per Galois orbit.

    One variable is eliminated at a time: the resultants in u_{k-1} of one random combination
    of the polynomials with k others vanish on the projection of their common zeros; the
    isolated zeros of the resultants (recursively) are lifted back by the gcd of the
    polynomials at them, and the extraneous ones have none.  Positive-dimensional parts project
    to positive-dimensional parts, never to isolated points, at a generic projection (the
    subspace is random).

    On a coordinate slice (``coordinate``) the projections are along coordinates.  There a
    fibre may hold several points, which are lifted over extensions of the field; and a
    positive-dimensional part below the hypersurface one raises :class:`_Curves`: it shows as
    a common factor of the resultants (or a fibre where every polynomial vanishes), and an
    isolated point whose fibre meets it would be divided out with it.  Without such a part the
    common zeros off the hypersurface are finitely many, each projects to a common zero of the
    resultants, and every one of them is found.  A variable absent from every polynomial (a
    cylinder) leaves no isolated point at the top and is a positive-dimensional part below.
    """
    polys = [p for p in polys if not p.is_zero()]
    if not polys:
        if coordinate and not top:
            raise _Curves("every resultant vanishes")
        raise _Degenerate("every polynomial vanishes")
    if k == 1:
        g = polys[0]
        for p in polys[1:]:
            g = g.gcd(p)
        return [(F, [x], d) for F, x, d in _univariate_points(_to_poly(g, P), P)]
    h = polys[0]
    for p in polys[1:]:
        h = h.gcd(p)
    if coordinate and not top and not h.is_constant():
        raise _Curves("the resultants have a common factor")
    reduced = [p / h for p in polys]
    if any(p.is_constant() for p in reduced) or len(reduced) < 2:
        return []
    if coordinate:
        used = [any(p.degrees()[j] for p in reduced) for j in range(k)]
        if not all(used):
            if top:
                return []       # a cylinder: no isolated point
            raise _Curves("a variable is absent from every resultant")
    var = f"u{k - 1}"
    combos = _combinations(reduced, k + 1, P, rng)
    deg = max(int(c.total_degree()) for c in combos)
    # the resultant has degree up to deg**2 in the k - 1 variables left: about
    # (deg**2)**(k - 1) / (k - 1)! terms
    degree, terms = deg * deg, (deg * deg) ** (k - 1) / math.factorial(k - 1)
    if coordinate:
        # per variable left, the resultant's degree is at most
        # deg_last(f) deg_j(g) + deg_j(f) deg_last(g) (the Sylvester matrix)
        dv = [max(int(c.degrees()[j]) for c in combos) for j in range(k)]
        bounds = [2 * dv[k - 1] * dv[j] for j in range(k - 1)]
        degree = min(degree, max(bounds))
        terms = min(terms, math.prod(b + 1 for b in bounds))
    if degree > MAX_ELIMINATION_DEGREE or terms > MAX_ELIMINATION_TERMS:
        raise _TooLarge(f"eliminating a variable from {k} with polynomials of degree {deg}")
    res = [combos[0].resultant(c, var) for c in combos[1:]]
    if all(r.is_zero() for r in res):
        if coordinate:
            raise _Curves("the combinations share a factor")
        raise _Degenerate("the combinations share a factor")
    lines, taken_apart = [], False
    if coordinate and top and k == 3:
        # curves of a 3-dimensional slice that lie in planes u_j = a (components that fix a
        # variable, as robots' do) are taken apart: the points off those planes come from
        # the resultants off their lines, the points in them from each plane on its own
        lines = _coordinate_lines([r for r in res if not r.is_zero()], P, infinity)
        taken_apart = True      # the common factor of the resultants is lines only
    out = []
    for F, coords, d in _isolated(res, k - 1, P, rng, coordinate=coordinate,
                                  top=taken_apart):
        common = None
        for p in reduced:
            q = _at(p, coords, F, k - 1)
            common = q if common is None else common.gcd(q)
        if common is None or common.is_zero():
            if coordinate and top:
                # a line along the last coordinate: every point over coords lies on it, and
                # no other point projects there
                continue
            if coordinate:
                raise _Curves("a fibre on which every polynomial vanishes")
            raise _Degenerate("a projection that is not generic")
        if common.degree() <= 0:
            continue        # extraneous: a zero of the resultants that lifts to none
        common = common.radical()
        if common.degree() > 1 and not coordinate:
            raise _Degenerate(f"the projection does not separate the witness points "
                              f"({common.degree()} over one)")
        if common.degree() > 1:
            lifted = _fibre_points(common, F, coords, d, P)
        else:
            c = common.coeffs()
            lifted = [(F, list(coords) + [-c[0] / c[1]], d)]
        for F2, point, d2 in lifted:
            if _value(h, point, F2).is_zero():
                continue        # on the hypersurface part: not isolated
            out.append((F2, point, d2))
    if lines:
        out += _in_planes(reduced, h, lines, P, rng)
    return out


def _isolated_in_some_order(polys, k, P, rng, angles=frozenset()):
    """:func:`_isolated` on a coordinate slice, eliminating the coordinates in the first order
    that meets no curve it cannot take apart: where one equation alone contains the variable
    eliminated first, the polynomials have a curve at infinity over the zeros of its leading
    coefficient, which every resultant has as a factor (a triangular system, as a component
    that fixes one variable, then a second, then a third, is one).  ``angles``: the
    coordinates that are angles' half-angle tangents (their values +-i are the circles' points
    at infinity).  Points come back in the slice's own coordinates."""
    last = None
    ctx = polys[0].context()
    gens = ctx.gens()
    for order in itertools.permutations(range(k)):
        # coordinate i of the elimination is the slice's coordinate order[i]
        where = [0] * k
        for i, j in enumerate(order):
            where[j] = i
        moved = [p.compose(*[gens[where[j]] for j in range(k)]) for p in polys] \
            if list(order) != list(range(k)) else polys
        try:
            found = _isolated(moved, k, P, rng, coordinate=True,
                              infinity={i for i, j in enumerate(order) if j in angles})
        except _Curves as exc:
            last = exc
            continue
        out = []
        for F, coords, d in found:
            point = [None] * k
            for i, j in enumerate(order):
                point[j] = coords[i]
            out.append((F, point, d))
        return out
    raise last


def _coordinate_lines(res, P, infinity=frozenset()):
    """(j, a) for each line u_j = a of the common factor of the bivariate ``res`` (none when
    it is constant); :class:`_Curves` when a factor is another curve, or a line over an
    extension of GF(P).  Lines u_j = +-i of a coordinate in ``infinity`` (an angle's) are
    the circle's points at infinity: every point over them is left out in the end, so they
    are divided out and not taken apart."""
    g = res[0]
    for r in res[1:]:
        g = g.gcd(r)
    if g.is_constant():
        return []
    lines = []
    rest = g
    terms = g.to_dict()
    for j in (0, 1):
        # the content of g as a polynomial in the other variable: a polynomial in u_j alone
        by_power: dict = {}
        for mon, coeff in terms.items():
            by_power.setdefault(mon[1 - j], {})[mon[j]] = int(coeff)
        content = None
        for part in by_power.values():
            q = flint.nmod_poly([part.get(e, 0) for e in range(max(part) + 1)], P)
            content = q if content is None else content.gcd(q)
        if content is None or content.degree() <= 0:
            continue
        circle = flint.nmod_poly([1, 0, 1], P)
        for fac, _ in content.factor()[1]:
            if j in infinity and (circle % fac).is_zero():
                line = sum((int(c) * rest.context().gens()[j] ** e
                            for e, c in enumerate(fac.coeffs())), rest.context().constant(0))
                while True:
                    q, r = divmod(rest, line)
                    if not r.is_zero():
                        break
                    rest = q
                continue
            if fac.degree() != 1:
                raise _Curves("the resultants have a common factor in one variable whose "
                              "roots lie outside GF(P)")
            c = fac.coeffs()
            a = -int(c[0]) * pow(int(c[1]), -1, P) % P
            lines.append((j, a))
            line = rest.context().gens()[j] - a
            while True:
                q, r = divmod(rest, line)
                if not r.is_zero():
                    break
                rest = q
    if not rest.is_constant():
        raise _Curves("the resultants have a common factor that is no coordinate line")
    return lines


def _in_planes(reduced, h, lines, P, rng):
    """The isolated common zeros of ``reduced`` (in u0, u1, u2, off the zeros of ``h``) that
    lie in the planes u_j = a of ``lines``.

    In a plane the polynomials are bivariate; their common factor there is the curves of the
    slice in that plane, and the isolated zeros off it are found as on a 2-dimensional slice.
    Every curve of the slice lies in one of the planes (:func:`_isolated` has checked it), so
    a point is isolated in the slice when it is off the curves of every plane it lies in."""
    ctx2 = flint.nmod_mpoly_ctx.get(("u0", "u1"), modulus=P)
    v = ctx2.gens()
    cuts = []
    for j, a in lines:
        others = [i for i in range(3) if i != j]
        images = [None] * 3
        images[j] = ctx2.constant(a)
        images[others[0]], images[others[1]] = v
        polys = [p.compose(*images, ctx=ctx2) for p in reduced]
        polys = [p for p in polys if not p.is_zero()]
        curve = polys[0] if polys else ctx2.constant(0)
        for p in polys[1:]:
            curve = curve.gcd(p)
        points = _isolated(polys, 2, P, rng, coordinate=True, top=True) if polys else []
        cuts.append((j, a, others, curve, points))
    out, seen = [], set()
    for j, a, others, _, points in cuts:
        for F, coords, d in points:
            point = [None] * 3
            point[j] = F(a)
            point[others[0]], point[others[1]] = coords
            if _value(h, point, F).is_zero():
                continue
            if any(point[j2] == F(a2) and _value(curve2, [point[o] for o in others2], F).is_zero()
                   for j2, a2, others2, curve2, _ in cuts if (j2, a2) != (j, a)):
                continue        # on a curve of another plane: not isolated
            if F.degree() == 1:
                key = tuple(int(x) for x in point)
                if key in seen:
                    continue    # in two planes
                seen.add(key)
            out.append((F, point, d))
    return out


def _value(p, coords, F):
    """The value in the field F of an nmod_mpoly at ``coords`` (powers computed once each)."""
    if F.degree() == 1:
        # a point over GF(P) itself: flint evaluates the polynomial at its integers (the
        # variables past ``coords`` are absent from p)
        args = [int(x) for x in coords]
        args += [0] * (p.context().nvars() - len(args))
        return F(int(p(*args)))
    powers = [[F(1)] for _ in coords]
    total = F(0)
    for mon, coeff in zip(p.monoms(), p.coeffs()):
        term = F(int(coeff))
        for j, e in enumerate(mon):
            if not e:
                continue        # also the variables past ``coords``, absent from p
            pw = powers[j]
            while len(pw) <= e:
                pw.append(pw[-1] * coords[j])
            term *= pw[e]
        total += term
    return total


def _isolated_points(polys, plane, rng, avoid=()):
    """Witness points: the isolated common zeros of ``polys`` on ``plane``, off the circles'
    points at infinity and off the zeros of every ``avoid`` polynomial; and the hypersurface
    part (the gcd of the polynomials, factors at infinity removed; a constant when there is
    none).  On a line the zeros of the gcd are the points."""
    P = plane.P
    polys = [p for p in polys if not p.is_zero()]
    if not polys:
        return None, None
    h = polys[0]
    for p in polys[1:]:
        h = h.gcd(p)
    curve = h
    for inf in plane.infinity:
        while not curve.is_constant():
            g = curve.gcd(inf)
            if g.is_constant():
                break
            curve = curve / g
    if isinstance(plane, _CoordinatePlane) and not plane.mixed:
        na = len(plane.forms.angles)
        raw = _isolated_in_some_order(polys, plane.c, P, rng,
                                      angles={k for k, i in enumerate(plane.free) if i < na})
    else:
        raw = _isolated(polys, plane.c, P, rng)
    points = []
    for F, coords, d in raw:
        pt = _Point(F, coords, d)
        if any(pt.value(q).is_zero() for q in [*plane.infinity, *avoid]):
            continue
        points.append(pt)
    if plane.c == 1:
        return points, plane.ctx.constant(1)
    return points, curve


# --- the certificate ------------------------------------------------------------------------


@dataclass
class _ComponentData:
    index: int
    codim: int
    dimension: int
    rank_drop: int
    equations: list      # homogeneous forms over Q
    excluding: list
    pieces: list | None = None   # per variable: None (free) or the list of its exact values
    real: bool = True            # False: a component without real points, reported apart
    real_part: bool = False      # the real points of a complex component (below the bound)

    @property
    def label(self) -> str:
        return f"component {self.index}" if self.real else f"complex component {self.index}"


def _half_tangent(value):
    """tan(value / 2) as an exact number, or None for value = pi (mod 2 pi)."""
    value = sp.sympify(value, strict=True)
    if isinstance(value, sp.Mul) and len(value.args) == 2 and value.args[0] == 2 \
            and isinstance(value.args[1], sp.atan):
        return value.args[1].args[0]
    ratio = sp.nsimplify(value / sp.pi) if value.is_number else None
    if ratio is not None and ratio.is_Rational and (ratio - 1) % 2 == 0:
        return None
    t = sp.tan(value / 2)
    if t.has(sp.tan) or t.has(sp.atan) or not t.is_number:
        raise NotCertifiable(f"the solved value {sp.sstr(value)} has no exact half-angle tangent")
    return t


def _pieces(c, variables, angles):
    """Per variable, its exact solved values (a finite set) or None when free; None when the
    component is not given in solved form (a variable neither free nor solved)."""
    solved = {str(k): v for k, v in (c.solved or {}).items()}
    free = {str(v) for v in c.free}
    out = []
    for v in variables:
        if v.name in solved and solved[v.name]:
            vals = []
            for x in solved[v.name]:
                if v in angles:
                    t = _half_tangent(x)
                    vals.append(("angle", t))
                else:
                    vals.append(("value", sp.sympify(x, strict=True)))
            out.append(vals)
        elif v.name in free:
            out.append(None)
        else:
            return None
    return out


def certify_components(matrix, variables, angles, components, *, seed: int = 0,
                       deadline=None, progress=None, complex_only=()) -> Certificate:
    """Certify that ``components`` are the rank-deficiency locus of ``matrix``.

    Parameters
    ----------
    matrix : sympy.Matrix
        The matrix, every parameter replaced by its (exact) value.
    variables, angles : sequence of sympy.Symbol
        The matrix's variables, and those that enter through sin and cos.
    components : sequence of rankloci.loci.Component
        The reported components, their equations with the same parameter values.
    seed : int
        Seed of the random choices.
    deadline : callable, optional
        Returns True when the time is up: the result is then ``"undecided"``.
    progress : callable, optional
        Called with one-line progress messages.
    complex_only : sequence of Component
        Components without real points (proved so where they were found), which cover
        witness points of the complex locus but are not part of the real one.

    Returns
    -------
    Certificate
        When witness points lie on no component and every one of them fixes the same few
        variables at values of small height, ``discovered`` holds the components they lie on
        (with real points) and ``discovered_complex`` those without real points.

    Examples
    --------
    >>> q1, q2 = sp.symbols("q1 q2", real=True)
    >>> from rankloci.loci import Component
    >>> J = sp.Matrix([[-sp.sin(q1) - sp.sin(q1 + q2), -sp.sin(q1 + q2)],
    ...                [sp.cos(q1) + sp.cos(q1 + q2), sp.cos(q1 + q2)]])
    >>> certify_components(J, (q1, q2), (q1, q2), [Component((sp.sin(q2),), dimension=1)]).verdict
    'passed'
    >>> certify_components(J, (q1, q2), (q1, q2), []).verdict
    'failed'
    """
    t0 = time.perf_counter()
    progress = progress or (lambda msg: None)
    deadline = deadline or (lambda: False)
    rng = np.random.default_rng(seed)
    M = sp.Matrix(matrix)
    if M.rows > M.cols:
        M = M.T
    n, m = M.shape
    N = len(variables)
    angles = tuple(a for a in variables if a in set(angles))
    others = tuple(v for v in variables if v not in set(angles))
    codims = tuple(range(1, min(m - n + 1, N) + 1))

    def result(verdict, findings, **kw):
        return Certificate(verdict, seed=seed, codimensions=codims, findings=tuple(findings),
                           seconds=time.perf_counter() - t0, **kw)

    try:
        exprs = list(M) + [sp.sympify(e, strict=True) for c in (*components, *complex_only)
                           for e in (*c.equations, *c.excluding)]
        exprs += [sp.sympify(x, strict=True) for c in (*components, *complex_only)
                  for vals in (c.solved or {}).values() for x in vals]
    except sp.SympifyError as exc:
        return result("undecided", [f"not certifiable: an equation is no sympy expression "
                                    f"({exc})"])
    surds = sorted({p for e in exprs for a in e.atoms(sp.Pow)
                    if a.is_number and _integer_root(a) for p in sp.factorint(_integer_root(a)[0])})

    covers, claims, real_parts = _real_part_claims(components, variables, angles, N)
    complex_only = tuple(complex_only) + tuple(covers)

    if n == 0:
        return result("passed" if not components else "failed",
                      [] if not components else ["a matrix without rows has full rank"])
    try:
        forms = _Forms(angles, others, surds)
        forms.variables = tuple(variables)
        rows = forms.homogeneous_rows(M)
        comps = []
        for k, c in enumerate(list(components) + list(complex_only), start=1):
            eqs = [forms.homogeneous_form(e) for e in c.equations]
            exc = [forms.homogeneous_form(e) for e in c.excluding]
            pieces = None
            if c.solved:
                try:
                    pieces = _pieces(c, variables, set(angles))
                    if pieces is not None:
                        for vals in pieces:
                            for _, x in vals or ():
                                if x is not None:
                                    forms.number(x)
                except NotCertifiable:
                    pieces = None
            real = k <= len(components)
            comps.append(_ComponentData(k if real else k - len(components), N - c.dimension,
                                        c.dimension, c.rank_drop, eqs, exc, pieces, real,
                                        real and bool(getattr(c, "real_points_of", ()))))
    except NotCertifiable as exc:
        return result("undecided", [f"not certifiable: {exc}"])

    last = None
    for _ in range(RETRIES):
        P, roots = _random_prime(rng, surds)
        try:
            cert = _certify(rows, comps, forms, n, m, N, codims, P, roots, rng, seed,
                            deadline, progress, t0)
            if claims and cert.verdict != "failed":
                cert = dataclasses.replace(cert, verdict="failed")
            return dataclasses.replace(cert, findings=tuple(claims) + cert.findings,
                                       real_parts=tuple(real_parts))
        except _TooLarge as exc:
            return result("undecided", [f"the certificate's elimination is too large ({exc})"])
        except (_Degenerate, ZeroDivisionError) as exc:
            last = exc
            progress(f"certificate: a degenerate random choice ({exc}); trying again")
        except TimeoutError:
            return result("undecided", ["the time ran out before the certificate was complete"])
    return result("undecided", [f"every random choice was degenerate ({last})"])


def _same_value(a, b, is_angle) -> bool:
    d = sp.sympify(a, strict=True) - sp.sympify(b, strict=True)
    if is_angle:
        return any(sp.simplify(d + k * 2 * sp.pi) == 0 for k in (0, 1, -1))
    return sp.simplify(d) == 0


def _holds(c, point, free, angle_names) -> bool:
    """Does component ``c`` (no exclusions) contain the real ``point`` of a real part, its
    ``free`` variables free?"""
    solved = {str(k): v for k, v in (c.solved or {}).items()}
    own_free = {str(v) for v in c.free}
    return not c.excluding and all(v.name in own_free for v in free) and all(
        v.name in solved and any(_same_value(x, val, v.name in angle_names)
                                 for x in solved[v.name])
        for v, val in point.items())


def _real_part_claims(components, variables, angles, N):
    """The complex components that components with ``real_points_of`` hold the real points
    of (as components that cover witness points), what disproves the claims, and a record
    of each for the certificate's JSON.

    A claim holds when the complex component's equation is proved a weighted sum of squares
    (:func:`rankloci.exact.real_points.real_part_of`) and every common real zero of the
    squares lies on a reported component that names it, with no exclusion."""
    from ..loci import Component
    from .real_points import real_part_of

    groups: dict = {}
    for i, c in enumerate(components, start=1):
        rpo = tuple(getattr(c, "real_points_of", ()) or ())
        if rpo:
            groups.setdefault(tuple(sp.sstr(e) for e in rpo), (rpo, []))[1].append((i, c))
    covers, findings, records = [], [], []
    names = {v.name: v for v in variables}
    angle_names = {a.name for a in angles}
    for key, (rpo, members) in groups.items():
        labels = ", ".join(str(i) for i, _ in members)
        text = " = 0, ".join(key) + " = 0"
        if len(rpo) != 1:
            findings.append(f"component {labels}: the real points of {text} are not "
                            "certified: only a hypersurface (one equation) is handled")
            continue
        part = real_part_of(rpo[0].xreplace({s: names[s.name] for s in rpo[0].free_symbols
                                             if s.name in names}), variables, angles)
        if part is None:
            findings.append(f"component {labels}: {text} is not proved to have real points "
                            "of lower dimension (no weighted sum of squares was found)")
            continue
        covers.append(Component(rpo, dimension=N - 1, rank_drop=1))
        for i, c in members:
            if c.excluding:
                findings.append(f"component {i}: the real points of {text} are reported "
                                "with exclusions")
        missed = sum(1 for p in part.points if not any(
            _holds(c, p, part.free, angle_names) for _, c in members))
        if missed:
            findings.append(f"{missed} of the {len(part.points)} real points of {text} lie "
                            "on no reported component")
        records.append({"complex_component": key[0],
                        "sum_of_squares": [sp.sstr(e) for e in part.squares],
                        "real_points": len(part.points),
                        "components": [i for i, _ in members]})
    return covers, findings, records


#: the last results of the certificate's costliest steps (restricting the matrix to a random
#: plane, its compressed determinants, their isolated zeros), by their exact inputs and the
#: state of the random generator before them: a certificate computed again for the same
#: matrix and seed (with other components, as when components are added to a locus that
#: failed) repeats none of them, and ends with the generator in the same state
_MEMO: dict = {}
_MEMO_LOCK = threading.Lock()

#: The coordinate slices of the loci certified last (planes, compressions, the locus's witness
#: points, or the reason none were found), by matrix, prime and free variables: a 6 x 8 chain
#: has 56 slices of codimension 3, and a recomputation certifies the same matrix again.
_SLICE_MEMO: dict = {}
SLICE_MEMO_SIZE = 256


def _rows_key(rows, forms, P, roots):
    """The exact inputs of the locus's planes: the matrix's forms, their variables, the prime,
    and the elimination budgets (a result computed within one is no result beyond another)."""
    return (tuple(forms.ctx.names()), tuple(forms.angles), tuple(forms.others), P,
            tuple(roots), tuple(tuple(str(x) for x in row) for row in rows),
            MAX_ELIMINATION_DEGREE, MAX_ELIMINATION_TERMS)


def _remembered(key, rng, compute):
    """``compute()``, or its remembered result for the same ``key`` and state of ``rng``
    (``rng`` then left in the state ``compute`` left it in)."""
    state = rng.bit_generator.state
    full = (key, repr(state))
    with _MEMO_LOCK:
        hit = _MEMO.get(full)
    if hit is not None:
        rng.bit_generator.state = hit[1]
        return hit[0]
    value = compute()
    with _MEMO_LOCK:
        if len(_MEMO) >= 16:        # the planes of one or two certificates
            _MEMO.pop(next(iter(_MEMO)))
        _MEMO[full] = (value, rng.bit_generator.state)
    return value


#: Decide codimension 3 on coordinate slices even where a random subspace is within the
#: budgets (the tests compare the two on small matrices).
_SLICES_FIRST = False


def _certify(rows, comps, forms, n, m, N, codims, P, roots, rng, seed, deadline, progress, t0):
    findings = []
    counts = {}
    degree_sum = 0

    def check_time():
        if deadline():
            raise TimeoutError

    key = _rows_key(rows, forms, P, roots)

    def take(c, sliced):
        """Record what :func:`_by_slices` decided for codimension c; its degree sum."""
        nonlocal total_uncovered
        if c in codims:
            counts[c] = sliced["count"]
        findings.extend(sliced["findings"])
        missing.extend(sliced["missing"])
        total_uncovered += sliced["uncovered"]
        if sliced["uncertain"]:
            uncertain.append(c)
        if sliced["uncovered"]:
            findings.append(f"{sliced['uncovered']} of the {sliced['count']} witness points "
                            f"of codimension {c} lie on no reported component: a component "
                            f"of dimension {N - c} is missing")
        return sliced["degree_sum"]

    def first_plane():
        line = _Plane(forms, P, roots, 1, rng)
        Ml = [[line.restrict(x) for x in row] for row in rows]
        return line, Ml, _compressions(Ml, n, m, 2, P, rng)

    line, Ml, H = _remembered(("plane", 1, key), rng, first_plane)
    degree_sum += sum(max(0, int(h.total_degree())) for h in H)
    if all(h.is_zero() for h in H):
        # rank deficient everywhere: the locus is the whole space
        ok = any(c.codim == 0 for c in comps)
        findings_ = [] if ok else ["the matrix is rank deficient at every configuration, and "
                                   "no component is the whole space"]
        for c in comps:
            if c.codim != 0:
                findings_.append(f"component {c.index} has dimension below {N}, but the "
                                 "matrix is rank deficient everywhere (it lies inside the "
                                 "whole space)")
        return Certificate("passed" if not findings_ else "failed", prime=P, seed=seed,
                           codimensions=(0,), witness_points={0: 1}, findings=tuple(findings_),
                           error_bound=_bound(degree_sum, P), seconds=time.perf_counter() - t0)
    planes = {1: (line, Ml, H)}
    uncertain = []
    missing = []
    total_uncovered = 0
    redundant = [k.index for k in comps
                 if k.real and not k.real_part and k.codim > 0 and k.codim > k.rank_drop * (m - n + k.rank_drop)]
    # below the Eagon-Northcott bound of its rank drop, a component lies inside a larger one if
    # it is singular at all: the caller leaves it out (the certificate is of the rest)
    comps = [k for k in comps if not (k.real and k.index in redundant)]
    extra = sorted({k.codim for k in comps if 0 < k.codim <= MAX_CODIMENSION} - set(codims))
    for c in sorted(set(codims) | set(extra)):
        check_time()
        if c > MAX_CODIMENSION:
            findings.append(f"codimension {c} components (possible for a {n}x{m} matrix) are "
                            f"not certified: witness points are computed for codimension up "
                            f"to {MAX_CODIMENSION}")
            continue
        if c not in planes:
            def restricted(c=c):
                plane = _Plane(forms, P, roots, c, rng)
                return plane, [[plane.restrict(x) for x in row] for row in rows]

            plane, Mp = _remembered(("plane", c, key), rng, restricted)
            # the determinants' degree, and whether the eliminations could stay in budget
            D = sum(max(int(x.total_degree()) for x in row) for row in Mp)
            if c > 2 and (D ** c / math.factorial(c) > MAX_ELIMINATION_TERMS or _SLICES_FIRST):
                sliced = {"undecided": f"codimension {c} components are not certified: "
                                       f"coordinate slices are used up to codimension "
                                       f"{MAX_SLICE_CODIMENSION}, and only where no higher "
                                       f"codimension can occur"}
                if c <= MAX_SLICE_CODIMENSION and max(codims) <= MAX_SLICE_CODIMENSION:
                    progress(f"certificate: witness points of codimension {c} on "
                             "coordinate slices")
                    sliced = _by_slices(c, rows, comps, forms, n, m, N, codims, P, roots, rng,
                                        key, check_time)
                if "undecided" not in sliced:
                    degree_sum += take(c, sliced)
                    continue
                findings.append(sliced["undecided"] + f" (on a random subspace the "
                                f"determinants would have degree up to {D} in {c} variables)")
                uncertain.append(c)
                for k in comps:
                    if k.codim == c and not _by_pieces(k, rows, forms, P, roots, rng, n,
                                                       findings):
                        uncertain.append(c)
                continue
            Hp = _remembered(("minors", c, key), rng,
                             lambda Mp=Mp, c=c: _compressions(Mp, n, m, c + 1, P, rng))
            degree_sum += sum(max(0, int(h.total_degree())) for h in Hp)
            planes[c] = (plane, Mp, Hp)
        plane, Mp, Hp = planes[c]
        progress(f"certificate: witness points of codimension {c}")
        if c not in codims:
            locus_points = []        # no component of the locus has this codimension
        else:
            try:
                locus_points, _ = _remembered(("points", c, key), rng,
                                              lambda Hp=Hp, plane=plane:
                                              _isolated_points(Hp, plane, rng))
            except _TooLarge as exc:
                sliced = (_by_slices(c, rows, comps, forms, n, m, N, codims, P, roots, rng, key,
                                     check_time)
                          if 2 < c <= MAX_SLICE_CODIMENSION and max(codims) <=
                          MAX_SLICE_CODIMENSION else {"undecided": ""})
                if "undecided" not in sliced:
                    degree_sum += take(c, sliced)
                    continue
                findings.append(f"codimension {c} components are not certified: the "
                                f"elimination is too large ({exc})")
                uncertain.append(c)
                locus_points = None
        if c in codims and locus_points is not None:
            counts[c] = sum(p.degree for p in locus_points)
        check_time()
        # every reported component of this codimension: its witness points, their rank
        mine = [k for k in comps if k.codim == c]
        comp_eqs = {}
        for k in mine:
            eqs = [plane.restrict(e) for e in k.equations]
            exc = [plane.restrict(e) for e in k.excluding]
            comp_eqs[k.label] = (eqs, exc)
            degree_sum += sum(max(0, int(e.total_degree())) for e in eqs + exc)
            try:
                pts = _component_points(eqs, exc, plane, rng, k, findings)
            except _TooLarge:
                if not _by_pieces(k, rows, forms, P, roots, rng, n, findings):
                    uncertain.append(c)
                continue
            if k.pieces is not None:
                # the solved values are a claim too: each piece is singular as stated
                findings.extend(_check_pieces(k, rows, forms, P, roots, rng, n))
            if pts is None:
                continue
            if not pts:
                findings.append(f"{k.label}: no point of dimension {N - c} (its "
                                f"equations off its exclusions have a smaller dimension, or "
                                f"no point)")
                continue
            wrong = _rank_finding(k, pts, Mp, n)
            if wrong:
                findings.append(wrong)
            check_time()
        # completeness: every witness point of the locus on a component of this codimension
        uncovered = 0
        for pt in locus_points or ():
            covered = False
            for k in mine:
                eqs, exc = comp_eqs[k.label]
                if all(pt.value(e).is_zero() for e in eqs) and not any(
                        pt.value(x).is_zero() for x in exc):
                    covered = True
                    break
            if not covered:
                uncovered += pt.degree
                missing.append((c, plane, pt))
        total_uncovered += uncovered
        if uncovered:
            findings.append(f"{uncovered} of the {counts[c]} witness points of codimension {c} "
                            f"lie on no reported component: a component of dimension {N - c} "
                            f"is missing")
    uncertified = [c for c in codims if c > MAX_CODIMENSION] + uncertain
    for k in comps:
        if k.codim <= MAX_CODIMENSION or k.codim == 0:
            continue
        check_time()
        if k.pieces is None:
            findings.append(f"{k.label} (dimension {k.dimension}) is not certified: "
                            f"its codimension {k.codim} is above {MAX_CODIMENSION} and it is "
                            "not given in solved form")
            uncertified.append(k.codim)
            continue
        found = _check_pieces(k, rows, forms, P, roots, rng, n)
        findings.extend(found)
    failed = [f for f in findings if "are not certified" not in f and "is not certified" not in f]
    for k in comps:
        if k.codim == 0:
            failed.append(f"{k.label} claims the whole space, but the matrix has "
                          "full rank at a random configuration")
    if redundant:
        failed.append(f"component{'s' * (len(redundant) > 1)} "
                      f"{', '.join(map(str, redundant))} {'have' if len(redundant) > 1 else 'has'}"
                      f" a dimension below the bound for {'their' if len(redundant) > 1 else 'its'}"
                      " rank drop: inside a larger component, or not singular")
    verdict = "failed" if failed else ("undecided" if uncertified else "passed")
    found, found_complex, slices, merged = (), (), (), ()
    if missing:
        try:
            found, found_complex, slices, merged = _discover(missing, forms, rows, n, N, P, rng)
        except NotCertifiable:
            pass
    return Certificate(verdict, prime=P, seed=seed, codimensions=codims, witness_points=counts,
                       findings=tuple(failed + [f for f in findings if f not in failed]),
                       error_bound=_bound(degree_sum, P), seconds=time.perf_counter() - t0,
                       redundant=tuple(redundant), discovered=found,
                       discovered_complex=found_complex, slices=slices,
                       discovered_merged=merged,
                       uncovered=total_uncovered)


def _by_slices(c, rows, comps, forms, n, m, N, codims, P, roots, rng, key, check_time):
    """Codimension ``c`` on the coordinate slices over every ``c`` of the variables, where a
    random subspace would need too large an elimination (see :class:`_CoordinatePlane`).

    Returns ``{"undecided": finding}`` when it cannot decide either (a slice whose elimination
    meets a curve of the locus or is too large), else a dict: ``count`` (witness points of the locus, summed over
    the slices), ``findings``, ``uncertain`` (whether a component stays uncertified),
    ``missing`` ((c, slice, point) of the uncovered points), ``uncovered`` and
    ``degree_sum``."""
    mine = [k for k in comps if k.codim == c]
    findings, missing = [], []
    count = uncovered = degree_sum = 0
    points_of = {k.label: 0 for k in mine}
    open_ = {k.label for k in mine}         # components whose witness points are computed
    checked = set()                         # components whose pieces were checked
    uncertain = False
    for free in itertools.combinations(range(N), c):
        check_time()
        # each slice has its own random stream, drawn from the prime and its variables: the
        # slices of the locus (planes, compressions, witness points) do not depend on the
        # components, and a certificate of another locus of the same matrix (a recomputation)
        # takes them from the memo
        srng = np.random.default_rng([P % 2 ** 63, c, *free])

        def build(free=free, srng=srng):
            plane = _CoordinatePlane(forms, P, roots, free, srng)
            Mp = [[plane.restrict(x) for x in row] for row in rows]
            Hp = _compressions(Mp, n, m, c + 1, P, srng)
            if c not in codims:
                return plane, Mp, Hp, []
            try:
                return plane, Mp, Hp, _isolated_points(Hp, plane, srng)[0]
            except (_Curves, _TooLarge) as failure:
                return plane, Mp, Hp, failure

        with _MEMO_LOCK:
            hit = _SLICE_MEMO.get((key, c, free))
        if hit is None:
            hit = build()
            with _MEMO_LOCK:
                if len(_SLICE_MEMO) >= SLICE_MEMO_SIZE:
                    _SLICE_MEMO.pop(next(iter(_SLICE_MEMO)))
                _SLICE_MEMO[(key, c, free)] = hit
        plane, Mp, Hp, pts = hit
        degree_sum += sum(max(0, int(h.total_degree())) for h in Hp)
        if isinstance(pts, Exception):
            return {"undecided": f"codimension {c} components are not certified: on the "
                                 f"coordinate slice where {plane.names()} vary, {pts}"}
        if pts is None:
            return {"undecided": f"codimension {c} components are not certified: the "
                                 f"matrix is rank deficient on the whole coordinate slice "
                                 f"where {plane.names()} vary"}
        count += sum(p.degree for p in pts)
        comp_eqs = {}
        for k in mine:
            eqs = [plane.restrict(e) for e in k.equations]
            exc = [plane.restrict(e) for e in k.excluding]
            comp_eqs[k.label] = (eqs, exc)
            if k.label not in open_:
                continue
            degree_sum += sum(max(0, int(e.total_degree())) for e in eqs + exc)
            try:
                kp = _component_points(eqs, exc, plane, rng, k, findings)
            except (_TooLarge, _Curves) as failure:
                open_.discard(k.label)
                why = (f"meet a curve outside the coordinate planes on the slice where "
                       f"{plane.names()} vary" if isinstance(failure, _Curves)
                       else "need too large an elimination")
                if not _by_pieces(k, rows, forms, P, roots, rng, n, findings, why):
                    uncertain = True
                checked.add(k.label)
                continue
            if kp is None:
                open_.discard(k.label)      # a finding was recorded
                continue
            points_of[k.label] += len(kp)
            wrong = _rank_finding(k, kp, Mp, n)
            if wrong:
                findings.append(wrong)
                open_.discard(k.label)
        for pt in pts:
            if not any(all(pt.value(e).is_zero() for e in comp_eqs[k.label][0])
                       and not any(pt.value(x).is_zero() for x in comp_eqs[k.label][1])
                       for k in mine):
                uncovered += pt.degree
                missing.append((c, plane, pt))
    for k in mine:
        if k.pieces is not None and k.label not in checked:
            # the solved values are a claim too: each piece is singular as stated
            findings.extend(_check_pieces(k, rows, forms, P, roots, rng, n))
        if k.label in open_ and not points_of[k.label]:
            findings.append(f"{k.label}: no point of dimension {N - c} (its equations off its "
                            f"exclusions have a smaller dimension, or no point)")
    return {"count": count, "findings": findings, "uncertain": uncertain, "missing": missing,
            "uncovered": uncovered, "degree_sum": degree_sum}


def _rank_finding(k, points, Mp, n):
    """The finding of the first of the component's witness ``points`` at which the matrix
    (``Mp``, on their plane) does not have rank n - rank drop, or None."""
    for pt in points:
        r = pt.rank(Mp)
        if r != n - k.rank_drop:
            what = "is regular" if r == n else f"has rank {r}, not {n - k.rank_drop}"
            return f"{k.label}: the matrix {what} at a witness point of the component"
    return None


def _by_pieces(k, rows, forms, P, roots, rng, n, findings,
               why="need too large an elimination") -> bool:
    """Check a component whose witness points are out of reach at its pieces, when it is in
    solved form (findings extended); False when it is not, and it stays uncertified."""
    if k.pieces is not None:
        findings.extend(_check_pieces(k, rows, forms, P, roots, rng, n))
        return True
    findings.append(f"{k.label} (dimension {k.dimension}) is not certified: its witness "
                    f"points {why}, and it is not given in solved form")
    return False


def _check_pieces(k, rows, forms, P, roots, rng, n):
    """Soundness of a component in solved form: at a random point of each of its pieces (the
    solved values of each variable, random values of the free ones) its equations vanish, its
    exclusions do not (a piece where one does is excluded), and the matrix has the stated rank.

    The rank at a random point of a piece is its generic rank except with probability at most
    degree / P (Schwartz-Zippel), the free coordinates being random."""
    import itertools

    fctx = flint.nmod_mpoly_ctx.get(forms.ctx.names(), modulus=P)
    na = len(forms.angles)

    def value(form, point):
        terms = {m: _mod(c, P) for m, c in zip(form.monoms(), form.coeffs())}
        if not terms:
            return 0
        return int(fctx.from_dict(terms)(*point))

    def number(x):
        return value(forms.number(x), [0] * (len(forms.ctx.names()) - len(roots)) + list(roots))

    found, admitted = [], 0
    choices = [vals if vals is not None else [None] for vals in k.pieces]
    combos = list(itertools.islice(itertools.product(*choices), 64))
    for combo in combos:
        C, S, X = [0] * na, [0] * na, [0] * len(forms.others)
        point_vals = dict(zip(forms.variables, combo))
        for i in range(na):
            ch = point_vals.get(forms.angles[i])
            if ch is None:
                C[i], S[i] = 1, int(rng.integers(0, P))
            elif ch[1] is None:
                C[i], S[i] = 0, 1
            else:
                C[i], S[i] = 1, number(ch[1])
        for j, x in enumerate(forms.others):
            ch = point_vals.get(x)
            X[j] = int(rng.integers(0, P)) if ch is None else number(ch[1])
        point = C + S + X + list(roots)
        if any(value(e, point) for e in k.equations):
            found.append(f"{k.label}: its solved values do not satisfy its equations")
            return found
        if any(value(x, point) == 0 for x in k.excluding):
            continue
        admitted += 1
        mat = flint.nmod_mat([[value(e, point) for e in row] for row in rows], P)
        r = mat.rank()
        if r != n - k.rank_drop:
            what = "is regular" if r == n else f"has rank {r}, not {n - k.rank_drop}"
            found.append(f"{k.label}: the matrix {what} at a random point of one "
                         "of its pieces")
            return found
    if not admitted:
        found.append(f"{k.label}: every piece of its solved form is excluded")
    dims = {sum(1 for c in combo if c is None) for combo in combos}
    if dims != {k.dimension}:
        found.append(f"{k.label}: its solved form has dimension "
                     f"{sorted(dims)}, not the stated {k.dimension}")
    return found


def _component_points(eqs, exc, plane, rng, k, findings):
    """Witness points of a component on ``plane`` (None when a finding was recorded)."""
    nonzero = [e for e in eqs if not e.is_zero()]
    if not nonzero:
        findings.append(f"{k.label}: its equations hold on the whole space, not on "
                        f"a set of codimension {k.codim}")
        return None
    pts, curve = _isolated_points(nonzero, plane, rng, avoid=exc)
    if curve is not None and not curve.is_constant():
        # a part of larger dimension: allowed only inside the exclusions
        rest = curve
        for x in exc:
            if x.is_zero():
                continue
            while not rest.is_constant():
                g = rest.gcd(x)
                if g.is_constant():
                    break
                rest = rest / g
        if not rest.is_constant():
            findings.append(f"{k.label}: its equations, off its exclusions, have a "
                            f"part of larger dimension than the stated {k.dimension}")
            return None
    return pts


def _rational(a: int, P: int):
    """The rational r/s = a mod P with |r|, s <= MAX_HEIGHT, or None (rational reconstruction)."""
    r0, r1, s0, s1 = P, a % P, 0, 1
    while r1 > MAX_HEIGHT:
        q = r0 // r1
        r0, r1, s0, s1 = r1, r0 - q * r1, s1, s0 - q * s1
    if s1 == 0 or abs(s1) > MAX_HEIGHT:
        return None
    f = sp.Rational(r1, s1)
    return f if (f.p - a * f.q) % P == 0 else None


def _minimal_polynomial(value, P):
    """Coefficients (low to high, ints mod P) of the minimal polynomial of a field element."""
    conj = [value]
    while True:
        nxt = conj[-1] ** P
        if nxt == conj[0]:
            break
        conj.append(nxt)
    coeffs = [value * 0 + 1]
    for r in conj:
        # multiply by (z - r)
        new = [value * 0] * (len(coeffs) + 1)
        for i, cf in enumerate(coeffs):
            new[i + 1] += cf
            new[i] -= cf * r
        coeffs = new
    out = []
    for cf in coeffs:
        rep = cf.to_list()
        if any(int(x) for x in rep[1:]):
            raise NotCertifiable("a minimal polynomial outside the prime field")
        out.append(int(rep[0]) if rep else 0)
    return tuple(out)


def _small_polynomials(polys, P, T):
    """Irreducible polynomials over Q of small height whose roots mod P are the roots of the
    ``polys`` (minimal polynomials over GF(P), coefficients low to high), or None.

    The product of the polynomials is tried first (its coefficients rational of small height:
    every conjugate of the values is among the roots); otherwise each root in GF(P) alone, by
    the shortest vector of the lattice of integer relations a_0 + a_1 r + ... = 0 mod P."""
    product = [1]
    for k in polys:
        new = [0] * (len(product) + len(k) - 1)
        for i, a in enumerate(product):
            for j, b in enumerate(k):
                new[i + j] = (new[i + j] + a * b) % P
        product = new
    coeffs = [_rational(a, P) for a in product]
    if all(c is not None for c in coeffs):
        f = sp.Poly(list(reversed(coeffs)), T)
        return list({sp.Poly(g.monic(), T): None for g, _ in f.factor_list()[1]})
    out = []
    for k in polys:
        if len(k) != 2:
            return None
        r = (-k[0]) * pow(k[1], -1, P) % P
        relation = _integer_relation(r, P)
        if relation is None:
            return None
        f = sp.Poly(list(reversed(relation)), T)
        for g, _ in f.factor_list()[1]:
            ints = g.clear_denoms()[1].all_coeffs()
            if sum(int(a) * pow(r, len(ints) - 1 - i, P) for i, a in enumerate(ints)) % P == 0:
                out.append(sp.Poly(g.monic(), T))
                break
        else:
            return None
    return list(dict.fromkeys(out))


def _integer_relation(r, P, degree=2):
    """Small integers (a_0 .. a_d), a_d nonzero, with a_0 + a_1 r + ... + a_d r**d = 0 mod P and
    every |a_k| <= MAX_RELATION_HEIGHT, for the smallest degree d <= ``degree``, or None.

    Every vector of the lattice spanned by (P, 0, ..), (-r**k mod P, e_k) is such a relation;
    LLL finds a short one.  A random r has none this short except with probability about
    (MAX_RELATION_HEIGHT**(d + 1) / P), below 1e-5 at d = 2; a wrong one costs only time, since
    the components built from it are certified like any other."""
    for d in range(1, degree + 1):
        basis = [[P] + [0] * d]
        for k in range(1, d + 1):
            row = [(-pow(r, k, P)) % P] + [0] * d
            row[k] = 1
            basis.append(row)
        for v in _lll(basis):
            if v[-1] and max(abs(x) for x in v) <= MAX_RELATION_HEIGHT \
                    and sum(a * pow(r, k, P) for k, a in enumerate(v)) % P == 0:
                return v
    return None


def _lll(basis):
    """LLL-reduced basis of an integer lattice (rows), exact arithmetic; small dimensions.

    The Gram-Schmidt coefficients are exact rationals of flint (``fmpq``, some ten times
    faster than Python's ``Fraction``); each is rounded as ``round`` rounds a ``Fraction``
    (halves to even)."""
    from fractions import Fraction

    b = [list(map(int, row)) for row in basis]
    n = len(b)
    zero = flint.fmpq(0)

    def dot(u, v):
        return sum((x * y for x, y in zip(u, v)), zero)

    def gram_schmidt():
        bs, mu = [], [[zero] * n for _ in range(n)]
        for i in range(n):
            v = [flint.fmpq(x) for x in b[i]]
            for j in range(i):
                mu[i][j] = dot(b[i], bs[j]) / dot(bs[j], bs[j]) if any(bs[j]) else zero
                v = [x - mu[i][j] * y for x, y in zip(v, bs[j])]
            bs.append(v)
        return bs, mu

    bs, mu = gram_schmidt()
    k = 1
    delta = flint.fmpq(3, 4)
    while k < n:
        for j in range(k - 1, -1, -1):
            q = round(Fraction(int(mu[k][j].p), int(mu[k][j].q)))
            if q:
                b[k] = [x - q * y for x, y in zip(b[k], b[j])]
                bs, mu = gram_schmidt()
        if dot(bs[k], bs[k]) >= (delta - mu[k][k - 1] ** 2) * dot(bs[k - 1], bs[k - 1]):
            k += 1
        else:
            b[k], b[k - 1] = b[k - 1], b[k]
            bs, mu = gram_schmidt()
            k = max(k - 1, 1)
    return sorted(b, key=lambda v: sum(x * x for x in v))


def _small_height(key, P) -> bool:
    """Is a value (its minimal polynomial over GF(P)) a root of a polynomial of small height?"""
    if len(key) == 2:
        r = (-key[0]) * pow(key[1], -1, P) % P
        return _integer_relation(r, P) is not None
    return all(_rational(a, P) is not None for a in key)


def _discover(missing, forms, rows, n, N, P, rng):
    """Components through witness points that lie on no reported component, when every such
    point fixes the same variables at a few values of small height (the values a robot's
    offsets give: tan q2 = 1/1600, say).  Returns (components with real points, components
    without, and (variable, real values) for variables fixed on components that more
    equations cut out)."""
    import itertools

    from ..loci import Component

    na = len(forms.angles)
    groups: dict = {}
    for c, plane, pt in missing:
        # the variables this point has at a value of small height, and those values
        keys = {}
        for i, q in enumerate(forms.angles):
            C, S = pt.value(plane.images[i]), pt.value(plane.images[na + i])
            keys[q] = "pi" if C.is_zero() else _minimal_polynomial(S / C, P)
        for j, xv in enumerate(forms.others):
            keys[xv] = _minimal_polynomial(pt.value(plane.images[2 * na + j]), P)
        small = {v: k for v, k in keys.items() if k == "pi" or _small_height(k, P)}
        groups.setdefault((c, frozenset(small)), []).append(small)
    found, found_complex, slices, merged = [], [], [], []
    for (c, _), points in groups.items():
        values: dict = {}
        for small in points:
            for var, key in small.items():
                values.setdefault(var, set()).add(key)
        fixed = {}
        for var, keys in values.items():
            polys = [k for k in keys if k != "pi"]
            if sum(len(k) - 1 for k in polys) > MAX_FIXED_DEGREE:
                continue
            Tsym = sp.Dummy("T")
            factors = _small_polynomials(polys, P, Tsym)
            if factors is None:
                continue
            factors = list({sp.Poly(g.monic(), Tsym): None for g in factors})
            fixed[var] = (Tsym, factors, "pi" in keys)
        if 0 < len(fixed) < c:
            # the missing components fix these variables but are cut out by more equations:
            # the caller computes the locus on each slice where they take a real value
            for var, (_, factors, has_pi) in fixed.items():
                vals = []
                for f in factors:
                    vals += _fixed_equation(var, f, var in set(forms.angles))[1]
                if has_pi:
                    vals.append(sp.pi)
                slices.append((var, tuple(vals)))
            continue
        if len(fixed) != c:
            continue
        variables = list(forms.variables)
        choices = []
        for var in variables:
            if var in fixed:
                Tsym, factors, has_pi = fixed[var]
                choices.append([(var, f) for f in factors] + ([(var, "pi")] if has_pi else []))
        combos = list(itertools.product(*choices))
        # one component per combination of values that a point has: the values of different
        # points need not combine (q3 = 0 with q5 = 0 at one point, sin q4 = 499/156 with
        # q5 = 0 at another)
        had = set()
        for small in points:
            had.add(tuple((var, "pi") if small[var] == "pi"
                          else (var, _factor_of(small[var], fixed[var][1], P))
                          for var in variables if var in fixed))
        combos = [combo for combo in combos if combo in had]
        if len(combos) > 1:
            # every combination at once, as one component (tried first by the caller)
            eqs, solved, real = [], {}, True
            for options in choices:
                var = options[0][0]
                parts = [_fixed_equation(var, f, var in set(forms.angles)) for _, f in options]
                vals = tuple(v for _, vs in parts for v in vs)
                real = real and all(vs for _, vs in parts)
                eqs.append(_product_equation(var, [e for e, _ in parts], vals))
                solved[var] = vals
            if real:
                merged.append(Component(tuple(eqs), solved=solved, dimension=N - c, rank_drop=1,
                                         free=tuple(v for v in variables if v not in fixed)))
        for combo in combos:
            eqs, solved, real = [], {}, True
            for var, f in combo:
                expr, vals = _fixed_equation(var, f, var in set(forms.angles))
                eqs.append(expr)
                if not vals:
                    real = False
                solved[var] = tuple(vals)
            free = tuple(v for v in variables if v not in fixed)
            comp = Component(tuple(eqs), solved=solved if real else {}, free=free,
                             dimension=N - c, rank_drop=1)
            (found if real else found_complex).append(comp)
    if not (found or found_complex or slices or merged):
        # no variable at a value of small height: a sine or cosine may be fixed instead (the
        # points then come in pairs q, pi - q or q, -q), at a number of Q(sqrt(d))
        found, found_complex = _trig_fixed(missing, forms, N, P)
    return tuple(found), tuple(found_complex), tuple(slices), tuple(merged)


def _factor_of(key, factors, P):
    """The polynomial among ``factors`` (over Q) whose roots mod P include those of ``key``
    (a minimal polynomial over GF(P), coefficients low to high), or None."""
    minimal = flint.nmod_poly([int(a) for a in key], P)
    for g in factors:
        coeffs = [sp.Rational(a) for a in reversed(g.all_coeffs())]
        try:
            values = [int(a.p) * pow(int(a.q), -1, P) % P for a in coeffs]
        except ValueError:
            continue
        if (flint.nmod_poly(values, P) % minimal).is_zero():
            return g
    return None


def _surd_relation(r, P, forms, roots):
    """An exact number v = (a0 + a1 sqrt(d)) / a2 with v = r mod P, d a product of the surds
    (d = 1: a rational), its integers of small height (lattice reduction), or None.

    A value r of GF(P) that is random has such a relation of height at most
    MAX_RELATION_HEIGHT with probability about MAX_RELATION_HEIGHT**3 / P per d, below 1e-5;
    a wrong one costs only time, since the components built from it are certified."""
    rational = _rational(r, P)
    if rational is not None:
        return rational
    for k in range(1, len(roots) + 1):
        for sub in itertools.combinations(range(len(roots)), k):
            s, d = 1, 1
            for j in sub:
                s, d = s * roots[j] % P, d * forms.surds[j]
            for v in _lll([[P, 0, 0], [(-s) % P, 1, 0], [(-r) % P, 0, 1]]):
                a0, a1, a2 = v
                if a2 and a1 and max(map(abs, v)) <= MAX_RELATION_HEIGHT \
                        and (a0 + a1 * s + a2 * r) % P == 0:
                    return -(sp.Integer(a0) + a1 * sp.sqrt(d)) / sp.Integer(a2)
    return None


def _trig_fixed(missing, forms, N, P):
    """Components through the missing witness points of one codimension c on which the sine
    or the cosine of c angles is fixed (the same number of GF(P) at every point), at a value
    of Q(sqrt(d)) found by :func:`_surd_relation`.  Returns (with real points, without)."""
    from ..loci import Component

    na = len(forms.angles)
    by_codim: dict = {}
    for c, plane, pt in missing:
        by_codim.setdefault(c, []).append((plane, pt))
    found, found_complex = [], []
    for c, points in by_codim.items():
        plane = points[0][0]
        roots = [int(x.coeffs()[0]) if not x.is_zero() else 0
                 for x in plane.images[2 * na + len(forms.others):]]
        fixed = []
        for i, q in enumerate(forms.angles):
            for fn in (sp.sin, sp.cos):
                values = set()
                for pl, pt in points:
                    C, S = pt.value(pl.images[i]), pt.value(pl.images[na + i])
                    norm = S * S + C * C
                    if norm.is_zero():
                        values.add(None)
                        break
                    v = (2 * S * C if fn is sp.sin else C * C - S * S) / norm
                    key = _minimal_polynomial(v, P)
                    values.add((-key[0]) * pow(key[1], -1, P) % P if len(key) == 2 else None)
                if len(values) == 1 and None not in values:
                    exact = _surd_relation(values.pop(), P, forms, roots)
                    if exact is not None:
                        fixed.append((q, fn, exact))
                        break
        if len(fixed) != c:
            continue
        eqs = tuple(fn(q) - v for q, fn, v in fixed)
        real = all(abs(float(v)) <= 1 for _, _, v in fixed)
        free = tuple(v for v in forms.variables if v not in {q for q, _, _ in fixed})
        if real:
            solved = {q: ((sp.asin(v), sp.pi - sp.asin(v)) if fn is sp.sin
                          else (sp.acos(v), -sp.acos(v))) for q, fn, v in fixed}
            found.append(Component(eqs, solved=solved, free=free, dimension=N - c))
        else:
            found_complex.append(Component(eqs, free=free, dimension=N - c))
    return found, found_complex


def _product_equation(var, exprs, values):
    """One equation for a variable fixed at several values: sin q for {0, pi}, cos q for
    {pi/2, -pi/2}, the product of the single equations otherwise."""
    vals = set(values)
    if vals == {sp.S.Zero, sp.pi}:
        return sp.sin(var)
    if vals == {sp.pi / 2, -sp.pi / 2}:
        return sp.cos(var)
    return sp.expand(sp.Mul(*exprs))


def _fixed_equation(var, f, is_angle):
    """The equation and real values of a variable fixed at the roots of ``f`` (a monic Poly in
    T = tan(q/2) for an angle, in the variable itself otherwise; "pi" for q = pi)."""
    if f == "pi":
        return sp.cos(var / 2), [sp.pi]
    coeffs = f.all_coeffs()                       # high to low, monic, rational
    den = sp.ilcm(*[sp.Rational(a).q for a in coeffs])
    ints = [sp.Integer(a * den) for a in coeffs]
    d = len(ints) - 1
    roots = [r for r in sp.Poly(ints, f.gen).real_roots()]
    if not is_angle:
        return sp.Add(*[a * var ** (d - k) for k, a in enumerate(ints)]), roots
    C, S = sp.cos(var / 2), sp.sin(var / 2)
    form = sp.Add(*[a * S ** (d - k) * C ** k for k, a in enumerate(ints)])
    if d % 2 == 0:
        # an even form is a polynomial in cos q and sin q: C**2 = (1 + c)/2, S**2 = (1 - c)/2,
        # C*S = s/2
        c, s = sp.cos(var), sp.sin(var)
        terms = []
        for k, a in enumerate(ints):
            ks, kc = d - k, k
            if ks % 2 == 0:
                t = ((1 - c) / 2) ** (ks // 2) * ((1 + c) / 2) ** (kc // 2)
            else:
                t = (s / 2) * ((1 - c) / 2) ** ((ks - 1) // 2) * ((1 + c) / 2) ** ((kc - 1) // 2)
            terms.append(a * t)
        poly = sp.Poly(sp.expand(sp.Add(*terms)), c, s, domain="QQ")
        form = poly.clear_denoms()[1].primitive()[1].as_expr()
    values = [2 * sp.atan(r) for r in roots]
    return form, values


def _bound(degree_sum, P):
    """Schwartz-Zippel: each random decision fails on a hypersurface of degree at most the
    degrees involved; their sum over P bounds the probability of a wrong verdict."""
    return float(min(1.0, (degree_sum + 1) ** 2 / P))
