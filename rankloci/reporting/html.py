"""The report as one self-contained HTML page, with an interactive view of the arm.

:func:`render_html` spells the blocks of :func:`~rankloci.reporting.content.report_blocks`
(the summary, the model, the equations, the checks: what the Markdown report
says) as HTML, and adds a section in which the arm can be moved along each
component of the locus.  Everything the page needs is inside it, so it opens
without a network:

- the math is rendered in the browser by KaTeX (bundled: ``assets/katex/``,
  MIT licence) to MathML, which browsers draw with their own fonts, so no
  font or style sheet of KaTeX is needed;
- the arm is drawn by a short script of this package (``assets/arm_view.js``)
  on a canvas, from the model's chain as numbers (:func:`view_data`).  The
  script computes the forward kinematics, the geometric Jacobian at the tool
  point and its singular values itself, and shows
  sigma_min/sigma_max at the pose: a check of the locus independent of the
  computation that found it.

The figures (PNG) are not embedded, to keep the page small; their captions
stay and name the files, which :func:`~rankloci.reporting.write.write_report`
writes beside the page.  Everything here is pure.
"""

from __future__ import annotations

import html
import json
import re
from importlib import resources

import sympy as sp

from ..tolerances import VIEW_ON_LOCUS_RTOL
from .blocks import Appendix, Bullets, Code, Figure, Heading, Marker, Math, Para, Table
from .content import report_blocks
from .escape import MD_REF, html_id, rich_html

__all__ = ["render_html", "view_data", "blocks_html", "KATEX_VERSION"]

#: The version of the bundled KaTeX (Debian's ``libjs-katex``, from the upstream release).
KATEX_VERSION = "0.16.4"

#: What the code of a solved value or an equation may hold once its names are taken out
#: (``Math.sin``, ``q[3]``): numbers, operators, brackets and commas.
_JS_SAFE = re.compile(r"[0-9.eE+\-*/(), ]*")
_JS_NAMES = re.compile(r"Math\.(?:sin|cos|tan|asin|acos|atan|atan2|sqrt|pow|abs|exp|log|PI|E)"
                       r"\b|q\[[0-9]+\]")


def _asset(name: str) -> str:
    return resources.files(__package__).joinpath("assets", *name.split("/")).read_text(
        encoding="utf-8")


def render_html(report, *, timings: bool = True) -> str:
    """The HTML page of a :class:`~rankloci.report.Report`: one file, nothing to fetch.

    Examples
    --------
    >>> from rankloci.io import load_model
    >>> from rankloci.reporting import build_report
    >>> page = render_html(build_report(load_model("planar2r"), samples=2, exact=False),
    ...                    timings=False)
    >>> page.startswith("<!DOCTYPE html>"), 'id="arm-canvas"' in page
    (True, True)
    """
    blocks = report_blocks(report, timings=timings)
    data = view_data(report)
    view = _view_section(data)
    # the view follows the summary: before the first section
    at = next((k for k, b in enumerate(blocks) if isinstance(b, Heading) and b.level == 2),
              len(blocks))
    body = blocks_html(blocks, extra={at: view})
    title = html.escape(f"Singularity report: {report.model.name}")
    payload = json.dumps(data, separators=(",", ":")).replace("<", "\\u003c")
    # the arm view only for a chain of joints (a matrix model has no arm)
    arm = ([f'<script id="rankloci-data" type="application/json">{payload}</script>',
            f"<script>\n{_script(_asset('arm_view.js'))}</script>"] if data else ["", ""])
    return "\n".join([
        "<!DOCTYPE html>",
        '<html lang="en">',
        "<head>",
        '<meta charset="utf-8">',
        '<meta name="viewport" content="width=device-width, initial-scale=1">',
        f"<title>{title}</title>",
        f"<style>\n{_STYLE}</style>",
        "</head>",
        "<body>",
        "<main>",
        body,
        "</main>",
        arm[0],
        f"<script>\n{_script(_asset('katex/katex.min.js'))}\n</script>",
        f"<script>\n{_RENDER_MATH}</script>",
        arm[1],
        "</body>",
        "</html>",
        "",
    ])


def _script(code: str) -> str:
    """JavaScript safe inside a ``<script>`` element (no closing tag in it)."""
    return code.replace("</script", "<\\/script")


