"""Polynomials of a :class:`~rankloci.algebra.ring.PolyRing`: determinants and factors."""

from __future__ import annotations

from flint.utils.flint_exceptions import DomainError

from ..errors import RanklociError
from .ring import PolyRing
from ..tolerances import PRODUCT_BUDGET_FACTOR

__all__ = ["laplace_det", "circle_free_det", "irreducible_factors", "abs_poly", "common_factor", "primitive_vector",
           "transpose", "PolyMemo", "TermLimit"]


class TermLimit(RanklociError):
    """A determinant with a term budget went over it (see :func:`laplace_det`)."""


def laplace_det(M, ring: PolyRing | None = None, poll=None, *, on_circles: bool = False,
                max_terms: int | None = None):
    """Determinant by Laplace expansion along rows, sharing minors (2**n subproducts).

    Jacobians are sparse and their entries small; with the minors of the
    lower rows memoised this beats fraction-free (Bareiss) elimination, whose
    exact divisions of large intermediate polynomials dominate (PUMA 560,
    6x6 in a middle frame: 0.004 s against 0.46 s).  Rows homogeneous in
    each (C, S) pair give a homogeneous determinant.  With ``ring``, the
    result is reduced by :meth:`PolyRing.normal`.  ``poll``, when given, is
    called before every product, so that a caller can stop a determinant
    that runs for minutes (it raises to stop).  With ``on_circles`` (and
    ``ring``), every product is reduced by :meth:`PolyRing.on_circles`: the
    result is the determinant's value on the circles, not the polynomial.  With
    ``max_terms``, :class:`TermLimit` is raised as soon as a minor or a sum of products has more
    terms than that, or before a product of more than PRODUCT_BUDGET_FACTOR times that many
    pairs of terms.
    """
    n = len(M)
    if n == 0:
        raise ValueError("empty matrix")
    memo = {}

    def minor(r, cols):
        # determinant of rows r..n-1 and the columns in ``cols`` (a sorted tuple)
        if r == n - 1:
            return M[r][cols[0]]
        key = (r, cols)
        got = memo.get(key)
        if got is not None:
            return got
        total = None
        for pos, c in enumerate(cols):
            a = M[r][c]
            if a.is_zero():
                continue
            sub = minor(r + 1, cols[:pos] + cols[pos + 1:])
            if sub.is_zero():
                continue
            if poll is not None:
                poll()
            if max_terms is not None and (len(sub) > max_terms or
                                          len(a) * len(sub) > PRODUCT_BUDGET_FACTOR * max_terms):
                raise TermLimit(f"a minor over {max_terms} terms")
            term = a * sub
            if on_circles:
                term = ring.on_circles(term)
            if pos % 2:
                term = -term
            total = term if total is None else total + term
            if max_terms is not None and len(total) > max_terms:
                raise TermLimit(f"a minor over {max_terms} terms")
        if total is None:
            total = M[r][cols[0]] * 0
        memo[key] = total
        return total

    if on_circles:
        M = [[ring.on_circles(x) for x in row] for row in M]
    det = minor(0, tuple(range(n)))
    return ring.normal(det) if ring is not None else det


def circle_free_det(M, ring: PolyRing, poll=None, *, max_terms: int | None = None):
    """The determinant of ``M`` divided by every power of ``C**2 + S**2`` that divides it.

    ``M`` is homogeneous in each pair by rows or by columns, and so is its determinant,
    which then carries powers of ``C**2 + S**2`` (= 1 on the circles): on romeo's 8-joint arm a
    6 x 6 minor of 1185408 terms is one of 213 terms times such powers.  The expansion runs on
    the circles instead (:meth:`PolyRing.on_circles`), where these powers are 1 and the
    products stay small (there: 0.01 s against 10 s), and the result is made homogeneous again
    (:meth:`PolyRing.homogenized`).  The factors that can vanish on the circles are those of
    the determinant.  A matrix homogeneous in neither way gets the plain determinant.
    ``max_terms`` is passed to :func:`laplace_det`.
    """
    reduced = laplace_det(M, ring, poll, on_circles=True, max_terms=max_terms)
    try:
        return ring.homogenized(reduced)
    except ValueError:
        return laplace_det(M, ring, poll, max_terms=max_terms)


def irreducible_factors(p, ring: PolyRing):
    """Distinct irreducible, non-constant factors of ``p``, spurious ones removed.

    ``C**2 + S**2`` has no zero on the circle and is dropped.
    """
    p = ring.normal(p)
    if p.is_zero():
        raise ValueError("zero polynomial has no factorisation")
    _, facs = _without_circles(p, ring).factor()
    out = []
    surds = set(range(ring.surd_start, len(ring.names)))
    for f, _ in facs:
        if f.is_constant():
            continue
        if _is_circle(f, ring):
            continue
        if surds and ring.variable_indices(f) <= surds:
            continue     # a nonzero number: reduced polynomials in the surds alone vanish only if zero
        lc = f.leading_coefficient()
        out.append(f / lc)
    return out


