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
        values = {k: float(v) for k, v in (model.parameters if params is None else params).items()}

        def num(M):
            return np.array(sp.Matrix(M).subs(values).evalf(), dtype=float)

        self.base = num(model.base)
        self.tool = num(model.tool)
        self.pre = [num(j.pre) for j in model.joints]
        self.post = [num(j.post) for j in model.joints]
        self.axes = [np.array([float(sp.sympify(a).subs(values)) for a in j.axis]) for j in model.joints]
        self.revolute = [j.kind == "revolute" for j in model.joints]
        self.rows = list(model.task)

    def _motion(self, i, q):
        N = q.shape[0]
        T = np.broadcast_to(np.eye(4), (N, 4, 4)).copy()
        x, y, z = self.axes[i]
        if not self.revolute[i]:
            T[:, :3, 3] = np.outer(q, self.axes[i])
            return T
        c, s = np.cos(q), np.sin(q)
        v = 1 - c
        T[:, 0, 0] = c + x * x * v
        T[:, 0, 1] = x * y * v - z * s
        T[:, 0, 2] = x * z * v + y * s
        T[:, 1, 0] = y * x * v + z * s
        T[:, 1, 1] = c + y * y * v
        T[:, 1, 2] = y * z * v - x * s
        T[:, 2, 0] = z * x * v - y * s
        T[:, 2, 1] = z * y * v + x * s
        T[:, 2, 2] = c + z * z * v
        return T

    def __call__(self, Q) -> np.ndarray:
        """J at each row of ``Q`` (N, n): an array (N, len(task rows), n)."""
        Q = np.atleast_2d(np.asarray(Q, dtype=float))
        N, n = Q.shape
        T = np.broadcast_to(self.base, (N, 4, 4)).copy()
        z = np.empty((N, n, 3))
        o = np.empty((N, n, 3))
        for i in range(n):
            T = T @ self.pre[i]
            z[:, i] = T[:, :3, :3] @ self.axes[i]
            o[:, i] = T[:, :3, 3]
            T = T @ self._motion(i, Q[:, i]) @ self.post[i]
        T = T @ self.tool
        p = T[:, :3, 3]
        J = np.zeros((N, 6, n))
        rev = np.array(self.revolute)
        lin = np.cross(z, p[:, None, :] - o)
        J[:, :3, :] = np.where(rev[None, :, None], lin, z).transpose(0, 2, 1)
        J[:, 3:, :] = np.where(rev[None, :, None], z, 0.0).transpose(0, 2, 1)
        return J[:, self.rows, :]
