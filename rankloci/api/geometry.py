"""The geometry of a robot at one configuration, as a function of a model.

:func:`pose_geometry` says what a notebook user asks of a pose: where the
joint axes are, which of them are parallel, collinear or meet there (beyond
what the design makes true everywhere), and, where J loses rank, what the
end-effector cannot do.  It takes a model as :func:`rankloci.load_model`
does and returns a frozen result; nothing is printed or written.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["PoseGeometry", "pose_geometry"]

#: The names of the six task rows, in the order of ``model.task``'s indices.
_ROW_NAMES = ("vx", "vy", "vz", "wx", "wy", "wz")


@dataclass(frozen=True)
class PoseGeometry:
    """A robot's joint axes at one configuration, the facts they make, what J loses there.

    Attributes
    ----------
    q : numpy.ndarray
        The configuration, one value per joint variable.
    axes : tuple of AxisLine
        Each joint axis in the base frame (:class:`rankloci.geometry.AxisLine`).
    task_point : numpy.ndarray
        The task point in the base frame.
    facts : frozenset
        Every geometric fact at ``q`` (keys of :func:`rankloci.geometry.facts_at`:
        ``("parallel", 2, 3)``, ``("collinear", 4, 6)``, ``("on-axis", "P", 1)``, ...).
    design : frozenset
        The facts that hold at random configurations too: the design's, not the pose's.
    rank_drop : int
        How many ranks the task Jacobian loses at ``q`` (relative to
        :data:`~rankloci.tolerances.RANK_RTOL` times sigma_max).
    lost : tuple of LostDirection
        For each lost rank, what the end-effector cannot do
        (:class:`rankloci.directions.LostDirection`).
    """

    q: np.ndarray
    axes: tuple
    task_point: np.ndarray
    facts: frozenset
    design: frozenset
    rank_drop: int
    lost: tuple

    @property
    def special(self) -> frozenset:
        """The facts of this pose that no random configuration shares."""
        return self.facts - self.design


def pose_geometry(model, q, *, seed: int = 0, tip: str | None = None,
                  base_link: str | None = None) -> PoseGeometry:
    """The joint axes of ``model`` at ``q``, their geometric facts and what J loses there.

    Parameters
    ----------
    model : str, path or RobotModel
    q : array_like
        One value per joint variable.
    seed : int
        Seed of the random configurations whose facts are the design's.
    tip, base_link : str, optional
        For a URDF file or a Pinocchio model: the chain (:func:`rankloci.load_model`).

    Returns
    -------
    PoseGeometry

    Examples
    --------
    >>> import rankloci
    >>> g = rankloci.pose_geometry("puma560", [0.3, 0.2, -0.4, 0.5, 0.0, 0.1])
    >>> sorted(f for f in g.special if f[0] == "collinear"), g.rank_drop
    ([('collinear', 4, 6)], 1)
    >>> g.lost[0].kind      # a rotation about the wrist's normal moves the task point too
    'wrench'
    """
    from ..directions import lost_direction
    from ..geometry import axis_lines, design_facts, facts_at
    from ..near.path import Kinematics
    from ..model import RobotModel
    from ..numeric.svd import null_directions, numeric_rank_drop
    from .calls import load_model

    model = load_model(model, tip=tip, base_link=base_link)
    if not isinstance(model, RobotModel):
        raise ValueError(f"model must be a robot model, got {type(model).__name__}")
    kin = Kinematics(model)
    q = np.asarray(q, dtype=float)
    if q.shape != (kin.n,):
        raise ValueError(f"q must have {kin.n} values (one per joint), got shape {q.shape}")
    if not np.all(np.isfinite(q)):
        raise ValueError("q must be finite")
    at = {str(v): float(x) for v, x in zip(model.variables, q)}
    meets, design = design_facts(model, None, np.random.default_rng(seed))
    lines, tool = axis_lines(model, at)
    J = kin.jacobian(q)
    tall = J.shape[0] > J.shape[1]
    drop = int(numeric_rank_drop(J))
    rows = [_ROW_NAMES[r] for r in kin.rows]
    lost = tuple(d for d in (lost_direction(J, u, rows, tall=tall, variables=model.variables)
                             for u in (null_directions(J, drop, tall) if drop else ()))
                 if d is not None)
    return PoseGeometry(q, tuple(lines), tool, frozenset(facts_at(model, at, None, meets)),
                        design, drop, lost)
