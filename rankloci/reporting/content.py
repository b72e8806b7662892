"""The report as a list of blocks, shared by the Markdown and the LaTeX renderers.

:func:`report_blocks` decides *what* the report says, section by section, as
plain data (the blocks of :mod:`~rankloci.reporting.blocks`);
:mod:`~rankloci.reporting.markdown` and :mod:`~rankloci.reporting.latex` only
decide how each block is spelled.  This module writes the summary, the model,
the symbolic Jacobian and the appendix (timings, how to reproduce the report);
:mod:`~rankloci.reporting.findings` the sections on the locus and its checks.
Everything here is pure.
"""

from __future__ import annotations

import sympy as sp

from ..expr import as_expression
from .blocks import (Appendix, Bullets, Code, Heading, Marker, Math, Para, Table, block_label,
                     counted, numbered, plural, variables_text)
from .escape import literal, ref
from .findings import appendix_findings, caveats, findings_blocks
from .mathfmt import LINE_WIDTH, broken_lines, latex, math_width, scaled_integers, trig_latex

__all__ = ["report_blocks", "matrix_blocks", "comparison_headline", "summary_table",
           "limits_sentence", "limits_text", "SUMMARY_EQUATION_WIDTH"]


def _m(expr) -> str:
    """An expression as inline math."""
    return f"${scaled_integers(sp.latex(expr, fold_short_frac=True))}$"


def _num(x, digits=6) -> str:
    """A number with ``digits`` significant digits."""
    return f"{float(x):.{digits}g}"


# --- sections ----------------------------------------------------------------------------------

def report_blocks(report, *, timings: bool = True) -> list:
    """The blocks of ``report``, in order."""
    title = literal(report.model.title) if report.model.title.strip() else report.name
    out = [Heading(1, f"Singularity report: {title} (`{report.name}`)", block_label(report))]
    out += _summary(report)
    out += _model_section(report)
    out += findings_blocks(report)
    out += _reproduce_section(report)
    out.append(Appendix())
    out += _jacobian_section(report)
    if timings and report.timings:   # before the tree and the notes: never a last page alone
        out += _timings_section(report)
    out += appendix_findings(report)
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
    bits = [f"The {report.locus.method} method finds {counted(len(comps), 'component')} for the "
            "model's parameter values"]
    if special:
        bits.append(f" and {len(special)} more that {'exists' if len(special) == 1 else 'exist'} "
                    "only for special parameter values")
    bits.append(".")
    if report.check is not None:
        ok = report.check.ok and (report.exact is None or report.exact.status != "disagree")
        bits.append(" The numeric cross-check " + ("passes." if ok else "FAILS."))
    if report.comparison is not None:
        bits.append(" " + comparison_headline(report.comparison))
    if report.locus.degenerate:
        bits.append(" The matrix is rank deficient at every configuration (degenerate design).")
    blocks.append(Para("".join(bits)))
    said = caveats(report)
    if said:
        blocks.append(Para(" ".join(said) + " Details are in the appendix.", lead="Caveats."))
    if comps:
        blocks.append(summary_table(report, comps))
        if hasattr(report.model, "joints"):
            blocks.append(Para(limits_sentence(report), lead="Joint limits."))
    return blocks


#: An equation wider than this (in :func:`~rankloci.reporting.mathfmt.math_width` units) is not
#: written out in the summary table, which points to the component's subsection instead: one
#: line of its equations column (0.3 of the line width in small type).  Each equation is kept
#: on one line, so that a reader never has to join "... =" and "0".
SUMMARY_EQUATION_WIDTH = 21.0


#: What stands for the equations of a component without any: J is rank deficient everywhere
#: (an all-zero matrix, a joint that never moves the tool).
EVERY_CONFIGURATION = "none (every configuration)"


