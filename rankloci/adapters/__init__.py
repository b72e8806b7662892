"""Models from other robotics libraries.

- :func:`from_rtb`: a Robotics Toolbox for Python ``DHRobot`` (standard or
  modified DH), through a model file;
- :func:`from_pinocchio`: the chain of a Pinocchio ``Model`` from its root to a
  frame, through a URDF document.

Every public function of :mod:`rankloci.api` also accepts these objects directly.
Neither library is imported until it is used: both are optional.
"""

from .pinocchio import from_pinocchio
from .rtb import from_rtb

__all__ = ["from_rtb", "from_pinocchio"]
