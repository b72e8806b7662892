"""The figures of a report, chosen and captioned: :func:`report_figures`.

:mod:`~rankloci.reporting.analysis` computes the numbers and
:mod:`~rankloci.reporting.figures` draws them; this module decides which
figures a report has (heat-map slices through the components, manipulability
along paths across them, the branch tree, J beside the augmented J) and
writes their captions.  Nothing is written to disk here.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np
import sympy as sp

from .blocks import SIGMA, numbered, plural, signed
from ..geometry import motion_arrow
from ..numeric.svd import sigma_ratio

__all__ = ["FigureFile", "report_figures", "reading_lines", "MAX_SLICES", "MAX_PATHS"]

#: At most this many heat-map slices and manipulability paths per report.
MAX_SLICES = 4
MAX_PATHS = 6


@dataclass(frozen=True)
class FigureFile:
    """One figure: its file name beside the report, PNG bytes and caption (text with $math$)."""

    name: str
    png: bytes
    caption: str
    kind: str
    title: str = ""
    components: tuple = ()    # the 1-based numbers of the components it shows
    through: int | None = None  # a heat map's slice passes through this component's sample
    boxes: int = 0            # the branch tree: how many boxes are drawn


def _units(model, model_tm) -> str:
    """The unit of the manipulability of ``model_tm``."""
    from ..model import RobotModel

    if not isinstance(model, RobotModel):
        return "units of the matrix entries"
    linear = sum(1 for r in model_tm.row_labels if r in ("vx", "vy", "vz"))
    if any(j.kind == "prismatic" for j in model.joints):
        return "mixed units (prismatic and revolute columns)"
    return "dimensionless" if linear == 0 else ("m" if linear == 1 else f"m^{linear}")


def _vector3(labels, vec, rows) -> np.ndarray:
    """The entries of ``vec`` on ``rows`` (e.g. vx vy vz) as a 3-vector (0 where absent)."""
    labels = list(labels)
    return np.array([float(vec[labels.index(r)]) if r in labels else 0.0 for r in rows])


def _robot_figures(model, model_tm, comps, views, nm, params, paths, stem) -> list:
    """A picture of the arm at each component's sample point and at a nearby regular pose."""
    from ..model import RobotModel
    from .figures import HIGHLIGHT_LONG_MAX, ROBOT_REGULAR_T, robot_png
    from .robot import robot_pose

    if not isinstance(model, RobotModel) or getattr(model, "frame", "base") != "base":
        return []
    names = [v.name for v in nm.variables]
    labels = list(model_tm.row_labels)
    lin = [k for k, r in enumerate(labels) if r in ("vx", "vy", "vz")]
    tall = model_tm.shape[0] > model_tm.shape[1]
    by_view = {v.index: v for v in views}
    out = []
    for path in paths:
        idx = path.component
        c = comps[idx]
        q0 = path.point
        ts = path.t[(path.t >= 0.2) & (path.t <= 0.6)]
        rs = path.ratio[(path.t >= 0.2) & (path.t <= 0.6)]
        t_reg = ROBOT_REGULAR_T if float(np.interp(ROBOT_REGULAR_T, path.t, path.ratio)) > \
            float(np.max(rs)) / 10 else float(ts[int(np.argmax(rs))])
        q1 = q0 + t_reg * path.step
        J0, J1 = nm(q0), nm(q1)
        arrow, what = None, ""
        view = by_view.get(idx)
        if view is not None and view.lost_axis:
            pattern = re.compile(r"joints (\d+) to (\d+) together cannot rotate", re.I)
            joints = next((m.groups() for r in view.readings if (m := pattern.match(r))), None)
            arrow = np.array(view.lost_axis)
            what = (f"axis of the rotation joints {joints[0]} to {joints[1]} lose" if joints
                    else "axis of the lost rotation")
        elif c.direction_at_sample and not tall:
            u = np.asarray(c.direction_at_sample[0], dtype=float)
            a = _vector3(labels, u, ("vx", "vy", "vz"))
            b = _vector3(labels, u, ("wx", "wy", "wz"))
            # a part counts from 1e-3: directions are read to 3 decimals
            vector, kind = motion_arrow(a, b, 1e-3)
            if kind is not None:
                arrow = vector
                what = {"translation": "lost translation",
                        "rotation": "axis of the lost rotation",
                        "translation part": "translation part of the lost motion"}[kind]
        axes = tuple(view.axes) if view is not None else ()
        # a shoulder singularity's reading names a plane through an axis: it is drawn
        through = re.compile(r"the task point lies in the plane through axis (\d+)\b")
        plane = next((int(m.group(1)) for r in (view.readings if view is not None else ())
                      if (m := through.search(r))), None)
        named = reading_lines(view.readings if view is not None else ())
        Jv0 = J0[lin] if lin else None
        Jv1 = J1[lin] if lin else None
        title = f"{stem}: component {idx}"
        pose0 = robot_pose(model, dict(zip(names, q0)), params)
        pose1 = robot_pose(model, dict(zip(names, q1)), params)
        png = robot_png(pose0, pose1, highlight=axes, arrow=arrow, arrow_label=what,
                        Jv_singular=Jv0, Jv_regular=Jv1, title=title, plane=plane,
                        lines=tuple((g[0], label) for g, label, _ in named))
        prismatic = "prismatic" in pose0.kinds
        flat = ""
        if lin:
            # the ratio of the semi-axes; 0 for J_v = 0 (an arm of zero length), not nan
            r0, r1 = (float(sigma_ratio(Jv)) for Jv in (Jv0, Jv1))
            flat = (" Green: the translational manipulability ellipsoid "
                    "$\\lbrace J_v \\dot q : \\lVert \\dot q \\rVert \\le 1 \\rbrace$ at the task "
                    "point, scaled to a quarter of the arm's size; its smallest semi-axis is "
                    f"{r0:.2g} of its largest at the singular pose and "
                    f"{r1:.2g} at the regular one"
                    + (" (flat: the lost motion is a translation)." if r0 < 1e-6
                       else " (not flat: the lost motion involves a rotation)."))
        planar = pose0.planar and pose1.planar
        if planar:
            hot = (f" Red: the joints the reading names ({', '.join(map(str, axes))})."
                   if axes else "")
            parts = ("Drawn in the arm's plane. Grey: the links through the frame origins, "
                     "from the base (dark triangle); circles: the revolute joints"
                     + ("; boxes: the prismatic joints" if prismatic else "")
                     + "; orange star: the task point, with the end-effector frame's x (red) "
                     "and y (green) axes.")
        else:
            hot = (f" Red{', long' if len(axes) <= HIGHLIGHT_LONG_MAX else ''}: the axes the "
                   f"reading names ({', '.join(map(str, axes))})." if axes else "")
            parts = ("Grey: the links through the frame origins, from the base (dark box) on "
                     "the floor (light grey); blue: the joint axes"
                     + (" (dashed, in a box, for prismatic joints)" if prismatic else "")
                     + "; orange star: the task point, with the end-effector frame's x, y and z "
                     "axes (red, green, blue).")
        arrow_text = f" Purple arrow: the {what} at the task point." if arrow is not None else ""
        if plane is not None and not planar:
            arrow_text += (f" Translucent red, left: the plane through axis {plane} and the "
                           "task point that the reading names.")
        if named and not planar:
            arrow_text += (" Broad magenta, dash-dot, extended through the arm, left: "
                           + "; ".join(what for _, _, what in named) + ".")
        caption = (f"The arm at the sample point of component {idx} (left) and at the regular "
                   f"configuration $q_0 + {t_reg:.2f}\\,d$ on its manipulability path (right; "
                   f"{SIGMA} = {float(np.interp(t_reg, path.t, path.ratio)):.2g}). "
                   + parts + hot + arrow_text + flat)
        out.append(FigureFile(f"{stem}-robot-{idx}.png", png, caption, "robot", title, (idx,),
                              idx))
    return out


