"""sigma_min/sigma_max over joint space: slices, paths through a component, regular points.

- :func:`slice_grid`: sigma_min/sigma_max of J over a 2-D slice of joint space
  through a point, and the curves where each locus component meets the slice;
- :func:`slice_joints`: the two joints that matter most for a component;
- :func:`path_through`: the manipulability w = sqrt(det(J J^T)) along a
  straight joint-space path that crosses a component, and every parameter at
  which the path meets the locus;
- :func:`component_points`, :func:`normal_directions`, :func:`regular_point`:
  points on a component, its normal space at a point, and a well-conditioned
  configuration.

The matrix is a :class:`~rankloci.numeric.equations.NumericMatrix`; the
components are those of a :class:`~rankloci.loci.Locus`.  numpy, scipy and
contourpy; the report draws what these return.

Examples
--------
>>> import numpy as np
>>> from rankloci.numeric.landscape import sigma_ratios
>>> sigma_ratios(np.array([[[1.0, 0.0], [0.0, 2.0]], [[1.0, 1.0], [1.0, 1.0]]])).round(12)
array([0.5, 0. ])
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass

import numpy as np

from ..expr import as_expression
from ..tolerances import (FACTOR_POINTS, FOLLOWER_RTOL, ON_LOCUS_RTOL, PATH_LENGTH,
                          PATH_NORMAL_SHARE, PATH_POINTS, PROBE_STEP, READING_POINTS,
                          REGULAR_MIN_RATIO, SENSITIVITY_MIN, SLICE_GRID, ZERO_CANDIDATE_RATIO)
from .equations import Equations, NumericMatrix, points_on

__all__ = ["SliceData", "PathData", "slice_grid", "slice_joints", "path_through",
           "model_components", "sigma_ratios", "component_points", "component_equations",
           "equation_weights", "regular_point", "normal_directions", "manipulability",
           "ratio_grid", "dependent_variables", "reading_points", "slice_point"]

def model_components(locus):
    """(1-based index, component) of the components that exist for the model's values."""
    return [(i, c) for i, c in enumerate(locus.components, start=1) if c.for_model]


def sigma_ratios(Js: np.ndarray) -> np.ndarray:
    """sigma_min/sigma_max of each matrix of a stack (..., m, n)."""
    s = np.linalg.svd(Js, compute_uv=False)
    top = s[..., 0]
    return np.where(top > 0, s[..., -1] / np.where(top > 0, top, 1.0), 0.0)


def manipulability(Js: np.ndarray) -> np.ndarray:
    """sqrt(det(J J^T)) (of J^T J for a tall J): the product of the singular values.

    Batched over the leading axes of ``Js`` (..., m, n).

    Examples
    --------
    >>> import numpy as np
    >>> float(manipulability(np.array([[2.0, 0.0, 0.0], [0.0, 3.0, 0.0]])))
    6.0
    """
    return np.prod(np.linalg.svd(Js, compute_uv=False), axis=-1)


def component_equations(comp, nm: NumericMatrix, parameters) -> Equations:
    """The component's equations and side conditions as numpy functions of ``nm``'s variables.

    The component is the closure of the set where its equations vanish and
    none of its ``excluding`` expressions does; :meth:`Equations.admits`
    tells whether a point keeps away from the excluded sets.  Parameters are
    replaced by their values in ``parameters``.
    """
    by_name = {v.name: v for v in nm.variables}
    params = {str(k): v for k, v in parameters.items()}

    def numeric(e):
        e = as_expression(e)
        e = e.xreplace({s: by_name[s.name] for s in e.free_symbols if s.name in by_name})
        return e.subs({s: params[s.name] for s in e.free_symbols if s.name in params})

    return Equations([numeric(e) for e in comp.equations], nm.variables, {},
                     excluding=[numeric(e) for e in getattr(comp, "excluding", ())])


