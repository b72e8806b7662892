"""Import a serial chain from a URDF file as a :class:`~rankloci.model.RobotModel`.

A URDF describes a tree of links joined by joints.  :func:`parse_urdf` picks
the chain from a base link to a tip link and turns it into the general joint
form ``T_i(q_i) = pre_i * Motion(axis_i, q_i) * post_i`` of
:mod:`rankloci.model`.

Conventions
-----------
- A joint's ``<origin xyz="x y z" rpy="r p y"/>`` is the pose of the child
  link frame in the parent link frame at ``q = 0``:
  ``trans(x, y, z) * R`` with ``R = Rz(yaw) * Ry(pitch) * Rx(roll)``, i.e.
  fixed-axis roll about x, then pitch about y, then yaw about z
  (:func:`rankloci.model.rpy_rotation`).  Missing ``<origin>``, ``xyz`` or
  ``rpy`` mean zero, as in the URDF specification.
- The joint moves *after* its origin, about or along ``<axis xyz>`` expressed
  in the child frame (default ``1 0 0``), so ``pre_i`` is the product of the
  fixed-joint origins since the previous movable joint times the joint's own
  origin, and ``post_i`` is the identity.  Fixed joints after the last movable
  joint make up :attr:`RobotModel.tool`; ``base`` is the identity.
- ``revolute`` and ``continuous`` joints are revolute, ``prismatic`` joints
  prismatic; ``floating`` and ``planar`` joints and ``mimic`` joints on the
  chain are not supported.  Joint limits are kept for revolute and prismatic
  joints; a continuous joint has none (the specification ignores them).
- Joint variables are ``q1..qn`` in chain order, whatever the URDF joint
  names (kept as :attr:`Joint.name`).

Exactness
---------
URDF numbers are decimal floats, but the symbolic algebra downstream must
stay exact.  Lengths become the rational of their shortest decimal form
(``0.089159`` is ``89159/1000000``).  An rpy angle within
:data:`~rankloci.tolerances.URDF_ANGLE_SNAP_ATOL` of a multiple of ``pi/12``
(``1.5708``, ``1.57079632679``) is taken as that exact multiple, so its sine
and cosine are exact radicals.  Any other angle ``t`` gives the rational
rotation with ``cos = (1 - u**2)/(1 + u**2)``, ``sin = 2u/(1 + u**2)`` where
``u`` is the shortest decimal of ``tan(t/2)``: every entry is an exact
rational within rounding error of the float value, and the matrix is exactly
orthogonal (converting float cosines entry by entry would not be).  Axis
components are snapped the same way (``0.9999999`` is ``1``); an axis that
does not snap becomes an exactly unit rational vector within rounding error
of the normalised float axis.

Model files may be hostile: the XML is parsed with :mod:`defusedxml`, which
refuses entity declarations (billion laughs) and external references.  Every
problem with the input is a :class:`~rankloci.errors.ModelError` carrying the
file name and, for a movable joint of the chain, its 1-based index.
"""

from __future__ import annotations

import dataclasses
import math
import re
from pathlib import Path
from xml.etree.ElementTree import Element, ParseError

import defusedxml
import defusedxml.ElementTree as SafeET
import sympy as sp

from ..errors import ModelError
from ..expr import exact_number
from ..model import TASKS, Joint, RobotModel, trans
from ..tolerances import URDF_ANGLE_SNAP_ATOL

__all__ = ["parse_urdf", "read_urdf", "JOINT_KINDS"]

#: URDF joint type -> RobotModel joint kind, for the joint types that move.
JOINT_KINDS: dict[str, str] = {
    "revolute": "revolute",
    "continuous": "revolute",
    "prismatic": "prismatic",
}
_UNSUPPORTED = ("floating", "planar")
_KNOWN_TYPES = tuple(JOINT_KINDS) + ("fixed",) + _UNSUPPORTED

_XACRO_NS = "{http://www.ros.org/wiki/xacro}"
_NUMBER = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?")

# Exact values a unit-axis component may snap to (besides their negatives).
_NICE_COMPONENTS = (sp.Integer(0), sp.Rational(1, 2), sp.sqrt(2) / 2, sp.sqrt(3) / 2,
                    sp.Integer(1))


@dataclasses.dataclass(frozen=True)
class _UrdfJoint:
    """The parts of a <joint> element needed to build the tree."""

    name: str
    type: str
    parent: str
    child: str
    element: Element