_COLLINEAR = re.compile(r"\baxes ((?:\d+, )*\d+) and (\d+) are collinear")
_ON_AXIS = re.compile(r"\b(the task point|the point where axes (?:(?:\d+, )*\d+ and )?\d+ meet)"
                      r" lies on axis (\d+)\b")


def reading_lines(readings) -> tuple:
    """The lines a component's readings name, to be drawn on the arm.

    Each is (joints, legend label, caption phrase): a group of collinear axes (one line
    through them all), or an axis a point lies on (the task point, a wrist centre).  A
    line is named once, by its first mention.

    Examples
    --------
    >>> reading_lines(["Wrist singularity: axes 4 and 6 are collinear"])
    (((4, 6), 'axes 4 and 6 (collinear)', 'the line of axes 4 and 6, collinear'),)
    >>> reading_lines(["Boom singularity: the point where axes 4, 5 and 6 meet lies on axis 2"])[0][:2]
    ((2,), 'axis 2 (a point on it)')
    """
    out, seen = [], set()
    for r in readings:
        found = []
        for m in _COLLINEAR.finditer(r):
            g = tuple(int(x) for x in m.group(1).split(", ")) + (int(m.group(2)),)
            names = ", ".join(map(str, g[:-1])) + f" and {g[-1]}"
            found.append((m.start(), g, f"axes {names} (collinear)",
                          f"the line of axes {names}, collinear"))
        for m in _ON_AXIS.finditer(r):
            k = int(m.group(2))
            found.append((m.start(), (k,), f"axis {k} (a point on it)",
                          f"the line of axis {k}, on which {m.group(1)} lies"))
        for _, g, label, what in sorted(found):
            if not seen & set(g):
                seen.update(g)
                out.append((g, label, what))
    return tuple(out)


