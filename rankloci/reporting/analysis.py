"""The numbers behind the report's figures, as the drawing code reads them.

They are computed in :mod:`rankloci.numeric.landscape`; this module names them
for the figures.  The comparison of two methods' loci is in :mod:`rankloci.compare`,
the branch tree cut down for drawing in :mod:`.tree_summary`.
"""

from __future__ import annotations

from ..numeric.landscape import (PathData, SliceData, component_equations, component_points,
                                 equation_weights, model_components, normal_directions,
                                 path_through, regular_point, sigma_ratios, slice_grid,
                                 slice_joints)
from ..tolerances import PATH_LENGTH, PATH_NORMAL_SHARE

__all__ = ["SliceData", "PathData", "slice_grid", "slice_joints", "path_through",
           "model_components", "sigma_ratios", "component_points", "component_equations",
           "equation_weights", "regular_point", "normal_directions", "PATH_LENGTH",
           "PATH_NORMAL_SHARE"]
