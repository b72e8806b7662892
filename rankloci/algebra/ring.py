"""Exact polynomial algebra for rank-deficiency loci.

Representation of an angle
--------------------------
A revolute joint variable q enters a Jacobian through c = cos q and
s = sin q.  Polynomials in (c, s) do not factor uniquely modulo
c**2 + s**2 - 1, and the half-angle substitution t = tan(q/2) loses q = pi.
We use the half-angle *homogeneous* coordinates instead::

    C = cos(q/2),  S = sin(q/2),  c = C**2 - S**2,  s = 2*C*S,  1 = C**2 + S**2

Every entry is padded with powers of (C**2 + S**2) until it is homogeneous of
the same degree in (C, S) along each matrix row.  Determinants, cofactors and
products of such matrices stay homogeneous in every pair, and a homogeneous
polynomial factors into homogeneous factors in the unique factorisation
domain Q[C, S, ...].  No point of the circle is outside the chart:
``S`` is the factor of q = 0, ``C`` the factor of q = pi, and the factor
``C**2 + S**2`` (no real zero on the circle) is dropped.

Polynomials are python-flint ``fmpq_mpoly`` objects: exact Bareiss
determinants and multivariate factorisation about a thousand times faster
than sympy on Jacobian polynomials.
"""

from __future__ import annotations

import functools
import itertools
import math
from dataclasses import dataclass

import flint
import numpy as np
import sympy as sp

from ..expr import as_expression
from ..errors import LocusError

__all__ = ["PolyRing", "square_root_primes"]


#: Largest integer multiple k of an angle in sin(k*q) or cos(k*q): the half-angle form of
#: cos(k*q) has degree 2k, and joint Jacobians have k <= 2 (k = 12 leaves room for raw matrices).
MAX_ANGLE_MULTIPLE = 12

#: Largest integer n whose square root sqrt(n) becomes surd generators (n is factored into primes).
MAX_SURD = 10 ** 12

#: Largest number of terms one matrix entry may have once padded to the degree of its row.
MAX_ENTRY_TERMS = 200_000


def _square_root_of_integer(atom):
    """(n, +1) for sqrt(n), (n, -1) for 1/sqrt(n), n a positive integer; else None."""
    if atom.base.is_Integer and 0 < atom.base <= MAX_SURD and atom.exp in (sp.S.Half, -sp.S.Half):
        return int(atom.base), 1 if atom.exp > 0 else -1
    return None


def square_root_primes(exprs) -> tuple:
    """The primes whose square roots occur in ``exprs`` (as sqrt(n), n an integer), sorted.

    Examples
    --------
    >>> import sympy as sp
    >>> square_root_primes([sp.sqrt(6) / 2, sp.sqrt(3) * sp.Symbol("x")])
    (2, 3)
    """
    primes = set()
    for e in exprs:
        for atom in as_expression(e).atoms(sp.Pow):
            if atom.is_number:
                root = _square_root_of_integer(atom)
                if root is not None:
                    primes |= set(sp.factorint(root[0]))
    return tuple(sorted(primes))


def _check_angle_multiples(expr, angles):
    """Refuse sin/cos of k*q with |k| > MAX_ANGLE_MULTIPLE (their expansion would not finish)."""
    for f in expr.atoms(sp.sin, sp.cos):
        arg = sp.expand(f.args[0])
        for q in angles:
            k = arg.coeff(q)
            if k.is_Number and abs(k) > MAX_ANGLE_MULTIPLE:
                raise LocusError(f"entry {sp.sstr(expr)}: {sp.sstr(f)} is a multiple of {q} above "
                                 f"{MAX_ANGLE_MULTIPLE}, too large for the exact algebra")


#: Terms of the polynomials whose evaluators PolyRing.compile keeps for reuse.  An evaluator
#: holds an integer exponent table of its terms (about 100 bytes a term), so the memo stays
#: within about 50 MB.
COMPILE_MEMO_TERMS = 500_000
#: Evaluations of at most this many (term, generator, point) factors gather them all at once;
#: larger ones gather per generator, without that temporary.
SMALL_GATHER = 20_000
#: Evaluations at more than 64 points gather every (point, term, generator) factor at once
#: when there are at most this many; larger ones go 64 points at a time.  The temporary of
#: one gather is 8 bytes a factor: at 2048 points of an equation of 2210 terms in 11
#: generators (centauro's arm) it took 170 ms against 34 ms in chunks, while for 56 terms the
#: single gather is as fast (2.3 ms against 2.1 ms).
MANY_GATHER = 1_000_000


