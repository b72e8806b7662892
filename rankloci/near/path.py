"""Joint rates along a task-space path: minimum two-norm, infinity-norm or mixed.

The tool point follows a polyline in the position rows of the model's task
(vx, vy, vz among them) at constant speed; rows of angular velocity hold the
starting orientation.  At each step the joint rates solve J(q) qdot = xdot,
with xdot the path's velocity plus a proportional correction of the tracking
error (closed-loop inverse kinematics, gain ``1 / (4 dt)``), and q moves by
qdot dt.  Each step records the minimum two-norm and minimum infinity-norm
rates, the discontinuity indices, the mixing ratio and sigma_min/sigma_max;
the path stops early, saying where, when J comes within REGULAR_MIN_RATIO of
rank deficiency or a joint would move more than ``max_step`` in one step.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..tolerances import REGULAR_MIN_RATIO
from .discontinuity import (DEFAULT_MIXING_GAIN, discontinuity_index, minor_index, mixing_ratio,
                            subspace_index)
from .min_inf_norm import ha_lee, linear_program

__all__ = ["NORMS", "PathRates", "joint_rates_along", "polyline", "Kinematics"]

#: The rate choices of :func:`joint_rates_along`.
NORMS = ("2", "inf", "mixed")


class Kinematics:
    """Numeric tool position, orientation and task Jacobian of a robot model.

    Parameters
    ----------
    model : RobotModel
        Its ``task`` rows select from (vx, vy, vz, wx, wy, wz) in the base frame.
    """

    def __init__(self, model):
        from ..kinematics import frame_position, numeric_frames
        from ..numeric.batch_jacobian import BatchJacobian

        self.model = model
        self._J = BatchJacobian(model)
        self._frames = numeric_frames
        self._tool = frame_position(model, "tool")
        self.rows = tuple(model.task)
        self.position_rows = tuple(r for r in self.rows if r < 3)
        self.n = model.dof

    def jacobian(self, q) -> np.ndarray:
        """J(q): the model's task rows."""
        return self._J(np.asarray(q, dtype=float)[None, :])[0]

    def pose(self, q) -> np.ndarray:
        """The 4x4 tool pose in the base frame."""
        values = dict(zip(self.model.variables, np.asarray(q, dtype=float)))
        return self._frames(self.model, values)[self._tool]

    def position(self, q) -> np.ndarray:
        """The tool point's coordinates along the task's position rows."""
        return self.pose(q)[list(self.position_rows), 3]


@dataclass(frozen=True)
class PathRates:
    """Joint rates and indices at each step of a path.

    Attributes
    ----------
    t : (N,) times, from 0 to the duration
    q : (N, n) configurations
    rates : (N, n) the rates applied (by ``norm``)
    rates_2, rates_inf : (N, n) minimum two-norm and minimum infinity-norm rates
    index : (N,) Ha and Lee's discontinuity index (orthonormal null-space form)
    minor_index : (N,) the same formed with J (vanishes on the locus)
    subspace_index : (N,) Gravagne's index over every face (Ha and Lee eq. 39)
    mixing : (N,) mixing ratio r
    sigma_ratio : (N,) sigma_min / sigma_max of J
    error : (N,) distance from the tool point to the path point
    norm : str
    stopped : str
        Why the path ended before its end ("" when it did not).
    lp_fallbacks : int
        Steps where Ha and Lee's algorithm did not certify an optimum and
        the linear program's solution was used.
    restricted : tuple of int
        Joints held still (0-based).
    """

    t: np.ndarray
    q: np.ndarray
    rates: np.ndarray
    rates_2: np.ndarray
    rates_inf: np.ndarray
    index: np.ndarray
    minor_index: np.ndarray
    subspace_index: np.ndarray
    mixing: np.ndarray
    sigma_ratio: np.ndarray
    error: np.ndarray
    norm: str
    stopped: str = ""
    lp_fallbacks: int = 0
    restricted: tuple = ()


def polyline(points, s):
    """Point and unit-speed tangent at arc length ``s`` along the polyline through ``points``."""
    P = np.asarray(points, dtype=float)
    seg = np.diff(P, axis=0)
    lengths = np.linalg.norm(seg, axis=1)
    cum = np.concatenate([[0.0], np.cumsum(lengths)])
    i = int(np.clip(np.searchsorted(cum, s, side="right") - 1, 0, len(seg) - 1))
    while lengths[i] == 0 and i + 1 < len(seg):
        i += 1
    tangent = seg[i] / lengths[i] if lengths[i] > 0 else np.zeros(P.shape[1])
    return P[i] + tangent * (s - cum[i]), tangent


def _two_norm(J, v, keep):
    """Minimum two-norm rates: the pseudo-inverse, or with restricted joints the least-norm
    point of the FSP solution space (ORNL/TM-12816, LeastNorm)."""
    if len(keep) < J.shape[1]:
        from ..numeric.fsp_solution import solve

        restricted = [j for j in range(J.shape[1]) if j not in keep]
        return np.asarray(solve(J, v, restricted=restricted).least_norm, dtype=float)
    return np.linalg.pinv(J) @ v


def _rotation_error(R_goal, R):
    """The rotation vector taking R to R_goal (base frame)."""
    from scipy.spatial.transform import Rotation

    return Rotation.from_matrix(R_goal @ R.T).as_rotvec()


