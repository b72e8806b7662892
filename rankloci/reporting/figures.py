"""The report's figures: a plotting API that starts from a locus, and PNG bytes for the report.

Every ``plot_*`` function takes a :class:`~rankloci.loci.Locus` (or, for
:func:`plot_robot`, also a model and a configuration) and draws into ``ax``
when given (a 3-D axes for :func:`plot_robot`), otherwise into a new
:class:`matplotlib.figure.Figure`; it returns the Axes it drew into, as
matplotlib's own plotting functions do.  The functions that draw several
panels (:func:`plot_augmented`, :func:`plot_manipulability_paths`,
:func:`robot_figure`) take and return an array of Axes.  Each also takes the
report's own data (``SliceData``, ``PathData``, ``RobotPose``,
``TreeSummary``), which is what the report passes.

No backend is chosen here (a Figure made without pyplot saves under any
backend); :func:`figure_png` turns a Figure into PNG bytes without a
timestamp or software version, so equal data give equal bytes.  The ``*_png``
functions are what the report uses.  matplotlib is imported inside the
functions (the command line's ``--help`` stays fast).
"""

from __future__ import annotations

import io
import itertools
import subprocess

import numpy as np

from ..geometry import (axis_line_ends, box_edges, plane_through_axis, rectangle_along,
                        scaled_to)
from ..numeric.svd import principal_axes

__all__ = ["plot_sigma_slice", "locus_slice", "plot_augmented", "plot_manipulability_path",
           "plot_manipulability_paths", "manipulability_paths", "plot_tree", "plot_robot",
           "robot_figure", "axis_line_ends", "figure_png", "heatmap_png", "augmented_png",
           "manipulability_png", "tree_png", "robot_png", "tree_dot_source", "HEATMAP_SIZE",
           "PATH_SIZE", "AUGMENTED_SIZE", "ROBOT_SIZE", "DPI"]

DPI = 100
#: Figure sizes in inches; at DPI they give the pixel sizes the tests expect.
HEATMAP_SIZE = (7.0, 5.2)
AUGMENTED_SIZE = (8.0, 3.6)
PATH_SIZE = (8.0, 4.8)
ROBOT_SIZE = (8.0, 4.2)

#: Font size (pt) of legends and joint numbers on the path and robot figures: the report
#: prints an 8-inch figure about 5.4 inches wide, so 9 pt reads as 6 pt.
LABEL_PT = 9

#: Highlighted axes are drawn long (through the arm) when at most this many are: more long
#: lines than this tangle over the arm (a reading that names all seven axes of the SSRMS),
#: and they are drawn at the length of the others, in red.
HIGHLIGHT_LONG_MAX = 4

#: A 3-D arm's cube fills this fraction of its panel, leaving room for the axis labels.
ROBOT_CUBE_ZOOM = 0.85

#: Locus curves: colours that stand out on viridis, with a dark outline; any two differ by a
#: CIE76 delta E of at least 20, and each differs by as much from every colour of viridis
#: (tests/report/test_report_figure_text.py).
CURVE_COLOURS = ("#ff2d55", "#ffffff", "#00e5ff", "#ffb000", "#ff66ff", "#7CFC00",
                 "#ff8c00", "#c0c0c0", "#1e90ff", "#a0522d")
_LINESTYLES = ("-", "--", "-.", ":")

#: Width (points) of a locus line on a heat map: a little over one pixel as printed, so
#: that its colour is seen and not only its dark edge.
CURVE_WIDTH = 0.9
#: Its dark edge is this much wider (points): a hairline on either side of the colour.
CURVE_EDGE = 0.3

#: Colour of the lines a reading names on a 3-D arm (collinear axes, an axis a point lies
#: on): magenta, told apart from the grey links, the blue and red axes, the green ellipsoid,
#: the purple arrow and the orange task point.
READING_LINE_COLOUR = "#e6007e"


def _new_axes(ax, size, projection=None):
    if ax is not None:
        return ax
    from matplotlib.figure import Figure

    fig = Figure(figsize=size, layout="constrained")
    return fig.add_subplot(projection=projection)


def figure_png(fig) -> bytes:
    """The PNG bytes of a matplotlib Figure at :data:`DPI`, without metadata that varies."""
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=DPI, metadata={"Software": None})
    return buf.getvalue()


def _rc():
    import matplotlib

    return matplotlib.rc_context({"font.size": 10, "axes.titlesize": 10, "legend.fontsize": 8,
                                  "font.family": "DejaVu Sans", "svg.hashsalt": "rankloci",
                                  "path.simplify": True})


def _pi_ticks(axis, lo, hi):
    """Ticks at the multiples of pi/2 in [lo, hi], labelled in pi, when the range spans 2 pi."""
    if abs((hi - lo) - 2 * np.pi) > 1e-9:
        return
    ks = np.arange(np.ceil(lo / (np.pi / 2) - 1e-9), np.floor(hi / (np.pi / 2) + 1e-9) + 1)
    names = {0: "0", 1: r"$\pi/2$", -1: r"$-\pi/2$", 2: r"$\pi$", -2: r"$-\pi$"}
    labels = [names.get(int(k), rf"${int(k) // 2}\pi$" if int(k) % 2 == 0
                        else rf"${int(k)}\pi/2$") for k in ks]
    axis.set_ticks(ks * np.pi / 2)
    axis.set_ticklabels(labels)


def _axis_label(name: str, prismatic: bool) -> str:
    return f"{name} [m]" if prismatic else f"{name} [rad]"


def _norm(*ratios):
    from matplotlib.colors import LogNorm

    lo = min(float(np.min(r)) for r in ratios)
    hi = max(float(np.max(r)) for r in ratios)
    hi = max(hi, 1e-12)
    lo = min(max(lo, 1e-6, hi * 1e-8), hi / 10)
    return LogNorm(vmin=lo, vmax=hi)


_CBAR_LABEL = r"$\sigma_{\min}/\sigma_{\max}$ of J (log scale)"


