"""The numbers behind the report's figures and comparisons (numpy, no plotting).

- :func:`slice_grid`: sigma_min/sigma_max of J over a 2-D slice of joint space
  through a point, and the curves where each locus component meets the slice;
- :func:`slice_joints`: the two joints that matter most for a component;
- :func:`path_through`: the manipulability w = sqrt(det(J J^T)) along a
  straight joint-space path that crosses a component;
- :func:`compare_loci`: do two loci (two methods) describe the same set, and where they
  differ, which one does the SVD side with?
- :func:`tree_summary`: a branch tree cut down to the paths that lead to
  components, for a legible figure.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field

import networkx as nx
import numpy as np
import sympy as sp

from ..locus import Outcome
from ..numeric.equations import Equations, NumericMatrix, points_on
from ..tolerances import COVER_RESIDUAL, RANK_RTOL, REGULAR_MIN_RATIO

__all__ = ["SliceData", "PathData", "Comparison", "Disagreement", "TreeSummary", "slice_grid",
           "slice_joints", "path_through", "compare_loci", "tree_summary", "model_components",
           "sigma_ratios", "component_points", "component_equations", "equation_weights",
           "regular_point", "node_outcome", "is_component_leaf"]

#: Grid points per axis of a heat map: 181 puts a node every 2 degrees on [-pi, pi].
GRID = 181

#: Points along a manipulability path.
PATH_POINTS = 401


def model_components(locus):
    """(1-based index, component) of the components that exist for the model's values."""
    return [(i, c) for i, c in enumerate(locus.components, start=1) if c.exists_for_model]


def sigma_ratios(Js: np.ndarray) -> np.ndarray:
    """sigma_min/sigma_max of each matrix of a stack (..., m, n)."""
    s = np.linalg.svd(Js, compute_uv=False)
    top = s[..., 0]
    return np.where(top > 0, s[..., -1] / np.where(top > 0, top, 1.0), 0.0)


def _manipulability(Js: np.ndarray) -> np.ndarray:
    """sqrt(det(J J^T)) (of J^T J for a tall J): the product of the singular values."""
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
        e = sp.sympify(e)
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
    if nm.variables[k] in nm.angles:
        return -np.pi, np.pi
    half = max(1.0, 2.0 * abs(center))
    return center - half, center + half


def _grid_points(nm, axes, point, n, margin: int = 0):
    (i, j) = axes

    def coords(k):
        lo, hi = _axis_range(nm, k, point[k])
        h = (hi - lo) / (n - 1)
        return np.linspace(lo - margin * h, hi + margin * h, n + 2 * margin)

    xs, ys = coords(i), coords(j)
    X, Y = np.meshgrid(xs, ys)
    Q = np.broadcast_to(point, X.shape + (len(point),)).copy()
    Q[..., i] = X
    Q[..., j] = Y
    return xs, ys, Q


def ratio_grid(nm: NumericMatrix, axes, point, n: int = GRID):
    """(xs, ys, sigma_min/sigma_max on the grid) of the slice through ``point``."""
    xs, ys, Q = _grid_points(nm, axes, point, n)
    R = sigma_ratios(nm.batch(Q.reshape(-1, Q.shape[-1]))).reshape(Q.shape[:2])
    return xs, ys, R


def slice_grid(nm: NumericMatrix, locus_components, parameters, axes, point, *, through=None,
               n: int = GRID) -> SliceData:
    """The heat map data of the slice ``axes`` through ``point`` with the locus curves.

    ``locus_components`` is a list of (index, Component); each is drawn where
    all its equations vanish on the slice: the zero contour of one equation,
    kept where the others vanish too, or, where they vanish only at isolated
    points, those points (refined by least squares).  Only points outside the
    component's excluded sets are drawn (:meth:`Equations.admits`): there the
    equations may vanish at regular configurations.
    """
    xs, ys, R = ratio_grid(nm, axes, point, n)
    # the curves are traced on a grid two steps wider, so that a component on the border
    # of the slice (q = +-pi) is drawn too; the figure clips them to the slice
    cx, cy, Q = _grid_points(nm, axes, point, n, margin=2)
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
    r = sigma_ratios(nm.batch(Q))
    return float(np.ptp(np.log10(np.maximum(r, 1e-16))))


