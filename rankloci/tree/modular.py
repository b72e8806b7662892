"""Exact rank and zero decisions on a branch, at random points modulo a prime.

The numeric probes of :mod:`.probe` decide ranks against a tolerance.  On
near-degenerate geometry (a 0.5 mm offset on a 0.4 m link, say) the
smallest singular value of a matrix that is regular on a branch can be
1e-7 of the largest, close enough to the tolerance that rounding decides
the branch.  Exact algebra decides it instead: points of a branch over
the integers modulo a large prime P are found without any rounding.  Free
generators take random residues; each implicit equation in turn is solved
for one generator as a univariate polynomial mod P (its roots, when it has
any), the others at their values so far; the substitutions then give the
solved generators.  The rank of a polynomial matrix at such a point is its
rank over GF(P).

Why this decides the generic rank: the rank of the matrix at a random point
of an irreducible branch, over any field, equals its rank at a generic point
except on a proper algebraic subset, hit with probability about
(degree / P) by the Schwartz-Zippel lemma, below 1e-15 here; conjugate
pieces of a branch that is irreducible over the rationals have equal rank.
A rank mod P is never above the rank over the rationals, and a branch cut by
several equations can consist of pieces of different rank, so the largest
rank at ``POINTS`` random points is used, as the numeric probes do at their
real sample points.  Branches with more than ``MAX_IMPLICIT`` implicit
equations, and branches without points mod P, are left to the numeric
probes.
"""

from __future__ import annotations

import flint
import numpy as np

from ..algebra import PolyRing
from .branch import Branch
from ..tolerances import (MODULAR_MAX_IMPLICIT as MAX_IMPLICIT, MODULAR_MISSES as MISSES,
                          MODULAR_POINTS as POINTS, MODULAR_PRIMES as PRIMES, PRIME_BITS)

__all__ = ["ModularProbe", "block_rank", "evaluate", "prime_with_roots"]


def prime_with_roots(rng, surds, bits: int, tries: int = 200):
    """A random prime P in [2**bits, 2**(bits + 1)) and a square root mod P of each of the
    ``surds`` (primes), or None when ``tries`` candidates gave none."""
    for _ in range(tries):
        cand = int(rng.integers(2 ** bits, 2 ** (bits + 1), dtype=np.uint64)) | 1
        if not flint.fmpz(cand).is_prime():
            continue
        roots = []
        for prime in surds:
            r = flint.nmod_poly([-prime, 0, 1], cand).roots()
            if not r:
                break
            roots.append(int(r[0][0]))
        else:
            return cand, roots
    return None


