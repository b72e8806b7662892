"""The report's section on motion near the locus: :func:`near_data` and :func:`near_blocks`.

For a robot model with position rows in its task, :func:`near_data` draws what
:func:`rankloci.api.near_study.near_study` finds at a regular pose and near each
component (manipulability ellipsoid and polytope, distance to the component) and
along one task-space line through a component (minimum infinity-norm joint
rates); :func:`near_blocks` turns the result into blocks of
:mod:`~rankloci.reporting.blocks`.  Nothing is written to disk here.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..api.near_study import NearPath, NearPose
from ..tolerances import (FULL_POLYTOPE_JOINTS, MAX_NEAR_COMPONENTS, NEAR_OFFSET, PATH_OFFSET,
                          PATH_STEPS)
from .blocks import SIGMA, Figure, Heading, Para, Table, block_label, numbered

__all__ = ["NearPose", "NearPath", "NearData", "near_data", "near_blocks", "NEAR_OFFSET",
           "PATH_OFFSET", "MAX_NEAR_COMPONENTS", "FULL_POLYTOPE_JOINTS"]

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


@dataclass(frozen=True)
class NearData:
    """What the section says: the poses, the path, and which rows the polytope uses."""

    poses: tuple
    path: NearPath | None
    polytope_rows: str      # "task" or "position"
    figures: tuple


def near_data(model, locus, nm, params, seed: int, stem: str) -> NearData | None:
    """Manipulability at a regular pose and near each component, and a path through one.

    ``locus`` is the report's locus (None: only the regular pose), ``nm`` J in the
    model's frame with the parameters at ``params``.  Returns None for a model that is
    not a robot or whose task has no position rows.
    """
    from ..api.near_study import near_study
    from ..model import RobotModel
    from ..near.figures import path_figure
    from .figure_files import FigureFile
    from .figures import figure_png

    if not isinstance(model, RobotModel) or not any(r < 3 for r in model.task):
        return None
    study = near_study(model, locus, nm, params, seed)
    poses, path = study.poses, study.path
    position_rows = [r for r in model.task if r < 3]

    # figure: the position rows' ellipsoid and polytope at each pose
    figs = []
    if len(position_rows) in (2, 3):
        fig = near_manipulability_figure(model, poses, three=len(position_rows) == 3)
        figs.append(FigureFile(f"{stem}-near-manipulability.png", figure_png(fig),
                               _pose_caption(poses, distance_unit(model)), "near-manipulability",
                               f"{stem}: manipulability ellipsoids and polytopes",
                               tuple(p.component for p in poses[1:])))
    if path is not None:
        fig = path_figure(study.rates)[0].figure
        for ax in fig.axes:
            _fixed_legend(ax, fontsize="small", loc="upper left", bbox_to_anchor=(1.01, 1.0))
        figs.append(FigureFile(f"{stem}-near-path.png", figure_png(fig),
                               _path_caption(path), "near-path",
                               f"{stem}: minimum infinity-norm rates through component "
                               f"{path.component}", (path.component,)))
    return NearData(poses, path, study.polytope_rows, tuple(figs))


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
