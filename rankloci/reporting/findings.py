"""The sections of a report on what was found: the locus and each of its components, the
singularity maps, the branch tree, the numeric cross-check, the method comparison and the
algorithmic singularities of an augmented Jacobian.

:func:`findings_blocks` returns them in this order, as blocks of
:mod:`~rankloci.reporting.blocks`; :func:`~rankloci.reporting.content.report_blocks`
puts them between the model and the appendix.  Everything here is pure.
"""

from __future__ import annotations

import struct

import sympy as sp

from ..methods import method_for
from ..tolerances import DET_FACTOR_RTOL, RANK_RTOL
from .blocks import (SIGMA, Bullets, Code, Figure, Heading, Math, Para, Table, block_label,
                     counted, plural, signed, variables_text)
from .escape import literal, ref
from .mathfmt import (LINE_WIDTH, LONG_INTEGER_DIGITS, SHOWN_DIGITS, broken_lines,
                      has_long_integers, latex, math_width, value_latex)
from .near_section import near_blocks

#: A drawn branch tree with more boxes than this is set on a page of its own.
TALL_TREE_BOXES = 12

#: A drawn branch tree wider than this (pixels) and 1.5 times wider than high is turned a
#: quarter on its page: at the line width it would be scaled below 6 pt text.
TURNED_TREE_PIXELS = 1300

__all__ = ["findings_blocks", "appendix_findings", "plain_equations", "disagreement_verdict",
           "figure_labels", "component_figures", "point_text"]


def findings_blocks(report) -> list:
    """The sections from the locus to the algorithmic singularities, in order."""
    out = _locus_section(report)
    out += _figure_section(report)
    out += near_blocks(report)
    out += _check_section(report)
    out += _comparison_section(report)
    out += _augmented_section(report)
    return out


def appendix_findings(report) -> list:
    """The second opinions, the notes of the analysis and the branch tree, for the appendix.

    The tree comes last: its figure, often a page of its own, then ends the document
    instead of leaving the page before the notes half empty.
    """
    out = _second_opinions(report)
    notes = (list(report.locus.notes) if report.locus is not None else []) + list(report.notes)
    if notes:
        out.append(Heading(2, "Notes of the analysis", block_label(report, "notes")))
        out.append(Bullets(tuple(n[0].upper() + n[1:] + ("" if n.endswith(".") else ".")
                                 for n in notes)))
    return out + _tree_section(report)


def _equation_math(exprs, excluding=(), *, width: float = LINE_WIDTH) -> Math:
    """``e = 0`` for each expression and ``x != 0`` for each of ``excluding``.

    Lines that are too wide are broken between terms.
    """
    rels = [(e, " = 0", " &= 0") for e in exprs]
    rels += [(x, r" \neq 0", r" &\neq 0") for x in excluding]
    parts = [broken_lines(e, tail=tail, width=width) for e, tail, _ in rels]
    if len(parts) == 1 and len(parts[0]) == 1:
        return Math((parts[0][0],))
    if all(len(p) == 1 for p in parts):
        return Math(tuple(latex(e) + tail for e, _, tail in rels), aligned=True)
    lines = []
    for p in parts:
        lines.append("&" + p[0])
        lines += [r"&\quad " + x for x in p[1:]]
    return Math(tuple(lines), aligned=True)


def _solved(solved: dict) -> str:
    """Exact values of joint variables (variable -> values), as inline math."""
    parts = []
    for q, vals in solved.items():
        vs = ", ".join(value_latex(v) for v in vals)
        parts.append(f"${latex(q)} \\in \\lbrace {vs} \\rbrace$" if len(vals) > 1
                     else f"${latex(q)} = {vs}$")
    return "; ".join(parts)


def _solved_at_values(report, comp) -> str:
    """The values a component fixes once the parameters have the model's values, or ""."""
    from ..methods.readable import solved_at_values

    params = dict(getattr(report.locus, "parameters", None) or {})
    if not params:
        return ""
    found = solved_at_values(comp.equations, report.tm.variables, params)
    return _solved(found) if found else ""


