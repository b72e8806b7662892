"""Reports: what rankloci finds about a model, as Markdown, LaTeX and PDF with figures.

:func:`build_report` computes everything a report shows (the locus with the
model's default method and, for a non-square matrix, the other method too;
the numeric cross-check; plain-language readings; the figures as PNG bytes)
and returns a frozen :class:`Report`.  :func:`~rankloci.report.markdown.render_markdown`
and :func:`~rankloci.report.latex.render_latex` turn it into text.
:func:`write_report` is the only function that writes files: it builds the
whole report in a temporary directory beside the target and then moves the
files into place, so that a failure leaves nothing half-written.

:func:`build_report` reads neither the clock nor the environment on its own:
the caller passes a ``clock`` (for the timings and the time limit) and the
path of graphviz's ``dot``, and :func:`write_report` the LaTeX command (or
None for each).  :func:`read_model_notes` reads the free-text notes of a
model file, which the model object does not keep.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import sympy as sp

__all__ = ["Report", "FigureFile", "ComponentView", "build_report", "write_report",
           "read_model_notes", "ReportError", "FORMATS"]

FORMATS = ("md", "tex", "pdf")

#: At most this many heat-map slices and manipulability paths per report.
MAX_SLICES = 4
MAX_PATHS = 6

#: Extra points per component on which geometric readings are confirmed.
READING_POINTS = 2

#: A direction reading longer than this is left out of the summary tables.
SUMMARY_CHARS = 110

SIGMA = r"$\sigma_{\min}/\sigma_{\max}$"


class ReportError(Exception):
    """A report could not be written (LaTeX failed on it): not bad input, a failure."""


@dataclass(frozen=True)
class FigureFile:
    """One figure: its file name beside the report, PNG bytes and caption (text with $math$)."""

    name: str
    png: bytes
    caption: str
    kind: str
    title: str = ""


@dataclass(frozen=True)
class ComponentView:
    """A locus component with what the report says about it."""

    index: int
    component: object
    special: bool
    readings: tuple = ()
    folded: tuple = ()        # equivalent compact forms of the equations (or ())
    kind: str | None = None
    summary: str = ""         # a short reading for tables: geometry first, "" if none is short


@dataclass(frozen=True)
class Report:
    """Everything a report shows; see :func:`build_report`."""

    model: object
    tm: object
    jacobian: object
    notation: tuple
    locus: object
    locus_status: str
    components: tuple
    second: object = None
    second_status: str = ""
    comparison: object = None
    check: object = None
    exact: object = None
    tree: object = None
    figures: tuple = ()
    timings: tuple = ()
    seed: int = 0
    samples: int = 10
    timeout: float | None = None
    numeric: bool = False
    augmented: tuple = ()     # ComponentView of the augmented locus when it has a base locus
    notes: tuple = ()
    model_notes: str = ""     # the free-text notes of the model file
    stamp: str = ""           # a date and time to print, only when asked for

    @property
    def name(self) -> str:
        return self.model.name

    @property
    def method(self) -> str:
        return _default_method(self.tm)

    def figure(self, kind: str):
        return [f for f in self.figures if f.kind == kind]


def _default_method(tm) -> str:
    return "determinant" if tm.shape[0] == tm.shape[1] else "svm"


# --- building ------------------------------------------------------------------------------------

def read_model_notes(model) -> str:
    """The ``notes`` of the TOML file a model was read from ("" for other models)."""
    import tomllib

    path = str(getattr(model, "path", "") or "")
    if not path.endswith(".toml"):
        return ""
    try:
        with open(path, "rb") as fh:
            notes = tomllib.load(fh).get("notes", "")
    except (OSError, tomllib.TOMLDecodeError):
        return ""
    return " ".join(notes.split()) if isinstance(notes, str) else ""


def build_report(model, *, seed: int = 0, samples: int = 10, numeric: bool = False,
                 timeout: float | None = None, clock=None, progress=None, dot: str | None = None,
                 exact: bool = True, model_notes: str = "", stamp: str = "") -> Report:
    """Compute the content of a report on ``model``.

    Parameters
    ----------
    model : RobotModel or MatrixModel
    seed : int
        Seed of every random choice (numeric probes, cross-check points, paths).
    samples : int
        Points per component, off-locus points and probe starts of the cross-check.
    numeric : bool
        Replace the parameters by their values before the algebra.
    timeout : float, optional
        Seconds allowed to each locus computation (needs ``clock``).  When the
        first one runs out, the report is built without the locus and says so.
    clock : callable, optional
        Returns seconds (``time.perf_counter``); without it no timing is recorded
        and ``timeout`` does not apply.
    progress : callable, optional
        Called with one-line progress messages.
    dot : str, optional
        Path of graphviz's ``dot``; without it the tree is drawn with matplotlib.
    exact : bool
        Also run the Singular cross-check of ``rankloci check`` (skipped by it
        when Singular is absent or the matrix is too large).
    model_notes : str
        Free-text notes on the model (see :func:`read_model_notes`), shown
        with its source.
    stamp : str
        A date and time to print under the title; empty (the default) keeps
        the report free of dates.

    Examples
    --------
    >>> from rankloci.io import load_model
    >>> report = build_report(load_model("planar2r"), samples=2, exact=False)
    >>> [str(v.component.equations[0]) for v in report.components if not v.special]
    ['sin(q2)']
    >>> [f.name for f in report.figures]
    ['planar2r-sigma-1.png', 'planar2r-manipulability.png', 'planar2r-tree.png']
    """
    from ..jacobian import task_matrix
    from ..methods import compute_locus
    from ..errors import LocusTimeout
    from ..numeric.crosscheck import cross_check
    from ..numeric.equations import NumericMatrix
    from . import analysis as A
    from .mathfmt import jacobian_display

    say = progress or (lambda msg: None)
    now = clock or (lambda: 0.0)
    timings = []

    def timed(label, fn):
        t0 = now()
        out = fn()
        timings.append((label, now() - t0))
        return out

    def stopper():
        if clock is None or not timeout or timeout <= 0:
            return None
        end = clock() + timeout
        return lambda: clock() > end

    say(f"{model.name}: building the symbolic matrix")
    tm = timed("symbolic J (locus frame)", lambda: task_matrix(model, frame="auto", numeric=numeric))
    model_tm = timed("symbolic J (model frame)", lambda: task_matrix(model))
    jac = timed("J for display", lambda: jacobian_display(tm.matrix, tm.variables,
                                                           tm.parameters, tm.row_labels))
    params = dict(model_tm.parameters)
    nm = NumericMatrix(sp.Matrix(model_tm.matrix).subs(params), model_tm.variables,
                       model_tm.angles)
    method = _default_method(tm)
    rng = np.random.default_rng

    # the locus
    say(f"{model.name}: {tm.shape[0]}x{tm.shape[1]} matrix, locus by {method}, seed {seed}")
    locus, status = None, ""
    try:
        locus = timed(f"locus ({method})", lambda: _primary_locus(
            model, tm, method, seed, progress, stopper(), clock))
    except LocusTimeout:
        timings.append((f"locus ({method})", float(timeout or 0.0)))
        status = (f"The locus computation ({method}) did not finish within {timeout:g} s "
                  "(the time limit of this report); the sections below that need it are "
                  "left out.")
        say(f"{model.name}: the locus did not finish within {timeout:g} s")

    # the other method
    second, second_status, comparison = None, "", None
    if locus is not None and tm.shape[0] != tm.shape[1]:
        say(f"{model.name}: locus by subdeterminant, for the comparison")
        try:
            second = timed("locus (subdeterminant)", lambda: compute_locus(
                tm, "subdeterminant", rng=rng(seed), should_stop=stopper(), clock=clock))
            comparison = timed("method comparison", lambda: A.compare_loci(
                locus, second, nm, params, rng(seed)))
        except LocusTimeout:
            timings.append(("locus (subdeterminant)", float(timeout or 0.0)))
            second_status = (f"The subdeterminant method did not finish within {timeout:g} s; "
                             "no comparison.")

    # the cross-check
    check = exact_result = None
    if locus is not None:
        say(f"{model.name}: cross-check, {samples} samples, seed {seed}")
        check = timed("numeric cross-check", lambda: cross_check(
            locus, model_tm.matrix, model_tm.variables, angles=model_tm.angles,
            parameters=params, samples=samples, rng=rng(seed), seed=seed))
        if exact:
            from ..exact.singular import singular_cross_check

            exact_result = timed("Singular cross-check", lambda: singular_cross_check(
                task_matrix(model, frame="auto", numeric=True), locus, rng=rng(seed)))

    # components, readings, folded equations
    views, notation = (), jac.abbreviations
    if locus is not None:
        views, notation = timed("readings", lambda: _component_views(
            model, model_tm, locus, nm, params, rng(seed), jac))
    augmented = ()
    base = getattr(locus, "base", None) if locus is not None else None
    if base is not None:
        augmented = tuple(ComponentView(i, c, bool(c.parameter_conditions or not c.for_model),
                                        kind=getattr(c, "kind", None))
                          for i, c in enumerate(locus.components, start=1))

    # figures
    say(f"{model.name}: figures")
    figures = timed("figures", lambda: _figures(model, model_tm, locus, nm, params, seed, dot))
    tree = A.tree_summary(locus.tree) if locus is not None and locus.tree is not None else None
    notes = ()
    if locus is not None and tm.frame is not None and (tm.frame, tm.point) != (
            getattr(model, "frame", None), "tool"):
        where = f"link frame {tm.frame}" if isinstance(tm.frame, int) else f"the {tm.frame} frame"
        about = (f", about the origin of link frame {tm.point}" if isinstance(tm.point, int)
                 else "")
        notes = (f"The locus was computed from J in {where}{about}, where its entries are "
                 "smallest; the rank, and so the locus, is the same in every frame. The lost "
                 "directions at the sample points are given in the model's frame.",)
    return Report(model=model, tm=tm, jacobian=jac, notation=notation, locus=locus,
                  locus_status=status, components=views, second=second,
                  second_status=second_status, comparison=comparison, check=check,
                  exact=exact_result, tree=tree, figures=figures, timings=tuple(timings),
                  seed=seed, samples=samples, timeout=timeout, numeric=numeric,
                  augmented=augmented, notes=notes, model_notes=model_notes, stamp=stamp)


def _primary_locus(model, tm, method, seed, progress, should_stop, clock):
    """The locus the report is about: for an augmented matrix, with J's own locus attached
    and each component classified (kinematic, algorithmic, mixed), where the package can."""
    from ..directions import directions_in_model_frame
    from ..methods import compute_locus

    try:
        from ..augmented import augmented_locus
    except ImportError:  # pragma: no cover - a package without augmented Jacobians
        augmented_locus = None
    if augmented_locus is not None:
        return augmented_locus(model, tm, method, seed=seed, progress=progress,
                               should_stop=should_stop, clock=clock)
    locus = compute_locus(tm, method, rng=np.random.default_rng(seed), progress=progress,
                          should_stop=should_stop, clock=clock)
    return directions_in_model_frame(locus, model, tm)


def _component_views(model, model_tm, locus, nm, params, rng, jac):
    from .analysis import component_points
    from .mathfmt import abbreviations, angle_sums, compact, latex, math_width
    from .reading import direction_readings

    variables = list(model_tm.variables)
    taken = {str(s) for e in model_tm.matrix for s in e.free_symbols}
    notation = dict((str(s), (s, f)) for s, f in jac.abbreviations)
    tall = model_tm.shape[0] > model_tm.shape[1]
    frame = getattr(model, "frame", "base")
    views = []
    for i, c in enumerate(locus.components, start=1):
        special = bool(c.parameter_conditions or not c.for_model)
        folded = []
        for e in c.equations:
            f = angle_sums(e)
            atoms = sorted(f.atoms(sp.sin, sp.cos), key=sp.default_sort_key)
            ab = abbreviations(variables, taken, atoms)
            g = compact(f.xreplace(ab), list(model_tm.parameters))
            if g.has(sp.sin, sp.cos) or math_width(latex(g)) > 0.8 * math_width(latex(e)):
                folded = []
                break
            for fn, s in ab.items():
                if s in g.free_symbols:
                    notation.setdefault(str(s), (s, fn))
            folded.append(g)
        geometry, directions = [], []
        if not special:
            geometry = _named_readings(model, c, nm, params, rng, component_points)
            q = np.array([c.sample[v.name] for v in nm.variables], dtype=float)
            J = nm(q)
            for vec in c.direction_at_sample:
                directions += direction_readings(J, vec, model_tm.row_labels, tall=tall,
                                                 frame=frame, variables=variables)
        short = [r for r in directions if len(r) <= SUMMARY_CHARS]
        summary = geometry[0] if geometry else (short[0] if short else "")
        views.append(ComponentView(i, c, special, tuple(geometry + directions), tuple(folded),
                                   getattr(c, "kind", None), summary))
    items = sorted(notation.values(), key=lambda p: _notation_key(p[1], variables))
    return tuple(views), tuple(items)


def _notation_key(f, variables):
    terms = sp.Add.make_args(f.args[0])
    return (len(terms), [variables.index(t) if t in variables else 99 for t in terms],
            isinstance(f, sp.sin))


def _named_readings(model, comp, nm, params, rng, component_points):
    """Geometric readings, with the conventional name of the singularity where it is clear."""
    from ..model import RobotModel
    from .reading import geometry_readings

    if not isinstance(model, RobotModel):
        return []
    pts = component_points(comp, nm, params, rng, READING_POINTS)
    qs = [{v.name: float(x) for v, x in zip(nm.variables, q)} for q in pts]
    facts = geometry_readings(model, qs, rng)
    if not facts:
        return []
    revolute = [k + 1 for k, j in enumerate(model.joints) if j.kind == "revolute"]
    wrist = set(revolute[-3:]) if len(revolute) >= 6 else set()
    shoulder = set(revolute[:3]) if len(revolute) >= 6 else set()
    first = revolute[0] if revolute else None
    named = []
    for f in facts:
        axes = [int(x) for x in re.findall(r"\d+", f)]
        if f.startswith("axes") and f.endswith("collinear") and set(axes) <= wrist:
            f = "wrist singularity: " + f
        elif f.startswith("axes") and f.endswith("collinear") and set(axes) <= shoulder:
            f = "shoulder singularity: " + f
        elif (f.startswith("axes") and f.endswith("collinear") and len(revolute) >= 7
              and axes[0] in shoulder and axes[1] in wrist):
            f = "elbow singularity (arm stretched out or folded back): " + f
        elif f.startswith("axis") and "parallel to" in f and axes[0] in wrist \
                and set(axes[1:]) & wrist:
            f = "wrist singularity: " + f
        elif (f == f"the task point lies on axis {first}"
              or f.startswith(f"the task point lies in the plane through axis {first} ")):
            f = "shoulder singularity: " + f
        elif (f.endswith("the plane they span") or f.endswith("lie in one plane")) \
                and axes == list(range(axes[0], axes[0] + len(axes))):
            f = "elbow singularity (arm stretched out or folded back): " + f
        named.append(f)
    return named


def _units(model, model_tm) -> str:
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


def _figures(model, model_tm, locus, nm, params, seed, dot):
    from ..jacobian import task_matrix
    from ..numeric.equations import NumericMatrix
    from . import analysis as A
    from .figures import augmented_png, heatmap_png, manipulability_png, tree_png

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
        title = f"{model.name}: ({names[i]}, {names[j]}) slice through {short}"
        shown = [str(c[0]) for c in data.curves]
        if shown:
            drawn = f". Lines and dots: where component(s) {', '.join(shown)} meet the slice."
        elif locus is None:
            drawn = ". The locus did not finish, so none is drawn."
        else:
            drawn = ". No component of the locus meets this slice."
        caption = (f"{SIGMA} of $J$ over the ({names[i]}, {names[j]}) slice through "
                   f"{where} (the cross), log colour scale"
                   + (f"; the other joints are fixed at {fixed}" if fixed else "") + drawn)
        out.append(FigureFile(f"{model.name}-sigma-{k}.png",
                              heatmap_png(data, names, prismatic, title=title), caption, "sigma",
                              title))
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
        title = f"{model.name}: manipulability across the locus"
        out.append(FigureFile(f"{model.name}-manipulability.png",
                              manipulability_png(paths, units=units, title=title),
                              caption, "manipulability", title))
    # the branch tree
    if locus is not None and locus.tree is not None and locus.tree.number_of_nodes():
        summary = A.tree_summary(locus.tree)
        cut = (f" It has {summary.total_nodes} nodes; only the paths to components are drawn, "
               f"the other {summary.collapsed} branches are counted in dashed boxes."
               if summary.collapsed else "")
        caption = (f"Branch tree of the {locus.method} method. Green leaves are components, grey "
                   "leaves other stop reasons (in brackets); each node shows its branch "
                   "condition." + cut)
        out.append(FigureFile(f"{model.name}-tree.png", tree_png(summary, dot=dot), caption,
                              "tree", f"{model.name}: branch tree of the {locus.method} method"))
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
        title = f"{model.name}: J and the augmented J"
        out.append(FigureFile(f"{model.name}-augmented.png",
                              augmented_png(left, data, names, prismatic, title=title),
                              caption, "augmented", title))
    return tuple(out)


# --- writing ---------------------------------------------------------------------------------------

#: Figure files a report owns: an older one that is not produced again is removed.
_FIGURE_PATTERNS = ("{name}-sigma-*.png", "{name}-manipulability.png", "{name}-tree.png",
                    "{name}-augmented.png")


def write_report(report: Report, directory, *, formats=FORMATS, fragment: bool = False,
                 latex: tuple | None = None, timings: bool = True) -> list[Path]:
    """Write ``report`` into ``directory`` (created if missing) and return the paths written.

    Parameters
    ----------
    report : Report
    directory : path
    formats : sequence of {"md", "tex", "pdf"}
        The PNG figures are always written beside the text.
    fragment : bool
        Write the LaTeX body without a preamble (for ``\\input`` into a paper).
    latex : (str, str) or None
        ``("latexmk", path)`` or ``("pdflatex", path)`` to build the PDF; None
        skips the PDF.
    timings : bool
        Include the timing table (it differs from run to run).

    Everything is first built in a temporary directory beside ``directory``;
    only when all of it succeeded are the files moved into place.
    """
    from .latex import render_latex
    from .markdown import render_markdown

    bad = [f for f in formats if f not in FORMATS]
    if bad:
        raise ValueError(f"formats {bad} are not among {FORMATS}")
    directory = Path(directory)
    # the temporary directory goes into the nearest directory that exists, so that a
    # failure creates nothing, and the final moves stay on one file system (atomic)
    anchor = directory.resolve().parent
    while not anchor.is_dir():
        anchor = anchor.parent
    tmp = Path(tempfile.mkdtemp(dir=anchor, prefix=f".{directory.name}.tmp-"))
    try:
        produced = []
        for fig in report.figures:
            (tmp / fig.name).write_bytes(fig.png)
            produced.append(fig.name)
        name = report.name
        if "md" in formats:
            (tmp / f"{name}.md").write_text(render_markdown(report, timings=timings),
                                            encoding="utf-8")
            produced.append(f"{name}.md")
        tex = render_latex(report, fragment=fragment, timings=timings)
        if "tex" in formats:
            (tmp / f"{name}.tex").write_text(tex, encoding="utf-8")
            produced.append(f"{name}.tex")
        if "pdf" in formats and latex is not None:
            _build_pdf(tmp, name, tex if not fragment else render_latex(
                report, fragment=False, timings=timings), latex)
            produced.append(f"{name}.pdf")
        directory.mkdir(parents=True, exist_ok=True)
        written = []
        stale = {p.name for pattern in _FIGURE_PATTERNS
                 for p in directory.glob(pattern.format(name=name))} - set(produced)
        for fname in produced:
            os.replace(tmp / fname, directory / fname)
            written.append(directory / fname)
        for fname in sorted(stale):
            (directory / fname).unlink(missing_ok=True)
        return written
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def _build_pdf(workdir: Path, name: str, document: str, latex: tuple):
    """Compile ``document`` in ``workdir`` to ``name.pdf``; raise ReportError with the log tail."""
    kind, exe = latex
    job = f"{name}-build"
    (workdir / f"{job}.tex").write_text(document, encoding="utf-8")
    env = dict(os.environ, SOURCE_DATE_EPOCH="0", FORCE_SOURCE_DATE="1")
    if kind == "latexmk":
        cmds = [[exe, "-pdf", "-interaction=nonstopmode", "-halt-on-error", "-file-line-error",
                 f"{job}.tex"]]
    else:
        run = [exe, "-interaction=nonstopmode", "-halt-on-error", "-file-line-error", f"{job}.tex"]
        cmds = [run, run]
    for cmd in cmds:
        try:
            proc = subprocess.run(cmd, cwd=workdir, capture_output=True, timeout=600, env=env,
                                  stdin=subprocess.DEVNULL)
        except subprocess.TimeoutExpired:
            raise ReportError(f"{kind} did not finish within 600 s on {name}.tex") from None
        if proc.returncode != 0:
            log = workdir / f"{job}.log"
            tail = log.read_text(errors="replace").splitlines()[-15:] if log.exists() else []
            errors = [ln for ln in tail if ln.startswith("!") or ":" in ln][:3]
            raise ReportError(f"{kind} failed on {name}.tex: "
                              + (" | ".join(errors) or f"exit code {proc.returncode}"))
    os.replace(workdir / f"{job}.pdf", workdir / f"{name}.pdf")


def latex_log_problems(log_text: str, *, overfull_pt: float = 1.0) -> list[str]:
    """Overfull boxes wider than ``overfull_pt`` and LaTeX warnings in a log."""
    import re

    out = []
    for line in log_text.splitlines():
        m = re.match(r"Overfull \\hbox \(([\d.]+)pt too wide\)", line)
        if m and float(m.group(1)) > overfull_pt:
            out.append(line.strip())
        elif line.startswith("LaTeX Warning") and "Label(s) may have changed" not in line:
            out.append(line.strip())
    return out