def blocks_html(blocks, *, extra=None) -> str:
    """HTML of a list of blocks (:mod:`~rankloci.reporting.blocks`), numbered as Markdown numbers
    them; ``extra`` maps a position in ``blocks`` to HTML put before the block there.

    Examples
    --------
    >>> from rankloci.reporting.blocks import Heading, Math, Para
    >>> print(blocks_html([Heading(2, "Locus"), Para("where $x_1 = 0$"), Math(("x_1 = 0",))]))
    <h2>1. Locus</h2>
    <p>where <span class="math">x_1 = 0</span></p>
    <div class="math display">x_1 = 0 \\tag{1}</div>
    """
    state = {"section": 0, "lettered": None, "equations": 0, "figures": {}}
    text = _spell(blocks, state, extra or {})
    figures = state["figures"]

    def link(m):
        kind, label, words = m[1], m[2], html.escape(m[3])
        if kind == "f" and label in figures:
            return f'<a href="#{html_id(label)}">{words} {figures[label]}</a>'
        return words

    return MD_REF.sub(link, text)


def _spell(blocks, state, extra) -> str:
    out = []
    for k, b in enumerate(blocks):
        if extra.get(k):
            out.append(extra[k])
        if isinstance(b, Appendix):
            state["lettered"] = 0
            out.append("<hr>")
        elif isinstance(b, Heading):
            text = rich_html(b.text)
            if b.level == 2 and state["lettered"] is not None:
                state["lettered"] += 1
                text = f"Appendix {chr(ord('A') + state['lettered'] - 1)}. {text}"
            elif b.level == 2 and not b.text.startswith("Reproducing"):
                state["section"] += 1
                text = f"{state['section']}. {text}"
            anchor = f' id="{html_id(b.label)}"' if b.label else ""
            out.append(f"<h{b.level}{anchor}>{text}</h{b.level}>")
        elif isinstance(b, Para):
            lead = f"<strong>{rich_html(b.lead)}</strong> " if b.lead else ""
            out.append(f"<p>{lead}{rich_html(b.text)}</p>")
        elif isinstance(b, Math):
            state["equations"] += 1
            if b.aligned or len(b.lines) > 1:
                body = "\\begin{aligned}" + " \\\\ ".join(b.lines) + "\\end{aligned}"
            else:
                body = b.lines[0]
            tex = html.escape(body + f" \\tag{{{state['equations']}}}")
            out.append(f'<div class="math display">{tex}</div>')
        elif isinstance(b, Table):
            out.append(_table(b))
        elif isinstance(b, Bullets):
            out.append("<ul>\n" + "\n".join(f"<li>{rich_html(i)}</li>" for i in b.items)
                       + "\n</ul>")
        elif isinstance(b, Figure):
            number = len(state["figures"]) + 1
            state["figures"][b.label] = number
            out.append(f'<p class="figure" id="{html_id(b.label)}"><em>Figure {number} '
                       f"(<code>{html.escape(b.file)}</code>, written beside this page):"
                       f"</em> {rich_html(b.caption)}</p>")
        elif isinstance(b, Code):
            out.append(f"<pre><code>{html.escape(b.text)}</code></pre>")
        elif isinstance(b, Marker):
            out.append(f"<!-- {html.escape(b.text).replace('--', '- -')} -->")
    if extra.get(len(blocks)):
        out.append(extra[len(blocks)])
    return "\n".join(out)


def _table(t: Table) -> str:
    spec = t.align or "l" * len(t.header)
    side = {"l": "left", "r": "right", "c": "center"}

    def cell(tag, k, text):
        a = side.get(spec[k] if k < len(spec) else "l", "left")
        return f'<{tag} style="text-align:{a}">{rich_html(text)}</{tag}>'

    rows = ["<tr>" + "".join(cell("th", k, h) for k, h in enumerate(t.header)) + "</tr>"]
    rows += ["<tr>" + "".join(cell("td", k, c) for k, c in enumerate(r)) + "</tr>"
             for r in t.rows]
    caption = f"<caption>{rich_html(t.caption)}</caption>" if t.caption else ""
    return f"<table>{caption}\n" + "\n".join(rows) + "\n</table>"


# --- the data of the view ------------------------------------------------------------------

