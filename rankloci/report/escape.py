"""Plain text as LaTeX and as Markdown: special characters escaped, ``$math$`` kept.

Text in the report's blocks may hold ``$math$`` and ```code``` segments;
:func:`rich_tex` and :func:`rich_md` escape the text around them for each
output, :func:`tex_escape` and :func:`md_escape` escape plain text.
Everything here is pure.
"""

from __future__ import annotations

import re

__all__ = ["tex_escape", "md_escape", "rich_tex", "rich_md"]

_TEX_SPECIAL = {"\\": r"\textbackslash{}", "&": r"\&", "%": r"\%", "$": r"\$", "#": r"\#",
                "_": r"\_", "{": r"\{", "}": r"\}", "~": r"\textasciitilde{}",
                "^": r"\textasciicircum{}", "<": r"\textless{}", ">": r"\textgreater{}",
                "|": r"\textbar{}"}

_TEX_UNICODE = {"π": r"$\pi$", "≈": r"$\approx$", "∈": r"$\in$", "σ": r"$\sigma$",
                "×": r"$\times$", "·": r"$\cdot$", "→": r"$\to$", "≤": r"$\le$", "≥": r"$\ge$",
                "−": "-", "–": "--", "—": "---", "‘": "`", "’": "'", "“": "``", "”": "''",
                "é": r"\'e", "è": r"\`e", "ö": r"\"o", "ü": r"\"u", "ä": r"\"a", "ᵀ": r"$^T$",
                "²": r"$^2$", "³": r"$^3$", "√": r"$\surd$", "†": r"$\dagger$"}


def tex_escape(text: str) -> str:
    """Plain text as LaTeX text: specials escaped, known Unicode spelled out, the rest dropped.

    Examples
    --------
    >>> tex_escape("a_2 & 50% of π")
    'a\\\\_2 \\\\& 50\\\\% of $\\\\pi$'
    """
    out = []
    for ch in text:
        if ch in _TEX_SPECIAL:
            out.append(_TEX_SPECIAL[ch])
        elif ch in _TEX_UNICODE:
            out.append(_TEX_UNICODE[ch])
        elif ord(ch) < 128:
            out.append(ch)
        else:
            out.append("?")
    return "".join(out)


_MD_SPECIAL = re.compile(r"([\\`*_<>|#])")


def md_escape(text: str) -> str:
    """Plain text safe in Markdown (also inside a table cell).

    Examples
    --------
    >>> md_escape("a_2 * b | c")
    'a\\\\_2 \\\\* b \\\\| c'
    """
    return _MD_SPECIAL.sub(r"\\\1", text)


_SEGMENTS = re.compile(r"(\$[^$]+\$|`[^`]+`)")


def rich_tex(text: str) -> str:
    """Text with ``$math$`` and ```code``` segments as LaTeX: text escaped, math kept.

    Examples
    --------
    >>> rich_tex("50% of $x_1$ in `a_b`")
    '50\\\\% of $x_1$ in \\\\texttt{a\\\\_b}'
    """
    out = []
    for p in _SEGMENTS.split(text):
        if p.startswith("$") and p.endswith("$") and len(p) > 1:
            out.append(p)
        elif p.startswith("`") and p.endswith("`") and len(p) > 1:
            out.append(r"\texttt{" + tex_escape(p[1:-1]) + "}")
        else:
            out.append(tex_escape(p))
    return "".join(out)


def rich_md(text: str) -> str:
    """Text with ``$math$`` and ```code``` segments as Markdown: text escaped, the rest kept.

    Examples
    --------
    >>> rich_md("a_b and $x_1$ in `a_b`")
    'a\\\\_b and $x_1$ in `a_b`'
    """
    out = []
    for p in _SEGMENTS.split(text):
        if len(p) > 1 and ((p[0] == p[-1] == "$") or (p[0] == p[-1] == "`")):
            out.append(p)
        else:
            out.append(md_escape(p))
    return "".join(out)