def _without_circles(p, ring: PolyRing):
    """``p`` divided by every power of ``C**2 + S**2`` that divides it.

    A determinant of a matrix homogeneous in each pair carries such factors to high powers (on
    centauro's arm, 179388 terms = a factor of 1130 terms times 16 of them), and factoring them
    with the rest takes FLINT 3 to 30 times as long as dividing them out first (0.43 s against
    0.15 + 0.015 s there).  Exact division stops early where it fails.
    """
    degs = p.degrees()
    for i in range(ring.n_angles):
        C, S = ring.C(i), ring.S(i)
        if degs[2 * i] + degs[2 * i + 1] < 2:
            continue
        circle = C * C + S * S
        while True:
            try:
                p = p / circle
            except DomainError:
                break
    return p


def _is_circle(f, ring):
    for i in range(ring.n_angles):
        C, S = ring.C(i), ring.S(i)
        g = C * C + S * S
        if f == g:
            return True
    return False


def abs_poly(p, ring: PolyRing):
    """``p`` with every coefficient replaced by its absolute value.

    Evaluated at the absolute values of the generators it bounds |p| and
    measures the size of p's terms, the scale against which "p vanishes
    here" is decided.
    """
    return ring.ctx.from_dict({m: abs(c) for m, c in zip(p.monoms(), p.coeffs())})


def common_factor(polys):
    """The greatest common divisor of the nonzero ``polys`` (None if there are none).

    Taken smallest polynomial first, and it stops once the divisor is a constant.
    """
    nonzero = sorted((p for p in polys if not p.is_zero()), key=len)
    if not nonzero:
        return None
    g = nonzero[0]
    for p in nonzero[1:]:
        if g.is_constant():
            break
        g = g.gcd(p)
    return g


def primitive_vector(v):
    """``v`` divided by the greatest common divisor of its entries.

    A vector of cofactors carries the factors common to all its minors (on
    a 6x8 Jacobian of romeo's arm, powers of ``C**2 + S**2`` of total degree
    42 in entries of degree 50); dividing them out scales the vector by a
    polynomial, so it spans the same line wherever the divisor is nonzero.

    Examples
    --------
    >>> import flint
    >>> ctx = flint.fmpq_mpoly_ctx.get(("x", "y"), "lex")
    >>> x, y = ctx.gens()
    >>> primitive_vector([(x**2 + y**2) * x, 0 * x, 2 * (x**2 + y**2) * y])
    [x, 0, 2*y]
    """
    g = common_factor(v)
    if g is None or g.is_constant():
        return list(v)
    return [p if p.is_zero() else p / g for p in v]


def transpose(M):
    """The transpose of a matrix given as a list of rows."""
    return [list(col) for col in zip(*M)]


class PolyMemo:
    """Values computed from tuples of polynomials, kept while their size allows.

    Polynomials are not hashable: a key is bucketed by the number of terms of
    each polynomial, and found by exact comparison within its bucket.  The
    oldest entries are dropped once the stored polynomials (keys and values)
    hold more than ``max_terms`` terms in all.

    Examples
    --------
    >>> import sympy as sp
    >>> ring = PolyRing((), (sp.Symbol("x"),), ())
    >>> x = ring.gens[0]
    >>> memo = PolyMemo(1000)
    >>> calls = []
    >>> det = lambda key: calls.append(key) or key[0] * key[1]
    >>> memo.get((x + 1, x), det), memo.get((x + 1, x), det), len(calls)
    (x^2 + x, x^2 + x, 1)
    """

    def __init__(self, max_terms: int):
        self.max_terms = max_terms
        self._entries: dict = {}
        self._terms = 0

    @staticmethod
    def _size(value) -> int:
        if isinstance(value, (list, tuple)):
            return sum(PolyMemo._size(v) for v in value)
        return len(value) if hasattr(value, "monoms") else 1

    def get(self, key: tuple, compute):
        """``compute(key)``, or its value from an earlier call with an equal key."""
        finger = tuple(len(p) for p in key)
        bucket = self._entries.get(finger)
        if bucket is not None:
            for k, v in bucket:
                if all(a == b for a, b in zip(k, key)):
                    return v
        value = compute(key)
        size = sum(finger) + self._size(value)
        if size > self.max_terms:
            return value
        self._entries.setdefault(finger, []).append((key, value))
        self._terms += size
        while self._terms > self.max_terms:
            oldest = next(iter(self._entries))
            k, v = self._entries[oldest].pop(0)
            self._terms -= sum(len(p) for p in k) + self._size(v)
            if not self._entries[oldest]:
                del self._entries[oldest]
        return value