def parse_urdf(text: str, *, name: str, file: str = "", base_link: str | None = None,
               tip_link: str | None = None) -> RobotModel:
    """Robot model of the serial chain ``base_link -> tip_link`` of a URDF document.

    Parameters
    ----------
    text : str
        The URDF XML.
    name : str
        :attr:`RobotModel.name` of the result (``read_urdf`` uses the file stem).
    file : str, optional
        File name used in error messages.
    base_link : str, optional
        First link of the chain; default: the root link (the one link that is
        no joint's child).
    tip_link : str, optional
        Last link of the chain; default: the only leaf link below
        ``base_link``.  Required when there are several.

    Returns
    -------
    RobotModel
        One joint per revolute, continuous or prismatic joint on the chain,
        with ``convention="urdf"``, the full 6-row task, base frame, the
        robot's ``name`` attribute as title, and fixed joints folded into the
        neighbouring transforms.

    Raises
    ------
    ModelError
        On invalid or hostile XML, a missing or malformed attribute, an
        unknown or unsupported joint type, a link tree that is cyclic or not
        connected, an unknown base or tip link, several leaves and no tip, or
        a chain without movable joints.

    Examples
    --------
    >>> urdf = '''<robot name="arm">
    ...   <link name="base"/><link name="l1"/><link name="l2"/><link name="tool"/>
    ...   <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    ...     <origin xyz="0 0 0.5"/><axis xyz="0 0 1"/>
    ...     <limit lower="-3.14" upper="3.14" effort="1" velocity="1"/></joint>
    ...   <joint name="j2" type="continuous"><parent link="l1"/><child link="l2"/>
    ...     <origin xyz="0.4 0 0" rpy="1.5708 0 0"/><axis xyz="0 0 1"/></joint>
    ...   <joint name="flange" type="fixed"><parent link="l2"/><child link="tool"/>
    ...     <origin xyz="0.25 0 0"/></joint>
    ... </robot>'''
    >>> m = parse_urdf(urdf, name="arm")
    >>> m.dof, m.variables, [j.name for j in m.joints], m.joints[0].limits
    (2, (q1, q2), ['j1', 'j2'], (-3.14, 3.14))
    >>> m.joints[1].pre
    Matrix([
    [1, 0,  0, 2/5],
    [0, 0, -1,   0],
    [0, 1,  0,   0],
    [0, 0,  0,   1]])
    >>> m.tool[:3, 3].T
    Matrix([[1/4, 0, 0]])
    """
    where = file or None
    root = _parse_xml(text, where)
    links = _links(root, where)
    joints = _joints(root, links, where)
    parent_of = _check_tree(links, joints, where)

    if base_link is None:
        base_link = next(link for link in links if link not in parent_of)
    elif base_link not in links:
        raise ModelError(f"base link {base_link!r} is not a link of this robot "
                         f"({_name_list(links)})", file=where, field="base_link")
    if tip_link is None:
        tip_link = _single_leaf(base_link, joints, where)
    elif tip_link not in links:
        raise ModelError(f"tip link {tip_link!r} is not a link of this robot "
                         f"({_name_list(links)})", file=where, field="tip_link")
    chain = _chain(base_link, tip_link, parent_of, where)

    index = {}  # joint name -> 1-based index among the chain's movable joints
    for j in chain:
        if j.type in _UNSUPPORTED:
            raise ModelError(f"joint {j.name!r} is {j.type}; only revolute, continuous, "
                             f"prismatic and fixed joints are supported (choose a base "
                             f"link below it with --base)", file=where, field="type")
        if j.type in JOINT_KINDS:
            index[j.name] = len(index) + 1
            if j.element.find("mimic") is not None:
                raise ModelError(f"joint {j.name!r} mimics another joint; mimic joints are "
                                 f"not supported", file=where, joint=index[j.name],
                                 field="mimic")
    for j in joints.values():
        _check_numbers(j, index.get(j.name), where)
    if not index:
        raise ModelError(f"no revolute, continuous or prismatic joint between "
                         f"{base_link!r} and {tip_link!r}", file=where)

    model_joints = []
    fixed = sp.eye(4)  # fixed transforms accumulated since the last movable joint
    for j in chain:
        i = index.get(j.name)
        fixed = _mul(fixed, _origin(j))
        if i is None:
            continue
        model_joints.append(Joint(
            kind=JOINT_KINDS[j.type],
            axis=_exact_axis(_axis_floats(j, i, where)),
            pre=sp.ImmutableMatrix(fixed),
            post=sp.ImmutableMatrix(sp.eye(4)),
            name=j.name,
            limits=_limits(j, i, where),
        ))
        fixed = sp.eye(4)

    title = root.get("name", "")
    return RobotModel(
        name=name,
        joints=tuple(model_joints),
        variables=tuple(sp.Symbol(f"q{i}", real=True) for i in range(1, len(model_joints) + 1)),
        parameters={},
        title=title,
        source=f"URDF robot {title!r}, chain {base_link} -> {tip_link}",
        base=sp.ImmutableMatrix(sp.eye(4)),
        tool=sp.ImmutableMatrix(fixed),
        task=TASKS["full"],
        frame="base",
        convention="urdf",
    )


