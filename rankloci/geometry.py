"""The geometry of an arm at one configuration: joint axes, the facts they make, the pose.

:func:`axis_lines` gives the joint axes and the task point in the world frame;
:func:`facts_at` lists what holds among them at a configuration (axes
collinear, parallel, perpendicular or meeting; the task point, or a design
point where consecutive axes meet at every configuration
(:func:`design_points`), on an axis or in a plane).  The readings of a
component keep the facts that hold on it and at no random configuration
(:func:`component_facts`).  :func:`dependent_joints` finds the
smallest set of dependent columns of J, and :func:`robot_pose` the chain of
frame origins that a figure draws.  numpy only; distances are relative to the
size of the arm (:func:`arm_scale`) and decided with
:data:`~rankloci.tolerances.GEOMETRY_RTOL`.

Examples
--------
>>> from rankloci.io import load_model
>>> from rankloci.geometry import facts_at
>>> arm = load_model("planar2r")
>>> sorted(facts_at(arm, {"q1": 0.0, "q2": 0.0}, None), key=str)   # stretched out
[('coplanar', 'P', frozenset({1, 2})), ('parallel', 1, 2)]
>>> sorted(facts_at(arm, {"q1": 0.0, "q2": 1.0}, None), key=str)
[('parallel', 1, 2)]
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np

from .expr import as_expression
from .kinematics import numeric_frames
from .model import RobotModel
from .tolerances import GEOMETRY_RTOL, RANDOM_POINTS, RANK_RTOL

__all__ = ["AxisLine", "axis_lines", "facts_at", "design_points", "dependent_joints",
           "meeting_point", "parallel", "distance_to_line", "arm_scale", "random_configuration",
           "RobotPose", "robot_pose", "ComponentFacts", "component_facts", "design_facts",
           "common_facts", "columns_fill_rows", "lost_rotation_axis", "design_point",
           "point_axis_distances", "equal_distances", "centres_distance", "dependence_left",
           "axis_line_ends", "plane_through_axis", "box_edges", "rectangle_along", "scaled_to",
           "motion_arrow"]


@dataclass(frozen=True)
class AxisLine:
    """A joint axis in the world frame at one configuration."""

    joint: int          # 1-based
    kind: str           # "revolute" or "prismatic"
    point: np.ndarray   # a point of the axis (the joint frame's origin)
    direction: np.ndarray  # unit vector


def axis_lines(model: RobotModel, q: dict, params=None):
    """Joint axes and the task point at configuration ``q`` (variable name -> value).

    Returns ``(lines, task_point)``, both in the world frame.
    """
    params = dict(model.parameters if params is None else params)
    qs = {v: float(q[str(v)]) for v in model.variables}
    poses = numeric_frames(model, qs, params)
    values = {k: float(v) for k, v in params.items()}
    lines = []
    for i, j in enumerate(model.joints):
        T = poses[3 * i + 2]
        axis = np.array([float(as_expression(a).subs(values)) for a in j.axis])
        d = T[:3, :3] @ axis
        lines.append(AxisLine(i + 1, j.kind, T[:3, 3].copy(), d / np.linalg.norm(d)))
    return lines, poses[-1][:3, 3].copy()


def parallel(u, v) -> bool:
    """Are the unit directions ``u`` and ``v`` parallel (to GEOMETRY_RTOL)?"""
    return float(np.linalg.norm(np.cross(u, v))) <= GEOMETRY_RTOL


def distance_to_line(p, line) -> float:
    """Distance from the point ``p`` to the axis ``line`` (an AxisLine)."""
    r = p - line.point
    return float(np.linalg.norm(r - (r @ line.direction) * line.direction))


def meeting_point(a, b):
    """The closest points (on ``a``, on ``b``) of two axes; None when they are parallel.

    The axes meet where the two points coincide.
    """
    n = np.cross(a.direction, b.direction)
    nn = float(np.linalg.norm(n))
    if nn <= GEOMETRY_RTOL:
        return None
    w = b.point - a.point
    # closest points: a.point + s a.d, b.point + t b.d
    s = np.dot(np.cross(w, b.direction), n) / nn ** 2
    t = np.dot(np.cross(w, a.direction), n) / nn ** 2
    pa, pb = a.point + s * a.direction, b.point + t * b.direction
    return pa, pb


def arm_scale(lines, tool) -> float:
    """The largest distance between two axis points or an axis point and the task point."""
    pts = [ln.point for ln in lines] + [tool]
    return max(max(float(np.linalg.norm(p - q)) for p in pts for q in pts), 1e-9)


def design_points(model, params, rng):
    """Points where consecutive revolute axes meet at every configuration (checked at random).

    Returns a tuple of joint tuples: the axes through each such point, the first
    two of which define it (pairs that meet at the same point are merged).
    """
    rev = [k + 1 for k, j in enumerate(model.joints) if j.kind == "revolute"]
    pairs = [(a, b) for a, b in zip(rev, rev[1:]) if b == a + 1]
    keep = set(pairs)
    same = {(p, r) for p, r in itertools.combinations(pairs, 2)}
    for _ in range(RANDOM_POINTS):
        lines, tool = axis_lines(model, random_configuration(model, rng), params)
        tol = GEOMETRY_RTOL * arm_scale(lines, tool)
        where = {}
        for a, b in list(keep):
            m = meeting_point(lines[a - 1], lines[b - 1])
            if m is None or float(np.linalg.norm(m[0] - m[1])) > tol:
                keep.discard((a, b))
            else:
                where[(a, b)] = m[0]
        same = {(p, r) for p, r in same if p in where and r in where
                and float(np.linalg.norm(where[p] - where[r])) <= tol}
    groups = []
    for p in sorted(keep):
        hit = [g for g in groups if any((min(p, r), max(p, r)) in same for r in g)]
        groups = [g for g in groups if g not in hit] + [sorted(set().union([p], *hit))]
    return tuple(tuple(sorted({j for pr in g for j in pr})) for g in sorted(groups))


def random_configuration(model, rng) -> dict:
    """A random configuration: angles uniform in [-pi, pi], lengths standard normal."""
    return {str(v): (rng.uniform(-np.pi, np.pi) if j.kind == "revolute" else rng.normal())
            for v, j in zip(model.variables, model.joints)}


def facts_at(model, q: dict, params, meets=()) -> set:
    """Every geometric fact at configuration ``q``, as hashable keys.

    ``meets`` lists consecutive axes (a, b) that meet by design; their meeting
    points are tested like the task point.  Keys: ``("collinear", a, b)``,
    ``("parallel", a, b)``, ``("perpendicular", a, b)``, ``("intersect", a, b)``,
    ``("on-axis", X, a)``, ``("in-plane", X, a, b)`` (X in the plane through
    axis a parallel to axis b), ``("coplanar", X, frozenset)`` (X and the
    parallel axes in one plane; X may be None), ``("coincide", X, Y)`` (two
    points of ``meets`` at one place) and ``("slide-parallel", p, a)`` (prismatic
    joint p slides parallel to revolute axis a), where X is ``"P"`` (the task
    point) or a tuple of the axes of ``meets`` that meet there.
    """
    lines, tool = axis_lines(model, q, params)
    tol = GEOMETRY_RTOL * arm_scale(lines, tool)
    rev = [ln for ln in lines if ln.kind == "revolute"]
    points = {"P": tool}
    for axes in meets:
        m = meeting_point(lines[axes[0] - 1], lines[axes[1] - 1])
        if m is not None and float(np.linalg.norm(m[0] - m[1])) <= tol:
            if float(np.linalg.norm(m[0] - tool)) > tol:
                points[axes] = 0.5 * (m[0] + m[1])
    facts = set()
    for a, b in itertools.combinations(rev, 2):
        if parallel(a.direction, b.direction):
            if distance_to_line(b.point, a) <= tol:
                facts.add(("collinear", a.joint, b.joint))
            else:
                facts.add(("parallel", a.joint, b.joint))
            continue
        if abs(float(a.direction @ b.direction)) <= GEOMETRY_RTOL:
            facts.add(("perpendicular", a.joint, b.joint))
        n = np.cross(a.direction, b.direction)
        if abs(float((b.point - a.point) @ n)) / float(np.linalg.norm(n)) <= tol:
            facts.add(("intersect", a.joint, b.joint))
    for name, p in points.items():
        own = set(name) if isinstance(name, tuple) else set()
        on = {a.joint for a in rev if a.joint not in own and distance_to_line(p, a) <= tol}
        facts |= {("on-axis", name, j) for j in on}
        for a, b in itertools.permutations(rev, 2):
            if a.joint in on or a.joint in own or parallel(a.direction, b.direction):
                continue
            n = np.cross(a.direction, b.direction)
            n /= np.linalg.norm(n)
            if abs(float((p - a.point) @ n)) <= tol:
                facts.add(("in-plane", name, a.joint, b.joint))
    # two design points that coincide (a wrist centre on a shoulder centre)
    named = [k for k in points if k != "P"]
    for x, y in itertools.combinations(sorted(named), 2):
        if float(np.linalg.norm(points[x] - points[y])) <= tol:
            facts.add(("coincide", x, y))
    # a prismatic joint sliding parallel to a revolute axis
    for s in (ln for ln in lines if ln.kind == "prismatic"):
        for a in rev:
            if parallel(s.direction, a.direction):
                facts.add(("slide-parallel", s.joint, a.joint))
    # planes of parallel axes, with or without a point
    for a, b in itertools.combinations(rev, 2):
        if not parallel(a.direction, b.direction) or distance_to_line(b.point, a) <= tol:
            continue
        n = np.cross(a.direction, b.point - a.point)
        n /= np.linalg.norm(n)
        members = frozenset(c.joint for c in rev if parallel(a.direction, c.direction)
                            and abs(float((c.point - a.point) @ n)) <= tol)
        if len(members) >= 3:
            facts.add(("coplanar", None, members))
        for name, p in points.items():
            own = set(name) if isinstance(name, tuple) else set()
            if not own & members and abs(float((p - a.point) @ n)) <= tol:
                facts.add(("coplanar", name, members))
    return facts


def dependent_joints(matrices, labels, columns=None) -> tuple:
    """The smallest set of columns that is rank deficient in every one of ``matrices``.

    A set counts as rank deficient when its smallest singular value is at most
    RANK_RTOL times the largest singular value of the whole matrix.  Returns the
    labels of the columns, or ``()`` when only the whole matrix is.  ``columns``
    (indices) limits the search to those columns.

    Examples
    --------
    >>> import numpy as np
    >>> J = np.array([[1.0, 2.0, 0.0], [0.0, 0.0, 1.0]])
    >>> dependent_joints([J], ["1", "2", "3"])
    ('1', '2')
    """
    Js = [np.asarray(J, dtype=float) for J in matrices]
    m, n = Js[0].shape
    pool = list(range(n)) if columns is None else list(columns)
    tops = [float(np.linalg.svd(J, compute_uv=False)[0]) for J in Js]
    for size in range(1, min(m, n - 1, len(pool)) + 1):
        for cols in itertools.combinations(pool, size):
            if all(float(np.linalg.svd(J[:, cols], compute_uv=False)[-1]) <= RANK_RTOL * top
                   for J, top in zip(Js, tops)):
                return tuple(labels[c] for c in cols)
    return ()


@dataclass(frozen=True)
class RobotPose:
    """The arm at one configuration (world frame)."""

    chain: np.ndarray             # (k, 3): base, every frame origin along the chain, task point
    axis_points: tuple            # a point of each joint axis
    axis_directions: tuple        # the unit direction of each joint axis
    kinds: tuple                  # "revolute" or "prismatic" per joint
    tool: np.ndarray              # the task point
    scale: float                  # the largest distance between two points of the chain
    tool_frame: np.ndarray | None = None  # (3, 3): the last frame's axes as columns

    @property
    def planar(self) -> bool:
        """Does the arm lie in the plane z = 0 with every revolute axis along z?"""
        tol = 1e-9 * self.scale
        flat = bool(np.all(np.abs(np.asarray(self.chain)[:, 2]) <= tol))
        return flat and all(abs(abs(float(d[2])) - 1.0) <= 1e-9 if k == "revolute"
                            else abs(float(d[2])) <= 1e-9
                            for d, k in zip(self.axis_directions, self.kinds))


def robot_pose(model, q: dict, params=None) -> RobotPose:
    """The :class:`RobotPose` of ``model`` at ``q`` (variable name -> value).

    Examples
    --------
    >>> from rankloci.io import load_model
    >>> pose = robot_pose(load_model("planar2r"), {"q1": 0.0, "q2": 0.0})
    >>> [float(x) for x in pose.tool], pose.scale
    ([2.0, 0.0, 0.0], 2.0)
    """
    lines, tool = axis_lines(model, q, params)
    qs = {v: float(q[str(v)]) for v in model.variables}
    poses = numeric_frames(model, qs, dict(model.parameters if params is None else params))
    chain = [poses[0][:3, 3]]
    for T in poses[1:]:
        p = T[:3, 3]
        if np.linalg.norm(p - chain[-1]) > 1e-12:
            chain.append(p)
    if np.linalg.norm(tool - chain[-1]) > 1e-12:
        chain.append(tool)
    chain = np.array(chain)
    diffs = chain[:, None, :] - chain[None, :, :]
    scale = max(float(np.max(np.linalg.norm(diffs, axis=-1))), 1e-9)
    return RobotPose(chain, tuple(ln.point for ln in lines), tuple(ln.direction for ln in lines),
                     tuple(ln.kind for ln in lines), np.asarray(tool, dtype=float), scale,
                     np.array(poses[-1][:3, :3], dtype=float))


# --- the facts of a component ------------------------------------------------------------------

@dataclass(frozen=True)
class ComponentFacts:
    """The geometric facts that hold on a component and at no random configuration.

    Attributes
    ----------
    whole : frozenset
        The facts (keys of :func:`facts_at`) that hold at every point of the
        component and at no random configuration.
    factors : tuple of (int, frozenset)
        For a component of several equations: for each (0-based index), the
        facts that hold wherever that equation alone vanishes (empty when it
        has no points); ``()`` for a component of one equation.
    design : frozenset
        The facts of the design: those that hold at a random configuration.
    meets : tuple of tuple of int
        The consecutive axes that meet at every configuration
        (:func:`design_points`).
    dependent : tuple of str
        The smallest set of joints (1-based, as strings) whose columns of J are
        dependent at every point, or ``()`` (none smaller than J, or no J given).
    dependent_fills_rows : bool
        Those columns are at least as many as the rows they reach: their
        dependence restates the locus (:func:`columns_fill_rows`).
    points : int
        How many points of the component the facts were checked on.
    """

    whole: frozenset
    factors: tuple
    design: frozenset
    meets: tuple
    dependent: tuple = ()
    dependent_fills_rows: bool = False
    points: int = 0


def design_facts(model, params, rng) -> tuple:
    """``(meets, design)``: the design points (:func:`design_points`) and the facts that hold
    at :data:`~rankloci.tolerances.RANDOM_POINTS` random configurations."""
    meets = design_points(model, params, rng)
    design = set()
    for _ in range(RANDOM_POINTS):
        design |= facts_at(model, random_configuration(model, rng), params, meets)
    return meets, frozenset(design)


def common_facts(model, qs, params, meets, design=frozenset()) -> frozenset:
    """The facts that hold at every configuration of ``qs`` and are not in ``design``."""
    common = None
    for q in qs:
        f = facts_at(model, q, params, meets)
        common = f if common is None else common & f
    return frozenset((common or set()) - design)


def columns_fill_rows(matrices, cols) -> bool:
    """Are ``cols`` at least as many as the rows they reach (a dependence that says nothing)?

    Where the other columns alone fill the remaining rows (a locked joint's row of an
    augmented J), the columns ``cols`` are dependent exactly where J is singular: naming
    them restates the locus.

    Examples
    --------
    >>> import numpy as np
    >>> J = np.array([[1.0, 2.0, 0.0], [1.0, 2.0, 1.0], [1.0, 2.0, 5.0]])
    >>> columns_fill_rows([J], [0, 1])
    False
    >>> J = np.array([[1.0, 2.0, 0.0], [2.0, 4.0, 0.0], [0.0, 0.0, 1.0]])
    >>> columns_fill_rows([J], [0, 1])   # the last row is the third joint's alone
    True
    """
    J = np.asarray(matrices[0], dtype=float)
    top = float(np.linalg.svd(J, compute_uv=False)[0])
    rows = [r for r in range(J.shape[0])
            if max(float(np.max(np.abs(np.asarray(M, dtype=float)[r, cols]))) for M in matrices)
            > RANK_RTOL * top]
    return len(cols) >= len(rows)


def component_facts(model, points, factor_points=(), rng=None, params=None,
                    matrix=None) -> ComponentFacts:
    """The geometric facts of one component of ``model``'s locus.

    Parameters
    ----------
    model : RobotModel
    points : sequence of dict
        Points of the component (variable name -> value); the first is its sample.
    factor_points : sequence of sequence of dict
        For each of the component's equations, points where it alone vanishes
        (the other joints free); read only when there are several.
    rng : numpy.random.Generator
        Draws the random configurations whose facts are design facts.
    params : dict, optional
        Parameter values (default: the model's).
    matrix : callable, optional
        J at a point (dict -> array, columns in joint order); with it, the
        smallest set of joints whose columns are dependent at every point.

    Examples
    --------
    >>> import numpy as np
    >>> from rankloci.io import load_model
    >>> puma = load_model("puma560")
    >>> q = {"q1": 0.3, "q2": 0.2, "q3": -0.4, "q4": 0.5, "q5": 0.0, "q6": 0.1}
    >>> f = component_facts(puma, [q, dict(q, q1=1.0, q4=-1.2)], rng=np.random.default_rng(0))
    >>> ("collinear", 4, 6) in f.whole     # the wrist: axes 4 and 6 in one line
    True
    >>> ("collinear", 4, 6) in f.design
    False
    """
    if rng is None:
        raise ValueError("component_facts needs rng, a numpy.random.Generator")
    meets, design = design_facts(model, params, rng)
    whole = common_facts(model, points, params, meets, design)
    dependent, fills = (), False
    if matrix is not None:
        Js = [matrix(q) for q in points]
        dependent = dependent_joints(Js, [str(k + 1) for k in range(len(model.joints))])
        fills = bool(dependent) and columns_fill_rows(Js, [int(c) - 1 for c in dependent])
    factors = ()
    if len(factor_points) > 1:
        factors = tuple((k, common_facts(model, qs, params, meets, design) if qs else frozenset())
                        for k, qs in enumerate(factor_points))
    return ComponentFacts(whole, factors, design, meets, dependent, fills, len(points))


def lost_rotation_axis(model, q: dict, params, joints) -> tuple:
    """The axis about which the revolute joints of ``joints`` cannot rotate the end-effector.

    When their axes (at least three) have a common normal at ``q``: that normal
    (unit, base frame, its largest coordinate positive); else ``()``.

    Examples
    --------
    >>> from rankloci.io import load_model
    >>> puma = load_model("puma560")
    >>> q = {"q1": 0.3, "q2": 0.2, "q3": -0.4, "q4": 0.5, "q5": 0.0, "q6": 0.1}
    >>> len(lost_rotation_axis(puma, q, None, [4, 5, 6]))
    3
    >>> lost_rotation_axis(puma, dict(q, q5=1.0), None, [4, 5, 6])
    ()
    """
    lines, _ = axis_lines(model, q, params)
    span = [lines[j - 1].direction for j in range(joints[0], joints[-1] + 1)
            if lines[j - 1].kind == "revolute"]
    if len(span) < 3:
        return ()
    _, s, vt = np.linalg.svd(np.array(span))
    if s[-1] > GEOMETRY_RTOL * s[0]:
        return ()
    n = vt[-1] * (1 if vt[-1][np.argmax(np.abs(vt[-1]))] > 0 else -1)
    return tuple(float(x) for x in n)


def design_point(lines, axes):
    """The point where the two axes ``axes`` (1-based, a pair of :func:`design_points`) meet."""
    m = meeting_point(lines[axes[0] - 1], lines[axes[1] - 1])
    return 0.5 * (m[0] + m[1])


def point_axis_distances(model, points, params, x, axis) -> list:
    """The distance, at each configuration of ``points``, from ``x`` to axis ``axis``.

    ``x`` is ``"P"`` (the task point) or a pair of axes that meet by design.
    """
    dists = []
    for q in points:
        lines, tool = axis_lines(model, q, params)
        p = tool if x == "P" else design_point(lines, x)
        dists.append(distance_to_line(p, lines[axis - 1]))
    return dists


def equal_distances(values) -> bool:
    """Are the non-negative ``values`` equal to :data:`~rankloci.tolerances.GEOMETRY_RTOL`
    of the largest?"""
    top = max(values)
    return top > 0 and top - min(values) <= GEOMETRY_RTOL * top


def centres_distance(model, q: dict, params, pair) -> tuple | None:
    """``(axis, distance)`` when two design points are equally far from the one other axis.

    ``pair`` holds two design points (each a pair of axes that meet by design).
    When exactly one revolute axis passes through neither and both points lie
    at one distance from it (to :data:`~rankloci.tolerances.GEOMETRY_RTOL`),
    turning that joint can bring them together: its number and the distance;
    else None.
    """
    lines, _ = axis_lines(model, q, params)
    through = set(pair[0]) | set(pair[1])
    rest = [ln for ln in lines if ln.kind == "revolute" and ln.joint not in through]
    if len(rest) != 1:
        return None
    axis = rest[0]
    dists = [distance_to_line(design_point(lines, x), axis) for x in pair]
    if abs(dists[0] - dists[1]) > GEOMETRY_RTOL * max(max(dists), 1e-12):
        return None
    return axis.joint, dists[0]


def dependence_left(matrix, points, factor_points, explained, n_joints: int) -> tuple:
    """``(dropped, rest)``: what the columns of J still lose where explained factors do not.

    Each factor of ``explained`` (indices into ``factor_points``, with points)
    makes one column depend on the others (the last of its smallest dependent
    set, ``dropped`` lists those joints, 1-based); ``rest`` is the smallest set
    of the remaining joints whose columns are dependent at every one of
    ``points`` (labels as strings, ``()`` if none).
    """
    cols = [str(k + 1) for k in range(n_joints)]
    keep = set(range(n_joints))
    for k in explained:
        if factor_points[k]:
            d = dependent_joints([matrix(q) for q in factor_points[k]], cols)
            keep -= {int(d[-1]) - 1} if d else set()
    rest = dependent_joints([matrix(q) for q in points], cols, sorted(keep))
    dropped = tuple(sorted(set(range(1, n_joints + 1)) - {c + 1 for c in keep}))
    return dropped, rest


# --- shapes a figure of the arm draws: computed here, drawn by the report ---------------------


def axis_line_ends(pose: RobotPose, joint: int) -> np.ndarray:
    """The two ends of the line of joint ``joint``'s axis (1-based), extended through the arm.

    The line runs along the axis from its point, as far as the arm reaches along that
    direction and half the arm's size beyond, so that every joint origin of the chain is
    passed on the way.

    Examples
    --------
    >>> from rankloci.io import load_model
    >>> pose = robot_pose(load_model("planar2r"), {"q1": 0.0, "q2": 0.0})
    >>> [[round(float(x), 2) + 0.0 for x in end] for end in axis_line_ends(pose, 1)]
    [[0.0, 0.0, -1.0], [0.0, 0.0, 1.0]]
    """
    p = np.asarray(pose.axis_points[joint - 1], dtype=float)
    d = np.asarray(pose.axis_directions[joint - 1], dtype=float)
    d = d / np.linalg.norm(d)
    s = (np.asarray(pose.chain, dtype=float) - p) @ d
    lo, hi = float(min(s.min(), 0.0)), float(max(s.max(), 0.0))
    margin = 0.5 * pose.scale
    return np.array([p + (lo - margin) * d, p + (hi + margin) * d])


def plane_through_axis(pose: RobotPose, joint: int) -> np.ndarray | None:
    """The four corners of the plane through joint ``joint``'s axis and the task point, as
    wide as the arm; None when the task point lies on that axis (no plane is defined).

    Examples
    --------
    >>> from rankloci.io import load_model
    >>> pose = robot_pose(load_model("planar2r"), {"q1": 0.0, "q2": 0.0})
    >>> corners = plane_through_axis(pose, 1)
    >>> corners.shape, bool(np.allclose(corners[:, 1], 0.0))   # the plane y = 0
    ((4, 3), True)
    """
    p = np.asarray(pose.axis_points[joint - 1], dtype=float)
    d = np.asarray(pose.axis_directions[joint - 1], dtype=float)
    d = d / np.linalg.norm(d)
    r = np.asarray(pose.tool, dtype=float) - p
    u = r - (r @ d) * d
    if np.linalg.norm(u) <= 1e-9 * pose.scale:
        return None
    u = u / np.linalg.norm(u)
    half = 0.6 * pose.scale
    reach = max(float(r @ u), 0.0)
    along = np.array([r @ d - half, r @ d + half])
    across = np.array([-0.2 * pose.scale, reach + 0.2 * pose.scale])
    return np.array([p + s * d + t * u for s, t in ((along[0], across[0]), (along[1], across[0]),
                                                     (along[1], across[1]), (along[0], across[1]))])


def box_edges(centre, direction, length: float, width: float) -> list:
    """The 12 edges of a box of square section along ``direction`` (3-D), each a (2, 3) array.

    Examples
    --------
    >>> edges = box_edges([0.0, 0.0, 0.0], [0.0, 0.0, 1.0], 2.0, 1.0)
    >>> len(edges), sorted({round(float(np.linalg.norm(e[1] - e[0])), 6) for e in edges})
    (12, [1.0, 2.0])
    """
    d = np.asarray(direction, dtype=float)
    u = np.cross(d, [1.0, 0.0, 0.0] if abs(d[0]) < 0.9 else [0.0, 1.0, 0.0])
    u /= np.linalg.norm(u)
    v = np.cross(d, u)
    corners = [np.asarray(centre) + a * length / 2 * d + b * width / 2 * u + c * width / 2 * v
               for a in (-1, 1) for b in (-1, 1) for c in (-1, 1)]
    pairs = [(i, j) for i in range(8) for j in range(i + 1, 8) if bin(i ^ j).count("1") == 1]
    return [np.array([corners[i], corners[j]]) for i, j in pairs]


def rectangle_along(point, direction, length: float, width: float) -> list:
    """The four corners of a rectangle in the plane, centred at ``point`` (2-D), its long side
    along ``direction`` (the first two coordinates are used).

    Examples
    --------
    >>> [[float(x) for x in c] for c in rectangle_along([0.0, 0.0], [2.0, 0.0], 2.0, 1.0)]
    [[-1.0, -0.5], [1.0, -0.5], [1.0, 0.5], [-1.0, 0.5]]
    """
    d2 = np.asarray(direction[:2], dtype=float)
    d2 = d2 / max(np.linalg.norm(d2), 1e-12)
    n2 = np.array([-d2[1], d2[0]])
    p = np.asarray(point[:2], dtype=float)
    return [p + a * length / 2 * d2 + b * width / 2 * n2 for a, b in
            ((-1, -1), (1, -1), (1, 1), (-1, 1))]


def scaled_to(vector, length: float) -> np.ndarray | None:
    """``vector`` scaled to ``length``, or None when it is zero.

    Examples
    --------
    >>> scaled_to([3.0, 4.0], 10.0).tolist(), scaled_to([0.0, 0.0], 1.0)
    ([6.0, 8.0], None)
    """
    v = np.asarray(vector, dtype=float)
    n = float(np.linalg.norm(v))
    return None if n == 0.0 else v / n * length


def motion_arrow(linear, angular, small: float):
    """Which part of a lost direction an arrow at the task point shows.

    ``linear`` and ``angular`` are its translational and rotational parts (3-vectors); a part
    counts when it is longer than ``small``.  Returns (vector, kind): the translation when it
    is alone (``"translation"``), the rotation axis when it is alone (``"rotation"``), the
    translation when both count (``"translation part"``), or (None, None) when neither does.

    Examples
    --------
    >>> motion_arrow([0.0, 0.0, 1.0], [0.0, 0.0, 0.0], 1e-3)[1]
    'translation'
    >>> motion_arrow([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], 1e-3)[1]
    'rotation'
    >>> motion_arrow([0.5, 0.0, 0.0], [0.0, 0.7, 0.0], 1e-3)[1]
    'translation part'
    """
    a = np.asarray(linear, dtype=float)
    b = np.asarray(angular, dtype=float)
    la, lb = float(np.linalg.norm(a)), float(np.linalg.norm(b))
    if la > small and lb <= small:
        return a, "translation"
    if lb > small and la <= small:
        return b, "rotation"
    if la > small:
        return a, "translation part"
    return None, None
