"""Branches of a locus computation: sets cut out by polynomial conditions.

A :class:`Branch` is the set of configurations where a list of polynomial
conditions vanish.  A condition that can be solved for one unknown is
*substituted* (the matrices shrink); the others are carried as implicit
equations.  Solvable conditions are

- ``S`` (q = 0) and ``C`` (q = pi) of an angle pair;
- ``a*C + b*S`` with ``a``, ``b`` free of that pair: (C, S) is proportional
  to (b, -a), valid where (a, b) != (0, 0); the points where both vanish
  form a separate branch;
- ``c*x + r`` with a nonzero rational ``c`` for a polynomial variable or a
  parameter ``x``.

Everything that needs a *point* of a branch (is it empty, what is the
generic rank of a matrix on it, does a polynomial vanish on it) uses
:class:`BranchSampler`: real points found by least squares from random
starts.  A point is accepted when every condition is below
``ROOT_XTOL`` relative to the size of its terms.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field

import numpy as np

from .algebra import PolyRing, abs_poly

__all__ = ["Branch", "Substitution", "solve_condition"]


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
        if g < 2 * na:
            continue
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
    if best is not None:
        _, i, a, b = best
        return Substitution("pair", i, (b, -a)), [[a, b]]
    return None, []


def apply_substitution(p, sub: Substitution, ring: PolyRing):
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
    return p.compose(*vals)


# --- numeric points of a branch ---------------------------------------------

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
        from .tolerances import NEAR_MISS_RTOL

        key = branch.key + (count,)
        return self.closest.get(key, np.inf) <= NEAR_MISS_RTOL

    def _unknowns(self, branch: Branch):
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

    def generators(self, branch: Branch, angles, others, params, x):
        """Full generator vector from the free unknowns ``x``, or None."""
        g = self.generators_batch(branch, angles, others, params, np.asarray(x)[None, :])[0]
        return None if np.isnan(g).any() else g

    def generators_batch(self, branch: Branch, angles, others, params, X):
        """Generator vectors (rows) from rows of free unknowns; NaN rows where undefined."""
        ring = self.ring
        na = ring.n_angles
        X = np.asarray(X, dtype=float)
        G = np.zeros((len(X), len(ring.names)))
        k = 0
        for i in angles:
            G[:, 2 * i], G[:, 2 * i + 1] = np.cos(X[:, k] / 2), np.sin(X[:, k] / 2)
            k += 1
        for j in others:
            G[:, j] = X[:, k]
            k += 1
        base = 2 * na + len(ring.others)
        for j, p in enumerate(ring.params):
            G[:, base + j] = float(self.param_values.get(p, 0.0))
        for j in params:
            G[:, j] = X[:, k]
            k += 1
        # substitutions, last first: each expresses generators in later-solved ones
        for sub in reversed(branch.substitutions):
            got = self._sub_eval.get(id(sub))
            if got is None or got[0] is not sub:
                got = (sub, ring.compile(list(sub.values)))
                self._sub_eval[id(sub)] = got
            vals = got[1](G)
            if sub.kind == "linear":
                G[:, sub.index] = vals[:, 0]
            else:
                norm = np.hypot(vals[:, 0], vals[:, 1])
                with np.errstate(invalid="ignore", divide="ignore"):
                    G[:, 2 * sub.index] = np.where(norm > 0, vals[:, 0] / norm, np.nan)
                    G[:, 2 * sub.index + 1] = np.where(norm > 0, vals[:, 1] / norm, np.nan)
        return G

    def _solve(self, branch: Branch, count: int):
        from .tolerances import EXCLUSION_RTOL, ROOT_XTOL

        angles, others, params = self._unknowns(branch)
        eqs = list(branch.implicit)
        ev = self.ring.compile(eqs) if eqs else None
        scale_ev = self.ring.compile([abs_poly(e, self.ring) for e in eqs]) if eqs else None
        nz = list(branch.nonzero)
        nz_ev = self.ring.compile(nz) if nz else None
        nz_scale = self.ring.compile([abs_poly(e, self.ring) for e in nz]) if nz else None
        n_x = len(angles) + len(others) + len(params)
        found = []

        def relative_nonzero(G):
            return nz_ev(G) / np.maximum(nz_scale(np.abs(G)), 1e-300)

        def residual(X):
            """Residual rows of the unknown rows X (the last columns are Rabinowitsch's t)."""
            G = self.generators_batch(branch, angles, others, params, X[:, :n_x])
            parts = []
            if eqs:
                parts.append(ev(G) / np.maximum(scale_ev(np.abs(G)), 1e-300))
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
                R = ev(G) / np.maximum(scale_ev(np.abs(G)), 1e-300)
                bad |= ~(np.max(np.abs(R), axis=1) <= ROOT_XTOL)
            if nz:
                bad |= ~(np.min(np.abs(relative_nonzero(G)), axis=1) > EXCLUSION_RTOL)
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


def gauss_newton(residual, x0, *, max_iter: int = 60, h: float = 1e-7):
    """:func:`gauss_newton_rows` from one start; returns the final point or None."""
    x = gauss_newton_rows(residual, np.asarray(x0, dtype=float)[None, :], max_iter=max_iter, h=h)[0]
    return x if np.all(np.isfinite(x)) else None


def gauss_newton_rows(residual, X0, *, max_iter: int = 60, h: float = 1e-7):
    """Minimum-norm Gauss-Newton from several starts at once (the rows of ``X0``).

    ``residual`` maps rows of unknowns (shape (B, n)) to rows of residuals,
    so that every start, and every column of the forward-difference
    Jacobians, is evaluated in one call.  Each step solves J dx = -r in the
    least-squares, minimum-norm sense, with step halving while the residual
    grows.  A start stops when its residual is below 1e-14, when a step
    cannot reduce it, or when it has not halved in 8 steps (no convergence
    in sight).  Returns the final rows (NaN where not finite).
    """
    X = np.array(X0, dtype=float)
    S, n = X.shape
    if n == 0:
        return X           # nothing left to move: the caller checks the residual
    R = residual(X)
    norm = np.linalg.norm(R, axis=1)
    norm[~np.isfinite(norm)] = np.inf
    active = np.isfinite(norm)
    shifts = np.vstack([np.zeros(n), h * np.eye(n)])
    history = [norm.copy()]
    for it in range(max_iter):
        active &= norm >= 1e-14
        if it >= 8:
            active &= norm <= 0.5 * history[it - 8]
        if not active.any():
            break
        idx = np.flatnonzero(active)
        P = (X[idx, None, :] + shifts[None, :, :]).reshape(-1, n)
        RR = residual(P).reshape(len(idx), n + 1, -1)
        J = np.transpose((RR[:, 1:, :] - RR[:, :1, :]) / h, (0, 2, 1))
        if not np.all(np.isfinite(J)):
            ok = np.all(np.isfinite(J), axis=(1, 2))
            active[idx[~ok]] = False
            idx, J = idx[ok], J[ok]
            if not len(idx):
                continue
        dX = -np.einsum("anm,am->an", np.linalg.pinv(J), R[idx])
        step = np.ones(len(idx))
        pending = np.ones(len(idx), dtype=bool)
        while pending.any():
            k = np.flatnonzero(pending)
            Xn = X[idx[k]] + step[k, None] * dX[k]
            Rn = residual(Xn)
            nn = np.linalg.norm(Rn, axis=1)
            better = np.isfinite(nn) & (nn < norm[idx[k]])
            rows = idx[k[better]]
            X[rows], R[rows], norm[rows] = Xn[better], Rn[better], nn[better]
            pending[k[better]] = False
            step[k[~better]] /= 2
            stuck = k[~better][step[k[~better]] <= 1e-4]
            pending[stuck] = False
            active[idx[stuck]] = False
        history.append(norm.copy())
    return X