@dataclass(frozen=True, eq=False)
class PolyRing:
    """Q[C_q, S_q for each angle q; x for each other variable; p for each parameter].

    Parameters
    ----------
    angles : tuple of Symbol
        Variables entering through sin and cos.
    others : tuple of Symbol
        Variables entering polynomially (prismatic joints, raw-matrix variables).
    params : tuple of Symbol
        Parameters kept symbolic.
    surds : tuple of int
        Primes p whose square roots occur in the entries (twists of pi/3,
        pi/4, pi/6 ...).  Each is a generator r_p with the fixed value sqrt(p);
        polynomials are kept reduced modulo r_p**2 - p (see :meth:`normal`),
        where a polynomial vanishes at the actual values exactly when it is
        zero, because the products of square roots of distinct primes are
        linearly independent over Q.  Surd generators come last.
    """

    angles: tuple
    others: tuple
    params: tuple
    surds: tuple = ()

    @functools.cached_property
    def names(self) -> tuple[str, ...]:
        out = []
        for q in self.angles:
            out += [f"C_{q.name}", f"S_{q.name}"]
        out += [x.name for x in self.others] + [p.name for p in self.params]
        out += [f"sqrt_{p}" for p in self.surds]
        return tuple(out)

    @property
    def surd_start(self) -> int:
        """Index of the first surd generator (the number of the other generators)."""
        return 2 * len(self.angles) + len(self.others) + len(self.params)

    @functools.cached_property
    def surd_values(self) -> np.ndarray:
        """The values sqrt(p) of the surd generators."""
        return np.sqrt(np.array(self.surds, dtype=float))

    def is_number(self, p) -> bool:
        """Is ``p`` a number: a constant, or (reduced) a polynomial in the surds alone?"""
        if p.is_constant():
            return True
        return bool(self.surds) and min(self.variable_indices(p)) >= self.surd_start

    def normal(self, p):
        """``p`` reduced modulo r**2 - prime for each surd generator r (identity without surds).

        Examples
        --------
        >>> import sympy as sp
        >>> x = sp.Symbol("x")
        >>> ring = PolyRing((), (x,), (), surds=(3,))
        >>> r = ring.gens[1]
        >>> ring.normal(r * r * ring.gens[0] + r)
        3*x + sqrt_3
        """
        if not self.surds or p.is_zero():
            return p
        degs = p.degrees()
        for k, rel in self._relations[self.n_angles:]:
            if degs[k] >= 2:
                p = divmod(p, rel)[1]
        return p

    @functools.cached_property
    def ctx(self):
        return flint.fmpq_mpoly_ctx.get(self.names, "degrevlex")

    @functools.cached_property
    def gens(self):
        return self.ctx.gens()

    def C(self, i):
        return self.gens[2 * i]

    def S(self, i):
        return self.gens[2 * i + 1]

    @property
    def n_angles(self) -> int:
        return len(self.angles)

    def pair_degrees(self, p) -> tuple[int, ...]:
        """Degree of ``p`` in each (C, S) pair (max total degree over the terms)."""
        if p.is_zero():
            return (0,) * self.n_angles
        degs = [0] * self.n_angles
        for mon in p.monoms():
            for i in range(self.n_angles):
                degs[i] = max(degs[i], mon[2 * i] + mon[2 * i + 1])
        return tuple(degs)

    @functools.cached_property
    def _relations(self) -> list:
        """(generator index, relation) for every pair, C**2 + S**2 - 1, and every surd, r**2 - p.

        Each relation's leading monomial (degrevlex) is the square of its generator, C or r, so
        together they are a Groebner basis and the remainder on division by each in turn is the
        unique normal form: C and the surds of degree at most 1.
        """
        out = [(2 * i, self.C(i) ** 2 + self.S(i) ** 2 - 1) for i in range(self.n_angles)]
        start = self.surd_start
        out += [(start + k, self.gens[start + k] ** 2 - prime)
                for k, prime in enumerate(self.surds)]
        return out

    def on_circles(self, p):
        """``p`` reduced modulo C**2 + S**2 = 1 for each pair (and r**2 = prime for each surd).

        On every real configuration the result has the value of ``p``. Products
        reduced this way stay as small as the polynomials they represent: a determinant of a
        matrix homogeneous in each pair carries powers of C**2 + S**2, up to 99.99 % of its
        terms on 8-joint chains, and here they are 1.  :meth:`homogenized` goes back.

        Examples
        --------
        >>> import sympy as sp
        >>> q = sp.Symbol("q")
        >>> ring = PolyRing((q,), (), ())
        >>> C, S = ring.gens
        >>> ring.on_circles((C**2 + S**2) ** 2 * C**3)
        -C_q*S_q^2 + C_q
        """
        if p.is_zero():
            return p
        degs = p.degrees()
        for k, rel in self._relations:
            if degs[k] >= 2:
                p = divmod(p, rel)[1]
        return p

    def homogenized(self, p, target=None):
        """The polynomial homogeneous in each pair equal to ``p`` on the circles.

        Each term is multiplied by the power of C**2 + S**2 that brings its degree in each pair
        to ``target`` (default: the largest degree there).  For ``p`` = ``on_circles(D)`` with
        ``D`` homogeneous in each pair this is ``D`` divided by every power of C**2 + S**2 that
        divides it, or, with ``target`` the degrees of ``D``, ``D`` itself: a polynomial
        homogeneous in each pair that vanishes on the circles is zero.  Raises ValueError when a
        degree differs from the target by an odd number (``p`` came from no homogeneous
        polynomial) or exceeds it.

        Examples
        --------
        >>> import sympy as sp
        >>> q = sp.Symbol("q")
        >>> ring = PolyRing((q,), (), ())
        >>> C, S = ring.gens
        >>> ring.homogenized(-C * S**2 + C)
        C_q^3
        """
        if p.is_zero():
            return p
        na = self.n_angles
        monoms, coeffs = p.monoms(), p.coeffs()
        degs = [tuple(m[2 * i] + m[2 * i + 1] for i in range(na)) for m in monoms]
        if target is None:
            target = tuple(max(d[i] for d in degs) for i in range(na))
        terms = []
        for mon, coeff, d in zip(monoms, coeffs, degs):
            pad = tuple((t - e) // 2 if t >= e and (t - e) % 2 == 0 else -1
                        for t, e in zip(target, d))
            if min(pad) < 0:
                raise ValueError("not the reduced form of a polynomial homogeneous in each pair")
            terms.append((mon, coeff, pad))
        circles = [self.C(i) ** 2 + self.S(i) ** 2 for i in range(na)]
        return self._padded(terms, 0, circles)

    def _padded(self, terms, i, circles):
        """Sum of ``coeff * mon * prod(circles[j] ** pad[j] for j >= i)`` over ``terms``.

        Horner's scheme in each pair in turn: the terms are grouped by their power of pair
        ``i``'s circle, each group is padded in the later pairs, and the groups are combined
        by multiplying by the circle once per power.  On tiago's 9-joint thumb chain this
        takes 1.6 s for its 1225 determinants against 10 s for one product per combination
        of powers added up term group by term group.
        """
        na = len(circles)
        while i < na and all(pad[i] == 0 for _, _, pad in terms):
            i += 1
        if i == na:
            return self.ctx.from_dict({mon: coeff for mon, coeff, _ in terms})
        groups: dict = {}
        for term in terms:
            groups.setdefault(term[2][i], []).append(term)
        top = max(groups)
        out = self._padded(groups[top], i + 1, circles)
        for power in range(top - 1, -1, -1):
            out = out * circles[i]
            if power in groups:
                out = out + self._padded(groups[power], i + 1, circles)
        return out

    def gradient(self, p) -> list:
        """Derivatives of ``p`` by each angle and each other variable.

        With C = cos(q/2), S = sin(q/2): d/dq = (C d/dS - S d/dC) / 2, which
        keeps a polynomial homogeneous in (C, S).
        """
        out = []
        for i in range(self.n_angles):
            c, s = self.gens[2 * i], self.gens[2 * i + 1]
            out.append((c * p.derivative(2 * i + 1) - s * p.derivative(2 * i)) / 2)
        base = 2 * self.n_angles
        for j in range(len(self.others)):
            out.append(p.derivative(base + j))
        return out

    def variable_indices(self, p) -> set[int]:
        """Generator indices that occur in ``p``."""
        if p.is_zero():
            return set()
        return {i for i, e in enumerate(p.degrees()) if e}

    # --- sympy -> polynomial ------------------------------------------------

    @functools.cached_property
    def _trig_symbols(self):
        cs = {q: (sp.Dummy(f"c_{q.name}"), sp.Dummy(f"s_{q.name}")) for q in self.angles}
        return cs

    def from_sympy_rows(self, M: sp.Matrix) -> list[list]:
        """Matrix of homogeneous polynomials; each row padded to one degree per pair.

        Scaling a row by a power of C**2 + S**2 (= 1 on the circle) changes
        nothing, so the rank of the result equals the rank of ``M`` at every
        real configuration.
        """
        rows = []
        for i in range(M.rows):
            raw = [self._raw(M[i, j]) for j in range(M.cols)]
            target = [max(d[k] for _, d in raw) for k in range(self.n_angles)]
            rows.append([self.normal(self._homogenize(p, d, target)) for p, d in raw])
        return rows

    def from_sympy(self, expr) -> "flint.fmpq_mpoly":
        p, d = self._raw(expr)
        return self.normal(self._homogenize(p, d, d))

    @functools.cached_property
    def _surd_symbols(self) -> dict:
        return {p: sp.Dummy(f"sqrt_{p}") for p in self.surds}

    def _with_surd_symbols(self, e, expr):
        """``e`` with sqrt(n) written as a product of surd generators; other irrationals refused."""
        rep = {}
        for atom in e.atoms(sp.Pow):
            if not atom.is_number:
                continue
            root = _square_root_of_integer(atom)
            if root is None:
                raise LocusError(f"entry {sp.sstr(expr)} contains the irrational number "
                                 f"{sp.sstr(atom)}; only square roots of integers up to "
                                 f"{MAX_SURD} are handled exactly")
            n, sign = root
            value = sp.Integer(1)
            for prime, mult in sp.factorint(n).items():
                if prime not in self._surd_symbols:
                    raise LocusError(f"entry {sp.sstr(expr)}: sqrt({prime}) is not a generator "
                                     "of this ring")
                value *= self._surd_symbols[prime] ** mult
            rep[atom] = value if sign > 0 else value / n
        return e.xreplace(rep) if rep else e

    def _raw(self, expr):
        """Polynomial in (c, s, x, p) as a dict, and its degree per angle."""
        expr = as_expression(expr)
        _check_angle_multiples(expr, self.angles)
        rep = {}
        for q, (c, s) in self._trig_symbols.items():
            rep[sp.cos(q)] = c
            rep[sp.sin(q)] = s
        e = expr.xreplace(rep) if rep else expr
        gens = [v for q in self.angles for v in self._trig_symbols[q]] + list(self.others) + list(self.params)
        gens += list(self._surd_symbols.values())
        if e.free_symbols - set(gens):
            e = sp.expand_trig(sp.expand(expr)).xreplace(rep)
        e = self._with_surd_symbols(e, expr)
        bad = e.free_symbols - set(gens)
        if bad:
            raise LocusError(
                f"entry {sp.sstr(expr)} is not a polynomial in sin/cos of the angles, the other "
                f"variables and the parameters (it contains {', '.join(sorted(map(str, bad)))})")
        try:
            poly = sp.Poly(e, *gens, domain="QQ")
        except (sp.PolynomialError, sp.polys.polyerrors.CoercionFailed, sp.GeneratorsNeeded) as exc:
            raise LocusError(
                f"entry {sp.sstr(expr)} is not a polynomial in sin/cos of the angles, the other "
                "variables and the parameters (a root, a power that is not a whole number, a "
                "denominator or a function of one of them; a parameter's value is substituted "
                "with numeric=True, --numeric)") from exc
        terms = poly.terms()
        degs = [0] * self.n_angles
        for mon, _ in terms:
            for k in range(self.n_angles):
                degs[k] = max(degs[k], mon[2 * k] + mon[2 * k + 1])
        return terms, degs

    def _homogenize(self, terms, degs, target):
        # padding with (C**2 + S**2)**pad multiplies the terms by up to pad + 1 per angle
        size = len(terms)
        for k in range(self.n_angles):
            size *= target[k] - degs[k] + 1
            if size > MAX_ENTRY_TERMS:
                raise LocusError(
                    f"an entry would have more than {MAX_ENTRY_TERMS} terms in half-angle form "
                    f"(a row mixes sin/cos of {self.n_angles} angles); the matrix is too large for "
                    "the exact algebra")
        g = self.gens
        na = self.n_angles
        out = self.ctx.constant(0)
        for mon, coeff in terms:
            term = self.ctx.constant(flint.fmpq(int(coeff.p), int(coeff.q)))
            for k in range(na):
                a, b = mon[2 * k], mon[2 * k + 1]
                C, S = g[2 * k], g[2 * k + 1]
                pad = target[k] - a - b
                term *= (C * C - S * S) ** a * (2 * C * S) ** b
                if pad:
                    term *= (C * C + S * S) ** pad
            rest = mon[2 * na:]
            for e, v in zip(rest, g[2 * na:]):
                if e:
                    term *= v ** e
            out += term
        return out

    # --- polynomial -> sympy --------------------------------------------------

    @functools.cached_property
    def _display(self):
        """Ring of the readable form: cos q, sin q, cos(q/2), sin(q/2) per angle, then the rest."""
        names = []
        symbols = []
        for q in self.angles:
            names += [f"c_{q.name}", f"s_{q.name}", f"hc_{q.name}", f"hs_{q.name}"]
            symbols += [sp.cos(q), sp.sin(q), sp.cos(q / 2), sp.sin(q / 2)]
        names += [x.name for x in self.others] + [p.name for p in self.params]
        symbols += list(self.others) + list(self.params)
        names += [f"sqrt_{p}" for p in self.surds]
        symbols += [sp.sqrt(p) for p in self.surds]
        ctx = flint.fmpq_mpoly_ctx.get(tuple(names), "degrevlex")
        return ctx, ctx.gens(), symbols

    def to_sympy(self, p, *, full_angles: bool = True, exact: bool = False) -> sp.Expr:
        """Readable trigonometric form of a homogeneous polynomial.

        Pairs of even degree are written with cos q and sin q (using
        C**2 = (1 + cos q)/2, S**2 = (1 - cos q)/2, C*S = sin(q)/2, which
        leaves sin q to the first power: the normal form modulo
        sin**2 + cos**2 - 1); pairs of odd degree keep half angles.  The
        rational content is cleared so that equations read with integer
        coefficients, unless ``exact``: then the expression equals ``p`` on the
        circle, as the entries of a vector must (clearing each entry's content
        on its own would change the vector's direction).
        """
        key = (id(p), full_angles, exact)
        got = self._to_sympy_cache.get(key)
        if got is not None and got[0] is p:
            return got[1]
        expr = self._to_sympy(p, full_angles, exact)
        if len(self._to_sympy_cache) > 4096:
            self._to_sympy_cache.clear()
        self._to_sympy_cache[key] = (p, expr)
        return expr

    @functools.cached_property
    def _to_sympy_cache(self) -> dict:
        return {}

    def _to_sympy(self, p, full_angles, exact=False):
        if p.is_zero():
            return sp.Integer(0)
        ctx, gens, symbols = self._display
        degs = self.pair_degrees(p)
        na = self.n_angles
        half = ctx.constant(flint.fmpq(1, 2))
        one = ctx.constant(1)
        powers = {}

        def power(k, kind, e):
            key = (k, kind, e)
            if key not in powers:
                c, s = gens[4 * k], gens[4 * k + 1]
                base = {"plus": (one + c) * half, "minus": (one - c) * half, "cs": s * half}[kind]
                powers[key] = base ** e
            return powers[key]

        rest_gens = gens[4 * na:]
        total = ctx.constant(0)
        for mon, coeff in zip(p.monoms(), p.coeffs()):
            term = ctx.constant(coeff)
            for k in range(na):
                a, b = mon[2 * k], mon[2 * k + 1]
                if a + b == 0:
                    continue
                if full_angles and degs[k] % 2 == 0:
                    if a % 2 == 0:
                        term *= power(k, "plus", a // 2) * power(k, "minus", b // 2)
                    else:
                        term *= power(k, "cs", 1) * power(k, "plus", (a - 1) // 2) * power(k, "minus", (b - 1) // 2)
                else:
                    term *= gens[4 * k + 2] ** a * gens[4 * k + 3] ** b
            for e, v in zip(mon[2 * na:], rest_gens):
                if e:
                    term *= v ** e
            total += term
        if total.is_zero():
            return sp.Integer(0)
        coeffs = total.coeffs()
        if exact:
            return self._sympy_terms(total, symbols)
        num = functools.reduce(lambda x, y: x.gcd(y), [flint.fmpz(c.p) for c in coeffs])
        den = functools.reduce(lambda x, y: x * y // x.gcd(y), [flint.fmpz(c.q) for c in coeffs])
        total = total * flint.fmpq(den, num)
        if len(coeffs) == 1 and total.coeffs()[0] < 0:
            total = -total
        return self._sympy_terms(total, symbols)

    @staticmethod
    def _sympy_terms(total, symbols) -> sp.Expr:
        """The sympy sum of the terms of ``total`` (a polynomial in the display generators)."""
        terms = []
        for mon, coeff in zip(total.monoms(), total.coeffs()):
            factors = [sym ** e for sym, e in zip(symbols, mon) if e]
            terms.append(sp.Mul(sp.Rational(int(coeff.p), int(coeff.q)), *factors))
        return sp.Add(*terms)

    # --- numeric evaluation ---------------------------------------------------

    def joint_values(self, g) -> dict:
        """Joint variable -> value at the generator vector ``g`` (angles in (-pi, pi])."""
        out = {}
        for i, q in enumerate(self.angles):
            v = 2.0 * math.atan2(g[2 * i + 1], g[2 * i])
            out[q] = math.remainder(v, 2 * math.pi)
        for j, x in enumerate(self.others):
            out[x] = g[2 * self.n_angles + j]
        return out

    def parameter_values(self, g) -> dict:
        """Parameter -> value at the generator vector ``g``."""
        base = 2 * self.n_angles + len(self.others)
        return {p: g[base + j] for j, p in enumerate(self.params)}

    @functools.cached_property
    def _compile_memo(self) -> dict:
        # (terms, degrees) of each polynomial -> [(polynomials, evaluator), ...], and the number
        # of terms held under the key None
        return {None: 0}

    def compile(self, polys, *, absolute: bool = False, sized: bool = False):
        """Vectorised evaluator of several polynomials at numeric generator values.

        With ``absolute``, the evaluator of the same polynomials with every
        coefficient replaced by its absolute value (of
        :func:`~rankloci.algebra.abs_poly` of each): at the absolute values
        of the generators it gives the size of their terms, the scale of
        the numeric zero tests.  With ``sized``, an evaluator that returns
        both, ``(values, sizes)`` at ``x``, the sizes being those of the
        absolute evaluator at ``|x|``, from one product of the terms.  The
        evaluators of a list are built from one reading of its terms, and no
        polynomial of absolute values is formed (on panda's finger chain
        forming them took 26 of 400 s).

        A list equal term for term to one compiled before gets the same
        evaluator: a branch's equations, exclusions and their term sizes are
        compiled by the sampler, the probes and the proofs alike (on panda's
        finger chain, 6294 of 7056 compilations repeated one before).  The
        memo holds at most COMPILE_MEMO_TERMS terms, then starts afresh.
        """
        polys = list(polys)
        key = tuple((len(p), tuple(int(d) for d in p.degrees())) for p in polys)
        memo = self._compile_memo
        for kept, evs in memo.get(key, ()):
            if all(a == b for a, b in zip(kept, polys)):
                return evs[2 if sized else int(absolute)]
        evs = self._compile(polys)
        terms = sum(len(p) for p in polys)
        if memo[None] + terms > COMPILE_MEMO_TERMS:
            memo.clear()
            memo[None] = 0
        memo.setdefault(key, []).append((polys, evs))
        memo[None] += terms
        return evs[2 if sized else int(absolute)]

    def _compile(self, polys):
        """The value, absolute and sized evaluators of ``polys`` (see :meth:`compile`)."""
        nv = len(self.names)
        mons, coeffs, owner = [], [], []
        for i, p in enumerate(polys):
            ms = p.monoms()
            mons.append(ms)
            coeffs.extend(float(c) for c in p.coeffs())
            owner.extend([i] * len(ms))
        chain = itertools.chain.from_iterable
        mons = np.fromiter(chain(chain(mons)), dtype=np.int64,
                           count=len(owner) * nv).reshape(-1, nv)
        coeffs = np.array(coeffs, dtype=float)
        owner = np.array(owner, dtype=np.int64)
        used = np.flatnonzero(mons.any(axis=0)) if len(mons) else np.array([], dtype=np.int64)
        mons = mons[:, used]
        npoly = len(polys)
        top = int(mons.max()) if mons.size else 0
        powers = np.arange(top + 1)[None, :, None]
        exponents = [np.ascontiguousarray(mons[:, j]) for j in range(len(used))]
        cols = np.arange(len(used))
        # terms are grouped by polynomial (owner is sorted): sum each group
        present = np.unique(owner)
        starts = np.searchsorted(owner, present)
        parts = (npoly, owner, used, present, starts, powers, exponents, cols, mons, top)
        return (_evaluator(coeffs, *parts), _evaluator(np.abs(coeffs), *parts),
                _evaluator(coeffs, *parts, sized=True))


def _signed_powers(x, powers):
    """``x ** powers`` as ``|x| ** powers`` with the sign put back by an exact negation.

    ``(-a) ** k`` and ``a ** k`` can differ in the last bit (numpy's vectorised
    ``power``), which would break the sized evaluator's promise that its sizes
    equal the absolute evaluator's at ``|x|``, bit for bit.
    """
    odd = powers % 2 == 1
    return np.abs(x) ** powers * np.where((x < 0) & odd, -1.0, 1.0)


def _evaluator(coeffs, npoly, owner, used, present, starts, powers, exponents, cols, mons, top,
               *, sized=False):
    """The evaluator of :meth:`PolyRing.compile` for terms read by ``PolyRing._compile``.

    With ``sized`` it returns the values and the sizes of the terms (the sums of their
    absolute values) from one product of the terms: ``|c x**e| = |c| |x|**e`` bit for bit, so
    the sizes equal those of the absolute evaluator at ``|x|``.
    """
    flat = cols[None, :] * (top + 1) + mons          # (term, generator) -> row of the power table
    odd = np.arange(top + 1) % 2 == 1

    def evaluate(x):
        """Values at one point (shape (nv,)) or at a batch of points (shape (B, nv))."""
        x = np.asarray(x, dtype=float)
        single = x.ndim == 1
        X = x[None, :] if single else x
        if len(X) > 64 and len(X) * flat.size > MANY_GATHER:
            parts = [evaluate(X[i:i + 64]) for i in range(0, len(X), 64)]
            if sized:
                return (np.concatenate([p[0] for p in parts]),
                        np.concatenate([p[1] for p in parts]))
            return np.concatenate(parts)
        out = np.zeros((len(X), npoly))
        size = np.zeros((len(X), npoly)) if sized else None
        if len(owner):
            if not len(used):
                terms = np.tile(coeffs, (len(X), 1))
                axis = 1
            elif len(X) <= 64 and len(X) * flat.size <= SMALL_GATHER:
                # few terms and points: one gather of every factor instead of one per
                # generator, multiplied in the order of the loop below (bit for bit its values)
                xu = X[:, used].T                                   # (generator, point)
                pw = np.abs(xu)[:, None, :] ** powers               # (generator, power, point)
                neg = xu < 0
                if neg.any():
                    pw *= np.where(neg[:, None, :] & odd[None, :, None], -1.0, 1.0)
                factors = pw.reshape(-1, len(X))[flat]              # (term, generator, point)
                terms = coeffs[:, None] * factors[:, 0, :]
                for j in range(1, len(used)):
                    terms *= factors[:, j, :]
                axis = 0
            elif len(X) <= 64:
                # terms x points, one gather of the power table per generator used:
                # no (point, term, generator) temporary (2-3x faster for large J)
                terms = np.repeat(coeffs[:, None], len(X), axis=1)
                pw = _signed_powers(X[:, used].T[:, None, :], powers)  # (generator, power, point)
                for j, e in enumerate(exponents):
                    terms *= pw[j][e]
                axis = 0
            else:
                # many points: one gather for all generators is faster
                pw = _signed_powers(X[:, used, None], np.arange(top + 1))
                terms = np.prod(pw[:, cols, mons], axis=2) * coeffs
                axis = 1
            sums = np.add.reduceat(terms, starts, axis=axis)
            out[:, present] = sums.T if axis == 0 else sums
            if sized:
                sums = np.add.reduceat(np.abs(terms), starts, axis=axis)
                size[:, present] = sums.T if axis == 0 else sums
        if sized:
            return (out[0], size[0]) if single else (out, size)
        return out[0] if single else out

    return evaluate
