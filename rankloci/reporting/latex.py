"""The report as LaTeX: a complete article, or (``fragment=True``) a body for a paper appendix.

The body needs ``amsmath``, ``amssymb``, ``graphicx`` and ``booktabs``; the
fragment says so in its first lines.  Figures are included by file name: set
``\\graphicspath`` to the report's directory when the fragment is input from
elsewhere.  Long equations are broken between terms in ``align*``; only
tables that are too wide are scaled (``\\resizebox``).  Labels are
``rankloci:MODEL:...`` so that several reports can share one document.
"""

from __future__ import annotations

from .blocks import Appendix, Bullets, Code, Figure, Heading, Marker, Math, Para, Table
from .content import report_blocks
from .escape import literal, rich_tex, tex_escape
from .mathfmt import math_width

__all__ = ["render_latex", "blocks_latex", "PACKAGES"]

PACKAGES = ("amsmath", "amssymb", "graphicx", "booktabs")

#: Width of the text block in "letters" of a table cell (about 0.55 em each at 11 pt):
#: a table whose estimated width exceeds it is scaled to the line width.
TABLE_WIDTH = 80.0

_PREAMBLE = r"""\documentclass[11pt,a4paper]{article}
\usepackage[T1]{fontenc}
\usepackage{lmodern}
\usepackage[margin=2.5cm]{geometry}
\usepackage{float}
\usepackage[section]{placeins}
\usepackage{longtable}
\usepackage{amsmath,amssymb}
\usepackage{graphicx}
\usepackage{booktabs}
\usepackage[hidelinks]{hyperref}
\ifdefined\pdftrailerid \pdftrailerid{}\fi
\ifdefined\pdfinfoomitdate \pdfinfoomitdate=1\fi
\setlength{\parindent}{0pt}
\setlength{\parskip}{0.5ex plus 0.2ex}
\setcounter{topnumber}{3}
\renewcommand{\topfraction}{0.9}
\renewcommand{\textfraction}{0.07}
\renewcommand{\floatpagefraction}{0.8}
\sloppy
"""


def render_latex(report, *, fragment: bool = False, timings: bool = True) -> str:
    """LaTeX of a :class:`~rankloci.reporting.Report`: a document, or a fragment to ``\\input``."""
    blocks = report_blocks(report, timings=timings)
    wide = report.tm.shape[1] > 10
    if fragment:
        body = blocks_latex(blocks, wide_matrix=wide, appendix=False, placement="!htbp")
        head = (f"% rankloci report on {report.name}: a fragment for \\input.\n"
                f"% Needs \\usepackage{{{','.join(PACKAGES)}}} and, when input from another\n"
                f"% directory, \\graphicspath{{{{path/to/reports/{report.name}/}}}}.\n"
                "% With hyperref its references are links; without it they are plain text.\n"
                "\\providecommand{\\hyperref}[2][]{#2}\n")
        return head + body
    # figures float (top, bottom or a page of their own) so that no page is left half blank;
    # placeins keeps each inside its section, and wide tables break across pages
    body = blocks_latex([b for b in blocks if not (isinstance(b, Heading) and b.level == 1)],
                        wide_matrix=wide, top=2, placement="htbp", breakable=True)
    title = rich_tex("Singularity report: " + (literal(report.model.title)
                                                 if report.model.title.strip() else report.name))
    return (_PREAMBLE + f"\\title{{{title}}}\n\\author{{rankloci}}\n\\date{{}}\n"
            "\\begin{document}\n\\maketitle\n" + body + "\\end{document}\n")


