"""The arm at one configuration, as the drawing code reads it.

:class:`~rankloci.geometry.RobotPose` and :func:`~rankloci.geometry.robot_pose`
are computed in :mod:`rankloci.geometry`; this module names them for the
figures.
"""

from __future__ import annotations

from ..geometry import RobotPose, robot_pose

__all__ = ["RobotPose", "robot_pose"]
