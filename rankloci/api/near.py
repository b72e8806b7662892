"""What ``rankloci ik`` and ``rankloci manipulability`` do, as functions of a model.

Each takes a model as :func:`rankloci.load_model` does (a built-in name, a file,
a :class:`~rankloci.model.RobotModel`, ...) and returns frozen results; nothing
is printed or written.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Manipulability", "manipulability", "joint_rates", "nearest_component"]


@dataclass(frozen=True)
class Manipulability:
    """The ellipsoid and polytope of a robot's Jacobian at one configuration.

    Attributes
    ----------
    q : numpy.ndarray
    J : numpy.ndarray
        The task rows of the base-frame Jacobian at the tool point.
    rows : tuple of int
        Which of (vx, vy, vz, wx, wy, wz) the rows of J are.
    ellipsoid : Ellipsoid
    polytope : Polytope or None
        None when J has more columns than the polytope enumerates.
    """

    q: np.ndarray
    J: np.ndarray
    rows: tuple
    ellipsoid: object
    polytope: object


def _robot(model, tip=None, base_link=None):
    from .calls import load_model
    from ..model import RobotModel

    model = load_model(model, tip=tip, base_link=base_link)
    if not isinstance(model, RobotModel):
        raise ValueError(f"model must be a robot model, got {type(model).__name__}")
    return model


def manipulability(model, q, *, position_only: bool = False, tip: str | None = None,
                   base_link: str | None = None) -> Manipulability:
    """Manipulability ellipsoid and polytope of ``model`` at ``q``.

    Parameters
    ----------
    model : str, path or RobotModel
    q : array_like
        One value per joint variable.
    position_only : bool
        Keep only the position rows (vx, vy, vz) of the task, as Kilic draws them.
    tip, base_link : str, optional
        For a URDF file or a Pinocchio model: the chain (:func:`rankloci.load_model`).

    Returns
    -------
    Manipulability

    Examples
    --------
    >>> m = manipulability("planar2r", [np.pi / 4, np.pi / 4])
    >>> round(m.ellipsoid.w, 6), round(m.polytope.w_p, 6)
    (0.707107, 2.828427)
    """
    from ..near.manipulability import MAX_POLYTOPE_COLUMNS, ellipsoid, polytope
    from ..near.path import Kinematics

    kin = Kinematics(_robot(model, tip, base_link))
    q = np.asarray(q, dtype=float)
    if q.shape != (kin.n,):
        raise ValueError(f"q must have {kin.n} values (one per joint), got shape {q.shape}")
    J = kin.jacobian(q)
    rows = kin.rows
    if position_only:
        keep = [i for i, r in enumerate(rows) if r < 3]
        J, rows = J[keep], tuple(rows[i] for i in keep)
    P = polytope(J) if J.shape[1] <= MAX_POLYTOPE_COLUMNS else None
    return Manipulability(q=q, J=J, rows=tuple(rows), ellipsoid=ellipsoid(J), polytope=P)


def joint_rates(model, q0, points, *, tip=None, base_link=None, **options):
    """Joint rates of ``model`` along the polyline ``points`` from ``q0``.

    ``options`` are those of :func:`rankloci.near.path.joint_rates_along` (``norm``,
    ``duration``, ``steps``, ``restricted``, ``gain``, ``max_step``); ``tip`` and
    ``base_link`` choose the chain of a URDF file (:func:`rankloci.load_model`).

    Examples
    --------
    >>> q0 = [0.62, 0.23, 1.0, 0.46]
    >>> path = joint_rates("planar4r", q0, [[0.524572, 3.032596], [0.0, 3.0]], steps=10)
    >>> path.rates.shape
    (11, 4)
    """
    from ..near.path import Kinematics, joint_rates_along

    return joint_rates_along(Kinematics(_robot(model, tip, base_link)), q0, points, **options)


def nearest_component(model, q, *, seed: int = 0, tip: str | None = None,
                      base_link: str | None = None):
    """The component of the model's locus nearest to ``q`` (joint space): a ``Nearest``.

    ``Nearest.component`` is the component's number, 1-based as the locus's
    text and JSON number components and as the ``nearest_component`` column
    of ``rankloci ik`` (``locus.components[near.component - 1]``); 0 when no
    component was reached.  ``tip`` and ``base_link`` choose the chain of a
    URDF file (:func:`rankloci.load_model`).

    Examples
    --------
    >>> near = nearest_component("planar2r", [0.3, 0.5])
    >>> near.component, round(near.distance, 12)
    (1, 0.5)
    """
    from ..near.nearest import ComponentDistance

    from .calls import certified_locus

    locus, tm = certified_locus(_robot(model, tip, base_link), seed=seed)
    return ComponentDistance(locus, tm.angles).nearest(np.asarray(q, dtype=float))
