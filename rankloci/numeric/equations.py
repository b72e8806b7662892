"""Numeric functions of a locus: J(q) and a component's equations, lambdified once.

:class:`NumericMatrix` evaluates J and its derivatives at configurations;
:class:`Equations` evaluates a component's equations, each scaled by the
size of its coefficients; :func:`points_on` solves points onto them, and
:func:`minimise_ratio` walks to a local minimum of sigma_min/sigma_max.
"""

from __future__ import annotations

import numpy as np
import sympy as sp

from ..tolerances import EXCLUSION_RTOL, ON_COMPONENT_RESIDUAL

__all__ = ["NumericMatrix", "Equations", "normalised", "coefficient_norm", "points_on", "minimise_ratio",
           "descend_to_singular", "ratio_and_gradient", "MAX_TRIES"]

#: Random starts per requested point (root finding, off-locus draws).
MAX_TRIES = 40


class NumericMatrix:
    """J(q) and its derivatives as numpy functions, lambdified once, evaluated in batches."""

    def __init__(self, matrix, variables, angles=()):
        M = sp.Matrix(matrix)
        self.shape = M.shape
        self.variables = tuple(variables)
        self.angles = frozenset(angles)
        self._J = sp.lambdify(self.variables, list(M), modules="numpy")
        self._dJ = sp.lambdify(self.variables, [list(M.diff(v)) for v in self.variables],
                               modules="numpy")

    def batch(self, Q) -> np.ndarray:
        """J at each row of Q (shape (N, n)): an array of shape (N, rows, cols)."""
        Q = np.atleast_2d(np.asarray(Q, dtype=float))
        vals = self._J(*Q.T)
        N = Q.shape[0]
        return np.stack([np.broadcast_to(np.asarray(v, dtype=float), (N,)) for v in vals],
                        axis=-1).reshape((N,) + self.shape)

    def __call__(self, q) -> np.ndarray:
        return self.batch(np.asarray(q, dtype=float)[None, :])[0]

    def derivatives(self, q) -> np.ndarray:
        """dJ/dq_k at q: shape (n, rows, cols)."""
        vals = self._dJ(*np.asarray(q, dtype=float))
        return np.array([[float(x) for x in row] for row in vals]).reshape((-1,) + self.shape)

    def random_q(self, rng, n: int) -> np.ndarray:
        """n random configurations: angles uniform in [-pi, pi), other variables normal."""
        cols = [rng.uniform(-np.pi, np.pi, n) if v in self.angles else rng.normal(size=n)
                for v in self.variables]
        return np.stack(cols, axis=-1) if cols else np.zeros((n, 0))


class Equations:
    """A component's equations as a scaled numpy function of the joint variables."""

    def __init__(self, equations, variables, parameters, excluding=()):
        exprs = [normalised(sp.expand(sp.sympify(e).subs(parameters))) for e in equations]
        self.scales = np.array([coefficient_norm(e) for e in exprs], dtype=float)
        self._f = sp.lambdify(tuple(variables), exprs, modules="numpy") if exprs else None
        excl = [normalised(sp.expand(sp.sympify(e).subs(parameters))) for e in excluding]
        self.excl_scales = np.array([coefficient_norm(e) for e in excl], dtype=float)
        self._g = sp.lambdify(tuple(variables), excl, modules="numpy") if excl else None

    def excluded_values(self, q) -> np.ndarray:
        """The excluded expressions at q, each divided by its coefficient norm."""
        if self._g is None:
            return np.zeros(0)
        return np.array(self._g(*q), dtype=float).reshape(-1) / self.excl_scales

    def admits(self, q) -> bool:
        """Is q outside the excluded sets (see EXCLUSION_RTOL)?"""
        v = self.excluded_values(q)
        return not v.size or float(np.min(np.abs(v))) > EXCLUSION_RTOL

    @property
    def empty(self) -> bool:
        """No equations: every configuration satisfies them."""
        return self._f is None

    def batch(self, Q) -> np.ndarray:
        """The scaled equations at every point of ``Q`` (last axis the variables).

        Returns an array of shape (number of equations,) + Q.shape[:-1].
        """
        Q = np.asarray(Q, dtype=float)
        if self._f is None:
            return np.zeros((0,) + Q.shape[:-1])
        raw = self._f(*np.moveaxis(Q, -1, 0))
        vals = np.stack([np.broadcast_to(np.asarray(v, dtype=float), Q.shape[:-1]) for v in raw])
        return vals / self.scales.reshape((-1,) + (1,) * (Q.ndim - 1))

    def __call__(self, q) -> np.ndarray:
        """The scaled equations at ``q``."""
        if self._f is None:
            return np.zeros(0)
        return np.array(self._f(*q), dtype=float).reshape(-1) / self.scales

    def residual(self, q) -> float:
        """The largest scaled equation at ``q`` in absolute value."""
        v = self(q)
        return float(np.max(np.abs(v))) if v.size else 0.0