def summary_table(report, views) -> Table:
    """One row per component: its equations with their side conditions, its geometric reading,
    the motion it loses and the figures that show it; each number links to its subsection."""
    from .findings import component_figures

    rows = []
    for v in views:
        c = v.component
        label = block_label(report, "component", v.index)
        eqs = list(v.folded) or [e for e in c.equations if e not in c.parameter_conditions]
        cells = [(e, "= 0") for e in eqs]
        cells += [(x, "\\neq 0") for x in (v.folded_excluding or c.excluding)]
        parts = []
        for e, rel in cells:
            text = f"{latex(e)} {rel}"
            if math_width(text) <= SUMMARY_EQUATION_WIDTH:
                parts.append(f"${{{text}}}$")   # braced: LaTeX does not break it
            else:
                terms = len(sp.Add.make_args(sp.expand(e)))
                what = "equation" if rel == "= 0" else "side condition"
                where = ref(label, f"component {v.index}")
                parts.append(f"an {what} of {terms} terms (see {where})")
        figs = component_figures(report, v.index)
        row = (ref(label, str(v.index)), ", ".join(parts) or EVERY_CONFIGURATION,
               "; ".join(v.geometry) or "-", "; ".join(v.motions) or "-",
               ", ".join(ref(lab, "Fig.", figure=True) for lab, _ in figs) or "-")
        if report.has_limits:
            check = report.limit_check(v.index)
            row += (check.word if check is not None else "-",)
        rows.append(row)
    if report.has_limits:
        return Table(("no.", "equations", "reading", "lost motion", "figures", "within limits"),
                     tuple(rows), "rlllll", widths=(0, 0.25, 0.21, 0.18, 0.07, 0.07), small=True)
    return Table(("no.", "equations", "reading", "lost motion", "figures"), tuple(rows),
                 "rllll", widths=(0, 0.30, 0.24, 0.21, 0.08), small=True)


def limits_sentence(report) -> str:
    """What the joint limits leave of the locus, in one or two sentences."""
    if not report.has_limits:
        return ("The model gives no joint limits, so every component is reachable; with "
                "limits (`limits = [lo, hi]` per joint) the report says which components the "
                "robot can reach.")
    checks = [c for c in report.limits]
    outside = [c.component for c in checks if c.meets is False]
    open_ = [c.component for c in checks if c.meets is None]
    inside = [c.component for c in checks if c.meets is True]
    bits = []
    if inside:
        bits.append(f"{numbered('component', inside).capitalize()} "
                    f"{'meets' if len(inside) == 1 else 'meet'} the joint-limit box (a point "
                    "inside the limits is given in each component's subsection)")
    if outside:
        bits.append(f"{numbered('component', outside)} {'lies' if len(outside) == 1 else 'lie'} "
                    "outside it (decided exactly: a joint is fixed at values outside its "
                    "limits), so the robot never reaches "
                    f"{'it' if len(outside) == 1 else 'them'}")
    if open_:
        bits.append(f"for {numbered('component', open_)} no point inside the limits was found "
                    "by a numeric search (not a proof that there is none)")
    text = "; ".join(bits)
    return text[0].upper() + text[1:] + "." if text else ""


def comparison_headline(cmp) -> str:
    """One sentence on whether the two methods agree and, if not, which one the SVD sides with.

    Examples
    --------
    >>> from rankloci.compare import Comparison, Disagreement
    >>> d = Disagreement("subdeterminant", "svm", 2, ("q1 = 0",), 5, ((0.0, 1.0),), (0.3,))
    >>> cmp = Comparison(("svm", "subdeterminant"), False, False, ("",), disagreements=(d,))
    >>> print(comparison_headline(cmp))  # doctest: +NORMALIZE_WHITESPACE
    The svm and subdeterminant methods disagree; the SVD at the points where they differ
    sides with the svm locus (see the method comparison).
    """
    a, b = cmp.methods
    if cmp.agree:
        return f"The {a} and {b} methods agree."
    if cmp.right:
        return (f"The {a} and {b} methods disagree; the SVD at the points where they differ "
                f"sides with the {cmp.right[0]} locus (see the method comparison).")
    if cmp.disagreements:
        return (f"The {a} and {b} methods disagree, and the SVD at the points where they differ "
                "finds each locus wrong somewhere (see the method comparison).")
    return f"The {a} and {b} methods disagree (see the method comparison)."


def _model_section(report):
    from ..model import RobotModel

    m = report.model
    out = [Heading(2, "The model", block_label(report, "model"))]
    if m.source:
        out.append(Para(literal(m.source), lead="Source."))
    notes = report.model_notes
    if notes:
        out.append(Para(literal(notes), lead="Notes."))
    if isinstance(m, RobotModel):
        out += _joint_table(report, m)
    else:
        out.append(Para(f"A symbolic {m.matrix.rows}x{m.matrix.cols} matrix in the variables "
                        f"{variables_text(m.variables)}; the angles (entering through sine and "
                        f"cosine only) are {variables_text(report.tm.angles)}."))
    if m.parameters:
        out.append(Heading(3, "Parameters"))
        rows = tuple((_m(k), _num(v)) for k, v in sorted(m.parameters.items(),
                                                          key=lambda kv: kv[0].name))
        out.append(Table(("parameter", "value"), rows, "lr"))
        out.append(Para(_units_sentence(m) + " The parameters "
                        + ("are replaced by these values before the algebra."
                           if report.numeric else
                           "stay symbols in the algebra; the values are used for the sample "
                           "points, the checks and the figures.")))
    out += _task_section(report, m)
    return out


