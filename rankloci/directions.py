"""Lost task directions expressed in the model's own frame.

A locus is computed from the Jacobian in whatever frame keeps it small; the
left null vectors found there are mapped back to the frame the model file
names (``frame = "base"`` or ``"tool"``, reference point at the tool) with
the numeric velocity map of the configuration: if J_used = A J_model then
u_model = A^T u_used.

:func:`lost_direction` says what a lost direction means for the end-effector
(:class:`LostDirection`): a translation it cannot make, a rotation, a wrench
the structure holds with no joint torque, a tie between task and constraint
rates, or, for a tall matrix, a joint motion that moves nothing.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from .kinematics import turns_about_z, velocity_map
from .model import RobotModel
from .tolerances import DIRECTION_PART_MIN, DIRECTION_RTOL

__all__ = ["directions_in_model_frame", "LostDirection", "lost_direction", "LINEAR_ROWS",
           "ANGULAR_ROWS"]

#: The names of the task rows: linear velocity, then angular velocity.
LINEAR_ROWS, ANGULAR_ROWS = ("vx", "vy", "vz"), ("wx", "wy", "wz")


@dataclass(frozen=True)
class LostDirection:
    """What a null vector of J at one configuration takes from the end-effector.

    Attributes
    ----------
    kind : str
        ``"translation"`` (the task point cannot translate along ``linear``),
        ``"rotation"`` (the end-effector cannot rotate about ``angular``),
        ``"wrench"`` (every velocity (v, w) has a.v + b.w = 0 with a =
        ``linear``, b = ``angular``: the force a with the moment b needs no joint
        torque), ``"mixed"`` (task and constraint rates tied, the relation is
        ``vector`` over ``rows``) or ``"self-motion"`` (a tall J: the joint
        velocity ``vector`` moves nothing).
    vector : numpy.ndarray
        The null vector, of unit length.
    rows : tuple of str
        The row labels of J (the joint variables' names for a self-motion).
    linear, angular : numpy.ndarray
        The parts of ``vector`` on ``vx vy vz`` and ``wx wy wz``, 0 where J has no
        such row.
    linear_norm, angular_norm, other_norm : float
        The lengths of the linear part, the angular part and the constraint rows' part.
    """

    kind: str
    vector: np.ndarray
    rows: tuple
    linear: np.ndarray
    angular: np.ndarray
    linear_norm: float
    angular_norm: float
    other_norm: float

    def present(self, names) -> tuple:
        """(row, value) for each row of ``names`` that J has, in the order of ``names``."""
        return tuple((r, float(self.vector[self.rows.index(r)])) for r in names
                     if r in self.rows)


def lost_direction(J, u, row_labels, *, tall: bool = False,
                   variables=()) -> LostDirection | None:
    """Read the null vector ``u`` of ``J``: what the end-effector cannot do there.

    Parameters
    ----------
    J : array_like
        The matrix at one configuration, rows as in ``row_labels``.
    u : sequence of float
        A left null vector of J (a right null vector when ``tall``).
    row_labels : sequence of str
        ``vx vy vz wx wy wz`` for task rows; anything else is a constraint row.
    tall : bool
        J has more rows than columns and ``u`` is a joint velocity.
    variables : sequence
        The joint variables (the ``rows`` of a self-motion).

    Returns
    -------
    LostDirection or None
        None when ``u`` is not a null vector of J to
        :data:`~rankloci.tolerances.DIRECTION_RTOL` times sigma_max (nothing is
        claimed then).  Parts below
        :data:`~rankloci.tolerances.DIRECTION_PART_MIN` count as zero.

    Examples
    --------
    >>> import numpy as np
    >>> J = np.array([[0.0, 0.0], [2.0, 1.0]])
    >>> d = lost_direction(J, [3.0, 0.0], ["vx", "vy"])
    >>> d.kind, d.vector.tolist()
    ('translation', [1.0, 0.0])
    >>> lost_direction(J, [0.0, 1.0], ["vx", "vy"]) is None     # not a null vector
    True
    >>> lost_direction(np.array([[1.0, 0.0], [0.0, 1.0], [1.0, 1.0]]), [1.0, 1.0, -1.0],
    ...                ["vx", "vy", "wz"]).kind
    'wrench'
    """
    J = np.asarray(J, dtype=float)
    u = np.asarray(u, dtype=float)
    smax = float(np.linalg.svd(J, compute_uv=False)[0]) if J.size else 0.0
    if smax == 0.0 or np.linalg.norm(u) == 0.0:
        return None
    u = u / np.linalg.norm(u)
    if np.linalg.norm((J @ u) if tall else (u @ J)) > DIRECTION_RTOL * smax:
        return None
    if tall:
        zero = np.zeros(3)
        return LostDirection("self-motion", u, tuple(str(v) for v in variables), zero, zero,
                             0.0, 0.0, 0.0)
    labels = tuple(row_labels)
    lin = np.array([u[labels.index(r)] if r in labels else 0.0 for r in LINEAR_ROWS])
    ang = np.array([u[labels.index(r)] if r in labels else 0.0 for r in ANGULAR_ROWS])
    others = [x for lab, x in zip(labels, u) if lab not in LINEAR_ROWS + ANGULAR_ROWS]
    n_lin, n_ang = float(np.linalg.norm(lin)), float(np.linalg.norm(ang))
    n_other = float(np.sqrt(sum(x * x for x in others)))
    if n_other > DIRECTION_PART_MIN:
        kind = "mixed"
    elif n_ang <= DIRECTION_PART_MIN and n_lin > DIRECTION_PART_MIN:
        kind = "translation"
    elif n_lin <= DIRECTION_PART_MIN and n_ang > DIRECTION_PART_MIN:
        kind = "rotation"
    else:
        kind = "wrench"
    return LostDirection(kind, u, labels, lin, ang, n_lin, n_ang, n_other)


def directions_in_model_frame(locus, model, tm):
    """The locus with ``direction_at_sample`` in the model's frame (robots only)."""
    if not isinstance(model, RobotModel) or tm.frame is None:
        return locus
    if (tm.frame, tm.point) == (model.frame, "tool"):
        return locus
    rows = list(tm.rows)
    n_task = len(rows)
    if locus.shape[0] > locus.shape[1]:
        return locus
    # the task rows must map among themselves: whole 3-row blocks, or the planar rows when
    # the frame is the model's frame turned about z (the same point)
    planar = (set(rows) <= {0, 1, 5} and tm.point == "tool"
              and turns_about_z(model, tm.frame))
    if rows not in ([0, 1, 2, 3, 4, 5], [0, 1, 2], [3, 4, 5]) and not planar:
        return locus
    def mapped(c):
        q = {v: c.sample[str(v)] for v in tm.variables}
        params = {p: c.sample.get(str(p), float(val)) for p, val in model.parameters.items()}
        A_used = velocity_map(model, q, tm.frame, tm.point, params)
        A_model = velocity_map(model, q, model.frame, "tool", params)
        # J_used = A_used J_bt and J_model = A_model J_bt, so J_used = A_used A_model^-1 J_model
        B = (A_used @ np.linalg.inv(A_model))[np.ix_(rows, rows)]
        new = []
        for vec in c.direction_at_sample:
            u = np.asarray(vec[:n_task], dtype=float)
            w = B.T @ u
            extra = np.asarray(vec[n_task:], dtype=float)
            full = np.concatenate([w, extra])
            full = full / max(np.linalg.norm(full), 1e-300)
            new.append(tuple(float(x) for x in full))
        return dataclasses.replace(c, direction_at_sample=tuple(new))

    return dataclasses.replace(locus, components=tuple(mapped(c) for c in locus.components),
                               special=tuple(mapped(c) for c in locus.special))
