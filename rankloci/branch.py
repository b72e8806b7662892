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

    def with_condition(self, f, ring: PolyRing) -> tuple["Branch", list]:
        """This branch and ``f = 0``; also the extra conditions of its exceptional part.

        Returns the new branch and a list of condition lists, each one
        describing a piece of {f = 0} the substitution does not cover.
        """
        f = self.reduce(f, ring)
        sub, exceptional = solve_condition(f, ring)
        if sub is None:
            return Branch(self.conditions + (f,), self.substitutions, self.implicit + (f,)), []
        return Branch(self.conditions + (f,), self.substitutions + (sub,), self.implicit), exceptional

    def reduce(self, p, ring: PolyRing):
        """``p`` with this branch's substitutions applied."""
        for sub in self.substitutions:
            p = apply_substitution(p, sub, ring)
        return p

    def reduce_matrix(self, M, ring):
        return [[self.reduce(p, ring) for p in row] for row in M]


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

    def points(self, branch: Branch, count: int = 3) -> list[np.ndarray]:
        """Up to ``count`` generator vectors of real points of ``branch``."""
        key = (tuple(str(c) for c in branch.conditions), count)
        if key in self.cache:
            return self.cache[key]
        pts = self._solve(branch, count)
        self.cache[key] = pts
        return pts

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
        """Full generator vector from the free unknowns ``x``."""
        ring = self.ring
        na = ring.n_angles
        g = np.zeros(len(ring.names))
        k = 0
        for i in angles:
            g[2 * i], g[2 * i + 1] = np.cos(x[k] / 2), np.sin(x[k] / 2)
            k += 1
        for j in others:
            g[j] = x[k]
            k += 1
        pnames = [p for p in ring.params]
        for j, p in enumerate(pnames):
            g[2 * na + len(ring.others) + j] = float(self.param_values.get(p, 0.0))
        for j in params:
            g[j] = x[k]
            k += 1
        # substitutions, last first: each expresses generators in later-solved ones
        for sub in reversed(branch.substitutions):
            got = self._sub_eval.get(id(sub))
            if got is None or got[0] is not sub:
                got = (sub, ring.compile(list(sub.values)))
                self._sub_eval[id(sub)] = got
            vals = got[1](g)
            if sub.kind == "linear":
                g[sub.index] = vals[0]
            else:
                norm = np.hypot(vals[0], vals[1])
                if norm == 0:
                    return None
                g[2 * sub.index], g[2 * sub.index + 1] = vals[0] / norm, vals[1] / norm
        return g

    def _solve(self, branch: Branch, count: int):
        from .tolerances import ROOT_XTOL

        angles, others, params = self._unknowns(branch)
        eqs = list(branch.implicit)
        ev = self.ring.compile(eqs) if eqs else None
        scale_ev = self.ring.compile([abs_poly(e, self.ring) for e in eqs]) if eqs else None
        found = []

        def residual(x):
            g = self.generators(branch, angles, others, params, x)
            if g is None:
                return np.full(len(eqs), 1e3)
            vals = ev(g)
            sc = scale_ev(np.abs(g))
            return vals / np.maximum(sc, 1e-300)

        starts = self.n_starts if eqs else count
        for _ in range(starts):
            x0 = np.concatenate([
                self.rng.uniform(-np.pi, np.pi, len(angles)),
                self.rng.uniform(-2.0, 2.0, len(others)),
                self.rng.uniform(-2.0, 2.0, len(params)),
            ])
            if eqs:
                x = gauss_newton(residual, x0)
                if x is None or np.max(np.abs(residual(x))) > ROOT_XTOL:
                    continue
            else:
                x = x0
            g = self.generators(branch, angles, others, params, x)
            if g is None:
                continue
            found.append(g)
            if len(found) >= count:
                break
        return found


def gauss_newton(residual, x0, *, max_iter: int = 60, h: float = 1e-7):
    """Minimum-norm Gauss-Newton for an under- or well-determined system.

    Each step solves J dx = -r in the least-squares, minimum-norm sense
    (forward-difference J), with step halving when the residual grows.
    Returns the final point, or None if it is not finite.
    """
    x = np.array(x0, dtype=float)
    r = residual(x)
    norm = np.linalg.norm(r)
    for _ in range(max_iter):
        if norm < 1e-14:
            break
        J = np.empty((len(r), len(x)))
        for j in range(len(x)):
            xp = x.copy()
            xp[j] += h
            J[:, j] = (residual(xp) - r) / h
        dx = np.linalg.lstsq(J, -r, rcond=None)[0]
        step = 1.0
        while step > 1e-4:
            xn = x + step * dx
            rn = residual(xn)
            nn = np.linalg.norm(rn)
            if np.isfinite(nn) and nn < norm:
                break
            step /= 2
        else:
            return x if np.all(np.isfinite(x)) else None
        x, r, norm = xn, rn, nn
    return x if np.all(np.isfinite(x)) else None
