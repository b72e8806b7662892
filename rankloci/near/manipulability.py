"""Manipulability ellipsoid and polytope of a Jacobian, after Yoshikawa and Kilic.

A. Kilic, *A Study on Kinematic Manipulability Measures for Redundant Arms:
Ellipsoids and Polytopes*, MSc thesis, Istanbul Technical University (2005):

- the **ellipsoid** {J qdot : ||qdot||_2 <= 1} (section 3.1): principal axes
  the left singular vectors u_i of J, semi-axes the singular values sigma_i,
  and Yoshikawa's index w = sqrt(det(J J')) = prod sigma_i;
- the **polytope** {J qdot : ||qdot||_inf <= 1} (section 3.2): the Minkowski
  sum of the segments [-j_i, j_i] of the columns of J, a zonotope; its
  vertices are among the 2^n points J s, s in {-1, 1}^n (the thesis's
  pseudo-code), kept by scipy's ConvexHull (Qhull);
- the **cone-cell index** w_p = sum_k S_k (eqs. 1.51-1.55): the cone cells are
  the simplices spanned by the origin and m vertices on a common facet (a
  primary vertex set), S_k = |det [V_k1 ... V_km]| / d_m.  Here each facet of
  the hull is triangulated in its own hyperplane (Delaunay), and d_m = m!, the
  factor that makes S_k the volume of the simplex; then w_p is the volume of
  the polytope, which the tests compare with Qhull's volume.  For this
  zonotope the volume is also 2^m sum over m-column subsets S of |det J_S|
  (the zonotope volume formula), and for square J, w_p = 2^m w.

Qhull (through scipy) is used rather than a polytope library: the polytope is
given by its generating points, and the hull, its facets and its volume are
what is needed.  Where J has rank r < m the polytope is flat: its hull is
formed in the r-dimensional range of J and its m-dimensional volume is 0.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from ..tolerances import FLAT_RTOL, RANK_RTOL

__all__ = ["Ellipsoid", "Polytope", "ellipsoid", "polytope", "zonotope_volume",
           "support", "MAX_POLYTOPE_COLUMNS"]

#: The polytope enumerates 2^n sign vectors; beyond this many columns it refuses.
MAX_POLYTOPE_COLUMNS = 16


@dataclass(frozen=True)
class Ellipsoid:
    """The manipulability ellipsoid {J qdot : ||qdot||_2 <= 1}.

    Attributes
    ----------
    axes : (m, m) array
        Principal directions, one per column (left singular vectors).
    radii : (m,) array
        Semi-axis lengths (singular values), largest first.
    w : float
        Yoshikawa's manipulability sqrt(det(J J')) = prod(radii).
    sigma_ratio : float
        radii[-1] / radii[0].
    """

    axes: np.ndarray
    radii: np.ndarray
    w: float
    sigma_ratio: float

    @property
    def volume(self) -> float:
        """The m-dimensional volume: w times the volume of the unit m-ball."""
        m = len(self.radii)
        return self.w * math.pi ** (m / 2) / math.gamma(m / 2 + 1)


@dataclass(frozen=True)
class Polytope:
    """The manipulability polytope {J qdot : ||qdot||_inf <= 1}.

    Attributes
    ----------
    vertices : (k, m) array
        Its vertices.
    normals : (f, m) array
        Outward unit normals of its facets (Qhull's triangulated facets,
        merged where coplanar); empty when flat.
    offsets : (f,) array
        Support values: the facet lies on {v : normal . v = offset}.
    simplices : (s, m) int array
        Qhull's triangulation of the boundary (vertex indices into the
        2^n points, see ``points``); empty when flat.
    points : (2^n, m) array
        The points J s, s in {-1, 1}^n.
    volume : float
        m-dimensional volume (0 when flat).
    w_p : float
        Kilic's cone-cell index, sum of |det [V_k1 ... V_km]| / m! over the
        boundary simplices (0 when flat).
    rank : int
        Numeric rank of J (RANK_RTOL): the dimension of the polytope.
    flatness : float
        Half-width along the left singular vector of sigma_min over that
        along the one of sigma_max (1 for a ball-like polytope, 0 for a flat one).
    """

    vertices: np.ndarray
    normals: np.ndarray
    offsets: np.ndarray
    simplices: np.ndarray
    points: np.ndarray
    volume: float
    w_p: float
    rank: int
    flatness: float

    @property
    def flat(self) -> bool:
        """Whether the polytope is flat: flatness <= FLAT_RTOL."""
        return self.flatness <= FLAT_RTOL


def _matrix(J) -> np.ndarray:
    J = np.array(J, dtype=float, copy=True)
    if J.ndim != 2 or 0 in J.shape:
        raise ValueError(f"J must be a non-empty 2-D matrix, got shape {J.shape}")
    if not np.all(np.isfinite(J)):
        raise ValueError("J must be finite")
    return J


def ellipsoid(J) -> Ellipsoid:
    """Yoshikawa's manipulability ellipsoid of J (m x n, m <= n).

    Examples
    --------
    The 2R arm with unit links at q1 = 0, q2 = pi/4: w = |sin q2|.

    >>> q2 = np.pi / 4
    >>> E = ellipsoid([[-np.sin(q2), -np.sin(q2)], [1 + np.cos(q2), np.cos(q2)]])
    >>> round(E.w, 6), round(float(np.sin(q2)), 6)
    (0.707107, 0.707107)
    """
    J = _matrix(J)
    U, s, _ = np.linalg.svd(J, full_matrices=True)
    m = J.shape[0]
    radii = np.zeros(m)
    radii[: len(s)] = s
    w = float(np.prod(radii))
    return Ellipsoid(axes=U, radii=radii, w=w,
                     sigma_ratio=float(radii[-1] / radii[0]) if radii[0] > 0 else 0.0)


def support(J, d) -> float:
    """Half-width of the polytope of J along the unit vector d: ||J' d||_1."""
    return float(np.abs(np.asarray(J, dtype=float).T @ np.asarray(d, dtype=float)).sum())


