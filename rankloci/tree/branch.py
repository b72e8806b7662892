"""Branches of a locus computation: sets cut out by polynomial conditions.

A :class:`Branch` is the set of configurations where a list of polynomial
conditions vanish.  A condition that can be solved for one unknown is
*substituted* (the matrices shrink); the others are carried as implicit
equations.  Solvable conditions are

- ``S`` (q = 0) and ``C`` (q = pi) of an angle pair;
- ``a*C + b*S`` with ``a``, ``b`` free of that pair and together at most
  ``PAIR_MAX_TERMS`` terms: (C, S) is proportional to (b, -a), valid where
  (a, b) != (0, 0); the points where both vanish form a separate branch;
- ``c*x + r`` with a nonzero rational ``c`` for a polynomial variable or a
  parameter ``x``.

Points of a branch are found by :class:`rankloci.tree.sampler.BranchSampler`.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

from ..algebra import PolyRing, TermLimit
from ..tolerances import PAIR_MAX_TERMS

__all__ = ["Branch", "Substitution", "SubstitutedMatrices", "solve_condition", "apply_substitution"]


@dataclass(frozen=True)
class Substitution:
    """Generators replaced by polynomials in the remaining ones.

    ``kind`` is "zero" (q = 0), "pi", "pair" (C, S proportional to two
    polynomials), or "linear" (x = polynomial).
    """

    kind: str
    index: int          # angle number for "zero"/"pi"/"pair", generator index for "linear"
    values: tuple       # the polynomials that replace the generator(s)


@dataclass(frozen=True)
class Branch:
    """Conditions (flint polynomials of the full ring) and how they were solved."""

    conditions: tuple = ()
    substitutions: tuple = ()
    implicit: tuple = ()
    nonzero: tuple = ()

    @functools.cached_property
    def key(self) -> tuple:
        """The conditions and exclusions as text: equal for equal branches."""
        return (tuple(str(c) for c in self.conditions), tuple(str(p) for p in self.nonzero))

    def excluding(self, p) -> "Branch":
        """This branch without the points where ``p`` vanishes (an open subset).

        The null vectors of a level are valid only where the determinant of
        their regular block is nonzero; the branches below that level live
        on that open set.  The excluded points are analysed on their own
        branch, so nothing is lost.
        """
        if p.is_constant() or any(p == q for q in self.nonzero):
            return self
        return Branch(self.conditions, self.substitutions, self.implicit, self.nonzero + (p,))

    def closure(self) -> "Branch":
        """The same conditions without the excluded sets."""
        return Branch(self.conditions, self.substitutions, self.implicit)

    def with_condition(self, f, ring: PolyRing) -> tuple["Branch", list]:
        """This branch and ``f = 0``; also the extra conditions of its exceptional part.

        Returns the new branch and a list of condition lists, each one
        describing a piece of {f = 0} the substitution does not cover.
        """
        f = self.reduce(f, ring)
        sub, exceptional = solve_condition(f, ring)
        if sub is None:
            return Branch(self.conditions + (f,), self.substitutions, self.implicit + (f,),
                          self.nonzero), []
        return (Branch(self.conditions + (f,), self.substitutions + (sub,), self.implicit,
                       self.nonzero), exceptional)

    def reduce(self, p, ring: PolyRing):
        """``p`` with this branch's substitutions applied."""
        for sub in self.substitutions:
            p = apply_substitution(p, sub, ring)
        return p


def _pair_parts(f, ring: PolyRing, i: int):
    """(a, b) with f = a*C_i + b*S_i if f is linear in pair i, else None."""
    ci, si = 2 * i, 2 * i + 1
    a, b = {}, {}
    for mon, coeff in zip(f.monoms(), f.coeffs()):
        e = mon[ci] + mon[si]
        if e != 1:
            return None
        rest = list(mon)
        rest[ci] = rest[si] = 0
        (a if mon[ci] else b)[tuple(rest)] = coeff
    ctx = ring.ctx
    return ctx.from_dict(a) if a else ctx.constant(0), ctx.from_dict(b) if b else ctx.constant(0)