def _draw_slice(ax, data, names, prismatic, norm, cmap, *, legend=True, prefix="component",
                legend_pt=None):
    import matplotlib.patheffects as pe

    i, j = data.axes
    hx = (data.xs[-1] - data.xs[0]) / max(len(data.xs) - 1, 1) / 2
    hy = (data.ys[-1] - data.ys[0]) / max(len(data.ys) - 1, 1) / 2
    mesh = ax.imshow(np.maximum(data.ratio, norm.vmin), origin="lower", aspect="auto",
                     extent=(data.xs[0] - hx, data.xs[-1] + hx, data.ys[0] - hy, data.ys[-1] + hy),
                     norm=norm, cmap=cmap, interpolation="nearest")
    # thin lines with a hairline dark edge, narrower than the valley of the ratio they mark;
    # each component differs from the others in colour and in dash pattern (told apart in grey)
    outline = [pe.Stroke(linewidth=CURVE_WIDTH + CURVE_EDGE, foreground="black"), pe.Normal()]
    for idx, lines, pts in data.curves:
        colour = CURVE_COLOURS[(idx - 1) % len(CURVE_COLOURS)]
        style = _LINESTYLES[(idx - 1) % len(_LINESTYLES)]
        label = f"{prefix} {idx}"
        for k, seg in enumerate(lines):
            ax.plot(seg[:, 0], seg[:, 1], color=colour, linestyle=style, linewidth=CURVE_WIDTH,
                    path_effects=outline, label=label if k == 0 else None)
        if len(pts):
            ax.plot(pts[:, 0], pts[:, 1], linestyle="none", marker="o", markersize=3.5,
                    markerfacecolor=colour, markeredgecolor="black", markeredgewidth=0.6,
                    label=label if not lines else None)
    ax.plot([data.point[i]], [data.point[j]], marker="X", markersize=8, color="white",
            markeredgecolor="black", linestyle="none", label="slice point")
    ax.set_xlim(data.xs[0], data.xs[-1])
    ax.set_ylim(data.ys[0], data.ys[-1])
    ax.set_xlabel(_axis_label(names[i], prismatic[i]))
    ax.set_ylabel(_axis_label(names[j], prismatic[j]))
    _pi_ticks(ax.xaxis, data.xs[0], data.xs[-1])
    _pi_ticks(ax.yaxis, data.ys[0], data.ys[-1])
    if legend:
        ax.legend(loc="upper right", framealpha=0.85, fontsize=legend_pt)
    return mesh


def plot_sigma_slice(data, names=None, prismatic=None, *, jacobian=None, component: int = 1,
                     axes=None, title: str = "", ax=None):
    """A heat map of sigma_min/sigma_max over one slice with the locus drawn on it.

    Parameters
    ----------
    data : Locus or SliceData
        A locus: the slice passes through a sample point of its component
        ``component``, along the two joints ``axes`` (default: the two the
        component's equations depend on most), and its components are drawn.
        Or the slice's data, from :func:`~rankloci.reporting.analysis.slice_grid`.
    names : sequence of str, optional
        For slice data: the names of all joint variables (``data.axes`` index them).
    prismatic : sequence of bool, optional
        For slice data: which variables are lengths (axis label in m) rather than
        angles (rad).
    jacobian : TaskMatrix or model, optional
        For a locus: its matrix (:func:`rankloci.jacobian`), or anything
        :func:`rankloci.load_model` takes; default: ``locus.model`` as a
        built-in model name.
    component : int
        For a locus: the 1-based component the slice passes through.
    axes : (int, int), optional
        For a locus: the indices of the joints on the x and y axes.
    title : str
    ax : matplotlib.axes.Axes, optional
        Drawn into; a new Figure otherwise.

    Returns
    -------
    matplotlib.axes.Axes

    Examples
    --------
    >>> import rankloci
    >>> from rankloci.reporting.figures import plot_sigma_slice
    >>> ax = plot_sigma_slice(rankloci.locus("planar2r"))
    >>> ax.get_xlabel(), ax.get_ylabel()
    ('q1 [rad]', 'q2 [rad]')
    """
    from ..loci import Locus

    if isinstance(data, Locus):
        data, names, prismatic = locus_slice(data, jacobian, component=component, axes=axes)
    elif names is None or prismatic is None:
        from ..errors import ArgumentError

        raise ArgumentError("names= and prismatic= are needed with slice data (a Locus needs "
                            "neither)", argument="names")
    with _rc():
        ax = _new_axes(ax, HEATMAP_SIZE)
        mesh = _draw_slice(ax, data, names, prismatic, _norm(data.ratio), "viridis")
        ax.figure.colorbar(mesh, ax=ax).set_label(_CBAR_LABEL)
        ax.set_title(title)
    return ax


def locus_slice(locus, jacobian=None, *, component: int = 1, axes=None):
    """The slice data of :func:`plot_sigma_slice` for a locus: (SliceData, names, prismatic).

    See :func:`plot_sigma_slice` for the arguments.
    """
    from ..errors import ArgumentError
    from . import analysis as A

    tm, nm, names = _locus_matrix(locus, jacobian)
    if len(names) < 2:
        raise ArgumentError("a slice needs two joint variables; the locus has one",
                            argument="locus")
    comps = A.model_components(locus)
    chosen = _component(locus, component)
    point = _sample(chosen, names)
    if axes is None:
        axes = A.slice_joints(nm, point, A.equation_weights([(component, chosen)], nm.variables))
    axes = tuple(int(a) for a in axes)
    if len(axes) != 2 or len(set(axes)) != 2 or not all(0 <= a < len(names) for a in axes):
        raise ArgumentError(f"axes= must be two different joint indices in 0..{len(names) - 1},"
                            f" got {axes!r}", argument="axes", value=axes)
    data = A.slice_grid(nm, comps, dict(tm.parameters), axes, point, through=component)
    return data, names, [v not in nm.angles for v in nm.variables]


def _with_values(tm):
    """The matrix of ``tm`` with its parameters at their values."""
    import sympy as sp

    return sp.Matrix(tm.matrix).subs(tm.parameters)


