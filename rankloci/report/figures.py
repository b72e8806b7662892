"""The report's figures as PNG bytes (matplotlib with the Agg backend; graphviz for trees).

Every function takes the data of :mod:`rankloci.report.analysis` and returns
the bytes of a PNG file; nothing is written here.  The PNGs carry no
timestamp or software version, so equal data give equal bytes.  matplotlib
is imported inside the functions (the command line's ``--help`` stays fast).
"""

from __future__ import annotations

import io
import subprocess

import numpy as np

__all__ = ["heatmap_png", "augmented_png", "manipulability_png", "tree_png", "tree_dot_source",
           "HEATMAP_SIZE", "PATH_SIZE", "AUGMENTED_SIZE", "DPI"]

DPI = 100
#: Figure sizes in inches; at DPI they give the pixel sizes the tests expect.
HEATMAP_SIZE = (7.0, 5.2)
AUGMENTED_SIZE = (11.0, 4.6)
PATH_SIZE = (8.0, 4.8)

#: Locus curves: colours that stand out on viridis, with a dark outline.
_CURVE_COLOURS = ("#ff2d55", "#ffffff", "#00e5ff", "#ffb000", "#ff66ff", "#7CFC00",
                  "#ff8c00", "#c0c0c0", "#1e90ff", "#ffd700")
_LINESTYLES = ("-", "--", "-.", ":")


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _png(fig) -> bytes:
    plt = _plt()
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=DPI, metadata={"Software": None})
    plt.close(fig)
    return buf.getvalue()


def _rc():
    import matplotlib

    return matplotlib.rc_context({"font.size": 10, "axes.titlesize": 10, "legend.fontsize": 8,
                                  "font.family": "DejaVu Sans", "svg.hashsalt": "rankloci",
                                  "path.simplify": True})


def _pi_ticks(axis, lo, hi):
    """Ticks at multiples of pi/2 labelled in pi, when the range is [-pi, pi]."""
    if abs(lo + np.pi) < 1e-9 and abs(hi - np.pi) < 1e-9:
        axis.set_ticks(np.pi * np.array([-1, -0.5, 0, 0.5, 1]))
        axis.set_ticklabels([r"$-\pi$", r"$-\pi/2$", "0", r"$\pi/2$", r"$\pi$"])


def _axis_label(name: str, prismatic: bool) -> str:
    return f"{name} [m]" if prismatic else f"{name} [rad]"


