"""Figures of joint rates along a path and of manipulability ellipsoids and polytopes.

Every function draws into ``ax`` when given (a 3-D axes for a 3-D polytope)
and otherwise into a new :class:`matplotlib.figure.Figure`, which it returns.
No backend is chosen here: a Figure made without pyplot can be saved with
``fig.savefig`` under any backend.
"""

from __future__ import annotations

import numpy as np

__all__ = ["plot_joint_rates", "plot_indices", "plot_distance", "path_figure",
           "plot_manipulability"]


def _axes(ax, projection=None):
    if ax is not None:
        return ax
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.4, 4.8) if projection else (6.4, 3.2), layout="constrained")
    return fig.add_subplot(projection=projection)


def plot_joint_rates(path, ax=None):
    """The applied joint rates against time, one line per joint."""
    ax = _axes(ax)
    for j in range(path.rates.shape[1]):
        ax.plot(path.t, path.rates[:, j], label=f"q{j + 1}")
    ax.set_xlabel("t")
    ax.set_ylabel("joint rate")
    names = {"2": "minimum 2-norm", "inf": "minimum infinity-norm", "mixed": "mixed"}
    ax.set_title(f"joint rates ({names[path.norm]})")
    ax.legend(fontsize="small", ncols=min(4, path.rates.shape[1]))
    return ax.figure


def plot_indices(path, ax=None):
    """The discontinuity indices, the mixing ratio and sigma_min/sigma_max against time."""
    ax = _axes(ax)
    ax.plot(path.t, path.index, label="discontinuity index")
    ax.plot(path.t, path.minor_index, label="index with J (0 on the locus)")
    ax.plot(path.t, path.subspace_index, "-.", lw=0.8, label="Gravagne's index (every face)")
    ax.plot(path.t, path.mixing, "--", label="mixing ratio r")
    ax.plot(path.t, path.sigma_ratio, ":", label="sigma_min/sigma_max")
    ax.set_xlabel("t")
    ax.set_ylim(bottom=0)
    ax.legend(fontsize="small")
    return ax.figure


def plot_distance(t, distance, labels=(), ax=None):
    """Joint-space distance to each locus component (columns of ``distance``) against time."""
    ax = _axes(ax)
    D = np.atleast_2d(np.asarray(distance, dtype=float).T).T
    for k in range(D.shape[1]):
        label = labels[k] if k < len(labels) else f"component {k + 1}"
        ax.plot(t, D[:, k], label=label)
    ax.set_xlabel("t")
    ax.set_ylabel("distance to the locus (joint space)")
    ax.set_ylim(bottom=0)
    if D.shape[1]:
        ax.legend(fontsize="small")
    return ax.figure


def path_figure(path, distance=None, labels=()):
    """Three panels: joint rates, indices, distance to each locus component."""
    from matplotlib.figure import Figure

    panels = 3 if distance is not None else 2
    fig = Figure(figsize=(7.0, 2.6 * panels), layout="constrained")
    axes = fig.subplots(panels, 1, sharex=True)
    plot_joint_rates(path, ax=axes[0])
    plot_indices(path, ax=axes[1])
    if distance is not None:
        plot_distance(path.t, distance, labels, ax=axes[2])
    for ax in axes[:-1]:
        ax.set_xlabel("")
    if path.stopped:
        fig.suptitle(path.stopped, fontsize="small")
    return fig


def _ellipse_points(E, k=200):
    t = np.linspace(0, 2 * np.pi, k)
    return (E.axes[:, :2] * E.radii[:2]) @ np.vstack([np.cos(t), np.sin(t)])


def plot_manipulability(J, ax=None):
    """The ellipsoid and polytope of a 2- or 3-row J: a 2-D or 3-D drawing."""
    from .manipulability import ellipsoid, polytope

    J = np.asarray(J, dtype=float)
    m = J.shape[0]
    if m not in (2, 3):
        raise ValueError(f"plot_manipulability draws 2 or 3 rows, J has {m}")
    E, P = ellipsoid(J), polytope(J)
    ax = _axes(ax, projection="3d" if m == 3 else None)
    if m == 2:
        xy = _ellipse_points(E)
        ax.plot(xy[0], xy[1], label=f"ellipsoid, w = {E.w:.4g}")
        V = P.vertices
        if len(V) > 2:
            order = np.argsort(np.arctan2(V[:, 1], V[:, 0]))
            V = np.vstack([V[order], V[order][:1]])
        ax.plot(V[:, 0], V[:, 1], "-o", ms=3, label=f"polytope, w_p = {P.w_p:.4g}")
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel("vx")
        ax.set_ylabel("vy")
    else:
        from mpl_toolkits.mplot3d.art3d import Poly3DCollection

        u, v = np.mgrid[0:2 * np.pi:30j, 0:np.pi:16j]
        ball = np.stack([np.cos(u) * np.sin(v), np.sin(u) * np.sin(v), np.cos(v)])
        X = np.tensordot(E.axes * E.radii, ball, axes=1)
        ax.plot_wireframe(X[0], X[1], X[2], color="C0", linewidth=0.4,
                          label=f"ellipsoid, w = {E.w:.4g}")
        if len(P.simplices):
            tris = P.points[P.simplices]
            label = f"polytope, w_p = {P.w_p:.4g}"
            ax.add_collection3d(Poly3DCollection(tris, alpha=0.25, facecolor="C1",
                                                 edgecolor="none", label=label))
        ax.scatter(*P.vertices.T, color="C1", s=6)
        lim = float(np.abs(P.vertices).max()) or 1.0
        ax.set(xlim=(-lim, lim), ylim=(-lim, lim), zlim=(-lim, lim), xlabel="vx", ylabel="vy",
               zlabel="vz")
        ax.set_box_aspect((1, 1, 1))
    ax.legend(fontsize="small")
    return ax.figure