def solve_condition(f, ring: PolyRing):
    """A :class:`Substitution` solving ``f = 0``, and its exceptional conditions."""
    used = ring.variable_indices(f)
    na = ring.n_angles
    zero, one = ring.ctx.constant(0), ring.ctx.constant(1)
    # angle pairs first, the simplest solution first
    best = None
    for i in range(na):
        if 2 * i not in used and 2 * i + 1 not in used:
            continue
        parts = _pair_parts(f, ring, i)
        if parts is None:
            continue
        a, b = parts
        if b.is_zero() and a.is_constant():
            return Substitution("pi", i, (zero, one)), []
        if a.is_zero() and b.is_constant():
            return Substitution("zero", i, (one, zero)), []
        size = len(a) + len(b)
        if best is None or size < best[0]:
            best = (size, i, a, b)
    for g in sorted(used):
        if g < 2 * na or g >= ring.surd_start:
            continue            # angles are solved above; surds have fixed values
        # linear in generator g with a constant coefficient?
        degs = [mon[g] for mon in f.monoms()]
        if max(degs) != 1:
            continue
        coeff_terms = {}
        rest_terms = {}
        for mon, c in zip(f.monoms(), f.coeffs()):
            m = list(mon)
            if m[g]:
                m[g] = 0
                coeff_terms[tuple(m)] = c
            else:
                rest_terms[tuple(m)] = c
        coeff = ring.ctx.from_dict(coeff_terms)
        if coeff.is_constant():
            rest = ring.ctx.from_dict(rest_terms) if rest_terms else zero
            return Substitution("linear", g, (-rest / coeff,)), []
    if best is not None and best[0] <= PAIR_MAX_TERMS:
        _, i, a, b = best
        return Substitution("pair", i, (b, -a)), [[a, b]]
    return None, []


def apply_substitution(p, sub: Substitution, ring: PolyRing):
    """``p`` with the generators that ``sub`` solves replaced by their values."""
    if p.is_zero():
        return p
    degs = p.degrees()
    if sub.kind == "linear":
        if not degs[sub.index]:
            return p
    elif not (degs[2 * sub.index] or degs[2 * sub.index + 1]):
        return p
    vals = list(ring.gens)
    if sub.kind == "linear":
        vals[sub.index] = sub.values[0]
    else:
        vals[2 * sub.index], vals[2 * sub.index + 1] = sub.values
    return ring.normal(p.compose(*vals))


class SubstitutedMatrices:
    """Matrices with the substitutions of a branch applied, memoised by prefix.

    Sibling branches share their parent's substitutions, so each entry is
    reduced by the newest substitution only.  An entry keeps the matrix and
    the substitutions alive, so their ids cannot be reused while it exists.
    """

    #: entries kept before the memo starts afresh
    LIMIT = 4096

    def __init__(self, ring: PolyRing):
        self.ring = ring
        self._memo = {}

    def of(self, M, branch: Branch, max_terms: int | None = None):
        """``M`` with the substitutions of ``branch`` applied.

        With ``max_terms``, :class:`~rankloci.algebra.TermLimit` is raised as soon as a
        matrix formed on the way holds more terms than that (nothing is memoised then).
        """
        return self._by(M, branch.substitutions, max_terms)

    def _by(self, M, subs, max_terms=None):
        if not subs:
            return M
        key = (id(M),) + tuple(id(s) for s in subs)
        got = self._memo.get(key)
        if got is None or got[0] is not M or any(a is not b for a, b in zip(got[1], subs)):
            prev = self._by(M, subs[:-1], max_terms)
            last = subs[-1]
            rows, terms = [], 0
            for row in prev:
                rows.append([apply_substitution(p, last, self.ring) for p in row])
                terms += sum(len(p) for p in rows[-1])
                if max_terms is not None and terms > max_terms:
                    raise TermLimit(f"substituted matrix over {max_terms} terms")
            got = (M, subs, rows)
            if len(self._memo) > self.LIMIT:
                self._memo.clear()
            self._memo[key] = got
        return got[2]
