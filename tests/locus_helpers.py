"""Numeric tools shared by the locus tests: cached loci, J(q), sigma ratios, points on components.

Everything here is independent of the locus engine except :func:`locus_of`, which calls it
(once per model, method and seed per test session: a locus is frozen, so sharing it is safe).
"""

from __future__ import annotations

import functools

import numpy as np
import sympy as sp
from scipy.optimize import least_squares, minimize

from rankloci.io import load_model
from rankloci.io.toml_model import parse_model
from rankloci.jacobians import task_matrix
from rankloci.methods import compute_locus
from rankloci.tolerances import EXCLUSION_RTOL, RANK_RTOL

#: A point found by least squares counts as on a component when every equation, divided by the
#: sum of the absolute values of its coefficients (so a trig polynomial is at most 1 on the
#: torus), is at most this.  Newton-type solves reach ~1e-15; this leaves four orders of margin.
ROOT_RESIDUAL = 1e-11


# --- building and caching -------------------------------------------------------------------

@functools.lru_cache(maxsize=None)
def model_tm(name: str, numeric: bool):
    """Task matrix of a built-in model (or a path), with the CLI's frame choice."""
    return task_matrix(load_model(name), frame="auto", numeric=numeric)


@functools.lru_cache(maxsize=None)
def raw_tm(text: str):
    """Task matrix of a raw-matrix TOML text."""
    return task_matrix(parse_model(text, name="raw"), frame="auto")


def raw_context(text: str):
    """A fresh tree :class:`~rankloci.tree.context.Context` of a raw-matrix TOML text, and the
    index of each angle in its ring by name."""
    from rankloci.tree.context import Context

    ctx = Context(raw_tm(text), method="svm", rng=np.random.default_rng(0))
    return ctx, {v.name: i for i, v in enumerate(ctx.ring.angles)}


@functools.lru_cache(maxsize=None)
def _locus(key, method: str, seed: int):
    kind, spec, numeric = key
    tm = model_tm(spec, numeric) if kind == "model" else raw_tm(spec)
    return tm, compute_locus(tm, method, rng=np.random.default_rng(seed))


def locus_of(name: str, numeric: bool = True, method: str = "svm", seed: int = 0):
    """(TaskMatrix, Locus) of a built-in model, computed once per session."""
    return _locus(("model", name, numeric), method, seed)


def raw_locus(text: str, method: str = "svm", seed: int = 0):
    """(TaskMatrix, Locus) of a raw-matrix TOML text, computed once per session."""
    return _locus(("raw", text, False), method, seed)


def model_components(locus):
    """The components that exist for the model's own parameter values."""
    return [c for c in locus.components if c.for_model]


# --- numeric J ------------------------------------------------------------------------------

class NumericJ:
    """J(q) and dJ/dq_k(q) as numpy functions, parameters replaced by the model's values."""

    def __init__(self, tm):
        self.tm = tm
        self.variables = tuple(tm.variables)
        M = sp.Matrix(tm.matrix.subs(tm.parameters))
        self.shape = M.shape
        self._J = sp.lambdify(self.variables, M, modules="numpy")
        self._dJ = [sp.lambdify(self.variables, M.diff(v), modules="numpy") for v in self.variables]

    def __call__(self, q) -> np.ndarray:
        return np.array(self._J(*q), dtype=float).reshape(self.shape)

    def derivatives(self, q) -> list[np.ndarray]:
        return [np.array(d(*q), dtype=float).reshape(self.shape) for d in self._dJ]


_NUMERIC_J: dict[int, tuple] = {}


def numeric_j(tm) -> NumericJ:
    """NumericJ of a task matrix, built once per matrix object (TaskMatrix is not hashable)."""
    got = _NUMERIC_J.get(id(tm))
    if got is None or got[0] is not tm:
        got = _NUMERIC_J[id(tm)] = (tm, NumericJ(tm))
    return got[1]


def singular_values(J: np.ndarray) -> np.ndarray:
    return np.linalg.svd(J, compute_uv=False)


def sigma_ratio(J: np.ndarray) -> float:
    """sigma_min / sigma_max (0 for a zero matrix)."""
    s = singular_values(J)
    return float(s[-1] / s[0]) if s[0] > 0 else 0.0


def numeric_rank_drop(J: np.ndarray, rtol: float = RANK_RTOL) -> int:
    """min(rows, cols) minus the number of singular values above rtol * sigma_max."""
    s = singular_values(J)
    if s[0] == 0:
        return len(s)
    return int(np.sum(s <= rtol * s[0]))


def random_q(tm, rng) -> np.ndarray:
    """A random configuration: angles uniform in [-pi, pi), other variables normal."""
    angles = set(tm.angles)
    return np.array([rng.uniform(-np.pi, np.pi) if v in angles else rng.normal()
                     for v in tm.variables])


