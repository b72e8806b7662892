"""What a report shows, computed: :func:`build_report` and the :class:`Report` it returns.

:func:`build_report` computes everything a report shows (the locus with the
model's default method and, for a non-square matrix, the other method too;
the numeric cross-check; plain-language readings; the figures as PNG bytes)
and returns a frozen :class:`Report`.  It reads neither the clock nor the
environment on its own: the caller passes a ``clock`` (for the timings and
the time limit) and the path of graphviz's ``dot`` (or None for each).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
import sympy as sp

from ..tolerances import RANK_RTOL, READING_POINTS

__all__ = ["Report", "ComponentView", "build_report", "component_views", "READING_POINTS",
           "SUMMARY_CHARS"]

#: A direction reading longer than this is left out of the summary tables.
SUMMARY_CHARS = 110

#: A geometric reading longer than this is shortened to its name in the summary table.
SUMMARY_READING_CHARS = 420

#: An equation a reading names is written out when its width (in
#: :func:`~rankloci.reporting.mathfmt.math_width` units) is at most this, else named by its order.
READING_EQUATION_WIDTH = 16.0


@dataclass(frozen=True)
class ComponentView:
    """A locus component with what the report says about it."""

    index: int
    component: object
    special: bool
    readings: tuple = ()
    folded: tuple = ()        # equivalent compact forms of the equations (or ())
    folded_excluding: tuple = ()  # compact forms of the side conditions (or ())
    kind: str | None = None
    summary: str = ""         # a short reading for tables: geometry first, "" if none is short
    geometry: tuple = ()      # the geometric readings (also the first of ``readings``)
    motions: tuple = ()       # the lost motion along each lost direction, in a few words
    axes: tuple = ()          # the joints whose axes the reading names (drawn highlighted)
    lost_axis: tuple = ()     # the axis of the rotation collinear axes lose (or ())
    equal_parameters: tuple = ()  # EqualParameterForm of equations that shrink (or ())


@dataclass(frozen=True)
class EqualParameterForm:
    """An equation of a component with parameters of equal value set equal, where terms cancel.

    ``equalities`` are (parameter, the parameter it is replaced by) pairs; ``terms``
    the numbers of terms before and after (expanded); ``form`` the shorter equation.
    """

    index: int                # 0-based, into the component's equations
    equalities: tuple
    terms: tuple
    form: object


def equal_parameter_forms(equations, params) -> tuple:
    """The equations that lose terms when parameters of equal value are set equal.

    Each parameter is replaced by the first (by name) of those with the same value; an
    equality is used only when it alone removes terms from the equation.

    Examples
    --------
    >>> a3, a4, q = sp.symbols("a3 a4 q")
    >>> e = a3 * sp.cos(q) - a4 * sp.cos(q) + a4 * sp.sin(q)
    >>> f = equal_parameter_forms([e], {a3: 7.11, a4: 7.11})[0]
    >>> f.equalities, f.terms, f.form
    (((a4, a3),), (3, 1), a3*sin(q))
    """
    groups: dict = {}
    for p in sorted(params, key=str):
        groups.setdefault(sp.nsimplify(params[p], rational=True), []).append(p)
    rep = {p: g[0] for g in groups.values() if len(g) > 1 for p in g[1:]}
    out = []
    for k, e in enumerate(equations):
        e = sp.sympify(e, strict=True)
        before = len(sp.Add.make_args(sp.expand(e)))
        used = tuple((p, r) for p, r in rep.items() if p in e.free_symbols
                     and len(sp.Add.make_args(sp.expand(e.xreplace({p: r})))) < before)
        if not used:
            continue
        form = sp.expand(e.xreplace(dict(used)))
        if form != 0:
            out.append(EqualParameterForm(k, used, (before, len(sp.Add.make_args(form))),
                                          sp.factor_terms(form)))
    return tuple(out)


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
    near: object = None       # near_section.NearData: manipulability and rates near the locus
    limits: tuple = ()        # rankloci.limits.LimitCheck per component of the model's locus
    determinant: object = None  # determinant.FactoredDeterminant of a square J, or None
    minor_gcd: object = None  # determinant.MinorGcd of a wide or tall J, or None

    def limit_check(self, index: int):
        """The :class:`~rankloci.limits.LimitCheck` of component ``index`` (1-based), or None."""
        return next((c for c in self.limits if c.component == index), None)

    @property
    def has_limits(self) -> bool:
        """Does any joint of the model have limits?"""
        return any(getattr(j, "limits", None) for j in getattr(self.model, "joints", ()))

    @property
    def name(self) -> str:
        """The model's name as a file stem (:func:`~rankloci.reporting.escape.file_stem`).

        It names the report's files and its LaTeX labels, so it holds only
        ASCII letters, digits, ``_`` and ``-``.
        """
        from .escape import file_stem

        return file_stem(self.model.name)

    @property
    def method(self) -> str:
        """The method of the locus the report is about (:func:`~rankloci.methods.method_for`)."""
        from ..methods import method_for

        return method_for(self.tm.shape)

    def figure(self, kind: str):
        """The figures of one ``kind`` (``"sigma"``, ``"manipulability"``, ``"tree"``, ...)."""
        return [f for f in self.figures if f.kind == kind]


def build_report(model, *, seed: int = 0, samples: int = 10, numeric: bool = False,
                 timeout: float | None = None, clock=None, progress=None, dot: str | None = None,
                 exact: bool = True, model_notes: str = "", stamp: str = "",
                 jobs: int | None = 1, rank_rtol: float = RANK_RTOL) -> Report:
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
        Free-text notes on the model (see
        :func:`~rankloci.reporting.write.read_model_notes`), shown
        with its source.
    stamp : str
        A date and time to print under the title; empty (the default) keeps
        the report free of dates.
    jobs : int, optional
        Processes for the locus (:func:`~rankloci.api.calls.certified_locus`); None: every
        core.  The report is the same for any.
    rank_rtol : float
        Rank threshold (sigma_min <= rank_rtol * sigma_max) of the locus's self-check and of
        the numeric cross-check; the report's other figures and readings keep
        :data:`~rankloci.tolerances.RANK_RTOL`.

    Examples
    --------
    >>> from rankloci.io import load_model
    >>> report = build_report(load_model("planar2r"), samples=2, exact=False)
    >>> [str(v.component.equations[0]) for v in report.components if not v.special]
    ['sin(q2)']
    >>> [f.name for f in report.figures]  # doctest: +NORMALIZE_WHITESPACE
    ['planar2r-sigma-1.png', 'planar2r-manipulability.png', 'planar2r-robot-1.png',
     'planar2r-tree.png', 'planar2r-near-manipulability.png', 'planar2r-near-path.png']
    """
    from ..api.calls import certified_locus
    from ..errors import LocusTimeout
    from ..jacobians import task_matrix
    from ..methods import compute_locus, method_for
    from ..numeric.crosscheck import cross_check
    from ..numeric.equations import NumericMatrix
    from ..compare import compare_loci
    from .tree_summary import tree_summary
    from .escape import file_stem
    from .figure_files import report_figures
    from .near_section import near_data
    from .matrixfmt import jacobian_display

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
    tm = timed("symbolic J (locus frame)",
               lambda: task_matrix(model, frame="auto", numeric=numeric))
    model_tm = timed("symbolic J (model frame)", lambda: task_matrix(model))
    jac = timed("J for display", lambda: jacobian_display(tm.matrix, tm.variables,
                                                           tm.parameters, tm.row_labels))
    params = dict(model_tm.parameters)
    nm = NumericMatrix(sp.Matrix(model_tm.matrix).subs(params), model_tm.variables,
                       model_tm.angles)
    nm.strokes = _strokes(model, nm)
    method = method_for(tm.shape)
    rng = np.random.default_rng

    # the locus
    say(f"{model.name}: {tm.shape[0]}x{tm.shape[1]} matrix, locus by {method}, seed {seed}")
    locus, status = None, ""
    try:
        # for an augmented matrix, with J's own locus attached and each component classified
        # the locus every command shows: certified, recomputed when its certificate fails
        locus = timed(f"locus ({method})", lambda: certified_locus(
            model, seed=seed, numeric=numeric, should_stop=stopper(), progress=progress,
            jobs=jobs, rank_rtol=rank_rtol)[0])
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
            comparison = timed("method comparison", lambda: compare_loci(
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
            parameters=params, samples=samples, rng=rng(seed), seed=seed, rank_rtol=rank_rtol))
        if exact:
            from ..exact.singular import singular_cross_check

            exact_result = timed("Singular cross-check", lambda: singular_cross_check(
                task_matrix(model, frame="auto", numeric=True), locus, rng=rng(seed)))

    # which components the joint limits let the robot reach
    limits = ()
    if locus is not None:
        from ..limits import within_limits

        limits = timed("joint limits", lambda: within_limits(locus, model, rng=rng(seed)))

    # sample points where the figures can show them: within the limits, lengths within
    # their stroke
    stroke_note = ""
    if locus is not None:
        locus, stroke_note = _samples_within_strokes(model, locus, nm, rng(seed))

    # components, readings, folded equations
    views, notation = (), jac.abbreviations
    if locus is not None:
        views, notation = timed("readings", lambda: _component_views(
            model, model_tm, locus, nm, params, rng(seed), jac))
    # det J of a square J as the product of the components' equations, in the forms shown
    determinant = None
    main = [v for v in views if not v.special]
    if (locus is not None and getattr(locus, "base", None) is None and model_tm.shape[0]
            == model_tm.shape[1] and main
            and all(len(v.component.equations) == 1 for v in main)):
        from ..numeric.factored_det import factored_determinant

        kinds = ["revolute" if v in model_tm.angles else "prismatic" for v in model_tm.variables]
        forms = [v.folded[0] if len(v.folded) == 1 else v.component.equations[0] for v in main]
        spelled = {s: f for s, f in notation}
        determinant = timed("det J factored", lambda: factored_determinant(
            model_tm.matrix, model_tm.variables, kinds,
            [sp.sympify(f, strict=True).subs(spelled) for f in forms], params, rng(seed)))
        if determinant is not None:   # shown in the notation of J, checked spelled out
            determinant = replace(determinant, factors=tuple(forms))
    # the gcd of the maximal minors of a wide or tall J, exactly, within bounds; in the
    # locus frame, where the minors are smallest: another frame and reference point multiply
    # J on the left by a matrix of determinant 1, and every maximal minor by that determinant
    minor_gcd = None
    if (locus is not None and getattr(locus, "base", None) is None
            and tm.shape[0] != tm.shape[1] and min(tm.shape) > 0):
        from ..numeric.factored_det import maximal_minor_gcd

        minor_gcd = timed("gcd of the maximal minors", lambda: maximal_minor_gcd(
            tm.matrix, tm.variables, tm.angles))

    augmented = ()
    base = getattr(locus, "base", None) if locus is not None else None
    if base is not None:
        augmented = tuple(ComponentView(i, c, not c.for_model,
                                        kind=getattr(c, "kind", None))
                          for i, c in enumerate(locus.components + locus.special, start=1))

    # figures
    say(f"{model.name}: figures")
    figures = timed("figures", lambda: report_figures(model, model_tm, locus, nm, params,
                                                      seed, dot, views))
    near = timed("near the locus", lambda: near_data(model, locus, nm, params, seed,
                                                      file_stem(model.name)))
    if near is not None:
        figures = tuple(figures) + near.figures
    tree = tree_summary(locus.tree) if locus is not None and locus.tree is not None else None
    notes = ()
    if locus is not None and tm.frame is not None and (tm.frame, tm.point) != (
            getattr(model, "frame", None), "tool"):
        where = f"link frame {tm.frame}" if isinstance(tm.frame, int) else f"the {tm.frame} frame"
        about = (f", about the origin of link frame {tm.point}" if isinstance(tm.point, int)
                 else "")
        notes = (f"The locus was computed from J in {where}{about}, where its entries are "
                 "smallest; the rank, and so the locus, is the same in every frame. The lost "
                 "directions at the sample points are given in the model's frame.",)
    if stroke_note:
        notes += (stroke_note,)
    return Report(model=model, tm=tm, jacobian=jac, notation=notation, locus=locus,
                  locus_status=status, components=views, second=second,
                  second_status=second_status, comparison=comparison, check=check,
                  exact=exact_result, tree=tree, figures=figures, timings=tuple(timings),
                  seed=seed, samples=samples, timeout=timeout, numeric=numeric,
                  augmented=augmented, notes=notes, model_notes=model_notes, stamp=stamp,
                  near=near, limits=limits, determinant=determinant,
                  minor_gcd=minor_gcd)


