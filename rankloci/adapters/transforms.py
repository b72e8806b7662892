"""Constant rigid transforms of other libraries, as the xyz and roll-pitch-yaw of model files."""

from __future__ import annotations

import math

import numpy as np

__all__ = ["xyz_rpy", "is_identity", "length_text"]


def xyz_rpy(T) -> tuple[list[float], list[float]]:
    """Translation and URDF roll-pitch-yaw of a 4x4 homogeneous transform.

    URDF's convention, as :func:`rankloci.model.rpy_rotation`:
    R = Rz(yaw) Ry(pitch) Rx(roll).

    Examples
    --------
    >>> xyz, rpy = xyz_rpy(np.array([[0, -1, 0, 1], [1, 0, 0, 2], [0, 0, 1, 3], [0, 0, 0, 1]]))
    >>> xyz, [round(a, 12) for a in rpy]
    ([1.0, 2.0, 3.0], [0.0, -0.0, 1.570796326795])
    """
    T = np.asarray(T, dtype=float)
    R = T[:3, :3]
    pitch = math.atan2(-R[2, 0], math.hypot(R[0, 0], R[1, 0]))
    if math.hypot(R[0, 0], R[1, 0]) > 1e-12:
        roll = math.atan2(R[2, 1], R[2, 2])
        yaw = math.atan2(R[1, 0], R[0, 0])
    else:  # pitch = +-pi/2: only roll - yaw (or roll + yaw) is defined; take yaw = 0
        roll = math.atan2(-R[1, 2], R[1, 1])
        yaw = 0.0
    return [float(x) for x in T[:3, 3]], [roll, pitch, yaw]


def is_identity(T) -> bool:
    """Is ``T`` exactly the 4x4 identity?"""
    return bool(np.array_equal(np.asarray(T, dtype=float), np.eye(4)))


def length_text(x: float) -> str:
    """A translation of a composed transform, to the 15 significant digits a float carries.

    Products of floating-point transforms leave rounding in the last digit
    (0.10300000000000001 for 0.103), which would become a long exact rational.

    Examples
    --------
    >>> length_text(0.1 + 0.003)
    '0.103'
    """
    return repr(float(f"{x:.15g}"))
