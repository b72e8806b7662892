"""Figures of joint rates along a path and of manipulability ellipsoids and polytopes.

They start from what the public functions return: the path of
:func:`rankloci.joint_rates`, the result of :func:`rankloci.manipulability`
(or a Jacobian as an array), and a :class:`~rankloci.loci.Locus` for the
distance to its components.  Every function draws into ``ax`` when given (a
3-D axes for a 3-D polytope) and otherwise into a new
:class:`matplotlib.figure.Figure`, and returns the Axes it drew into
(:func:`path_figure`, which draws several panels, an array of them).  No
backend is chosen here: ``ax.figure.savefig`` works under any backend.
"""

from __future__ import annotations

import numpy as np

__all__ = ["plot_joint_rates", "plot_indices", "plot_distance", "path_distances", "path_figure",
           "plot_manipulability"]


def _axes(ax, projection=None):
    if ax is not None:
        return ax
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.4, 4.8) if projection else (6.4, 3.2), layout="constrained")
    return fig.add_subplot(projection=projection)


def plot_joint_rates(path, ax=None):
    """The applied joint rates against time, one line per joint.

    Parameters
    ----------
    path : PathRates
        From :func:`rankloci.joint_rates`.
    ax : matplotlib.axes.Axes, optional

    Returns
    -------
    matplotlib.axes.Axes

    Examples
    --------
    >>> import rankloci
    >>> from rankloci.near.figures import plot_joint_rates
    >>> path = rankloci.joint_rates("planar2r", [0.3, 1.0], [[1.2, 0.9], [1.0, 1.2]], steps=5)
    >>> [line.get_label() for line in plot_joint_rates(path).lines]
    ['q1', 'q2']
    """
    ax = _axes(ax)
    for j in range(path.rates.shape[1]):
        ax.plot(path.t, path.rates[:, j], label=f"q{j + 1}")
    ax.set_xlabel("t")
    ax.set_ylabel("joint rate")
    names = {"2": "minimum 2-norm", "inf": "minimum infinity-norm", "mixed": "mixed"}
    ax.set_title(f"joint rates ({names[path.norm]})")
    ax.legend(fontsize="small", ncols=min(4, path.rates.shape[1]))
    return ax


def plot_indices(path, ax=None):
    """The discontinuity indices, the mixing ratio and sigma_min/sigma_max against time.

    ``path`` is the result of :func:`rankloci.joint_rates`; returns the Axes.
    """
    ax = _axes(ax)
    ax.plot(path.t, path.index, label="discontinuity index")
    ax.plot(path.t, path.minor_index, label="index with J (0 on the locus)")
    ax.plot(path.t, path.subspace_index, "-.", lw=0.8, label="Gravagne's index (every face)")
    ax.plot(path.t, path.mixing, "--", label="mixing ratio r")
    ax.plot(path.t, path.sigma_ratio, ":", label="sigma_min/sigma_max")
    ax.set_xlabel("t")
    ax.set_ylim(bottom=0)
    ax.legend(fontsize="small")
    return ax


def _is_locus(obj) -> bool:
    from ..loci import Locus

    return isinstance(obj, Locus)


def path_distances(path, locus, *, model=None):
    """The joint-space distance from each configuration of ``path`` to each component.

    Parameters
    ----------
    path : PathRates
        From :func:`rankloci.joint_rates`.
    locus : Locus
        Of the same robot (its variables are the path's joints).
    model : optional
        The robot, anything :func:`rankloci.load_model` takes (which joints are
        angles, whose differences are taken modulo 2 pi); default:
        ``locus.model`` as a built-in model name.

    Returns
    -------
    (numpy.ndarray, list of str)
        The distances, shape (len(path.t), number of components), and a label
        per component (``"component 1: sin(q2) = 0"``).
    """
    from ..api.calls import jacobian
    from ..errors import ArgumentError
    from .nearest import ComponentDistance

    tm = jacobian(locus.model if model is None else model)
    if [str(v) for v in tm.variables] != [str(v) for v in locus.variables]:
        raise ArgumentError(f"model=: its variables {[str(v) for v in tm.variables]} are "
                            f"not the locus's {[str(v) for v in locus.variables]}",
                            argument="model")
    q = np.asarray(path.q, dtype=float)
    if q.ndim != 2 or q.shape[1] != len(locus.variables):
        raise ArgumentError(f"the path has {q.shape[-1]} joints, the locus "
                            f"{len(locus.variables)}", argument="path")
    cd = ComponentDistance(locus, tm.angles)
    D = np.array([cd.nearest(x, warm=True).distances for x in q], dtype=float)
    labels = [f"component {k}: " + ", ".join(f"{e} = 0" for e in c.equations)
              for k, c in enumerate(locus.components, start=1)]
    return D.reshape(len(q), len(labels)), labels


