"""Lost task directions expressed in the model's own frame.

A locus is computed from the Jacobian in whatever frame keeps it small; the
left null vectors found there are mapped back to the frame the model file
names (``frame = "base"`` or ``"tool"``, reference point at the tool) with
the numeric velocity map of the configuration: if J_used = A J_model then
u_model = A^T u_used.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .kinematics import turns_about_z, velocity_map
from .model import RobotModel

__all__ = ["directions_in_model_frame"]


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