def view_data(report) -> dict:
    """What the arm view needs, as plain JSON-ready data (numbers and short code strings).

    ``chain``: the model's transforms (base, each joint's ``pre`` and ``post``,
    tool; 16 numbers each, row by row), each joint's unit axis, kind, and the
    variable that moves it with its multiple (a mimic joint), the task rows and
    the frame of the Jacobian, the rows that augment it (the gradients of the
    model's constraint functions, as JavaScript expressions), a sample pose and
    a slider range per variable.
    ``components``: per component of the locus that exists for the model's
    parameters, its number, the variables its sliders move (its free variables
    and as many more as its equations leave free), the variables that follow them
    (``moving``), its sample pose, solved values and
    equations as JavaScript expressions in ``q[0..n-1]`` (the parameters
    replaced by their values).  A component whose expressions hold anything
    else is left out of ``components`` and named in ``omitted``.  An empty
    dict for a model that is not a chain of joints (or whose constraint
    gradients are not plain functions of the joints).
    """
    from ..limits import joint_kinds, joint_limits, joint_strokes
    from ..model import TASKS, RobotModel

    model = report.model
    if not isinstance(model, RobotModel):
        return {}
    params = {s: sp.sympify(v, strict=True) for s, v in dict(model.parameters).items()}
    variables = list(model.variables)
    index = {v: k for k, v in enumerate(variables)}

    def numbers(M):
        return [float(x) for x in sp.Matrix(M).subs(params).evalf()]

    joints, reach = [], 0.0
    for j, coord in zip(model.joints, model.joint_coordinates):
        multiple, var = sp.sympify(coord, strict=True).as_coeff_Mul()
        pre, post = numbers(j.pre), numbers(j.post)
        reach += _length(pre) + _length(post)
        joints.append({"kind": j.kind, "axis": [float(sp.sympify(a, strict=True).subs(params)) for a in j.axis],
                       "pre": pre, "post": post, "variable": index[var],
                       "multiplier": float(multiple)})
    base, tool = numbers(model.base), numbers(model.tool)
    # the rows of the constraint gradients that augment J (exact derivatives)
    from ..kinematics import augmented_rows

    grads = augmented_rows(model, [g for _, g in model.augment])
    augment = [[_js(x, variables, params) for x in grads.row(r)] for r in range(grads.rows)]
    if any(x is None for row in augment for x in row):
        return {}
    kinds = joint_kinds(model)
    strokes = joint_strokes(model)
    reach += _length(tool) + sum(max(abs(lo), abs(hi)) for (lo, hi), k in zip(strokes, kinds)
                                 if k == "prismatic")
    comps, omitted, poses = [], [], []
    locus = report.locus
    for view in report.components:
        c = view.component
        if view.special or locus is None:
            continue
        sample = [float(c.sample.get(v.name, 0.0)) for v in variables]
        free = [index[v] for v in c.free if v in index]
        for k in free:     # a free angle is shown within one turn of zero
            if kinds[k] == "revolute":
                sample[k] = (sample[k] + 3.141592653589793) % 6.283185307179586 \
                    - 3.141592653589793
        coded = _component_code(c, variables, params, sample)
        if coded is None:
            omitted.append(view.index)
            continue
        solved, equations = coded
        rest = [k for k in range(len(variables))
                if k not in free and k not in {v for v, _ in solved}]
        moving = _followers(c, variables, params, sample, rest)
        sliders = sorted(free + [k for k in rest if k not in moving])
        check = report.limit_check(view.index)
        comps.append({"index": view.index, "sliders": sliders, "sample": sample, "solved": solved,
                      "equations": equations, "scales": _scales(c, params), "moving": moving,
                      "outside": bool(check is not None and check.meets is False)})
        poses.append(sample)
    ranges = []
    for k, (lo, hi) in enumerate(strokes):
        values = [p[k] for p in poses]
        ranges.append([min([lo, *values]), max([hi, *values])])
    return {
        "chain": {"variables": [v.name for v in variables], "joints": joints, "base": base,
                  "tool": tool, "task": list(model.task), "frame": model.frame,
                  "augment": augment,
                  "prismatic": [k == "prismatic" for k in kinds], "ranges": ranges,
                  "reach": max(reach, 1e-3), "rtol": VIEW_ON_LOCUS_RTOL,
                  "planar": tuple(model.task) == TASKS["planar"],
                  "limits": [None if lim is None else [float(lim[0]), float(lim[1])]
                             for lim in joint_limits(model)],
                  "sample": poses[0] if poses else [0.0] * len(variables)},
        "components": comps,
        "omitted": omitted,
    }


def _followers(c, variables, params, sample, candidates) -> list:
    """The variables among ``candidates`` that follow the sliders on component ``c``
    (:func:`~rankloci.numeric.landscape.dependent_variables`)."""
    from ..numeric.landscape import dependent_variables

    return dependent_variables(c.equations, variables, params, sample, candidates)


def _scales(c, params) -> list:
    """The scale of each equation: the sum of the absolute values of its coefficients."""
    out = []
    for e in c.equations:
        terms = sp.Add.make_args(sp.expand(sp.sympify(e, strict=True).subs(params)))
        total = sum(abs(float(t.as_coeff_Mul()[0])) for t in terms)
        out.append(total if total > 0 else 1.0)
    return out


def _length(T) -> float:
    return (T[3] ** 2 + T[7] ** 2 + T[11] ** 2) ** 0.5


