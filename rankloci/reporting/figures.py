"""The report's figures as matplotlib Figures: a plotting API, and PNG bytes for the report.

Every ``plot_*`` function draws into ``ax`` when given (a 3-D axes for
:func:`plot_robot`) and otherwise into a new :class:`matplotlib.figure.Figure`,
which it returns.  No backend is chosen here (a Figure made without pyplot
saves under any backend); :func:`figure_png` turns a Figure into PNG bytes
without a timestamp or software version, so equal data give equal bytes.
The ``*_png`` functions are what the report uses.  matplotlib is imported
inside the functions (the command line's ``--help`` stays fast).
"""

from __future__ import annotations

import io
import subprocess

import numpy as np

__all__ = ["plot_sigma_slice", "locus_slice", "plot_augmented", "plot_manipulability_path",
           "plot_manipulability_paths", "plot_tree", "plot_robot", "robot_figure", "figure_png",
           "heatmap_png", "augmented_png", "manipulability_png", "tree_png", "robot_png",
           "tree_dot_source", "HEATMAP_SIZE", "PATH_SIZE", "AUGMENTED_SIZE", "ROBOT_SIZE", "DPI"]

DPI = 100
#: Figure sizes in inches; at DPI they give the pixel sizes the tests expect.
HEATMAP_SIZE = (7.0, 5.2)
AUGMENTED_SIZE = (11.0, 4.6)
PATH_SIZE = (8.0, 4.8)
ROBOT_SIZE = (10.0, 4.8)

#: Locus curves: colours that stand out on viridis, with a dark outline.
_CURVE_COLOURS = ("#ff2d55", "#ffffff", "#00e5ff", "#ffb000", "#ff66ff", "#7CFC00",
                  "#ff8c00", "#c0c0c0", "#1e90ff", "#ffd700")
_LINESTYLES = ("-", "--", "-.", ":")

#: Width (points) of a locus line on a heat map; its dark edge is half a point wider.
CURVE_WIDTH = 0.6


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


def _draw_slice(ax, data, names, prismatic, norm, cmap, *, legend=True, prefix="component"):
    import matplotlib.patheffects as pe

    i, j = data.axes
    hx = (data.xs[-1] - data.xs[0]) / max(len(data.xs) - 1, 1) / 2
    hy = (data.ys[-1] - data.ys[0]) / max(len(data.ys) - 1, 1) / 2
    mesh = ax.imshow(np.maximum(data.ratio, norm.vmin), origin="lower", aspect="auto",
                     extent=(data.xs[0] - hx, data.xs[-1] + hx, data.ys[0] - hy, data.ys[-1] + hy),
                     norm=norm, cmap=cmap, interpolation="nearest")
    # thin lines with a hairline dark edge, narrower than the valley of the ratio they mark;
    # each component differs from the others in colour and in dash pattern (told apart in grey)
    outline = [pe.Stroke(linewidth=CURVE_WIDTH + 0.5, foreground="black"), pe.Normal()]
    for idx, lines, pts in data.curves:
        colour = _CURVE_COLOURS[(idx - 1) % len(_CURVE_COLOURS)]
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
        ax.legend(loc="upper right", framealpha=0.85)
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
    from ..api.calls import jacobian as task_jacobian
    from ..errors import ArgumentError
    from ..jacobians import TaskMatrix
    from ..numeric.equations import NumericMatrix
    from . import analysis as A

    tm = jacobian if isinstance(jacobian, TaskMatrix) else task_jacobian(
        locus.model if jacobian is None else jacobian)
    names = [v.name for v in tm.variables]
    if names != [str(v) for v in locus.variables]:
        raise ArgumentError(f"jacobian=: its variables {names} are not the locus's "
                            f"{[str(v) for v in locus.variables]}", argument="jacobian")
    if len(names) < 2:
        raise ArgumentError("a slice needs two joint variables; the locus has one",
                            argument="locus")
    comps = A.model_components(locus)
    chosen = dict(comps).get(component)
    if chosen is None:
        raise ArgumentError(f"component={component!r} is not a component of the locus (1.."
                            f"{len(locus.components)})", argument="component", value=component)
    nm = NumericMatrix(_with_values(tm), tm.variables, tm.angles)
    point = np.array([chosen.sample[n] for n in names], dtype=float)
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


def plot_augmented(plain, augmented, names, prismatic, *, title: str = "", ax=None):
    """Two heat maps on one slice and one colour scale: J and J augmented.

    ``ax`` is a pair of axes, or None for a new Figure.
    """
    from matplotlib.figure import Figure

    with _rc():
        if ax is None:
            fig = Figure(figsize=AUGMENTED_SIZE, layout="constrained")
            ax = fig.subplots(1, 2, sharey=True)
        norm = _norm(plain.ratio, augmented.ratio)
        _draw_slice(ax[0], plain, names, prismatic, norm, "viridis", prefix="J's component")
        mesh = _draw_slice(ax[1], augmented, names, prismatic, norm, "viridis")
        ax[0].set_title("J (task rows only)")
        ax[1].set_title("J augmented with the constraint rows")
        ax[1].set_ylabel("")
        fig = ax[0].figure
        fig.colorbar(mesh, ax=list(ax)).set_label(r"$\sigma_{\min}/\sigma_{\max}$ (log scale)")
        if title:
            fig.suptitle(title)
    return fig


def _units_math(units: str) -> str:
    """``m^3`` as matplotlib mathtext; other unit texts unchanged."""
    import re

    m = re.fullmatch(r"m\^(\d+)", units)
    return rf"$\mathrm{{m}}^{{{m.group(1)}}}$" if m else units