def read_urdf(path, *, base_link: str | None = None, tip_link: str | None = None) -> RobotModel:
    """Read a URDF file: :func:`parse_urdf` with name = file stem, file = base name.

    Parameters
    ----------
    path : str or os.PathLike
    base_link, tip_link : str, optional
        See :func:`parse_urdf`.

    Raises
    ------
    ModelError
        If the file cannot be read or decoded as UTF-8, or does not parse.
    """
    p = Path(path)
    try:
        text = p.read_bytes().decode("utf-8-sig")
    except OSError as e:
        raise ModelError(f"cannot read file: {e.strerror or e}", file=p.name) from None
    except UnicodeDecodeError as e:
        raise ModelError(f"not UTF-8 text ({e.reason} at byte {e.start})", file=p.name) from None
    model = parse_urdf(text, name=p.stem, file=p.name, base_link=base_link, tip_link=tip_link)
    return dataclasses.replace(model, path=str(p))


# --- document structure -----------------------------------------------------

def _parse_xml(text, where) -> Element:
    if isinstance(text, bytes):
        try:
            text = text.decode("utf-8-sig")
        except UnicodeDecodeError as e:
            raise ModelError(f"not UTF-8 text ({e.reason} at byte {e.start})", file=where) from None
    if not isinstance(text, str):
        raise ModelError(f"expected URDF text, got {type(text).__name__}", file=where)
    try:
        root = SafeET.fromstring(text)
    except defusedxml.EntitiesForbidden:
        raise ModelError("XML entity declarations are not allowed in a URDF file (they can "
                         "be used for entity-expansion attacks)", file=where) from None
    except defusedxml.DefusedXmlException as e:
        raise ModelError(f"refused unsafe XML: {type(e).__name__}", file=where) from None
    except ParseError as e:
        raise ModelError(f"invalid XML: {e}", file=where) from None
    except (ValueError, RecursionError) as e:  # e.g. NUL characters, absurd nesting
        raise ModelError(f"invalid XML: {e or type(e).__name__}", file=where) from None
    if root.tag != "robot":
        raise ModelError(f"root element is <{root.tag}>, expected <robot>", file=where)
    if any(isinstance(el.tag, str) and el.tag.startswith(_XACRO_NS) for el in root.iter()):
        raise ModelError("this is a xacro file; expand it to URDF with xacro first", file=where)
    return root


def _required(el: Element, attr: str, what: str, where, *, joint=None, field=None) -> str:
    value = el.get(attr)
    if value is None or not value.strip():
        raise ModelError(f"{what} has no {attr!r} attribute", file=where, joint=joint,
                         field=field or attr)
    return value.strip()


def _links(root: Element, where) -> list[str]:
    links = []
    seen = set()
    for k, el in enumerate(root.findall("link"), 1):
        name = _required(el, "name", f"link number {k}", where, field="link name")
        if name in seen:
            raise ModelError(f"link {name!r} is defined twice", file=where, field="link name")
        seen.add(name)
        links.append(name)
    if not links:
        raise ModelError("the robot has no <link> elements", file=where)
    return links


def _joints(root: Element, links: list[str], where) -> dict[str, _UrdfJoint]:
    known = set(links)
    joints: dict[str, _UrdfJoint] = {}
    for k, el in enumerate(root.findall("joint"), 1):
        name = _required(el, "name", f"joint number {k}", where, field="joint name")
        what = f"joint {name!r}"
        if name in joints:
            raise ModelError(f"{what} is defined twice", file=where, field="joint name")
        jtype = _required(el, "type", what, where, field="type")
        if jtype not in _KNOWN_TYPES:
            raise ModelError(f"{what} has unknown type {jtype!r}; URDF joint types are "
                             f"{', '.join(_KNOWN_TYPES)}", file=where, field="type")
        ends = []
        for tag in ("parent", "child"):
            sub = el.find(tag)
            if sub is None:
                raise ModelError(f"{what} has no <{tag}> element", file=where, field=tag)
            link = _required(sub, "link", f"<{tag}> of {what}", where, field=tag)
            if link not in known:
                raise ModelError(f"{what} names {tag} link {link!r}, which is not defined "
                                 f"by a <link> element", file=where, field=tag)
            ends.append(link)
        if ends[0] == ends[1]:
            raise ModelError(f"{what} joins link {ends[0]!r} to itself", file=where, field="child")
        joints[name] = _UrdfJoint(name, jtype, ends[0], ends[1], el)
    return joints


