"""A robot near its locus: manipulability at a regular pose and near each component, and the
joint rates along one task-space line through a component.

:func:`near_study` evaluates the functions of :mod:`rankloci.near` (through
:func:`rankloci.manipulability` and :func:`rankloci.joint_rates`) where a
locus makes them telling, and returns frozen values (:class:`NearStudy`); the
report draws and tabulates them.  Nothing is printed or written.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..tolerances import (FULL_POLYTOPE_JOINTS, MAX_NEAR_COMPONENTS, NEAR_OFFSET, PATH_OFFSET,
                          PATH_STEPS, PEAK_RATIO, PEAK_WINDOW)

__all__ = ["NearPose", "NearPath", "NearStudy", "near_study", "PATH_MISS"]

#: Joint-space distances at which the path is aimed past the component (it would stop on it:
#: the rates are unbounded there); the path that peaks at its crossing and goes on is kept.
PATH_MISS = (0.08, 0.02)


@dataclass(frozen=True)
class NearPose:
    """The manipulability at one pose: ``component`` 0 for the regular pose, else 1-based."""

    component: int
    q: np.ndarray
    distance: float       # joint-space distance to the component (nan for the regular pose)
    sigma_ratio: float
    w: float
    radii: np.ndarray
    volume: float


@dataclass(frozen=True)
class NearPath:
    """Minimum infinity-norm rates along a line through a component, at its closest approach."""

    component: int
    start: np.ndarray
    t: float
    rate_max: float
    rate_max_start: float
    index: float
    sigma_ratio: float
    distance: float
    stopped: str
    miss: float = 0.0     # how far from the sample point (joint space) the line is aimed


@dataclass(frozen=True)
class NearStudy:
    """The poses, the chosen path (with its rates, what :func:`rankloci.joint_rates`
    returned) and which rows the polytope uses (``"task"`` or ``"position"``)."""

    poses: tuple
    path: NearPath | None
    rates: object
    polytope_rows: str


def near_study(model, locus, nm, params, seed: int) -> NearStudy:
    """Manipulability at a regular pose and near each component, and a path through one.

    Parameters
    ----------
    model : RobotModel
        A robot whose task has position rows.
    locus : Locus or None
        Its locus (None: only the regular pose).
    nm : NumericMatrix
        J in the model's frame with the parameters at ``params``.
    params : dict
        Parameter values.
    seed : int
        Seed of the regular pose and of the directions off each component.

    The pose near a component lies :data:`~rankloci.tolerances.NEAR_OFFSET` from
    its sample point across it (:func:`rankloci.near.across.direction_across`),
    for the first :data:`~rankloci.tolerances.MAX_NEAR_COMPONENTS` components.
    The path is a task-space line aimed :data:`PATH_MISS` past a component's
    sample point; of the lines tried, the one whose rates peak where it comes
    closest to the locus and that goes on past it is kept.
    """
    from ..near.across import across_keeping_orientation, direction_across
    from ..near.manipulability import ellipsoid
    from ..near.nearest import ComponentDistance
    from ..near.path import Kinematics
    from ..numeric import landscape as A
    from .near import joint_rates, manipulability

    rng = np.random.default_rng(seed)
    kin = Kinematics(model)
    position = model.dof > FULL_POLYTOPE_JOINTS
    comps = A.model_components(locus) if locus is not None else []
    cd = ComponentDistance(locus, nm.angles) if comps else None

    def pose(k, q, distance):
        if position:  # the ellipsoid of all task rows, the polytope of the position rows
            E = ellipsoid(kin.jacobian(q))
            poly = manipulability(model, q, position_only=True)
        else:
            poly = manipulability(model, q)
            E = poly.ellipsoid
        return NearPose(k, q, distance, float(E.sigma_ratio), float(E.w),
                        np.asarray(E.radii, dtype=float), float(poly.polytope.volume))

    poses = [pose(0, A.regular_point(nm, rng), float("nan"))]
    starts = {}
    for idx, c in comps[:MAX_NEAR_COMPONENTS]:
        q0 = np.array([c.sample[v.name] for v in nm.variables], dtype=float)
        d = direction_across(A.component_equations(c, nm, params), q0, rng)
        q = q0 + NEAR_OFFSET * d
        k = idx - 1  # model_components numbers locus.components from 1
        poses.append(pose(idx, q, float(cd.distance(k, q)[0])))
        starts[idx] = (q0, d, k)

    best = None
    for (idx, (q0, d, k)), miss in ((item, m) for item in starts.items() for m in PATH_MISS):
        # a line in task space from q0 + PATH_OFFSET e to q0 + miss e and as far beyond,
        # e across the component with the orientation kept to first order: the joints pass
        # about miss from the component, where the rates peak
        e = across_keeping_orientation(kin, q0, d)
        start = q0 + PATH_OFFSET * e
        x0, x1 = kin.position(start), kin.position(q0 + miss * e)
        rates = joint_rates(model, start, [x0, x1, 2 * x1 - x0], norm="inf", steps=PATH_STEPS)
        if len(rates.t) < 2:
            continue
        size = np.abs(rates.rates_inf).max(axis=1)
        j = int(np.argmin(rates.sigma_ratio))
        peak = int(np.argmax(size))
        # a peak where the path comes closest to the locus, on a path that goes on past it (at
        # the workspace boundary it cannot), the higher over the start the better
        ratio = float(size[peak] / max(size[0], 1e-12))
        score = (bool(abs(rates.t[peak] - rates.t[j]) <= PEAK_WINDOW and ratio >= PEAK_RATIO),
                 not rates.stopped, ratio)
        if best is None or score > best[0]:
            best = (score, idx, k, start, rates, j, miss)
    path, got = None, None
    if best is not None:
        _, idx, k, start, got, j, miss = best
        dist = cd.distance(k, got.q[j])[0]
        path = NearPath(idx, start, float(got.t[j]), float(np.abs(got.rates_inf[j]).max()),
                        float(np.abs(got.rates_inf[0]).max()), float(got.index[j]),
                        float(got.sigma_ratio[j]), float(dist), got.stopped, miss)
    return NearStudy(tuple(poses), path, got, "position" if position else "task")
