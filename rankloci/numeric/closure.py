"""Is a point in the closure of a component: are admitted points of its equations near it?

A component is the zero set of its equations minus the zero set of its
exclusions, and its closure adds limit points where an exclusion vanishes
too.  :func:`near_admitted` tells such a point from one of a different set
by projecting small random moves of it back onto the equations
(Gauss-Newton) and asking whether one lands close by with every exclusion
nonzero.  The locus's :meth:`~rankloci.loci.Locus.contains` and the methods'
leaves-to-components step ask it, each with its own test of "on the
equations" and "admitted".
"""

from __future__ import annotations

import numpy as np

from ..tolerances import NEAR_ADMITTED_RADIUS, NEAR_ADMITTED_STEP, NEAR_ADMITTED_TRIES
from .gauss_newton import gauss_newton_rows

__all__ = ["near_admitted"]


def near_admitted(rows, on, admits, x, rng, *, tries: int = NEAR_ADMITTED_TRIES) -> bool:
    """Are there admitted points of the equations within NEAR_ADMITTED_RADIUS of ``x``?

    Parameters
    ----------
    rows : callable
        Rows of points, shape (B, n), to rows of equation values.
    on : callable
        Rows of points to a boolean mask: which are on the equations.
    admits : callable
        One point to a bool: is it admitted (every exclusion nonzero)?
    x : numpy.ndarray
        The point, shape (n,).
    rng : numpy.random.Generator
        The random moves: ``tries`` of them, NEAR_ADMITTED_STEP in size.

    Examples
    --------
    >>> import numpy as np
    >>> rows = lambda Y: Y[:, :1]                    # the line y0 = 0 ...
    >>> on = lambda Y: np.abs(Y[:, 0]) < 1e-12
    >>> near_admitted(rows, on, lambda y: y[1] != 0, np.zeros(2), np.random.default_rng(0))
    True
    >>> near_admitted(rows, on, lambda y: abs(y[1]) > 1, np.zeros(2), np.random.default_rng(0))
    False
    """
    x = np.asarray(x, dtype=float)
    starts = x + NEAR_ADMITTED_STEP * rng.standard_normal((tries, x.size))
    Y = gauss_newton_rows(rows, starts)
    Y = Y[np.all(np.isfinite(Y), axis=1)]
    if not len(Y):
        return False
    near = on(Y) & (np.max(np.abs(Y - x), axis=1, initial=0.0) <= NEAR_ADMITTED_RADIUS)
    return any(admits(y) for y in Y[near])