def _component_blocks(report, view, level: int = 3):
    c = view.component
    out = [Heading(level, f"Component {view.index}",
                   block_label(report, "component", view.index))]
    eqs = [e for e in c.equations if e not in c.parameter_conditions] or list(c.equations)
    if view.folded and list(view.folded) != eqs:
        # one display, in the notation of J; the plain text at the end spells it out
        jac = ref(block_label(report, "jacobian"), "the Jacobian section")
        out.append(Para(f"In the notation of {jac} (the plain text at the end of this "
                        "subsection writes the sines and cosines out):"))
        out.append(_equation_math(view.folded, view.folded_excluding or c.excluding))
    elif eqs or c.excluding:
        out.append(_equation_math(eqs, c.excluding))
    else:
        # an empty display is a LaTeX error ("Paragraph ended before \align* was complete")
        out.append(Para("No equation: the component is all of joint space (the rank of $J$ is "
                        "below its maximum at every configuration)."))
    items = []
    if c.solved:
        items.append(f"Solved: {_solved(c.solved)}.")
    elif not c.parameter_conditions:
        at_values = _solved_at_values(report, c)
        if at_values:
            items.append(f"Solved at the model's parameter values: {at_values}.")
    n = len(report.tm.variables)
    items.append(f"Dimension {c.dimension} in the {n}-dimensional joint space; rank drop "
                 f"{c.rank_drop}; free joint variables: {variables_text(c.free)}.")
    if view.kind:
        items.append(f"Kind: {view.kind}.")
    if c.parameter_conditions:
        conds = ", ".join(f"${latex(e)} = 0$" for e in c.parameter_conditions)
        items.append(f"Exists only when {conds} (not the model's values).")
    elif not c.for_model:
        items.append("Has no real point for the model's parameter values.")
    if c.excluding:
        ex = ", ".join(f"${latex(e)} \\neq 0$" for e in view.folded_excluding or c.excluding)
        items.append(f"Side condition: the component is the closure of the set where the "
                     f"equations hold and {ex}. Where the excluded expression vanishes the "
                     "equations can hold at regular configurations, so points there are not "
                     "taken as points of the component (sample points, checks, figures).")
    labels = list(report.tm.row_labels)
    tall = report.tm.shape[0] > report.tm.shape[1]
    over = [str(v) for v in report.tm.variables] if tall else labels
    for vec in c.direction_at_sample:
        what = "Lost joint direction (right null vector)" if tall else "Lost direction"
        items.append(f"{what} at the sample point: ({', '.join(signed(x, 3) for x in vec)}) "
                     f"over ({literal(', '.join(over))}).")
    if not c.direction_at_sample and c.direction:
        items.append("Lost direction: $(" + ", ".join(latex(x) for x in c.direction[0]) + ")$.")
    items.append(f"Sample point: {point_text(report.model, c.sample)}.")
    check = report.limit_check(view.index) if report.has_limits else None
    if check is not None:
        items.append(_limits_item(check, report.model))
    figs = component_figures(report, view.index)
    if figs:
        items.append(f"{plural('Figure', len(figs))}: "
                     + ", ".join(f"{ref(label, 'Figure', figure=True)} ({what})"
                                 for label, what in figs) + ".")
    out.append(Bullets(tuple(items)))
    for f in getattr(view, "equal_parameters", ()):
        eqs_n = len(c.equations)
        which = "The equation" if eqs_n == 1 else f"Equation {f.index + 1} of {eqs_n}"
        same = ", ".join(f"${latex(p)} = {latex(r)}$" for p, r in f.equalities)
        out.append(Para(f"{which} is shorter with the model's equal parameter values "
                        f"{same}: {f.terms[0] - f.terms[1]} of its {f.terms[0]} terms cancel, "
                        "and it reads"))
        out.append(_equation_math([f.form]))
    if view.readings:
        out.append(Para("Geometric facts hold at the sample point and at other points of the "
                        "component, and at no random configuration; directions are checked "
                        "at the sample point (all numerically):", lead="Reading."))
        out.append(Bullets(tuple(r[0].upper() + r[1:] + "." for r in view.readings)))
    if c.equations or c.excluding:
        out.append(Para("The equations as plain text:"))
        out.append(Code(plain_equations(c)))
    labels = figure_labels(report)
    for f in report.figure("robot"):
        if f.through == view.index:
            out.append(Figure(f.name, f.caption, labels[f.name], alt=f.title))
    return out