def plot_manipulability_path(path, *, units: str = "", ax=None):
    """w = sqrt(det(J J^T)) along one path, with every singular crossing marked.

    ``path`` is a :class:`~rankloci.reporting.analysis.PathData`; its ``zeros``
    (the parameters where the path meets the locus) get a red marker and a
    dotted line each.
    """
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
    return ax.figure


def plot_manipulability_paths(paths, *, units: str, title: str = "", ax=None):
    """One panel per path (each with its own w scale), in a grid of up to three columns.

    ``ax``: an array of at least ``len(paths)`` axes, or None for a new Figure.
    """
    from matplotlib.figure import Figure

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
            axes[0].legend(loc="upper left", fontsize=7, framealpha=0.85)
        if title:
            fig.suptitle(title + "  (q(t) = q0 + t d; t = 0 on the component)")
    return fig


# --- the robot ---------------------------------------------------------------------------------

def _ellipsoid(ax, centre, Jv, size, colour):
    """The translational manipulability ellipsoid {Jv x : |x| <= 1}, scaled to ``size``."""
    U, s, _ = np.linalg.svd(Jv)
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


def plot_robot(pose, *, highlight=(), arrow=None, arrow_label="", Jv=None, title: str = "",
               ax=None):
    """The arm at one configuration in 3-D: links, joint axes, task point.

    Parameters
    ----------
    pose : RobotPose
        From :func:`~rankloci.reporting.robot.robot_pose`.
    highlight : sequence of int
        1-based joints whose axes are drawn long and red (the axes a reading names).
    arrow : array_like of 3 floats, optional
        A direction drawn as an arrow at the task point (the lost direction).
    Jv : numpy.ndarray, optional
        The translational rows of J (2 or 3 rows); its manipulability ellipsoid is
        drawn at the task point.
    ax : mpl_toolkits.mplot3d.axes3d.Axes3D, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    with _rc():
        ax = _new_axes(ax, (5.0, 4.8), projection="3d")
        chain = np.asarray(pose.chain)
        scale = pose.scale
        ax.plot(chain[:, 0], chain[:, 1], chain[:, 2], color="#333333", linewidth=2.2,
                marker="o", markersize=2.5)
        for k, (p, d, kind) in enumerate(zip(pose.axis_points, pose.axis_directions,
                                             pose.kinds), start=1):
            hot = k in highlight
            half = (0.45 if hot else 0.12) * scale
            seg = np.array([p - half * d, p + half * d])
            ax.plot(seg[:, 0], seg[:, 1], seg[:, 2], color="#d62728" if hot else "#1f77b4",
                    linewidth=2.0 if hot else 1.0, linestyle="-" if kind == "revolute" else "--")
            if hot:
                ax.text(*(p + half * d), f"{k}", color="#d62728", fontsize=8)
        tip = np.asarray(pose.tool)
        ax.plot([tip[0]], [tip[1]], [tip[2]], marker="*", markersize=9, color="#ff7f0e",
                linestyle="none", label="task point")
        if Jv is not None and np.size(Jv):
            _ellipsoid(ax, tip, np.asarray(Jv, dtype=float), 0.25 * scale, "#2ca02c")
        if arrow is not None and np.linalg.norm(arrow) > 0:
            a = np.asarray(arrow, dtype=float)
            a = a / np.linalg.norm(a) * 0.35 * scale
            ax.quiver(*tip, *a, color="#9467bd", linewidth=1.8, arrow_length_ratio=0.25,
                      label=arrow_label or None)
        lo = chain.min(axis=0) - 0.3 * scale
        hi = chain.max(axis=0) + 0.3 * scale
        mid, half = (lo + hi) / 2, float(np.max(hi - lo)) / 2
        ax.set_xlim(mid[0] - half, mid[0] + half)
        ax.set_ylim(mid[1] - half, mid[1] + half)
        ax.set_zlim(mid[2] - half, mid[2] + half)
        ax.set_box_aspect((1, 1, 1))
        ax.set_xlabel("x")
        ax.set_ylabel("y")
        ax.set_zlabel("z")
        ax.tick_params(labelsize=7)
        ax.view_init(elev=22, azim=-60)
        if title:
            ax.set_title(title, fontsize=9)
        ax.legend(loc="upper left", fontsize=7)
    return ax.figure


def robot_figure(singular, regular, *, highlight=(), arrow=None, arrow_label="",
                 Jv_singular=None, Jv_regular=None, title: str = ""):
    """Two 3-D panels: the arm at a component's sample point and at a nearby regular pose."""
    from matplotlib.figure import Figure

    with _rc():
        fig = Figure(figsize=ROBOT_SIZE, layout="constrained")
        a = fig.add_subplot(1, 2, 1, projection="3d")
        b = fig.add_subplot(1, 2, 2, projection="3d")
        plot_robot(singular, highlight=highlight, arrow=arrow, arrow_label=arrow_label,
                   Jv=Jv_singular, title="singular: the sample point", ax=a)
        plot_robot(regular, highlight=highlight, Jv=Jv_regular,
                   title="regular: a nearby configuration", ax=b)
        if title:
            fig.suptitle(title)
    return fig


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
    return figure_png(plot_augmented(plain, augmented, names, prismatic, title=title))


def manipulability_png(paths, *, units: str, title: str) -> bytes:
    """:func:`plot_manipulability_paths` as PNG bytes."""
    return figure_png(plot_manipulability_paths(paths, units=units, title=title))


def robot_png(singular, regular, **kwargs) -> bytes:
    """:func:`robot_figure` as PNG bytes."""
    return figure_png(robot_figure(singular, regular, **kwargs))


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
