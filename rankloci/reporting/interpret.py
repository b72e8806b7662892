"""One complete reading of each component: what every one of its equations does to the arm.

A component of a robot's locus is cut out by one or more equations (its
factors).  :func:`component_reading` says, for each factor, which geometric
facts hold wherever that factor alone vanishes (sampled points of its
hypersurface, not of the component) and at no random configuration; then
which facts hold on the component but on no single factor's hypersurface
(they need the factors together).  From these it names the classical case
when the geometry makes one clear (shoulder, elbow, wrist, all links
aligned), and for collinear axes it names the rotation the joints between
them lose.  Every statement is checked at several points; nothing is read
from the model's name.

The facts are about joint axes (collinear, parallel, perpendicular,
intersecting) and about points that the design fixes on the axes: the task
point and the meeting points of consecutive axes that meet at every
configuration (the centre of a spherical wrist, the shoulder point of an arm
whose first two axes meet).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np

from ..model import RobotModel
from .blocks import plural, signed
from ..geometry import (axis_lines, dependent_joints, design_points, distance_to_line, facts_at,
                        meeting_point, random_configuration)
from ..tolerances import GEOMETRY_RTOL, RANDOM_POINTS

__all__ = ["Reading", "component_reading", "FACTOR_POINTS"]

#: Points sampled on each factor's hypersurface, and on the component besides its sample.
FACTOR_POINTS = 3


@dataclass(frozen=True)
class Reading:
    """The reading of one component.

    Attributes
    ----------
    name : str
        The classical case ("shoulder singularity", ...) or "" when none is clear.
    text : str
        One sentence covering every factor (with its name in front when there is one).
    factors : tuple of (int, str)
        For each factor (0-based index into the component's equations) what it does alone.
    joint : str
        What the factors do only together ("" if nothing beyond the factors).
    lost_rotation : str
        For collinear axes: the rotation the joints between them cannot produce.
    points : int
        How many points of the component the facts were checked on.
    axes : tuple of int
        The joints whose axes the reading names.
    lost_axis : tuple of float
        The axis of ``lost_rotation`` (unit, base frame) or ``()``.
    short : str
        The name and the first fact of each factor, for a summary table.
    """

    name: str
    text: str
    factors: tuple = ()
    joint: str = ""
    lost_rotation: str = ""
    points: int = 0
    axes: tuple = ()
    lost_axis: tuple = ()
    short: str = ""


# --- reading the facts -------------------------------------------------------------------------

def _and(items) -> str:
    items = [str(x) for x in items]
    return items[0] if len(items) == 1 else ", ".join(items[:-1]) + " and " + items[-1]


def _point_name(x, meets_all) -> str:
    if x == "P":
        return "the task point"
    return f"the point where axes {_and(x)} meet"


def _groups(pairs):
    """Connected groups of joints from pairs (collinear axes form lines)."""
    groups = []
    for a, b in sorted(pairs):
        hit = [g for g in groups if a in g or b in g]
        merged = set().union({a, b}, *hit)
        groups = [g for g in groups if g not in hit] + [merged]
    return sorted((sorted(g) for g in groups), key=lambda g: g[0])


def _always_parallel(design, a, b) -> bool:
    """Are axes ``a`` and ``b`` parallel at every pose (a design fact)?"""
    a, b = sorted((a, b))
    return ("parallel", a, b) in design or ("collinear", a, b) in design


def _new_parallel_axes(group, design) -> list:
    """The axes of a parallel ``group`` that say what is new here.

    Axes parallel to each other at every pose form a class; each class with
    more than one axis is named by its member nearest (in joint number) to the
    other classes.  UR5: 2, 3 and 4 are always parallel, so the group 2, 3, 4, 6
    reads as axes 4 and 6.

    Examples
    --------
    >>> _new_parallel_axes([2, 3, 4, 6], {("parallel", 2, 3), ("parallel", 2, 4),
    ...                                   ("parallel", 3, 4)})
    [4, 6]
    >>> _new_parallel_axes([2, 5], set())
    [2, 5]
    """
    classes: list[list[int]] = []
    for a in group:
        home = next((c for c in classes if _always_parallel(design, a, c[0])), None)
        if home is None:
            classes.append([a])
        else:
            home.append(a)
    if len(classes) < 2:
        return list(group)
    out = []
    for c in classes:
        others = [x for d in classes if d is not c for x in d]
        out.append(min(c, key=lambda x: (min(abs(x - y) for y in others), -x)))
    return sorted(out)


def _sentences(facts, meets, context=None, design=frozenset()) -> list:
    """The most telling facts in words, most telling first (each with its kind).

    ``context`` (default ``facts``) is the whole set the facts come from: a plane of
    axes is not read where those axes are parallel only here (the parallelism is).
    ``design`` holds the facts true at every pose: a parallelism among them is not
    stated as if it were a property of the component.
    """
    context = facts if context is None else context
    out = []
    for f in sorted((f for f in facts if f[0] == "coincide"), key=str):
        out.append(("coincide", (f[1], f[2]),
                    f"{_point_name(f[2], meets)} coincides with {_point_name(f[1], meets)}"))
    for g in _groups(f[1:] for f in facts if f[0] == "collinear"):
        out.append(("collinear", tuple(g), f"axes {_and(g)} are collinear"))
    for f in sorted(f for f in facts if f[0] == "slide-parallel"):
        # a slide parallel by design to an axis collinear here with axis f[2] says no more
        if any(g[0] == "slide-parallel" and g[1] == f[1]
               and any(h[0] == "collinear" and set(h[1:]) == {g[2], f[2]}
                       for h in context)
               for g in design):
            continue
        out.append(("slide-parallel", (f[1], f[2]),
                    f"the prismatic joint {f[1]} slides parallel to axis {f[2]}"))
    for f in sorted((f for f in facts if f[0] == "on-axis"), key=str):
        out.append(("on-axis", (f[1], f[2]), f"{_point_name(f[1], meets)} lies on axis {f[2]}"))
    new_parallel = {frozenset(f[1:]) for f in context if f[0] in ("parallel", "collinear")}
    # a plane of axes that are parallel only here follows from that parallelism: not read
    planes = [f for f in facts if f[0] == "coplanar"
              and not any(frozenset(p) in new_parallel for p in itertools.combinations(f[2], 2))]
    biggest = [f for f in planes if not any(f[2] < g[2] and f[1] == g[1] for g in planes)]
    for f in sorted(biggest, key=lambda f: (f[1] is None, str(f))):
        axes = sorted(f[2])
        always = all(_always_parallel(design, a, b) for a, b in itertools.combinations(axes, 2))
        if f[1] is None:
            if any(g[1] is not None and g[2] >= f[2] for g in biggest):
                continue
            out.append(("coplanar", (None, tuple(axes)),
                        f"axes {_and(axes)} " + ("lie in one plane" if always
                                                 else "are parallel and lie in one plane")))
        elif always:
            out.append(("coplanar", (f[1], tuple(axes)),
                        f"{_point_name(f[1], meets)} lies in the plane of axes {_and(axes)}"))
        else:
            out.append(("coplanar", (f[1], tuple(axes)),
                        f"axes {_and(axes)} are parallel and {_point_name(f[1], meets)} lies in "
                        "their plane"))
    if out:
        return out
    pairs = sorted(f[1:] for f in facts if f[0] == "parallel")
    for g in _groups(pairs):
        named = _new_parallel_axes(g, design)
        out.append(("parallel", tuple(named), f"axes {_and(named)} are parallel"))
    through: dict = {}
    for f in sorted((f for f in facts if f[0] == "in-plane"), key=str):
        through.setdefault((f[1], f[2]), []).append(f[3])
    through = {k: sorted(v) for k, v in through.items()}
    for (x, a), bs in sorted(through.items(), key=lambda kv: (kv[0][0] != "P", str(kv[0]))):
        word = "axis" if len(bs) == 1 else "axes"
        out.append(("in-plane", (x, a, tuple(bs)),
                    f"{_point_name(x, meets)} lies in the plane through axis {a} parallel to "
                    f"{word} {_and(bs)}"))
        break
    if out:
        return out
    for kind, verb in (("perpendicular", "are perpendicular"), ("intersect", "meet")):
        for a, b in sorted(f[1:] for f in facts if f[0] == kind):
            out.append((kind, (a, b), f"axes {a} and {b} {verb}"))
    return out


def _common(model, qs, params, meets, random_facts):
    common = None
    for q in qs:
        f = facts_at(model, q, params, meets)
        common = f if common is None else common & f
    return (common or set()) - random_facts


def _arm_position(model, joint) -> tuple[int, int]:
    """Position of ``joint`` among the last (at most seven) revolute joints, and their count."""
    rev = [k + 1 for k, j in enumerate(model.joints) if j.kind == "revolute"]
    arm = rev[-7:]
    return (arm.index(joint) + 1 if joint in arm else 0), len(arm)


def _name(model, kind, what, meets) -> str:
    """The classical case a sentence describes, decided from the joints it involves."""
    rev = [k + 1 for k, j in enumerate(model.joints) if j.kind == "revolute"]
    if not rev:
        return ""
    if kind == "coplanar" and what[0] is not None and set(what[1]) == set(rev):
        return "all links aligned"
    if kind == "coincide":
        ends = any(rev[0] in x for x in what) and any(rev[-1] in x for x in what)
        return "wrist centre on the shoulder" if ends else ""
    if kind == "slide-parallel":
        return "shoulder singularity" if what[1] == rev[0] else ""
    if kind == "parallel" and len(what) == 2 and len(model.joints) >= 6:
        mids = [_arm_position(model, j)[0] for j in what]
        n = _arm_position(model, what[0])[1]
        if min(mids) >= n - 2:
            return "wrist singularity"
        if min(mids) >= 1 and max(mids) <= 3:
            return "shoulder singularity"
    if kind == "collinear" and len(model.joints) >= 6:
        pos = [_arm_position(model, j) for j in what]
        n = pos[0][1]
        mids = [p for p, _ in pos]
        if min(mids) >= n - 2 and len(what) == 2:
            return "wrist singularity"
        if max(mids) <= 3 and len(what) == 2 and min(mids) >= 1:
            return "shoulder singularity"
        if len(what) == 2 and 2 <= min(mids) and max(mids) <= n - 1:
            return "elbow singularity"
        return ""
    if kind in ("on-axis", "in-plane") and what[1] == rev[0] and (
            what[0] == "P" or rev[0] not in what[0]):
        return "shoulder singularity"
    if kind == "coplanar" and (what[0] is not None or list(what[1]) == list(
            range(what[1][0], what[1][0] + len(what[1])))):
        return "elbow singularity"
    if kind == "parallel" and len(rev) >= 6 and rev[-1] in what and len(what) >= 3:
        return "wrist singularity"
    return ""


#: The order in which the names of several classical cases are joined.
_ORDER = ("boom", "shoulder", "elbow", "wrist", "wrist centre on the shoulder")


def _boom_at_zero(model, equations) -> int:
    """The prismatic joint (1-based) that one of ``equations`` fixes at zero length, or 0."""
    import sympy as sp

    for k, (v, j) in enumerate(zip(model.variables, model.joints)):
        if j.kind != "prismatic":
            continue
        for e in equations:
            e = sp.sympify(e, strict=True)
            if e.free_symbols == {v} and sp.Poly(e, v).degree() == 1 and e.subs(v, 0) == 0:
                return k + 1
    return 0


def _centres_remark(model, points, params, used) -> str:
    """Why two design points can coincide, and what that costs the rank."""
    what = next((w for kind, w, _ in used if kind == "coincide"), None)
    if what is None:
        return ""
    lines, _ = axis_lines(model, points[0], params)
    through = set(what[0]) | set(what[1])
    rest = [ln for ln in lines if ln.kind == "revolute" and ln.joint not in through]
    if len(rest) != 1:
        return ""
    axis = rest[0]
    dists = []
    for x in what:
        m = meeting_point(lines[x[0] - 1], lines[x[1] - 1])
        dists.append(distance_to_line(0.5 * (m[0] + m[1]), axis))
    if abs(dists[0] - dists[1]) > GEOMETRY_RTOL * max(max(dists), 1e-12):
        return ""
    return (f"both points lie {dists[0]:.4g} length units from axis {axis.joint} (equal link "
            f"lengths on either side of joint {axis.joint}), so turning joint {axis.joint} can "
            f"bring them together; then every axis but {axis.joint} passes through one point, "
            f"those joints give only rotations about it, and with joint {axis.joint} the rank of "
            "J is at most 4")


_GLOSS = {
    "all links aligned": "the arm is stretched out or folded back",
    "elbow singularity": "the arm is stretched out or folded back",
}


def _lost_rotation(model, q, params, group) -> str:
    """The rotation that the joints from the first to the last of collinear ``group`` lose."""
    lines, _ = axis_lines(model, q, params)
    span = [lines[j - 1].direction for j in range(group[0], group[-1] + 1)
            if lines[j - 1].kind == "revolute"]
    if len(span) < 3:
        return "", ()
    _, s, vt = np.linalg.svd(np.array(span))
    if s[-1] > GEOMETRY_RTOL * s[0]:
        return "", ()
    n = vt[-1] * (1 if vt[-1][np.argmax(np.abs(vt[-1]))] > 0 else -1)
    joints = f"joints {group[0]} to {group[-1]}"
    return (f"{joints} together cannot rotate the end-effector about the common normal "
            f"[{', '.join(signed(x, 3) for x in n)}] (base frame) of their axes at the sample "
            "point; the other joints give that rotation only together with a translation",
            tuple(float(x) for x in n))


def _offset_remark(model, points, params, x, axis) -> str:
    """Why a point in a plane through ``axis`` is the general form of the point on ``axis``."""
    dists = []
    for q in points:
        lines, tool = axis_lines(model, q, params)
        p = tool if x == "P" else None
        if p is None:
            m = meeting_point(lines[x[0] - 1], lines[x[1] - 1])
            p = 0.5 * (m[0] + m[1])
        dists.append(distance_to_line(p, lines[axis - 1]))
    scale = max(dists)
    # the same distance at every point (to GEOMETRY_RTOL of it): an offset of the design
    if scale <= 0 or max(dists) - min(dists) > GEOMETRY_RTOL * scale:
        return ""
    return (f"{_point_name(x, ())} keeps a distance of {dists[0]:.4g} length units from axis "
            f"{axis} at every point of the component (a lateral offset of the design), so it "
            f"can never lie on axis {axis}; the plane through axis {axis} is the general form "
            "of the "
            f"classical condition '{_point_name(x, ())} on axis {axis}', to which it reduces "
            "when that offset is zero")


def component_reading(model, equations, labels, points, factor_points, rng, params=None,
                      matrix=None):
    """The reading of one component.

    Parameters
    ----------
    model : RobotModel
        Any other model gives ``None``.
    equations : sequence of sympy.Expr
        The component's equations (its factors).
    labels : sequence of str
        How the text names each equation (inline math, e.g. ``"$s_{5} = 0$"``).
    points : sequence of dict
        Points of the component (variable name -> value); the first is its sample.
    factor_points : sequence of sequence of dict
        For each equation, points where it alone vanishes (the other joints free).
    rng : numpy.random.Generator
        Draws the random configurations whose facts are design facts.
    params : dict, optional
        Parameter values (default: the model's).
    matrix : callable, optional
        J at a point (dict -> array, columns in joint order); with it, a component
        or factor that no geometric fact explains is read by the smallest set of
        joints whose columns are dependent at every point.

    Returns
    -------
    Reading or None
        ``None`` when no geometric fact holds at all the points.

    Examples
    --------
    >>> import numpy as np, sympy as sp
    >>> from rankloci.io import load_model
    >>> puma = load_model("puma560")
    >>> q = {"q1": 0.3, "q2": 0.2, "q3": -0.4, "q4": 0.5, "q5": 0.0, "q6": 0.1}
    >>> r = component_reading(puma, [sp.sin(sp.Symbol("q5"))], ["$s_5 = 0$"],
    ...                       [q, dict(q, q1=1.0, q4=-1.2)], [[]], np.random.default_rng(0))
    >>> r.name, r.text
    ('wrist singularity', 'Wrist singularity: axes 4 and 6 are collinear')
    """
    if not isinstance(model, RobotModel) or not points:
        return None
    meets = design_points(model, params, rng)
    random_facts = set()
    for _ in range(RANDOM_POINTS):
        random_facts |= facts_at(model, random_configuration(model, rng), params, meets)
    whole = _common(model, points, params, meets, random_facts)
    dependent, whole_arm = "", ""
    if matrix is not None:
        cols = dependent_joints([matrix(q) for q in points],
                                [str(k + 1) for k in range(len(model.joints))])
        if cols and not _fills_rows([matrix(q) for q in points], [int(c) - 1 for c in cols]):
            dependent = (f"the columns of joints {_and(cols)} of J are linearly dependent "
                         f"(checked at {len(points)} points)")
        elif cols:
            # naming these columns would restate the locus; what is said is that no fewer do
            whole_arm = (f"no fact about the axes holds at all {len(points)} points checked, "
                         f"and no set of fewer than {len(cols)} joints has dependent columns: "
                         "a singularity of the arm as a whole, not of its shoulder, elbow or "
                         "wrist alone")
    if not whole:
        if whole_arm and not dependent:
            text = whole_arm[0].upper() + whole_arm[1:]
            return Reading("", text, (), "", "", len(points), (), (), text)
        if not dependent:
            return None
        text = dependent[0].upper() + dependent[1:]
        return Reading("", text, (), dependent, "", len(points), tuple(int(c) for c in cols),
                       (), text)
    per = []
    if len(equations) > 1:
        per = [(k, _common(model, qs, params, meets, random_facts) if qs else set())
               for k, qs in enumerate(factor_points)]
    said = set()
    for _, f in per:
        said |= {t for _, _, t in _sentences(f, meets, design=random_facts)}
    whole_s = _sentences(whole, meets, design=random_facts)
    together = [x for x in _sentences(whole - set().union(*(f for _, f in per)), meets, whole,
                                    design=random_facts)
                if x[2] not in said] if per else []
    factors, names, used, brief = [], [], [], []
    for k, f in per:
        s = _sentences(f, meets, design=random_facts)[:2]
        if s:
            factors.append((k, "; ".join(t for _, _, t in s)))
            brief.append(f"where {_holds(labels[k])}, {s[0][2]}")
            names.append(_name(model, s[0][0], s[0][1], meets))
            used += s
    joint = together[:2] if per else whole_s[:2]
    used += joint
    if joint:
        first = _name(model, joint[0][0], joint[0][1], meets)
        brief.append(("together, " if brief else "") + joint[0][2])
        # all links aligned says everything the factors say; other names add up
        names = [first] if first == "all links aligned" else names + [first]
    unexplained = [k for k, f in per if not _sentences(f, meets, design=random_facts)]
    if unexplained and not joint:
        names = []  # a factor nothing explains: the classical name of the others would mislead
    names = [n for n in names if n]
    boom = _boom_at_zero(model, equations)
    if boom:
        names = ["boom singularity"] + names
    name = ""
    if names:
        uniq = sorted(dict.fromkeys(n.replace(" singularity", "") for n in names),
                      key=lambda n: _ORDER.index(n) if n in _ORDER else len(_ORDER))
        name = names[0] if len(uniq) == 1 else f"{_and(uniq)} singularities at once"
    joint_text = "; ".join(t for _, _, t in joint)
    if per:
        parts = [f"where {_holds(labels[k])}, {text}" for k, text in factors]
        missing = [labels[k] for k, f in per if not _sentences(f, meets, design=random_facts)]
        if joint_text:
            parts.append(("together, " if parts else "") + joint_text)
        if missing:
            why = ""
            if matrix is not None:
                cols = [str(k + 1) for k in range(len(model.joints))]
                keep = set(range(len(cols)))
                for k, f in per:
                    if _sentences(f, meets, design=random_facts) and factor_points[k]:
                        d = dependent_joints([matrix(q) for q in factor_points[k]], cols)
                        keep -= {int(d[-1]) - 1} if d else set()
                rest = dependent_joints([matrix(q) for q in points], cols, sorted(keep))
                if rest and len(keep) < len(cols):
                    dropped = _and(sorted(set(range(1, len(cols) + 1)) - {c + 1 for c in keep}))
                    told = _and([labels[k] for k, f in per if k not in unexplained])
                    why = (f"; {told} already {'makes' if len(per) - len(missing) == 1 else 'make'}"
                           f" the column of joint {dropped} depend on the others, and "
                           f"{_and(missing)} is where the columns of "
                           f"joints {_and(rest)} become dependent too (checked at "
                           f"{len(points)} points)")
                elif dependent:
                    why = f"; at the points of the component, {dependent}"
            parts.append(f"{_and(missing)} alone gives no fact about the axes: it acts only "
                         f"together with the other {plural('equation', len(equations) - 1)}"
                         + why)
            brief.append(f"{_and(missing)} acts only with the others")
        body = "; ".join(parts)
    else:
        body = joint_text
    extra = []
    for kind, what, _ in used:
        if kind == "in-plane" and _name(model, kind, what, meets) == "shoulder singularity":
            remark = _offset_remark(model, points, params, what[0], what[1])
            if remark:
                extra.append(remark)
                break
    lost, lost_axis = "", ()
    rev = [k + 1 for k, j in enumerate(model.joints) if j.kind == "revolute"]
    for kind, what, _ in used:
        if kind == "collinear":
            lost, lost_axis = _lost_rotation(model, points[0], params, list(what))
        elif kind == "parallel" and "wrist" in name and len(rev) >= 3:
            lost, lost_axis = _lost_rotation(model, points[0], params, rev[-3:])
        if lost:
            break
    gloss = _GLOSS.get(name, "")
    if boom and name == "boom singularity":
        gloss = f"the boom, joint {boom}, at zero extension"
    elif boom:
        extra.insert(0, f"the boom, joint {boom}, is at zero extension")
    if name == "wrist centre on the shoulder":
        remark = _centres_remark(model, points, params, used)
        if remark:
            extra.append(remark)
    head = (name[0].upper() + name[1:] + (f" ({gloss})" if gloss else "") + ": ") if name else ""
    text = head + (body if head else body[0].upper() + body[1:])
    text = ". ".join([text] + [e[0].upper() + e[1:] for e in extra])
    short = "; ".join(brief) if per else (joint[0][2] if joint else body)
    if name == "all links aligned" and joint:
        short = joint[0][2]  # the one fact that says it all
    short = head + (short if head else short[0].upper() + short[1:])
    return Reading(name, text, tuple(factors), joint_text, lost, len(points), _named_axes(used),
                   lost_axis, short)


def _fills_rows(matrices, cols) -> bool:
    """Are ``cols`` at least as many as the rows they reach (a dependence that says nothing)?

    Where the other columns alone fill the remaining rows (a locked joint's row of an
    augmented J), the columns ``cols`` are dependent exactly where J is singular: naming
    them restates the locus.
    """
    from ..tolerances import RANK_RTOL

    J = np.asarray(matrices[0], dtype=float)
    top = float(np.linalg.svd(J, compute_uv=False)[0])
    rows = [r for r in range(J.shape[0])
            if max(float(np.max(np.abs(np.asarray(M, dtype=float)[r, cols]))) for M in matrices)
            > RANK_RTOL * top]
    return len(cols) >= len(rows)


def _holds(label: str) -> str:
    """``$e = 0$`` as it is; a named equation ("the second equation") with "holds"."""
    return label if label.startswith("$") else f"{label} holds"


def _named_axes(sentences) -> tuple:
    """The joints whose axes a list of sentences (kind, what, text) names."""
    out = set()

    def take(x):
        if isinstance(x, int):
            out.add(x)
        elif isinstance(x, (tuple, list, frozenset, set)):
            for y in x:
                take(y)

    for _, what, _ in sentences:
        take(what)
    return tuple(sorted(out))