def _strokes(model, nm) -> dict:
    """Variable -> the interval a length is plotted over (:func:`~rankloci.limits.joint_strokes`)."""
    from ..limits import joint_strokes
    from ..model import RobotModel

    if not isinstance(model, RobotModel):
        return {}
    return {v: s for v, s in zip(nm.variables, joint_strokes(model)) if v not in nm.angles}


def _samples_within_strokes(model, locus, nm, rng):
    """``locus`` with each sample point moved within the joints' strokes, and a note saying so.

    A sample point of the locus computation can lie outside a joint's limits, or, for a
    prismatic joint without limits, far outside :data:`~rankloci.limits.DEFAULT_STROKE`.
    Where :func:`~rankloci.limits.within_limits` finds a point of the component within the
    strokes (:func:`~rankloci.limits.joint_strokes`), that point becomes the sample the
    report shows, and the lost directions there are recomputed from the SVD of $J$.
    """
    import dataclasses

    from ..limits import DEFAULT_STROKE, joint_strokes, within_limits
    from ..model import RobotModel
    from ..numeric.svd import null_directions

    if not isinstance(model, RobotModel):
        return locus, ""
    if not any(j.kind == "prismatic" or j.limits for j in model.joints):
        return locus, ""
    checks = within_limits(locus, model, rng=rng, box=joint_strokes(model))
    names = [v.name for v in nm.variables]
    tall = nm.shape[0] > nm.shape[1]
    comps, moved = [], []
    for comp, check in zip(locus.components, checks):
        if check.meets and check.sample is not None and check.sample != dict(comp.sample):
            q = np.array([check.sample[n] for n in names], dtype=float)
            changes = dict(sample=dict(check.sample))
            if check.how != "sample point":   # whole turns of an angle leave J as it was
                changes["direction_at_sample"] = null_directions(nm(q), comp.rank_drop, tall)
                moved.append(check.component)
            comp = dataclasses.replace(comp, **changes)
        comps.append(comp)
    prismatic = any(j.kind == "prismatic" and not j.limits for j in model.joints)
    note = ("Sample points are taken within the joint limits"
            + (f", and prismatic joints without limits within [{DEFAULT_STROKE[0]:g}, "
               f"{DEFAULT_STROKE[1]:g}] m" if prismatic else "")
            + (f"; for {_numbered('component', moved)} the locus computation's sample lay "
               "outside, and a point found by bounded least squares replaces it (lost "
               "directions there from the SVD of J)" if moved else "") + ".")
    return dataclasses.replace(locus, components=tuple(comps)), note