def _units_sentence(m) -> str:
    """How to read the parameter values: unit links, or lengths in metres."""
    from ..model import RobotModel

    if not isinstance(m, RobotModel):
        return "The values are in the units of the matrix entries."
    if all(as_expression(v) == 1 for v in m.parameters.values()):
        return "Every link length is 1 (unit links), so the values carry no unit."
    return "Lengths in metres."


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
        limited = any(j.limits for j in m.joints)
        for i, (j, q) in enumerate(zip(m.joints, m.variables), start=1):
            theta = j.dh.theta + q if j.kind == "revolute" else j.dh.theta
            d = j.dh.d + q if j.kind == "prismatic" else j.dh.d
            rows.append((str(i), j.kind, _m(theta), _m(d), _m(j.dh.a), _m(j.dh.alpha))
                        + ((limits_text(j),) if limited else ()))
        out.append(Table(("joint", "type", "$\\theta$", "$d$", "$a$", "$\\alpha$")
                         + (("limits",) if limited else ()), tuple(rows),
                         "llcccc" + ("c" if limited else "")))
    else:
        out.append(Heading(3, "Joints"))
        rows = []
        for i, (j, q) in enumerate(zip(m.joints, m.variables), start=1):
            pre = sp.Matrix(j.pre)
            xyz = ", ".join(_num(float(pre[k, 3].subs(m.parameters)), 4) for k in range(3))
            axis = ", ".join(_num(float(as_expression(a).subs(m.parameters)), 4) for a in j.axis)
            lim = limits_text(j)
            rows.append((str(i), literal(j.name, code=True) if j.name else "-", j.kind, _m(q),
                         f"({xyz})", f"({axis})", lim))
        out.append(Table(("joint", "name", "type", "variable", "origin xyz", "axis", "limits"),
                         tuple(rows), "lllcccc"))
        out.append(Para("Origins are the translations of the fixed transform before each "
                        "joint's motion; axes are in the joint's frame."))
    return out


def limits_text(joint) -> str:
    """A joint's limits with their unit: degrees for an angle, metres for a length.

    Examples
    --------
    >>> import math
    >>> from types import SimpleNamespace
    >>> limits_text(SimpleNamespace(kind="revolute", limits=(-math.pi / 2, 3 * math.pi / 4)))
    '[-90, 135] deg'
    >>> limits_text(SimpleNamespace(kind="prismatic", limits=(0.0, 0.5)))
    '[0, 0.5] m'
    >>> limits_text(SimpleNamespace(kind="prismatic", limits=None))
    'none'
    """
    import math

    if not joint.limits:
        return "none"
    lo, hi = joint.limits
    if joint.kind == "revolute":
        return f"[{_nozero(math.degrees(lo), 4)}, {_nozero(math.degrees(hi), 4)}] deg"
    return f"[{_nozero(lo, 4)}, {_nozero(hi, 4)}] m"


def _nozero(x: float, digits: int) -> str:
    """``x`` to ``digits`` significant digits, never a signed zero."""
    text = f"{float(x):.{digits}g}"
    return "0" if float(text) == 0 else text


def _task_section(report, m):
    from ..model import RobotModel

    tm = report.tm
    out = [Heading(3, "Task, frame and constraint rows")]
    labels = ", ".join(literal(r, code=True) for r in tm.row_labels)
    items = [f"Rows of $J$: {labels}."]
    if isinstance(m, RobotModel):
        rows = _velocity_rows(tm.row_labels)
        if rows:
            items.append(f"{rows}; the model expresses them in the {m.frame} frame.")
        for what, T in (("base", m.base), ("tool", m.tool)):
            T = sp.Matrix(T)
            if T != sp.eye(4):
                xyz = ", ".join(_num(float(T[k, 3].subs(m.parameters)), 4) for k in range(3))
                items.append(f"A constant {what} transform with translation ({xyz}) is part "
                             "of the chain.")
    if m.augment:
        for name, g in m.augment:
            items.append(f"Constraint row {literal(name, code=True)}: the gradient of "
                         f"$g(q) = {latex(g)}$.")
    items.append(f"Joint variables (columns): {variables_text(tm.variables)}.")
    out.append(Bullets(tuple(items)))
    return out


