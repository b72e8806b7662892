"""Reading a URDF document: the links, the joints, the chain and their numbers.

:func:`parse_document` parses the XML safely: with :mod:`defusedxml`, which
refuses entity declarations (billion laughs) and external references.  The
functions below check that the links form one tree and find the chain of
joints between two links; the ``*_floats`` functions read and validate the
numbers of a joint's ``<origin>``, ``<axis>``, ``<limit>`` and ``<mimic>``.  Every problem
is a :class:`~rankloci.errors.ModelError` carrying the file name (``where``)
and, for a movable joint of the chain, its 1-based index.

:mod:`rankloci.io.urdf` builds the robot model from what is read here.
"""

from __future__ import annotations

import dataclasses
import math
import re
from xml.etree.ElementTree import Element, ParseError

import defusedxml
import defusedxml.ElementTree as SafeET

from ..errors import ModelError

__all__ = [
    "JOINT_KINDS", "KNOWN_TYPES", "UNSUPPORTED_TYPES", "UrdfJoint",
    "parse_document", "link_names", "joints_by_name", "parent_joints", "single_leaf",
    "chain_joints", "name_list", "origin_floats", "axis_floats", "joint_limits",
    "mimic_floats", "check_joint_numbers",
]

#: URDF joint type -> RobotModel joint kind, for the joint types that move.
JOINT_KINDS: dict[str, str] = {
    "revolute": "revolute",
    "continuous": "revolute",
    "prismatic": "prismatic",
}
#: URDF joint types rankloci cannot put on a chain.
UNSUPPORTED_TYPES = ("floating", "planar")
#: Every joint type of the URDF specification.
KNOWN_TYPES = tuple(JOINT_KINDS) + ("fixed",) + UNSUPPORTED_TYPES

_XACRO_NS = "{http://www.ros.org/wiki/xacro}"
_NUMBER = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?")


@dataclasses.dataclass(frozen=True)
class UrdfJoint:
    """The parts of a <joint> element needed to build the tree."""

    name: str
    type: str
    parent: str
    child: str
    element: Element


def parse_document(text, where) -> Element:
    """The <robot> root element of URDF text (str or UTF-8 bytes), parsed safely."""
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


def link_names(root: Element, where) -> list[str]:
    """Names of the <link> elements, in document order (each defined once)."""
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


def joints_by_name(root: Element, links: list[str], where) -> dict[str, UrdfJoint]:
    """The <joint> elements by name, each with a known type and two distinct known links."""
    known = set(links)
    joints: dict[str, UrdfJoint] = {}
    for k, el in enumerate(root.findall("joint"), 1):
        name = _required(el, "name", f"joint number {k}", where, field="joint name")
        what = f"joint {name!r}"
        if name in joints:
            raise ModelError(f"{what} is defined twice", file=where, field="joint name")
        jtype = _required(el, "type", what, where, field="type")
        if jtype not in KNOWN_TYPES:
            raise ModelError(f"{what} has unknown type {jtype!r}; URDF joint types are "
                             f"{', '.join(KNOWN_TYPES)}", file=where, field="type")
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
        joints[name] = UrdfJoint(name, jtype, ends[0], ends[1], el)
    return joints


def parent_joints(links, joints, where) -> dict[str, UrdfJoint]:
    """Map child link -> joint, after checking the links form one tree."""
    parent_of: dict[str, UrdfJoint] = {}
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
                         f"joint ({name_list(roots)})", file=where)
    return parent_of


def single_leaf(base: str, joints: dict[str, UrdfJoint], where) -> str:
    """The one leaf link below ``base``; an error naming them when there are several."""
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
                         f"({name_list(leaves)}); choose the tip link with --tip",
                         file=where, field="tip_link")
    return leaves[0]


def chain_joints(base: str, tip: str, parent_of, where) -> list[UrdfJoint]:
    """The joints from ``base`` down to ``tip``, in chain order."""
    chain = []
    link = tip
    while link != base:
        if link not in parent_of:
            raise ModelError(f"tip link {tip!r} is not below base link {base!r}",
                             file=where, field="tip_link")
        chain.append(parent_of[link])
        link = parent_of[link].parent
    return chain[::-1]


def name_list(names, limit: int = 12) -> str:
    """``'a', 'b', ...``: at most ``limit`` names quoted, for an error message."""
    shown = ", ".join(repr(n) for n in names[:limit])
    return shown + (f", ... ({len(names) - limit} more)" if len(names) > limit else "")


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


def origin_floats(j: UrdfJoint, i, where) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """``(xyz, rpy)`` of a joint's <origin>, zeros where missing."""
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


def axis_floats(j: UrdfJoint, i, where) -> tuple[float, ...]:
    """A joint's <axis xyz> (default ``1 0 0``); never the zero vector."""
    el = j.element.find("axis")
    if el is None or el.get("xyz") is None:
        return (1.0, 0.0, 0.0)
    v = _floats(el.get("xyz"), 3, f"joint {j.name!r}: <axis xyz>", where,
                joint=i, field="axis xyz")
    if not any(v):
        raise ModelError(f"joint {j.name!r}: <axis xyz> {el.get('xyz')!r} is zero",
                         file=where, joint=i, field="axis xyz")
    return v


def joint_limits(j: UrdfJoint, i, where) -> tuple[float, float] | None:
    """``(lower, upper)`` of a joint's <limit>; None for a continuous joint or no limit."""
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


def mimic_floats(j: UrdfJoint, i, where) -> tuple[str, float, float] | None:
    """``(joint, multiplier, offset)`` of a joint's <mimic> (defaults 1 and 0); None without one.

    The joint moves by ``multiplier * q + offset`` where ``q`` is the position
    of the joint named ``joint``.
    """
    el = j.element.find("mimic")
    if el is None:
        return None
    leader = _required(el, "joint", f"<mimic> of joint {j.name!r}", where, joint=i, field="mimic")
    values = []
    for attr, default in (("multiplier", "1"), ("offset", "0")):
        values.append(_floats(el.get(attr, default), 1, f"joint {j.name!r}: <mimic {attr}>",
                              where, joint=i, field=f"mimic {attr}")[0])
    return leader, values[0], values[1]


def check_joint_numbers(j: UrdfJoint, i, where) -> None:
    """Validate every number of a joint, on the chain or not."""
    origin_floats(j, i, where)
    if j.type in JOINT_KINDS:
        axis_floats(j, i, where)
        joint_limits(j, i, where)
        mimic_floats(j, i, where)
