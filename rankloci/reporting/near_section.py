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
#: Panels of the near-manipulability figure in one row.
NEAR_COLUMNS = 3
#: The 3-D panels of that figure draw their cube at this fraction of the panel: at full size
#: the label of the third axis (vz), which constrained layout does not place, runs off the
#: right edge of the figure by about 10 pixels.
NEAR_CUBE_ZOOM = 0.85
#: Font size (pt) of that figure as drawn: a row of three 3.4-inch panels is printed at about
#: half size (0.85 of a 6.3-inch line), so 13 pt titles and 12 pt legends and ticks read as
#: 6 pt and more.
NEAR_FONT_PT = 13
#: Joint-space distances at which the path is aimed past the component (it would stop on it:
#: the rates are unbounded there); the path that peaks at its crossing and goes on is kept.
PATH_MISS = (0.08, 0.02)
#: A rate peak counts as the path's crossing when it lies within this much of the path
#: parameter (0..1) from the point closest to the locus.
PEAK_WINDOW = 0.05
#: A peak counts when the largest rate is at least this many times the rate at the start.
PEAK_RATIO = 3.0
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
    miss: float = 0.0     # how far from the sample point (joint space) the line is aimed


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
    from ..near.figures import path_figure
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
    figs = []
    if len(kin.position_rows) in (2, 3):
        fig = near_manipulability_figure(model, poses, three=len(kin.position_rows) == 3)
        figs.append(FigureFile(f"{stem}-near-manipulability.png", figure_png(fig),
                               _pose_caption(poses, distance_unit(model)), "near-manipulability",
                               f"{stem}: manipulability ellipsoids and polytopes",
                               tuple(p.component for p in poses[1:])))

    path, got, best = None, None, None
    for (idx, (q0, d, k)), miss in ((item, m) for item in starts.items() for m in PATH_MISS):
        # a line in task space from q0 + PATH_OFFSET e to q0 + miss e and as far beyond,
        # e across the component with the orientation kept to first order: the joints pass
        # about miss from the component, where the rates peak
        e = _across_keeping_orientation(kin, q0, d)
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
    if best is not None:
        _, idx, k, start, got, j, miss = best
        dist = cd.distance(k, got.q[j])[0]
        path = NearPath(idx, start, float(got.t[j]), float(np.abs(got.rates_inf[j]).max()),
                        float(np.abs(got.rates_inf[0]).max()), float(got.index[j]),
                        float(got.sigma_ratio[j]), float(dist), got.stopped, miss)
        fig = path_figure(got)[0].figure
        for ax in fig.axes:
            _fixed_legend(ax, fontsize="small", loc="upper left", bbox_to_anchor=(1.01, 1.0))
        figs.append(FigureFile(f"{stem}-near-path.png", figure_png(fig),
                               _path_caption(path), "near-path",
                               f"{stem}: minimum infinity-norm rates through component {idx}",
                               (idx,)))
    return NearData(tuple(poses), path, "position" if position else "task", tuple(figs))