def _locus_matrix(locus, jacobian=None, *, rows=None):
    """(TaskMatrix, NumericMatrix, variable names) of the matrix a locus is of.

    ``jacobian``: the matrix (:func:`rankloci.jacobian`) or anything
    :func:`rankloci.load_model` takes; default ``locus.model`` as a built-in
    model name.  ``rows``: keep only the first ``rows`` rows (J without its
    constraint rows).
    """
    from ..api.calls import jacobian as task_jacobian
    from ..errors import ArgumentError
    from ..jacobians import TaskMatrix
    from ..numeric.equations import NumericMatrix

    tm = jacobian if isinstance(jacobian, TaskMatrix) else task_jacobian(
        locus.model if jacobian is None else jacobian)
    names = [v.name for v in tm.variables]
    if names != [str(v) for v in locus.variables]:
        raise ArgumentError(f"jacobian=: its variables {names} are not the locus's "
                            f"{[str(v) for v in locus.variables]}", argument="jacobian")
    M = _with_values(tm)
    if rows is not None:
        M = M[:rows, :]
    return tm, NumericMatrix(M, tm.variables, tm.angles), names


def _component(locus, component):
    """The component numbered ``component`` (1-based) that exists for the model's values."""
    from ..errors import ArgumentError
    from . import analysis as A

    chosen = dict(A.model_components(locus)).get(component)
    if chosen is None:
        raise ArgumentError(f"component={component!r} is not a component of the locus (1.."
                            f"{len(locus.components)})", argument="component", value=component)
    return chosen


def _sample(component, names) -> np.ndarray:
    return np.array([component.sample[n] for n in names], dtype=float)


def _is_locus(obj) -> bool:
    from ..loci import Locus

    return isinstance(obj, Locus)


def plot_augmented(plain, augmented=None, names=None, prismatic=None, *, jacobian=None,
                   component: int = 1, axes=None, title: str = "", ax=None):
    """Two heat maps on one slice and one colour scale: J and J augmented.

    Parameters
    ----------
    plain : Locus or SliceData
        The locus of an augmented matrix (``Locus.base`` is J's own locus):
        the slice passes through the sample point of its component
        ``component`` along ``axes`` (as :func:`plot_sigma_slice`); left J
        with the components of ``locus.base``, right the augmented J with
        the locus's components.  Or J's slice data, with ``augmented``,
        ``names`` and ``prismatic``.
    augmented : SliceData, optional
        For slice data: the augmented matrix's slice.
    names, prismatic : sequence, optional
        For slice data: as :func:`plot_sigma_slice`.
    jacobian : TaskMatrix or model, optional
        For a locus: the augmented matrix (``rankloci.jacobian(model,
        augment=[...])``), or a model whose file declares the constraint
        rows; default: ``locus.model`` as a built-in model name.
    component : int
        For a locus: the 1-based component of the augmented locus.
    axes : (int, int), optional
        For a locus: the joints on the x and y axes.
    title : str
    ax : pair of matplotlib.axes.Axes, optional
        Drawn into; two panels of a new Figure otherwise.

    Returns
    -------
    numpy.ndarray of two matplotlib.axes.Axes

    Examples
    --------
    >>> import rankloci
    >>> from rankloci.reporting.figures import plot_augmented
    >>> J = rankloci.jacobian("planar3r", augment=["q1 + q2 + q3"], numeric=True)
    >>> L = rankloci.locus("planar3r", augment=["q1 + q2 + q3"], numeric=True)
    >>> left, right = plot_augmented(L, jacobian=J)
    >>> left.get_title(), right.get_title()
    ('J (task rows only)', 'J augmented with the constraint rows')
    """
    from matplotlib.figure import Figure

    if _is_locus(plain):
        plain, augmented, names, prismatic = _augmented_slices(
            plain, jacobian, component=component, axes=axes)
    elif augmented is None or names is None or prismatic is None:
        from ..errors import ArgumentError

        raise ArgumentError("augmented=, names= and prismatic= are needed with slice data (a "
                            "Locus needs none of them)", argument="augmented")
    with _rc():
        if ax is None:
            fig = Figure(figsize=AUGMENTED_SIZE, layout="constrained")
            ax = fig.subplots(1, 2, sharey=True)
        norm = _norm(plain.ratio, augmented.ratio)
        _draw_slice(ax[0], plain, names, prismatic, norm, "viridis", prefix="J's component",
                    legend_pt=LABEL_PT)
        mesh = _draw_slice(ax[1], augmented, names, prismatic, norm, "viridis",
                           legend_pt=LABEL_PT)
        ax[0].set_title("J (task rows only)")
        ax[1].set_title("J augmented with the constraint rows")
        ax[1].set_ylabel("")
        fig = ax[0].figure
        fig.colorbar(mesh, ax=list(ax)).set_label(r"$\sigma_{\min}/\sigma_{\max}$ (log scale)")
        if title:
            fig.suptitle(title)
    return np.asarray(ax)


def _augmented_slices(locus, jacobian, *, component, axes):
    """(J's slice, J_aug's slice, names, prismatic) through a component of an augmented locus."""
    from ..errors import ArgumentError
    from . import analysis as A

    if locus.base is None:
        raise ArgumentError("the locus is not of an augmented matrix (Locus.base is None); "
                            "compute it with augment=", argument="locus")
    data, names, prismatic = locus_slice(locus, jacobian, component=component, axes=axes)
    tm, _, _ = _locus_matrix(locus, jacobian)
    if not tm.n_constraint_rows:
        raise ArgumentError("jacobian=: the matrix has no constraint rows; give the augmented "
                            "matrix (rankloci.jacobian(model, augment=[...]))",
                            argument="jacobian")
    _, nm_plain, _ = _locus_matrix(locus, tm, rows=tm.shape[0] - tm.n_constraint_rows)
    plain = A.slice_grid(nm_plain, A.model_components(locus.base), dict(tm.parameters),
                         data.axes, data.point, through=None)
    return plain, data, names, prismatic