def _limits_item(check, model) -> str:
    """Whether the component meets the joint-limit box, as a bullet."""
    if check.meets is True:
        where = point_text(model, check.sample)
        return f"Within the joint limits: yes, for example at {where} ({check.how})."
    if check.meets is False:
        return f"Within the joint limits: no; {literal(check.reason)} (decided exactly)."
    return f"Within the joint limits: not decided; {literal(check.reason)}."


def point_text(model, point: dict) -> str:
    """``q1 = +0.8606 rad, q2 = 0 m``: a configuration, with units for a robot's joints."""
    from ..limits import joint_kinds

    units = {}
    if hasattr(model, "joints"):
        units = {str(v): (" rad" if k == "revolute" else " m")
                 for v, k in zip(model.variables, joint_kinds(model))}
    return ", ".join(f"{k} = {signed(v)}{units.get(k, '')}" for k, v in point.items())


def figure_labels(report) -> dict:
    """The label of each figure of ``report``, by file name."""
    out = {}
    for k, f in enumerate(report.figure("sigma"), start=1):
        out[f.name] = block_label(report, "fig", f"sigma{k}")
    for kind in ("manipulability", "tree", "augmented"):
        for f in report.figure(kind):
            out[f.name] = block_label(report, "fig", kind)
    for f in report.figure("robot"):
        out[f.name] = block_label(report, "fig", f"robot{f.through}")
    return out


def component_figures(report, index: int) -> list:
    """(label, what it shows) of each figure that shows component ``index``."""
    labels = figure_labels(report)
    out = [(labels[f.name], "the arm at its sample point") for f in report.figure("robot")
           if f.through == index]
    for f in report.figure("sigma"):
        if index in f.components:
            what = ("heat map through its sample point" if f.through == index
                    else "heat map")
            out.append((labels[f.name], what))
    out.sort(key=lambda item: (item[1] != "the arm at its sample point",
                               item[1] != "heat map through its sample point"))
    for f in report.figure("manipulability"):
        if index in f.components:
            out.append((labels[f.name], "manipulability along a path through it"))
    return out


def plain_equations(comp) -> str:
    """The component's equations and side conditions as plain text (Python syntax).

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> q1, q2 = sp.symbols("q1 q2")
    >>> print(plain_equations(SimpleNamespace(equations=(sp.sin(q1),), excluding=(q2,))))
    sin(q1) = 0
    where q2 != 0
    """
    text = ",  ".join(f"{sp.sstr(e)} = 0" for e in comp.equations)
    if comp.excluding:
        text += "\nwhere " + ",  ".join(f"{sp.sstr(e)} != 0" for e in comp.excluding)
    return text


def _locus_section(report):
    out = [Heading(2, "The singularity locus", block_label(report, "locus"))]
    if report.locus is None:
        out.append(Para(report.locus_status, lead="Not computed."))
        out.append(Para("The model, the Jacobian and the heat maps are still given; rerun with a "
                        "larger `--timeout` (or `--numeric`) for the rest."))
        return out
    loc = report.locus
    out.append(Para(f"Method: {loc.method} (seed {report.seed}). Each component is the set "
                    "where its equations vanish; the rank drop is how many ranks $J$ loses "
                    "at its generic points, and the lost directions span the left null space "
                    "of $J$ there (the task velocities no joint velocity produces)."))
    main = [v for v in report.components if not v.special]
    special = [v for v in report.components if v.special]
    if any(has_long_integers(e) for v in report.components
           for e in tuple(v.component.equations) + tuple(v.component.excluding)):
        out.append(Para(f"Integers of more than {LONG_INTEGER_DIGITS} digits in the displayed "
                        f"equations are rounded to {SHOWN_DIGITS} significant digits, as "
                        r"$m \cdot 10^{k}$; the plain text of each component's equations and "
                        "the JSON (`rankloci locus --format json`) keep them exact."))
    if main:
        rows = []
        for v in main:
            c = v.component
            rows.append((ref(block_label(report, "component", v.index), str(v.index)),
                         str(c.dimension), str(c.rank_drop), variables_text(c.free)))
        out.append(Table(("no.", "dim.", "rank drop", "free joints"), tuple(rows), "rrrl"))
    else:
        out.append(Para("No component exists for the model's parameter values: $J$ has full "
                        "rank everywhere."))
    out += _determinant_blocks(report, main)
    out += _minor_gcd_blocks(report, main)
    for v in main:
        out += _component_blocks(report, v)
    if special:
        out.append(Heading(3, "Components for special parameter values"))
        out.append(Para("These exist only for parameter values other than the model's; they "
                        "are listed for designers who may change the geometry."))
        for v in special:   # one level down: they belong to this subsection
            out += _component_blocks(report, v, level=4)
    if list(loc.notes) + list(report.notes):
        out.append(Para("The notes of the analysis (special parameter values it did not pursue, "
                        "the frame it worked in) are in "
                        f"{ref(block_label(report, 'notes'), 'the appendix')}."))
    return out