def _tol_text() -> str:
    from ..tolerances import ON_LOCUS_RTOL

    return f"{ON_LOCUS_RTOL:.0e}".replace("e-0", "e-")


def _isolated_sentence(data, comps, n: int) -> str:
    """Why a component of codimension two or more shows as dots on a two-joint slice."""
    dots = [i for i, lines, pts in data.curves if not lines and len(pts)]
    if not dots:
        return ""
    by = dict(comps)
    codim = sorted({n - by[i].dimension for i in dots})
    what = numbered("component", dots)
    c = codim[0] if len(codim) == 1 else None
    size = (f"codimension {c}" if c is not None
            else "codimensions " + ", ".join(str(x) for x in codim))
    return (f" {what[0].upper() + what[1:]} {'has' if len(dots) == 1 else 'have'} {size} in "
            f"the {n}-dimensional joint space (a redundant arm keeps its rank until two or more "
            "conditions hold at once), so a two-joint slice meets "
            f"{'it' if len(dots) == 1 else 'them'} only at isolated points (dots), where the "
            "ratio is zero; next to them it can stay small along a valley where the slice runs "
            "close to the component without meeting it.")


def _units_text(units: str) -> str:
    """``m^3`` as LaTeX math (``$\\mathrm{m}^{3}$``); other unit texts unchanged."""
    m = re.fullmatch(r"m\^(\d+)", units)
    return f"$\\mathrm{{m}}^{{{m.group(1)}}}$" if m else units


def _slice_point_without_locus(nm, rng):
    """A configuration for a heat map when no component is known, and how to name it
    (:func:`~rankloci.numeric.landscape.slice_point`)."""
    from ..numeric.landscape import slice_point

    q, singular = slice_point(nm, rng)
    if singular:
        return q, "a singular configuration found numerically (a minimum of the ratio)"
    return q, "a random regular configuration"


def _solved_variants(c, names) -> list:
    """The sample point of ``c`` with each solved variable at each of its values in turn: a
    component made of several leaves (q5 = 0 and q5 = pi) then has a point on each."""
    out = []
    solved = {str(k): v for k, v in (c.solved or {}).items()}
    for var, values in solved.items():
        if var not in names or len(values) < 2:
            continue
        for v in values:
            try:
                x = float(v)
            except (TypeError, ValueError):
                continue
            out.append(np.array([x if n == var else c.sample[n] for n in names], dtype=float))
    return out


def report_figures(model, model_tm, locus, nm, params, seed, dot, views=()) -> tuple:
    """The :class:`FigureFile` of each figure of a report.

    ``model_tm`` is J in the model's own frame and ``nm`` its numeric form
    with the parameters at ``params``; ``locus`` may be None (it did not
    finish), and then the heat map passes through a configuration found
    numerically.  ``seed`` fixes the paths, ``dot`` is graphviz's ``dot``
    (or None: the tree is drawn with matplotlib).  ``views`` are the report's
    :class:`~rankloci.reporting.build.ComponentView` (their readings name the axes
    the pictures of the robot highlight).
    """
    from . import analysis as A
    from .escape import file_stem

    stem = file_stem(model.name)  # names the files and titles the figures
    rng = np.random.default_rng(seed)
    comps = A.model_components(locus) if locus is not None else []
    slices = _slices(nm, comps, params, rng)
    out = _slice_figures(slices, comps, locus, nm, stem)
    if comps:
        out += _path_figures(model, model_tm, comps, views, nm, params, rng, seed, stem)
    if locus is not None and locus.tree is not None and locus.tree.number_of_nodes():
        out.append(_tree_figure(locus, comps, nm, params, rng, dot, stem))
    base = getattr(locus, "base", None) if locus is not None else None
    if base is not None and slices:
        out.append(_augmented_figure(model, base, slices[0][0], nm, params, stem))
    return tuple(out)