def _numbered(word, numbers):
    from .blocks import numbered

    return numbered(word, numbers)


def component_views(model, locus, *, seed: int = 0) -> tuple:
    """The :class:`ComponentView` of each component of ``locus`` (a locus of ``model``).

    What :func:`build_report` says about the components (readings, compact
    forms, lost motions), without the figures and checks.

    Examples
    --------
    >>> import numpy as np
    >>> from rankloci.io import load_model
    >>> from rankloci.jacobians import task_matrix
    >>> from rankloci.methods import compute_locus
    >>> arm = load_model("planar2r")
    >>> locus = compute_locus(task_matrix(arm), "determinant", rng=np.random.default_rng(0))
    >>> print(component_views(arm, locus)[0].summary)  # doctest: +NORMALIZE_WHITESPACE
    All links aligned (the arm is stretched out or folded back): the task point lies in the
    plane of axes 1 and 2
    """
    from ..jacobians import task_matrix
    from ..numeric.equations import NumericMatrix
    from .matrixfmt import jacobian_display

    tm = task_matrix(model)
    jac = jacobian_display(tm.matrix, tm.variables, tm.parameters, tm.row_labels)
    params = dict(tm.parameters)
    nm = NumericMatrix(sp.Matrix(tm.matrix).subs(params), tm.variables, tm.angles)
    return _component_views(model, tm, locus, nm, params, np.random.default_rng(seed), jac)[0]


