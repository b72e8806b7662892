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


from ..geometry import (ComponentFacts, centres_distance, component_facts, dependence_left,
                        equal_distances, lost_rotation_axis, point_axis_distances)
from ..model import RobotModel
from ..tolerances import FACTOR_POINTS
from .blocks import plural, signed

__all__ = ["Reading", "component_reading", "FACTOR_POINTS"]


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
    return (_structure_sentences(facts, meets, context, design)
            or _parallel_sentences(facts, meets, design) or _meeting_sentences(facts))


def _structure_sentences(facts, meets, context, design) -> list:
    """Points that coincide, collinear axes, slides, points on axes and planes of axes."""
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
    return out


def _parallel_sentences(facts, meets, design) -> list:
    """Parallel axes, and the first plane through an axis that a point lies in."""
    out = []
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
    return out


def _meeting_sentences(facts) -> list:
    """Perpendicular axes and axes that meet: the weakest facts."""
    out = []
    for kind, verb in (("perpendicular", "are perpendicular"), ("intersect", "meet")):
        for a, b in sorted(f[1:] for f in facts if f[0] == kind):
            out.append((kind, (a, b), f"axes {a} and {b} {verb}"))
    return out


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
    found = None if what is None else centres_distance(model, points[0], params, what)
    if found is None:
        return ""
    axis, distance = found
    return (f"both points lie {distance:.4g} length units from axis {axis} (equal link "
            f"lengths on either side of joint {axis}), so turning joint {axis} can "
            f"bring them together; then every axis but {axis} passes through one point, "
            f"those joints give only rotations about it, and with joint {axis} the rank of "
            "J is at most 4")


_GLOSS = {
    "all links aligned": "the arm is stretched out or folded back",
    "elbow singularity": "the arm is stretched out or folded back",
}


def _lost_rotation(model, q, params, group) -> tuple:
    """The rotation that the joints from the first to the last of collinear ``group`` lose,
    in words, and its axis."""
    n = lost_rotation_axis(model, q, params, group)
    if not n:
        return "", ()
    joints = f"joints {group[0]} to {group[-1]}"
    return (f"{joints} together cannot rotate the end-effector about the common normal "
            f"[{', '.join(signed(x, 3) for x in n)}] (base frame) of their axes at the sample "
            "point; the other joints give that rotation only together with a translation", n)


def _offset_remark(model, points, params, x, axis) -> str:
    """Why a point in a plane through ``axis`` is the general form of the point on ``axis``."""
    dists = point_axis_distances(model, points, params, x, axis)
    # the same distance at every point: an offset of the design
    if not equal_distances(dists):
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
    facts = component_facts(model, points, factor_points, rng, params, matrix)
    dependent, whole_arm = _dependence_notes(facts)
    if not facts.whole:
        return _reading_without_facts(facts, dependent, whole_arm)
    w = _wording(facts)
    name, boom = _case_name(model, equations, w)
    body = _body(model, equations, labels, points, factor_points, matrix, facts, w, dependent)
    extra = _offset_remarks(model, points, params, w.used)
    lost, lost_axis = _lost(model, points[0], params, w.used, name)
    gloss = _GLOSS.get(name, "")
    if boom and name == "boom singularity":
        gloss = f"the boom, joint {boom}, at zero extension"
    elif boom:
        extra.insert(0, f"the boom, joint {boom}, is at zero extension")
    if name == "wrist centre on the shoulder":
        remark = _centres_remark(model, points, params, w.used)
        if remark:
            extra.append(remark)
    head = (name[0].upper() + name[1:] + (f" ({gloss})" if gloss else "") + ": ") if name else ""
    text = head + (body if head else body[0].upper() + body[1:])
    text = ". ".join([text] + [e[0].upper() + e[1:] for e in extra])
    short = _short(labels, facts, w, name, body)
    short = head + (short if head else short[0].upper() + short[1:])
    return Reading(name, text, tuple(w.factors), w.joint_text, lost, len(points),
                   _named_axes(w.used), lost_axis, short)


# --- the steps of a reading: facts -> sentences -> names -> text --------------------------------

def _dependence_notes(facts: ComponentFacts) -> tuple[str, str]:
    """What the dependent columns of J say: ``(dependent, whole_arm)``, each "" or a clause.

    When the smallest dependent set fills the rows it reaches, naming it would restate the
    locus: what is said instead is that no fewer joints have dependent columns.
    """
    cols, n = facts.dependent, facts.points
    if cols and not facts.dependent_fills_rows:
        return (f"the columns of joints {_and(cols)} of J are linearly dependent "
                f"(checked at {n} points)"), ""
    if cols:
        return "", (f"no fact about the axes holds at all {n} points checked, "
                    f"and no set of fewer than {len(cols)} joints has dependent columns: "
                    "a singularity of the arm as a whole, not of its shoulder, elbow or "
                    "wrist alone")
    return "", ""


def _reading_without_facts(facts: ComponentFacts, dependent: str, whole_arm: str):
    """The reading of a component on which no geometric fact holds (or None)."""
    if whole_arm and not dependent:
        text = whole_arm[0].upper() + whole_arm[1:]
        return Reading("", text, (), "", "", facts.points, (), (), text)
    if not dependent:
        return None
    text = dependent[0].upper() + dependent[1:]
    return Reading("", text, (), dependent, "", facts.points,
                   tuple(int(c) for c in facts.dependent), (), text)