def _units_math(units: str) -> str:
    """``m^3`` as matplotlib mathtext; other unit texts unchanged."""
    import re

    m = re.fullmatch(r"m\^(\d+)", units)
    return rf"$\mathrm{{m}}^{{{m.group(1)}}}$" if m else units


def plot_manipulability_path(path, *, units: str = "", jacobian=None, component: int = 1,
                             seed: int = 0, ax=None):
    """w = sqrt(det(J J^T)) along one path, with every singular crossing marked.

    Parameters
    ----------
    path : Locus or PathData
        A locus: the path is a straight joint-space line through the sample
        point of its component ``component``, across it, between two regular
        configurations (as the report draws it; :func:`manipulability_paths`).
        Or the path's data.  The parameters where the path meets the locus
        get a red marker and a dotted line each.
    units : str
        The unit of w, on the y axis (``"m^3"``).
    jacobian : TaskMatrix or model, optional
        For a locus: as :func:`plot_sigma_slice`.
    component : int
        For a locus: the 1-based component the path crosses.
    seed : int
        For a locus: the seed of the path's random direction.
    ax : matplotlib.axes.Axes, optional

    Returns
    -------
    matplotlib.axes.Axes

    Examples
    --------
    >>> import rankloci
    >>> from rankloci.reporting.figures import plot_manipulability_path
    >>> ax = plot_manipulability_path(rankloci.locus("planar2r"))
    >>> ax.get_xlabel()
    'path parameter t'
    """
    if _is_locus(path):
        path = manipulability_paths(path, jacobian, components=(component,), seed=seed)[0]
    with _rc():
        ax = _new_axes(ax, (4.0, 3.0))
        ax.plot(path.t, path.w, color="#1f77b4", linewidth=1.4)
        zeros = list(getattr(path, "zeros", ()))
        for k, t0 in enumerate(zeros):
            ax.axvline(t0, color="#d62728", linewidth=0.8, linestyle=":")
            ax.plot([t0], [0.0], marker="o", markersize=5, color="#d62728", clip_on=False,
                    zorder=5, label="singular (J loses rank)" if k == 0 else None)
        ax.set_xlim(float(path.t[0]), float(path.t[-1]))
        ax.set_ylim(bottom=0, top=max(float(np.max(path.w)), 1e-300) * 1.08)
        ax.set_title(f"through component {path.component}", fontsize=9, loc="right")
        ax.grid(True, alpha=0.3)
        ax.ticklabel_format(axis="y", style="sci", scilimits=(-2, 3))
        if units:
            ax.set_ylabel(rf"$w = \sqrt{{\det(J J^T)}}$ [{_units_math(units)}]")
        ax.set_xlabel("path parameter t")
    return ax


def manipulability_paths(locus, jacobian=None, *, components=None, seed: int = 0) -> list:
    """The report's manipulability paths of a locus: one ``PathData`` per component.

    Each is a straight joint-space path through the component's sample point,
    mostly across the component, between two regular configurations; every
    crossing of the locus on it is in ``zeros``.

    Parameters
    ----------
    locus : Locus
    jacobian : TaskMatrix or model, optional
        As :func:`plot_sigma_slice`.
    components : sequence of int, optional
        1-based components (default: every one that exists for the model's values).
    seed : int
        Seed of the random part of each direction.
    """
    from . import analysis as A

    tm, nm, names = _locus_matrix(locus, jacobian)
    chosen = ([(k, _component(locus, k)) for k in components] if components is not None
              else A.model_components(locus))
    rng = np.random.default_rng(seed)
    paths = []
    for idx, c in chosen:
        q0 = _sample(c, names)
        normals = A.normal_directions(A.component_equations(c, nm, dict(tm.parameters)), q0)
        paths.append(A.path_through(nm, q0, rng, component=idx, normals=normals))
    return paths


def plot_manipulability_paths(paths, *, units: str = "", title: str = "", jacobian=None,
                              seed: int = 0, ax=None):
    """One panel per path (each with its own w scale), in a grid of up to three columns.

    Parameters
    ----------
    paths : Locus or sequence of PathData
        A locus: one path across each of its components
        (:func:`manipulability_paths`).
    units, title : str
    jacobian : TaskMatrix or model, optional
        For a locus: as :func:`plot_sigma_slice`.
    seed : int
        For a locus: the seed of the paths' random directions.
    ax : array of matplotlib.axes.Axes, optional
        At least one per path; a new Figure otherwise.

    Returns
    -------
    numpy.ndarray of matplotlib.axes.Axes
        Every panel, flattened (the unused ones switched off).

    Examples
    --------
    >>> import rankloci
    >>> from rankloci.reporting.figures import plot_manipulability_paths
    >>> len(plot_manipulability_paths(rankloci.locus("puma560", numeric=True)))
    3
    """
    from matplotlib.figure import Figure

    if _is_locus(paths):
        paths = manipulability_paths(paths, jacobian, seed=seed)

    n = max(len(paths), 1)
    cols = min(n, 3)
    rows = -(-n // cols)
    with _rc():
        if ax is None:
            fig = Figure(figsize=PATH_SIZE, layout="constrained")
            ax = fig.subplots(rows, cols, sharex=True, squeeze=False)
        axes = np.asarray(ax).reshape(-1)
        for k, a in enumerate(axes):
            if k >= len(paths):
                a.axis("off")
                continue
            plot_manipulability_path(paths[k], units=units if k % cols == 0 else "", ax=a)
            if not (k // cols == rows - 1 or k + cols >= len(paths)):
                a.set_xlabel("")
        fig = axes[0].figure
        if any(len(getattr(p, "zeros", ())) for p in paths):
            axes[0].legend(loc="upper left", fontsize=LABEL_PT, framealpha=0.85)
        if title:
            fig.suptitle(title + "  (q(t) = q0 + t d; t = 0 on the component)")
    return axes


# --- the robot ---------------------------------------------------------------------------------

def _ellipsoid(ax, centre, Jv, size, colour):
    """The translational manipulability ellipsoid {Jv x : |x| <= 1}, scaled to ``size``."""
    U, s = principal_axes(Jv)
    top = float(s[0]) if s.size and s[0] > 0 else 1.0
    radii = np.zeros(3)
    radii[:len(s)] = s / top * size
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, 25), np.linspace(0, np.pi, 13))
    sphere = np.stack([np.cos(u) * np.sin(v), np.sin(u) * np.sin(v), np.cos(v)], axis=-1)
    basis = np.zeros((3, 3))
    basis[:U.shape[0], :U.shape[1]] = U
    if U.shape[0] < 3:
        basis[2, 2] = 1.0
    pts = centre + (sphere * radii) @ basis.T
    ax.plot_wireframe(pts[..., 0], pts[..., 1], pts[..., 2], color=colour, linewidth=0.4,
                      alpha=0.6)


