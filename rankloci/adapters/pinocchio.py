"""The chain of a Pinocchio model as a rankloci model.

Pinocchio keeps each joint's placement in its parent joint's frame
(``model.jointPlacements``) and each frame's placement in its joint's.  The
chain from the root to a frame is written as a URDF document, one joint per
Pinocchio joint and a fixed joint for the frame, and read by
:func:`rankloci.io.urdf.parse_urdf`: its angles and lengths become exact as a
URDF file's do (angles within 1e-5 of a multiple of pi/12 snap to it, other
rotations become exact rational rotations).
"""

from __future__ import annotations

import re
from xml.sax.saxutils import quoteattr

import numpy as np

from ..errors import ModelError
from .transforms import length_text, xyz_rpy

__all__ = ["from_pinocchio", "urdf_text"]

#: Pinocchio joint types -> (URDF type, axis); None: the axis is the joint's own ``axis``.
_JOINTS = {
    "JointModelRX": ("revolute", (1, 0, 0)), "JointModelRY": ("revolute", (0, 1, 0)),
    "JointModelRZ": ("revolute", (0, 0, 1)), "JointModelRevoluteUnaligned": ("revolute", None),
    "JointModelRUBX": ("continuous", (1, 0, 0)), "JointModelRUBY": ("continuous", (0, 1, 0)),
    "JointModelRUBZ": ("continuous", (0, 0, 1)),
    "JointModelRevoluteUnboundedUnaligned": ("continuous", None),
    "JointModelPX": ("prismatic", (1, 0, 0)), "JointModelPY": ("prismatic", (0, 1, 0)),
    "JointModelPZ": ("prismatic", (0, 0, 1)), "JointModelPrismaticUnaligned": ("prismatic", None),
}


def _origin(placement) -> str:
    xyz, rpy = xyz_rpy(np.asarray(placement.homogeneous))
    return (f'<origin xyz="{" ".join(length_text(x) for x in xyz)}" '
            f'rpy="{" ".join(repr(a) for a in rpy)}"/>')


def _tip_joint(model, tip):
    """The joint the chain ends at, and the frame placement after it (None for the joint)."""
    if tip is None:
        leaves = [j for j in range(1, model.njoints) if j not in set(model.parents[1:])]
        if len(leaves) != 1:
            raise ModelError("the model has several chain ends; give tip= (a frame name)")
        return leaves[0], None
    if not isinstance(tip, str):
        raise ModelError(f"tip must be a frame name, not {type(tip).__name__}")
    if model.existFrame(tip):
        frame = model.frames[model.getFrameId(tip)]
        return int(frame.parentJoint), frame.placement
    names = sorted({f.name for f in model.frames})
    raise ModelError(f"no frame {tip!r} in the model; frames: {', '.join(names[:20])}"
                     + (" ..." if len(names) > 20 else ""))


def urdf_text(model, tip=None) -> str:
    """The URDF document of the chain of ``model`` from its root to the frame ``tip``."""
    j, placement = _tip_joint(model, tip)
    chain = []
    while j > 0:
        chain.append(j)
        j = int(model.parents[j])
    chain.reverse()
    lines = ['<robot name="chain">', '<link name="root"/>']
    parent = "root"
    lower, upper = np.asarray(model.lowerPositionLimit), np.asarray(model.upperPositionLimit)
    for k in chain:
        joint = model.joints[k]
        kind = joint.shortname()
        if kind not in _JOINTS:
            raise ModelError(f"joint {model.names[k]!r} is a {kind}; only revolute and "
                             "prismatic joints (one axis each) are supported")
        urdf_type, axis = _JOINTS[kind]
        if axis is None:
            axis = tuple(float(x) for x in joint.axis)
        limit = ""
        if urdf_type != "continuous":
            lo, hi = float(lower[joint.idx_q]), float(upper[joint.idx_q])
            if not (np.isfinite(lo) and np.isfinite(hi) and lo < hi):
                lo, hi = -1e3, 1e3
            limit = f'<limit lower="{lo!r}" upper="{hi!r}" effort="0" velocity="0"/>'
        child = f"{model.names[k]}_link"
        lines += [f"<joint name={quoteattr(model.names[k])} type=\"{urdf_type}\">",
                  f'<parent link={quoteattr(parent)}/><child link={quoteattr(child)}/>',
                  _origin(model.jointPlacements[k]),
                  f'<axis xyz="{" ".join(repr(float(a)) for a in axis)}"/>{limit}</joint>',
                  f"<link name={quoteattr(child)}/>"]
        parent = child
    if placement is not None:
        lines += ['<joint name="tip_joint" type="fixed">',
                  f'<parent link={quoteattr(parent)}/><child link="tip"/>',
                  _origin(placement), "</joint>", '<link name="tip"/>']
    return "\n".join(lines + ["</robot>"])


def from_pinocchio(model, *, tip=None, name=None):
    """A rankloci model of the chain of a Pinocchio model from its root to a frame.

    Parameters
    ----------
    model : pinocchio.Model
        With revolute (``RX``, ``RY``, ``RZ``, unaligned, unbounded) and
        prismatic joints on the chain; a free-flyer, spherical or planar
        joint is refused.
    tip : str, optional
        The frame the task point is at (a link, joint or operational frame);
        default: the one chain end when the model has one.
    name : str, optional
        Model name (default: the Pinocchio model's name, made a valid name).

    Returns
    -------
    RobotModel
        Joint variables ``q1..qn`` are the chain's joints in order from the
        root: Pinocchio's configuration entries of those joints.  The task is
        the full Jacobian of the tip's origin in the root frame (Pinocchio's
        ``LOCAL_WORLD_ALIGNED`` frame Jacobian, linear rows first).

    Examples
    --------
    A planar arm built by hand (two joints about z, links of 1 and 0.5):

    >>> import numpy as np, pinocchio as pin, rankloci
    >>> m = pin.Model()
    >>> j1 = m.addJoint(0, pin.JointModelRZ(), pin.SE3.Identity(), "j1")
    >>> j2 = m.addJoint(j1, pin.JointModelRZ(), pin.SE3(np.eye(3), np.array([1.0, 0, 0])), "j2")
    >>> tip = pin.SE3(np.eye(3), np.array([0.5, 0, 0]))
    >>> _ = m.addFrame(pin.Frame("tip", j2, tip, pin.FrameType.OP_FRAME))
    >>> robot = from_pinocchio(m, tip="tip")
    >>> robot
    <RobotModel 'model': 2 revolute joints, URDF joints>
    >>> [str(c.equations[0]) for c in rankloci.locus(robot, task="planar").components]
    ['sin(q2)']
    """
    from ..io.urdf import parse_urdf

    if not all(hasattr(model, a) for a in ("jointPlacements", "parents", "frames")):
        raise ModelError(f"from_pinocchio takes a pinocchio.Model, not {type(model).__name__}")
    label = name or re.sub(r"[^a-z0-9_-]+", "_", str(model.name or "model").lower()).strip("_-")
    return parse_urdf(urdf_text(model, tip), name=label or "model", file=f"{label}.urdf")