def _factor_latex(e, power: int) -> str:
    text = latex(e)
    if isinstance(e, sp.Add) or (power > 1 and not isinstance(e, sp.Symbol)
                                 and len(text) > 2 and not text.endswith("}")):
        text = rf"\left({text}\right)"
    return text + (f"^{{{power}}}" if power > 1 else "")


def _minor_gcd_blocks(report, main):
    """The gcd of the maximal minors of a wide or tall J, factored, or why it is 1 or not given."""
    g = getattr(report, "minor_gcd", None)
    if g is None:
        return []
    m, n = g.shape
    what = (rf"$J$ is {m} $\times$ {n}: it loses rank where all its {g.minors} maximal "
            rf"({min(m, n)} $\times$ {min(m, n)}) minors vanish")
    if g.skipped:
        return [Para(f"{what}. Their greatest common divisor is not computed: {g.skipped}.")]
    if not g.factors:
        return [Para(f"{what}. Their greatest common divisor is 1 (computed exactly, in the "
                     "polynomials of the half-angle sines and cosines and the parameters): no "
                     "factor is common to all of them, so no component is a hypersurface: the "
                     "locus has codimension 2 or more in joint space.")]
    factors = " ".join(_factor_latex(f, k) for f, k in zip(g.factors, g.powers))
    param = ("" if g.parameter_factor == 1 else
             f" The gcd also has the factor ${latex(g.parameter_factor)}$ in the parameters "
             "alone, which vanishes only for special parameter values.")
    return [Para(f"{what}. Their greatest common divisor, computed exactly and factored, is "
                 "(up to a constant factor):"),
            Math((r"\gcd(\text{maximal minors of } J) = " + factors,)),
            Para("Where it vanishes, every maximal minor does: these are the components of "
                 "codimension 1 (hypersurfaces) of the locus; the other components have "
                 "codimension 2 or more." + param)]


def _determinant_blocks(report, main):
    """det J factored into the components' equations (square J), with how it was checked."""
    d = report.determinant
    if d is None or len(d.factors) != len(main):
        return []
    factors = [_factor_latex(f, m) for f, m in zip(d.factors, d.powers)]
    head = latex(d.constant)
    head = "" if head == "1" else "-" if head == "-1" else head + " "
    one = r"\det J = " + head + " ".join(factors)
    if math_width(one) <= LINE_WIDTH:
        lines, aligned = (one,), False
    else:
        lines = (r"\det J &= " + head + factors[0],) + tuple(r"&\quad \cdot " + f
                                                            for f in factors[1:])
        aligned = True
    how = (f"${latex(d.constant)}$, which matches at the model's parameter values and at "
           "two other random sets of values" if d.exact_constant else
           "a number at the model's parameter values, given to 6 significant digits")
    return [Para(r"$J$ is square, so its components are the factors of $\det J$. With their "
                 "multiplicities and the constant factor:"),
            Math(lines, aligned=aligned),
            Para(rf"The product was checked against $\det J$ at {d.points} random "
                 "configurations (the ratio is one constant to a relative "
                 f"{DET_FACTOR_RTOL:g}); the constant factor is {how}.")]


