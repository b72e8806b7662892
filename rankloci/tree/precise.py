"""Singular or regular at a real point of a branch, decided in extended precision.

The exact decisions of :mod:`.modular` are made at points modulo a prime,
which know nothing of real numbers.  A branch whose equations are
irreducible over the rationals can still split into pieces over the reals,
and some of those pieces can have no real points at all.  The 7R arm with
0.5 mm offsets has one: on ``1 - 800 sin q4 = 0`` the second equation
factors over Q(sqrt(71111)).  One factor is ``cos q6 + 3 sqrt(71111) sin q6``
(real, J regular, sigma_min/sigma_max about 1e-6).  The other is
``1 + (3 sqrt(71111) - 800) sin q2``, which asks for sin q2 = 1600: it has
no real points, and J is singular on it.  The points modulo a prime fell on
that second piece.  The real sample points, in double precision, show
ratios from 1e-6 down to 1e-14, because the geometry is nearly degenerate.
Neither test sees that the branch's real points are regular.

This module decides at a real sample point ``g`` instead.  ``g`` is moved
onto the branch in ``PRECISE_DPS`` digits: Gauss-Newton steps on the
branch's conditions in the joint angles (each pair (C, S) rotated, so
it stays on the circle) and the other joint variables, with the
parameters fixed.  Then the smallest singular value of the matrix there is
compared with its largest.  At a point of the branch accurate to
``PRECISE_RESIDUAL``, a singular matrix shows a ratio near that residual.
Nearly degenerate regular ones show 1e-17 and more (the offset arm's
closest, at 60 digits).  ``PRECISE_SINGULAR_RTOL`` lies between the two, with
seven orders of margin on either side.  A point whose refinement does not
converge (a branch whose equations are critical at their real zeros) is
left undecided.
"""

from __future__ import annotations

import mpmath
import numpy as np

from ..algebra import PolyRing
from ..numeric.equations import minimum_norm_step
from .branch import Branch
from .certify import at_dyadic
from ..tolerances import PRECISE_MAX_TERMS, PRECISE_STEPS

__all__ = ["PreciseProbe"]