def _slices(nm, comps, params, rng) -> list:
    """(SliceData, where the slice passes through) for the heat maps: one through a sample
    point of each component that no earlier slice shows (at most MAX_SLICES), or one through
    a configuration found numerically when there are no components."""
    from . import analysis as A

    names = [v.name for v in nm.variables]
    slices = []
    if len(names) >= 2:
        used = []
        for idx, comp in (comps or [(None, None)]):
            if len(slices) >= MAX_SLICES:
                break
            if comp is None:
                point, where = _slice_point_without_locus(nm, rng)
                weights = {}
            else:
                point = np.array([comp.sample[n] for n in names], dtype=float)
                where = f"a sample point of component {idx}"
                weights = A.equation_weights([(idx, comp)], nm.variables)
            axes = A.slice_joints(nm, point, weights)
            if any(axes == a and idx in {c[0] for c in s.curves} for a, s in used):
                continue
            data = A.slice_grid(nm, comps, params, axes, point, through=idx)
            used.append((axes, data))
            slices.append((data, where))
    return slices


def _slice_figures(slices, comps, locus, nm, stem) -> list:
    """The heat map of each slice, with its caption."""
    from .figures import heatmap_png

    names = [v.name for v in nm.variables]
    prismatic = [v not in nm.angles for v in nm.variables]
    out = []
    for k, (data, where) in enumerate(slices, start=1):
        i, j = data.axes
        fixed = ", ".join(f"{names[m]} = {signed(data.point[m], 3)}" for m in range(len(names))
                          if m not in (i, j))
        short = (f"a point of component {data.through}" if data.through
                 else "a singular point" if where.startswith("a singular") else "a regular point")
        title = f"{stem}: ({names[i]}, {names[j]}) slice through {short}"
        shown = [c[0] for c in data.curves]
        if shown:
            drawn = (f". Lines and dots: where {numbered('component', shown)} "
                     f"{'meets' if len(shown) == 1 else 'meet'} the slice")
            sided = [i for i in shown if dict(comps)[i].excluding]
            if sided:
                drawn += (f", drawn only away from the excluded {plural('set', len(sided))} "
                          f"of {numbered('component', sided)} (there the equations also "
                          "vanish at regular configurations)")
            drawn += "."
            drawn += _isolated_sentence(data, comps, len(names))
        elif locus is None:
            drawn = ". The locus did not finish, so none is drawn."
        else:
            drawn = ". No component of the locus meets this slice."
        caption = (f"{SIGMA} of $J$ over the ({names[i]}, {names[j]}) slice through "
                   f"{where} (the cross), log colour scale"
                   + (f"; the other joints are fixed at {fixed}" if fixed else "") + drawn)
        out.append(FigureFile(f"{stem}-sigma-{k}.png",
                              heatmap_png(data, names, prismatic, title=title), caption, "sigma",
                              title, tuple(shown), data.through))
    return out