def _figure_section(report):
    sig = report.figure("sigma")
    man = report.figure("manipulability")
    if not sig and not man:
        return []
    out = [Heading(2, "Singularity maps", block_label(report, "maps"))]
    how = ("through a point of a component, the other joints fixed; the two joints are those "
           "the component's equations use most, ties broken by how much the ratio changes "
           "along each" if report.components else
           "through one configuration, the other joints fixed; the two joints are those along "
           "which the ratio changes most")
    out.append(Para(f"The heat maps show {SIGMA} of $J$ (the model's own frame and "
                    "task point, parameters at the model's values) over two-joint slices of "
                    f"joint space {how}. It is zero exactly on the locus. Its values depend on "
                    "the length unit when $J$ mixes linear and angular rows."))
    labels = figure_labels(report)
    for f in sig + man:
        out.append(Figure(f.name, f.caption, labels[f.name], alt=f.title))
    return out


def _tree_section(report):
    tree = report.tree
    figs = report.figure("tree")
    if tree is None:
        return []
    out = [Heading(2, "Branch tree", block_label(report, "tree"))]
    text = [Para(f"The {report.locus.method} method grows a tree of branches; each leaf "
                 "stops for the reason shown. The tree has "
                 f"{counted(tree.total_nodes, 'node')}."),
            Table(("stop reason of the leaves", "leaves"),
                  tuple((reason or "(none)", str(n)) for reason, n in sorted(tree.outcomes.items())),
                  "lr")]
    # the figure first: a float that goes to a page of its own leaves the text to fill this one
    for f in figs:
        # a tree of more than a dozen boxes gets a page of its own, where it can be read
        width, height = struct.unpack(">II", f.png[16:24])
        # a tree much wider than high reads better turned on a page of its own
        turned = width > TURNED_TREE_PIXELS and width > 1.5 * height
        out.append(Figure(f.name, f.caption, block_label(report, "fig", "tree"),
                          tall=f.boxes > TALL_TREE_BOXES and not turned, alt=f.title,
                          turned=turned))
    return out + text


