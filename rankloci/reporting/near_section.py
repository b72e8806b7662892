"""The report's section on motion near the locus: :func:`near_data` and :func:`near_blocks`.

For a robot model with position rows in its task, :func:`near_data` evaluates the
functions of :mod:`rankloci.near` at a regular pose and near each component
(manipulability ellipsoid and polytope, distance to the component) and along one
task-space line through a component (minimum infinity-norm joint rates), and draws
their figures; :func:`near_blocks` turns the result into blocks of
:mod:`~rankloci.reporting.blocks`.  Nothing is written to disk here.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .blocks import SIGMA, Figure, Heading, Para, Table, block_label, numbered

__all__ = ["NearPose", "NearPath", "NearData", "near_data", "near_blocks", "NEAR_OFFSET",
           "PATH_OFFSET", "MAX_NEAR_COMPONENTS", "FULL_POLYTOPE_JOINTS"]

#: Joint-space distance (rad, or m along a prismatic joint) from a component's sample point to
#: the pose "near" it.
NEAR_OFFSET = 0.05
#: Joint-space distance (rad, or m along a prismatic joint) from a component's sample point to
#: the start of the path.
PATH_OFFSET = 0.4
#: Poses near at most this many components (the first ones).
MAX_NEAR_COMPONENTS = 4
#: Arms with more joints get the polytope of the position rows only (2^n vertices).
FULL_POLYTOPE_JOINTS = 7
#: Steps of the path through a component.
PATH_STEPS = 120


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


@dataclass(frozen=True)
class NearData:
    """What the section says: the poses, the path, and which rows the polytope uses."""

    poses: tuple
    path: NearPath | None
    polytope_rows: str      # "task" or "position"
    figures: tuple


def _unit(v) -> np.ndarray:
    v = np.asarray(v, dtype=float)
    n = float(np.linalg.norm(v))
    return v / n if n > 0 else v


def _away(eqs, q0, rng) -> np.ndarray:
    """A unit joint-space direction across the component at ``q0`` (its first normal)."""
    from .analysis import normal_directions

    normals = normal_directions(eqs, q0)
    if len(normals):
        return _unit(normals[0])
    return _unit(rng.standard_normal(len(q0)))  # pragma: no cover - equations without gradient


def near_data(model, locus, nm, params, seed: int, stem: str) -> NearData | None:
    """Manipulability at a regular pose and near each component, and a path through one.

    ``locus`` is the report's locus (None: only the regular pose), ``nm`` J in the
    model's frame with the parameters at ``params``.  Returns None for a model that is
    not a robot or whose task has no position rows.
    """
    from ..model import RobotModel
    from ..api.near import joint_rates, manipulability
    from ..near.figures import path_figure, plot_manipulability
    from ..near.manipulability import ellipsoid
    from ..near.nearest import ComponentDistance
    from ..near.path import Kinematics
    from . import analysis as A
    from .figure_files import FigureFile
    from .figures import figure_png

    if not isinstance(model, RobotModel) or not any(r < 3 for r in model.task):
        return None
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
        d = _away(A.component_equations(c, nm, params), q0, rng)
        q = q0 + NEAR_OFFSET * d
        k = idx - 1  # model_components numbers locus.components from 1
        poses.append(pose(idx, q, float(cd.distance(k, q)[0])))
        starts[idx] = (q0, d, k)

    # figure: the position rows' ellipsoid and polytope at each pose
    from matplotlib.figure import Figure as MplFigure

    three = len(kin.position_rows) == 3
    figs = []
    if len(kin.position_rows) in (2, 3):
        fig = MplFigure(figsize=(3.2 * len(poses), 3.4 if three else 3.0), layout="constrained")
        for i, p in enumerate(poses, start=1):
            ax = fig.add_subplot(1, len(poses), i, projection="3d" if three else None)
            plot_manipulability(manipulability(model, p.q, position_only=True).J, ax=ax)
            ax.set_title("regular pose" if p.component == 0 else f"near component {p.component}",
                         fontsize="small")
            _fixed_legend(ax, fontsize="x-small", loc="upper left")
        figs.append(FigureFile(f"{stem}-near-manipulability.png", figure_png(fig),
                               _pose_caption(poses, distance_unit(model)), "near-manipulability",
                               f"{stem}: manipulability ellipsoids and polytopes",
                               tuple(p.component for p in poses[1:])))

    path = None
    for idx, (q0, d, k) in starts.items():
        # the first component whose path takes a step (it stops at once from a start
        # that is itself too close to the locus)
        start = q0 + PATH_OFFSET * d
        x0, x1 = kin.position(start), kin.position(q0)
        got = joint_rates(model, start, [x0, x1, 2 * x1 - x0], norm="inf", steps=PATH_STEPS)
        if len(got.t) < 2:
            continue
        j = int(np.argmin(got.sigma_ratio))
        dist = cd.distance(k, got.q[j])[0]
        path = NearPath(idx, start, float(got.t[j]), float(np.abs(got.rates_inf[j]).max()),
                        float(np.abs(got.rates_inf[0]).max()), float(got.index[j]),
                        float(got.sigma_ratio[j]), float(dist), got.stopped)
        fig = path_figure(got)
        for ax in fig.axes:
            _fixed_legend(ax, fontsize="small", loc="upper left", bbox_to_anchor=(1.01, 1.0))
        figs.append(FigureFile(f"{stem}-near-path.png", figure_png(fig),
                               _path_caption(path), "near-path",
                               f"{stem}: minimum infinity-norm rates through component {idx}",
                               (idx,)))
        break
    return NearData(tuple(poses), path, "position" if position else "task", tuple(figs))


def _fixed_legend(ax, **where):
    """Redraw the legend of ``ax`` at a fixed place: "best" would search at draw time."""
    if ax.get_legend() is not None:
        ax.legend(**where)


def distance_unit(model) -> str:
    """The unit of a joint-space distance: rad, or mixed when some joint is prismatic.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> distance_unit(SimpleNamespace(joints=[SimpleNamespace(kind="prismatic")]))
    'joint-space units (rad for revolute, m for prismatic joints)'
    """
    if any(j.kind == "prismatic" for j in getattr(model, "joints", ())):
        return "joint-space units (rad for revolute, m for prismatic joints)"
    return "rad"


def _pose_caption(poses, unit: str = "rad") -> str:
    near = [p.component for p in poses[1:]]
    return ("Manipulability ellipsoid (blue) and polytope (orange, the image of the cube "
            "$|\\dot q_i| \\le 1$) of the position rows of $J$ at the regular pose"
            + (f" and {NEAR_OFFSET:g} {unit} from the sample point of "
               + numbered("component", near) if near else "")
            + "; $w$ and $w_p$ of the position rows in the legends.")


def _path_caption(path) -> str:
    return ("Minimum infinity-norm joint rates (top) and the discontinuity indices, mixing "
            f"ratio and {SIGMA} (bottom) as the tool point follows a straight line through "
            f"the tool position at the sample point of component {path.component}, the "
            "orientation held.")


def _g(x, digits: int = 4) -> str:
    return f"{x:.{digits}g}"


def near_blocks(report) -> list:
    """The section's blocks, or [] when the report has no such data."""
    data = getattr(report, "near", None)
    if data is None:
        return []
    out = [Heading(2, "Motion near the locus", block_label(report, "near"))]
    unit = distance_unit(report.model)
    rows = "the position rows of $J$" if data.polytope_rows == "position" else "$J$"
    reason = (f" (the arm has more than {FULL_POLYTOPE_JOINTS} joints: the polytope of all "
              "task rows has too many vertices to compute quickly)"
              if data.polytope_rows == "position" else "")
    out.append(Para(
        "The manipulability ellipsoid $\\lbrace J \\dot q : \\lVert \\dot q \\rVert_2 \\le 1 "
        "\\rbrace$ has semi-axes the singular values of $J$ and $w = \\sqrt{\\det(J J^T)}$; "
        f"the polytope $\\lbrace J \\dot q : \\lVert \\dot q \\rVert_\\infty \\le 1 \\rbrace$ of "
        f"{rows}{reason} is given by its volume. Both are evaluated at the best conditioned "
        f"of 50 random configurations (seed {report.seed}) and {NEAR_OFFSET:g} {unit} from the "
        "sample point of each component, across it; the distance is the joint-space distance "
        "to the component found numerically."
        + (" They are those of the task rows alone, without the constraint rows: the "
           "locus is the augmented $J$'s, so near a component of it $w$ need not be small."
           if getattr(report.model, "augment", ()) else "")))
    table = []
    for p in data.poses:
        where = "regular pose" if p.component == 0 else f"near component {p.component}"
        table.append((where, "" if p.component == 0 else _g(p.distance, 3), _g(p.sigma_ratio, 3),
                      _g(p.w), ", ".join(_g(r, 3) for r in p.radii), _g(p.volume)))
    out.append(Table(("pose", "distance", SIGMA, "$w$", "semi-axes", "polytope volume"),
                     tuple(table), "lrrrlr"))
    reg = data.poses[0]
    nearer = [p for p in data.poses[1:] if p.w < reg.w]
    if len(data.poses) == 2:
        out.append(Para(f"$w$ is {'smaller' if nearer else 'not smaller'} near component "
                        f"{data.poses[1].component} than at the regular pose ({_g(reg.w)})."))
    elif len(data.poses) > 2:
        out.append(Para(f"$w$ is smaller near {len(nearer)} of the {len(data.poses) - 1} "
                        f"components than at the regular pose ({_g(reg.w)})."))
    labels = {f.name: block_label(report, "fig", f.kind) for f in data.figures}
    for f in data.figures:
        if f.kind == "near-manipulability":
            out.append(Figure(f.name, f.caption, labels[f.name], alt=f.title))
    p = data.path
    if p is not None:
        stop = f" The path {p.stopped}." if p.stopped else ""
        out.append(Para(
            "Minimum infinity-norm motion: from the configuration "
            f"{PATH_OFFSET:g} {unit} across component {p.component} from its sample point, the "
            "tool point follows a straight line through the tool position at the sample point "
            f"and as far beyond, the orientation held, with the joint rates of least "
            f"$\\max_i |\\dot q_i|$ (Ha and Lee's algorithm, {PATH_STEPS} steps). At the "
            f"closest approach (the step where {SIGMA} is smallest, $t = {p.t:.3g}$, "
            f"{SIGMA} = {_g(p.sigma_ratio, 3)}, {_g(p.distance, 3)} {unit} from the component) "
            f"the largest joint rate is {_g(p.rate_max)} (against {_g(p.rate_max_start)} at the "
            f"start) and Ha and Lee's discontinuity index is {_g(p.index, 3)}." + stop))
        for f in data.figures:
            if f.kind == "near-path":
                out.append(Figure(f.name, f.caption, labels[f.name], alt=f.title))
    return out
