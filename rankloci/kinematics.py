"""Forward kinematics and the geometric Jacobian, symbolically.

The chain is a product of elementary factors::

    base, pre_1, M_1(q_1), post_1, pre_2, M_2(q_2), post_2, ..., tool

Transforms are computed *relative to a chosen frame*: factors after it are
multiplied forward, factors before it backward (as exact inverses).  A
Jacobian expressed in a middle link's frame therefore comes out small,
without any simplification of a base-frame expression.

Frames and reference points are named by :func:`frame_position`:

- ``"base"``: the world frame, before the base transform;
- ``"tool"``: the tool frame, after the tool transform;
- an integer ``k`` in ``0..n``: the frame after joint ``k`` (``0`` is the
  frame after the base transform).

A mimic joint moves by ``multiplier * q`` (:attr:`RobotModel.joint_coordinates`),
so by the chain rule the Jacobian column of ``q`` is the sum of the twists of
the joints that move with ``q``, each times its multiplier: one column per
variable.

The Jacobian rows are the linear velocity of the reference point, then the
angular velocity, both expressed in the chosen frame.  Its rank does not
depend on the frame; for the full 6-row task it does not depend on the
reference point either (a change of point is an invertible row operation).
"""

from __future__ import annotations

from functools import lru_cache

import sympy as sp

from .model import RobotModel, task_rows

__all__ = [
    "forward_kinematics",
    "geometric_jacobian",
    "frame_position",
    "relative_transforms",
    "augmented_rows",
    "trig_normal",
    "turns_about_z",
]


