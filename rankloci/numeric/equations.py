"""Numeric functions of a locus: J(q) and a component's equations, lambdified once.

:class:`NumericMatrix` evaluates J and its derivatives at configurations;
:class:`Equations` evaluates a component's equations, each scaled by the
size of its coefficients; :func:`points_on` solves points onto them, and
:func:`minimise_ratio` walks to a local minimum of sigma_min/sigma_max.
"""

from __future__ import annotations

import functools

import numpy as np
import sympy as sp

from ..expr import as_expression
from ..tolerances import (COMPLEX_STEP, DIMENSION_RTOL, EQUATIONS_MAX_TRIES as MAX_TRIES,
                          EXCLUSION_RTOL, LEAST_SQUARES_TOL, ON_COMPONENT_RESIDUAL, SETTLED_ULPS,
                          STALL_ITERATIONS)
from .functions import numpy_function

__all__ = ["NumericMatrix", "Equations", "normalised", "dimension_from_gradient",
           "coefficient_norm", "minimum_norm_step", "points_on", "minimise_ratio",
           "descend_to_singular", "ratio_and_gradient", "is_analytic", "MAX_TRIES",
           "STALL_ITERATIONS", "REFINE_DIGITS", "REFINE_STEPS", "COMPLEX_STEP",
           "ANALYTIC_FUNCTIONS"]


#: Decimal digits and Newton steps of :meth:`Equations.refined`.  Near a point where the
#: component's equations have a multiple root, double-precision least squares stops at a scaled
#: residual of 1e-12 up to 0.03 rad away from the component (tiago_dual's left arm, a component
#: through q4 = pi/2, q5 = pi, q6 = 0), where J's sigma ratio is still 1e-7 to 1e-5.  Newton's
#: iteration converges linearly at a root of multiplicity k (the distance shrinks by (k - 1)/k a
#: step), so 200 steps bring a start 0.03 rad away from a root of multiplicity up to 8 within
#: 1e-10 of it; 50 digits keep the residual of such a point (its k-th power) far above rounding.
REFINE_DIGITS, REFINE_STEPS = 50, 200


#: Functions whose numpy versions are analytic where J is finite, so that the complex step
#: below differentiates them; any other function (Abs, sign, Max, Piecewise, floor, ...) sends
#: the matrix to the symbolic derivative.  Powers (sqrt included) are analytic away from 0.
ANALYTIC_FUNCTIONS = (sp.sin, sp.cos, sp.tan, sp.exp, sp.log, sp.sinh, sp.cosh, sp.tanh,
                      sp.asin, sp.acos, sp.atan)


def dimension_from_gradient(G) -> int:
    """Local dimension of a zero set, from its equations' gradient ``G`` at a point.

    ``G`` has one row per equation and one column per variable.  Equations differ in
    scale by orders of magnitude, so the rows are compared as directions (scaled to
    unit norm) and singular values at most DIMENSION_RTOL times the largest count as
    zero.  At a singular point of the zero set the gradient loses rank, and the
    count is an upper bound.

    Examples
    --------
    >>> dimension_from_gradient(np.array([[2.0, 0.0, 0.0], [1e-9, 0.0, 0.0]]))
    2
    >>> dimension_from_gradient(np.zeros((1, 3)))
    3
    """
    G = np.atleast_2d(np.asarray(G, dtype=float))
    norms = np.linalg.norm(G, axis=1)
    G = G[norms > 0] / norms[norms > 0, None]
    if not len(G):
        return G.shape[1]
    s = np.linalg.svd(G, compute_uv=False)
    return G.shape[1] - int(np.sum(s > DIMENSION_RTOL * s[0]))


def is_analytic(expressions) -> bool:
    """Are ``expressions`` built from rationals, symbols, powers and :data:`ANALYTIC_FUNCTIONS`?

    Examples
    --------
    >>> x = sp.Symbol("x")
    >>> is_analytic([sp.sin(x) * sp.sqrt(1 + x**2)]), is_analytic([sp.Abs(x)])
    (True, False)
    """
    ok = (sp.Symbol, sp.Number, sp.NumberSymbol, sp.Add, sp.Mul, sp.Pow) + ANALYTIC_FUNCTIONS
    return all(isinstance(node, ok) for e in expressions
               for node in sp.preorder_traversal(as_expression(e)))


