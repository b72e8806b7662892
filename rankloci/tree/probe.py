"""Numeric probes of polynomial matrices at points of a branch.

The tree decides "is this matrix of full rank on the branch" and "does this
polynomial vanish on the branch" at sample points (see
:mod:`rankloci.tree.sampler`).  A :class:`Probe` compiles the polynomials
once and keeps them, so that a matrix met again on a sibling branch is not
compiled again.  Every decision is relative: a value is zero when it is
small against the size of its terms (``ZERO_RTOL``), and a matrix is rank
deficient when sigma_min <= ``RANK_RTOL`` * sigma_max.
"""

from __future__ import annotations

import numpy as np

from ..algebra import PolyRing
from ..tolerances import RANK_RTOL, ZERO_RTOL

__all__ = ["Probe", "numeric_rank", "scaled_ratio"]

#: How many compiled matrices (and polynomials) a probe keeps before it starts afresh.
_MATRIX_CACHE = 512
_POLY_CACHE = 4096


def numeric_rank(A, sizes) -> int:
    """Rank of the evaluated matrix ``A`` whose entries have term sizes ``sizes``.

    Rows are scaled to unit norm first (row scaling keeps the rank and
    removes the arbitrary powers of C**2 + S**2); a row whose entries all
    vanish relative to the size of their terms (ZERO_RTOL) is a zero row.

    Examples
    --------
    >>> import numpy as np
    >>> numeric_rank(np.array([[1.0, 2.0], [2.0, 4.0]]), np.ones((2, 2)))
    1
    """
    s = _scaled_singular_values(A, sizes)
    return int(np.sum(s > RANK_RTOL * s[0])) if len(s) else 0


def scaled_ratio(A, sizes) -> float:
    """sigma_min / sigma_max of ``A`` with its rows scaled as :func:`numeric_rank` scales them
    (0 when some row is zero).

    Examples
    --------
    >>> import numpy as np
    >>> scaled_ratio(np.array([[3.0, 0.0], [0.0, 1e-3]]), np.ones((2, 2)))
    1.0
    """
    s = _scaled_singular_values(A, sizes)
    return float(s[-1] / s[0]) if len(s) == min(A.shape) else 0.0


def _scaled_singular_values(A, sizes):
    """Singular values of ``A``'s nonzero rows (ZERO_RTOL of their term sizes), each scaled to
    unit norm."""
    # rows scaled by their largest term size first: entries of 1e156 would overflow the norms
    big = np.max(np.abs(sizes), axis=1, keepdims=True)
    big[~(big > 0)] = 1.0
    A, sizes = A / big, sizes / big
    norms = np.linalg.norm(A, axis=1)
    nz = norms > ZERO_RTOL * np.linalg.norm(sizes, axis=1)
    if not np.any(nz):
        return np.zeros(0)
    return np.linalg.svd(A[nz] / norms[nz, None], compute_uv=False)


