"""The model objects: serial robots and plain symbolic matrices.

A :class:`RobotModel` is a chain of joints.  Every joint, whatever file it came
from, is stored in one general form::

    T_i(q_i) = pre_i * Motion(axis_i, q_i) * post_i

where ``pre_i`` and ``post_i`` are constant 4x4 homogeneous transforms (exact
sympy matrices, possibly containing parameter symbols) and ``Motion`` is a
rotation about (revolute) or a translation along (prismatic) the unit vector
``axis_i``.  Standard DH puts the motion first (``pre = I``), modified DH puts
it last (``post = I``) and URDF puts the origin in ``pre``.  The DH fields are
kept beside, for display.

A joint with a :class:`Mimic` (a URDF gripper finger) has no variable of its
own: it moves by ``multiplier * q`` where ``q`` is the variable of the joint it
follows, so ``variables`` holds one symbol per joint *without* a mimic, and
the Jacobian one column per variable.

A :class:`MatrixModel` is any symbolic matrix in named variables.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field
from typing import Mapping

import sympy as sp

__all__ = [
    "DHParams",
    "Mimic",
    "Joint",
    "RobotModel",
    "MatrixModel",
    "TASKS",
    "task_rows",
    "rot_x",
    "rot_y",
    "rot_z",
    "trans",
    "rpy_rotation",
    "homogeneous",
]

#: Named task-row selections of the 6-row (linear velocity, then angular) Jacobian.
TASKS: dict[str, tuple[int, ...]] = {
    "full": (0, 1, 2, 3, 4, 5),
    "position": (0, 1, 2),
    "orientation": (3, 4, 5),
    "planar": (0, 1),
}


def task_rows(task) -> tuple[int, ...]:
    """Return the row indices selected by a task name or an explicit row list.

    Examples
    --------
    >>> task_rows("planar")
    (0, 1)
    >>> task_rows([0, 1, 5])
    (0, 1, 5)
    """
    if isinstance(task, str):
        try:
            return TASKS[task]
        except KeyError:
            raise ValueError(
                f"task {task!r} is not one of {sorted(TASKS)} or a list of rows"
            ) from None
    rows = tuple(task)
    if not rows:
        raise ValueError("task row list is empty")
    for r in rows:
        if isinstance(r, bool) or not isinstance(r, int) or not 0 <= r <= 5:
            raise ValueError(f"task row {r!r} is not an integer in 0..5")
    if len(set(rows)) != len(rows):
        raise ValueError(f"task rows {list(rows)} repeat a row")
    return rows


@dataclass(frozen=True)
class DHParams:
    """The four DH fields of a joint, as written in the model file."""

    convention: str  # "dh" or "mdh"
    a: sp.Expr
    alpha: sp.Expr
    d: sp.Expr
    theta: sp.Expr


@dataclass(frozen=True)
class Mimic:
    """The coupling of a joint that follows another: it moves by ``multiplier * q``.

    ``q`` is the variable of joint ``joint`` (0-based index in
    :attr:`RobotModel.joints`), which has no mimic itself.  A constant offset
    of the coupling is part of the follower's ``pre`` transform.
    """

    joint: int
    multiplier: sp.Expr


@dataclass(frozen=True)
class Joint:
    """One joint of a serial chain in the general form ``pre * Motion * post``."""

    kind: str                # "revolute" or "prismatic"
    axis: tuple[sp.Expr, sp.Expr, sp.Expr]
    pre: sp.ImmutableMatrix  # 4x4 constant transform before the motion
    post: sp.ImmutableMatrix  # 4x4 constant transform after the motion
    name: str = ""
    dh: DHParams | None = None
    limits: tuple[float, float] | None = None
    mimic: Mimic | None = None  # set when the joint follows another joint's variable

    def __repr__(self) -> str:
        motion = "about" if self.kind == "revolute" else "along"
        dh = (f", {self.dh.convention} a={self.dh.a} alpha={self.dh.alpha} d={self.dh.d} "
              f"theta={self.dh.theta}") if self.dh is not None else ""
        mimic = f", follows joint {self.mimic.joint + 1}" if self.mimic is not None else ""
        return (f"<Joint {self.name!r}: {self.kind} {motion} "
                f"({', '.join(str(c) for c in self.axis)}){dh}{mimic}>")

    def __post_init__(self):
        if self.kind not in ("revolute", "prismatic"):
            raise ValueError(f"joint kind {self.kind!r} is not 'revolute' or 'prismatic'")


class _ContentIdentity:
    """Equality and hashing by :meth:`content_key`, so models can key caches."""

    @functools.cached_property
    def _key(self) -> str:
        return self.content_key()

    def __eq__(self, other):
        return type(self) is type(other) and self._key == other._key

    def __hash__(self):
        return hash(self._key)


@dataclass(frozen=True, eq=False)
class RobotModel(_ContentIdentity):
    """A serial manipulator, validated once, with exact symbolic geometry.

    Attributes
    ----------
    name : str
        Identifier; equals the file stem for model files.
    joints : tuple of Joint
        Joint ``i`` (0-based) moves by ``joint_coordinates[i]``: variable
        ``variables[i]`` when no joint has a :class:`Mimic`.
    variables : tuple of sympy.Symbol
        Joint variables ``q1..qn`` (real symbols), one per joint without a
        mimic, in chain order.
    parameters : dict
        Parameter symbol -> numeric value (a sympy number).
    base, tool : sympy.ImmutableMatrix
        Constant 4x4 transforms before the first joint and after the last.
    task : tuple of int
        Default task rows of the 6-row Jacobian.
    frame : str
        Default frame the Jacobian is expressed in.
    augment : tuple of (str, sympy.Expr)
        Named constraint functions g(q) whose gradients augment J.
    points : tuple of (str, int)
        Named points (``elbow``, ``wrist``, ...): the origin of a link frame.
    notes : tuple of str
        What reading the model file changed (a URDF's snapped angles and
        lengths); every locus of the model carries them in its notes.
    """

    name: str
    joints: tuple[Joint, ...]
    variables: tuple[sp.Symbol, ...]
    parameters: Mapping[sp.Symbol, sp.Expr] = field(default_factory=dict)
    title: str = ""
    source: str = ""
    base: sp.ImmutableMatrix = sp.ImmutableMatrix(sp.eye(4))
    tool: sp.ImmutableMatrix = sp.ImmutableMatrix(sp.eye(4))
    task: tuple[int, ...] = TASKS["full"]
    frame: str = "base"
    augment: tuple[tuple[str, sp.Expr], ...] = ()
    convention: str = "dh"
    path: str = ""
    points: tuple[tuple[str, int], ...] = ()
    notes: tuple[str, ...] = ()

    def __repr__(self) -> str:
        kinds = [j.kind for j in self.joints]
        counts = ", ".join(f"{kinds.count(k)} {k}" for k in ("revolute", "prismatic")
                           if k in kinds)
        convention = {"dh": "standard DH", "mdh": "modified DH",
                      "urdf": "URDF joints"}.get(self.convention, self.convention)
        params = ", ".join(sorted(p.name for p in self.parameters))
        return (f"<RobotModel {self.name!r}: {counts or 'no'} joint{'s' * (len(kinds) != 1)}, "
                f"{convention}" + (f", parameters {params}" if params else "") + ">")

    @property
    def dof(self) -> int:
        """Number of joints (mimic joints included: the link frames are 0..dof)."""
        return len(self.joints)

    @property
    def joint_coordinates(self) -> tuple[sp.Expr, ...]:
        """What each joint moves by: its variable, or ``multiplier * q`` for a mimic joint."""
        own = dict(zip((i for i, j in enumerate(self.joints) if j.mimic is None), self.variables))
        return tuple(own[i] if j.mimic is None else j.mimic.multiplier * own[j.mimic.joint]
                     for i, j in enumerate(self.joints))

    @property
    def angle_variables(self) -> tuple[sp.Symbol, ...]:
        """Joint variables of revolute joints (they enter through sin and cos)."""
        own = (j for j in self.joints if j.mimic is None)
        return tuple(v for v, j in zip(self.variables, own) if j.kind == "revolute")

    def content_key(self) -> str:
        """A string that changes whenever anything the kinematics depend on changes."""
        parts = [self.name, self.convention, repr(self.task), self.frame,
                 repr([v.name for v in self.variables]), srepr_matrix(self.base), srepr_matrix(self.tool)]
        for j in self.joints:
            parts += [j.kind, sp.srepr(sp.Tuple(*j.axis)), srepr_matrix(j.pre), srepr_matrix(j.post)]
            if j.mimic is not None:
                parts.append(f"mimic {j.mimic.joint} {sp.srepr(j.mimic.multiplier)}")
        parts += [f"{k}={sp.srepr(v)}" for k, v in sorted(self.parameters.items(), key=lambda kv: kv[0].name)]
        parts += [f"{n}:{sp.srepr(e)}" for n, e in self.augment]
        parts += [f"point {n}={k}" for n, k in self.points]
        return "|".join(parts)


@dataclass(frozen=True, eq=False)
class MatrixModel(_ContentIdentity):
    """Any symbolic matrix in named variables.

    Attributes
    ----------
    name : str
    matrix : sympy.ImmutableMatrix
    variables : tuple of sympy.Symbol
    parameters : dict
        Parameter symbol -> numeric value.
    """

    name: str
    matrix: sp.ImmutableMatrix
    variables: tuple[sp.Symbol, ...]
    parameters: Mapping[sp.Symbol, sp.Expr] = field(default_factory=dict)
    title: str = ""
    source: str = ""
    augment: tuple[tuple[str, sp.Expr], ...] = ()
    path: str = ""

    def __repr__(self) -> str:
        params = ", ".join(sorted(p.name for p in self.parameters))
        return (f"<MatrixModel {self.name!r}: {self.matrix.rows}x{self.matrix.cols} in "
                f"{', '.join(v.name for v in self.variables)}"
                + (f", parameters {params}" if params else "") + ">")

    def content_key(self) -> str:
        """A string that changes whenever the matrix or its parameters change."""
        parts = [self.name, srepr_matrix(self.matrix), repr([v.name for v in self.variables])]
        parts += [f"{k}={sp.srepr(v)}" for k, v in sorted(self.parameters.items(), key=lambda kv: kv[0].name)]
        parts += [f"{n}:{sp.srepr(e)}" for n, e in self.augment]
        return "|".join(parts)

    @property
    def angle_variables(self) -> tuple[sp.Symbol, ...]:
        """Variables that appear only inside sin, cos or tan."""
        out = []
        trig = (sp.sin, sp.cos, sp.tan)
        for v in self.variables:
            inside = outside = False
            for e in self.matrix:
                inside |= any(v in f.free_symbols for f in e.atoms(*trig))
                bare = e.replace(lambda x: isinstance(x, trig), lambda x: sp.Integer(1))
                outside |= v in bare.free_symbols
            if inside and not outside:
                out.append(v)
        return tuple(out)


def srepr_matrix(m) -> str:
    return sp.srepr(sp.ImmutableMatrix(m))


# --- homogeneous transforms -------------------------------------------------

def rot_x(t) -> sp.Matrix:
    c, s = sp.cos(t), sp.sin(t)
    return sp.Matrix([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1]])


def rot_y(t) -> sp.Matrix:
    c, s = sp.cos(t), sp.sin(t)
    return sp.Matrix([[c, 0, s, 0], [0, 1, 0, 0], [-s, 0, c, 0], [0, 0, 0, 1]])


def rot_z(t) -> sp.Matrix:
    c, s = sp.cos(t), sp.sin(t)
    return sp.Matrix([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])


def trans(x, y, z) -> sp.Matrix:
    return sp.Matrix([[1, 0, 0, x], [0, 1, 0, y], [0, 0, 1, z], [0, 0, 0, 1]])


def rpy_rotation(roll, pitch, yaw) -> sp.Matrix:
    """URDF convention: R = Rz(yaw) Ry(pitch) Rx(roll) (fixed-axis X, then Y, then Z)."""
    return rot_z(yaw) * rot_y(pitch) * rot_x(roll)


def homogeneous(xyz, rpy) -> sp.ImmutableMatrix:
    """Transform with translation ``xyz`` and URDF roll-pitch-yaw rotation ``rpy``."""
    return sp.ImmutableMatrix(trans(*xyz) * rpy_rotation(*rpy))