def normalised(e):
    """``e`` divided by its largest coefficient in absolute value (exactly, when rational).

    Equations of URDF chains with rotations that do not snap carry integer
    coefficients of hundreds of digits, beyond the range of a float; divided by
    the largest, every coefficient is at most 1.

    Examples
    --------
    >>> x = sp.Symbol("x")
    >>> normalised(10**400 * x - 3 * 10**399)
    x - 3/10
    """
    coeffs = [t.as_coeff_Mul()[0] for t in sp.Add.make_args(e)]
    if not coeffs or not all(c.is_Rational for c in coeffs):
        return e
    big = max(abs(c) for c in coeffs)
    return sp.expand(e / big) if big not in (0, 1) else e


def coefficient_norm(e) -> float:
    """Sum of the absolute values of the coefficients of ``e`` (1 for zero)."""
    total = sum(abs(complex(t.as_coeff_Mul()[0])) for t in sp.Add.make_args(e))
    return float(total) if total > 0 else 1.0


def points_on(eqs: Equations, nm: NumericMatrix, rng, n: int) -> list:
    """Up to ``n`` points where the equations vanish and no exclusion does (least squares)."""
    from scipy.optimize import least_squares

    if eqs.empty:
        return list(nm.random_q(rng, n))
    out = []
    opts = dict(method="trf", xtol=1e-15, ftol=1e-15, gtol=1e-15)
    for q0 in nm.random_q(rng, MAX_TRIES * n):
        q = least_squares(eqs, q0, max_nfev=200 * len(q0), **opts).x
        if eqs.residual(q) <= ON_COMPONENT_RESIDUAL and not eqs.admits(q):
            # landed in an excluded set: solve again with t * e(q) = 1 (Rabinowitsch)
            m = len(q0)
            t0 = 1.0 / np.clip(np.abs(eqs.excluded_values(q0)), 1e-3, None)

            def lifted(x):
                return np.concatenate([eqs(x[:m]), eqs.excluded_values(x[:m]) * x[m:] - 1.0])

            q = least_squares(lifted, np.concatenate([q0, t0]), max_nfev=200 * (m + len(t0)),
                              **opts).x[:m]
        if eqs.residual(q) <= ON_COMPONENT_RESIDUAL and eqs.admits(q):
            out.append(q)
            if len(out) == n:
                break
    return out


def minimise_ratio(nm: NumericMatrix, q0):
    """Local minimum of (sigma_min/sigma_max)^2 from q0 (BFGS, analytic gradient)."""
    from scipy.optimize import minimize

    def f(q):
        U, s, Vt = np.linalg.svd(nm(q), full_matrices=False)
        if s[0] == 0:
            return 0.0, np.zeros_like(q)
        r = s[-1] / s[0]
        dJ = nm.derivatives(q)
        ds_min = np.einsum("i,kij,j->k", U[:, -1], dJ, Vt[-1])
        ds_max = np.einsum("i,kij,j->k", U[:, 0], dJ, Vt[0])
        return r * r, 2 * r * (ds_min * s[0] - s[-1] * ds_max) / s[0] ** 2

    res = minimize(f, q0, jac=True, method="BFGS", options={"gtol": 1e-20, "maxiter": 400})
    return res.x


def ratio_and_gradient(nm: NumericMatrix, q) -> tuple[float, np.ndarray]:
    """sigma_min/sigma_max of J(q) and its gradient in q."""
    U, s, Vt = np.linalg.svd(nm(q), full_matrices=False)
    if s[0] == 0:
        return 0.0, np.zeros_like(q)
    dJ = nm.derivatives(q)
    ds_min = np.einsum("i,kij,j->k", U[:, -1], dJ, Vt[-1])
    ds_max = np.einsum("i,kij,j->k", U[:, 0], dJ, Vt[0])
    return float(s[-1] / s[0]), (ds_min * s[0] - s[-1] * ds_max) / s[0] ** 2


def descend_to_singular(nm: NumericMatrix, q, *, steps: int = 60) -> tuple[np.ndarray, float]:
    """Newton steps on r = sigma_min/sigma_max from ``q``; the best point and its ratio.

    Near a rank-deficient configuration r grows like the distance to it, so
    the step r * grad r / |grad r|**2 lands on it and r falls to the
    rounding floor (~1e-15) in a few steps.  At a positive local minimum of
    r (a configuration that is only nearly singular) the gradient vanishes,
    the steps stop reducing r, and the ratio stays where it was.
    """
    q = np.asarray(q, dtype=float).copy()
    r, g = ratio_and_gradient(nm, q)
    for _ in range(steps):
        gg = float(g @ g)
        if r == 0.0 or gg == 0.0:
            break
        trial = q - r * g / gg
        rt, gt = ratio_and_gradient(nm, trial)
        if not rt < r / 1.5:
            break
        q, r, g = trial, rt, gt
    return q, r
