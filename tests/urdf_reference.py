"""An independent numeric reading of URDF origins, shared by the URDF tests."""

from __future__ import annotations

import math

import numpy as np

from rankloci.tolerances import URDF_ANGLE_SNAP_ATOL, URDF_LENGTH_SNAP_ATOL


def snapped(t: float) -> float:
    """The documented idealisation of an rpy angle: a multiple of pi/12 when within tolerance."""
    k = round(t / (math.pi / 12))
    return k * math.pi / 12 if abs(t - k * math.pi / 12) <= URDF_ANGLE_SNAP_ATOL else t


def snapped_length(x: float) -> float:
    """The documented idealisation of an origin length: 0 when within tolerance of it."""
    return 0.0 if abs(x) <= URDF_LENGTH_SNAP_ATOL else x


def rot(axis, t: float) -> np.ndarray:
    """Rotation by ``t`` about ``axis`` (Rodrigues), in floats."""
    k = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + math.sin(t) * K + (1 - math.cos(t)) * K @ K