def slice_joints(nm: NumericMatrix, point, weights: dict) -> tuple[int, int]:
    """The two joints that matter most at ``point``.

    Joints are ranked by ``weights`` (variable index -> how many equations use
    it), ties broken by how much sigma_min/sigma_max changes when that joint
    alone sweeps its range; the result is in variable order.
    """
    n = len(nm.variables)
    if n < 2:
        raise ValueError(f"a slice needs two joint variables, the matrix has {n}")
    sens = [_sensitivity(nm, point, k) for k in range(n)]
    ranked = sorted(range(n), key=lambda k: (-weights.get(k, 0), -round(sens[k], 6), k))
    return tuple(sorted(ranked[:2]))


def equation_weights(comps, variables) -> dict:
    """Variable index -> number of component equations that use it."""
    counts = Counter()
    index = {v.name: k for k, v in enumerate(variables)}
    for _, c in comps:
        for e in c.equations:
            for s in sp.sympify(e).free_symbols:
                if s.name in index:
                    counts[index[s.name]] += 1
    return dict(counts)


def regular_point(nm: NumericMatrix, rng, tries: int = 50) -> np.ndarray:
    """The best conditioned of ``tries`` random configurations."""
    Q = nm.random_q(rng, tries)
    return Q[int(np.argmax(sigma_ratios(nm.batch(Q))))]


# --- manipulability along a path -------------------------------------------------------------

@dataclass(frozen=True)
class PathData:
    """w = sqrt(det(J J^T)) along q(t) = point + t * step, t in [-1, 1]."""

    component: int
    point: np.ndarray
    step: np.ndarray
    t: np.ndarray
    w: np.ndarray
    ratio: np.ndarray


def path_through(nm: NumericMatrix, point, rng, *, component: int, length: float = 1.0,
                 n: int = PATH_POINTS, tries: int = 40) -> PathData:
    """A straight path through ``point`` between two random regular configurations.

    The direction is random (``rng``) with ``|step| = length``; directions whose
    end points are not clearly regular (sigma_min/sigma_max above
    REGULAR_MIN_RATIO) are drawn again.
    """
    point = np.asarray(point, dtype=float)
    best = None
    for _ in range(tries):
        d = rng.normal(size=len(point))
        d *= length / np.linalg.norm(d)
        ends = sigma_ratios(nm.batch(np.stack([point - d, point + d])))
        if best is None or ends.min() > best[1]:
            best = (d, ends.min())
        if ends.min() > REGULAR_MIN_RATIO:
            break
    d = best[0]
    t = np.linspace(-1.0, 1.0, n)
    Js = nm.batch(point[None, :] + t[:, None] * d[None, :])
    return PathData(component, point, d, t, _manipulability(Js), sigma_ratios(Js))


# --- method comparison -----------------------------------------------------------------------

@dataclass(frozen=True)
class Disagreement:
    """Points of one method's component that lie on no component of the other method.

    The SVD decides which method is right at each of them: where J is singular
    (``sigma_min/sigma_max <= RANK_RTOL``) the point belongs to the locus and
    the other method misses it; where J is regular the component is too large
    there and the other method is right.

    Attributes
    ----------
    method, other : str
        The method whose component it is, and the method that misses the points.
    index : int
        The component's 1-based number among ``method``'s components.
    equations : tuple of str
        Its equations (and ``... != 0`` for its side conditions), as plain text.
    tested : int
        How many of its points were tested.
    points : tuple of tuple of float
        The points on no component of ``other``.
    ratios : tuple of float
        sigma_min/sigma_max of J at each of ``points``.
    """

    method: str
    other: str
    index: int
    equations: tuple
    tested: int
    points: tuple
    ratios: tuple

    @property
    def regular(self) -> tuple:
        """Indices into ``points`` where J has full rank: the component is wrong there."""
        return tuple(k for k, r in enumerate(self.ratios) if r > RANK_RTOL)

    @property
    def singular(self) -> tuple:
        """Indices into ``points`` where J is rank deficient: ``other`` misses them."""
        return tuple(k for k, r in enumerate(self.ratios) if r <= RANK_RTOL)

    @property
    def right(self) -> tuple:
        """The methods the SVD sides with at these points (one, or none when both err).

        ``(other,)`` when every point is regular (the component holds regular
        points), ``(method,)`` when every point is singular (``other`` misses
        them), ``()`` when some are each.
        """
        if not self.singular:
            return (self.other,)
        if not self.regular:
            return (self.method,)
        return ()