def minimise_sigma_ratio(nj: NumericJ, q0) -> tuple[np.ndarray, float]:
    """Local minimum of (sigma_min/sigma_max)^2 from q0 (BFGS, analytic gradient).

    d sigma_i = u_i^T dJ v_i for a simple singular value; (sigma_min/sigma_max)^2 is smooth
    where sigma_min and sigma_max are simple, including where sigma_min crosses zero.
    """

    def f(q):
        J = nj(q)
        U, s, Vt = np.linalg.svd(J, full_matrices=False)
        if s[0] == 0:
            return 0.0, np.zeros_like(q)
        r = s[-1] / s[0]
        grad = np.empty(len(q))
        for k, dJ in enumerate(nj.derivatives(q)):
            ds_min = U[:, -1] @ dJ @ Vt[-1]
            ds_max = U[:, 0] @ dJ @ Vt[0]
            grad[k] = 2 * r * (ds_min * s[0] - s[-1] * ds_max) / s[0] ** 2
        return r * r, grad

    res = minimize(f, q0, jac=True, method="BFGS", options={"gtol": 1e-20, "maxiter": 400})
    return res.x, sigma_ratio(nj(res.x))


# --- component equations --------------------------------------------------------------------

class ComponentEquations:
    """The equations of a component as a numpy function of the joint variables, each divided
    by the sum of the absolute values of its coefficients (parameters substituted)."""

    def __init__(self, comp, tm, params=None):
        params = dict(tm.parameters if params is None else params)
        self.comp = comp
        self.variables = tuple(tm.variables)
        exprs = [sp.expand(sp.sympify(e).subs(params)) for e in comp.equations]
        self.exprs = exprs
        self.scales = np.array([_coefficient_norm(e) for e in exprs], dtype=float)
        self._f = sp.lambdify(self.variables, exprs, modules="numpy") if exprs else None
        excl = [sp.expand(sp.sympify(e).subs(params)) for e in getattr(comp, "excluding", ())]
        self.excl_scales = np.array([_coefficient_norm(e) for e in excl], dtype=float)
        self._g = sp.lambdify(self.variables, excl, modules="numpy") if excl else None

    def excluded(self, q) -> np.ndarray:
        """The component's excluded expressions at q, scaled like the equations."""
        if self._g is None:
            return np.zeros(0)
        return np.array(self._g(*q), dtype=float).reshape(-1) / self.excl_scales

    def admits(self, q) -> bool:
        """Is q away from every excluded set (by more than EXCLUSION_RTOL)?"""
        v = self.excluded(q)
        return not v.size or float(np.min(np.abs(v))) > EXCLUSION_RTOL

    def __call__(self, q) -> np.ndarray:
        if self._f is None:
            return np.zeros(0)
        return np.array(self._f(*q), dtype=float).reshape(-1) / self.scales

    def residual(self, q) -> float:
        """Largest scaled |equation| at q (0 when there is no equation)."""
        v = self(q)
        return float(np.max(np.abs(v))) if v.size else 0.0


def _coefficient_norm(e) -> float:
    total = sum(abs(float(t.as_coeff_Mul()[0])) for t in sp.Add.make_args(e))
    return total if total > 0 else 1.0


def points_on(eqs: ComponentEquations, tm, rng, n: int, *, tries: int = 40) -> list[np.ndarray]:
    """Up to n points where the equations vanish, from random starts (least squares).

    Returns fewer than n points only if fewer than n of ``tries`` starts converge.
    A component with exclusions (``comp.excluding``) is the closure of the set where its
    equations vanish and the exclusions do not; a start that lands in an excluded set is
    solved again with one more unknown t per exclusion e and the equation t * e = 1.
    """
    out = []
    if eqs._f is None:
        return [random_q(tm, rng) for _ in range(n)]
    opts = dict(method="trf", xtol=1e-15, ftol=1e-15, gtol=1e-15)
    for _ in range(tries):
        q0 = random_q(tm, rng)
        q = least_squares(eqs, q0, max_nfev=200 * len(q0), **opts).x
        if eqs.residual(q) <= ROOT_RESIDUAL and not eqs.admits(q):
            m = len(q0)
            t0 = 1.0 / np.clip(np.abs(eqs.excluded(q0)), 1e-3, None)

            def lifted(x, m=m):
                return np.concatenate([eqs(x[:m]), eqs.excluded(x[:m]) * x[m:] - 1.0])

            q = least_squares(lifted, np.concatenate([q0, t0]), **opts).x[:m]
        if eqs.residual(q) <= ROOT_RESIDUAL and eqs.admits(q):
            out.append(q)
            if len(out) == n:
                break
    return out


def sample_point(comp, tm) -> np.ndarray:
    """The component's own sample point as a vector in tm.variables order."""
    return np.array([comp.sample[str(v)] for v in tm.variables], dtype=float)


def fmt(q, names) -> str:
    return "(" + ", ".join(f"{n}={x:+.6f}" for n, x in zip(names, q)) + ")"


def describe(comp) -> str:
    eqs = ", ".join(f"{sp.sstr(e)} = 0" for e in comp.equations) or "(no equation)"
    return f"{{{eqs}}} (dimension {comp.dimension}, rank drop {comp.rank_drop})"