def _check_section(report):
    chk = report.check
    if chk is None:
        return []
    out = [Heading(2, "Numeric cross-check", block_label(report, "check"))]
    rtol = chk.thresholds.get("RANK_RTOL", RANK_RTOL)
    option = f" --rank-rtol {rtol:g}" if rtol != RANK_RTOL else ""
    out.append(Para(f"As `rankloci check {report.name} --samples {report.samples} --seed "
                    f"{report.seed}{option}`: $J$ in the model's frame, parameters at their "
                    f"values, decided by the SVD (rank deficient when {SIGMA} is at most "
                    f"{rtol:g}). On-locus: points solved onto "
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
    mn = min((p.sigma_ratio for p in chk.off_locus), default=None)
    rows.append(("off-locus (regular)", str(len(chk.off_locus)),
                 "pass" if not chk.off_locus_failures else "FAIL",
                 f"{len(chk.off_locus_failures)} singular; smallest sigma ratio {mn:.1e}"
                 if mn is not None else "no configuration is off the locus"))
    rows.append(("completeness probe", str(chk.probe_starts),
                 "pass" if not chk.uncovered else "FAIL",
                 f"{chk.probe_singular} singular minima, {len(chk.uncovered)} on no component"))
    out.append(Table(("check", "points", "result", "detail"), tuple(rows), "lrll",
                     caption=f"seed {chk.seed}, {chk.samples} samples"))
    out.append(Para(f"Result: {'PASS' if chk.ok else 'FAIL'} (seed {chk.seed})."))
    if chk.findings or report.exact is not None:
        out.append(Para("The second opinions (the exact check with Singular, the FSP reducer "
                        "and the largest maximal minor beside the SVD) are in "
                        f"{ref(block_label(report, 'second'), 'the appendix')}."))
    for p in chk.uncovered[:5]:
        out.append(Para("Uncovered singular point: (" + ", ".join(signed(x, 6) for x in p.q)
                        + f"), sigma ratio {p.sigma_ratio:.1e}."))
    return out


def _second_opinions(report) -> list:
    """The exact check with Singular and the FSP and minor findings, for the appendix."""
    chk = report.check
    if chk is None or not (chk.findings or report.exact is not None):
        return []
    out = [Heading(2, "Second opinions", block_label(report, "second"))]
    if report.exact is not None:
        ex = report.exact
        out.append(Table(("check", "result", "detail"),
                         (("Singular (exact primes)", ex.status, ex.reason),), "lll"))
    if chk.findings:
        out.append(Para(f"{counted(len(chk.findings), 'finding')} where the FSP reducer or the "
                        "largest maximal minor disagrees with the SVD (recorded, not failures; "
                        "the SVD decides):"))
        items = list(chk.findings[:10])
        if len(chk.findings) > 10:
            items.append(f"... and {len(chk.findings) - 10} more")
        out.append(Bullets(tuple(items)))
        out.append(Para(_findings_explained(chk.findings)))
    return out


def caveats(report) -> list:
    """What limits the summary's verdict, in sentences: said on the first page, not only in
    the appendix (a special case of the symbolic analysis, a skipped or disagreeing exact
    check, second opinions that differ from the SVD)."""
    out = []
    notes = list(report.locus.notes) if report.locus is not None else []
    for n in notes:
        if "rerun with --numeric-parameters" in n:
            out.append(n[0].upper() + n[1:].replace("rerun with --numeric-parameters",
                                                    "components there may be missing; rerun "
                                                    "with `--numeric-parameters`") + ".")
    ex = report.exact
    if ex is not None and ex.status == "disagree":
        out.append(f"The exact check with Singular disagrees: {ex.reason}.")
    elif ex is not None and ex.status == "skipped":
        out.append(f"The exact check with Singular was skipped ({ex.reason}).")
    chk = report.check
    if chk is not None and chk.findings:
        out.append(f"At {counted(len(chk.findings), 'point')} the FSP reducer or the largest "
                   "maximal minor disagrees with the SVD (recorded, not failures).")
    return out


def _findings_explained(findings) -> str:
    """What a disagreement of the FSP reducer or of the maximal minor with the SVD means."""
    from ..tolerances import (FSP_N_BND_NUMERATOR, FSP_SMALL_FRACTION, FSP_SV_SMALL,
                              MINOR_RTOL)

    out = []
    if any("FSP" in f for f in findings):
        out.append(
            "The FSP reducer is the row reduction of the Full Space Parameterization method "
            "(K. A. Morgansen and F. G. Pin, ORNL/TM-12816, 1995), run at each point as a "
            "second opinion. It keeps that method's own thresholds: an entry of $J$ at most "
            f"{FSP_SMALL_FRACTION:g} times the largest counts as zero, a singular value below "
            f"{FSP_SV_SMALL:g} (absolute, not relative to the largest) counts as zero, and a row "
            "is named dependent only when a null vector's component there reaches "
            f"{FSP_N_BND_NUMERATOR:g}/(N + 1), N the number of rows. The report's rank "
            f"decisions use the SVD with the relative threshold {RANK_RTOL:g} instead, so at "
            "a point that the SVD finds singular the reducer can still \"find no dependent "
            "row\" (for example when zeroing small entries restricts the rows that carry the "
            "dependency). This compares the two tests; it is not an error of the locus or of "
            "the check.")
    if any("maximal minor" in f for f in findings):
        out.append(
            "The largest maximal minor, divided by the product of the row norms, is a "
            f"scale-free test of rank with its own threshold ({MINOR_RTOL:g}); it is "
            "recorded beside the SVD in the same way.")
    return " ".join(out)


def _comparison_section(report):
    if report.locus is None:
        return []
    out = [Heading(2, "Method comparison", block_label(report, "methods"))]
    if method_for(report.tm.shape) == "determinant":
        out.append(Para("$J$ is square, so the determinant method is the only one: the "
                        "singular vector and subdeterminant methods both reduce to "
                        "$\\det J = 0$ here."))
        return out
    loc, sec = report.locus, report.second
    rows = [(x.method, str(sum(c.for_model for c in x.components)),
             str(x.tree.number_of_nodes() if x.tree is not None else "-"))
            for x in (loc, sec) if x is not None]
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
        text = "The two methods disagree." if cmp.disagreements else "The two methods disagree:"
    out.append(Para(text))
    if cmp.disagreements:
        out += _disagreement_blocks(cmp, report.locus.method)
    elif cmp.differences:
        out.append(Bullets(tuple(cmp.differences)))
    if not cmp.special_same:
        out.append(Para("Their components for special parameter values differ; those are side "
                        "results of where each method's branching meets a parameter factor, "
                        "not part of the model's locus."))
    return out


def _point_text(q) -> str:
    return "(" + ", ".join(signed(x, 3) for x in q) + ")"


def disagreement_verdict(d) -> str:
    """The SVD's verdict on a :class:`~rankloci.reporting.comparison.Disagreement`, in a sentence.

    Examples
    --------
    >>> from rankloci.compare import Disagreement
    >>> d = Disagreement("subdeterminant", "svm", 2, ("q1 = 0",), 5, ((0.0, 1.0),), (0.3,))
    >>> print(disagreement_verdict(d))  # doctest: +NORMALIZE_WHITESPACE
    The subdeterminant component 2 contains regular points: sigma ratio 3.0e-01 at
    q = (0, +1.000); the svm locus is the right one there.
    """
    name = f"{d.method} component {d.index}"
    out = []
    if d.regular:
        k = max(d.regular, key=lambda i: d.ratios[i])
        many = "all" if len(d.regular) == len(d.points) else f"{len(d.regular)} of the"
        more = (f" ({many} {len(d.points)} points are regular; the largest ratio is shown)"
                if len(d.regular) > 1 else "")
        out.append(f"The {name} contains regular points: sigma ratio {d.ratios[k]:.1e} at "
                   f"q = {_point_text(d.points[k])}{more}; the {d.other} locus is the right "
                   "one there.")
    if d.singular:
        k = max(d.singular, key=lambda i: d.ratios[i])
        count = "it is" if len(d.singular) == 1 else f"all {len(d.singular)} are"
        if d.regular:
            count = f"{len(d.singular)} of them are"
        out.append(f"The {d.other} locus misses points of the {name}: {count} singular (sigma "
                   f"ratio at most {d.ratios[k]:.1e}, at q = {_point_text(d.points[k])}); the "
                   f"{d.method} locus is the right one there.")
    return " ".join(out)


def _disagreement_blocks(cmp, method):
    """Each disagreement with the SVD's verdict, and the equations of the other method's
    components (the report's own have their sections)."""
    out = [Para(f"At the points where the loci differ, the SVD of $J$ decides ({SIGMA} at "
                f"most {RANK_RTOL:g} is singular, as in the cross-check): a component that "
                "holds regular points is too large there, and a locus that misses singular "
                "points is incomplete there.")]
    for d in cmp.disagreements:
        n = len(d.points)
        head = (f"The {d.method} component {d.index}: {n} of its {d.tested} tested "
                f"{plural('point', d.tested)} {'lies' if n == 1 else 'lie'} on no {d.other} "
                "component.")
        out.append(Para(head + " " + disagreement_verdict(d)))
        if d.method != method:
            out.append(Code("\n".join(d.equations)))
    return out


def _augmented_section(report):
    if not report.augmented:
        return []
    out = [Heading(2, "Algorithmic singularities", block_label(report, "algorithmic"))]
    out.append(Para("$J$ is augmented with constraint rows. A component where $J$ without those "
                    "rows already loses rank is kinematic; one where only the augmented matrix "
                    "does is algorithmic (the constraint, not the arm, fails there); mixed "
                    "components have both."))
    rows = []
    for v in report.augmented:
        c = v.component
        kind = v.kind or ("special parameter values" if v.special else "not classified")
        meets = sorted({m.get("base_component") for m in getattr(c, "meets", ())
                        if isinstance(m, dict)} - {None})
        if meets:
            kind += f" (meets component{'s' if len(meets) > 1 else ''} " \
                    f"{', '.join(map(str, meets))} of the locus of $J$)"
        rows.append((ref(block_label(report, "component", v.index), f"component {v.index}"),
                     kind))
    out.append(Table(("component", "kind"), tuple(rows), "ll"))
    base = getattr(report.locus, "base", None)
    if base is not None:
        comps = [c for c in base.components if c.for_model]
        out.append(Para(f"The locus of $J$ without the constraint rows ({base.shape[0]}x"
                        f"{base.shape[1]}, {base.method} method) has "
                        f"{counted(len(comps), 'component')} for the model's values"
                        + (":" if comps else ".")))
        if comps:
            out.append(Bullets(tuple(
                f"Component {i} of $J$: " + ", ".join(f"${latex(e)} = 0$" for e in c.equations)
                for i, c in enumerate(base.components, start=1) if c in comps)))
    for f in report.figure("augmented"):
        out.append(Figure(f.name, f.caption, block_label(report, "fig", "augmented"), alt=f.title))
    return out