_LINEAR, _ANGULAR = ("vx", "vy", "vz"), ("wx", "wy", "wz")


def _velocity_rows(labels) -> str:
    """What the task rows among ``labels`` are, as a sentence without its end.

    Examples
    --------
    >>> print(_velocity_rows(["vx", "vy", "orientation"]))  # doctest: +NORMALIZE_WHITESPACE
    Rows `vx`, `vy` are the x and y components of the linear velocity of the task point
    (the origin of the tool frame)
    >>> print(_velocity_rows(["vx", "vy", "vz", "wx", "wy", "wz"]))
    ... # doctest: +NORMALIZE_WHITESPACE
    Rows `vx`, `vy`, `vz` are the linear velocity of the task point (the origin of the tool
    frame) and `wx`, `wy`, `wz` the angular velocity of the end-effector
    """
    def part(rows, what, verb):
        names = ", ".join(f"`{r}`" for r in rows)
        verb = (verb + " ") if verb else ""
        if len(rows) == 3:
            return f"{names} {verb}the {what}"
        axes = [r[1] for r in rows]
        comps = axes[0] if len(axes) == 1 else f"{axes[0]} and {axes[1]}"
        return f"{names} {verb}the {comps} {plural('component', len(rows))} of the {what}"

    lin = [r for r in labels if r in _LINEAR]
    ang = [r for r in labels if r in _ANGULAR]
    n = len(lin) + len(ang)
    if not n:
        return ""
    verb = "is" if n == 1 else "are"
    parts = []
    if lin:
        parts.append(part(lin, "linear velocity of the task point (the origin of the tool "
                               "frame)", verb))
    if ang:
        parts.append(part(ang, "angular velocity of the end-effector",
                          "" if parts else verb))
    return f"{plural('Row', n)} " + " and ".join(parts)


def _jacobian_section(report):
    tm, jd = report.tm, report.jacobian
    out = [Heading(2, "The symbolic Jacobian", block_label(report, "jacobian"))]
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
    out += matrix_blocks(jd)
    if jd.definitions:
        out.append(Para("where the common subexpressions are"))
        lines = []
        for s, e in jd.definitions:
            parts = broken_lines(e, lead=f"{latex(s)} &= ")
            lines.append(parts[0])
            lines += [r"&\quad " + p for p in parts[1:]]
        out.append(Math(tuple(lines), aligned=True))
    return out


def matrix_blocks(jd) -> list:
    """Blocks showing a :class:`~rankloci.reporting.matrixfmt.JacobianDisplay`.

    The whole matrix when it fits on a line (``jd.layout == "matrix"``);
    otherwise its columns, as many side by side as fit on a line, and each
    column too wide for a line as its non-zero entries, one equation each.
    """
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


def _timings_section(report):
    rows = tuple((label, f"{sec:.2f}") for label, sec in report.timings)
    total = sum(sec for _, sec in report.timings)
    rows += (("total", f"{total:.2f}"),)
    return [Heading(2, "Timings", block_label(report, "timings")),
            Marker("timings: these vary from run to run; everything else is fixed by the seed"),
            Para("Wall-clock seconds on the machine that wrote this report (they vary from run "
                 "to run; everything else in the report is fixed by the seed)."),
            Table(("step", "seconds"), rows, "lr"),
            Marker("end of timings")]


def _model_argument(model) -> str:
    """How a command names the model: its built-in name, or the path of its file."""
    import shlex
    from pathlib import Path

    from ..io import builtin_models, models_dir

    path = str(getattr(model, "path", "") or "")
    if not path:
        return model.name
    p = Path(path)
    try:
        builtin = p.resolve().parent == models_dir().resolve() and p.stem in builtin_models()
    except OSError:  # pragma: no cover - an unreadable directory
        builtin = False
    return model.name if builtin else shlex.quote(path)


def _reproduce_section(report):
    args = [f"rankloci report {_model_argument(report.model)}", f"--seed {report.seed}",
            f"--samples {report.samples}"]
    if report.numeric:
        args.append("--numeric")
    if report.timeout:
        args.append(f"--timeout {report.timeout:g}")
    return [Heading(2, "Reproducing this report", block_label(report, "reproduce")),
            Code(" ".join(args), "sh"),
            Para(f"rankloci {_version()}; the report depends only on the model, the options and "
                 "the seed (the timings aside).")]


def _version() -> str:
    """The version of rankloci that writes the report."""
    from ..version import __version__

    return __version__