#: The regular pose beside each picture of the robot: this far along the component's path.
ROBOT_REGULAR_T = 0.35


def _robot_and_q(robot, q, *, model=None, component: int = 1):
    """(RobotModel, {name: value}) for a locus's component sample or a model and q."""
    from ..api.calls import load_model
    from ..errors import ArgumentError
    from ..model import RobotModel

    if _is_locus(robot):
        locus = robot
        m = load_model(locus.model if model is None else model)
        if q is None:
            q = _component(locus, component).sample
    else:
        if model is not None:
            raise ArgumentError("model= goes with a Locus; the robot is the first argument",
                                argument="model")
        m = load_model(robot)
    if not isinstance(m, RobotModel):
        raise ArgumentError(f"a robot is needed to draw an arm, not a {type(m).__name__}",
                            argument="robot")
    names = [v.name for v in m.variables]
    if q is None:
        raise ArgumentError("q= is needed with a model: the configuration to draw", argument="q")
    if hasattr(q, "items"):
        values = {str(k): float(v) for k, v in q.items()}
        missing = [n for n in names if n not in values]
        if missing:
            raise ArgumentError(f"q=: no value for {missing[0]!r}", argument="q")
    else:
        arr = np.asarray(q, dtype=float).reshape(-1)
        if arr.shape != (len(names),):
            raise ArgumentError(f"q= must have {len(names)} values (one per joint), got "
                                f"{arr.size}", argument="q")
        values = dict(zip(names, arr.tolist()))
    if not all(np.isfinite(values[n]) for n in names):
        raise ArgumentError("q= must be finite numbers", argument="q")
    return m, values


#: Colours of the end-effector frame's x, y and z axes.
_FRAME_COLOURS = ("#d62728", "#2ca02c", "#1f77b4")


def _plot_robot_2d(pose, *, highlight, arrow, arrow_label, Jv, title, ax):
    """The arm of a planar model in its plane: links, joints, prismatic boxes, task point."""
    from matplotlib.patches import Polygon

    chain = np.asarray(pose.chain)[:, :2]
    scale = pose.scale
    ax.plot(chain[:, 0], chain[:, 1], color="#333333", linewidth=2.2, zorder=2)
    base = chain[0]
    ax.add_patch(Polygon([base + scale * np.array(x) for x in
                          ((-0.06, -0.06), (0.06, -0.06), (0.0, 0.02))],
                         closed=True, color="#555555", zorder=1))
    for k, (p, d, kind) in enumerate(zip(pose.axis_points, pose.axis_directions, pose.kinds),
                                     start=1):
        hot = k in highlight
        colour = "#d62728" if hot else "#1f77b4"
        if kind == "revolute":
            ax.plot([p[0]], [p[1]], marker="o", markersize=7 if hot else 5,
                    markerfacecolor="white", markeredgecolor=colour, zorder=3)
        else:
            pts = rectangle_along(p, d, 0.12 * scale, 0.05 * scale)
            ax.add_patch(Polygon(pts, closed=True, fill=False, edgecolor=colour, linewidth=1.2,
                                 zorder=3))
        if hot:
            ax.annotate(f"{k}", p[:2], xytext=(4, 4), textcoords="offset points",
                        color="#d62728", fontsize=LABEL_PT)
    tip = np.asarray(pose.tool)[:2]
    ax.plot([tip[0]], [tip[1]], marker="*", markersize=10, color="#ff7f0e", linestyle="none",
            label="task point", zorder=4)
    if pose.tool_frame is not None:
        for c in range(2):
            v = pose.tool_frame[:2, c] * 0.12 * scale
            ax.quiver(*tip, *v, color=_FRAME_COLOURS[c], angles="xy", scale_units="xy", scale=1,
                      width=0.004, zorder=4)
    if Jv is not None and np.size(Jv):
        U, sv = principal_axes(np.asarray(Jv, dtype=float)[:2])
        top = float(sv[0]) if sv.size and sv[0] > 0 else 1.0
        t = np.linspace(0, 2 * np.pi, 80)
        circle = np.stack([np.cos(t), np.sin(t)])
        radii = np.zeros(2)
        radii[:len(sv)] = sv[:2] / top * 0.25 * scale
        pts = tip[:, None] + U[:2, :2] @ (radii[:, None] * circle)
        ax.plot(pts[0], pts[1], color="#2ca02c", linewidth=0.8, alpha=0.8)
    a = scaled_to(np.asarray(arrow, dtype=float)[:2], 0.35 * scale) if arrow is not None \
        else None
    if a is not None:
        ax.quiver(*tip, *a, color="#9467bd", angles="xy", scale_units="xy", scale=1,
                  width=0.008, zorder=5, label=arrow_label or None)
    lo = chain.min(axis=0) - 0.3 * scale
    hi = chain.max(axis=0) + 0.3 * scale
    mid, half = (lo + hi) / 2, float(np.max(hi - lo)) / 2
    ax.set_xlim(mid[0] - half, mid[0] + half)
    ax.set_ylim(mid[1] - half, mid[1] + half)
    ax.set_aspect("equal")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.tick_params(labelsize=LABEL_PT)
    if title:
        ax.set_title(title, fontsize=10)
    ax.legend(loc="lower right", fontsize=LABEL_PT)
    return ax


