"""The geometry of a robot at one configuration, as a function of a model.

:func:`pose_geometry` says what a notebook user asks of a pose: where the
joint axes are, which of them are parallel, collinear or meet there (beyond
what the design makes true everywhere), and, where J loses rank, what the
end-effector cannot do.  :func:`component_geometry` says it of a component of
a locus: the facts that hold at every point checked on it, and what its lost
directions take from the end-effector.  It takes a model as :func:`rankloci.load_model`
does and returns a frozen result; nothing is printed or written.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["PoseGeometry", "pose_geometry", "ComponentGeometry", "component_geometry"]

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
    from ..numeric.svd import null_directions, numeric_rank_drop

    model = _robot_model(model, tip, base_link)
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


def _robot_model(model, tip, base_link):
    from ..model import RobotModel
    from .calls import load_model

    model = load_model(model, tip=tip, base_link=base_link)
    if not isinstance(model, RobotModel):
        raise ValueError(f"model must be a robot model, got {type(model).__name__}")
    return model


@dataclass(frozen=True)
class ComponentGeometry:
    """The geometry of one component of a robot's locus.

    Attributes
    ----------
    index : int
        The component's number (1-based, as in ``locus.components``).
    facts : ComponentFacts
        The facts that hold at every point checked and at no random
        configuration, per equation when there are several
        (:class:`rankloci.geometry.ComponentFacts`).
    lost : tuple of LostDirection
        What each lost direction at the sample point takes from the end-effector
        (:class:`rankloci.directions.LostDirection`).
    """

    index: int
    facts: object
    lost: tuple


def component_geometry(model, locus, index: int, *, seed: int = 0, tip: str | None = None,
                       base_link: str | None = None) -> ComponentGeometry:
    """The geometric facts of component ``index`` of ``locus`` and what it takes from the arm.

    The facts are checked at the component's sample point and at
    :data:`~rankloci.tolerances.READING_POINTS` more points solved onto it; for a
    component of several equations, each equation's facts at
    :data:`~rankloci.tolerances.FACTOR_POINTS` points where it alone vanishes.
    They are those of the report's reading of the component.

    Parameters
    ----------
    model : str, path or RobotModel
        The robot whose locus ``locus`` is.
    locus : Locus
        What :func:`rankloci.locus` returned for ``model``.
    index : int
        1-based, as in ``locus.components``.
    seed : int
        Seed of the points on the component and of the random configurations.
    tip, base_link : str, optional
        For a URDF file or a Pinocchio model: the chain (:func:`rankloci.load_model`).

    Examples
    --------
    >>> import rankloci
    >>> L = rankloci.locus("planar2r")
    >>> g = rankloci.component_geometry("planar2r", L, 1)
    >>> sorted(g.facts.whole, key=str)    # the task point in the plane of both axes
    [('coplanar', 'P', frozenset({1, 2}))]
    >>> g.lost[0].kind
    'translation'
    """
    import sympy as sp

    from ..directions import lost_direction
    from ..expr import as_expression
    from ..geometry import component_facts
    from ..jacobians import task_matrix
    from ..loci import Locus
    from ..numeric.equations import NumericMatrix
    from ..numeric.landscape import reading_points

    model = _robot_model(model, tip, base_link)
    if not isinstance(locus, Locus):
        raise ValueError(f"locus must be a Locus, got {type(locus).__name__}")
    n = len(locus.components)
    if isinstance(index, bool) or not isinstance(index, int) or not 1 <= index <= n:
        raise ValueError(f"index must be a component number from 1 to {n}, got {index!r}")
    comp = locus.components[index - 1]
    tm = task_matrix(model)
    params = dict(tm.parameters)
    nm = NumericMatrix(sp.Matrix(tm.matrix).subs(params), tm.variables, tm.angles)
    names = [v.name for v in nm.variables]
    known = set(names) | {str(p) for p in params}
    strange = {str(s) for e in comp.equations for s in as_expression(e).free_symbols} - known
    missing = set(names) - set(comp.sample)
    if strange or missing:
        raise ValueError(f"locus is not a locus of {model.name}: "
                         + (f"its equations use {sorted(strange)}" if strange
                            else f"its sample point has no value for {sorted(missing)}"))
    rng = np.random.default_rng(seed)
    eqs = [e for e in comp.equations if e not in comp.parameter_conditions] or list(
        comp.equations)
    pts, factor_points = reading_points(comp, eqs, nm, params, rng)
    facts = component_facts(model, pts, factor_points, rng,
                             matrix=lambda d: nm(np.array([d[k] for k in names])))
    J = nm(np.array([comp.sample[k] for k in names], dtype=float))
    tall = tm.shape[0] > tm.shape[1]
    lost = tuple(d for d in (lost_direction(J, u, tm.row_labels, tall=tall,
                                            variables=tm.variables)
                             for u in comp.direction_at_sample) if d is not None)
    return ComponentGeometry(index, facts, lost)
