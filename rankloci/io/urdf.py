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

from ..errors import ModelError
from ..model import TASKS, Joint, RobotModel
from .urdf_exact import exact_axis, exact_origin, expanded_product
from .urdf_xml import (
    JOINT_KINDS,
    UNSUPPORTED_TYPES,
    axis_floats,
    chain_joints,
    check_joint_numbers,
    joint_limits,
    joints_by_name,
    link_names,
    name_list,
    origin_floats,
    parent_joints,
    parse_document,
    single_leaf,
)

__all__ = ["parse_urdf", "read_urdf", "JOINT_KINDS"]


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
    root = parse_document(text, where)
    links = link_names(root, where)
    joints = joints_by_name(root, links, where)
    parent_of = parent_joints(links, joints, where)

    if base_link is None:
        base_link = next(link for link in links if link not in parent_of)
    elif base_link not in links:
        raise ModelError(f"base link {base_link!r} is not a link of this robot "
                         f"({name_list(links)})", file=where, field="base_link")
    if tip_link is None:
        tip_link = single_leaf(base_link, joints, where)
    elif tip_link not in links:
        raise ModelError(f"tip link {tip_link!r} is not a link of this robot "
                         f"({name_list(links)})", file=where, field="tip_link")
    chain = chain_joints(base_link, tip_link, parent_of, where)

    index = {}  # joint name -> 1-based index among the chain's movable joints
    for j in chain:
        if j.type in UNSUPPORTED_TYPES:
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
        check_joint_numbers(j, index.get(j.name), where)
    if not index:
        raise ModelError(f"no revolute, continuous or prismatic joint between "
                         f"{base_link!r} and {tip_link!r}", file=where)

    model_joints = []
    fixed = sp.eye(4)  # fixed transforms accumulated since the last movable joint
    for j in chain:
        i = index.get(j.name)
        fixed = expanded_product(fixed, exact_origin(*origin_floats(j, None, None)))
        if i is None:
            continue
        model_joints.append(Joint(
            kind=JOINT_KINDS[j.type],
            axis=exact_axis(axis_floats(j, i, where)),
            pre=sp.ImmutableMatrix(fixed),
            post=sp.ImmutableMatrix(sp.eye(4)),
            name=j.name,
            limits=joint_limits(j, i, where),
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