def _joint_numbers(ax, labels):
    """Write each (point, joint) of ``labels`` on the 3-D ``ax``; numbers that would fall
    on one another as seen (axes through one point, axes seen end-on) are written once,
    together, at the first one's place."""
    from mpl_toolkits.mplot3d import proj3d

    if not labels:
        return
    M = ax.get_proj()
    corners = np.array(list(itertools.product(ax.get_xlim3d(), ax.get_ylim3d(),
                                              ax.get_zlim3d())))
    cx, cy, _ = proj3d.proj_transform(*corners.T, M)
    span = max(float(np.ptp(cx)), float(np.ptp(cy)))
    groups = []
    for where, k in labels:
        x, y, _ = proj3d.proj_transform(*where, M)
        near = next((g for g in groups if np.hypot(g[1][0] - x, g[1][1] - y) < 0.06 * span),
                    None)
        if near is None:
            groups.append((where, (x, y), [k]))
        else:
            near[2].append(k)
    for where, _, ks in groups:
        ax.text(*where, ", ".join(map(str, ks)), color="#d62728", fontsize=LABEL_PT)


def _clipped_to_box(ends, lo, hi):
    """The part of the segment ``ends`` (2, 3) inside the box ``lo``..``hi``, or None."""
    a, b = np.asarray(ends, dtype=float)
    t0, t1 = 0.0, 1.0
    for k in range(3):
        step = b[k] - a[k]
        if step == 0:
            if not lo[k] <= a[k] <= hi[k]:
                return None
            continue
        u, v = (lo[k] - a[k]) / step, (hi[k] - a[k]) / step
        t0, t1 = max(t0, min(u, v)), min(t1, max(u, v))
    return None if t0 >= t1 else np.array([a + t0 * (b - a), a + t1 * (b - a)])


def plot_robot(pose, q=None, *, component: int = 1, model=None, highlight=(), arrow=None,
               arrow_label="", Jv=None, title: str = "", ax=None, plane=None, lines=()):
    """The arm at one configuration in 3-D: links, joint axes, task point.

    Parameters
    ----------
    pose : Locus, model or RobotPose
        A locus: the arm at the sample point of its component ``component``
        (the robot is ``model``, default ``locus.model`` as a built-in name).
        A model (anything :func:`rankloci.load_model` takes): the arm at
        ``q``.  Or the pose from :func:`~rankloci.reporting.robot.robot_pose`.
    q : array_like or mapping, optional
        For a model: one value per joint variable, or variable name -> value.
    component : int
        For a locus: the 1-based component.
    model : optional
        For a locus: the robot it is of.
    highlight : sequence of int
        1-based joints whose axes are drawn red (the axes a reading names), and long
        when there are at most :data:`HIGHLIGHT_LONG_MAX` of them.
    arrow : array_like of 3 floats, optional
        A direction drawn as an arrow at the task point (the lost direction).
    Jv : numpy.ndarray, optional
        The translational rows of J (2 or 3 rows); its manipulability ellipsoid is
        drawn at the task point.
    ax : mpl_toolkits.mplot3d.axes3d.Axes3D, optional
    plane : int, optional
        A 1-based joint: the plane through its axis and the task point is drawn
        translucent (the plane a shoulder singularity's reading names).  3-D only.
    lines : sequence of (int, str)
        Lines a reading names: for each (1-based joint, label), the line of that joint's
        axis is drawn through the whole arm (:func:`axis_line_ends`), magenta and dash-dot,
        with the label in the legend (collinear axes: one line for the group; an axis a
        point lies on).  3-D only.

    Returns
    -------
    mpl_toolkits.mplot3d.axes3d.Axes3D

    Examples
    --------
    >>> import rankloci
    >>> from rankloci.reporting.figures import plot_robot
    >>> plot_robot(rankloci.locus("puma560", numeric=True), component=2).name
    '3d'
    >>> ax = plot_robot("planar2r", [0.3, 0.5])
    """
    from .robot import RobotPose, robot_pose

    if not isinstance(pose, RobotPose):
        robot, values = _robot_and_q(pose, q, model=model, component=component)
        pose = robot_pose(robot, values)
    planar = getattr(pose, "planar", False) and (ax is None or ax.name != "3d")
    with _rc():
        if planar:
            ax = _new_axes(ax, (5.0, 4.8))
            return _plot_robot_2d(pose, highlight=highlight, arrow=arrow,
                                  arrow_label=arrow_label, Jv=Jv, title=title, ax=ax)
        ax = _new_axes(ax, (5.0, 4.8), projection="3d")
        chain = np.asarray(pose.chain)
        scale = pose.scale
        lo = chain.min(axis=0) - 0.3 * scale
        hi = chain.max(axis=0) + 0.3 * scale
        mid, half = (lo + hi) / 2, float(np.max(hi - lo)) / 2
        # the floor under the base, and the base on it
        floor_z = float(chain[0][2])
        gx = np.array([mid[0] - half, mid[0] + half])
        gy = np.array([mid[1] - half, mid[1] + half])
        X, Y = np.meshgrid(gx, gy)
        ax.plot_surface(X, Y, np.full_like(X, floor_z), color="#dddddd", alpha=0.35,
                        linewidth=0, shade=False)
        for edge in box_edges(chain[0] - [0, 0, 0.03 * scale], [0.0, 0.0, 1.0], 0.06 * scale,
                               0.14 * scale):
            ax.plot(edge[:, 0], edge[:, 1], edge[:, 2], color="#555555", linewidth=1.2)
        ax.plot(chain[:, 0], chain[:, 1], chain[:, 2], color="#333333", linewidth=2.2,
                marker="o", markersize=2.5)
        hot_labels = []
        long_axes = len(highlight) <= HIGHLIGHT_LONG_MAX
        for k, (p, d, kind) in enumerate(zip(pose.axis_points, pose.axis_directions,
                                             pose.kinds), start=1):
            hot = k in highlight
            colour = "#d62728" if hot else "#1f77b4"
            half_axis = (0.45 if hot and long_axes else 0.12) * scale
            seg = np.array([p - half_axis * d, p + half_axis * d])
            ax.plot(seg[:, 0], seg[:, 1], seg[:, 2], color=colour,
                    linewidth=2.0 if hot else 1.0, linestyle="-" if kind == "revolute" else "--")
            if kind == "prismatic":
                for edge in box_edges(p, d, 0.14 * scale, 0.05 * scale):
                    ax.plot(edge[:, 0], edge[:, 1], edge[:, 2], color=colour, linewidth=1.0)
            if hot:
                hot_labels.append((p + half_axis * d, k))
        tip = np.asarray(pose.tool)
        box = (mid - half, mid + half)
        for joint, label in lines:
            ends = _clipped_to_box(axis_line_ends(pose, joint), *box)
            if ends is None:
                continue
            ax.plot(ends[:, 0], ends[:, 1], ends[:, 2], color=READING_LINE_COLOUR,
                    linewidth=3.5, alpha=0.6, linestyle="-.", label=label, zorder=5)
        if plane is not None:
            corners = plane_through_axis(pose, plane)
            if corners is not None:
                from mpl_toolkits.mplot3d.art3d import Poly3DCollection

                ax.add_collection3d(Poly3DCollection([corners], facecolor="#d62728", alpha=0.15,
                                                     edgecolor="#d62728", linewidth=0.6,
                                                     label=f"plane through axis {plane}"))
        ax.plot([tip[0]], [tip[1]], [tip[2]], marker="*", markersize=9, color="#ff7f0e",
                linestyle="none", label="task point")
        if getattr(pose, "tool_frame", None) is not None:
            for c in range(3):
                v = pose.tool_frame[:, c] * 0.15 * scale
                ax.quiver(*tip, *v, color=_FRAME_COLOURS[c], linewidth=1.0,
                          arrow_length_ratio=0.2)
        if Jv is not None and np.size(Jv):
            _ellipsoid(ax, tip, np.asarray(Jv, dtype=float), 0.25 * scale, "#2ca02c")
        a = scaled_to(arrow, 0.35 * scale) if arrow is not None else None
        if a is not None:
            ax.quiver(*tip, *a, color="#9467bd", linewidth=1.8, arrow_length_ratio=0.25,
                      label=arrow_label or None)
        ax.set_xlim(mid[0] - half, mid[0] + half)
        ax.set_ylim(mid[1] - half, mid[1] + half)
        ax.set_zlim(mid[2] - half, mid[2] + half)
        # constrained layout does not see the labels at the cube's corners: a smaller cube
        # keeps them inside the figure
        ax.set_box_aspect((1, 1, 1), zoom=ROBOT_CUBE_ZOOM)
        ax.set_xlabel("x")
        ax.set_ylabel("y")
        ax.set_zlabel("z")
        ax.tick_params(labelsize=LABEL_PT)
        ax.view_init(elev=22, azim=-60)
        _joint_numbers(ax, hot_labels)
        if title:
            ax.set_title(title, fontsize=10)
        ax.legend(loc="upper left", fontsize=LABEL_PT,
                  ncols=2 if len(ax.get_legend_handles_labels()[1]) > 2 else 1)
    return ax