def plot_distance(t, distance=None, labels=(), ax=None, *, model=None):
    """Joint-space distance to each locus component against time.

    Parameters
    ----------
    t : PathRates or array_like
        The path of :func:`rankloci.joint_rates`, with ``distance`` a Locus
        (its distances from :func:`path_distances`); or the times, with
        ``distance`` an array (one column per component).
    distance : Locus or array_like
    labels : sequence of str
        A label per column (default: from the locus, or ``component k``).
    ax : matplotlib.axes.Axes, optional
    model : optional
        With a locus: as :func:`path_distances`.

    Returns
    -------
    matplotlib.axes.Axes

    Examples
    --------
    >>> import rankloci
    >>> from rankloci.near.figures import plot_distance
    >>> path = rankloci.joint_rates("planar2r", [0.3, 1.0], [[1.2, 0.9], [1.0, 1.2]], steps=5)
    >>> ax = plot_distance(path, rankloci.locus("planar2r"))
    >>> [line.get_label() for line in ax.lines]
    ['component 1: sin(q2) = 0']
    """
    if _is_locus(distance):
        D, own = path_distances(t, distance, model=model)
        t, distance, labels = t.t, D, (labels or own)
    elif distance is None:
        from ..errors import ArgumentError

        raise ArgumentError("distance= is needed: a Locus, or an array of distances",
                            argument="distance")
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
    return ax


def path_figure(path, distance=None, labels=(), *, model=None, ax=None):
    """Three panels: joint rates, indices, distance to each locus component.

    Parameters
    ----------
    path : PathRates
        From :func:`rankloci.joint_rates`.
    distance : Locus or array_like, optional
        The locus (or the distances, as :func:`plot_distance`); without it,
        two panels.
    labels : sequence of str
    model : optional
        With a locus: as :func:`path_distances`.
    ax : array of matplotlib.axes.Axes, optional
        Two or three axes (one per panel); a new Figure's otherwise.

    Returns
    -------
    numpy.ndarray of matplotlib.axes.Axes

    Examples
    --------
    >>> import rankloci
    >>> from rankloci.near.figures import path_figure
    >>> path = rankloci.joint_rates("planar2r", [0.3, 1.0], [[1.2, 0.9], [1.0, 1.2]], steps=5)
    >>> len(path_figure(path, rankloci.locus("planar2r")))
    3
    """
    from matplotlib.figure import Figure

    panels = 3 if distance is not None else 2
    if ax is None:
        fig = Figure(figsize=(7.0, 2.6 * panels), layout="constrained")
        axes = fig.subplots(panels, 1, sharex=True)
    else:
        axes = np.asarray(ax, dtype=object).reshape(-1)
        if len(axes) != panels:
            from ..errors import ArgumentError

            raise ArgumentError(f"ax= must be {panels} axes (one per panel), got {len(axes)}",
                                argument="ax")
        fig = axes[0].figure
    plot_joint_rates(path, ax=axes[0])
    plot_indices(path, ax=axes[1])
    if distance is not None:
        plot_distance(path, distance, labels, ax=axes[2], model=model) if _is_locus(distance) \
            else plot_distance(path.t, distance, labels, ax=axes[2])
    for a in axes[:-1]:
        a.set_xlabel("")
    if path.stopped:
        fig.suptitle(path.stopped, fontsize="small")
    return np.asarray(axes, dtype=object)


def _ellipse_points(E, k=200):
    t = np.linspace(0, 2 * np.pi, k)
    return (E.axes[:, :2] * E.radii[:2]) @ np.vstack([np.cos(t), np.sin(t)])


def plot_manipulability(J, ax=None):
    """The ellipsoid and polytope of a 2- or 3-row J: a 2-D or 3-D drawing.

    Parameters
    ----------
    J : Manipulability or array_like
        The result of :func:`rankloci.manipulability` (its ``J``; with
        ``position_only=True`` for a spatial arm), or a 2- or 3-row Jacobian.
    ax : matplotlib.axes.Axes, optional
        A 3-D axes for three rows.

    Returns
    -------
    matplotlib.axes.Axes

    Examples
    --------
    >>> import rankloci
    >>> from rankloci.near.figures import plot_manipulability
    >>> m = rankloci.manipulability("puma560", [0.1, 0.5, -0.3, 0.2, 0.4, 0.0],
    ...                             position_only=True)
    >>> plot_manipulability(m).name
    '3d'
    """
    from .manipulability import ellipsoid, polytope

    J = getattr(J, "J", J)        # a Manipulability result carries its J
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
    return ax
