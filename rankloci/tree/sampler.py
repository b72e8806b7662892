"""Real points of branches, found numerically.

Everything that needs a *point* of a branch (is it empty, what is the
generic rank of a matrix on it, does a polynomial vanish on it) asks a
:class:`BranchSampler`: real points found by least squares from random
starts.  A point is accepted when every condition is below ``ROOT_XTOL``
relative to the size of its terms, and every excluded polynomial is above
``EXCLUSION_RTOL``, or above ``EXCLUSION_CERTIFY_RTOL`` with an exact point
of the branch next to it at which the exclusions are nonzero by proof
(:mod:`.certify`): on near-degenerate geometry an exclusion can be 1e-6 of
its term size on a whole component.
"""

from __future__ import annotations

import functools

from dataclasses import dataclass, field

import numpy as np

from ..algebra import PolyRing
from ..numeric.gauss_newton import gauss_newton_rows
from .branch import Branch
from .certify import certified_point
from ..tolerances import CERTIFY_ROWS

__all__ = ["BranchSampler"]


@dataclass
class BranchSampler:
    """Finds real points of branches, for a fixed ring and parameter values."""

    ring: PolyRing
    param_values: dict
    rng: np.random.Generator
    n_starts: int = 24
    cache: dict = field(default_factory=dict)
    _sub_eval: dict = field(default_factory=dict)
    closest: dict = field(default_factory=dict)
    #: sampler with the model's own parameter values, asked when these values give no point
    fallback: "BranchSampler | None" = None
    fell_back: set = field(default_factory=set)
    #: keys of branches with a point accepted by proof (see .certify) despite a tiny exclusion
    certified: set = field(default_factory=set)

    def copy(self, rng: np.random.Generator, *, fallback: "BranchSampler | None" = None):
        """This sampler drawing from ``rng``, with its own copies of the points it found and
        ``fallback`` in place of its own."""
        import copy

        new = copy.copy(self)
        new.rng = rng
        new.cache = dict(self.cache)
        new.closest = dict(self.closest)
        new.fell_back = set(self.fell_back)
        new.certified = set(self.certified)
        new._sub_eval = dict(self._sub_eval)
        new.fallback = fallback
        return new

    @functools.cached_property
    def _fixed(self) -> np.ndarray:
        """A generator row with the parameter values and the surds, zeros elsewhere."""
        ring = self.ring
        g = np.zeros(len(ring.names))
        base = 2 * ring.n_angles + len(ring.others)
        for j, p in enumerate(ring.params):
            g[base + j] = float(self.param_values.get(p, 0.0))
        if ring.surds:
            g[ring.surd_start:] = ring.surd_values
        return g

    def points(self, branch: Branch, count: int = 3) -> list[np.ndarray]:
        """Up to ``count`` generator vectors of real points of ``branch``."""
        key = branch.key + (count,)
        if key in self.cache:
            return self.cache[key]
        pts = self._solve(branch, count)
        if not pts and self.fallback is not None:
            # real points can exist for some parameter values only (a semi-algebraic
            # condition no zero test sees): the model's own values decide then
            pts = self.fallback.points(branch, count)
            if pts:
                self.fell_back.add(key)
        self.cache[key] = pts
        return pts

    def near_miss(self, branch: Branch, count: int = 3) -> bool:
        """Did the solve of a branch without points get close to a real point?

        Gauss-Newton converges only linearly to a point where the equations
        and their gradient vanish together (a real zero set of lower
        dimension than the equations suggest, like that of x**2 + y**2), and
        stops short of ROOT_XTOL there.
        """
        from ..tolerances import NEAR_MISS_RTOL

        key = branch.key + (count,)
        return self.closest.get(key, np.inf) <= NEAR_MISS_RTOL

    def coefficient_scaled_points(self, branch: Branch, starts: int = 12) -> list[np.ndarray]:
        """Generator vectors of real points of ``branch`` solved with coefficient-scaled residuals.

        :meth:`points` scales each equation by the size of its terms at the point.  That
        repels its solves from a piece on which every term of an equation vanishes on its own
        (there the scaled value stays of order one however close a point comes), and it
        missed the regular pieces of romeo_laas_small's 8-joint arm, where 60-digit
        coefficients cancel: none of 48 of its solves on a part {g = 0} of a leaf reached one,
        14 of 24 of these did (refined in 40 digits, J is regular there).  Here each equation
        is divided exactly by its largest coefficient, then by the sum of the absolute values
        of its coefficients (the scaling of ``rankloci check``); it is solved from ``starts``
        random starts of a stream of the branch's own, and a point is accepted when every
        scaled equation is below ROOT_XTOL and the exclusions are above EXCLUSION_RTOL of
        their terms.  Such a point can be a zero of the terms with the largest coefficients
        only (1e156 cos x sin x + cos x cos y + ...): it serves where a wrong point costs no
        soundness (finalize keeps an exclusion at a regular one; the component's closure is
        the same).
        """
        from ..tolerances import EXCLUSION_RTOL, ROOT_XTOL

        eqs = list(branch.implicit)
        angles, others, params = self.unknowns(branch)
        n_x = len(angles) + len(others) + len(params)
        if not eqs or not n_x:
            return []
        # divided by the largest coefficient exactly first: coefficients of 300 digits are
        # past the range of a float
        eqs = [q / max(abs(c) for c in q.coeffs()) for q in eqs]
        values = self.ring.compile(eqs)
        scale = self.ring.compile(eqs, absolute=True)(np.ones((1, len(self.ring.names))))[0]

        def residual(X):
            G = self.generators_batch(branch, angles, others, params, X)
            R = values(G) / scale
            R[np.isnan(G).any(axis=1)] = 1e3
            return R

        rng = np.random.default_rng(len(branch.conditions) + 3)
        X0 = np.concatenate([rng.uniform(-np.pi, np.pi, (starts, len(angles))),
                             rng.uniform(-2.0, 2.0, (starts, len(others) + len(params)))], axis=1)
        with np.errstate(all="ignore"):
            X = gauss_newton_rows(residual, X0)
            G = self.generators_batch(branch, angles, others, params, X)
            ok = ~np.isnan(G).any(axis=1) & (np.max(np.abs(residual(X)), axis=1) <= ROOT_XTOL)
            if branch.nonzero and ok.any():
                V, S = self.ring.compile(list(branch.nonzero), sized=True)(G)
                ok &= np.min(np.abs(V) / np.maximum(S, 1e-300), axis=1) > EXCLUSION_RTOL
        return list(G[ok])

    def unknowns(self, branch: Branch):
        """Which angles, other variables and parameters are free to vary."""
        ring = self.ring
        na = ring.n_angles
        solved_angles = {s.index for s in branch.substitutions if s.kind != "linear"}
        solved_gens = {s.index for s in branch.substitutions if s.kind == "linear"}
        angles = [i for i in range(na) if i not in solved_angles]
        n_other = len(ring.others)
        others = [2 * na + j for j in range(n_other) if 2 * na + j not in solved_gens]
        param_gens = [2 * na + n_other + j for j in range(len(ring.params))]
        joint_gens = set(range(2 * na + n_other))
        free_params = set()
        for c in branch.conditions:
            used = ring.variable_indices(c)
            if not used & joint_gens:
                free_params |= used
        free_params -= solved_gens
        params = [g for g in param_gens if g in free_params]
        return angles, others, params

    def generators_batch(self, branch: Branch, angles, others, params, X):
        """Generator vectors (rows) from rows of free unknowns; NaN rows where undefined."""
        ring = self.ring
        X = np.asarray(X, dtype=float)
        # the fixed generators (parameters, surds), then the free unknowns in column blocks
        G = np.repeat(self._fixed[None, :], len(X), axis=0)
        na, no = len(angles), len(others)
        if na:
            cols = 2 * np.asarray(angles, dtype=np.int64)
            half = X[:, :na] / 2
            G[:, cols], G[:, cols + 1] = np.cos(half), np.sin(half)
        if no:
            G[:, list(others)] = X[:, na:na + no]
        if params:
            G[:, list(params)] = X[:, na + no:na + no + len(params)]
        # substitutions, last first: each expresses generators in later-solved ones
        for sub in reversed(branch.substitutions):
            got = self._sub_eval.get(id(sub))
            if got is None or got[0] is not sub:
                got = (sub, _substitution_evaluator(ring, sub))
                self._sub_eval[id(sub)] = got
            if isinstance(got[1], tuple):
                # constant values (q = 0, q = pi, x = c): the columns are set, nothing evaluated
                # (on panda's finger chain half of all evaluator calls were such constants)
                for col, v in got[1]:
                    G[:, col] = v
                continue
            vals = got[1](G)
            if sub.kind == "linear":
                G[:, sub.index] = vals[:, 0]
            else:
                norm = np.hypot(vals[:, 0], vals[:, 1])
                with np.errstate(invalid="ignore", divide="ignore"):
                    G[:, 2 * sub.index] = np.where(norm > 0, vals[:, 0] / norm, np.nan)
                    G[:, 2 * sub.index + 1] = np.where(norm > 0, vals[:, 1] / norm, np.nan)
        return G

    def _certified(self, branch: Branch, g, angles, others, params):
        """The generator row of a proved point of ``branch`` next to ``g`` (see .certify), or None."""
        movable = [k for i in angles for k in (2 * i, 2 * i + 1)] + list(others) + list(params)
        got = certified_point(self.ring, branch, g, movable)
        if got is None:
            return None
        x = [2 * np.arctan2(got[2 * i + 1], got[2 * i]) for i in angles]
        x += [got[j] for j in others] + [got[j] for j in params]
        row = self.generators_batch(branch, angles, others, params, np.array([x]))[0]
        self.certified.add(branch.key)
        return None if np.isnan(row).any() else row

    def _solve(self, branch: Branch, count: int):
        from ..tolerances import EXCLUSION_CERTIFY_RTOL, EXCLUSION_RTOL, ROOT_XTOL

        angles, others, params = self.unknowns(branch)
        eqs = list(branch.implicit)
        sized = self.ring.compile(eqs, sized=True) if eqs else None
        nz = list(branch.nonzero)
        nz_sized = self.ring.compile(nz, sized=True) if nz else None
        n_x = len(angles) + len(others) + len(params)
        found = []

        def relative(G):
            values, sizes = sized(G)
            return values / np.maximum(sizes, 1e-300)

        def relative_nonzero(G):
            values, sizes = nz_sized(G)
            return values / np.maximum(sizes, 1e-300)

        def residual(X):
            """Residual rows of the unknown rows X (the last columns are Rabinowitsch's t)."""
            G = self.generators_batch(branch, angles, others, params, X[:, :n_x])
            parts = []
            if eqs:
                parts.append(relative(G))
            if X.shape[1] > n_x:
                # Rabinowitsch: t * e(q) = 1 keeps e away from zero
                parts.append(relative_nonzero(G) * X[:, n_x:] - 1.0)
            R = np.concatenate(parts, axis=1)
            R[np.isnan(G).any(axis=1)] = 1e3
            return R

        def accepted(X):
            """Generator rows of the solved unknown rows X, NaN rows where not accepted."""
            G = self.generators_batch(branch, angles, others, params, X[:, :n_x])
            bad = np.isnan(G).any(axis=1)
            if eqs:
                R = relative(G)
                bad |= ~(np.max(np.abs(R), axis=1) <= ROOT_XTOL)
            if nz:
                near = np.min(np.abs(relative_nonzero(G)), axis=1)
                small = ~bad & (near > EXCLUSION_CERTIFY_RTOL) & ~(near > EXCLUSION_RTOL)
                bad |= ~(near > EXCLUSION_RTOL)
                for r in np.flatnonzero(small)[:CERTIFY_ROWS]:
                    # an exclusion small against its terms: accepted when an exact point of
                    # the branch next to this one provably keeps it nonzero
                    got = self._certified(branch, G[r], angles, others, params)
                    if got is not None:
                        G[r], bad[r] = got, False
            G[bad] = np.nan
            return G

        starts = self.n_starts if (eqs or nz) else count
        chunk = 8 if (eqs or nz) else count
        done = 0
        while done < starts and len(found) < count:
            size = min(chunk, starts - done)
            done += size
            X0 = np.concatenate([
                self.rng.uniform(-np.pi, np.pi, (size, len(angles))),
                self.rng.uniform(-2.0, 2.0, (size, len(others))),
                self.rng.uniform(-2.0, 2.0, (size, len(params))),
            ], axis=1)
            X = gauss_newton_rows(residual, X0) if eqs else X0
            G = accepted(X)
            if eqs:
                # how close the solves came, among rows not rejected for an exclusion
                Gx = self.generators_batch(branch, angles, others, params, X[:, :n_x])
                R = np.abs(residual(X[:, :n_x]))
                fine = ~np.isnan(Gx).any(axis=1)
                if nz:
                    with np.errstate(invalid="ignore"):
                        fine &= np.min(np.abs(relative_nonzero(Gx)), axis=1) > EXCLUSION_RTOL
                best = float(np.min(np.max(R[fine], axis=1))) if fine.any() and R.shape[1] else np.inf
                key = branch.key + (count,)
                self.closest[key] = min(self.closest.get(key, np.inf), best)
            retry = np.isnan(G).any(axis=1)
            if nz and eqs and retry.any():
                # a plain solve that landed in the excluded set: solve again, kept away from it
                G0 = self.generators_batch(branch, angles, others, params, X0[retry])
                V0 = np.nan_to_num(relative_nonzero(G0), nan=1.0)
                T0 = 1.0 / np.where(np.abs(V0) > 1e-3, V0, 1e-3)
                G[retry] = accepted(gauss_newton_rows(residual, np.concatenate([X0[retry], T0], axis=1)))
            for g in G:
                if not np.isnan(g).any() and len(found) < count:
                    found.append(g)
        return found


def _substitution_evaluator(ring: PolyRing, sub):
    """How :meth:`BranchSampler.generators_batch` applies ``sub``: the compiled evaluator of its
    values, or, when they are constants, the (column, value) pairs it sets."""
    if not all(v.is_constant() for v in sub.values):
        return ring.compile(list(sub.values))
    vals = [float(v.leading_coefficient()) if not v.is_zero() else 0.0 for v in sub.values]
    if sub.kind == "linear":
        return ((sub.index, vals[0]),)
    norm = np.hypot(vals[0], vals[1])
    c, s = (vals[0] / norm, vals[1] / norm) if norm > 0 else (np.nan, np.nan)
    return ((2 * sub.index, c), (2 * sub.index + 1, s))