class NumericMatrix:
    """J(q) and its derivatives as numpy functions, lambdified once, evaluated in batches.

    The derivatives dJ/dq_k come from the complex step, Im J(q + i h e_k) / h,
    when every entry is analytic (:func:`is_analytic`): no subtraction, so they
    are exact to rounding, at the cost of one batched complex evaluation of J.
    Other matrices get the symbolic derivative, lambdified when first needed.
    """

    def __init__(self, matrix, variables, angles=()):
        M = sp.Matrix(matrix)
        self.shape = M.shape
        self.variables = tuple(variables)
        self.angles = frozenset(angles)
        self._J = numpy_function(self.variables, list(M), cse=True)
        self.complex_step = is_analytic(M)
        self._matrix = M
        self._dJ = self._Jmp = None
        self._typical = None

    def _values(self, Q, dtype) -> np.ndarray:
        vals = self._J(*Q.T)
        N = Q.shape[0]
        return np.stack([np.broadcast_to(np.asarray(v, dtype=dtype), (N,)) for v in vals],
                        axis=-1).reshape((N,) + self.shape)

    def batch(self, Q) -> np.ndarray:
        """J at each row of Q (shape (N, n)): an array of shape (N, rows, cols)."""
        return self._values(np.atleast_2d(np.asarray(Q, dtype=float)), float)

    def __call__(self, q) -> np.ndarray:
        return self.batch(np.asarray(q, dtype=float)[None, :])[0]

    def typical_scale(self) -> float:
        """The median largest singular value of J over 16 random configurations (a fixed
        seed, angles and other variables uniform in [-pi, pi]): the matrix's own size."""
        if getattr(self, "_typical", None) is None:
            Q = np.random.default_rng(0).uniform(-np.pi, np.pi, (16, len(self.variables)))
            with np.errstate(all="ignore"):
                s = np.linalg.svd(self.batch(Q), compute_uv=False)[..., 0]
            s = s[np.isfinite(s)]
            self._typical = float(np.median(s)) if s.size else 0.0
        return self._typical

    def derivatives(self, q) -> np.ndarray:
        """dJ/dq_k at q: shape (n, rows, cols)."""
        q = np.asarray(q, dtype=float)
        if self.complex_step:
            n = len(q)
            Q = q[None, :] + 1j * COMPLEX_STEP * np.eye(n)
            return self._values(Q, complex).imag / COMPLEX_STEP
        if self._dJ is None:
            flat = [e for v in self.variables for e in self._matrix.diff(v)]
            n_entries = len(self._matrix)
            derivatives = numpy_function(self.variables, flat)

            def nested(*q, f=derivatives, k=n_entries):
                vals = f(*q)
                return [vals[i:i + k] for i in range(0, len(vals), k)]

            self._dJ = nested
        vals = self._dJ(*q)
        return np.array([[float(x) for x in row] for row in vals]).reshape((-1,) + self.shape)

    def precise_ratio(self, x, digits: int):
        """sigma_min / sigma_max of J at the mpmath point ``x``, evaluated in ``digits`` digits
        (an mpmath number; 0 for a zero matrix)."""
        import mpmath

        if self._Jmp is None:
            self._Jmp = numpy_function(self.variables, list(self._matrix), modules="mpmath",
                                       cse=True)
        with mpmath.workdps(digits):
            rows, cols = self.shape
            vals = self._Jmp(*x)
            A = mpmath.matrix([[vals[i * cols + j] for j in range(cols)] for i in range(rows)])
            s = [abs(v) for v in mpmath.svd_r(A, compute_uv=False)]
            top = max(s)
            return min(s) / top if top else mpmath.mpf(0)

    def random_q(self, rng, n: int) -> np.ndarray:
        """n random configurations: angles uniform in [-pi, pi), other variables normal."""
        cols = [rng.uniform(-np.pi, np.pi, n) if v in self.angles else rng.normal(size=n)
                for v in self.variables]
        return np.stack(cols, axis=-1) if cols else np.zeros((n, 0))