def _component_views(model, model_tm, locus, nm, params, rng, jac):
    """A :class:`ComponentView` of each component, and the notation the views use."""
    from .mathfmt import abbreviations, angle_sums, compact, latex, math_width
    from .reading import direction_readings, lost_motion

    variables = list(model_tm.variables)
    taken = {str(s) for e in model_tm.matrix for s in e.free_symbols}
    notation = dict((str(s), (s, f)) for s, f in jac.abbreviations)
    tall = model_tm.shape[0] > model_tm.shape[1]
    frame = getattr(model, "frame", "base")
    views = []

    def fold(exprs):
        """Compact forms of all of ``exprs`` in the Jacobian's notation, or () if one has none."""
        out = []
        for e in exprs:
            f = angle_sums(e)
            atoms = sorted(f.atoms(sp.sin, sp.cos), key=sp.default_sort_key)
            ab = abbreviations(variables, taken, atoms)
            g = compact(f.xreplace(ab), list(model_tm.parameters))
            if g.has(sp.sin, sp.cos) or math_width(latex(g)) > 0.8 * math_width(latex(e)):
                return ()
            for fn, s in ab.items():
                if s in g.free_symbols:
                    notation.setdefault(str(s), (s, fn))
            out.append(g)
        return tuple(out)

    for i, c in enumerate(locus.components + locus.special, start=1):
        special = not c.for_model
        folded = fold(c.equations)
        folded_excluding = fold(c.excluding) if folded else ()
        geometry, directions, motions = [], [], []
        summary, named, lost_axis = "", (), ()
        if not special:
            eqs = [e for e in c.equations if e not in c.parameter_conditions] or list(c.equations)
            shown = list(folded) if len(folded) == len(c.equations) else []
            labels = [_equation_label(k, (shown[c.equations.index(e)] if shown else e))
                      for k, e in enumerate(eqs)]
            reading = _reading(model, c, eqs, labels, nm, params, rng)
            if reading is not None:
                named, lost_axis = reading.axes, reading.lost_axis
                geometry = [reading.text] + ([reading.lost_rotation]
                                             if reading.lost_rotation else [])
                first = reading.short or reading.text
                summary = first if len(first) <= SUMMARY_READING_CHARS else (
                    (reading.name[0].upper() + reading.name[1:] + "; " if reading.name else "")
                    + "see the component's subsection")
            q = np.array([c.sample[v.name] for v in nm.variables], dtype=float)
            J = nm(q)
            for vec in c.direction_at_sample:
                directions += direction_readings(J, vec, model_tm.row_labels, tall=tall,
                                                 frame=frame, variables=variables)
                motion = lost_motion(J, vec, model_tm.row_labels, tall=tall,
                                     variables=variables)
                if motion:
                    motions.append(motion)
        short = [r for r in directions if len(r) <= SUMMARY_CHARS]
        summary = summary or (short[0] if short else "")
        equal = ()
        if not special and params:
            equal = tuple(
                replace(f, form=(fold([f.form]) or (f.form,))[0])
                for f in equal_parameter_forms(c.equations, params))
        views.append(ComponentView(i, c, special, tuple(geometry + directions), folded,
                                   folded_excluding, getattr(c, "kind", None), summary,
                                   (summary,) if geometry else (), tuple(motions), named,
                                   lost_axis, equal))
    items = sorted(notation.values(), key=lambda p: _notation_key(p[1], variables))
    return tuple(views), tuple(items)