class Probe:
    """Values, ranks and zero tests of polynomial matrices of one ring at points.

    Points are generator vectors of the ring (see
    :meth:`rankloci.algebra.PolyRing.names`).  Compiled functions are cached
    by the identity of the polynomials; each cache entry keeps its
    polynomials alive, so an id cannot be reused while its entry exists.
    """

    def __init__(self, ring: PolyRing):
        self.ring = ring
        self._matrices = {}
        self._polys = {}

    def _evaluator(self, flat, *, absolute: bool = False, sized: bool = False):
        """``ring.compile(flat, ...)``, cached by the identity of the polynomials of ``flat``."""
        key = (absolute, sized) + tuple(id(p) for p in flat)
        got = self._matrices.get(key)
        if got is None or any(a is not b for a, b in zip(got[0], flat)):
            got = (flat, self.ring.compile(flat, absolute=absolute, sized=sized))
            if len(self._matrices) > _MATRIX_CACHE:
                self._matrices.clear()
            self._matrices[key] = got
        return got[1]

    def values(self, M, g, *, scale: bool = False) -> np.ndarray:
        """Values of the entries of ``M`` at ``g`` (or, with ``scale``, the size of their terms)."""
        ev = self._evaluator([p for row in M for p in row], absolute=scale)
        return ev(np.abs(g) if scale else g).reshape(len(M), len(M[0]))

    def evaluated(self, M, g) -> tuple[np.ndarray, np.ndarray]:
        """The values of ``M`` at ``g`` and the sizes of their terms (one evaluation)."""
        values, sizes = self._evaluator([p for row in M for p in row], sized=True)(g)
        return values.reshape(len(M), len(M[0])), sizes.reshape(len(M), len(M[0]))

    def rank_at(self, M, g) -> int:
        """Numeric rank of ``M`` at ``g``; see :func:`numeric_rank`."""
        return numeric_rank(*self.evaluated(M, g))

    def generic_rank(self, M, points) -> int:
        """The largest numeric rank of ``M`` at the points (its rank on the branch)."""
        return max(self.rank_at(M, g) for g in points)

    def vanishes(self, p, points) -> bool:
        """Does ``p`` vanish at every point (relative to the size of its terms)?"""
        if p.is_zero():
            return True
        got = self._polys.get(id(p))
        if got is None or got[0] is not p:
            if len(self._polys) > _POLY_CACHE:
                self._polys.clear()
            got = (p, self.ring.compile([p], sized=True))
            self._polys[id(p)] = got
        val, scale = got[1](np.asarray(points, dtype=float))
        return bool(np.all(np.abs(val[:, 0]) <= ZERO_RTOL * np.maximum(scale[:, 0], 1e-300)))

    def vanishing(self, polys, points) -> np.ndarray:
        """Which of ``polys`` vanish at which points: booleans, one row per point.

        The test of :meth:`vanishes` for several polynomials and points in
        one evaluation.
        """
        polys = tuple(polys)
        G = np.asarray(points, dtype=float).reshape(-1, len(self.ring.names))
        if not polys:
            return np.ones((len(G), 0), dtype=bool)
        val, scale = self._evaluator(list(polys), sized=True)(G)
        return np.abs(val) <= ZERO_RTOL * np.maximum(scale, 1e-300)

    def changes_sign(self, p, points, angles, others, rng, *, step: float, directions: int = 6) -> bool:
        """Does ``p`` take both signs within ``step`` of some point, along a few directions?

        At a regular point of a real hypersurface p changes sign across it;
        at a real zero that is a local extremum of p (a zero of x**2 + y**2)
        it does not.  ``angles`` (angle numbers) and ``others`` (generator
        indices) are the free unknowns; the directions are the gradient's
        and random ones.  Values within ZERO_RTOL of the term size count as
        no sign.
        """
        sized = self.ring.compile([p], sized=True)
        grad = [self.ring.compile([d]) for d in self.ring.gradient(p)]
        n = len(angles) + len(others)
        if n == 0:
            return False
        for g in points:
            g = np.asarray(g, dtype=float)
            # the gradient in the free unknowns (ring.gradient: angles first, then the others)
            dg = np.array([f(g[None, :])[0, 0] for f in grad])
            na = self.ring.n_angles
            u0 = [dg[i] for i in angles] + [dg[na + j - 2 * na] for j in others]
            dirs = [np.asarray(u0, dtype=float)] + [rng.normal(size=n) for _ in range(directions)]
            for u in dirs:
                norm = np.linalg.norm(u)
                if not norm > 0:
                    continue
                u = u / norm
                G = np.array([self._moved(g, angles, others, s * step * u) for s in (1.0, -1.0)])
                v, size = sized(G)
                v = v[:, 0]
                tol = ZERO_RTOL * np.maximum(size[:, 0], 1e-300)
                if np.all(np.abs(v) > tol) and v[0] * v[1] < 0:
                    return True
        return False

    @staticmethod
    def _moved(g, angles, others, delta):
        """The generator vector ``g`` with the free unknowns moved by ``delta``."""
        out = g.copy()
        k = 0
        for i in angles:
            c, s = np.cos(delta[k] / 2), np.sin(delta[k] / 2)
            C, S = g[2 * i], g[2 * i + 1]
            out[2 * i], out[2 * i + 1] = c * C - s * S, s * C + c * S
            k += 1
        for j in others:
            out[j] = g[j] + delta[k]
            k += 1
        return out

    def gradient_vanishes(self, p, points, rtol: float) -> bool:
        """Does the gradient of ``p`` vanish at every point, relative to its terms' size?"""
        grad = [d for d in self.ring.gradient(p) if not d.is_zero()]
        if not grad:
            return False
        val, size = self.ring.compile(grad, sized=True)(np.asarray(points, dtype=float))
        return bool(np.all(np.abs(val) <= rtol * np.maximum(size, 1e-300)))