def blocks_latex(blocks, *, wide_matrix: bool = False, top: int = 1,
                 appendix: bool = True, placement: str = "H", breakable: bool = False) -> str:
    """LaTeX of a list of blocks (:mod:`~rankloci.reporting.blocks`).

    Headings of level ``top`` become ``\\section``, the next level
    ``\\subsection`` and so on.  Figures stay where they are in the text
    (``placement`` ``H``, from the ``float`` package the document loads; a
    fragment for a paper passes ``!htbp``, the full document ``htbp`` with
    ``placeins`` keeping figures in their sections); a tall one (the branch tree)
    gets a page of its own.  With ``breakable`` (the full document loads
    ``longtable``) a table with fixed column widths may break across pages, so a
    long summary table starts on the first page.  :class:`~rankloci.reporting.blocks.Appendix` becomes
    ``\\appendix`` (a comment when ``appendix`` is false, for a fragment).

    Examples
    --------
    >>> from rankloci.reporting.blocks import Heading, Math
    >>> print(blocks_latex([Heading(2, "Locus", "l"), Math(("x_1 = 0",))], top=1))
    \\subsection{Locus}\\label{l}
    <BLANKLINE>
    \\begin{equation}
    x_1 = 0
    \\end{equation}
    <BLANKLINE>
    """
    out = []
    if wide_matrix:
        out.append("\\setcounter{MaxMatrixCols}{20}")
    for b in blocks:
        if isinstance(b, Heading):
            cmd = {0: "section", 1: "subsection", 2: "subsubsection"}.get(b.level - top,
                                                                          "paragraph")
            label = f"\\label{{{b.label}}}" if b.label else ""
            out.append(f"\\{cmd}{{{rich_tex(b.text)}}}{label}")
        elif isinstance(b, Para):
            lead = f"\\textbf{{{rich_tex(b.lead)}}} " if b.lead else ""
            out.append(lead + rich_tex(b.text))
        elif isinstance(b, Math):
            # every display gets one number (on its last line), so that a paper can cite it
            if b.aligned or len(b.lines) > 1:
                lines = b.lines if b.aligned else tuple("&" + ln for ln in b.lines)
                out.append("\\begin{align}\n" + " \\notag \\\\\n".join(lines)
                           + "\n\\end{align}")
            else:
                out.append("\\begin{equation}\n" + b.lines[0] + "\n\\end{equation}")
        elif isinstance(b, Table):
            out.append(_fixed_table(b, breakable=True) if breakable and b.widths
                       else _table(b))
        elif isinstance(b, Bullets):
            out.append("\\begin{itemize}\n" + "\n".join(f"  \\item {rich_tex(i)}" for i in b.items)
                       + "\n\\end{itemize}")
        elif isinstance(b, Figure):
            size = ("width=\\linewidth,height=0.78\\textheight,keepaspectratio" if b.tall
                    else "width=0.85\\linewidth,height=0.42\\textheight,keepaspectratio")
            if b.turned:
                size = "angle=90,width=\\linewidth,height=0.85\\textheight,keepaspectratio"
            floating = placement != "H"
            page = "\\clearpage\n" if (b.tall or b.turned) and not floating else ""
            where = "p" if (b.tall or b.turned) and floating else placement
            out.append(page + f"\\begin{{figure}}[{where}]\n\\centering\n"
                       f"\\includegraphics[{size}]{{{b.file}}}\n"
                       f"\\caption{{{rich_tex(b.caption)}}}\\label{{{b.label}}}\n\\end{{figure}}"
                       + ("\n\\clearpage" if page else ""))
        elif isinstance(b, Appendix):
            out.append("\\appendix" if appendix else "% appendix")
        elif isinstance(b, Code):
            out.append(_code(b.text))
        elif isinstance(b, Marker):
            out.append(f"% {b.text}")
    return "\n\n".join(out) + "\n"


def _code(text: str) -> str:
    """Verbatim-like text that may be broken across lines (plain-text equations can be long).

    Each line of ``text`` starts a new line.
    """
    lines = []
    for line in text.split("\n"):
        # "-{}": no "--" ligature (an en dash in T1 fonts), so options copy as typed
        body = tex_escape(line).replace("-", "-{}").replace(",  ", ", \\allowbreak ")
        for op in (" + ", " -{} ", " = ", " != ", "*"):
            body = body.replace(op, op + "\\allowbreak{}" if op != "*" else "*\\allowbreak{}")
        lines.append(body)
    joined = "\\\\".join(lines)
    return f"{{\\raggedright\\small\\texttt{{{joined}}}\\par}}"