def _notation_key(f, variables):
    """Abbreviations ordered by the number of angles they sum, then by variable."""
    terms = sp.Add.make_args(f.args[0])
    return (len(terms), [variables.index(t) if t in variables else 99 for t in terms],
            isinstance(f, sp.sin))


_ORDINALS = ("first", "second", "third", "fourth", "fifth", "sixth", "seventh", "eighth")


def _equation_label(k: int, e) -> str:
    """How a reading names equation ``k`` (0-based): inline math when short, else its ordinal."""
    from .mathfmt import latex, math_width

    text = f"{latex(e)} = 0"
    if math_width(text) <= READING_EQUATION_WIDTH:
        return f"${text}$"
    word = _ORDINALS[k] if k < len(_ORDINALS) else f"number {k + 1}"
    return f"the {word} equation"


def _reading(model, comp, eqs, labels, nm, params, rng):
    """The :class:`~rankloci.reporting.interpret.Reading` of one component (or None)."""
    from ..model import RobotModel
    from ..numeric.landscape import reading_points
    from .interpret import component_reading

    if not isinstance(model, RobotModel):
        return None
    names = [v.name for v in nm.variables]
    pts, factor_points = reading_points(comp, eqs, nm, params, rng)
    return component_reading(model, eqs, labels, pts, factor_points, rng, params,
                             matrix=lambda d: nm(np.array([d[n] for n in names])))
