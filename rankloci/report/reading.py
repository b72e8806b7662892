"""Plain-language readings of a singularity, each verified numerically.

Two kinds of statement are made about a component of the locus:

- **geometry** (robots only): at points of the component, joint axes become
  collinear, parallel or intersecting, or the task point falls on an axis or
  into the plane of two parallel axes, where that does *not* hold at random
  configurations (so it is a property of the singularity, not of the design);
- **the lost direction**: ``u^T J = 0`` at the sample point, read as "the
  task point cannot translate along ...", "the end-effector cannot rotate
  about ..." or, for a mixed direction, the linear relation every achievable
  velocity obeys (equivalently, a wrench the structure resists with zero
  joint torques).

A statement is returned only when it holds numerically at the component's
sample point (and, for geometry, at the other points of the component it is
tested on) within the tolerances below.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np
import sympy as sp

from ..model import RobotModel

__all__ = ["AxisLine", "axis_lines", "geometry_readings", "direction_readings", "lost_motion",
           "GEOMETRY_RTOL", "DIRECTION_RTOL"]

#: Two unit axis directions count as parallel, and distances as zero relative to the size of
#: the arm, below this.  Points on a component are accurate to ~1e-12 (ROOT_XTOL); random
#: configurations keep these quantities of order 1e-2 and above, so 1e-7 separates them
#: with five orders of margin on either side.
GEOMETRY_RTOL = 1e-7

#: ``|u^T J| <= DIRECTION_RTOL * sigma_max(J)`` verifies a lost direction at the sample
#: point: rank decisions use RANK_RTOL = 1e-8 on sigma_min/sigma_max, and the direction is
#: printed to 3 decimals, so 1e-6 is checked on the unrounded vector.
DIRECTION_RTOL = 1e-6

_RANDOM_CONFIGURATIONS = 4


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
    from ..kinematics import numeric_frames

    params = dict(model.parameters if params is None else params)
    qs = {v: float(q[str(v)]) for v in model.variables}
    poses = numeric_frames(model, qs, params)
    values = {k: float(v) for k, v in params.items()}
    lines = []
    for i, j in enumerate(model.joints):
        T = poses[3 * i + 2]
        axis = np.array([float(sp.sympify(a).subs(values)) for a in j.axis])
        d = T[:3, :3] @ axis
        lines.append(AxisLine(i + 1, j.kind, T[:3, 3].copy(), d / np.linalg.norm(d)))
    return lines, poses[-1][:3, 3].copy()


# --- geometric predicates ---------------------------------------------------------------------

def _parallel(a: AxisLine, b: AxisLine) -> bool:
    return np.linalg.norm(np.cross(a.direction, b.direction)) <= GEOMETRY_RTOL


def _distance_to_line(p, line: AxisLine) -> float:
    r = p - line.point
    return float(np.linalg.norm(r - (r @ line.direction) * line.direction))


def _facts(lines, tool, scale):
    """Every geometric fact that holds at this configuration, as hashable keys.

    ``("plane", members)``: parallel revolute axes (and ``"P"``, the task point)
    that lie in one plane, at least three members.
    """
    tol = GEOMETRY_RTOL * scale
    rev = [ln for ln in lines if ln.kind == "revolute"]
    facts = set()
    on_axis = {a.joint for a in rev if _distance_to_line(tool, a) <= tol}
    for j in on_axis:
        facts.add(("point-on-axis", j))
    for a, b in itertools.permutations(rev, 2):
        # the task point in the plane through axis a parallel to the (non-parallel) axis b
        if a.joint in on_axis or _parallel(a, b):
            continue
        n = np.cross(a.direction, b.direction)
        n /= np.linalg.norm(n)
        if abs((tool - a.point) @ n) <= tol:
            facts.add(("point-in-plane-parallel", a.joint, b.joint))
    for a, b in itertools.combinations(rev, 2):
        if _parallel(a, b):
            if _distance_to_line(b.point, a) <= tol:
                facts.add(("collinear", a.joint, b.joint))
                continue
            facts.add(("parallel", a.joint, b.joint))
            n = np.cross(a.direction, b.point - a.point)
            n /= np.linalg.norm(n)
            members = {a.joint, b.joint}
            members |= {c.joint for c in rev if c.joint not in members and _parallel(a, c)
                        and abs((c.point - a.point) @ n) <= tol}
            # the task point counts only when it is not on one of the axes (then it adds nothing)
            if abs((tool - a.point) @ n) <= tol and not (members & on_axis):
                members.add("P")
            if len(members) >= 3:
                facts.add(("plane", frozenset(members)))
        else:
            n = np.cross(a.direction, b.direction)
            if abs((b.point - a.point) @ n) / np.linalg.norm(n) <= tol:
                facts.add(("intersect", a.joint, b.joint))
    pris = [ln for ln in lines if ln.kind == "prismatic"]
    for a, b in itertools.combinations(pris, 2):
        if _parallel(a, b):
            facts.add(("parallel-prismatic", a.joint, b.joint))
    return facts


def _scale(lines, tool) -> float:
    pts = [ln.point for ln in lines] + [tool]
    return max(max(float(np.linalg.norm(p - q)) for p in pts for q in pts), 1e-9)


def _facts_at(model, q, params):
    lines, tool = axis_lines(model, q, params)
    return _facts(lines, tool, _scale(lines, tool))


#: At most this many geometric sentences per component: the most telling ones.
MAX_GEOMETRY_SENTENCES = 3


def _phrase_groups(facts) -> list[str]:
    """Sentences for the most telling facts.

    Collinear axes, the task point on an axis and coplanar parallel axes come
    first; then axes that become parallel; the task point in a plane through an
    axis only when none of those holds, and intersecting axes only when nothing
    else does (they mostly follow from the others).
    """
    tier1 = []
    for a, b in sorted(f[1:] for f in facts if f[0] == "collinear"):
        tier1.append(("collinear", a, b, f"axes {a} and {b} are collinear"))
    on_axis = sorted(f[1] for f in facts if f[0] == "point-on-axis")
    if on_axis:
        word = "axis" if len(on_axis) == 1 else "axes"
        tier1.append(("on-axis", on_axis[0], None,
                      f"the task point lies on {word} {_and(on_axis)}"))
    planes = [f[1] for f in facts if f[0] == "plane"]
    # keep the largest planes only (a plane of 2, 3, 4 also yields one of 2, 3)
    planes = [p for p in planes if not any(p < q for q in planes)]
    for members in sorted(planes, key=lambda m: sorted(str(x) for x in m)):
        axes = sorted(x for x in members if x != "P")
        if "P" in members and len(axes) == 2:
            text = (f"axes {axes[0]} and {axes[1]} are parallel and the task point lies in "
                    "the plane they span")
        elif "P" in members:
            text = f"axes {_and(axes)} are parallel and the task point lies in their common plane"
        else:
            text = f"axes {_and(axes)} are parallel and lie in one plane"
        tier1.append(("plane", axes[0], axes[1] if len(axes) == 2 and "P" in members else None,
                      text))
    if tier1:
        return [t[3] for t in tier1][:MAX_GEOMETRY_SENTENCES]
    pairs = {tuple(f[1:]) for f in facts if f[0] == "parallel"}
    out = []
    while pairs:
        count: dict = {}
        for a, b in pairs:
            count[a] = count.get(a, 0) + 1
            count[b] = count.get(b, 0) + 1
        axis = min(count, key=lambda k: (-count[k], k))
        partners = sorted(b if a == axis else a for a, b in pairs if axis in (a, b))
        out.append(f"axes {axis} and {partners[0]} are parallel" if len(partners) == 1
                   else f"axis {axis} is parallel to axes {_and(partners)}")
        pairs = {p for p in pairs if axis not in p}
    if out:
        return out[:MAX_GEOMETRY_SENTENCES]
    through: dict = {}
    for f in sorted(f for f in facts if f[0] == "point-in-plane-parallel"):
        through.setdefault(f[1], []).append(f[2])
    if through:
        a = min(through)
        bs = through[a]
        word = "axis" if len(bs) == 1 else "axes"
        return [f"the task point lies in the plane through axis {a} parallel to {word} "
                f"{_and(bs)}"]
    out = [f"axes {a} and {b} intersect" for a, b in
           sorted(f[1:] for f in facts if f[0] == "intersect")]
    out += [f"the prismatic axes {a} and {b} are parallel" for a, b in
            sorted(f[1:] for f in facts if f[0] == "parallel-prismatic")]
    return out[:MAX_GEOMETRY_SENTENCES]


def _and(items) -> str:
    items = [str(x) for x in items]
    return items[0] if len(items) == 1 else ", ".join(items[:-1]) + " and " + items[-1]


def geometry_readings(model, points, rng, params=None) -> list[str]:
    """Geometric facts that hold at every one of ``points`` and at no random configuration.

    Parameters
    ----------
    model : RobotModel
        A :class:`~rankloci.model.MatrixModel` gives no reading.
    points : sequence of dict
        Points of one component (variable name -> value); the first is its sample.
    rng : numpy.random.Generator
        Draws the random configurations that tell design facts from singular ones.
    params : dict, optional
        Parameter values (default: the model's).

    Examples
    --------
    >>> import numpy as np
    >>> from rankloci.io import load_model
    >>> puma = load_model("puma560")
    >>> geometry_readings(puma, [{"q1": 0.3, "q2": 0.2, "q3": -0.4, "q4": 0.5, "q5": 0.0,
    ...                           "q6": 0.1}], np.random.default_rng(0))
    ['axes 4 and 6 are collinear']
    """
    if not isinstance(model, RobotModel) or not points:
        return []
    common = None
    for q in points:
        f = _facts_at(model, q, params)
        common = f if common is None else common & f
    if not common:
        return []
    for _ in range(_RANDOM_CONFIGURATIONS):
        q = {str(v): (rng.uniform(-np.pi, np.pi) if j.kind == "revolute" else rng.normal())
             for v, j in zip(model.variables, model.joints)}
        common -= _facts_at(model, q, params)
        if not common:
            return []
    return _phrase_groups(common)


# --- lost directions ---------------------------------------------------------------------------

_LINEAR, _ANGULAR = ("vx", "vy", "vz"), ("wx", "wy", "wz")


def _vec(values, digits=3) -> str:
    return "[" + ", ".join(f"{x:+.{digits}f}" for x in values) + "]"


def direction_readings(J, u, row_labels, *, tall: bool = False, frame: str = "base",
                       variables=()) -> list[str]:
    """Read the lost direction ``u`` of ``J`` (numeric, at the sample point) in words.

    Parameters
    ----------
    J : numpy.ndarray
        The matrix at the sample point, rows as in ``row_labels``.
    u : sequence of float
        A left null vector of J (a right null vector when ``tall``).
    row_labels : sequence of str
        ``vx vy vz wx wy wz`` for task rows; anything else is a constraint row.
    frame : str
        Name of the frame the rows are expressed in (for the wording).

    Returns the empty list when ``u`` is not a null vector of ``J`` to
    :data:`DIRECTION_RTOL` (nothing is claimed then).

    Examples
    --------
    >>> import numpy as np
    >>> J = np.array([[0.0, 0.0], [2.0, 1.0]])
    >>> direction_readings(J, [1.0, 0.0], ["vx", "vy"])
    ['the task point cannot translate along [+1.000, +0.000] over (x, y) in the base frame']
    """
    J = np.asarray(J, dtype=float)
    u = np.asarray(u, dtype=float)
    smax = float(np.linalg.svd(J, compute_uv=False)[0]) if J.size else 0.0
    if smax == 0.0 or np.linalg.norm(u) == 0.0:
        return []
    u = u / np.linalg.norm(u)
    residual = np.linalg.norm((J @ u) if tall else (u @ J))
    if residual > DIRECTION_RTOL * smax:
        return []
    if tall:
        names = ", ".join(str(v) for v in variables) if variables else "the joint variables"
        return [f"the joint velocity {_vec(u)} over ({names}) moves nothing: J q' = 0 there, a "
                "self-motion of the joints that the task does not see"]
    labels = list(row_labels)
    lin = np.array([u[labels.index(r)] if r in labels else 0.0 for r in _LINEAR])
    ang = np.array([u[labels.index(r)] if r in labels else 0.0 for r in _ANGULAR])
    others = [(lab, x) for lab, x in zip(labels, u) if lab not in _LINEAR + _ANGULAR]
    small = 1e-3  # directions are read to 3 decimals
    n_lin, n_ang = np.linalg.norm(lin), np.linalg.norm(ang)
    n_other = float(np.sqrt(sum(x * x for _, x in others)))
    missing_lin = [r[1] for r in _LINEAR if r not in labels]
    missing_ang = [r[1] for r in _ANGULAR if r not in labels]
    out = []
    if n_other <= small and n_ang <= small and n_lin > small:
        present = [r for r in _LINEAR if r in labels]
        vec = np.array([u[labels.index(r)] for r in present]) / n_lin
        out.append(f"the task point cannot translate along {_vec(vec)}"
                   f"{_rows_note(present, missing_lin, frame)}")
    elif n_other <= small and n_lin <= small and n_ang > small:
        present = [r for r in _ANGULAR if r in labels]
        vec = np.array([u[labels.index(r)] for r in present]) / n_ang
        out.append(f"the end-effector cannot rotate about {_vec(vec)}"
                   f"{_rows_note(present, missing_ang, frame)}")
    elif n_other <= small:
        out.append(f"every end-effector velocity (v, w) the joints can produce has a.v + b.w = 0, "
                   f"a = {_vec(lin)}, b = {_vec(ang)} ({frame} frame, v at the task point): "
                   "the force a with the moment b about the task point needs no joint torque "
                   "to be held")
    else:
        def rate(lab):
            return lab if lab in _LINEAR + _ANGULAR else f"d({lab})/dt"

        terms = " ".join(f"{x:+.3f} {rate(lab)}" for lab, x in zip(labels, u) if abs(x) > small)
        out.append(f"the task velocity and the constraint rate are tied: {terms} = 0 for every "
                   "joint velocity")
    return out


def _rows_note(present, missing, frame) -> str:
    if missing:
        axes = ", ".join(r[1] for r in present)
        return f" over ({axes}) in the {frame} frame"
    return f" (x, y, z of the {frame} frame)"


def lost_motion(J, u, row_labels, *, tall: bool = False, variables=()) -> str:
    """The motion lost along the null vector ``u`` of ``J``, in a few words for a table.

    The same classification as :func:`direction_readings` (and the same
    check: ``""`` when ``u`` is not a null vector of ``J``), without the
    explanation: a translation, a rotation, a translation combined with a
    rotation, or a combination of task and constraint rates.  Numbers have two
    decimals (the component's subsection gives the direction to three).

    Examples
    --------
    >>> import numpy as np
    >>> J = np.array([[0.0, 0.0], [2.0, 1.0]])
    >>> lost_motion(J, [1.0, 0.0], ["vx", "vy"])
    'translation along [+1.00, +0.00] (x, y)'
    >>> J = np.array([[1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])
    >>> print(lost_motion(J, [1.0, 1.0, -1.0], ["vx", "vy", "wz"]))
    ... # doctest: +NORMALIZE_WHITESPACE
    translation a with rotation b: a = [+0.58, +0.58, +0.00], b = [+0.00, +0.00, -0.58]
    """
    J = np.asarray(J, dtype=float)
    u = np.asarray(u, dtype=float)
    smax = float(np.linalg.svd(J, compute_uv=False)[0]) if J.size else 0.0
    if smax == 0.0 or np.linalg.norm(u) == 0.0:
        return ""
    u = u / np.linalg.norm(u)
    if np.linalg.norm((J @ u) if tall else (u @ J)) > DIRECTION_RTOL * smax:
        return ""
    if tall:
        names = ", ".join(str(v) for v in variables) if variables else "the joints"
        return f"none: the joint motion {_vec(u, 2)} over ({names}) moves nothing"
    labels = list(row_labels)
    small = 1e-3
    lin = [(r, u[labels.index(r)]) for r in _LINEAR if r in labels]
    ang = [(r, u[labels.index(r)]) for r in _ANGULAR if r in labels]
    others = [(lab, x) for lab, x in zip(labels, u) if lab not in _LINEAR + _ANGULAR]
    n_lin = float(np.sqrt(sum(x * x for _, x in lin)))
    n_ang = float(np.sqrt(sum(x * x for _, x in ang)))
    n_other = float(np.sqrt(sum(x * x for _, x in others)))

    def along(rows, norm):
        axes = ", ".join(r[1] for r, _ in rows)
        return f"{_vec([x / norm for _, x in rows], 2)} ({axes})"

    if n_other <= small and n_ang <= small:
        return f"translation along {along(lin, n_lin)}"
    if n_other <= small and n_lin <= small:
        return f"rotation about {along(ang, n_ang)}"
    if n_other <= small:
        a = np.array([u[labels.index(r)] if r in labels else 0.0 for r in _LINEAR])
        b = np.array([u[labels.index(r)] if r in labels else 0.0 for r in _ANGULAR])
        return f"translation a with rotation b: a = {_vec(a, 2)}, b = {_vec(b, 2)}"

    def rate(lab):
        return lab if lab in _LINEAR + _ANGULAR else f"d({lab})/dt"

    terms = " ".join(f"{x:+.2f} {rate(lab)}" for lab, x in zip(labels, u) if abs(x) > small)
    return f"task and constraint rates together: {terms}"