def component_points(comp, nm: NumericMatrix, parameters, rng, n: int) -> list[np.ndarray]:
    """The component's sample point and up to ``n`` more points solved onto it.

    The points keep away from the component's excluded sets: where an excluded
    expression vanishes, the equations may hold at regular configurations.
    """
    eqs = component_equations(comp, nm, parameters)
    first = np.array([comp.sample[v.name] for v in nm.variables], dtype=float)
    return [first] + [np.asarray(q) for q in points_on(eqs, nm, rng, n)]


# --- slices ----------------------------------------------------------------------------------

@dataclass(frozen=True)
class SliceData:
    """sigma_min/sigma_max over a 2-D slice of joint space, and the locus on it.

    Attributes
    ----------
    axes : (int, int)
        Indices of the joint variables on the x and y axes.
    xs, ys : numpy.ndarray
        Grid coordinates.
    ratio : numpy.ndarray
        sigma_min/sigma_max, shape (len(ys), len(xs)).
    point : numpy.ndarray
        The configuration the slice passes through (the other joints keep its values).
    through : int or None
        The 1-based index of the component whose sample ``point`` is.
    curves : tuple of (int, tuple of (k, 2) arrays, (m, 2) array)
        Per component: its index, the polylines where it meets the slice and
        isolated points of it on the slice.
    """

    axes: tuple
    xs: np.ndarray
    ys: np.ndarray
    ratio: np.ndarray
    point: np.ndarray
    through: int | None
    curves: tuple = ()


def _axis_range(nm: NumericMatrix, k: int, center: float):
    """A full turn centred on ``center`` for an angle (the locus through it stays off the
    frame's edges); for a length its stroke (``nm.strokes``, set by the report: the joint's
    limits or :data:`~rankloci.limits.DEFAULT_STROKE`), widened to hold ``center``, else twice
    ``|center|`` (at least 1) either side."""
    if nm.variables[k] in nm.angles:
        return center - np.pi, center + np.pi
    stroke = getattr(nm, "strokes", {}).get(nm.variables[k])
    if stroke is not None:
        return min(stroke[0], center), max(stroke[1], center)
    half = max(1.0, 2.0 * abs(center))
    return center - half, center + half


def _grid_points(nm, axes, point, n, margin: int = 0, centres=None):
    (i, j) = axes
    centres = dict(zip(axes, centres)) if centres is not None else {}

    def coords(k):
        lo, hi = _axis_range(nm, k, centres.get(k, point[k]))
        h = (hi - lo) / (n - 1)
        return np.linspace(lo - margin * h, hi + margin * h, n + 2 * margin)

    xs, ys = coords(i), coords(j)
    X, Y = np.meshgrid(xs, ys)
    Q = np.broadcast_to(point, X.shape + (len(point),)).copy()
    Q[..., i] = X
    Q[..., j] = Y
    return xs, ys, Q


def ratio_grid(nm: NumericMatrix, axes, point, n: int = SLICE_GRID, centres=None):
    """(xs, ys, sigma_min/sigma_max on the grid) of the slice through ``point``.

    ``centres`` (one per axis) centres the window elsewhere than on ``point``.
    """
    xs, ys, Q = _grid_points(nm, axes, point, n, centres=centres)
    R = sigma_ratios(nm.batch(Q.reshape(-1, Q.shape[-1]))).reshape(Q.shape[:2])
    return xs, ys, R