@dataclass(frozen=True)
class Comparison:
    """Whether two loci of the same matrix describe the same set.

    ``identical``: the same equations component by component.  Otherwise
    ``agree`` is decided point by point: every point of a component of one
    (its sample and points solved onto it, away from its excluded sets) must
    lie on a component of the other.  ``disagreements`` holds, per component,
    the points where that fails with the SVD's verdict on them, and
    ``differences`` says the same in words.  Components for special parameter
    values are compared by equations only (``special_same``).
    """

    methods: tuple
    identical: bool
    agree: bool
    differences: tuple = ()
    special_same: bool = True
    points_tested: int = 0
    disagreements: tuple = ()

    @property
    def right(self) -> tuple:
        """The methods the SVD sides with wherever the loci differ (see :class:`Disagreement`).

        One method when every disagreement is decided for it, ``()`` when the
        loci agree or when each method errs somewhere.
        """
        wrong = set()
        for d in self.disagreements:
            if d.regular:
                wrong.add(d.method)
            if d.singular:
                wrong.add(d.other)
        if not self.disagreements or len(wrong) != 1:
            return ()
        return tuple(m for m in self.methods if m not in wrong)


def _normal(e):
    e = sp.sympify(e)
    return sp.sstr(-e if e.could_extract_minus_sign() else e)


def equation_sets(locus, special: bool = False):
    """The equations of each component, normalised and sorted: of the model's own components,
    or (``special=True``) of the others."""
    comps = locus.special if special else locus.components
    return sorted(tuple(sorted(_normal(e) for e in c.equations)) for c in comps)


def compare_loci(a, b, nm: NumericMatrix, parameters, rng, *, points: int = 4) -> Comparison:
    """Compare the loci ``a`` and ``b`` of one matrix (see :class:`Comparison`)."""
    methods = (a.method, b.method)
    special_same = equation_sets(a, True) == equation_sets(b, True)
    if equation_sets(a) == equation_sets(b) and a.degenerate == b.degenerate:
        return Comparison(methods, True, True, (), special_same, 0)
    diffs, found, tested = [], [], 0
    if a.degenerate != b.degenerate:
        diffs.append(f"{a.method} says degenerate={a.degenerate}, {b.method} {b.degenerate}")
    for x, y in ((a, b), (b, a)):
        ys = [component_equations(c, nm, parameters) for _, c in model_components(y)]
        for i, comp in model_components(x):
            pts = component_points(comp, nm, parameters, rng, points)
            tested += len(pts)
            off = [q for q in pts if not any(e.residual(q) <= COVER_RESIDUAL for e in ys)]
            if off:
                ratios = sigma_ratios(nm.batch(np.array(off)))
                eqs = tuple(f"{sp.sstr(e)} = 0" for e in comp.equations)
                eqs += tuple(f"{sp.sstr(e)} != 0" for e in comp.excluding)
                found.append(Disagreement(x.method, y.method, i, eqs, len(pts),
                                          tuple(tuple(float(v) for v in q) for q in off),
                                          tuple(float(r) for r in ratios)))
                diffs.append(f"{x.method} component {i} has {len(off)} of {len(pts)} tested "
                             f"points on no {y.method} component")
    return Comparison(methods, False, not diffs, tuple(diffs), special_same, tested, tuple(found))


# --- the branch tree, cut down ---------------------------------------------------------------

def node_outcome(data) -> Outcome | None:
    """The :class:`~rankloci.locus.Outcome` of a branch-tree node with attributes ``data``.

    None when the node has no outcome; a text that is no outcome is a ValueError.
    """
    outcome = data.get("outcome")
    return None if outcome is None else Outcome(outcome)


def is_component_leaf(data) -> bool:
    """Does a branch-tree node with attributes ``data`` stop as a component of the locus?

    A node without an outcome is not one.

    Examples
    --------
    >>> is_component_leaf({"outcome": Outcome.ALL_MINORS_VANISH}), is_component_leaf({})
    (True, False)
    """
    outcome = node_outcome(data)
    return outcome is not None and outcome.is_component


