"""The figures of a report, chosen and captioned: :func:`report_figures`.

:mod:`~rankloci.report.analysis` computes the numbers and
:mod:`~rankloci.report.figures` draws them; this module decides which
figures a report has (heat-map slices through the components, manipulability
along paths across them, the branch tree, J beside the augmented J) and
writes their captions.  Nothing is written to disk here.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np
import sympy as sp

from .blocks import SIGMA, numbered, plural

__all__ = ["FigureFile", "report_figures", "MAX_SLICES", "MAX_PATHS"]

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


def _units(model, model_tm) -> str:
    """The unit of the manipulability of ``model_tm``."""
    from ..model import RobotModel

    if not isinstance(model, RobotModel):
        return "units of the matrix entries"
    linear = sum(1 for r in model_tm.row_labels if r in ("vx", "vy", "vz"))
    if any(j.kind == "prismatic" for j in model.joints):
        return "mixed units (prismatic and revolute columns)"
    return "dimensionless" if linear == 0 else ("m" if linear == 1 else f"m^{linear}")


def _units_text(units: str) -> str:
    """``m^3`` as LaTeX math (``$\\mathrm{m}^{3}$``); other unit texts unchanged."""
    m = re.fullmatch(r"m\^(\d+)", units)
    return f"$\\mathrm{{m}}^{{{m.group(1)}}}$" if m else units


def _slice_point_without_locus(nm, rng):
    """A configuration for a heat map when no component is known, and how to name it.

    A minimum of sigma_min/sigma_max from the best of some random starts, when it is
    singular (the slice then shows a piece of the locus); else a random regular one.
    """
    from ..numeric.equations import minimise_ratio
    from ..tolerances import RANK_RTOL
    from .analysis import regular_point, sigma_ratios

    start = regular_point(nm, rng)
    try:
        q = minimise_ratio(nm, start)
    except (ValueError, np.linalg.LinAlgError):  # pragma: no cover - numeric trouble
        q = None
    if q is not None and float(sigma_ratios(nm.batch(q[None, :]))[0]) <= RANK_RTOL:
        return q, "a singular configuration found numerically (a minimum of the ratio)"
    return start, "a random regular configuration"


def report_figures(model, model_tm, locus, nm, params, seed, dot) -> tuple:
    """The :class:`FigureFile` of each figure of a report.

    ``model_tm`` is J in the model's own frame and ``nm`` its numeric form
    with the parameters at ``params``; ``locus`` may be None (it did not
    finish), and then the heat map passes through a configuration found
    numerically.  ``seed`` fixes the paths, ``dot`` is graphviz's ``dot``
    (or None: the tree is drawn with matplotlib).
    """
    from ..jacobian import task_matrix
    from ..numeric.equations import NumericMatrix
    from . import analysis as A
    from .tree_summary import tree_summary
    from .escape import file_stem
    from .figures import augmented_png, heatmap_png, manipulability_png, tree_png

    stem = file_stem(model.name)  # names the files and titles the figures
    rng = np.random.default_rng(seed)
    names = [v.name for v in nm.variables]
    prismatic = [v not in nm.angles for v in nm.variables]
    comps = A.model_components(locus) if locus is not None else []
    out = []
    slices = []          # (SliceData, where the slice passes through)
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
    for k, (data, where) in enumerate(slices, start=1):
        i, j = data.axes
        fixed = ", ".join(f"{names[m]} = {data.point[m]:+.3f}" for m in range(len(names))
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
    slices = [data for data, _ in slices]
    # manipulability along paths
    if comps:
        paths = [A.path_through(nm, np.array([c.sample[n] for n in names], dtype=float), rng,
                                component=idx) for idx, c in comps[:MAX_PATHS]]
        units = _units(model, model_tm)
        caption = (f"Manipulability $w = \\sqrt{{\\det(J J^T)}}$ [{_units_text(units)}] along "
                   "straight joint-space "
                   "paths $q(t) = q_0 + t d$, $-1 \\le t \\le 1$, each through the sample "
                   "point $q_0$ of one component (at $t = 0$) between two regular "
                   f"configurations; $d$ is random with $\\lVert d \\rVert = 1$ (seed {seed}).")
        title = f"{stem}: manipulability across the locus"
        out.append(FigureFile(f"{stem}-manipulability.png",
                              manipulability_png(paths, units=units, title=title),
                              caption, "manipulability", title,
                              tuple(p.component for p in paths)))
    # the branch tree
    if locus is not None and locus.tree is not None and locus.tree.number_of_nodes():
        summary = tree_summary(locus.tree)
        cut = (f" It has {summary.total_nodes} nodes; only the paths to components are drawn, "
               f"the other {summary.collapsed} branches are counted in dashed boxes."
               if summary.collapsed else "")
        caption = (f"Branch tree of the {locus.method} method. Green leaves are components, grey "
                   "leaves other stop reasons (in brackets); each node shows its branch "
                   "condition." + cut)
        out.append(FigureFile(f"{stem}-tree.png", tree_png(summary, dot=dot), caption,
                              "tree", f"{stem}: branch tree of the {locus.method} method"))
    # augmented Jacobian: J and J_aug side by side
    base = getattr(locus, "base", None) if locus is not None else None
    if base is not None and slices:
        plain_tm = task_matrix(model, use_model_augment=False)
        nm_plain = NumericMatrix(sp.Matrix(plain_tm.matrix).subs(params), plain_tm.variables,
                                 plain_tm.angles)
        data = slices[0]
        left = A.slice_grid(nm_plain, A.model_components(base), params, data.axes, data.point,
                            through=data.through)
        i, j = data.axes
        caption = (f"{SIGMA} over the ({names[i]}, {names[j]}) slice of the first "
                   "heat map, one colour scale: left J without the constraint rows, with the "
                   "components of its own locus; right the augmented J, with the components "
                   "of the augmented locus. Components drawn on the right only are algorithmic "
                   "singularities.")
        title = f"{stem}: J and the augmented J"
        out.append(FigureFile(f"{stem}-augmented.png",
                              augmented_png(left, data, names, prismatic, title=title),
                              caption, "augmented", title))
    return tuple(out)
