"""Every serial chain of a URDF document, for sweeps over robot collections.

A URDF file describes a tree of links; :func:`urdf_chains` lists the serial
chains in it that :func:`rankloci.io.urdf.parse_urdf` can read.  Each path
from the root link to a leaf link is a candidate; its chain runs from the root
to the child link of the path's last movable joint, so paths that differ only
after that joint give one chain.  Chains whose joints have the same types,
origins and axes are kept once.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

__all__ = ["UrdfChain", "urdf_chains", "example_robot_data_dir"]


@dataclass(frozen=True)
class UrdfChain:
    """One serial chain of a URDF document.

    Attributes
    ----------
    base : str
        The root link: ``--base-link``.
    tip : str
        The child link of the last movable joint: ``--tip``.
    joints : tuple of str
        The names of the movable joints, root to tip.
    also : tuple of str
        Other leaf links whose paths from the root give the same chain.
    """

    base: str
    tip: str
    joints: tuple
    also: tuple = ()

    @property
    def n(self) -> int:
        """The number of movable joints."""
        return len(self.joints)


def urdf_chains(text, *, file: str = "", min_joints: int = 1,
                max_joints: int | None = None) -> tuple[list[UrdfChain], int]:
    """The chains of a URDF document with ``min_joints`` to ``max_joints`` movable joints.

    Parameters
    ----------
    text : str or bytes
        The URDF XML (bytes are read as UTF-8).
    file : str, optional
        File name used in error messages.
    min_joints, max_joints : int, optional
        Bounds on the number of movable joints (``max_joints=None``: no upper bound).

    Returns
    -------
    (list of UrdfChain, int)
        The chains in depth-first order of the link tree (children in document
        order), and how many root-to-leaf paths fell outside the bounds.

    Raises
    ------
    ModelError
        When the document is not a readable link tree.

    Examples
    --------
    >>> urdf = '''<robot name="y">
    ...   <link name="b"/><link name="l1"/><link name="l2"/><link name="l3"/>
    ...   <joint name="j1" type="revolute"><parent link="b"/><child link="l1"/>
    ...     <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
    ...   <joint name="j2" type="continuous"><parent link="l1"/><child link="l2"/>
    ...     <origin xyz="1 0 0"/></joint>
    ...   <joint name="j3" type="continuous"><parent link="l1"/><child link="l3"/>
    ...     <origin xyz="0 1 0"/></joint>
    ... </robot>'''
    >>> chains, outside = urdf_chains(urdf, min_joints=2)
    >>> [(c.base, c.tip, c.joints) for c in chains], outside
    ([('b', 'l2', ('j1', 'j2')), ('b', 'l3', ('j1', 'j3'))], 0)
    """
    from .urdf_xml import JOINT_KINDS, joints_by_name, link_names, parent_joints, parse_document

    root = parse_document(text, file)
    links = link_names(root, file)
    joints = joints_by_name(root, links, file)
    parent_of = parent_joints(links, joints, file)
    base = next(link for link in links if link not in parent_of)
    children: dict[str, list] = {}
    for j in joints.values():
        children.setdefault(j.parent, []).append(j)

    def geometry(j):
        origin, axis = j.element.find("origin"), j.element.find("axis")
        return (j.type, None if origin is None else (origin.get("xyz"), origin.get("rpy")),
                None if axis is None else axis.get("xyz"))

    found: dict[tuple, tuple[UrdfChain, list]] = {}
    outside = 0
    stack = [(base, ())]
    while stack:
        link, path = stack.pop()
        if link in children:
            stack.extend((j.child, path + (j,)) for j in reversed(children[link]))
            continue
        movable = [k for k, j in enumerate(path) if j.type in JOINT_KINDS]
        if not movable or len(movable) < min_joints or (
                max_joints is not None and len(movable) > max_joints):
            outside += 1
            continue
        head = path[: movable[-1] + 1]
        key = tuple(geometry(j) for j in head)
        if key in found:
            found[key][1].append(link)
            continue
        found[key] = (UrdfChain(base, head[-1].child, tuple(path[k].name for k in movable)),
                      [link])
    out = []
    for chain, leaves in found.values():
        others = tuple(leaf for leaf in leaves if leaf != chain.tip)
        out.append(UrdfChain(chain.base, chain.tip, chain.joints, others))
    return out, outside


def example_robot_data_dir() -> Path | None:
    """The ``robots`` directory of an installed example-robot-data package, or None."""
    import site
    import sysconfig

    roots = list(site.getsitepackages()) + [site.getusersitepackages(),
                                            sysconfig.get_paths()["purelib"]]
    for root in roots:
        d = Path(root) / "cmeel.prefix" / "share" / "example-robot-data" / "robots"
        if d.is_dir():
            return d
    return None
