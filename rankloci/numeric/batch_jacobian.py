"""Geometric Jacobians of a robot model at many configurations at once (numpy).

The symbolic chain ``base, pre_i, Motion_i(q_i), post_i, ..., tool`` is
evaluated numerically once per constant factor; the joint motions and the
products are then batched over N configurations with ``@`` on (N, 4, 4)
arrays.  Rows: linear velocity of the tool point, then angular velocity,
both in the base frame.
"""

from __future__ import annotations

import numpy as np
import sympy as sp

from ..expr import as_expression
from ..errors import ModelError
from ..model import RobotModel

__all__ = ["BatchJacobian"]


class BatchJacobian:
    """Numeric base-frame geometric Jacobian of ``model``, batched.

    Examples
    --------
    >>> import numpy as np
    >>> from rankloci.io import load_model
    >>> bj = BatchJacobian(load_model("planar2r"))
    >>> J = bj(np.array([[0.0, 0.0]]))
    >>> np.round(J[0], 6)
    array([[0., 0.],
           [2., 1.]])
    """

    def __init__(self, model: RobotModel, params=None):
        if any(getattr(j, "mimic", None) is not None for j in model.joints):
            raise ModelError("the batched Jacobian does not support mimic joints; use the "
                             "symbolic Jacobian (rankloci.kinematics.geometric_jacobian)")
        values = {k: float(v) for k, v in (model.parameters if params is None else params).items()}

        def num(M):
            return np.array(sp.Matrix(M).subs(values).evalf(), dtype=float)

        self.base = num(model.base)
        self.tool = num(model.tool)
        self.pre = [num(j.pre) for j in model.joints]
        self.post = [num(j.post) for j in model.joints]
        self.axes = [np.array([float(as_expression(a).subs(values)) for a in j.axis]) for j in model.joints]
        self.revolute = [j.kind == "revolute" for j in model.joints]
        self.rows = list(model.task)

    def _apply_motion(self, T, i, q):
        """T @ Motion_i(q) for a batch; a motion about z only mixes two columns."""
        axis = self.axes[i]
        if not self.revolute[i]:
            T = T.copy()
            T[:, :, 3] += (T[:, :, :3] @ axis)[:, :] * q[:, None]
            return T
        c, s = np.cos(q)[:, None], np.sin(q)[:, None]
        if np.array_equal(axis, (0.0, 0.0, 1.0)):
            out = T.copy()
            out[:, :, 0] = c * T[:, :, 0] + s * T[:, :, 1]
            out[:, :, 1] = c * T[:, :, 1] - s * T[:, :, 0]
            return out
        x, y, z = axis
        v = 1 - c[:, 0]
        sv = s[:, 0]
        cv = c[:, 0]
        R = np.empty((len(q), 3, 3))
        R[:, 0, 0] = cv + x * x * v
        R[:, 0, 1] = x * y * v - z * sv
        R[:, 0, 2] = x * z * v + y * sv
        R[:, 1, 0] = y * x * v + z * sv
        R[:, 1, 1] = cv + y * y * v
        R[:, 1, 2] = y * z * v - x * sv
        R[:, 2, 0] = z * x * v - y * sv
        R[:, 2, 1] = z * y * v + x * sv
        R[:, 2, 2] = cv + z * z * v
        out = T.copy()
        out[:, :, :3] = T[:, :, :3] @ R
        return out

    def __call__(self, Q) -> np.ndarray:
        """J at each row of ``Q`` (N, n): an array (N, len(task rows), n)."""
        Q = np.atleast_2d(np.asarray(Q, dtype=float))
        N, n = Q.shape
        # constant factors between consecutive motions, multiplied once
        links = [self.base @ self.pre[0]] + [self.post[i] @ self.pre[i + 1] for i in range(n - 1)]
        links.append(self.post[n - 1] @ self.tool)
        T = np.broadcast_to(links[0], (N, 4, 4)).copy()
        z = np.empty((N, n, 3))
        o = np.empty((N, n, 3))
        for i in range(n):
            z[:, i] = T[:, :3, :3] @ self.axes[i]
            o[:, i] = T[:, :3, 3]
            T = self._apply_motion(T, i, Q[:, i])
            # (N, 4, 4) @ (4, 4) as one matrix product of a (4N, 4) array
            T = (T.reshape(-1, 4) @ links[i + 1]).reshape(N, 4, 4)
        p = T[:, :3, 3]
        J = np.zeros((N, 6, n))
        rev = np.array(self.revolute)
        lin = np.cross(z, p[:, None, :] - o)
        J[:, :3, :] = np.where(rev[None, :, None], lin, z).transpose(0, 2, 1)
        J[:, 3:, :] = np.where(rev[None, :, None], z, 0.0).transpose(0, 2, 1)
        return J[:, self.rows, :]