def _motion(kind: str, axis, q) -> sp.Matrix:
    """4x4 transform of a joint moving by ``q`` about/along the unit ``axis``.

    ``q`` is a variable or, for a mimic joint, an integer multiple of one:
    ``cos(2*q)`` is expanded to a polynomial in ``cos(q)`` and ``sin(q)``.
    """
    x, y, z = axis
    if kind == "prismatic":
        return sp.Matrix([[1, 0, 0, x * q], [0, 1, 0, y * q], [0, 0, 1, z * q], [0, 0, 0, 1]])
    c, s = sp.cos(q), sp.sin(q)
    if not isinstance(q, sp.Symbol):
        c, s = sp.expand_trig(c), sp.expand_trig(s)
    if (x, y, z) == (0, 0, 1):
        R = sp.Matrix([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    elif (x, y, z) == (0, 0, -1):
        R = sp.Matrix([[c, s, 0], [-s, c, 0], [0, 0, 1]])
    else:
        v = 1 - c
        R = sp.Matrix([
            [c + x * x * v, x * y * v - z * s, x * z * v + y * s],
            [y * x * v + z * s, c + y * y * v, y * z * v - x * s],
            [z * x * v - y * s, z * y * v + x * s, c + z * z * v],
        ])
    T = sp.eye(4)
    T[:3, :3] = R
    return T


def _inverse(T: sp.Matrix) -> sp.Matrix:
    R, p = T[:3, :3], T[:3, 3]
    Ti = sp.eye(4)
    Ti[:3, :3] = R.T
    Ti[:3, 3] = -R.T * p
    return Ti


def _is_sin_power(e) -> bool:
    return e.is_Pow and isinstance(e.base, sp.sin) and e.exp.is_Integer and e.exp >= 2


def _sin_power_reduced(e):
    k, r = divmod(int(e.exp), 2)
    s = e.base
    return (1 - sp.cos(s.args[0]) ** 2) ** k * s ** r


def trig_normal(expr):
    """Expanded form with every ``sin(x)**2`` written as ``1 - cos(x)**2``.

    This is the normal form modulo ``sin(x)**2 + cos(x)**2 - 1``: a polynomial
    in the cosines, at most linear in each sine.  Identical functions have
    identical normal forms, so cancellations happen without ``simplify``.

    Examples
    --------
    >>> import sympy as sp
    >>> x = sp.Symbol("x")
    >>> trig_normal(sp.sin(x)**2 * sp.cos(x) + sp.cos(x)**3)
    cos(x)
    """
    e = sp.expand(expr)
    if e.has(sp.sin):
        e = sp.expand(e.replace(_is_sin_power, _sin_power_reduced))
    return e


def _mul(A: sp.Matrix, B: sp.Matrix) -> sp.Matrix:
    """Product of two homogeneous transforms, entries in :func:`trig_normal` form."""
    return (A * B).applyfunc(trig_normal)


def _factors(model: RobotModel) -> list[sp.Matrix]:
    out = [sp.Matrix(model.base)]
    for j, q in zip(model.joints, model.joint_coordinates):
        out += [sp.Matrix(j.pre), _motion(j.kind, j.axis, q), sp.Matrix(j.post)]
    out.append(sp.Matrix(model.tool))
    return out


def frame_position(model: RobotModel, frame) -> int:
    """Index in the factor list at which ``frame`` sits (0 = world).

    Examples
    --------
    >>> from rankloci.io.toml_model import parse_model
    >>> m = parse_model('name = "r"\\n[[joint]]\\nkind = "revolute"\\na = 1\\nalpha = 0\\nd = 0\\n')
    >>> frame_position(m, "base"), frame_position(m, 1), frame_position(m, "tool")
    (0, 4, 5)
    """
    n = model.dof
    if frame == "base":
        return 0
    if frame == "tool":
        return 3 * n + 2
    if isinstance(frame, int) and not isinstance(frame, bool) and 0 <= frame <= n:
        return 1 + 3 * frame
    raise ValueError(f"frame {frame!r} is not 'base', 'tool' or an integer in 0..{n}")


@lru_cache(maxsize=64)
def _relative_cached(model: RobotModel, ref: int) -> tuple[sp.ImmutableMatrix, ...]:
    F = _factors(model)
    T = [None] * (len(F) + 1)
    T[ref] = sp.eye(4)
    for p in range(ref, len(F)):
        T[p + 1] = _mul(T[p], F[p])
    for p in range(ref - 1, -1, -1):
        T[p] = _mul(T[p + 1], _inverse(F[p]))
    return tuple(sp.ImmutableMatrix(t) for t in T)


def relative_transforms(model: RobotModel, frame="base") -> tuple[sp.ImmutableMatrix, ...]:
    """Transforms from ``frame`` to every position of the factor list.

    Entry ``p`` is the pose, seen from ``frame``, of the frame between factor
    ``p - 1`` and factor ``p``; entry ``3 i - 1`` (1-based joint ``i``) is the
    frame in which joint ``i`` moves, the last entry is the tool frame.
    Cached by model.
    """
    return _relative_cached(model, frame_position(model, frame))


def turns_about_z(model: RobotModel, frame) -> bool:
    """Is ``frame`` the model's own frame turned about its z axis, for every q?

    Decided exactly: the third row and column of the relative rotation must
    expand to (0, 0, 1).  Then vx, vy and wz seen from ``frame`` are those of
    the model's frame turned about z, which keeps the rank of those rows (a
    planar arm).  Anything not identically so (a spatial arm) answers False.
    """
    R = relative_transforms(model, model.frame)[frame_position(model, frame)][:3, :3]
    return all(sp.expand(R[i, j]) == (1 if i == j == 2 else 0)
               for i, j in ((2, 0), (2, 1), (2, 2), (0, 2), (1, 2)))


def forward_kinematics(model: RobotModel, frame="base") -> sp.Matrix:
    """Pose of the tool frame as a 4x4 homogeneous transform, seen from ``frame``.

    Examples
    --------
    >>> from rankloci.io.toml_model import parse_model
    >>> m = parse_model('name = "r"\\n[[joint]]\\nkind = "revolute"\\na = 1\\nalpha = 0\\nd = 0\\n')
    >>> forward_kinematics(m)[:2, 3].T
    Matrix([[cos(q1), sin(q1)]])
    """
    return sp.Matrix(relative_transforms(model, frame)[-1])


def _cross(a, b):
    return sp.Matrix([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


@lru_cache(maxsize=64)
def _jacobian_cached(model: RobotModel, frame, point) -> sp.ImmutableMatrix:
    T = relative_transforms(model, frame)
    p_ref = T[frame_position(model, point)][:3, 3]
    twists = []
    for i, joint in enumerate(model.joints):
        Ti = T[3 * i + 2]  # frame in which joint i+1 moves
        z = Ti[:3, :3] * sp.Matrix(joint.axis)
        if joint.kind == "revolute":
            v = _cross(z, p_ref - Ti[:3, 3]).applyfunc(trig_normal)
            w = z
        else:
            v, w = z, sp.zeros(3, 1)
        twists.append(v.col_join(w))
    if all(j.mimic is None for j in model.joints):
        return sp.ImmutableMatrix(sp.Matrix.hstack(*twists))
    cols = []
    for q in model.variables:  # chain rule: d/dq of every joint that moves with q
        col = sp.zeros(6, 1)
        for c, t in zip(model.joint_coordinates, twists):
            col += sp.diff(c, q) * t
        cols.append(col.applyfunc(trig_normal))
    return sp.ImmutableMatrix(sp.Matrix.hstack(*cols))


def geometric_jacobian(model: RobotModel, *, frame=None, point="tool", task=None) -> sp.Matrix:
    """Geometric Jacobian: linear velocity of ``point``, then angular velocity.

    Parameters
    ----------
    model : RobotModel
    frame : "base", "tool" or int, optional
        Frame in which the velocities are expressed (default: the model's).
    point : "base", "tool" or int, default "tool"
        Reference point: the origin of that frame, moving with the tool.
    task : str or list of int, optional
        Rows to keep (default: the model's task).

    Examples
    --------
    >>> from rankloci.io.toml_model import parse_model
    >>> m = parse_model('name = "r"\\ntask = "planar"\\n[[joint]]\\nkind = "revolute"\\n'
    ...                 'a = 1\\nalpha = 0\\nd = 0\\n')
    >>> geometric_jacobian(m)
    Matrix([
    [-sin(q1)],
    [ cos(q1)]])
    """
    frame = model.frame if frame is None else frame
    frame_position(model, frame)
    frame_position(model, point)
    J = _jacobian_cached(model, frame, point)
    rows = model.task if task is None else task_rows(task)
    return sp.Matrix(J)[list(rows), :]


def augmented_rows(model, constraints) -> sp.Matrix:
    """Rows d g / d q of constraint functions ``g`` (exact gradients)."""
    q = list(model.variables)
    rows = [[sp.diff(g, v) for v in q] for g in constraints]
    return sp.Matrix(rows) if rows else sp.zeros(0, len(q))


def numeric_frames(model: RobotModel, q, params=None):
    """Numeric poses (4x4 arrays, in the world frame) at every factor position.

    ``q`` maps joint variables to values; ``params`` maps parameter symbols
    to values (default: the model's).  Entry ``p`` matches
    :func:`relative_transforms` with ``frame="base"``.
    """
    import numpy as np

    params = dict(model.parameters if params is None else params)
    names, funcs = _factor_functions(model)
    values = {**{k: float(v) for k, v in params.items()}, **{k: float(v) for k, v in q.items()}}
    args = [values[s] if s in values else float(model.parameters[s]) for s in names]
    poses = [np.eye(4)]
    for f in funcs:
        poses.append(poses[-1] @ np.array(f(*args), dtype=float).reshape(4, 4))
    return poses


@lru_cache(maxsize=64)
def _factor_functions(model: RobotModel):
    """The factors of :func:`_factors` as numpy functions of (variables, parameters)."""
    names = list(model.variables) + list(model.parameters)
    return names, [sp.lambdify(names, sp.Matrix(F), modules="numpy") for F in _factors(model)]


def velocity_map(model: RobotModel, q, frame, point, params=None):
    """6x6 matrix A with J(frame, point) = A @ J(base, tool) at configuration ``q``.

    Rows are linear velocity, then angular.  Left null vectors map back by
    ``u_base = A.T @ u``.
    """
    import numpy as np

    poses = numeric_frames(model, q, params)
    R = poses[frame_position(model, frame)][:3, :3]
    p_point = poses[frame_position(model, point)][:3, 3]
    p_tool = poses[frame_position(model, "tool")][:3, 3]
    r = p_point - p_tool
    S = np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])
    shift = np.eye(6)
    shift[:3, 3:] = -S
    rot = np.zeros((6, 6))
    rot[:3, :3] = R.T
    rot[3:, 3:] = R.T
    return rot @ shift