def _check_tree(links, joints, where) -> dict[str, _UrdfJoint]:
    """Map child link -> joint, after checking the links form one tree."""
    parent_of: dict[str, _UrdfJoint] = {}
    for j in joints.values():
        if j.child in parent_of:
            raise ModelError(f"link {j.child!r} is the child of two joints, "
                             f"{parent_of[j.child].name!r} and {j.name!r}; a URDF must be "
                             f"a tree", file=where, field="child")
        parent_of[j.child] = j
    done: set[str] = set()  # links known to lead up to a root
    for link in links:
        path, seen = [], set()
        while link in parent_of and link not in done:
            if link in seen:
                cycle = path[path.index(link):] + [link]
                raise ModelError(f"the links form a cycle: {' -> '.join(reversed(cycle))}",
                                 file=where)
            seen.add(link)
            path.append(link)
            link = parent_of[link].parent
        done.update(path)
    roots = [link for link in links if link not in parent_of]
    if len(roots) > 1:
        raise ModelError(f"the links are not connected: {len(roots)} links have no parent "
                         f"joint ({_name_list(roots)})", file=where)
    return parent_of


def _single_leaf(base: str, joints: dict[str, _UrdfJoint], where) -> str:
    children: dict[str, list[str]] = {}
    for j in joints.values():
        children.setdefault(j.parent, []).append(j.child)
    leaves, stack = [], [base]
    while stack:
        link = stack.pop()
        if link in children:
            stack.extend(reversed(children[link]))
        else:
            leaves.append(link)
    if len(leaves) > 1:
        raise ModelError(f"link {base!r} has {len(leaves)} leaf links below it "
                         f"({_name_list(leaves)}); choose the tip link with --tip",
                         file=where, field="tip_link")
    return leaves[0]


def _chain(base: str, tip: str, parent_of, where) -> list[_UrdfJoint]:
    chain = []
    link = tip
    while link != base:
        if link not in parent_of:
            raise ModelError(f"tip link {tip!r} is not below base link {base!r}",
                             file=where, field="tip_link")
        chain.append(parent_of[link])
        link = parent_of[link].parent
    return chain[::-1]


def _name_list(names, limit: int = 12) -> str:
    shown = ", ".join(repr(n) for n in names[:limit])
    return shown + (f", ... ({len(names) - limit} more)" if len(names) > limit else "")


# --- numbers ----------------------------------------------------------------

def _floats(value: str, count: int, what: str, where, *, joint, field) -> tuple[float, ...]:
    expected = "a finite decimal number" if count == 1 else \
        f"{count} finite decimal numbers separated by spaces"
    parts = value.split()
    if len(parts) != count:
        raise ModelError(f"{what} must be {expected}, got {len(parts)} values in {value!r}",
                         file=where, joint=joint, field=field)
    out = []
    for part in parts:
        x = float(part) if _NUMBER.fullmatch(part) else math.nan
        if not math.isfinite(x):
            raise ModelError(f"{what} must be {expected}, got {value!r}",
                             file=where, joint=joint, field=field)
        out.append(x)
    return tuple(out)


def _origin_floats(j: _UrdfJoint, i, where) -> tuple[tuple[float, ...], tuple[float, ...]]:
    el = j.element.find("origin")
    values = []
    for attr in ("xyz", "rpy"):
        text = None if el is None else el.get(attr)
        if text is None:
            values.append((0.0, 0.0, 0.0))
        else:
            values.append(_floats(text, 3, f"joint {j.name!r}: <origin {attr}>", where,
                                  joint=i, field=f"origin {attr}"))
    return values[0], values[1]


def _axis_floats(j: _UrdfJoint, i, where) -> tuple[float, ...]:
    el = j.element.find("axis")
    if el is None or el.get("xyz") is None:
        return (1.0, 0.0, 0.0)
    v = _floats(el.get("xyz"), 3, f"joint {j.name!r}: <axis xyz>", where,
                joint=i, field="axis xyz")
    if not any(v):
        raise ModelError(f"joint {j.name!r}: <axis xyz> {el.get('xyz')!r} is zero",
                         file=where, joint=i, field="axis xyz")
    return v


