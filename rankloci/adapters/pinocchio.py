"""The chain of a Pinocchio model as a rankloci model.

Pinocchio keeps each joint's placement in its parent joint's frame
(``model.jointPlacements``) and each frame's placement in its joint's.  The
chain from one frame to another (by default from the root, or from the body a
free-flyer root joint carries, to the one chain end) is written as a URDF
document, one joint per Pinocchio joint and a fixed joint for the frame, and
read by
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


def _origin(T) -> str:
    xyz, rpy = xyz_rpy(np.asarray(T, dtype=float))
    return (f'<origin xyz="{" ".join(length_text(x) for x in xyz)}" '
            f'rpy="{" ".join(repr(a) for a in rpy)}"/>')


def _homogeneous(placement) -> np.ndarray:
    return np.asarray(placement.homogeneous, dtype=float)


def _inverse(T) -> np.ndarray:
    """The inverse of a rigid transform (R^T, -R^T p), without a general matrix inverse."""
    out = np.eye(4)
    out[:3, :3] = T[:3, :3].T
    out[:3, 3] = -T[:3, :3].T @ T[:3, 3]
    return out


def _frame(model, name, role):
    """(joint, placement in that joint's frame) of the frame, or joint, ``name``."""
    if not isinstance(name, str):
        raise ModelError(f"{role} must be a frame name, not {type(name).__name__}")
    if model.existFrame(name):
        frame = model.frames[model.getFrameId(name)]
        return int(frame.parentJoint), _homogeneous(frame.placement)
    if name in list(model.names):          # a joint without a frame of its own (a model built
        return int(model.getJointId(name)), np.eye(4)     # by hand): the joint's frame
    names = sorted({f.name for f in model.frames})
    raise ModelError(f"no frame {name!r} in the model ({role}); frames: {', '.join(names[:20])}"
                     + (" ..." if len(names) > 20 else ""))


def _tip_joint(model, tip):
    """The joint the chain ends at, and the frame placement after it (None for the joint)."""
    if tip is None:
        leaves = [j for j in range(1, model.njoints) if j not in set(model.parents[1:])]
        if len(leaves) != 1:
            raise ModelError("the model has several chain ends; give tip= (a frame name)")
        return leaves[0], None
    return _frame(model, tip, "tip")


def _ancestors(model, j) -> list[int]:
    """``j`` and the joints above it, up to the universe (0) included."""
    out = [j]
    while j > 0:
        j = int(model.parents[j])
        out.append(j)
    return out


def _supported(model, j) -> bool:
    return model.joints[j].shortname() in _JOINTS


def _chain(model, tip, base_link):
    """(joints up from the base, joints down to the tip, base placement, tip placement).

    The path between two frames of the kinematic tree climbs from the base's
    joint to the deepest joint both hang from, then descends to the tip's
    joint.  Without ``base_link`` the chain starts at the root, below a run
    of joints at the root that are not revolute or prismatic (a free-flyer):
    in the frame of the body they carry.
    """
    jt, tip_placement = _tip_joint(model, tip)
    if base_link is None:
        down = _ancestors(model, jt)[::-1][1:]        # root -> tip, the universe left out
        k = 0
        while k < len(down) and not _supported(model, down[k]):
            k += 1
        jb = down[k - 1] if k else 0
        base_placement = np.eye(4)
    else:
        jb, base_placement = _frame(model, base_link, "base_link")
    above_tip, above_base = _ancestors(model, jt), _ancestors(model, jb)
    common = next(j for j in above_base if j in set(above_tip))
    up = above_base[:above_base.index(common)]             # base's joint first
    down = above_tip[:above_tip.index(common)][::-1]       # ends with the tip's joint
    if not up and not down:
        skipped = ("" if base_link is not None or jb == 0 else
                   f" (the chain starts below the root joint {model.names[jb]!r}, a "
                   f"{model.joints[jb].shortname()})")
        raise ModelError(f"no joint between the base and the tip{skipped}; give tip= a frame "
                         "further down the chain")
    return up, down, base_placement, tip_placement


def urdf_text(model, tip=None, base_link=None) -> str:
    """The URDF document of the chain of ``model`` from the frame ``base_link`` to ``tip``.

    A joint on the climbing part of the path (from the base up to the joint
    both frames hang from) moves the base relative to the tip the other way:
    it is written with its axis reversed, so its variable keeps its value and
    sign, and with the inverse of its placement after it.
    """
    up, down, base_placement, tip_placement = _chain(model, tip, base_link)
    lines = ['<robot name="chain">', '<link name="root"/>']
    parent = "root"
    lower, upper = np.asarray(model.lowerPositionLimit), np.asarray(model.upperPositionLimit)
    pending = _inverse(base_placement) if base_link is not None else np.eye(4)
    for k, reverse in [(j, True) for j in up] + [(j, False) for j in down]:
        joint = model.joints[k]
        kind = joint.shortname()
        if kind not in _JOINTS:
            raise ModelError(f"joint {model.names[k]!r} is a {kind}; only revolute and "
                             "prismatic joints (one axis each) are supported between the base "
                             "and the tip (base_link= may start the chain below it)")
        urdf_type, axis = _JOINTS[kind]
        if axis is None:
            axis = tuple(float(x) for x in joint.axis)
        if reverse:
            axis = tuple(-a for a in axis)
            origin = pending
        else:
            origin = pending @ _homogeneous(model.jointPlacements[k])
        limit = ""
        if urdf_type != "continuous":
            lo, hi = float(lower[joint.idx_q]), float(upper[joint.idx_q])
            if not (np.isfinite(lo) and np.isfinite(hi) and lo < hi):
                lo, hi = -1e3, 1e3
            limit = f'<limit lower="{lo!r}" upper="{hi!r}" effort="0" velocity="0"/>'
        child = f"{model.names[k]}_link"
        lines += [f"<joint name={quoteattr(model.names[k])} type=\"{urdf_type}\">",
                  f'<parent link={quoteattr(parent)}/><child link={quoteattr(child)}/>',
                  _origin(origin),
                  f'<axis xyz="{" ".join(repr(float(a)) for a in axis)}"/>{limit}</joint>',
                  f"<link name={quoteattr(child)}/>"]
        parent = child
        pending = _inverse(_homogeneous(model.jointPlacements[k])) if reverse else np.eye(4)
    if tip_placement is not None or not np.array_equal(pending, np.eye(4)):
        last = pending if tip_placement is None else pending @ tip_placement
        lines += ['<joint name="tip_joint" type="fixed">',
                  f'<parent link={quoteattr(parent)}/><child link="tip"/>',
                  _origin(last), "</joint>", '<link name="tip"/>']
    return "\n".join(lines + ["</robot>"])


def from_pinocchio(model, *, tip=None, base_link=None, name=None):
    """A rankloci model of the chain of a Pinocchio model from one frame to another.

    Parameters
    ----------
    model : pinocchio.Model or pinocchio.RobotWrapper
        A wrapper's ``model`` is taken.  The joints on the chain must be
        revolute (``RX``, ``RY``, ``RZ``, unaligned, unbounded) or prismatic;
        a free-flyer, spherical or planar joint between the base and the tip
        is refused.
    tip : str, optional
        The frame the task point is at (a link, joint or operational frame,
        or a joint's name); default: the one chain end when the model has one.
    base_link : str, optional
        The frame the chain starts at, whose axes the Jacobian is expressed
        in: any frame of the model, also one that is not above the tip (the
        chain then climbs to the joint both hang from and descends to the
        tip).  Default: the root; when the model's root joint is a free-flyer
        (a legged or humanoid robot, ``pin.JointModelFreeFlyer()``), the body
        it carries (the floating base), so the free-flyer is left out.
    name : str, optional
        Model name (default: the Pinocchio model's name, made a valid name).

    Returns
    -------
    RobotModel
        Joint variables ``q1..qn`` are the chain's joints in order from the
        base (``RobotModel.joints[k].name`` is the Pinocchio joint's name):
        Pinocchio's configuration entries of those joints, with their own
        signs.  The task is the full Jacobian of the tip's origin in the base
        frame (from the root: Pinocchio's ``LOCAL_WORLD_ALIGNED`` frame
        Jacobian, linear rows first).

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

    inner = getattr(model, "model", None)
    if not hasattr(model, "jointPlacements") and inner is not None:
        model = inner                                   # a RobotWrapper
    if not all(hasattr(model, a) for a in ("jointPlacements", "parents", "frames")):
        raise ModelError("from_pinocchio takes a pinocchio.Model or RobotWrapper, not "
                         f"{type(model).__name__}")
    label = name or re.sub(r"[^a-z0-9_-]+", "_", str(model.name or "model").lower()).strip("_-")
    return parse_urdf(urdf_text(model, tip, base_link), name=label or "model",
                      file=f"{label}.urdf")