class PreciseProbe:
    """Extended-precision rank decisions of a matrix at real points of branches.

    Parameters
    ----------
    ring : PolyRing
    M : list of rows of ring polynomials
        The matrix whose rank is decided (the computation's whole matrix).
    """

    def __init__(self, ring: PolyRing, M):
        self.ring = ring
        self.M = M
        self._terms: dict = {}
        self._grads: dict = {}
        self._memo: dict = {}
        self._last = None

    def _abs(self, p):
        """``p`` with every coefficient made positive (its value at |x| is the size of its
        terms at x), kept by identity."""
        got = self._terms.get(id(p))
        if got is None or got[0] is not p:
            got = (p, p.context().from_dict({m: abs(c) for m, c in zip(p.monoms(), p.coeffs())}))
            self._terms[id(p)] = got
        return got[1]

    def _point(self, x):
        """``x`` and ``|x|`` as exact dyadic rationals (the last point is kept)."""
        key = tuple(v._mpf_ for v in x)
        if self._last is None or self._last[0] != key:
            xs = [_dyadic(v) for v in x]
            self._last = (key, xs, [abs(v) for v in xs])
        return self._last[1], self._last[2]

    def _value(self, p, x):
        """``p`` at ``x``, exactly, rounded to the working precision.

        Evaluated in integers at the dyadic rationals that the working-precision numbers
        ``x`` are (:func:`.certify.at_dyadic`): no rounding inside the sum, whatever
        cancellation it has, and about a hundred times faster than a term-by-term sum in
        mpmath.
        """
        if p.is_zero():
            return mpmath.mpf(0)
        v = at_dyadic(p, self._point(x)[0], self._memo)
        return mpmath.mpf(int(v.p)) / int(v.q)

    def _size(self, p, x):
        """The size of ``p``'s terms at ``x`` (the sum of their absolute values)."""
        if p.is_zero():
            return mpmath.mpf(0)
        v = at_dyadic(self._abs(p), self._point(x)[1], self._memo)
        return mpmath.mpf(int(v.p)) / int(v.q)

    def _gradient(self, p):
        got = self._grads.get(id(p))
        if got is None or got[0] is not p:
            got = (p, self.ring.gradient(p))
            self._grads[id(p)] = got
        return got[1]

    def refine(self, branch: Branch, g):
        """``g`` moved onto ``branch`` in extended precision, or None where that fails.

        The unknowns are the angles and the other joint variables (the
        parameters stay at ``g``'s values); an angle moves by rotating its
        pair (C, S), which stays on the circle.
        """
        from ..tolerances import PRECISE_DPS, PRECISE_RESIDUAL

        ring = self.ring
        na, base = ring.n_angles, 2 * ring.n_angles
        with mpmath.workdps(PRECISE_DPS):
            x = self._exact_start(g)
            eqs = list(branch.conditions)
            if not eqs:
                return x
            for _ in range(PRECISE_STEPS):
                F, worst = [], mpmath.mpf(0)
                for p in eqs:
                    v, s = self._value(p, x), self._size(p, x)
                    F.append(v)
                    worst = max(worst, abs(v) / s if s else mpmath.mpf(0))
                if worst <= PRECISE_RESIDUAL:
                    return x
                A = mpmath.matrix([[self._value(d, x) for d in self._gradient(p)]
                                   for p in eqs])
                step = minimum_norm_step(A, mpmath.matrix(F))
                if step is None:
                    return None
                for i in range(na):
                    h = -step[i] / 2
                    c, s = mpmath.cos(h), mpmath.sin(h)
                    C, S = x[2 * i], x[2 * i + 1]
                    x[2 * i], x[2 * i + 1] = c * C - s * S, s * C + c * S
                for j in range(len(ring.others)):
                    x[base + j] -= step[na + j]
            return None

    def _exact_start(self, g) -> list:
        """``g`` in the working precision, with the relations of the generators exact.

        Each surd generator gets its value sqrt(p) in full precision and each pair
        (C, S) = (cos q/2, sin q/2) is put back on the unit circle: in double precision both
        are off by ~1e-16, and a matrix that is singular only modulo those relations shows
        that much of a ratio, regular to every digit after (the Jaco2's entries in sqrt(3)
        made the branch of its one component look regular at 40 digits).
        """
        ring = self.ring
        x = [mpmath.mpf(float(v)) for v in g]
        for i in range(ring.n_angles):
            C, S = x[2 * i], x[2 * i + 1]
            r = mpmath.sqrt(C * C + S * S)
            if r:
                x[2 * i], x[2 * i + 1] = C / r, S / r
        for k, prime in enumerate(ring.surds):
            x[ring.surd_start + k] = mpmath.sqrt(prime)
        return x

    def ratio(self, branch: Branch, g) -> float | None:
        """sigma_min / sigma_max of the matrix at ``g`` refined onto ``branch`` (None: no point).

        Rows are scaled to unit norm, and a row that vanishes against the size
        of its terms makes the ratio 0, as in :func:`.probe.scaled_ratio`.
        """
        from ..tolerances import PRECISE_DPS, PRECISE_RESIDUAL

        x = self.refine(branch, g)
        if x is None:
            return None
        with mpmath.workdps(PRECISE_DPS):
            rows = []
            for row in self.M:
                vals = [(self._value(p, x), self._size(p, x)) for p in row]
                norm = mpmath.sqrt(sum(v * v for v, _ in vals))
                size = mpmath.sqrt(sum(s * s for _, s in vals))
                if not norm > PRECISE_RESIDUAL * size:
                    return 0.0
                rows.append([v / norm for v, _ in vals])
            A = mpmath.matrix(rows)
            if A.rows > A.cols:
                A = A.T
            s = mpmath.svd_r(A, compute_uv=False)
            s = sorted((abs(v) for v in s), reverse=True)
            return float(s[-1] / s[0]) if len(s) == min(A.rows, A.cols) else 0.0

    def regular_columns(self, branch: Branch, M, points):
        """Columns of a square block of the wide matrix ``M`` that is regular at one of the
        points refined onto ``branch``, smallest entries first; None if there is none."""
        import itertools

        from ..tolerances import PRECISE_DPS, PRECISE_SINGULAR_RTOL

        n, m = len(M), len(M[0])
        size = [sum(len(M[i][j]) for i in range(n)) for j in range(m)]
        combos = sorted(itertools.combinations(range(m), n), key=lambda cs: sum(size[c] for c in cs))
        for g in points:
            x = self.refine(branch, g)
            if x is None:
                continue
            with mpmath.workdps(PRECISE_DPS):
                vals = [[self._value(p, x) for p in row] for row in M]
                norms = [mpmath.sqrt(sum(v * v for v in row)) for row in vals]
                if not all(norms):
                    continue
                A = mpmath.matrix([[v / nr for v in row] for row, nr in zip(vals, norms)])
                for cols in combos:
                    B = mpmath.matrix([[A[i, c] for c in cols] for i in range(n)])
                    if abs(_det(B)) > PRECISE_SINGULAR_RTOL:
                        return list(cols)
        return None

    def affordable(self, branch: Branch) -> bool:
        """Are ``branch``'s conditions small enough (``PRECISE_MAX_TERMS``) to refine points on?"""
        return sum(len(p) for p in branch.conditions) <= PRECISE_MAX_TERMS

    def singular(self, branch: Branch, g) -> bool | None:
        """Is the matrix singular at the point of ``branch`` next to ``g``?  None: undecided."""
        from ..tolerances import PRECISE_SINGULAR_RTOL

        r = self.ratio(branch, g)
        return None if r is None else r <= PRECISE_SINGULAR_RTOL


def _det(B):
    """The determinant of the square mpmath matrix ``B``, by elimination with partial pivoting.

    ``mpmath.det`` fails with a TypeError on some singular matrices (a column that
    is zero below the diagonal leaves its pivot unset); here such a column gives 0.
    """
    A = B.copy()
    n = A.rows
    det = mpmath.mpf(1)
    for j in range(n):
        p = max(range(j, n), key=lambda k: abs(A[k, j]))
        if not A[p, j]:
            return mpmath.mpf(0)
        if p != j:
            for c in range(n):
                A[p, c], A[j, c] = A[j, c], A[p, c]
            det = -det
        det *= A[j, j]
        for k in range(j + 1, n):
            f = A[k, j] / A[j, j]
            if f:
                for c in range(j + 1, n):
                    A[k, c] -= f * A[j, c]
    return det


def _dyadic(v) -> "flint.fmpq":
    """The exact value of the mpf ``v``: a rational whose denominator is a power of two."""
    import flint

    sign, man, exp, _ = v._mpf_
    man = -int(man) if sign else int(man)
    return flint.fmpq(man) * 2 ** exp if exp >= 0 else flint.fmpq(man, 2 ** (-exp))