def robot_figure(singular, regular=None, *, component: int = 1, model=None, seed: int = 0,
                 highlight=(), arrow=None, arrow_label="", Jv_singular=None, Jv_regular=None,
                 title: str = "", ax=None, plane=None, lines=()):
    """Two 3-D panels: the arm at a component's sample point and at a nearby regular pose.

    Parameters
    ----------
    singular : Locus or RobotPose
        A locus: the arm at the sample point of its component ``component``
        and at a regular pose across it, as the report draws them: a step
        along the report's manipulability path (:func:`manipulability_paths`, ``seed``) away;
        the robot is ``model`` (default ``locus.model`` as a built-in name).
        Or the singular pose, with ``regular``.
    regular : RobotPose, optional
    highlight, arrow, arrow_label, Jv_singular, Jv_regular, title
        As :func:`plot_robot`.
    plane, lines : optional
        As :func:`plot_robot`, on the singular panel.
    ax : pair of 3-D axes, optional
        A new Figure's otherwise.

    Returns
    -------
    numpy.ndarray of two 3-D Axes

    Examples
    --------
    >>> import rankloci
    >>> from rankloci.reporting.figures import robot_figure
    >>> [a.get_title() for a in robot_figure(rankloci.locus("planar2r"))]
    ['singular: the sample point', 'regular: a nearby configuration']
    """
    from matplotlib.figure import Figure

    if _is_locus(singular):
        from .robot import robot_pose

        locus = singular
        robot, values = _robot_and_q(locus, None, model=model, component=component)
        path = manipulability_paths(locus, robot, components=(component,), seed=seed)[0]
        names = [v.name for v in robot.variables]
        q1 = path.point + ROBOT_REGULAR_T * path.step
        singular = robot_pose(robot, values)
        regular = robot_pose(robot, dict(zip(names, q1.tolist())))
    elif regular is None:
        from ..errors import ArgumentError

        raise ArgumentError("regular= is needed with a pose (a Locus needs none)",
                            argument="regular")
    with _rc():
        flat = getattr(singular, "planar", False) and getattr(regular, "planar", False)
        if ax is None:
            fig = Figure(figsize=ROBOT_SIZE, layout="constrained")
            ax = [fig.add_subplot(1, 2, 1, projection=None if flat else "3d"),
                  fig.add_subplot(1, 2, 2, projection=None if flat else "3d")]
        a, b = ax
        plot_robot(singular, highlight=highlight, arrow=arrow, arrow_label=arrow_label,
                   Jv=Jv_singular, title="singular: the sample point", ax=a, plane=plane,
                   lines=lines)
        plot_robot(regular, highlight=highlight, Jv=Jv_regular,
                   title="regular: a nearby configuration", ax=b)
        if not flat and a.get_legend() is not None:
            # one legend for both 3-D panels, below them: in a panel, a legend of several
            # entries would cover the arm or widen its panel at the other's expense
            handles, labels = a.get_legend_handles_labels()
            for x in (a, b):
                if x.get_legend() is not None:
                    x.get_legend().remove()
            a.figure.legend(handles, labels, loc="outside lower center", fontsize=LABEL_PT,
                            ncols=min(len(labels), 3), frameon=False)
        if title:
            a.figure.suptitle(title)
    return np.asarray([a, b], dtype=object)


