"""The nearest component of a locus to a configuration, and the distance to it.

The distance from q to a component is min ||p - q|| over the points p where
the component's equations vanish (joint-space Euclidean distance, angle
differences taken in (-pi, pi]).  It is found in two steps: minimum-norm
Gauss-Newton on the equations from q with steps of at most MAX_PROJECTION_STEP
(each step is the shortest move that zeroes the linearised equations, so it
lands near the closest point; least squares from q where that fails), then
SLSQP on ||p - q||^2 with the equations as constraints, skipped when the point
is already stationary (p - q normal to the component there).  Both steps are
local: the distance returned is that to the nearest point found, an upper
bound of the true distance, equal to it when the closest point is the one the
descent reaches (the tests compare it with closed forms on the built-in models).
A point in a component's excluded set (its ``excluding`` expressions vanish
there, and its equations can hold at regular configurations) is not counted.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..tolerances import DIMENSION_RTOL, DIMENSION_STEP, MAX_PROJECTION_STEP, ON_COMPONENT_RESIDUAL

__all__ = ["Nearest", "ComponentDistance", "MAX_PROJECTION_STEP"]


@dataclass(frozen=True)
class Nearest:
    """The nearest component to a configuration.

    Attributes
    ----------
    component : int
        The component's number, 1-based as in the locus's text and JSON and in
        the ``nearest_component`` column of ``rankloci ik`` (``locus.components
        [component - 1]``); 0 when no component was reached.
    distance : float
        Joint-space distance to its nearest point found (inf when none).
    point : numpy.ndarray
        That point.
    distances : tuple of float
        The distance to every component, in the locus's order.
    """

    component: int
    distance: float
    point: np.ndarray
    distances: tuple


def _short_steps(eqs, p, max_iter: int = 200):
    """Minimum-norm Gauss-Newton from ``p`` with steps capped at MAX_PROJECTION_STEP."""
    p = np.array(p, dtype=float)
    h = DIMENSION_STEP
    eye = np.eye(len(p))
    for _ in range(max_iter):
        r = eqs(p)
        if not np.all(np.isfinite(r)) or np.max(np.abs(r)) <= 1e-15:
            break
        G = np.array([(eqs(p + h * e) - eqs(p - h * e)) / (2 * h) for e in eye]).T
        dx = -np.linalg.lstsq(G, r, rcond=None)[0]
        size = float(np.linalg.norm(dx))
        if size > MAX_PROJECTION_STEP:
            dx *= MAX_PROJECTION_STEP / size
        p = p + dx
        if size <= 1e-15:
            break
    return p


class ComponentDistance:
    """Distances from configurations to the components of a locus.

    Parameters
    ----------
    locus : Locus
        Its ``components`` are used (the model's own).
    angles : collection of sympy.Symbol
        The variables whose differences are taken modulo 2 pi.
    """

    def __init__(self, locus, angles=()):
        from ..numeric.equations import Equations

        self.components = tuple(locus.components)
        self.variables = tuple(locus.variables)
        params = dict(locus.parameters)
        self._eqs = [Equations(c.equations, self.variables, params, c.excluding)
                     for c in self.components]
        self._angle = np.array([v in set(angles) for v in self.variables], dtype=bool)
        self._last = {}

    def _wrap(self, d):
        d = np.array(d, dtype=float)
        d[self._angle] = (d[self._angle] + np.pi) % (2 * np.pi) - np.pi
        return d

    def _project(self, i, q, start):
        from scipy.optimize import least_squares, minimize

        eqs = self._eqs[i]
        if eqs.empty:
            return q.copy()
        p = _short_steps(eqs, start)
        if eqs.residual(p) > ON_COMPONENT_RESIDUAL:
            p = least_squares(eqs, start, method="trf", xtol=1e-15, ftol=1e-15, gtol=1e-15,
                              max_nfev=200 * len(q)).x
        if eqs.residual(p) > ON_COMPONENT_RESIDUAL or not eqs.admits(p):
            return None
        if self._stationary(eqs, p, q):
            return p

        def f(x):
            d = self._wrap(x - q)
            return float(d @ d), 2 * d

        res = minimize(f, p, jac=True, method="SLSQP",
                       constraints=[{"type": "eq", "fun": eqs}], options={"ftol": 1e-14,
                                                                         "maxiter": 200})
        better = res.x
        if (eqs.residual(better) <= ON_COMPONENT_RESIDUAL and eqs.admits(better)
                and np.linalg.norm(self._wrap(better - q)) < np.linalg.norm(self._wrap(p - q))):
            p = better
        return p

    def _stationary(self, eqs, p, q) -> bool:
        """Whether p - q is normal to the component at p (a stationary point of the distance).

        The equations' gradient G (central differences, DIMENSION_STEP) spans the normal
        space; p - q must lie in its row space to DIMENSION_RTOL.
        """
        d = self._wrap(p - q)
        size = float(np.linalg.norm(d))
        if size == 0:
            return True
        h = DIMENSION_STEP
        G = np.array([(eqs(p + h * e) - eqs(p - h * e)) / (2 * h) for e in np.eye(len(p))]).T
        if not G.size:
            return False
        coef = np.linalg.lstsq(G.T, d, rcond=None)[0]
        return float(np.linalg.norm(G.T @ coef - d)) <= DIMENSION_RTOL * 100 * size

    def distance(self, i: int, q, start=None):
        """(distance, point) from ``q`` to component ``i`` ((inf, None) if no point is reached)."""
        q = np.asarray(q, dtype=float)
        p = self._project(i, q, q if start is None else np.asarray(start, dtype=float))
        if p is None and start is not None:
            p = self._project(i, q, q)
        if p is None:
            return np.inf, None
        return float(np.linalg.norm(self._wrap(p - q))), p

    def nearest(self, q, *, warm: bool = False) -> Nearest:
        """The nearest component to ``q``.

        With ``warm``, each search starts from the point found for the
        previous ``q`` moved by the change in q (for points along a path).
        """
        q = np.asarray(q, dtype=float)
        dists, points = [], []
        for i in range(len(self.components)):
            start = None
            if warm and i in self._last:
                p_prev, q_prev = self._last[i]
                start = p_prev + (q - q_prev)
            d, p = self.distance(i, q, start)
            dists.append(d)
            points.append(p)
            if p is not None:
                self._last[i] = (p, q)
        if not dists or not np.isfinite(min(dists)):
            return Nearest(0, np.inf, np.full(len(q), np.nan), tuple(dists))
        k = int(np.argmin(dists))
        return Nearest(k + 1, float(dists[k]), points[k], tuple(float(d) for d in dists))
