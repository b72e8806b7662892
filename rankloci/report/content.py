"""The report as a list of blocks, shared by the Markdown and the LaTeX renderers.

:func:`report_blocks` decides *what* the report says, section by section, as
plain data (:class:`Heading`, :class:`Para`, :class:`Math`, :class:`Table`,
...); :mod:`~rankloci.report.markdown` and :mod:`~rankloci.report.latex` only
decide how each block is spelled.  Text in blocks may hold ``$math$`` and
```code``` segments.  Everything here is pure.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .mathfmt import LINE_WIDTH, broken_lines, latex, math_width, trig_latex, value_latex

__all__ = ["Heading", "Para", "Math", "Table", "Bullets", "Figure", "Code", "Marker",
           "report_blocks"]


# --- blocks ------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Heading:
    level: int            # 1 title, 2 section, 3 subsection
    text: str
    label: str = ""


@dataclass(frozen=True)
class Para:
    text: str
    lead: str = ""        # a bold run-in heading such as "Source."


@dataclass(frozen=True)
class Math:
    """Displayed math: one line, or several aligned at ``&`` (``aligned=True``)."""

    lines: tuple
    aligned: bool = False


@dataclass(frozen=True)
class Table:
    header: tuple
    rows: tuple
    align: str = ""       # one of l, r, c per column
    caption: str = ""


@dataclass(frozen=True)
class Bullets:
    items: tuple


@dataclass(frozen=True)
class Figure:
    file: str
    caption: str
    label: str
    tall: bool = False
    alt: str = ""         # a short plain-text description (Markdown's image text)


@dataclass(frozen=True)
class Code:
    text: str
    language: str = ""


@dataclass(frozen=True)
class Marker:
    """A comment in the output, such as the start and end of the timings."""

    text: str


# --- helpers -----------------------------------------------------------------------------------

SIGMA = r"$\sigma_{\min}/\sigma_{\max}$"


def _m(expr) -> str:
    return f"${sp.latex(expr, fold_short_frac=True)}$"


def _num(x, digits=6) -> str:
    return f"{float(x):.{digits}g}"


def _equation_math(exprs, *, width: float = LINE_WIDTH) -> Math:
    """``e = 0`` for each expression, broken between terms where a line is too wide."""
    parts = [broken_lines(e, tail=" = 0", width=width) for e in exprs]
    if len(parts) == 1 and len(parts[0]) == 1:
        return Math((parts[0][0],))
    if all(len(p) == 1 for p in parts):
        return Math(tuple(latex(e) + " &= 0" for e in exprs), aligned=True)
    lines = []
    for p in parts:
        lines.append("&" + p[0])
        lines += [r"&\quad " + x for x in p[1:]]
    return Math(tuple(lines), aligned=True)


def _vars_text(variables) -> str:
    return ("$" + ", ".join(latex(v) for v in variables) + "$") if variables else "none"


def _solved(comp) -> str:
    parts = []
    for q, vals in comp.solved.items():
        vs = ", ".join(value_latex(v) for v in vals)
        parts.append(f"${latex(q)} \\in \\lbrace {vs} \\rbrace$" if len(vals) > 1
                     else f"${latex(q)} = {vs}$")
    return "; ".join(parts)


def _direction_cells(vec, labels):
    return ", ".join(f"{lab} {x:+.3f}" for lab, x in zip(labels, vec))


def _label(report, *parts) -> str:
    return ":".join(("rankloci", report.name) + tuple(str(p) for p in parts))


# --- sections ----------------------------------------------------------------------------------

def report_blocks(report, *, timings: bool = True) -> list:
    """The blocks of ``report``, in order."""
    out = [Heading(1, f"Singularity report: {report.model.title or report.name} "
                      f"(`{report.name}`)", _label(report))]
    out += _summary(report)
    out += _model_section(report)
    out += _jacobian_section(report)
    out += _locus_section(report)
    out += _figure_section(report)
    out += _tree_section(report)
    out += _check_section(report)
    out += _comparison_section(report)
    out += _augmented_section(report)
    if timings and report.timings:
        out += _timings_section(report)
    out += _reproduce_section(report)
    return out


def _summary(report):
    tm = report.tm
    rows, cols = tm.shape
    kind = "robot" if hasattr(report.model, "joints") else "matrix"
    text = (f"This report gives the configurations at which the {rows}x{cols} "
            f"{'Jacobian' if kind == 'robot' else 'matrix'} $J$ of `{report.name}` loses rank, "
            "in closed form, with a numeric check of each piece.")
    blocks = [Para(text)]
    if report.stamp:
        blocks.append(Para(f"Written {report.stamp}."))
    if report.locus is None:
        blocks.append(Para(report.locus_status, lead="Locus not finished."))
        return blocks
    comps = [v for v in report.components if not v.special]
    special = [v for v in report.components if v.special]
    bits = [f"The {report.locus.method} method finds {len(comps)} component(s) for the model's "
            "parameter values"]
    if special:
        bits.append(f" and {len(special)} more that exist only for special parameter values")
    bits.append(".")
    if report.check is not None:
        ok = report.check.ok and (report.exact is None or report.exact.status != "disagree")
        bits.append(" The numeric cross-check " + ("passes." if ok else "FAILS."))
    if report.comparison is not None:
        bits.append(" The svm and subdeterminant methods "
                    + ("agree." if report.comparison.agree else "disagree (see the method comparison)."))
    if report.locus.degenerate:
        bits.append(" The matrix is rank deficient at every configuration (degenerate design).")
    blocks.append(Para("".join(bits)))
    named = [(v.index, v.summary) for v in comps if v.summary]
    if named:
        blocks.append(Bullets(tuple(f"Component {i}: {r}." for i, r in named)))
    return blocks


def _model_section(report):
    from ..model import RobotModel

    m = report.model
    out = [Heading(2, "The model", _label(report, "model"))]
    if m.source:
        out.append(Para(" ".join(m.source.split()), lead="Source."))
    notes = report.model_notes
    if notes:
        out.append(Para(" ".join(notes.split()), lead="Notes."))
    if isinstance(m, RobotModel):
        out += _joint_table(report, m)
    else:
        out.append(Para(f"A symbolic {m.matrix.rows}x{m.matrix.cols} matrix in the variables "
                        f"{_vars_text(m.variables)}; the angles (entering through sine and "
                        f"cosine only) are {_vars_text(report.tm.angles)}."))
    if m.parameters:
        out.append(Heading(3, "Parameters"))
        rows = tuple((_m(k), _num(v)) for k, v in sorted(m.parameters.items(),
                                                          key=lambda kv: kv[0].name))
        out.append(Table(("parameter", "value"), rows, "lr"))
        out.append(Para("Lengths in metres (the planar arms have unit links). The parameters "
                        + ("are replaced by these values before the algebra."
                           if report.numeric else
                           "stay symbols in the algebra; the values are used for the sample "
                           "points, the checks and the figures.")))
    out += _task_section(report, m)
    return out


def _joint_table(report, m):
    out = []
    if all(j.dh is not None for j in m.joints):
        conv = m.joints[0].dh.convention
        formula = ("$T_i = R_z(\\theta_i) T_z(d_i) T_x(a_i) R_x(\\alpha_i)$" if conv == "dh"
                   else "$T_i = R_x(\\alpha_{i-1}) T_x(a_{i-1}) R_z(\\theta_i) T_z(d_i)$")
        name = "standard" if conv == "dh" else "modified (Craig)"
        out.append(Heading(3, "Denavit-Hartenberg table"))
        out.append(Para(f"{name.capitalize()} DH convention, {formula}."))
        rows = []
        for i, (j, q) in enumerate(zip(m.joints, m.variables), start=1):
            theta = j.dh.theta + q if j.kind == "revolute" else j.dh.theta
            d = j.dh.d + q if j.kind == "prismatic" else j.dh.d
            rows.append((str(i), j.kind, _m(theta), _m(d), _m(j.dh.a), _m(j.dh.alpha)))
        out.append(Table(("joint", "type", "$\\theta$", "$d$", "$a$", "$\\alpha$"),
                         tuple(rows), "llcccc"))
    else:
        out.append(Heading(3, "Joints"))
        rows = []
        for i, (j, q) in enumerate(zip(m.joints, m.variables), start=1):
            pre = sp.Matrix(j.pre)
            xyz = ", ".join(_num(float(pre[k, 3].subs(m.parameters)), 4) for k in range(3))
            axis = ", ".join(_num(float(sp.sympify(a).subs(m.parameters)), 4) for a in j.axis)
            lim = (f"[{j.limits[0]:.4g}, {j.limits[1]:.4g}]" if j.limits else "none")
            rows.append((str(i), f"`{j.name}`" if j.name else "-", j.kind, _m(q),
                         f"({xyz})", f"({axis})", lim))
        out.append(Table(("joint", "name", "type", "variable", "origin xyz", "axis", "limits"),
                         tuple(rows), "lllcccc"))
        out.append(Para("Origins are the translations of the fixed transform before each "
                        "joint's motion; axes are in the joint's frame."))
    return out


def _task_section(report, m):
    from ..model import RobotModel

    tm = report.tm
    out = [Heading(3, "Task, frame and constraint rows")]
    labels = ", ".join(f"`{r}`" for r in tm.row_labels)
    items = [f"Rows of $J$: {labels}."]
    if isinstance(m, RobotModel):
        items.append(f"Rows `vx vy vz` are the linear velocity of the task point (the origin of "
                     f"the tool frame), `wx wy wz` the angular velocity; the model expresses "
                     f"them in the {m.frame} frame.")
        for what, T in (("base", m.base), ("tool", m.tool)):
            T = sp.Matrix(T)
            if T != sp.eye(4):
                xyz = ", ".join(_num(float(T[k, 3].subs(m.parameters)), 4) for k in range(3))
                items.append(f"A constant {what} transform with translation ({xyz}) is part "
                             "of the chain.")
    if m.augment:
        for name, g in m.augment:
            items.append(f"Constraint row `{name}`: the gradient of $g(q) = {latex(g)}$.")
    items.append(f"Joint variables (columns): {_vars_text(tm.variables)}.")
    out.append(Bullets(tuple(items)))
    return out


def _jacobian_section(report):
    tm, jd = report.tm, report.jacobian
    out = [Heading(2, "The symbolic Jacobian", _label(report, "jacobian"))]
    own = (getattr(report.model, "frame", None), "tool")
    if tm.frame is not None and (tm.frame, tm.point) == own:
        out.append(Para(f"$J$ is shown as the locus was computed from it: in the model's own "
                        f"frame (the {tm.frame} frame), rows the velocity of the task point."))
    elif tm.frame is not None:
        where = (f"link frame {tm.frame}" if isinstance(tm.frame, int) else f"the {tm.frame} frame")
        about = (f", with the velocity taken at the origin of link frame {tm.point}"
                 if isinstance(tm.point, int) else "")
        out.append(Para(f"$J$ is shown as the locus was computed from it: expressed in {where}"
                        f"{about}, where its entries are smallest. A change of frame (and, "
                        "for the full six-row task, of reference point) multiplies $J$ by an "
                        "invertible matrix, so its rank and its singular configurations are "
                        "those of the model's own $J$."))
    if report.notation:
        defs = ", ".join(f"${latex(s)} = {trig_latex(f)}$" for s, f in report.notation)
        out.append(Para(f"Notation: {defs}.", lead=""))
    out += _matrix_blocks(jd)
    if jd.definitions:
        out.append(Para("where the common subexpressions are"))
        lines = []
        for s, e in jd.definitions:
            parts = broken_lines(e, lead=f"{latex(s)} &= ")
            lines.append(parts[0])
            lines += [r"&\quad " + p for p in parts[1:]]
        out.append(Math(tuple(lines), aligned=True))
    return out


def _matrix_blocks(jd):
    rows, cols = jd.shape
    if jd.layout == "matrix":
        body = r" \\ ".join(" & ".join(latex(e) for e in row) for row in jd.entries)
        return [Math((r"J = \begin{bmatrix} " + body + r" \end{bmatrix}",))]
    out = [Para(f"$J$ is too wide for one line; it is shown column by column, "
                f"$J = \\begin{{bmatrix}} \\boldsymbol{{j}}_{{1}} & \\cdots & "
                f"\\boldsymbol{{j}}_{{{cols}}} \\end{{bmatrix}}$, the column of each joint "
                f"variable.")]
    group, width = [], 0.0
    wide = []

    def flush():
        if group:
            out.append(Math((r",\quad ".join(group),)))
            group.clear()

    for j in range(cols):
        col = [jd.entries[i][j] for i in range(rows)]
        w = max(math_width(latex(e)) for e in col) + 5.0
        if w > LINE_WIDTH:
            wide.append(j)
            continue
        text = (rf"\boldsymbol{{j}}_{{{j + 1}}} = \begin{{bmatrix}} "
                + r" \\ ".join(latex(e) for e in col) + r" \end{bmatrix}")
        if group and width + w + 2 > LINE_WIDTH:
            flush()
            width = 0.0
        group.append(text)
        width += w + 2
    flush()
    for j in wide:
        out.append(Para(f"Column {j + 1} (non-zero entries):"))
        lines = []
        for i in range(rows):
            e = jd.entries[i][j]
            if e == 0:
                continue
            parts = broken_lines(e, lead=f"J_{{{i + 1},{j + 1}}} &= ")
            lines.append(parts[0])
            lines += [r"&\quad " + p for p in parts[1:]]
        out.append(Math(tuple(lines), aligned=True))
    return out


def _component_blocks(report, view):
    c = view.component
    out = [Heading(3, f"Component {view.index}", _label(report, "component", view.index))]
    eqs = [e for e in c.equations if e not in c.parameter_conditions] or list(c.equations)
    out.append(_equation_math(eqs))
    if view.folded and list(view.folded) != eqs:
        out.append(Para("Equivalently, in the notation of the Jacobian section:"))
        out.append(_equation_math(view.folded))
    items = []
    if c.solved:
        items.append(f"Solved: {_solved(c)}.")
    n = len(report.tm.variables)
    items.append(f"Dimension {c.dimension} in the {n}-dimensional joint space; rank drop "
                 f"{c.rank_drop}; free joint variables: {_vars_text(c.free)}.")
    if view.kind:
        items.append(f"Kind: {view.kind}.")
    if c.parameter_conditions:
        conds = ", ".join(f"${latex(e)} = 0$" for e in c.parameter_conditions)
        items.append(f"Exists only when {conds} (not the model's values).")
    elif not c.for_model:
        items.append("Has no real point for the model's parameter values.")
    if c.excluding:
        ex = ", ".join(f"${latex(e)} \\neq 0$" for e in c.excluding)
        items.append(f"The closure of the set where the equations hold and {ex}.")
    labels = list(report.tm.row_labels)
    tall = report.tm.shape[0] > report.tm.shape[1]
    over = [str(v) for v in report.tm.variables] if tall else labels
    for vec in c.direction_at_sample:
        what = "Lost joint direction (right null vector)" if tall else "Lost direction"
        items.append(f"{what} at the sample point: ({', '.join(f'{x:+.3f}' for x in vec)}) "
                     f"over ({', '.join(over)}).")
    if not c.direction_at_sample and c.direction:
        items.append("Lost direction: $(" + ", ".join(latex(x) for x in c.direction[0]) + ")$.")
    sample = ", ".join(f"{k} = {v:+.4f}" for k, v in c.sample.items())
    items.append(f"Sample point: {sample}.")
    out.append(Bullets(tuple(items)))
    if view.readings:
        out.append(Para("At the sample point (verified numerically):", lead="Reading."))
        out.append(Bullets(tuple(r[0].upper() + r[1:] + "." for r in view.readings)))
    plain = ",  ".join(f"{sp.sstr(e)} = 0" for e in c.equations)
    out.append(Code(plain))
    return out


def _locus_section(report):
    out = [Heading(2, "The singularity locus", _label(report, "locus"))]
    if report.locus is None:
        out.append(Para(report.locus_status, lead="Not computed."))
        out.append(Para("The model, the Jacobian and the heat maps are still given; rerun with a larger `--timeout` (or `--numeric-parameters`) "
                        "for the rest."))
        return out
    loc = report.locus
    out.append(Para(f"Method: {loc.method} (seed {report.seed}). Each component is the set "
                    "where its equations vanish; the rank drop is how many ranks $J$ loses "
                    "at its generic points, and the lost directions span the left null space "
                    "of $J$ there (the task velocities no joint velocity produces)."))
    main = [v for v in report.components if not v.special]
    special = [v for v in report.components if v.special]
    if main:
        rows = []
        for v in main:
            c = v.component
            first = v.summary or "-"
            rows.append((str(v.index), str(c.dimension), str(c.rank_drop),
                         _vars_text(c.free), first))
        out.append(Table(("no.", "dim.", "rank drop", "free joints", "reading"),
                         tuple(rows), "rrrll"))
    else:
        out.append(Para("No component exists for the model's parameter values: $J$ has full "
                        "rank everywhere."))
    for v in main:
        out += _component_blocks(report, v)
    if special:
        out.append(Heading(3, "Components for special parameter values"))
        out.append(Para("These exist only for parameter values other than the model's; they "
                        "are listed for designers who may change the geometry."))
        for v in special:
            out += _component_blocks(report, v)
    notes = list(loc.notes) + list(report.notes)
    if notes:
        out.append(Heading(3, "Notes of the analysis"))
        out.append(Bullets(tuple(n[0].upper() + n[1:] + ("" if n.endswith(".") else ".")
                                 for n in notes)))
    return out


def _figure_section(report):
    sig = report.figure("sigma")
    man = report.figure("manipulability")
    if not sig and not man:
        return []
    out = [Heading(2, "Singularity maps", _label(report, "maps"))]
    how = ("through a point of a component, the other joints fixed; the two joints are those "
           "the component's equations use most, ties broken by how much the ratio changes "
           "along each" if report.components else
           "through one configuration, the other joints fixed; the two joints are those along "
           "which the ratio changes most")
    out.append(Para(f"The heat maps show {SIGMA} of $J$ (the model's own frame and "
                    "task point, parameters at the model's values) over two-joint slices of "
                    f"joint space {how}. It is zero exactly on the locus. Its values depend on "
                    "the length unit when $J$ mixes linear and angular rows."))
    for k, f in enumerate(sig, start=1):
        out.append(Figure(f.name, f.caption, _label(report, "fig", f"sigma{k}"), alt=f.title))
    for f in man:
        out.append(Figure(f.name, f.caption, _label(report, "fig", "manipulability"),
                          alt=f.title))
    return out


def _tree_section(report):
    tree = report.tree
    figs = report.figure("tree")
    if tree is None:
        return []
    out = [Heading(2, "Branch tree", _label(report, "tree"))]
    out.append(Para(f"The {report.locus.method} method grows a tree of branches; each leaf "
                    "stops for the reason shown. The tree has "
                    f"{tree.total_nodes} node(s)."))
    rows = tuple((reason or "(none)", str(n)) for reason, n in sorted(tree.outcomes.items()))
    out.append(Table(("stop reason of the leaves", "leaves"), rows, "lr"))
    for f in figs:
        out.append(Figure(f.name, f.caption, _label(report, "fig", "tree"), tall=True,
                          alt=f.title))
    return out


def _check_section(report):
    chk = report.check
    if chk is None:
        return []
    out = [Heading(2, "Numeric cross-check", _label(report, "check"))]
    out.append(Para(f"As `rankloci check {report.name} --samples {report.samples} --seed "
                    f"{report.seed}`: $J$ in the model's frame, parameters at their values, "
                    f"decided by the SVD (rank deficient when {SIGMA} is at most "
                    f"{chk.thresholds.get('RANK_RTOL', 1e-8):g}). On-locus: points solved onto "
                    "each component must be singular. Off-locus: random configurations away "
                    "from every component must be regular. Completeness: minima of "
                    f"{SIGMA} from random starts that are singular must lie on a "
                    "component."))
    rows = []
    for c in chk.components:
        detail = c.message or f"largest sigma ratio {c.max_ratio:.1e}"
        rows.append((f"on component {c.index}", str(len(c.points)), "pass" if c.ok else "FAIL",
                     detail))
    for eqs in chk.skipped:
        rows.append(("on " + ", ".join(eqs)[:40], "-", "skip", "special parameter values"))
    mn = min((p.sigma_ratio for p in chk.off_locus), default=float("nan"))
    rows.append(("off-locus (regular)", str(len(chk.off_locus)),
                 "pass" if not chk.off_locus_failures else "FAIL",
                 f"{len(chk.off_locus_failures)} singular; smallest sigma ratio {mn:.1e}"))
    rows.append(("completeness probe", str(chk.probe_starts),
                 "pass" if not chk.uncovered else "FAIL",
                 f"{chk.probe_singular} singular minima, {len(chk.uncovered)} on no component"))
    if report.exact is not None:
        ex = report.exact
        rows.append(("Singular (exact primes)", "-", ex.status, ex.reason))
    out.append(Table(("check", "points", "result", "detail"), tuple(rows), "lrll",
                     caption=f"seed {chk.seed}, {chk.samples} samples"))
    out.append(Para(f"Result: {'PASS' if chk.ok else 'FAIL'} (seed {chk.seed})."))
    if chk.findings:
        out.append(Para(f"{len(chk.findings)} finding(s) where the FSP reducer or the largest "
                        "maximal minor disagrees with the SVD (recorded, not failures; the SVD "
                        "decides):"))
        items = list(chk.findings[:10])
        if len(chk.findings) > 10:
            items.append(f"... and {len(chk.findings) - 10} more")
        out.append(Bullets(tuple(items)))
    for p in chk.uncovered[:5]:
        out.append(Para("Uncovered singular point: (" + ", ".join(f"{x:+.6f}" for x in p.q)
                        + f"), sigma ratio {p.sigma_ratio:.1e}."))
    return out


def _comparison_section(report):
    if report.locus is None:
        return []
    out = [Heading(2, "Method comparison", _label(report, "methods"))]
    tm = report.tm
    if tm.shape[0] == tm.shape[1]:
        out.append(Para("$J$ is square, so the determinant method is the only one: the "
                        "singular vector and subdeterminant methods both reduce to "
                        "$\\det J = 0$ here."))
        return out
    loc, sec = report.locus, report.second
    rows = [(loc.method, str(len([c for c in loc.components if c.for_model
                                  and not c.parameter_conditions])),
             str(loc.tree.number_of_nodes() if loc.tree is not None else "-"))]
    if sec is not None:
        rows.append((sec.method, str(len([c for c in sec.components if c.for_model
                                          and not c.parameter_conditions])),
                     str(sec.tree.number_of_nodes() if sec.tree is not None else "-")))
    out.append(Table(("method", "components (model values)", "tree nodes"), tuple(rows), "lrr"))
    cmp = report.comparison
    if cmp is None:
        out.append(Para(report.second_status or "The second method was not run."))
        return out
    if cmp.identical:
        text = ("The two methods give the same components, equation for equation.")
    elif cmp.agree:
        text = (f"The two methods write the locus differently but describe the same set: each "
                f"of the {cmp.points_tested} points tested on a component of one lies on a "
                "component of the other.")
    else:
        text = "The two methods disagree:"
    out.append(Para(text))
    if cmp.differences:
        out.append(Bullets(tuple(cmp.differences)))
    if not cmp.special_same:
        out.append(Para("Their components for special parameter values differ; those are side "
                        "results of where each method's branching meets a parameter factor, "
                        "not part of the model's locus."))
    return out


def _augmented_section(report):
    if not report.augmented:
        return []
    out = [Heading(2, "Algorithmic singularities", _label(report, "algorithmic"))]
    out.append(Para("$J$ is augmented with constraint rows. A component where $J$ without those "
                    "rows already loses rank is kinematic; one where only the augmented matrix "
                    "does is algorithmic (the constraint, not the arm, fails there); mixed "
                    "components have both."))
    rows = []
    for v in report.augmented:
        c = v.component
        eqs = ", ".join(f"${latex(e)} = 0$" for e in c.equations)
        kind = v.kind or ("special parameter values" if v.special else "not classified")
        meets = sorted({m.get("base_component") for m in getattr(c, "meets", ())
                        if isinstance(m, dict)} - {None})
        if meets:
            kind += f" (meets component{'s' if len(meets) > 1 else ''} " \
                    f"{', '.join(map(str, meets))} of the locus of $J$)"
        rows.append((str(v.index), eqs, kind))
    out.append(Table(("no.", "equations", "kind"), tuple(rows), "rll"))
    base = getattr(report.locus, "base", None)
    if base is not None:
        comps = [c for c in base.components if c.for_model and not c.parameter_conditions]
        out.append(Para(f"The locus of $J$ without the constraint rows ({base.shape[0]}x"
                        f"{base.shape[1]}, {base.method} method) has {len(comps)} "
                        "component(s) for the model's values:"))
        if comps:
            out.append(Bullets(tuple(
                f"Component {i} of $J$: " + ", ".join(f"${latex(e)} = 0$" for e in c.equations)
                for i, c in enumerate(base.components, start=1) if c in comps)))
    for f in report.figure("augmented"):
        out.append(Figure(f.name, f.caption, _label(report, "fig", "augmented"), alt=f.title))
    return out


def _timings_section(report):
    rows = tuple((label, f"{sec:.2f}") for label, sec in report.timings)
    total = sum(sec for _, sec in report.timings)
    rows += (("total", f"{total:.2f}"),)
    return [Heading(2, "Timings", _label(report, "timings")),
            Marker("timings: these vary from run to run; everything else is fixed by the seed"),
            Para("Wall-clock seconds on the machine that wrote this report (they vary from run "
                 "to run; everything else in the report is fixed by the seed)."),
            Table(("step", "seconds"), rows, "lr"),
            Marker("end of timings")]


def _reproduce_section(report):
    args = [f"rankloci report {report.name}", f"--seed {report.seed}",
            f"--samples {report.samples}"]
    if report.numeric:
        args.append("--numeric-parameters")
    if report.timeout:
        args.append(f"--timeout {report.timeout:g}")
    return [Heading(2, "Reproducing this report", _label(report, "reproduce")),
            Code(" ".join(args), "sh"),
            Para(f"rankloci {_version()}; the report depends only on the model, the options and "
                 "the seed (the timings aside).")]


def _version() -> str:
    from .. import __version__

    return __version__
