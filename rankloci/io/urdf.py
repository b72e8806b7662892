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
  prismatic; ``floating`` and ``planar`` joints are not supported.  Joint
  limits are kept for revolute and prismatic joints; a continuous joint has
  none (the specification ignores them).
- A joint with ``<mimic joint="J" multiplier="m" offset="o"/>`` (defaults 1
  and 0) moves by ``m * q_J + o`` and has no variable of its own
  (:class:`~rankloci.model.Mimic`); its offset is a constant motion folded
  into its ``pre``, and the Jacobian column of ``q_J`` gets ``m`` times its
  twist.  A mimic of a mimic is followed (multipliers and offsets compose) to
  a joint that mimics nothing, the leader, before or after the follower;
  intermediate joints may lie off the chain.  Every joint on the way must be
  of the follower's kind (revolute or prismatic), and a revolute follower's
  composed multiplier must be an integer, so the kinematics stay polynomial
  in the cosines and sines of the variables.  Multipliers are read as the
  rational of their shortest decimal form, offsets as rpy angles (revolute)
  or lengths (prismatic).
- A leader off the chain (a gripper's other finger) moves nothing on the
  chain but its followers.  The first of them with multiplier 1 or -1 carries
  the leader's variable: it has no :class:`~rankloci.model.Mimic`, its offset
  is folded into its ``pre``, its axis is multiplied by the multiplier, and
  its limits are the leader's, so its variable is ``q_J``; the leader's other
  followers on the chain follow it.  When no follower has multiplier 1 or -1,
  a single follower moves by a variable of its own (its own position ``m *
  q_J + o``: a change of variable that keeps the rank), and several are
  refused.
- Joint variables are ``q1..qn`` in chain order for the joints without a
  mimic, whatever the URDF joint names (kept as :attr:`Joint.name`).

The document is read by :mod:`rankloci.io.urdf_xml` (safely: entity
declarations and external references are refused) and its decimal numbers
are made exact by :mod:`rankloci.io.urdf_exact`.  Every problem with the
input is a :class:`~rankloci.errors.ModelError` carrying the file name and,
for a movable joint of the chain, its 1-based index.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import sympy as sp

from ..errors import ExpressionError, ModelError
from ..expr import exact_number
from ..model import TASKS, Joint, Mimic, RobotModel
from .urdf_exact import Snaps, bounded, exact_axis, exact_motion, exact_origin, expanded_product
from .urdf_xml import (
    JOINT_KINDS,
    UNSUPPORTED_TYPES,
    UrdfJoint,
    axis_floats,
    chain_joints,
    check_joint_numbers,
    joint_limits,
    joints_by_name,
    link_names,
    mimic_floats,
    name_list,
    origin_floats,
    parent_joints,
    parse_document,
    single_leaf,
)

__all__ = ["parse_urdf", "read_urdf", "JOINT_KINDS"]

#: Largest URDF file read (the biggest URDF of example-robot-data is about 0.2 MB; meshes live
#: in their own files).
MAX_FILE_BYTES = 10_000_000
#: Most joints (fixed ones included) on the chain from the base link to the tip.
MAX_CHAIN_JOINTS = 500
#: Most movable joints on the chain, as for a TOML model file.
MAX_MOVABLE_JOINTS = 64


def parse_urdf(text: str, *, name: str, file: str = "", base_link: str | None = None,
               tip: str | None = None, tip_link: str | None = None) -> RobotModel:
    """Robot model of the serial chain ``base_link -> tip`` of a URDF document.

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
    tip : str, optional
        Last link of the chain; default: the only leaf link below
        ``base_link``.  Required when there are several.  The same name as
        :func:`rankloci.locus`'s ``tip=``.
    tip_link : str, optional
        Deprecated: the old name of ``tip`` (a :class:`DeprecationWarning`).

    Returns
    -------
    RobotModel
        One joint per revolute, continuous or prismatic joint on the chain,
        one variable per such joint without a mimic, with
        ``convention="urdf"``, the full 6-row task, base frame, the robot's
        ``name`` attribute as title, and fixed joints folded into the
        neighbouring transforms.

    Raises
    ------
    ModelError
        On invalid or hostile XML, a missing or malformed attribute, an
        unknown or unsupported joint type, a link tree that is cyclic or not
        connected, an unknown base or tip link, several leaves and no tip, a
        chain without movable joints, or a mimic that cannot be followed (see
        the module docstring).

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

    A finger that mimics the joint before it adds its twist to that joint's
    column:

    >>> finger = urdf.replace('<joint name="flange" type="fixed">',
    ...     '<joint name="flange" type="revolute"><mimic joint="j2" multiplier="-1"/>'
    ...     '<axis xyz="0 0 1"/>')
    >>> m = parse_urdf(finger, name="arm")
    >>> m.variables, m.joint_coordinates
    ((q1, q2), (q1, q2, -q2))
    """
    from ..renamed import renamed_argument

    tip = renamed_argument(tip, tip_link, new="tip", old="tip_link", where="parse_urdf")
    where = file or None
    root = parse_document(text, where)
    links = link_names(root, where)
    joints = joints_by_name(root, links, where)
    parent_of = parent_joints(links, joints, where)

    if base_link is None:
        base_link = next(link for link in links if link not in parent_of)
    elif base_link not in links:
        raise ModelError(f"base link {base_link!r} is not a link of this robot "
                         f"({name_list(links)})", file=where, field="base_link")
    if tip is None:
        tip = single_leaf(base_link, joints, where)
    elif tip not in links:
        raise ModelError(f"tip link {tip!r} is not a link of this robot "
                         f"({name_list(links)})", file=where, field="tip_link")
    chain = chain_joints(base_link, tip, parent_of, where)
    if len(chain) > MAX_CHAIN_JOINTS:
        raise ModelError(f"the chain {base_link} -> {tip} has {len(chain)} joints, more than "
                         f"{MAX_CHAIN_JOINTS}", file=where)
    movable = sum(j.type in JOINT_KINDS for j in chain)
    if movable > MAX_MOVABLE_JOINTS:
        raise ModelError(f"the chain {base_link} -> {tip} has {movable} movable joints, more "
                         f"than {MAX_MOVABLE_JOINTS}", file=where)

    index = {}  # joint name -> 1-based index among the chain's movable joints
    for j in chain:
        if j.type in UNSUPPORTED_TYPES:
            raise ModelError(f"joint {j.name!r} is {j.type}; only revolute, continuous, "
                             f"prismatic and fixed joints are supported (choose a base "
                             f"link below it with --base)", file=where, field="type")
        if j.type in JOINT_KINDS:
            index[j.name] = len(index) + 1
    for j in joints.values():
        check_joint_numbers(j, index.get(j.name), where)
    if not index:
        raise ModelError(f"no revolute, continuous or prismatic joint between "
                         f"{base_link!r} and {tip!r}", file=where)
    chain_text = f"{base_link} -> {tip}"
    followed = {j.name: _followed_joint(j, joints, index, chain_text, where)
                for j in chain if j.name in index and j.element.find("mimic") is not None}
    carried = _carried_leaders(followed, joints, index, chain_text, where)

    model_joints = []
    snaps = Snaps()
    fixed = sp.eye(4)  # fixed transforms accumulated since the last movable joint
    for j in chain:
        i = index.get(j.name)
        fixed = bounded(expanded_product(fixed, exact_origin(*origin_floats(j, None, None),
                                                             snaps)))
        if i is None:
            continue
        kind = JOINT_KINDS[j.type]
        axis = exact_axis(axis_floats(j, i, where), snaps)
        mimic, limits = None, joint_limits(j, i, where)
        if j.name in followed:
            leader, multiplier, offset = followed[j.name]
            if offset != 0:
                fixed = expanded_product(fixed, exact_motion(kind, axis, offset, snaps))
            if j.name in carried:  # the variable is the leader's: the motion is +-q
                axis = tuple(multiplier * a for a in axis)
                limits = joint_limits(joints[leader], i, where)
            else:
                mimic = Mimic(joint=index[leader] - 1, multiplier=multiplier)
        model_joints.append(Joint(
            kind=kind,
            axis=axis,
            pre=sp.ImmutableMatrix(fixed),
            post=sp.ImmutableMatrix(sp.eye(4)),
            name=j.name,
            limits=limits,
            mimic=mimic,
        ))
        fixed = sp.eye(4)

    title = root.get("name", "")
    free = sum(j.mimic is None for j in model_joints)
    note = snaps.note()
    return RobotModel(
        name=name,
        joints=tuple(model_joints),
        variables=tuple(sp.Symbol(f"q{i}", real=True) for i in range(1, free + 1)),
        parameters={},
        title=title,
        source=f"URDF robot {title!r}, chain {base_link} -> {tip}",
        base=sp.ImmutableMatrix(sp.eye(4)),
        tool=sp.ImmutableMatrix(fixed),
        task=TASKS["full"],
        frame="base",
        convention="urdf",
        notes=(note,) if note else (),
    )


def _followed_joint(j: UrdfJoint, joints: dict[str, UrdfJoint], index: dict[str, int],
                    chain_text: str, where) -> tuple[str, sp.Expr, sp.Expr]:
    """``(leader, multiplier, offset)``: the chain joint ``j`` moves by ``multiplier * q + offset``.

    ``q`` is the variable of ``leader``, reached from ``j`` through its
    ``<mimic>`` and the mimics of the joints it names; multiplier and offset
    are exact, composed along the way.
    """
    i = index[j.name]
    kind = JOINT_KINDS[j.type]
    path = [j.name]
    multiplier, offset = sp.Integer(1), sp.Integer(0)
    current = j
    while (m := mimic_floats(current, index.get(current.name), where)) is not None:
        name, mult, off = m
        via = "" if current is j else f" (through {' -> '.join(map(repr, path))})"
        if name in path:
            cycle = " -> ".join(map(repr, path[path.index(name):] + [name]))
            raise ModelError(f"the mimic joints form a cycle: {cycle}; one of them must "
                             f"have a variable of its own", file=where, joint=i, field="mimic")
        leader = joints.get(name)
        if leader is None:
            raise ModelError(f"joint {j.name!r} mimics joint {name!r}{via}, which is not a "
                             f"joint of this robot", file=where, joint=i, field="mimic")
        if leader.type not in JOINT_KINDS:
            raise ModelError(f"joint {j.name!r} mimics joint {name!r}{via}, which is "
                             f"{leader.type}; only a revolute, continuous or prismatic joint "
                             f"can be followed", file=where, joint=i, field="mimic")
        if JOINT_KINDS[leader.type] != kind:
            raise ModelError(f"joint {j.name!r} is {kind} but mimics joint {name!r}{via}, "
                             f"which is {JOINT_KINDS[leader.type]}; a mimic joint must be of "
                             f"the kind of the joint it follows", file=where, joint=i,
                             field="mimic")
        try:
            mult, off = exact_number(mult), exact_number(off)
        except ExpressionError as e:
            raise ModelError(f"joint {j.name!r}: <mimic> of {current.name!r}: {e}",
                             file=where, joint=i, field="mimic") from None
        multiplier, offset = multiplier * mult, multiplier * off + offset
        path.append(name)
        current = leader
    if current.name not in index:
        return current.name, multiplier, offset  # off the chain: see _carried_leaders
    _check_multiplier(kind, j.name, current.name, multiplier, i, where)
    return current.name, multiplier, offset


def _check_multiplier(kind: str, follower: str, leader: str, multiplier: sp.Expr, i,
                      where) -> None:
    """Refuse a revolute coupling whose multiplier is not an integer."""
    if kind == "revolute" and not multiplier.is_integer:
        raise ModelError(f"joint {follower!r} follows joint {leader!r} with multiplier "
                         f"{multiplier}; a revolute mimic joint needs an integer multiplier "
                         f"(the kinematics must stay polynomial in cos and sin of the "
                         f"variables)", file=where, joint=i, field="mimic multiplier")


def _carried_leaders(followed: dict, joints: dict[str, UrdfJoint], index: dict[str, int],
                     chain_text: str, where) -> set[str]:
    """The chain joints that carry the variable of a leader off the chain; ``followed`` updated.

    ``followed`` maps each follower on the chain to ``(leader, multiplier, offset)``.  For each
    leader off the chain, the first of its followers with multiplier +-1 carries the leader's
    variable (its motion is +-q plus the offset) and stays in ``followed``; the leader's other
    followers then follow that joint, whose variable is ``q`` (revolute ones with an integer
    multiplier).  A leader whose followers all have
    other multipliers has no joint to carry its variable: its one follower moves by a variable
    of its own (``q_follower = m q + o`` is a change of variable that keeps the rank) and leaves
    ``followed``; several such followers are refused.
    """
    off_chain: dict[str, list[str]] = {}
    for follower, (leader, _, _) in followed.items():
        if leader not in index:
            off_chain.setdefault(leader, []).append(follower)
    carried = set()
    for leader, followers in off_chain.items():
        carrier = next((f for f in followers if abs(followed[f][1]) == 1), None)
        if carrier is None:
            if len(followers) > 1:
                raise ModelError(
                    f"joints {', '.join(map(repr, followers))} all follow joint {leader!r}, "
                    f"which is not on the chain {chain_text}, none with multiplier 1 or -1, so "
                    f"that no joint of the chain moves by its variable alone; choose a chain "
                    f"through it with --base-link and --tip", file=where,
                    joint=index[followers[-1]], field="mimic")
            del followed[followers[0]]
            continue
        carried.add(carrier)
        for f in followers:
            if f != carrier:
                _, multiplier, offset = followed[f]
                _check_multiplier(JOINT_KINDS[joints[f].type], f, leader, multiplier, index[f],
                                  where)
                followed[f] = (carrier, multiplier, offset)
    return carried


def read_urdf(path, *, base_link: str | None = None, tip: str | None = None,
              tip_link: str | None = None) -> RobotModel:
    """Read a URDF file: :func:`parse_urdf` with name = file stem, file = base name.

    Parameters
    ----------
    path : str or os.PathLike
    base_link, tip : str, optional
        See :func:`parse_urdf`.
    tip_link : str, optional
        Deprecated: the old name of ``tip``.

    Raises
    ------
    ModelError
        If the file cannot be read or decoded as UTF-8, or does not parse.
    """
    from ..renamed import renamed_argument
    from .files import read_bounded

    tip = renamed_argument(tip, tip_link, new="tip", old="tip_link", where="read_urdf")
    p = Path(path)

    try:
        text = read_bounded(p, MAX_FILE_BYTES).decode("utf-8-sig")
    except OSError as e:
        raise ModelError(f"cannot read file: {e.strerror or e}", file=p.name) from None
    except UnicodeDecodeError as e:
        raise ModelError(f"not UTF-8 text ({e.reason} at byte {e.start})", file=p.name) from None
    model = parse_urdf(text, name=p.stem, file=p.name, base_link=base_link, tip=tip)
    return dataclasses.replace(model, path=str(p))