def _draw_slice(ax, data, names, prismatic, norm, cmap, *, legend=True, prefix="component"):
    import matplotlib.patheffects as pe

    i, j = data.axes
    hx = (data.xs[-1] - data.xs[0]) / max(len(data.xs) - 1, 1) / 2
    hy = (data.ys[-1] - data.ys[0]) / max(len(data.ys) - 1, 1) / 2
    mesh = ax.imshow(np.maximum(data.ratio, norm.vmin), origin="lower", aspect="auto",
                     extent=(data.xs[0] - hx, data.xs[-1] + hx, data.ys[0] - hy, data.ys[-1] + hy),
                     norm=norm, cmap=cmap, interpolation="nearest")
    outline = [pe.Stroke(linewidth=3.2, foreground="black"), pe.Normal()]
    for n, (idx, lines, pts) in enumerate(data.curves):
        colour = _CURVE_COLOURS[(idx - 1) % len(_CURVE_COLOURS)]
        style = _LINESTYLES[((idx - 1) // len(_CURVE_COLOURS)) % len(_LINESTYLES)]
        label = f"{prefix} {idx}"
        for k, seg in enumerate(lines):
            ax.plot(seg[:, 0], seg[:, 1], color=colour, linestyle=style, linewidth=1.6,
                    path_effects=outline, label=label if k == 0 else None)
        if len(pts):
            ax.plot(pts[:, 0], pts[:, 1], linestyle="none", marker="o", markersize=6,
                    markerfacecolor=colour, markeredgecolor="black",
                    label=label if not lines else None)
    ax.plot([data.point[i]], [data.point[j]], marker="X", markersize=9, color="white",
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


def _norm(*ratios):
    from matplotlib.colors import LogNorm

    lo = min(float(np.min(r)) for r in ratios)
    hi = max(float(np.max(r)) for r in ratios)
    hi = max(hi, 1e-12)
    lo = min(max(lo, 1e-6, hi * 1e-8), hi / 10)
    return LogNorm(vmin=lo, vmax=hi)


_CBAR_LABEL = r"$\sigma_{\min}/\sigma_{\max}$ of J (log scale)"


def heatmap_png(data, names, prismatic, *, title: str) -> bytes:
    """A heat map of sigma_min/sigma_max over one slice with the locus drawn on it.

    Parameters
    ----------
    data : SliceData
    names : sequence of str
        Names of all joint variables (``data.axes`` index them).
    prismatic : sequence of bool
        Which variables are lengths (axis label in m) rather than angles (rad).
    title : str
    """
    plt = _plt()
    with _rc():
        fig, ax = plt.subplots(figsize=HEATMAP_SIZE, layout="constrained")
        norm = _norm(data.ratio)
        mesh = _draw_slice(ax, data, names, prismatic, norm, "viridis")
        cbar = fig.colorbar(mesh, ax=ax)
        cbar.set_label(_CBAR_LABEL)
        ax.set_title(title)
        return _png(fig)


def augmented_png(plain, augmented, names, prismatic, *, title: str) -> bytes:
    """Two heat maps side by side on one slice and one colour scale: J and J augmented."""
    plt = _plt()
    with _rc():
        fig, axes = plt.subplots(1, 2, figsize=AUGMENTED_SIZE, layout="constrained",
                                 sharey=True)
        norm = _norm(plain.ratio, augmented.ratio)
        _draw_slice(axes[0], plain, names, prismatic, norm, "viridis", prefix="J's component")
        mesh = _draw_slice(axes[1], augmented, names, prismatic, norm, "viridis")
        axes[0].set_title("J (task rows only)")
        axes[1].set_title("J augmented with the constraint rows")
        axes[1].set_ylabel("")
        cbar = fig.colorbar(mesh, ax=list(axes))
        cbar.set_label(r"$\sigma_{\min}/\sigma_{\max}$ (log scale)")
        fig.suptitle(title)
        return _png(fig)


def _units_math(units: str) -> str:
    """``m^3`` as matplotlib mathtext; other unit texts unchanged."""
    import re

    m = re.fullmatch(r"m\^(\d+)", units)
    return rf"$\mathrm{{m}}^{{{m.group(1)}}}$" if m else units


def manipulability_png(paths, *, units: str, title: str) -> bytes:
    """w = sqrt(det(J J^T)) along straight paths, each crossing one component at t = 0.

    One panel per path (each with its own w scale), in a grid of up to three columns.
    """
    plt = _plt()
    n = max(len(paths), 1)
    cols = min(n, 3)
    rows = -(-n // cols)
    with _rc():
        fig, axes = plt.subplots(rows, cols, figsize=PATH_SIZE, layout="constrained",
                                 sharex=True, squeeze=False)
        for k, ax in enumerate(axes.flat):
            if k >= len(paths):
                ax.axis("off")
                continue
            p = paths[k]
            ax.plot(p.t, p.w, color="#1f77b4", linewidth=1.4)
            ax.axvline(0.0, color="black", linewidth=0.8, linestyle=":")
            ax.set_xlim(-1, 1)
            ax.set_ylim(bottom=0, top=max(float(np.max(p.w)), 1e-300) * 1.08)
            ax.set_title(f"through component {p.component}", fontsize=9, loc="right")
            ax.grid(True, alpha=0.3)
            ax.ticklabel_format(axis="y", style="sci", scilimits=(-2, 3))
            if k % cols == 0:
                ax.set_ylabel(rf"$w = \sqrt{{\det(J J^T)}}$ [{_units_math(units)}]")
            if k // cols == rows - 1 or k + cols >= len(paths):
                ax.set_xlabel("path parameter t")
        fig.suptitle(title + "  (q(t) = q0 + t d; t = 0 on the component)")
        return _png(fig)


# --- the branch tree ---------------------------------------------------------------------------

_ROLE_STYLE = {
    "component": 'style="filled,rounded", fillcolor="#c8f0c8"',
    "leaf": 'style="filled,rounded", fillcolor="#eeeeee"',
    "inner": 'style="rounded"',
    "summary": 'style="dashed,rounded", fontcolor="#444444"',
}


def tree_dot_source(summary) -> str:
    """Graphviz source of a :class:`~rankloci.report.tree_summary.TreeSummary`."""
    def esc(s):
        return str(s).replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n")

    ids = {n: f"n{k}" for k, n in enumerate(summary.graph.nodes)}
    leaves = sum(1 for n in summary.graph if summary.graph.out_degree(n) == 0)
    rankdir = "TB" if leaves <= 10 else "LR"
    out = ["digraph branch_tree {",
           f'  graph [rankdir={rankdir}, nodesep=0.12, ranksep=0.3, size="15,20", margin=0.1];',
           '  node [shape=box, fontname="Helvetica", fontsize=10, margin="0.06,0.03"];',
           '  edge [arrowsize=0.6];']
    for n, d in summary.graph.nodes(data=True):
        out.append(f'  {ids[n]} [label="{esc(d["label"])}", {_ROLE_STYLE[d["role"]]}];')
    for a, b in summary.graph.edges():
        out.append(f"  {ids[a]} -> {ids[b]};")
    out.append("}")
    return "\n".join(out)


def tree_png(summary, *, dot: str | None = None) -> bytes:
    """The branch tree as a PNG: with graphviz ``dot`` when its path is given, else matplotlib."""
    if dot:
        try:
            run = subprocess.run([dot, "-Tpng", "-Gdpi=96"], input=tree_dot_source(summary).encode(),
                                 capture_output=True, timeout=120, check=True)
            if run.stdout.startswith(b"\x89PNG"):
                return run.stdout
        except (OSError, subprocess.SubprocessError):
            pass
    return _tree_png_matplotlib(summary)


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


def _tree_png_matplotlib(summary) -> bytes:
    plt = _plt()
    G = summary.graph
    pos = _tree_layout(G)
    width = max(x for x, _ in pos.values()) + 1 if pos else 1
    depth = -min(y for _, y in pos.values()) + 1 if pos else 1
    colours = {"component": "#c8f0c8", "leaf": "#eeeeee", "inner": "white", "summary": "#f8f8f8"}
    with _rc():
        fig, ax = plt.subplots(figsize=(min(max(6.0, 2.0 * width), 30.0),
                                        min(max(3.0, 1.1 * depth), 30.0)))
        for a, b in G.edges():
            ax.plot([pos[a][0], pos[b][0]], [pos[a][1], pos[b][1]], color="#888888",
                    linewidth=0.8, zorder=1)
        for n, d in G.nodes(data=True):
            x, y = pos[n]
            ax.text(x, y, d["label"], ha="center", va="center", fontsize=6.5, zorder=2,
                    bbox=dict(boxstyle="round,pad=0.3", fc=colours[d["role"]],
                              ec="#333333", linestyle="--" if d["role"] == "summary" else "-"))
        ax.set_xlim(-0.7, width - 0.3)
        ax.set_ylim(-depth + 0.4, 0.6)
        ax.axis("off")
        fig.tight_layout()
        return _png(fig)
