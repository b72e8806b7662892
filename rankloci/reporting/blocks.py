"""The blocks a report is made of, and the spellings the sections share.

A report is a list of blocks (:class:`Heading`, :class:`Para`, :class:`Math`,
:class:`Table`, ...), plain data that :mod:`~rankloci.reporting.markdown` and
:mod:`~rankloci.reporting.latex` spell each in their own way.  Text in blocks
may hold ``$math$`` and ```code``` segments.  Everything here is pure.
"""

from __future__ import annotations

from dataclasses import dataclass

from .mathfmt import latex

__all__ = ["Heading", "Para", "Math", "Table", "Bullets", "Figure", "Code", "Marker", "Appendix",
           "SIGMA",
           "block_label", "variables_text", "plural", "counted", "numbered"]

#: The ratio the checks and the heat maps are about, as text with math.
SIGMA = r"$\sigma_{\min}/\sigma_{\max}$"


@dataclass(frozen=True)
class Heading:
    """A heading: the title, a section or a subsection, with a label to refer to it."""

    level: int            # 1 title, 2 section, 3 subsection
    text: str
    label: str = ""


@dataclass(frozen=True)
class Para:
    """A paragraph of text."""

    text: str
    lead: str = ""        # a bold run-in heading such as "Source."


@dataclass(frozen=True)
class Math:
    """Displayed math: one line, or several aligned at ``&`` (``aligned=True``)."""

    lines: tuple
    aligned: bool = False


@dataclass(frozen=True)
class Table:
    """A table of text cells under a header row."""

    header: tuple
    rows: tuple
    align: str = ""       # one of l, r, c per column
    caption: str = ""
    widths: tuple = ()    # LaTeX: a fraction of the line width per column (0: as ``align``)
    small: bool = False   # LaTeX: set in a smaller font


@dataclass(frozen=True)
class Bullets:
    """A list of items, each a line of text."""

    items: tuple


@dataclass(frozen=True)
class Figure:
    """A figure: a PNG file beside the report, with its caption and label."""

    file: str
    caption: str
    label: str
    tall: bool = False
    alt: str = ""         # a short plain-text description (Markdown's image text)
    turned: bool = False  # LaTeX: a page of its own, turned a quarter (a wide figure)


@dataclass(frozen=True)
class Code:
    """Text shown as it is, such as a command line or equations in plain text."""

    text: str
    language: str = ""


@dataclass(frozen=True)
class Appendix:
    """The start of the appendix: the sections after it are lettered A, B, ..."""


@dataclass(frozen=True)
class Marker:
    """A comment in the output, such as the start and end of the timings."""

    text: str



def block_label(report, *parts) -> str:
    """A cross-reference label unique to ``report``: ``rankloci:MODEL:part:...``.

    Several reports can share one LaTeX document without clashing labels.
    """
    return ":".join(("rankloci", report.name) + tuple(str(p) for p in parts))


def variables_text(variables) -> str:
    """The variables as inline math (``$q_{1}, q_{2}$``), or ``none``.

    Examples
    --------
    >>> import sympy as sp
    >>> variables_text(sp.symbols("q1 q2")), variables_text(())
    ('$q_{1}, q_{2}$', 'none')
    """
    return ("$" + ", ".join(latex(v) for v in variables) + "$") if variables else "none"


def plural(word: str, n: int, many: str | None = None) -> str:
    """``word`` for one, its plural (``many``, by default ``word + "s"``) for any other number.

    Examples
    --------
    >>> plural("component", 1), plural("component", 2), plural("branch", 3, "branches")
    ('component', 'components', 'branches')
    """
    return word if n == 1 else (many or word + "s")


def counted(n: int, word: str, many: str | None = None) -> str:
    """``1 component``, ``2 components``: a number with its noun in the right form.

    Examples
    --------
    >>> counted(1, "branch", "branches"), counted(0, "node")
    ('1 branch', '0 nodes')
    """
    return f"{n} {plural(word, n, many)}"


def numbered(word: str, numbers) -> str:
    """``component 1``, ``components 1 and 3``, ``components 1, 2 and 3``.

    Examples
    --------
    >>> numbered("component", [2]), numbered("component", [1, 2, 3])
    ('component 2', 'components 1, 2 and 3')
    """
    items = [str(n) for n in numbers]
    listed = items[0] if len(items) == 1 else ", ".join(items[:-1]) + " and " + items[-1]
    return f"{plural(word, len(items))} {listed}"


def signed(x: float, digits: int = 4) -> str:
    """``x`` with a sign and ``digits`` decimals; a value that rounds to zero is ``0``
    (never a signed zero such as ``-0.00``).

    Examples
    --------
    >>> signed(-1e-9), signed(0.25), signed(-2.0, 2)
    ('0', '+0.2500', '-2.00')
    """
    text = f"{float(x):+.{digits}f}"
    return "0" if float(text) == 0 else text