def _path_figures(model, model_tm, comps, views, nm, params, rng, seed, stem) -> list:
    """Manipulability along a path through each component, and the pictures of the arm."""
    from . import analysis as A
    from .figures import manipulability_png

    names = [v.name for v in nm.variables]
    out = []
    paths = []
    for idx, c in comps[:MAX_PATHS]:
        q0 = np.array([c.sample[n] for n in names], dtype=float)
        normals = A.normal_directions(A.component_equations(c, nm, params), q0)
        paths.append(A.path_through(nm, q0, rng, component=idx, normals=normals))
    units = _units(model, model_tm)
    caption = (f"Manipulability $w = \\sqrt{{\\det(J J^T)}}$ [{_units_text(units)}] along "
               "straight joint-space "
               "paths $q(t) = q_0 + t d$, $-1 \\le t \\le 1$, each through the sample "
               "point $q_0$ of one component (at $t = 0$) between two regular "
               f"configurations. $\\lVert d \\rVert = {A.PATH_LENGTH:g}$, "
               f"{A.PATH_NORMAL_SHARE:g} of it across the component (in the span of its "
               f"equations' gradients) and the rest random (seed {seed}), so each path "
               "crosses its component transversally. Red dots: every parameter $t$ at which "
               f"the path meets the locus ({SIGMA} refined to at most "
               f"{_tol_text()}), some of them on other components.")
    title = f"{stem}: manipulability across the locus"
    out.append(FigureFile(f"{stem}-manipulability.png",
                          manipulability_png(paths, units=units, title=title),
                          caption, "manipulability", title,
                          tuple(p.component for p in paths)))
    out += _robot_figures(model, model_tm, dict(comps), views, nm, params, paths, stem)
    return out


def _tree_figure(locus, comps, nm, params, rng, dot, stem) -> FigureFile:
    """The branch tree, with the leaves of each component marked."""
    from . import analysis as A
    from .figures import tree_png
    from .tree_summary import component_leaves, tree_summary

    names = [v.name for v in nm.variables]
    points = {idx: [np.array([c.sample[n] for n in names], dtype=float)]
              + A.component_points(c, nm, params, rng, 2)[1:]
              + _solved_variants(c, names) for idx, c in comps}
    leaves = component_leaves(locus.tree, points, nm.variables, params)
    summary = tree_summary(locus.tree, components=leaves)
    cut = (f" The tree has {summary.total_nodes} nodes; drawn are the paths to one leaf of "
           f"each component, the other {summary.collapsed} branches are left out (the "
           "table above counts the stop reasons of all leaves)." if summary.collapsed
           else "")
    found = sorted(set(leaves.values()))
    missing = [idx for idx, _ in comps if idx not in found]
    miss = (f" No leaf matches {numbered('component', missing)}: the final merge of "
            "the leaves formed it." if missing else "")
    caption = (f"Branch tree of the {locus.method} method, top-down; each node shows its "
               "branch condition (in half-angle coordinates, cut after three lines) and the "
               "columns and k of its level. Green leaves are branches "
               "that give a component of the model, labelled with its number (their "
               "conditions vanish at its points); grey leaves stop for the reason in "
               "brackets, among them branches that exist only for special parameter "
               "values." + cut + miss)
    return FigureFile(f"{stem}-tree.png", tree_png(summary, dot=dot), caption, "tree",
                      f"{stem}: branch tree of the {locus.method} method",
                      boxes=summary.graph.number_of_nodes())


def _augmented_figure(model, base, data, nm, params, stem) -> FigureFile:
    """J and the augmented J over the first heat map's slice, side by side."""
    from ..jacobians import task_matrix
    from ..numeric.equations import NumericMatrix
    from . import analysis as A
    from .figures import augmented_png

    names = [v.name for v in nm.variables]
    prismatic = [v not in nm.angles for v in nm.variables]
    plain_tm = task_matrix(model, use_model_augment=False)
    nm_plain = NumericMatrix(sp.Matrix(plain_tm.matrix).subs(params), plain_tm.variables,
                             plain_tm.angles)
    nm_plain.strokes = getattr(nm, "strokes", {})
    # the same window as the augmented slice: the panels share their axes, and a window
    # chosen for J alone would leave a white band in one of them
    # (an angle's window is a full turn about its middle, a length's is set by the point)
    window = tuple((g[0] + g[-1]) / 2 if nm.variables[k] in nm.angles else data.point[k]
                   for g, k in ((data.xs, data.axes[0]), (data.ys, data.axes[1])))
    left = A.slice_grid(nm_plain, A.model_components(base), params, data.axes, data.point,
                        through=data.through, n=len(data.xs), centres=window)
    i, j = data.axes
    caption = (f"{SIGMA} over the ({names[i]}, {names[j]}) slice of the first "
               "heat map, one colour scale: left J without the constraint rows, with the "
               "components of its own locus; right the augmented J, with the components "
               "of the augmented locus. Components drawn on the right only are algorithmic "
               "singularities.")
    title = f"{stem}: J and the augmented J"
    return FigureFile(f"{stem}-augmented.png",
                      augmented_png(left, data, names, prismatic, title=title),
                      caption, "augmented", title)