def _js(expr, variables, params):
    """``expr`` as a JavaScript expression in ``q[0..n-1]``, or None if it holds anything else.

    The parameters are replaced by their values; what is left must be numbers, operators and
    the functions of ``Math`` (checked on the text, so that nothing else reaches the page).
    """
    slots = {v: sp.Symbol(f"q[{k}]") for k, v in enumerate(variables)}
    e = sp.sympify(expr, strict=True).subs(params).xreplace(slots)
    if e.free_symbols - set(slots.values()):
        return None
    text = sp.jscode(sp.N(e, 17))
    return text if _JS_SAFE.fullmatch(_JS_NAMES.sub("", text)) else None


def _component_code(c, variables, params, sample):
    """(solved, equations) of component ``c`` as JavaScript, or None if one is not plain.

    A variable with several solved values takes the one nearest its sample value.
    """
    index = {v: k for k, v in enumerate(variables)}
    at = {v: sample[k] for k, v in enumerate(variables)}

    def code(expr):
        return _js(expr, variables, params)

    solved = []
    for v, values in c.solved.items():
        if v not in index:
            continue
        options = values if isinstance(values, (tuple, list)) else (values,)
        try:
            best = min(options, key=lambda x: abs(float(sp.sympify(x, strict=True).subs(params).subs(at))
                                                  - at[v]))
        except TypeError:
            return None
        text = code(best)
        if text is None:
            return None
        solved.append([index[v], text])
    equations = [code(e) for e in c.equations]
    if any(e is None for e in equations):
        return None
    return solved, equations


def _view_section(data) -> str:
    """The HTML of the arm view (empty for a model that is not a chain of joints)."""
    if not data:
        return ""
    none = ("" if data["components"] else " No component of the locus exists for the model's "
            "parameter values: the arm can only be moved freely.")
    omitted = data["omitted"]
    left_out = (f" Components {', '.join(map(str, omitted))} are left out: their equations "
                "are not plain functions of the joints." if omitted else "")
    return f"""<h2 id="arm-view">The arm on the locus</h2>
<p>Choose a component and move the arm along it with the sliders, one per dimension of the
component (its free joints, and as many of the joints in its equations). The other joints follow:
values the locus gives in closed form are evaluated, and the remaining joints are moved by
least-norm Gauss-Newton steps back onto the component's equations (the largest residual,
each equation divided by the sum of its coefficients' sizes, is shown). The ratio
&sigma;<sub>min</sub>/&sigma;<sub>max</sub> is that of the geometric Jacobian at the tool
point, computed in this page from the joint chain alone; on the locus it stays near zero.
Drag the picture to turn it. Only components that exist for the model's parameter values are
offered; "none" frees every joint, and the ratio is then that of an ordinary pose.{left_out}{none}</p>
<div class="arm-view">
<canvas id="arm-canvas" width="560" height="440" aria-label="the arm"></canvas>
<div class="arm-controls">
<label>Component <select id="arm-component"></select></label>
<div id="arm-sliders"></div>
<p>&sigma;<sub>min</sub>/&sigma;<sub>max</sub> = <output id="sigma-ratio"></output></p>
<p>largest equation residual = <output id="arm-residual"></output></p>
<p class="pose"><output id="arm-pose"></output></p>
</div>
</div>"""


_RENDER_MATH = """"use strict";
// every span and div of class "math" holds LaTeX: rendered in place to MathML
for (const el of document.querySelectorAll(".math")) {
  katex.render(el.textContent, el, {displayMode: el.classList.contains("display"),
                                    output: "mathml", throwOnError: false, strict: "ignore"});
}
"""

_STYLE = """body { font-family: system-ui, sans-serif; margin: 0; color: #111; }
main { max-width: 68rem; margin: 0 auto; padding: 1rem 1.5rem 4rem; line-height: 1.45; }
table { border-collapse: collapse; margin: 0.8rem 0; }
th, td { border-bottom: 1px solid #ccc; padding: 0.25rem 0.6rem; vertical-align: top; }
caption { caption-side: bottom; font-style: italic; text-align: left; }
.math.display { display: block; margin: 0.8rem 0; overflow-x: auto; }
pre { background: #f4f4f4; padding: 0.6rem; overflow-x: auto; }
.figure { color: #444; }
.arm-view { display: flex; flex-wrap: wrap; gap: 1.5rem; align-items: flex-start; }
#arm-canvas { border: 1px solid #bbb; background: #fff; touch-action: none; cursor: grab; }
.arm-controls { min-width: 18rem; }
#arm-sliders label { display: grid; grid-template-columns: 3rem 12rem 6rem; gap: 0.5rem;
                     align-items: center; margin: 0.3rem 0; }
.pose { font-size: 0.85rem; color: #444; }
"""