class ModularProbe:
    """Exact ranks and zero tests at random points of branches modulo large primes."""

    def __init__(self, ring: PolyRing, rng: np.random.Generator):
        self.ring = ring
        self.rng = rng
        self._points: dict = {}
        self._codims: dict = {}
        self._prime = None

    def copy(self) -> "ModularProbe":
        """A copy with its own random stream and its own record of the points it found."""
        import copy

        new = copy.copy(self)
        new.rng = copy.deepcopy(self.rng)
        new._points = dict(self._points)
        new._codims = dict(self._codims)
        return new

    # --- primes and points ------------------------------------------------------------------

    def _new_prime(self) -> tuple[int, list[int]] | None:
        """A prime P and square roots mod P of the ring's surd primes (None if none found)."""
        return prime_with_roots(self.rng, self.ring.surds, PRIME_BITS)

    def points(self, branch: Branch) -> tuple[int, list[list[int]]] | None:
        """A prime P and ``POINTS`` generator vectors of ``branch`` mod P, or None.

        None when the branch has more than ``MAX_IMPLICIT`` implicit equations,
        or no point was found (the branch may have no points at all).
        """
        key = branch.key
        if key in self._points:
            return self._points[key]
        got = self._search(branch) if len(branch.implicit) <= MAX_IMPLICIT else None
        self._points[key] = got
        return got

    def _search(self, branch: Branch):
        # whether a univariate polynomial has roots mod P can depend on P alone (a quadratic
        # with a non-square discriminant), so a prime that keeps failing is replaced
        primes = ([self._prime] if self._prime else []) + [None] * PRIMES
        for prime in primes:
            prime = prime or self._new_prime()
            if prime is None:
                return None
            P, roots = prime
            found, codims, misses = [], [], 0
            while len(found) < POINTS and misses < MISSES:
                got = self._point(branch, P, roots)
                if got is None:
                    misses += 1
                else:
                    found.append(got[0])
                    codims.append(got[1])
            if len(found) == POINTS:
                self._prime = prime
                self._codims[branch.key] = codims
                return P, found
        return None

    def _free(self, branch: Branch) -> list[int]:
        """Generators not solved by a substitution, surds excluded."""
        ring = self.ring
        solved = set()
        for s in branch.substitutions:
            if s.kind == "linear":
                solved.add(s.index)
            else:
                solved |= {2 * s.index, 2 * s.index + 1}
        return [g for g in range(ring.surd_start) if g not in solved]

    def _joint_count(self) -> int:
        return self.ring.n_angles + len(self.ring.others)

    def _point(self, branch: Branch, P: int, roots: list[int]) -> tuple[list[int], int] | None:
        """A point of ``branch`` mod P and the number of joint degrees of freedom it fixed."""
        ring = self.ring
        vals = [0] * len(ring.names)
        for g in self._free(branch):
            vals[g] = int(self.rng.integers(1, P - 1, dtype=np.uint64))
        vals[ring.surd_start:] = roots
        joint = 2 * ring.n_angles + len(ring.others)
        codim = self._substituted_joints(branch)
        solved = set()
        for f in branch.implicit:
            # each equation is solved for a generator no earlier equation was solved for,
            # with every other generator at its value so far (earlier solutions included)
            target = self._solve_for(f, solved)
            if target is None:
                return None
            coeffs = _univariate(f, target, vals, P)
            if all(c == 0 for c in coeffs):
                continue            # implied by the earlier equations at this point
            rts = flint.nmod_poly(coeffs, P).roots()
            if not rts:
                return None
            vals[target] = int(rts[int(self.rng.integers(len(rts)))][0])
            solved.add(target)
            codim += target < joint
        for sub in reversed(branch.substitutions):
            got = [evaluate(v, vals, P) for v in sub.values]
            if sub.kind == "linear":
                vals[sub.index] = got[0]
            else:
                if got[0] == 0 and got[1] == 0:
                    return None
                vals[2 * sub.index], vals[2 * sub.index + 1] = got
        if any(evaluate(c, vals, P) for c in branch.implicit):
            return None
        if any(evaluate(e, vals, P) == 0 for e in branch.nonzero):
            return None
        return vals, codim

    def _solve_for(self, f, solved) -> int | None:
        """The generator to solve ``f`` for: the lowest degree among those it uses, not ``solved``.

        A joint generator when ``f`` has one, so that a parameter takes up no
        joint degree of freedom.
        """
        degs = f.degrees()
        joint = 2 * self.ring.n_angles + len(self.ring.others)
        used = [g for g in range(self.ring.surd_start) if degs[g] and g not in solved]
        if any(g < joint for g in used):
            used = [g for g in used if g < joint]
        if not used:
            return None
        return min(used, key=lambda g: (degs[g], g))

    # --- decisions ----------------------------------------------------------------------------

    def values(self, M, branch: Branch) -> list | None:
        """``M`` at the points of ``branch`` mod P, as ``nmod_mat`` objects; None if undecided."""
        got = self.points(branch)
        if got is None or not M or not M[0]:
            return None
        P, pts = got
        n, m = len(M), len(M[0])
        return [flint.nmod_mat(n, m, [evaluate(p, g, P) for row in M for p in row], P)
                for g in pts]

    def rank(self, M, branch: Branch) -> int | None:
        """Rank of the polynomial matrix ``M`` on ``branch``, exactly; None if undecided here."""
        vals = self.values(M, branch)
        return None if vals is None else max(A.rank() for A in vals)

    def _substituted_joints(self, branch: Branch) -> int:
        """Joint degrees of freedom that the substitutions of ``branch`` fix."""
        joint = 2 * self.ring.n_angles + len(self.ring.others)
        return sum(1 for sub in branch.substitutions if sub.kind != "linear" or sub.index < joint)

    def complete_intersection(self, branch: Branch) -> bool | None:
        """Does every implicit equation of ``branch`` fix one joint degree of freedom?

        Exact; None if undecided here.  When not, some equation is implied by the others on
        a piece of the branch, and the equations can also hold on smaller pieces.
        """
        dim = self.dimension(branch)
        if dim is None:
            return None
        return dim == self._joint_count() - self._substituted_joints(branch) - len(branch.implicit)

    def dimension(self, branch: Branch) -> int | None:
        """Dimension of ``branch`` in the joint variables, exactly; None if undecided here.

        Every substitution of a joint generator and every implicit equation
        solved for one removes one degree of freedom; an equation that held
        already at the point (implied by the earlier ones) removes none.  A
        squared equation, whose gradient vanishes on its zero set, counts once,
        which a gradient rank would not see.
        """
        got = self.points(branch)
        if got is None:
            return None
        return self._joint_count() - min(self._codims[branch.key])

    def vanishes(self, p, branch: Branch) -> bool | None:
        """Does ``p`` vanish on ``branch``?  Exact; None if undecided here."""
        got = self.points(branch)
        if got is None:
            return None
        P, pts = got
        return all(evaluate(p, g, P) == 0 for g in pts)


def evaluate(p, vals, P: int) -> int:
    """The value of the flint polynomial ``p`` at the integer vector ``vals``, mod P."""
    if p.is_zero():
        return 0
    v = p(*[flint.fmpz(x) for x in vals])
    num, den = int(v.p), int(v.q)
    if den % P == 0:
        raise ZeroDivisionError("a coefficient's denominator is divisible by the prime")
    return num % P * pow(den, -1, P) % P


def _univariate(f, target: int, vals, P: int) -> list[int]:
    """Coefficients (low degree first) of ``f`` in generator ``target``, the others at ``vals``, mod P."""
    coeffs = [0] * (f.degrees()[target] + 1)
    for mon, c in zip(f.monoms(), f.coeffs()):
        term = int(c.p) % P * pow(int(c.q), -1, P) % P
        for g, e in enumerate(mon):
            if e and g != target:
                term = term * pow(vals[g], e, P) % P
        coeffs[mon[target]] = (coeffs[mon[target]] + term) % P
    return coeffs


def block_rank(A, rows, cols) -> int:
    """Rank of the block ``rows`` x ``cols`` of the ``nmod_mat`` ``A``."""
    B = flint.nmod_mat(len(rows), len(cols), [int(A[i, j]) for i in rows for j in cols],
                       A.modulus())
    return B.rank()
