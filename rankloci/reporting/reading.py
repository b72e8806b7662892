"""Plain-language readings of a lost direction.

:func:`rankloci.directions.lost_direction` checks that a vector is lost at the
sample point and says what it takes from the end-effector; this module puts
that in words: "the task point cannot translate along ...", "the end-effector
cannot rotate about ..." or, for a mixed direction, the linear relation every
achievable velocity obeys (equivalently, a wrench the structure resists with
zero joint torques).  Nothing is said of a vector that is not lost.
"""

from __future__ import annotations

import numpy as np

from ..directions import ANGULAR_ROWS, LINEAR_ROWS, lost_direction
from ..tolerances import DIRECTION_PART_MIN
from .blocks import signed

__all__ = ["direction_readings", "lost_motion"]


def _vec(values, digits=3) -> str:
    return "[" + ", ".join(signed(x, digits) for x in values) + "]"


def _rate(lab) -> str:
    return lab if lab in LINEAR_ROWS + ANGULAR_ROWS else f"d({lab})/dt"


def direction_readings(J, u, row_labels, *, tall: bool = False, frame: str = "base",
                       variables=()) -> list[str]:
    """Read the lost direction ``u`` of ``J`` (numeric, at the sample point) in words.

    Parameters
    ----------
    J : numpy.ndarray
        The matrix at the sample point, rows as in ``row_labels``.
    u : sequence of float
        A left null vector of J (a right null vector when ``tall``).
    row_labels : sequence of str
        ``vx vy vz wx wy wz`` for task rows; anything else is a constraint row.
    frame : str
        Name of the frame the rows are expressed in (for the wording).

    Returns the empty list when ``u`` is not a null vector of ``J`` to
    :data:`~rankloci.tolerances.DIRECTION_RTOL` (nothing is claimed then); the
    reading itself is :func:`rankloci.directions.lost_direction`.

    Examples
    --------
    >>> import numpy as np
    >>> J = np.array([[0.0, 0.0], [2.0, 1.0]])
    >>> direction_readings(J, [1.0, 0.0], ["vx", "vy"])
    ['the task point cannot translate along [+1.000, 0] over (x, y) in the base frame']
    """
    d = lost_direction(J, u, row_labels, tall=tall, variables=variables)
    if d is None:
        return []
    u = d.vector
    if d.kind == "self-motion":
        names = ", ".join(str(v) for v in variables) if variables else "the joint variables"
        return [f"the joint velocity {_vec(u)} over ({names}) moves nothing: J q' = 0 there, a "
                "self-motion of the joints that the task does not see"]
    labels = list(row_labels)
    missing_lin = [r[1] for r in LINEAR_ROWS if r not in labels]
    missing_ang = [r[1] for r in ANGULAR_ROWS if r not in labels]
    if d.kind == "translation":
        present = [r for r in LINEAR_ROWS if r in labels]
        vec = np.array([u[labels.index(r)] for r in present]) / d.linear_norm
        return [f"the task point cannot translate along {_vec(vec)}"
                f"{_rows_note(present, missing_lin, frame)}"]
    if d.kind == "rotation":
        present = [r for r in ANGULAR_ROWS if r in labels]
        vec = np.array([u[labels.index(r)] for r in present]) / d.angular_norm
        return [f"the end-effector cannot rotate about {_vec(vec)}"
                f"{_rows_note(present, missing_ang, frame)}"]
    if d.kind == "wrench":
        return [f"every end-effector velocity (v, w) the joints can produce has a.v + b.w = 0, "
                f"a = {_vec(d.linear)}, b = {_vec(d.angular)} ({frame} frame, v at the task "
                "point): the force a with the moment b about the task point needs no joint "
                "torque to be held"]
    terms = " ".join(f"{signed(x, 3)} {_rate(lab)}" for lab, x in zip(labels, u)
                     if abs(x) > DIRECTION_PART_MIN)
    return [f"the task velocity and the constraint rate are tied: {terms} = 0 for every "
            "joint velocity"]


def _rows_note(present, missing, frame) -> str:
    if missing:
        axes = ", ".join(r[1] for r in present)
        return f" over ({axes}) in the {frame} frame"
    return f" (x, y, z of the {frame} frame)"


def lost_motion(J, u, row_labels, *, tall: bool = False, variables=()) -> str:
    """The motion lost along the null vector ``u`` of ``J``, in a few words for a table.

    The same reading as :func:`direction_readings` (and the same check:
    ``""`` when ``u`` is not a null vector of ``J``), without the explanation:
    what the end-effector cannot do.  No translation along a direction, no
    rotation about an axis, or, for a direction with both parts, no velocity
    (v, w) with a.v + b.w != 0: that direction is a wrench (force a, moment b),
    not a motion, and is labelled so.  Else a combination of task and
    constraint rates.  Numbers have two decimals (the component's subsection
    gives the direction to three); a value that rounds to zero is written 0.

    Examples
    --------
    >>> import numpy as np
    >>> J = np.array([[0.0, 0.0], [2.0, 1.0]])
    >>> lost_motion(J, [1.0, 0.0], ["vx", "vy"])
    'no translation along [+1.00, 0] (x, y)'
    >>> J = np.array([[1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])
    >>> print(lost_motion(J, [1.0, 1.0, -1.0], ["vx", "vy", "wz"]))
    ... # doctest: +NORMALIZE_WHITESPACE
    no motion with a.v + b.w != 0; as a wrench, force a = [+0.58, +0.58, 0] with moment
    b = [0, 0, -0.58] needs no joint torque
    """
    d = lost_direction(J, u, row_labels, tall=tall, variables=variables)
    if d is None:
        return ""
    if d.kind == "self-motion":
        names = ", ".join(str(v) for v in variables) if variables else "the joints"
        return f"none: the joint motion {_vec(d.vector, 2)} over ({names}) moves nothing"

    def along(rows, norm):
        axes = ", ".join(r[1] for r, _ in rows)
        return f"{_vec([x / norm for _, x in rows], 2)} ({axes})"

    if d.kind == "translation":
        return f"no translation along {along(d.present(LINEAR_ROWS), d.linear_norm)}"
    if d.kind == "rotation":
        return f"no rotation about {along(d.present(ANGULAR_ROWS), d.angular_norm)}"
    if d.kind == "wrench":
        return (f"no motion with a.v + b.w != 0; as a wrench, force a = {_vec(d.linear, 2)} with "
                f"moment b = {_vec(d.angular, 2)} needs no joint torque")
    terms = " ".join(f"{signed(x, 2)} {_rate(lab)}" for lab, x in zip(d.rows, d.vector)
                     if abs(x) > DIRECTION_PART_MIN)
    return f"task and constraint rates together: {terms}"