def joint_rates_along(kin: Kinematics, q0, points, *, norm: str = "inf", duration: float = 1.0,
                      steps: int = 200, restricted=(), gain: float = DEFAULT_MIXING_GAIN,
                      max_step: float = 0.1) -> PathRates:
    """Follow the polyline ``points`` from configuration ``q0`` and record the joint rates.

    Parameters
    ----------
    kin : Kinematics
    q0 : array_like, shape (n,)
        Start; the tool point must be at ``points[0]``.
    points : array_like, shape (k, len(kin.position_rows))
        Waypoints in the position rows of the task.
    norm : {"2", "inf", "mixed"}
        The rates applied: minimum two-norm, minimum infinity-norm, or the
        mixture r x_inf + (1 - r) x_2 with r from the discontinuity index.
    duration : float
        Time to traverse the path at constant speed.
    steps : int
        Time steps.
    restricted : sequence of int
        Joints (0-based) held still.
    gain : float
        The gain of the mixing ratio.
    max_step : float
        The path stops when a joint would move more than this in one step (the
        rates blow up faster than the steps can follow, as when the path leaves the
        workspace through the locus).

    Returns
    -------
    PathRates
    """
    if norm not in NORMS:
        raise ValueError(f"norm={norm!r}: choose one of {', '.join(NORMS)}")
    if steps < 1 or not duration > 0:
        raise ValueError(f"steps must be >= 1 and duration > 0, got {steps}, {duration}")
    P = np.asarray(points, dtype=float)
    q = np.array(q0, dtype=float)
    n = kin.n
    keep = [j for j in range(n) if j not in set(restricted)]
    length = float(np.sum(np.linalg.norm(np.diff(P, axis=0), axis=1)))
    dt = duration / steps
    k_fb = 1.0 / (4 * dt)
    pos = [kin.rows.index(r) for r in kin.position_rows]
    ang = [i for i, r in enumerate(kin.rows) if r >= 3]
    R0 = kin.pose(q)[:3, :3]
    rec = {k: [] for k in ("t", "q", "rates", "rates_2", "rates_inf", "index", "minor",
                           "subspace", "mixing", "ratio", "error")}
    stopped, fallbacks = "", 0
    for k in range(steps + 1):
        t = k * dt
        goal, tangent = polyline(P, length * t / duration)
        pose = kin.pose(q)
        J = kin.jacobian(q)
        Jk = J[:, keep]
        s = np.linalg.svd(Jk, compute_uv=False)
        ratio = s[-1] / s[0] if s[0] > 0 else 0.0
        err = goal - pose[list(kin.position_rows), 3]
        if ratio <= REGULAR_MIN_RATIO:
            stopped = (f"stopped at t = {t:.4g}: sigma_min/sigma_max = {ratio:.1e} "
                       f"(J is about to lose rank)")
            break
        v = np.zeros(len(kin.rows))
        v[pos] = tangent * length / duration + k_fb * err
        if ang:
            v[ang] = k_fb * _rotation_error(R0, pose[:3, :3])[[kin.rows[i] - 3 for i in ang]]
        x2 = _two_norm(J, v, keep)
        sol = ha_lee(Jk, v)
        if not sol.converged:
            fallbacks += 1
            sol = linear_program(Jk, v)
        xi = np.zeros(n)
        xi[keep] = sol.x
        d = dm = np.nan    # not defined without n - m + 1 saturated columns (an LP fallback)
        if len(sol.saturated) == len(keep) - Jk.shape[0] + 1:
            d = discontinuity_index(Jk, sol.saturated)
            dm = minor_index(Jk, sol.saturated)
        r = float(mixing_ratio(d, gain)) if np.isfinite(d) else 1.0
        rates = {"2": x2, "inf": xi, "mixed": r * xi + (1 - r) * x2}[norm]
        if np.max(np.abs(rates)) * dt > max_step:
            stopped = (f"stopped at t = {t:.4g}: a joint would move "
                       f"{np.max(np.abs(rates)) * dt:.3g} in one step (more than {max_step:g}); "
                       f"sigma_min/sigma_max = {ratio:.1e}")
            break
        for key, val in (("t", t), ("q", q.copy()), ("rates", rates), ("rates_2", x2),
                         ("rates_inf", xi), ("index", d), ("minor", dm),
                         ("subspace", subspace_index(Jk)), ("mixing", r),
                         ("ratio", ratio), ("error", float(np.linalg.norm(err)))):
            rec[key].append(val)
        q = q + rates * dt
    arr = {k: np.array(v) for k, v in rec.items()}
    return PathRates(t=arr["t"], q=arr["q"].reshape(-1, n), rates=arr["rates"].reshape(-1, n),
                     rates_2=arr["rates_2"].reshape(-1, n),
                     rates_inf=arr["rates_inf"].reshape(-1, n),
                     index=arr["index"], minor_index=arr["minor"],
                     subspace_index=arr["subspace"], mixing=arr["mixing"],
                     sigma_ratio=arr["ratio"], error=arr["error"], norm=norm, stopped=stopped,
                     lp_fallbacks=fallbacks, restricted=tuple(sorted(set(restricted))))