class Equations:
    """A component's equations as a scaled numpy function of the joint variables."""

    def __init__(self, equations, variables, parameters, excluding=()):
        # a string value would be evaluated by subs (through sympify): parse it instead
        parameters = {k: as_expression(v) for k, v in dict(parameters).items()}
        exprs = [normalised(sp.expand(as_expression(e).subs(parameters))) for e in equations]
        self._exprs, self._variables, self._newton = exprs, tuple(variables), None
        self.scales = np.array([coefficient_norm(e) for e in exprs], dtype=float)
        # cse: each sine and cosine once, not once per term (long chains' equations have
        # hundreds of terms in a dozen of them)
        self._f = (numpy_function(tuple(variables), exprs, cse=True)
                   if exprs else None)
        excl = [normalised(sp.expand(as_expression(e).subs(parameters))) for e in excluding]
        self.excl_scales = np.array([coefficient_norm(e) for e in excl], dtype=float)
        self._g = (numpy_function(tuple(variables), excl, cse=True)
                   if excl else None)
        self._excl = excl

    def excluded_values(self, q) -> np.ndarray:
        """The excluded expressions at q, each divided by its coefficient norm."""
        if self._g is None:
            return np.zeros(0)
        return np.array(self._g(*q), dtype=float).reshape(-1) / self.excl_scales

    def excluded_batch(self, Q) -> np.ndarray:
        """:meth:`excluded_values` at every row of ``Q`` (shape (N, n)): shape (N, exclusions)."""
        Q = np.atleast_2d(np.asarray(Q, dtype=float))
        if self._g is None:
            return np.zeros((Q.shape[0], 0))
        vals = np.stack([np.broadcast_to(np.asarray(v, dtype=float), Q.shape[:1])
                         for v in self._g(*Q.T)], axis=-1)
        return vals / self.excl_scales

    def admits(self, q, rtol: float = EXCLUSION_RTOL) -> bool:
        """Is q outside the excluded sets, each excluded expression above ``rtol``?"""
        v = self.excluded_values(q)
        return not v.size or float(np.min(np.abs(v))) > rtol

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

    def _newton_functions(self):
        """The equations with ``t_i * e_i - 1`` appended, their Jacobian and the excluded
        expressions, as mpmath functions (lambdified once).

        The Jacobian is the complex-step derivative of the equations (:func:`complex_step`),
        not a lambdified symbolic one: on a component of alex's arm (equations of 28, 237 and
        497 terms with 47-digit coefficients) sympy took 12 s to differentiate them, most of
        the check's time.
        """
        if self._newton is None:
            ts = sp.symbols(f"t:{len(self._excl)}")
            F = list(self._exprs) + [t * e - 1 for t, e in zip(ts, self._excl)]
            unknowns = self._variables + tuple(ts)
            f = numpy_function(unknowns, F, modules="mpmath", cse=True)
            self._newton = (f, functools.partial(complex_step, f),
                            numpy_function(self._variables, self._excl, modules="mpmath"))
        return self._newton

    def refined(self, q) -> np.ndarray:
        """``q`` moved onto the equations, off the excluded sets, by Newton's method.

        In REFINE_DIGITS digits, the least-norm Newton step of the equations together with
        ``t_i * e_i(q) = 1`` for each excluded expression ``e_i`` (Rabinowitsch's trick: the
        point stays where every ``e_i`` is nonzero), ``REFINE_STEPS`` at most, stopped once
        a step no longer moves the double-precision point (SETTLED_ULPS).  Points that
        :func:`points_on` solved near a multiple root of the equations can lie far from the
        component for their small residual; refined, they lie on it to double precision (see
        REFINE_DIGITS).  A
        refined point can end close to an excluded set (the iteration heads for the nearest
        exact point); :meth:`settled` tells whether it is still a point of the component.

        Examples
        --------
        >>> x, y = sp.symbols("x y")
        >>> eqs = Equations([sp.sin(x)**3 - y**3], (x, y), {})
        >>> q = eqs.refined(np.array([1e-3, -1e-3]))
        >>> bool(abs(np.sin(q[0]) - q[1]) < 1e-12)
        True
        """
        import mpmath

        if self._f is None:
            return np.asarray(q, dtype=float)
        m = len(self._variables)
        with mpmath.workdps(REFINE_DIGITS):
            x = self._newton_start(q)
            for _ in range(REFINE_STEPS):
                nxt = self._newton_step(x, self._newton_functions()[0](*x))
                if nxt is None:
                    break
                before = np.array([float(v) for v in x[:m]])
                x = nxt
                after = np.array([float(v) for v in x[:m]])
                ulp = np.spacing(np.maximum(np.abs(before), 1.0))
                if np.all(np.abs(after - before) <= SETTLED_ULPS * ulp):
                    break
            return np.array([float(x[i]) for i in range(m)])

    def _newton_start(self, q):
        """``q`` in the working precision, with ``t_i = 1 / e_i(q)`` appended."""
        import mpmath

        x0 = [mpmath.mpf(float(v)) for v in q]
        excluded = self._newton_functions()[2]
        return mpmath.matrix(x0 + [1 / v if v else mpmath.mpf(1) for v in excluded(*x0)])

    def _newton_step(self, x, F):
        """``x`` after one least-norm Newton step on the values ``F`` there
        (:func:`minimum_norm_step`); None where the Jacobian vanishes."""
        import mpmath

        D = mpmath.matrix(self._newton_functions()[1](*x))
        step = minimum_norm_step(D, mpmath.matrix(F))
        return None if step is None else x - step

    def precise(self, q, digits: int):
        """``q`` moved onto the equations in ``digits`` digits, as mpmath numbers, or None.

        The iteration of :meth:`refined` (exclusions kept nonzero), run until every scaled
        equation is below ``10**-(digits - 10)`` rather than until the double-precision
        point stops moving: at a multiple root Newton's method converges linearly, and the
        step count it needs grows with the digits asked for.  None when it does not get
        there within ``4 * REFINE_STEPS`` steps (no point of the equations nearby, or one
        inside an excluded set).
        """
        import mpmath

        if self._f is None:
            return [mpmath.mpf(float(v)) for v in q]
        from ..tolerances import EXCLUSION_CERTIFY_RTOL

        f = self._newton_functions()[0]
        m, k = len(self._variables), len(self._exprs)
        with mpmath.workdps(digits):
            target = mpmath.mpf(10) ** -(digits - 10)
            scales = [mpmath.mpf(float(s)) for s in self.scales]
            x = self._newton_start(q)
            for _ in range(4 * REFINE_STEPS):
                F = f(*x)
                if max(abs(F[i]) / (scales[i] if i < k else 1) for i in range(len(F))) <= target:
                    point = [x[i] for i in range(m)]
                    if self.admits(np.array([float(v) for v in point]), EXCLUSION_CERTIFY_RTOL):
                        return point
                    return None
                x = self._newton_step(x, F)
                if x is None:
                    return None
            return None

    def settled(self, q) -> np.ndarray | None:
        """:meth:`refined` ``q`` when it is a point of the component, else None.

        On the equations (ON_COMPONENT_RESIDUAL) and off every excluded set beyond rounding
        (EXCLUSION_CERTIFY_RTOL: the refined value is exact to far below it).  The checks
        evaluate J there instead of at ``q`` before they call ``q`` regular.
        """
        from ..tolerances import EXCLUSION_CERTIFY_RTOL

        p = self.refined(q)
        if self.residual(p) <= ON_COMPONENT_RESIDUAL and self.admits(p, EXCLUSION_CERTIFY_RTOL):
            return p
        return None