def _cell_width(text: str) -> float:
    import re

    w = 0.0
    for part in re.split(r"(\$[^$]+\$)", text):
        if part.startswith("$") and part.endswith("$") and len(part) > 1:
            w += math_width(part[1:-1])
        else:
            w += 0.85 * len(part)
    return w


def _table(t: Table) -> str:
    if t.widths:
        return _fixed_table(t)
    spec = t.align or "l" * len(t.header)
    widths = [max([_cell_width(h) for h in [t.header[k]]] + [_cell_width(r[k]) for r in t.rows])
              for k in range(len(t.header))]
    wrap_col = None
    total = sum(widths) + 2.0 * len(widths)
    if total > TABLE_WIDTH:
        # let the widest text column wrap rather than shrinking the whole table
        k = max(range(len(widths)), key=lambda i: widths[i])
        rest = total - widths[k]
        if rest < 0.6 * TABLE_WIDTH:
            wrap_col = k
            spec = spec[:k] + "p{%.2f\\linewidth}" % max(0.25, min(0.75, 1 - rest / TABLE_WIDTH - 0.05)) + spec[k + 1:]
    head = " & ".join(rich_tex(h) for h in t.header) + " \\\\"
    rows = [" & ".join(rich_tex(c) for c in r) + " \\\\" for r in t.rows]
    tabular = ("\\begin{tabular}{" + spec + "}\n\\toprule\n" + head + "\n\\midrule\n"
               + "\n".join(rows) + "\n\\bottomrule\n\\end{tabular}")
    if total > TABLE_WIDTH and wrap_col is None:
        tabular = "\\resizebox{\\linewidth}{!}{%\n" + tabular + "}"
    cap = f"\\\\[0.5ex]\n{{\\small {rich_tex(t.caption)}}}" if t.caption else ""
    return "\\begin{center}\n" + tabular + cap + "\n\\end{center}"


def _fixed_table(t: Table, *, breakable: bool = False) -> str:
    """A table with the column widths it asks for: text wraps, ragged, inside its columns.

    Only the kernel's tabular is used (no ``array`` package): each cell of a
    wrapping column starts with ``\\raggedright`` and rows end with
    ``\\tabularnewline``, which ``\\raggedright`` does not redefine.
    """
    align = t.align or "l" * len(t.header)
    spec = "".join(f"p{{{w:.2f}\\linewidth}}" if w else a for a, w in zip(align, t.widths))

    def row(cells):
        return " & ".join(("\\raggedright " if w else "") + rich_tex(c)
                          for c, w in zip(cells, t.widths)) + " \\tabularnewline"

    size = "\\small\n" if t.small else ""
    cap = f"\\\\[0.5ex]\n{{\\small {rich_tex(t.caption)}}}" if t.caption else ""
    if breakable:
        # the header repeats on each page the table runs onto
        body = ("\\begin{longtable}{" + spec + "}\n\\toprule\n" + row(t.header)
                + "\n\\midrule\n\\endhead\n" + "\n".join(row(r) for r in t.rows)
                + "\n\\bottomrule\n\\end{longtable}")
        after = f"\n{{\\small {rich_tex(t.caption)}}}\n" if t.caption else ""
        return ("{" + size + body + "}" if size else body) + after
    tabular = (size + "\\begin{tabular}{" + spec + "}\n\\toprule\n" + row(t.header)
               + "\n\\midrule\n" + "\n".join(row(r) for r in t.rows)
               + "\n\\bottomrule\n\\end{tabular}")
    return "\\begin{center}\n" + tabular + cap + "\n\\end{center}"