# --- the branch tree ---------------------------------------------------------------------------

_ROLE_STYLE = {
    "component": 'style="filled,rounded", fillcolor="#c8f0c8"',
    "leaf": 'style="filled,rounded", fillcolor="#eeeeee"',
    "inner": 'style="rounded"',
    "summary": 'style="dashed,rounded", fontcolor="#444444"',
}


def tree_dot_source(summary) -> str:
    """Graphviz source of a :class:`~rankloci.reporting.tree_summary.TreeSummary`, top-down."""
    def esc(s):
        return str(s).replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n")

    ids = {n: f"n{k}" for k, n in enumerate(summary.graph.nodes)}
    out = ["digraph branch_tree {",
           '  graph [rankdir=TB, nodesep=0.15, ranksep=0.3, margin=0.05];',
           '  node [shape=box, fontname="Helvetica", fontsize=12, margin="0.08,0.04"];',
           '  edge [arrowsize=0.6];']
    for n, d in summary.graph.nodes(data=True):
        out.append(f'  {ids[n]} [label="{esc(d["label"])}", {_ROLE_STYLE[d["role"]]}];')
    for a, b in summary.graph.edges():
        out.append(f"  {ids[a]} -> {ids[b]};")
    out.append("}")
    return "\n".join(out)


def _tree_layout(G):
    """Leaves left to right in depth-first order, parents centred over their children."""
    roots = sorted((n for n in G if G.in_degree(n) == 0), key=str)
    pos, next_x = {}, [0.0]

    def place(n, depth):
        kids = sorted(G.successors(n), key=lambda c: (isinstance(c, str), str(c).zfill(8)))
        if not kids:
            pos[n] = (next_x[0], -depth)
            next_x[0] += 1.0
            return
        for c in kids:
            place(c, depth + 1)
        pos[n] = (sum(pos[c][0] for c in kids) / len(kids), -depth)

    for r in roots:
        place(r, 0)
    return pos


def plot_tree(summary, ax=None):
    """The cut-down branch tree drawn top-down with matplotlib (no graphviz needed).

    Parameters
    ----------
    summary : Locus or TreeSummary
        A locus (its branch tree ``Locus.tree``, cut down by
        :func:`~rankloci.reporting.tree_summary.tree_summary`), or the cut-down tree.
    ax : matplotlib.axes.Axes, optional
        Drawn into; a new Figure otherwise.

    Returns
    -------
    matplotlib.axes.Axes

    Examples
    --------
    >>> import rankloci
    >>> from rankloci.reporting.figures import plot_tree
    >>> L = rankloci.locus("planar2r")
    >>> ax = plot_tree(L)
    >>> len(ax.texts) == L.tree.number_of_nodes(), ax.axison    # a small tree is drawn whole
    (True, False)
    """
    from ..loci import Locus

    if isinstance(summary, Locus):
        from .tree_summary import tree_summary

        if summary.tree is None:
            from ..errors import ArgumentError

            raise ArgumentError("the locus has no branch tree (one read from JSON has none)",
                                argument="summary")
        summary = tree_summary(summary.tree)
    G = summary.graph
    pos = _tree_layout(G)
    width = max(x for x, _ in pos.values()) + 1 if pos else 1
    depth = -min(y for _, y in pos.values()) + 1 if pos else 1
    colours = {"component": "#c8f0c8", "leaf": "#eeeeee", "inner": "white", "summary": "#f8f8f8"}
    with _rc():
        ax = _new_axes(ax, (min(max(6.0, 1.9 * width), 16.0), min(max(3.0, 1.2 * depth), 22.0)))
        for a, b in G.edges():
            ax.plot([pos[a][0], pos[b][0]], [pos[a][1], pos[b][1]], color="#888888",
                    linewidth=0.8, zorder=1)
        for n, d in G.nodes(data=True):
            x, y = pos[n]
            ax.text(x, y, d["label"], ha="center", va="center", fontsize=8, zorder=2,
                    bbox=dict(boxstyle="round,pad=0.3", fc=colours[d["role"]],
                              ec="#333333", linestyle="--" if d["role"] == "summary" else "-"))
        ax.set_xlim(-0.7, width - 0.3)
        ax.set_ylim(-depth + 0.4, 0.6)
        ax.axis("off")
    return ax


# --- PNG bytes for the report ------------------------------------------------------------------

def heatmap_png(data, names, prismatic, *, title: str) -> bytes:
    """:func:`plot_sigma_slice` as PNG bytes."""
    return figure_png(plot_sigma_slice(data, names, prismatic, title=title).figure)


def augmented_png(plain, augmented, names, prismatic, *, title: str) -> bytes:
    """:func:`plot_augmented` as PNG bytes."""
    return figure_png(plot_augmented(plain, augmented, names, prismatic, title=title)[0].figure)


def manipulability_png(paths, *, units: str, title: str) -> bytes:
    """:func:`plot_manipulability_paths` as PNG bytes."""
    return figure_png(plot_manipulability_paths(paths, units=units, title=title)[0].figure)


def robot_png(singular, regular, **kwargs) -> bytes:
    """:func:`robot_figure` as PNG bytes."""
    return figure_png(robot_figure(singular, regular, **kwargs)[0].figure)


def tree_png(summary, *, dot: str | None = None) -> bytes:
    """The branch tree as a PNG: with graphviz ``dot`` when its path is given, else matplotlib."""
    if dot:
        try:
            run = subprocess.run([dot, "-Tpng", "-Gdpi=110"],
                                 input=tree_dot_source(summary).encode(),
                                 capture_output=True, timeout=120, check=True)
            if run.stdout.startswith(b"\x89PNG"):
                return run.stdout
        except (OSError, subprocess.SubprocessError):
            pass
    return figure_png(plot_tree(summary).figure)