def near_manipulability_figure(model, poses, *, three: bool = True):
    """The position rows' ellipsoid and polytope at each of ``poses``, a matplotlib Figure.

    At most :data:`NEAR_COLUMNS` panels a row, with text of :data:`NEAR_FONT_PT`, so that
    the text keeps a legible size when the figure is scaled to the line width.
    """
    import matplotlib
    from matplotlib.figure import Figure as MplFigure
    from matplotlib.ticker import MaxNLocator

    from ..api.near import manipulability
    from ..near.figures import plot_manipulability

    cols = min(NEAR_COLUMNS, len(poses))
    rows = -(-len(poses) // cols)
    with matplotlib.rc_context({"font.size": NEAR_FONT_PT}):
        fig = MplFigure(figsize=(3.4 * cols, 3.8 * rows),
                        layout="constrained")
        # each panel is a row for its legend (and title) above the plot: a legend over the
        # plot would cover the ellipsoid and the polytope
        grid = fig.add_gridspec(2 * rows, cols, height_ratios=[1, 4.0] * rows)
        for i, p in enumerate(poses):
            r, c = divmod(i, cols)
            ax = fig.add_subplot(grid[2 * r + 1, c], projection="3d" if three else None)
            plot_manipulability(manipulability(model, p.q, position_only=True).J, ax=ax)
            if three:
                # constrained layout does not see a 3-D axis label: draw the cube smaller so
                # that the labels at its corners (vz on the right) stay inside the figure
                ax.set_box_aspect((1, 1, 1), zoom=NEAR_CUBE_ZOOM)
            ax.tick_params(labelsize=NEAR_FONT_PT - 1)
            # three ticks an axis: at this size more would run into each other
            for axis in (ax.xaxis, ax.yaxis) + ((ax.zaxis,) if three else ()):
                axis.set_major_locator(MaxNLocator(3))
            handles, labels = ax.get_legend_handles_labels()
            if ax.get_legend() is not None:
                ax.get_legend().remove()
            key = fig.add_subplot(grid[2 * r, c])
            key.set_axis_off()
            key.legend(handles, labels, loc="center", fontsize=NEAR_FONT_PT - 1, frameon=False,
                       title="regular pose" if p.component == 0
                       else f"near component {p.component}", title_fontsize=NEAR_FONT_PT,
                       borderaxespad=0.0)
    return fig


def _across_keeping_orientation(kin, q0, d) -> np.ndarray:
    """The unit joint direction nearest to ``d`` that leaves the orientation unchanged at
    ``q0`` to first order (``d`` itself when the task has no angular rows or none is left)."""
    ang = [i for i, r in enumerate(kin.rows) if r >= 3]
    if not ang:
        return _unit(d)
    Jw = kin.jacobian(q0)[ang]
    _, s, vt = np.linalg.svd(Jw)
    rank = int(np.sum(s > 1e-9 * max(float(s[0]), 1e-300))) if s.size else 0
    null = vt[rank:]
    e = null.T @ (null @ np.asarray(d, dtype=float))
    return _unit(e) if np.linalg.norm(e) > 0.1 * np.linalg.norm(d) else _unit(d)


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
            f"ratio and {SIGMA} (bottom) as the tool point follows a straight line from its "
            f"position at $q_0 + {PATH_OFFSET:g}\\,e$ through its position at "
            f"$q_0 + {path.miss:g}\\,e$ and as far beyond, the orientation held; $q_0$ is the "
            f"sample point of component {path.component} and $e$ a unit joint direction across "
            "it that keeps the orientation to first order, so the joints pass close to the "
            f"component. Where {SIGMA} is smallest (t = {path.t:.3g}) the largest joint rate is "
            f"{path.rate_max:.3g}, against {path.rate_max_start:.3g} at the start.")


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
            f"{PATH_OFFSET:g} {unit} across component {p.component} from its sample point (in a "
            "direction that keeps the orientation to first order), the tool point follows a "
            f"straight line through its position {p.miss:g} {unit} from the sample point "
            "on the same side and as far beyond, the orientation held, so that the joints pass "
            f"close to the component, with the joint rates of least "
            f"$\\max_i |\\dot q_i|$ (Ha and Lee's algorithm, {PATH_STEPS} steps). At the "
            f"closest approach (the step where {SIGMA} is smallest, $t = {p.t:.3g}$, "
            f"{SIGMA} = {_g(p.sigma_ratio, 3)}, {_g(p.distance, 3)} {unit} from the component) "
            f"the largest joint rate is {_g(p.rate_max)} (against {_g(p.rate_max_start)} at the "
            f"start) and Ha and Lee's discontinuity index is {_g(p.index, 3)}." + stop))
        for f in data.figures:
            if f.kind == "near-path":
                out.append(Figure(f.name, f.caption, labels[f.name], alt=f.title))
    return out