def _window_centres(nm: NumericMatrix, axes, point, R):
    """Centres of the slice's window that keep the locus off the frame's edges.

    An angle's window is a full turn, so it may start anywhere: the start whose
    edge line has the largest mean log ratio (the edge runs along no valley) is
    taken, the centred one on ties.  The slice point stays inside the window.
    ``R`` is the ratio on the centred window (rows: y).
    """
    logr = np.log10(np.maximum(R, REGULAR_MIN_RATIO))
    out = []
    for axis, k in enumerate(axes):
        if nm.variables[k] not in nm.angles:
            out.append(float(point[k]))
            continue
        lines = logr if axis == 0 else logr.T   # lines[:, m]: the line at grid index m
        n = lines.shape[1] - 1                  # the last index repeats the first (a full turn)
        h = 2 * np.pi / n
        best = None
        for m in range(-n // 2, n // 2 + 1):
            # the mean: a valley along the edge lowers it, a curve crossing the edge hardly
            score = float(np.mean(lines[:, m % n])) - 1e-3 * abs(m)
            if best is None or score > best[0]:
                best = (score, m)
        out.append(float(point[k]) + best[1] * h)
    return tuple(out)


def slice_grid(nm: NumericMatrix, locus_components, parameters, axes, point, *, through=None,
               n: int = SLICE_GRID, centres=None) -> SliceData:
    """The heat map data of the slice ``axes`` through ``point`` with the locus curves.

    ``locus_components`` is a list of (index, Component); each is drawn where
    all its equations vanish on the slice: the zero contour of one equation,
    kept where the others vanish too, or, where they vanish only at isolated
    points, those points (refined by least squares).  Only points outside the
    component's excluded sets are drawn (:meth:`Equations.admits`): there the
    equations may vanish at regular configurations.  ``centres`` (one per
    axis) fixes the window, so that two slices drawn side by side cover the
    same one; by default it is chosen to keep the locus off the frame's edges.
    """
    if centres is None:
        xs, ys, R = ratio_grid(nm, axes, point, n)
        centres = _window_centres(nm, axes, point, R)
        if centres != (float(point[axes[0]]), float(point[axes[1]])):
            xs, ys, R = ratio_grid(nm, axes, point, n, centres)
    else:
        centres = (float(centres[0]), float(centres[1]))
        xs, ys, R = ratio_grid(nm, axes, point, n, centres)
    # the curves are traced on a grid two steps wider, so that a component on the border
    # of the slice is drawn too; the figure clips them to the slice
    cx, cy, Q = _grid_points(nm, axes, point, n, margin=2, centres=centres)
    curves = []
    for idx, comp in locus_components:
        lines, pts = _component_on_slice(component_equations(comp, nm, parameters), Q, axes,
                                         cx, cy, point)
        if lines or len(pts):
            curves.append((idx, tuple(lines), pts))
    return SliceData(tuple(axes), xs, ys, R, np.asarray(point, dtype=float), through,
                     tuple(curves))


def _admitted_runs(seg, admitted):
    """The runs of at least two consecutive points of ``seg`` where ``admitted`` holds."""
    runs, start = [], None
    for k, ok in enumerate(list(admitted) + [False]):
        if ok and start is None:
            start = k
        elif not ok and start is not None:
            if k - start >= 2:
                runs.append(seg[start:k])
            start = None
    return runs


def _component_on_slice(eqs: Equations, Q, axes, xs, ys, point):
    """(polylines, isolated points) of the component on the slice, outside its excluded sets."""
    lines, pts = _zero_set_on_slice(eqs, Q, axes, xs, ys, point)

    def admits(xy):
        q = np.array(point, dtype=float)
        q[axes[0]], q[axes[1]] = xy
        return eqs.admits(q)

    kept = []
    for seg in lines:
        kept += _admitted_runs(seg, [admits(p) for p in seg])
    pts = np.array([p for p in pts if admits(p)]).reshape(-1, 2)
    return kept, pts


def _zero_set_on_slice(eqs: Equations, Q, axes, xs, ys, point):
    """(polylines, isolated points) where all the equations vanish on the slice."""
    import contourpy

    if eqs.empty:
        return [], np.zeros((0, 2))
    vals = eqs.batch(Q)
    # equations constant on the slice: they hold on all of it or on none of it
    active = []
    for k in range(vals.shape[0]):
        v = vals[k]
        if np.ptp(v) <= 1e-12:
            if abs(v.flat[0]) > 1e-9:
                return [], np.zeros((0, 2))
        else:
            active.append(k)
    if not active:
        return [], np.zeros((0, 2))
    first, others = active[0], active[1:]
    gen = contourpy.contour_generator(xs, ys, vals[first])
    segments = [np.asarray(s) for s in gen.lines(0.0) if len(s) >= 2]
    if not others:
        return segments, np.zeros((0, 2))

    def at(xy):
        q = np.array(point, dtype=float)
        q[axes[0]], q[axes[1]] = xy
        return q

    lines, points = [], []
    step = max(xs[1] - xs[0], ys[1] - ys[0])
    for seg in segments:
        resid = np.array([np.max(np.abs(eqs(at(p))[others])) for p in seg])
        on = resid <= 1e-9
        if on.sum() >= 2 and on.mean() > 0.5:
            lines.append(seg[on] if on.all() else seg)
            continue
        # isolated crossings: local minima of the other equations' residual, refined
        for k in range(len(seg)):
            lo = resid[max(k - 1, 0)]
            hi = resid[min(k + 1, len(seg) - 1)]
            if resid[k] <= lo and resid[k] <= hi and resid[k] < 10 * step:
                p = _refine(eqs, at, seg[k], active)
                if p is not None and not any(np.linalg.norm(p - r) < 1e-6 for r in points):
                    points.append(p)
    pts = np.array(points).reshape(-1, 2)
    inside = ((pts[:, 0] >= xs[0] - 1e-9) & (pts[:, 0] <= xs[-1] + 1e-9)
              & (pts[:, 1] >= ys[0] - 1e-9) & (pts[:, 1] <= ys[-1] + 1e-9))
    return lines, pts[inside]


def _refine(eqs, at, xy0, active):
    from scipy.optimize import least_squares

    res = least_squares(lambda xy: eqs(at(xy))[active], np.asarray(xy0, dtype=float),
                        xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=200)
    return res.x if np.max(np.abs(eqs(at(res.x))[active])) <= 1e-10 else None


def _sensitivity(nm: NumericMatrix, point, k: int, n: int = 64) -> float:
    """Spread of log10 sigma_min/sigma_max when joint k alone sweeps its range."""
    lo, hi = _axis_range(nm, k, point[k])
    Q = np.broadcast_to(point, (n, len(point))).copy()
    Q[:, k] = np.linspace(lo, hi, n)
    # floored at REGULAR_MIN_RATIO: at a singular point the ratio's rounding noise (1e-16 to
    # 1e-12) would otherwise count as change along a joint it does not depend on
    r = sigma_ratios(nm.batch(Q))
    return float(np.ptp(np.log10(np.maximum(r, REGULAR_MIN_RATIO))))


def slice_joints(nm: NumericMatrix, point, weights: dict) -> tuple[int, int]:
    """The two joints that matter most at ``point``.

    Joints are ranked by ``weights`` (variable index -> how many equations use
    it), ties broken by how much sigma_min/sigma_max changes when that joint
    alone sweeps its range; the result is in variable order.
    """
    n = len(nm.variables)
    if n < 2:
        raise ValueError(f"a slice needs two joint variables, the matrix has {n}")
    # on the locus, the ratio stays 0 along the joints the component leaves free: probe also
    # off it, with each joint the equations use moved by PROBE_STEP
    point = np.asarray(point, dtype=float)
    probes = [point]
    for k in weights:
        moved = point.copy()
        moved[k] += PROBE_STEP
        probes.append(moved)
    sens = [max(_sensitivity(nm, q, k) for q in probes) for k in range(n)]
    # a joint the ratio does not depend on (a base rotation) only draws stripes: last
    ranked = sorted(range(n), key=lambda k: (sens[k] <= SENSITIVITY_MIN, -weights.get(k, 0),
                                             -round(sens[k], 6), k))
    return tuple(sorted(ranked[:2]))


def equation_weights(comps, variables) -> dict:
    """Variable index -> number of component equations that use it."""
    counts = Counter()
    index = {v.name: k for k, v in enumerate(variables)}
    for _, c in comps:
        for e in c.equations:
            for s in as_expression(e).free_symbols:
                if s.name in index:
                    counts[index[s.name]] += 1
    return dict(counts)


def regular_point(nm: NumericMatrix, rng, tries: int = 50) -> np.ndarray:
    """The best conditioned of ``tries`` random configurations (lengths within their
    strokes, where ``nm.strokes`` gives them)."""
    Q = nm.random_q(rng, tries)
    for k, v in enumerate(nm.variables):
        stroke = getattr(nm, "strokes", {}).get(v)
        if stroke is not None:
            Q[:, k] = rng.uniform(stroke[0], stroke[1], tries)
    return Q[int(np.argmax(sigma_ratios(nm.batch(Q))))]


# --- manipulability along a path -------------------------------------------------------------

@dataclass(frozen=True)
class PathData:
    """w = sqrt(det(J J^T)) along q(t) = point + t * step, t in [-1, 1].

    ``zeros`` holds every parameter t at which the path meets the locus
    (sigma_min/sigma_max at most ON_LOCUS_RTOL after refinement), t = 0 among them.
    """

    component: int
    point: np.ndarray
    step: np.ndarray
    t: np.ndarray
    w: np.ndarray
    ratio: np.ndarray
    zeros: tuple = ()


def normal_directions(eqs: Equations, point, h: float = 1e-6) -> np.ndarray:
    """An orthonormal basis (rows) of the span of the equations' gradients at ``point``."""
    point = np.asarray(point, dtype=float)
    f0 = eqs(point)
    G = np.empty((len(f0), len(point)))
    for k in range(len(point)):
        e = np.zeros(len(point))
        e[k] = h
        G[:, k] = (eqs(point + e) - eqs(point - e)) / (2 * h)
    if not G.size:
        return np.zeros((0, len(point)))
    _, s, vt = np.linalg.svd(G)
    rank = int(np.sum(s > 1e-8 * max(float(s[0]), 1e-300)))
    return vt[:rank]


def _zeros_along(nm, point, d, t, ratio) -> tuple:
    """The parameters where the path meets the locus: local minima of the ratio, refined."""
    from scipy.optimize import minimize_scalar

    out = []
    for k in range(len(t)):
        lo, hi = max(k - 1, 0), min(k + 1, len(t) - 1)
        if ratio[k] > ratio[lo] or ratio[k] > ratio[hi] or ratio[k] > ZERO_CANDIDATE_RATIO:
            continue
        res = minimize_scalar(lambda s: float(sigma_ratios(nm(point + s * d)[None])[0]),
                              bounds=(t[lo], t[hi]), method="bounded",
                              options={"xatol": 1e-13})
        if res.fun <= ON_LOCUS_RTOL and not any(abs(res.x - z) < 1e-6 for z in out):
            out.append(float(res.x))
    return tuple(sorted(out))


def path_through(nm: NumericMatrix, point, rng, *, component: int, length: float = PATH_LENGTH,
                 n: int = PATH_POINTS, tries: int = 40, normals=None) -> PathData:
    """A straight path through ``point`` between two regular configurations.

    With ``normals`` (rows spanning the component's normal space at ``point``,
    :func:`normal_directions`) the path crosses the component transversally:
    PATH_NORMAL_SHARE of its direction lies in that space, the rest is random.
    Without, the direction is random.  ``|step| = length``; directions whose end
    points are not clearly regular (sigma_min/sigma_max above REGULAR_MIN_RATIO)
    are drawn again.  Every crossing of the locus on the path is in ``zeros``.
    """
    point = np.asarray(point, dtype=float)
    best = None
    for _ in range(tries):
        d = rng.normal(size=len(point))
        if normals is not None and len(normals):
            N = np.asarray(normals)
            across = N.T @ rng.normal(size=len(N))
            across /= np.linalg.norm(across)
            along = d - N.T @ (N @ d)
            nrm = np.linalg.norm(along)
            along = along / nrm if nrm > 1e-12 else np.zeros_like(d)
            share = PATH_NORMAL_SHARE if nrm > 1e-12 else 1.0
            d = share * across + np.sqrt(1 - share ** 2) * along
        d *= length / np.linalg.norm(d)
        ends = sigma_ratios(nm.batch(np.stack([point - d, point + d])))
        if best is None or ends.min() > best[1]:
            best = (d, ends.min())
        if ends.min() > REGULAR_MIN_RATIO:
            break
    d = best[0]
    t = np.linspace(-1.0, 1.0, n)
    Js = nm.batch(point[None, :] + t[:, None] * d[None, :])
    ratio = sigma_ratios(Js)
    zeros = _zeros_along(nm, point, d, t, ratio)
    return PathData(component, point, d, t, manipulability(Js), ratio, zeros)


# --- the variables a component ties -----------------------------------------------------------

def dependent_variables(equations, variables, params, sample, candidates) -> list:
    """The variables among ``candidates`` that the ``equations`` tie to the others at ``sample``.

    As many as the rank of the equations' gradient at the sample point (indices
    into ``variables``, whose values ``sample`` holds), chosen by a QR
    factorization with column pivoting (the best-conditioned set): moving the
    other variables, these follow to stay on the component.  Parameters are
    replaced by ``params`` first.

    Examples
    --------
    >>> import sympy as sp
    >>> q1, q2, q3 = sp.symbols("q1 q2 q3")
    >>> dependent_variables([sp.sin(q2 + q3)], [q1, q2, q3], {}, [0.0, 0.1, -0.1], [0, 1, 2])
    [1]
    """
    import scipy.linalg
    import sympy as sp

    eqs = [sp.sympify(e, strict=True).subs(params) for e in equations]
    if not eqs or not candidates:
        return []
    at = {v: sample[k] for k, v in enumerate(variables)}
    G = np.array([[float(sp.diff(e, variables[k]).subs(at)) for k in candidates] for e in eqs])
    _, R, order = scipy.linalg.qr(G, pivoting=True, mode="economic")
    diag = np.abs(np.diag(R))
    if diag.size == 0 or diag[0] == 0:
        return []
    rank = int(np.sum(diag > FOLLOWER_RTOL * diag[0]))
    return sorted(candidates[k] for k in order[:rank])


# --- the points a reading is checked at -------------------------------------------------------

@dataclass(frozen=True)
class _SomeEquations:
    """A stand-in component with only some of the equations (points on a factor alone)."""

    equations: tuple
    excluding: tuple = ()


def reading_points(comp, equations, nm: NumericMatrix, parameters, rng) -> tuple:
    """``(points, factor_points)``: where the geometric reading of ``comp`` is checked.

    ``points`` are the component's sample point and
    :data:`~rankloci.tolerances.READING_POINTS` more solved onto it
    (:func:`component_points`); for several ``equations`` (the component's,
    parameter conditions aside), ``factor_points`` holds for each
    :data:`~rankloci.tolerances.FACTOR_POINTS` points where it alone vanishes,
    else it is empty.  Each point is a dict, variable name -> value.
    """
    names = [v.name for v in nm.variables]

    def as_dict(q):
        return {n: float(x) for n, x in zip(names, q)}

    pts = component_points(comp, nm, parameters, rng, READING_POINTS)
    factor_points = []
    if len(equations) > 1:
        for e in equations:
            single = component_equations(_SomeEquations((e,)), nm, parameters)
            factor_points.append([as_dict(q) for q in points_on(single, nm, rng, FACTOR_POINTS)])
    return [as_dict(q) for q in pts], factor_points


def slice_point(nm: NumericMatrix, rng) -> tuple:
    """A configuration to centre a slice of sigma_min/sigma_max on when no component is known.

    A minimum of the ratio from a random regular start (:func:`regular_point`), when that
    minimum is singular (sigma_min/sigma_max <= RANK_RTOL: the slice then shows a piece of the
    locus); else the regular start.  Returns (q, singular).
    """
    from ..tolerances import RANK_RTOL
    from .equations import minimise_ratio

    start = regular_point(nm, rng)
    try:
        q = minimise_ratio(nm, start)
    except (ValueError, np.linalg.LinAlgError):  # pragma: no cover - numeric trouble
        q = None
    if q is not None and float(sigma_ratios(nm.batch(q[None, :]))[0]) <= RANK_RTOL:
        return q, True
    return start, False
