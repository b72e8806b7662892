"""The report as Markdown (GitHub, GitLab, VS Code, pandoc): math in ``$...$`` and ``$$...$$``.

Displayed math is a ``$$`` block on lines of its own; several lines use the
``aligned`` environment, which MathJax and KaTeX both know.  Figures are
linked by their file names, so the Markdown file and its PNGs move together.
"""

from __future__ import annotations

from .blocks import Appendix, Bullets, Code, Figure, Heading, Marker, Math, Para, Table
from .content import report_blocks
from .escape import heading_anchor, md_escape, md_refs, rich_md

__all__ = ["render_markdown", "blocks_markdown"]


def render_markdown(report, *, timings: bool = True) -> str:
    """The Markdown text of a :class:`~rankloci.reporting.Report`."""
    return blocks_markdown(report_blocks(report, timings=timings))


def blocks_markdown(blocks) -> str:
    """Markdown of a list of blocks (:mod:`~rankloci.reporting.blocks`).

    Examples
    --------
    >>> from rankloci.reporting.blocks import Heading, Math, Para
    >>> print(blocks_markdown([Heading(2, "Locus"), Para("where $x_1 = 0$"), Math(("x_1 = 0",))]))
    ## 1. Locus
    <BLANKLINE>
    where $x_1 = 0$
    <BLANKLINE>
    $$
    x_1 = 0 \\tag{1}
    $$
    <BLANKLINE>
    """
    out = []
    section, lettered, equations = 0, None, 0
    figures, headings = {}, {}
    for b in blocks:
        if isinstance(b, Appendix):
            lettered = 0
            out.append("---")
        elif isinstance(b, Heading):
            text = rich_md(b.text)
            if b.level == 2 and lettered is not None:
                lettered += 1
                text = f"Appendix {chr(ord('A') + lettered - 1)}. {text}"
            elif b.level == 2:
                section += 1
                text = f"{section}. {text}" if not text.startswith("Reproducing") else text
            out.append("#" * b.level + " " + text)
            if b.label:
                headings[b.label] = heading_anchor(text)
        elif isinstance(b, Para):
            lead = f"**{rich_md(b.lead)}** " if b.lead else ""
            out.append(lead + rich_md(b.text))
        elif isinstance(b, Math):
            # numbered as the LaTeX report numbers its displays (MathJax and KaTeX know \tag)
            equations += 1
            if b.aligned or len(b.lines) > 1:
                body = "\\begin{aligned}\n" + " \\\\\n".join(b.lines) + "\n\\end{aligned}"
            else:
                body = b.lines[0]
            out.append("$$\n" + body + f" \\tag{{{equations}}}\n$$")
        elif isinstance(b, Table):
            out.append(_table(b))
        elif isinstance(b, Bullets):
            out.append("\n".join("- " + rich_md(item) for item in b.items))
        elif isinstance(b, Figure):
            figures[b.label] = (len(figures) + 1, b.file)
            alt = md_escape((b.alt or b.file).replace("[", "(").replace("]", ")"))
            out.append(f"![{alt}]({b.file})\n\n*Figure {len(figures)}: {rich_md(b.caption)}*")
        elif isinstance(b, Code):
            out.append(f"```{b.language or 'text'}\n{b.text}\n```")
        elif isinstance(b, Marker):
            out.append(f"<!-- {b.text} -->")
    return md_refs("\n\n".join(out) + "\n", figures, headings)


def _table(t: Table) -> str:
    align = {"l": ":---", "r": "---:", "c": ":---:"}
    spec = t.align or "l" * len(t.header)
    lines = ["| " + " | ".join(rich_md(h) for h in t.header) + " |",
             "| " + " | ".join(align.get(a, "---") for a in spec) + " |"]
    for row in t.rows:
        lines.append("| " + " | ".join(rich_md(c).replace("\n", " ") for c in row) + " |")
    if t.caption:
        lines.append("")
        lines.append(f"*{rich_md(t.caption)}*")
    return "\n".join(lines)