def complex_step(f, *x):
    """The Jacobian of ``f`` (real-analytic, evaluated in mpmath) at ``x``, by complex steps.

    Column j is Im f(x + i h e_j) / h with h = 10**-dps at the working precision: no
    difference of close values is taken, so the error is that of the Taylor remainder,
    O(h**2) relative, far below the precision.  The equations of a component are
    polynomials in sines and cosines of the variables (and the ``t_i * e_i - 1`` rows), real
    for real arguments and analytic, as the method needs.

    Examples
    --------
    >>> import mpmath
    >>> J = complex_step(lambda x, y: [x * mpmath.sin(y), x ** 2], mpmath.mpf(2), mpmath.mpf(1))
    >>> [[round(float(v), 12) for v in row] for row in J]
    [[0.841470984808, 1.080604611736], [4.0, 0.0]]
    """
    import mpmath

    h = mpmath.mpf(10) ** -mpmath.mp.dps
    cols = []
    for j in range(len(x)):
        shifted = list(x)
        shifted[j] = mpmath.mpc(x[j], h)
        cols.append([mpmath.im(v) / h for v in f(*shifted)])
    return [[col[i] for col in cols] for i in range(len(cols[0]))] if cols else []


def minimum_norm_step(A, F):
    """The least-norm solution d of A d = F in mpmath (A of full row rank or nearly), or None.

    Solved as d = A^T (A A^T + r I)^-1 F with a ridge r at the working precision: rows that
    depend on the others stay solvable.  k equations that cut a component of more than n - k
    dimensions have a Jacobian of lower rank than k everywhere on it (nine of
    romeo_laas_small's gripper chain, of dimension 3 in 9 joints; a condition and its
    gradient in :mod:`rankloci.tree.precise`).
    """
    import mpmath

    AAt = A * A.T
    n = AAt.rows
    scale = max((abs(AAt[i, i]) for i in range(n)), default=mpmath.mpf(0))
    if not scale > 0:
        return None
    ridge = scale * mpmath.mpf(10) ** (-(mpmath.mp.dps - 5))
    for i in range(n):
        AAt[i, i] += ridge
    try:
        y = mpmath.lu_solve(AAt, F)
    except ZeroDivisionError:
        return None
    return A.T * y


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