def _limits(j: _UrdfJoint, i, where) -> tuple[float, float] | None:
    el = j.element.find("limit")
    if j.type == "continuous" or el is None:
        return None
    if el.get("lower") is None and el.get("upper") is None:
        return None
    lower, upper = (
        _floats(el.get(attr, "0"), 1, f"joint {j.name!r}: <limit {attr}>", where,
                joint=i, field=f"limit {attr}")[0]
        for attr in ("lower", "upper"))
    if lower > upper:
        raise ModelError(f"joint {j.name!r}: <limit> lower {lower} is above upper {upper}",
                         file=where, joint=i, field="limit lower")
    return (lower, upper)


def _check_numbers(j: _UrdfJoint, i, where) -> None:
    """Validate every number of a joint, on the chain or not."""
    _origin_floats(j, i, where)
    if j.type in JOINT_KINDS:
        _axis_floats(j, i, where)
        _limits(j, i, where)


# --- exact transforms -------------------------------------------------------

def _snap_angle(t: float) -> sp.Expr | None:
    """The exact multiple of pi/12 within URDF_ANGLE_SNAP_ATOL of ``t``, or None."""
    k = round(t / (math.pi / 12))
    if abs(t - k * math.pi / 12) <= URDF_ANGLE_SNAP_ATOL:
        return sp.pi * sp.Rational(k, 12)
    return None


def _cos_sin(t: float) -> tuple[sp.Expr, sp.Expr]:
    """Exact (cos, sin) of an angle read as a float; see the module docstring."""
    t = math.remainder(t, 2 * math.pi)  # in [-pi, pi]
    snapped = _snap_angle(t)
    if snapped is not None:
        return sp.cos(snapped), sp.sin(snapped)
    u = exact_number(math.tan(t / 2))  # finite: angles near +-pi snap
    return (1 - u**2) / (1 + u**2), 2 * u / (1 + u**2)


def _rotation(axis: str, t: float) -> sp.Matrix:
    """Exact 4x4 rotation by the float angle ``t`` about the x, y or z axis."""
    c, s = _cos_sin(t)
    m = sp.eye(4)
    i, j = {"x": (1, 2), "y": (2, 0), "z": (0, 1)}[axis]
    m[i, i], m[i, j], m[j, i], m[j, j] = c, -s, s, c
    return m


def _mul(a: sp.Matrix, b: sp.Matrix) -> sp.Matrix:
    return (a * b).applyfunc(sp.expand)


def _origin(j: _UrdfJoint) -> sp.Matrix:
    """Exact 4x4 transform of a joint's <origin> (numbers already validated)."""
    xyz, (roll, pitch, yaw) = _origin_floats(j, None, None)
    T = trans(*(exact_number(x) for x in xyz))
    for axis, t in (("z", yaw), ("y", pitch), ("x", roll)):
        if t != 0.0:
            T = _mul(T, _rotation(axis, t))
    return T


def _exact_axis(v: tuple[float, ...]) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """Exact unit vector for a float axis; see the module docstring."""
    big = max(abs(x) for x in v)  # > 0, checked by _axis_floats
    v = [x / big for x in v]        # no overflow or underflow in the norm
    norm = math.sqrt(sum(x * x for x in v))
    u = [x / norm for x in v]
    snapped = []
    for x in u:
        nice = next((n for n in _NICE_COMPONENTS if abs(abs(x) - float(n)) <= URDF_ANGLE_SNAP_ATOL),
                    None)
        snapped.append(None if nice is None else (nice if x > 0 else -nice))
    if None not in snapped and sp.expand(sum(x**2 for x in snapped)) == 1:
        return tuple(snapped)
    # An exactly unit rational vector: inverse stereographic projection, from the
    # pole opposite the largest component, of the rationalised projected point.
    k = max(range(3), key=lambda m: abs(u[m]))
    others = [m for m in range(3) if m != k]
    a, b = (sp.Integer(0) if abs(u[m]) <= URDF_ANGLE_SNAP_ATOL
            else exact_number(u[m] / (1 + abs(u[k]))) for m in others)
    d = 1 + a**2 + b**2
    out = [sp.Integer(0)] * 3
    out[others[0]], out[others[1]] = 2 * a / d, 2 * b / d
    out[k] = (1 if u[k] > 0 else -1) * (1 - a**2 - b**2) / d
    return tuple(out)