def _outcome_text(data) -> str:
    """The outcome of a node as it is shown, "" when it has none."""
    outcome = node_outcome(data)
    return "" if outcome is None else str(outcome)


@dataclass(frozen=True)
class TreeSummary:
    """A branch tree cut down for drawing; ``graph`` nodes carry ``label`` and ``role``."""

    graph: nx.DiGraph
    total_nodes: int
    collapsed: int
    outcomes: dict = field(default_factory=dict)


def tree_summary(tree: nx.DiGraph, max_nodes: int = 45) -> TreeSummary:
    """The branch tree cut down to at most about ``max_nodes`` nodes for drawing.

    A small tree is kept whole.  A larger one keeps the paths from the root to
    the component leaves; every subtree off those paths becomes one dashed node
    that counts its leaves by stop reason.  If that is still too big, the tree
    is cut at the deepest level that fits, each cut subtree again one dashed
    node.  Node roles: ``"component"`` (a leaf that is a component), ``"leaf"``
    (another stop reason), ``"inner"``, ``"summary"``.
    """
    outcomes = Counter(_outcome_text(d) for n, d in tree.nodes(data=True)
                       if tree.out_degree(n) == 0)

    def role(n):
        if tree.out_degree(n):
            return "inner"
        return "component" if is_component_leaf(tree.nodes[n]) else "leaf"

    if tree.number_of_nodes() <= max_nodes:
        G = nx.DiGraph()
        for n, d in tree.nodes(data=True):
            G.add_node(n, label=_label(n, d, leaf=tree.out_degree(n) == 0), role=role(n))
        G.add_edges_from(tree.edges())
        return TreeSummary(G, tree.number_of_nodes(), 0, dict(outcomes))
    keep = {n for n in tree if role(n) == "component"}
    for n in list(keep):
        keep |= nx.ancestors(tree, n)
    keep |= {n for n in tree if tree.in_degree(n) == 0}
    depth = {}
    for r in (n for n in tree if tree.in_degree(n) == 0):
        depth.update(nx.single_source_shortest_path_length(tree, r))
    # the deepest cut that fits: kept nodes down to `cut`, one summary per cut or pruned subtree
    levels = sorted({depth[n] for n in keep}, reverse=True)
    for cut in levels:
        shown = {n for n in keep if depth[n] <= cut}
        summaries = sum(1 for n in shown if any(c not in shown for c in tree.successors(n)))
        if len(shown) + summaries <= max_nodes:
            break
    G = nx.DiGraph()
    collapsed = 0
    for n in sorted(shown):
        G.add_node(n, label=_label(n, tree.nodes[n], leaf=tree.out_degree(n) == 0), role=role(n))
    for n in sorted(shown):
        rest = []
        for c in tree.successors(n):
            if c in shown:
                G.add_edge(n, c)
            else:
                rest.append(c)
        if rest:
            sub = set(rest)
            for c in rest:
                sub |= nx.descendants(tree, c)
            leaves = Counter(_outcome_text(tree.nodes[m]) for m in sub
                             if tree.out_degree(m) == 0)
            found = sum(1 for m in sub if tree.out_degree(m) == 0 and role(m) == "component")
            collapsed += len(sub)
            what = "\n".join(f"{v} x {k}" for k, v in sorted(leaves.items()))
            head = f"{len(sub)} more {'branch' if len(sub) == 1 else 'branches'}"
            if found:
                head += f", {found} component {'leaf' if found == 1 else 'leaves'}"
            sid = f"s{n}"
            G.add_node(sid, label=f"{head}\n{what}", role="summary")
            G.add_edge(n, sid)
    return TreeSummary(G, tree.number_of_nodes(), collapsed, dict(outcomes))


def _short(text: str, width: int = 38) -> str:
    text = " ".join(str(text).split())
    return text if len(text) <= width else text[:width - 3] + "..."


def _label(n, d, *, leaf: bool) -> str:
    lines = [f"{n}: {_short(d.get('condition', ''))}"]
    bits = []
    if "columns" in d:
        bits.append(f"cols {d['columns']}")
    if "k" in d:
        bits.append(f"k={d['k']}")
    if bits:
        lines.append(", ".join(bits))
    if leaf:
        lines.append(f"[{_outcome_text(d)}]")
    return "\n".join(lines)