def zonotope_volume(J) -> float:
    """2^m sum over m-column subsets S of |det J_S|: the polytope's volume in closed form.

    Examples
    --------
    >>> zonotope_volume([[1.0, 0.0], [0.0, 2.0]])
    8.0
    """
    J = _matrix(J)
    m, n = J.shape
    if n < m:
        return 0.0
    subsets = itertools.combinations(range(n), m)
    total = sum(abs(float(np.linalg.det(J[:, list(S)]))) for S in subsets)
    return 2.0 ** m * total


def polytope(J) -> Polytope:
    """The manipulability polytope of J: the image of the cube |qdot_i| <= 1.

    Parameters
    ----------
    J : array_like, shape (m, n), n <= MAX_POLYTOPE_COLUMNS

    Returns
    -------
    Polytope

    Examples
    --------
    >>> P = polytope([[1.0, 0.0, 1.0], [0.0, 1.0, 1.0]])
    >>> len(P.vertices), round(P.volume, 6), round(P.w_p, 6)
    (6, 12.0, 12.0)
    """
    from scipy.spatial import ConvexHull

    J = _matrix(J)
    m, n = J.shape
    if n > MAX_POLYTOPE_COLUMNS:
        raise ValueError(f"J has {n} columns; the polytope enumerates 2^n points and allows "
                         f"at most {MAX_POLYTOPE_COLUMNS}")
    signs = np.array(list(itertools.product((-1.0, 1.0), repeat=n)))
    points = signs @ J.T
    U, s, _ = np.linalg.svd(J, full_matrices=True)
    rank = int(np.sum(s > RANK_RTOL * s[0])) if s[0] > 0 else 0
    h_max = support(J, U[:, 0])
    flatness = support(J, U[:, m - 1]) / h_max if h_max > 0 and len(s) == m else 0.0
    empty_f, empty_s = np.zeros((0, m)), np.zeros((0, m), dtype=int)
    if rank < m or m == 1:
        if rank == 0:
            vertices = np.zeros((1, m))
        else:
            coords = points @ U[:, :rank]
            if rank == 1:
                idx = [int(np.argmin(coords[:, 0])), int(np.argmax(coords[:, 0]))]
            else:
                idx = ConvexHull(coords).vertices
            vertices = points[sorted(set(idx))]
        if m == 1 and rank == 1:
            lo, hi = float(vertices.min()), float(vertices.max())
            normals = np.array([[-1.0], [1.0]])
            return Polytope(vertices, normals, np.array([-lo, hi]), empty_s, points,
                            hi - lo, hi - lo, 1, 1.0)
        return Polytope(vertices, empty_f, np.zeros(0), empty_s, points, 0.0, 0.0, rank, flatness)
    hull = ConvexHull(points)
    normals, offsets = hull.equations[:, :m], -hull.equations[:, m]
    # merge coplanar triangles into facets
    key = np.round(np.hstack([normals, offsets[:, None]]) / max(1.0, np.abs(offsets).max()), 9)
    _, first = np.unique(key, axis=0, return_index=True)
    first.sort()
    vertices = points[hull.vertices]
    w_p = _cone_cell_index(vertices, normals[first], offsets[first])
    return Polytope(vertices=vertices, normals=normals[first], offsets=offsets[first],
                    simplices=hull.simplices, points=points, volume=float(hull.volume),
                    w_p=w_p, rank=rank, flatness=flatness)


def _cone_cell_index(vertices, normals, offsets) -> float:
    """Kilic's w_p: sum of |det [V_k1 ... V_km]| / m! over the cone cells.

    Each facet is triangulated on its own (Delaunay in the facet's hyperplane) and each
    simplex of it, a primary vertex set, spans a cone cell with the origin.  Qhull's
    triangulated output is not used for this: where facets have many vertices (6-D
    polytopes of 7 columns), its simplices can overlap.
    """
    from scipy.spatial import Delaunay

    m = vertices.shape[1]
    scale = float(np.abs(vertices).max())
    total = 0.0
    for n, b in zip(normals, offsets):
        V = vertices[np.abs(vertices @ n - b) <= 1e-9 * scale]
        centre = V.mean(axis=0)
        basis = np.linalg.svd(V - centre)[2][: m - 1]
        flat = (V - centre) @ basis.T
        if m == 2:
            order = np.argsort(flat[:, 0])
            cells = [order[[0, -1]]]
        elif len(V) == m:
            cells = [np.arange(m)]
        else:
            cells = Delaunay(flat).simplices
        total += float(np.abs(np.linalg.det(V[np.asarray(cells)])).sum())
    return total / math.factorial(m)
