"""Joint-space directions that leave a component of the locus.

:func:`direction_across` is the first normal of a component at one of its
points (the quickest way off it); :func:`across_keeping_orientation` bends a
direction so that, to first order, the end-effector keeps its orientation
while the joints move along it.  numpy only.
"""

from __future__ import annotations

import numpy as np

from ..numeric.landscape import normal_directions
from ..tolerances import ACROSS_KEEP_SHARE, ORIENTATION_NULL_RTOL

__all__ = ["unit_vector", "direction_across", "across_keeping_orientation"]


def unit_vector(v) -> np.ndarray:
    """``v`` over its length (``v`` itself when it is zero).

    Examples
    --------
    >>> unit_vector([3.0, 4.0]).tolist(), unit_vector([0.0, 0.0]).tolist()
    ([0.6, 0.8], [0.0, 0.0])
    """
    v = np.asarray(v, dtype=float)
    n = float(np.linalg.norm(v))
    return v / n if n > 0 else v


def direction_across(eqs, q0, rng) -> np.ndarray:
    """A unit joint-space direction across the component of ``eqs`` at ``q0`` (its first
    normal, :func:`~rankloci.numeric.landscape.normal_directions`).

    ``rng`` draws a direction when the equations have no gradient there.

    Examples
    --------
    >>> import numpy as np, sympy as sp
    >>> from rankloci.numeric.equations import Equations
    >>> q1, q2 = sp.symbols("q1 q2")
    >>> eqs = Equations([sp.sin(q2)], [q1, q2], {})
    >>> np.abs(direction_across(eqs, np.zeros(2), np.random.default_rng(0))).round(6).tolist()
    [0.0, 1.0]
    """
    normals = normal_directions(eqs, q0)
    if len(normals):
        return unit_vector(normals[0])
    return unit_vector(rng.standard_normal(len(q0)))  # pragma: no cover - no gradient


def across_keeping_orientation(kin, q0, d) -> np.ndarray:
    """The unit joint direction nearest to ``d`` that leaves the orientation unchanged at
    ``q0`` to first order.

    ``kin`` is a :class:`~rankloci.near.path.Kinematics`.  ``d`` itself (made
    unit) when the task has no angular rows, or when what is left of ``d`` in
    the null space of the angular rows is shorter than
    :data:`~rankloci.tolerances.ACROSS_KEEP_SHARE` of it.
    """
    ang = [i for i, r in enumerate(kin.rows) if r >= 3]
    if not ang:
        return unit_vector(d)
    Jw = kin.jacobian(q0)[ang]
    _, s, vt = np.linalg.svd(Jw)
    rank = int(np.sum(s > ORIENTATION_NULL_RTOL * max(float(s[0]), 1e-300))) if s.size else 0
    null = vt[rank:]
    e = null.T @ (null @ np.asarray(d, dtype=float))
    keep = np.linalg.norm(e) > ACROSS_KEEP_SHARE * np.linalg.norm(d)
    return unit_vector(e) if keep else unit_vector(d)