@dataclass(frozen=True)
class _Wording:
    """The sentences a reading is made of (each sentence is (kind, what, text))."""

    factors: list          # (factor index, its sentences joined) for each explained factor
    firsts: list           # the first sentence of each explained factor, in the same order
    joint: list            # at most two sentences of what holds on the whole component
    used: list             # every sentence the reading states
    unexplained: list      # the factors no fact explains

    @property
    def joint_text(self) -> str:
        return "; ".join(t for _, _, t in self.joint)


def _wording(facts: ComponentFacts) -> _Wording:
    """The sentences of each factor and of the whole component, most telling first."""
    meets, design, per = facts.meets, facts.design, facts.factors
    said = set()
    for _, f in per:
        said |= {t for _, _, t in _sentences(f, meets, design=design)}
    if per:
        joint = [x for x in _sentences(facts.whole - set().union(*(f for _, f in per)), meets,
                                       facts.whole, design=design)
                 if x[2] not in said][:2]
    else:
        joint = _sentences(facts.whole, meets, design=design)[:2]
    factors, firsts, used, unexplained = [], [], [], []
    for k, f in per:
        s = _sentences(f, meets, design=design)[:2]
        if s:
            factors.append((k, "; ".join(t for _, _, t in s)))
            firsts.append(s[0])
            used += s
        else:
            unexplained.append(k)
    return _Wording(factors, firsts, joint, used + joint, unexplained)


def _case_name(model, equations, w: _Wording) -> tuple[str, int]:
    """``(name, boom)``: the classical case the sentences make, and the prismatic joint (or
    0) that an equation fixes at zero length."""
    names = [_name(model, kind, what, ()) for kind, what, _ in w.firsts]
    if w.joint:
        first = _name(model, w.joint[0][0], w.joint[0][1], ())
        # all links aligned says everything the factors say; other names add up
        names = [first] if first == "all links aligned" else names + [first]
    if w.unexplained and not w.joint:
        names = []  # a factor nothing explains: the classical name of the others would mislead
    names = [n for n in names if n]
    boom = _boom_at_zero(model, equations)
    if boom:
        names = ["boom singularity"] + names
    if not names:
        return "", boom
    uniq = sorted(dict.fromkeys(n.replace(" singularity", "") for n in names),
                  key=lambda n: _ORDER.index(n) if n in _ORDER else len(_ORDER))
    return (names[0] if len(uniq) == 1 else f"{_and(uniq)} singularities at once"), boom


def _body(model, equations, labels, points, factor_points, matrix, facts, w: _Wording,
          dependent: str) -> str:
    """The sentence covering every factor, then what they do only together."""
    if not facts.factors:
        return w.joint_text
    parts = [f"where {_holds(labels[k])}, {text}" for k, text in w.factors]
    if w.joint_text:
        parts.append(("together, " if parts else "") + w.joint_text)
    if w.unexplained:
        missing = [labels[k] for k in w.unexplained]
        why = ""
        if matrix is not None:
            explained = [k for k, _ in w.factors]
            dropped, rest = dependence_left(matrix, points, factor_points, explained,
                                            len(model.joints))
            if rest and dropped:
                told = _and([labels[k] for k, _ in facts.factors if k not in w.unexplained])
                why = (f"; {told} already "
                       f"{'makes' if len(facts.factors) - len(missing) == 1 else 'make'}"
                       f" the column of joint {_and(dropped)} depend on the others, and "
                       f"{_and(missing)} is where the columns of "
                       f"joints {_and(rest)} become dependent too (checked at "
                       f"{len(points)} points)")
            elif dependent:
                why = f"; at the points of the component, {dependent}"
        parts.append(f"{_and(missing)} alone gives no fact about the axes: it acts only "
                     f"together with the other {plural('equation', len(equations) - 1)}"
                     + why)
    return "; ".join(parts)


def _short(labels, facts, w: _Wording, name: str, body: str) -> str:
    """The name's companion in a summary table: the first fact of each factor."""
    if name == "all links aligned" and w.joint:
        return w.joint[0][2]  # the one fact that says it all
    if not facts.factors:
        return w.joint[0][2] if w.joint else body
    brief = [f"where {_holds(labels[k])}, {first[2]}"
             for (k, _), first in zip(w.factors, w.firsts)]
    if w.joint:
        brief.append(("together, " if brief else "") + w.joint[0][2])
    if w.unexplained:
        brief.append(f"{_and([labels[k] for k in w.unexplained])} acts only with the others")
    return "; ".join(brief)


def _offset_remarks(model, points, params, used) -> list:
    """The remark on the first plane through the first axis that names a shoulder case."""
    for kind, what, _ in used:
        if kind == "in-plane" and _name(model, kind, what, ()) == "shoulder singularity":
            remark = _offset_remark(model, points, params, what[0], what[1])
            if remark:
                return [remark]
    return []


def _lost(model, q, params, used, name) -> tuple:
    """The rotation the joints of the first collinear (or wrist-parallel) group lose."""
    rev = [k + 1 for k, j in enumerate(model.joints) if j.kind == "revolute"]
    for kind, what, _ in used:
        lost = ("", ())
        if kind == "collinear":
            lost = _lost_rotation(model, q, params, list(what))
        elif kind == "parallel" and "wrist" in name and len(rev) >= 3:
            lost = _lost_rotation(model, q, params, rev[-3:])
        if lost[0]:
            return lost
    return "", ()


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
