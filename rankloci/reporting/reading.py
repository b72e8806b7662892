"""Plain-language readings of a lost direction, verified numerically, and the joint axes.

The joint axes the geometric readings are made of are in
:mod:`rankloci.geometry`.  The lost direction is read here:

- **the lost direction**: ``u^T J = 0`` at the sample point, read as "the
  task point cannot translate along ...", "the end-effector cannot rotate
  about ..." or, for a mixed direction, the linear relation every achievable
  velocity obeys (equivalently, a wrench the structure resists with zero
  joint torques).

A statement is returned only when it holds numerically at the component's
sample point within the tolerances below.
"""

from __future__ import annotations

import numpy as np

from .blocks import signed

__all__ = ["direction_readings", "lost_motion", "DIRECTION_RTOL"]

#: ``|u^T J| <= DIRECTION_RTOL * sigma_max(J)`` verifies a lost direction at the sample
#: point: rank decisions use RANK_RTOL = 1e-8 on sigma_min/sigma_max, and the direction is
#: printed to 3 decimals, so 1e-6 is checked on the unrounded vector.
DIRECTION_RTOL = 1e-6


# --- lost directions ---------------------------------------------------------------------------

_LINEAR, _ANGULAR = ("vx", "vy", "vz"), ("wx", "wy", "wz")


def _vec(values, digits=3) -> str:
    return "[" + ", ".join(signed(x, digits) for x in values) + "]"


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
    :data:`DIRECTION_RTOL` (nothing is claimed then).

    Examples
    --------
    >>> import numpy as np
    >>> J = np.array([[0.0, 0.0], [2.0, 1.0]])
    >>> direction_readings(J, [1.0, 0.0], ["vx", "vy"])
    ['the task point cannot translate along [+1.000, 0] over (x, y) in the base frame']
    """
    J = np.asarray(J, dtype=float)
    u = np.asarray(u, dtype=float)
    smax = float(np.linalg.svd(J, compute_uv=False)[0]) if J.size else 0.0
    if smax == 0.0 or np.linalg.norm(u) == 0.0:
        return []
    u = u / np.linalg.norm(u)
    residual = np.linalg.norm((J @ u) if tall else (u @ J))
    if residual > DIRECTION_RTOL * smax:
        return []
    if tall:
        names = ", ".join(str(v) for v in variables) if variables else "the joint variables"
        return [f"the joint velocity {_vec(u)} over ({names}) moves nothing: J q' = 0 there, a "
                "self-motion of the joints that the task does not see"]
    labels = list(row_labels)
    lin = np.array([u[labels.index(r)] if r in labels else 0.0 for r in _LINEAR])
    ang = np.array([u[labels.index(r)] if r in labels else 0.0 for r in _ANGULAR])
    others = [(lab, x) for lab, x in zip(labels, u) if lab not in _LINEAR + _ANGULAR]
    small = 1e-3  # directions are read to 3 decimals
    n_lin, n_ang = np.linalg.norm(lin), np.linalg.norm(ang)
    n_other = float(np.sqrt(sum(x * x for _, x in others)))
    missing_lin = [r[1] for r in _LINEAR if r not in labels]
    missing_ang = [r[1] for r in _ANGULAR if r not in labels]
    out = []
    if n_other <= small and n_ang <= small and n_lin > small:
        present = [r for r in _LINEAR if r in labels]
        vec = np.array([u[labels.index(r)] for r in present]) / n_lin
        out.append(f"the task point cannot translate along {_vec(vec)}"
                   f"{_rows_note(present, missing_lin, frame)}")
    elif n_other <= small and n_lin <= small and n_ang > small:
        present = [r for r in _ANGULAR if r in labels]
        vec = np.array([u[labels.index(r)] for r in present]) / n_ang
        out.append(f"the end-effector cannot rotate about {_vec(vec)}"
                   f"{_rows_note(present, missing_ang, frame)}")
    elif n_other <= small:
        out.append(f"every end-effector velocity (v, w) the joints can produce has a.v + b.w = 0, "
                   f"a = {_vec(lin)}, b = {_vec(ang)} ({frame} frame, v at the task point): "
                   "the force a with the moment b about the task point needs no joint torque "
                   "to be held")
    else:
        def rate(lab):
            return lab if lab in _LINEAR + _ANGULAR else f"d({lab})/dt"

        terms = " ".join(f"{signed(x, 3)} {rate(lab)}" for lab, x in zip(labels, u)
                         if abs(x) > small)
        out.append(f"the task velocity and the constraint rate are tied: {terms} = 0 for every "
                   "joint velocity")
    return out


def _rows_note(present, missing, frame) -> str:
    if missing:
        axes = ", ".join(r[1] for r in present)
        return f" over ({axes}) in the {frame} frame"
    return f" (x, y, z of the {frame} frame)"


def lost_motion(J, u, row_labels, *, tall: bool = False, variables=()) -> str:
    """The motion lost along the null vector ``u`` of ``J``, in a few words for a table.

    The same classification as :func:`direction_readings` (and the same
    check: ``""`` when ``u`` is not a null vector of ``J``), without the
    explanation: what the end-effector cannot do.  No translation along a
    direction, no rotation about an axis, or, for a direction with both parts,
    no velocity (v, w) with a.v + b.w != 0: that direction is a wrench (force a,
    moment b), not a motion, and is labelled so.  Else a combination of task and
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
    J = np.asarray(J, dtype=float)
    u = np.asarray(u, dtype=float)
    smax = float(np.linalg.svd(J, compute_uv=False)[0]) if J.size else 0.0
    if smax == 0.0 or np.linalg.norm(u) == 0.0:
        return ""
    u = u / np.linalg.norm(u)
    if np.linalg.norm((J @ u) if tall else (u @ J)) > DIRECTION_RTOL * smax:
        return ""
    if tall:
        names = ", ".join(str(v) for v in variables) if variables else "the joints"
        return f"none: the joint motion {_vec(u, 2)} over ({names}) moves nothing"
    labels = list(row_labels)
    small = 1e-3
    lin = [(r, u[labels.index(r)]) for r in _LINEAR if r in labels]
    ang = [(r, u[labels.index(r)]) for r in _ANGULAR if r in labels]
    others = [(lab, x) for lab, x in zip(labels, u) if lab not in _LINEAR + _ANGULAR]
    n_lin = float(np.sqrt(sum(x * x for _, x in lin)))
    n_ang = float(np.sqrt(sum(x * x for _, x in ang)))
    n_other = float(np.sqrt(sum(x * x for _, x in others)))

    def along(rows, norm):
        axes = ", ".join(r[1] for r, _ in rows)
        return f"{_vec([x / norm for _, x in rows], 2)} ({axes})"

    if n_other <= small and n_ang <= small:
        return f"no translation along {along(lin, n_lin)}"
    if n_other <= small and n_lin <= small:
        return f"no rotation about {along(ang, n_ang)}"
    if n_other <= small:
        a = np.array([u[labels.index(r)] if r in labels else 0.0 for r in _LINEAR])
        b = np.array([u[labels.index(r)] if r in labels else 0.0 for r in _ANGULAR])
        return (f"no motion with a.v + b.w != 0; as a wrench, force a = {_vec(a, 2)} with "
                f"moment b = {_vec(b, 2)} needs no joint torque")

    def rate(lab):
        return lab if lab in _LINEAR + _ANGULAR else f"d({lab})/dt"

    terms = " ".join(f"{signed(x, 2)} {rate(lab)}" for lab, x in zip(labels, u) if abs(x) > small)
    return f"task and constraint rates together: {terms}"