def _batched(rows):
    """A map-like for scipy's finite differences: every shifted point in one call of ``rows``.

    scipy's ``least_squares`` evaluates the residual at the n shifted points of
    its 2-point Jacobian through ``workers(fun, points)``; the residuals here
    are lambdified numpy expressions, so ``rows`` (shape (N, n) -> (N, m))
    evaluates them all at once instead of n calls of ``fun``.  Same difference
    scheme and steps; values agree with ``fun`` to rounding.
    """
    def workers(fun, points):
        return list(rows(np.array(list(points), dtype=float)))
    return workers


def _stall_guard():
    """A ``least_squares`` callback that gives up a start stuck above the acceptance threshold.

    A start that converges to a point of the component (Gauss-Newton on a
    zero-residual problem) keeps halving its cost; one that has reached a
    positive local minimum of the cost creeps on until ``max_nfev`` and is
    rejected.  The callback stops a start whose cost has not halved in
    :data:`STALL_ITERATIONS` iterations while its largest residual is above
    ON_COMPONENT_RESIDUAL, about four times the longest such wait measured on
    starts that did converge.
    """
    state = {"ref": np.inf, "at": 0, "it": 0}

    def callback(intermediate_result):
        state["it"] += 1
        cost = intermediate_result.cost
        if cost <= 0.5 * state["ref"]:
            state["ref"], state["at"] = cost, state["it"]
        fun = intermediate_result.fun
        above = fun.size and float(np.max(np.abs(fun))) > ON_COMPONENT_RESIDUAL
        if above and state["it"] - state["at"] >= STALL_ITERATIONS:
            raise StopIteration     # scipy ends the run and returns the current point

    return callback


def points_on(eqs: Equations, nm: NumericMatrix, rng, n: int) -> list:
    """Up to ``n`` points where the equations vanish and no exclusion does (least squares)."""
    from scipy.optimize import least_squares

    if eqs.empty:
        return list(nm.random_q(rng, n))
    out = []
    opts = dict(method="trf", xtol=LEAST_SQUARES_TOL, ftol=LEAST_SQUARES_TOL,
                gtol=LEAST_SQUARES_TOL)
    on_rows = _batched(lambda X: eqs.batch(X).T)
    for q0 in nm.random_q(rng, MAX_TRIES * n):
        q = least_squares(eqs, q0, max_nfev=200 * len(q0), callback=_stall_guard(),
                          workers=on_rows, **opts).x
        if eqs.residual(q) <= ON_COMPONENT_RESIDUAL and not eqs.admits(q):
            # landed in an excluded set: solve again with t * e(q) = 1 (Rabinowitsch)
            m = len(q0)
            t0 = 1.0 / np.clip(np.abs(eqs.excluded_values(q0)), 1e-3, None)

            def lifted(x, m=m):
                return np.concatenate([eqs(x[:m]), eqs.excluded_values(x[:m]) * x[m:] - 1.0])

            def lifted_rows(X, m=m):
                return np.concatenate([eqs.batch(X[:, :m]).T,
                                       eqs.excluded_batch(X[:, :m]) * X[:, m:] - 1.0], axis=1)

            q = least_squares(lifted, np.concatenate([q0, t0]), max_nfev=200 * (m + len(t0)),
                              callback=_stall_guard(), workers=_batched(lifted_rows), **opts).x[:m]
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
