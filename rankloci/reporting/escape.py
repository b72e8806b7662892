"""Plain text as LaTeX and as Markdown: special characters escaped, ``$math$`` kept.

Text in the report's blocks may hold ``$math$`` and ```code``` segments;
:func:`rich_tex` and :func:`rich_md` escape the text around them for each
output, :func:`tex_escape` and :func:`md_escape` escape plain text.

Text taken from a model file (its title, source, joint names) is not rich
text: a ``$`` or a backtick in it is a character, not markup.  Such text
enters a block through :func:`literal`, which marks it so that both
renderers escape all of it.  :func:`file_stem` turns a model's name into a
name for the report's files.  Everything here is pure.
"""

from __future__ import annotations

import re

__all__ = ["tex_escape", "md_escape", "rich_tex", "rich_md", "literal", "file_stem", "ref",
           "md_refs", "heading_anchor", "rich_html", "html_id", "MAX_STEM"]

#: The longest file stem :func:`file_stem` returns.
MAX_STEM = 64

_STEM_BAD = re.compile(r"[^A-Za-z0-9_-]+")


def file_stem(name: str) -> str:
    """``name`` as the stem of a file name: ASCII letters, digits, ``_`` and ``-`` only.

    Every run of other characters becomes one ``_``; the stem starts with a
    letter or a digit (so that no program reads it as an option, and it is
    never ``.`` or ``..``) and has at most :data:`MAX_STEM` characters.  A
    name with nothing usable is ``model``.  Valid model names are unchanged.

    Examples
    --------
    >>> file_stem("puma560"), file_stem("my robot$%\\\\x"), file_stem(".."), file_stem("*")
    ('puma560', 'my_robot_x', 'model', 'model')
    """
    stem = _STEM_BAD.sub("_", name).lstrip("_-")[:MAX_STEM]
    return stem or "model"


# A literal segment: _OPEN, "t" (text) or "c" (code), the text, _CLOSE.  The
# marks are control characters, which literal() removes from the text it wraps.
_OPEN, _CLOSE = "\x0e", "\x0f"
_LITERAL = re.compile("\x0e([tcfs])([^\x0e\x0f]*)\x0f")
# A cross-reference (kind "f" a figure, "s" a section) is a literal segment too, its label
# and text apart by _SEP.  In Markdown it stays a placeholder, _REF_OPEN kind label _SEP text
# _REF_CLOSE, until the whole document is known (see :func:`md_refs`).
_SEP, _REF_OPEN, _REF_CLOSE = "\x1f", "\x10", "\x11"
MD_REF = re.compile("\x10([fs])([^\x1f]*)\x1f([^\x11]*)\x11")
_CONTROL = re.compile(r"[\x00-\x1f\x7f]+")


def literal(text: str, *, code: bool = False) -> str:
    """Plain ``text`` (from a model file) marked for rich text: every character is shown as is.

    Runs of white space and control characters become one space, so that the
    text stays on one line.  With ``code=True`` it is set as code where the
    output can do so safely.

    Examples
    --------
    >>> title = literal("Arm with $x$ and ![img](http://x)")
    >>> print(rich_md("Title: " + title + ", $q_1$"))
    Title: Arm with &#36;x&#36; and !&#91;img&#93;(http://x), $q_1$
    >>> print(rich_tex("joint " + literal("a_1", code=True)))
    joint \\texttt{a\\_1}
    """
    flat = " ".join(_CONTROL.sub(" ", text).split())
    return _OPEN + ("c" if code else "t") + flat + _CLOSE


def ref(label: str, text: str, *, figure: bool = False) -> str:
    """A cross-reference in rich text: to the figure or the section (heading) labelled ``label``.

    A figure reference reads ``text`` and the figure's number (``text`` is
    the word before it, such as ``Figure``); a section reference reads
    ``text``.  LaTeX resolves them itself (``\\ref``, ``\\hyperref``);
    Markdown numbers its figures and links to the PNG or to the heading's
    anchor (:func:`md_refs`).

    Examples
    --------
    >>> print(rich_tex("see " + ref("m:fig:1", "Figure", figure=True)))
    see Figure~\\ref{m:fig:1}
    >>> print(rich_tex(ref("m:component:2", "component 2")))
    \\hyperref[m:component:2]{component 2}
    """
    flat = " ".join(_CONTROL.sub(" ", text).split())
    return _OPEN + ("f" if figure else "s") + label + _SEP + flat + _CLOSE


def heading_anchor(text: str) -> str:
    """The anchor GitHub, GitLab and VS Code give a Markdown heading (without the ``#``).

    Examples
    --------
    >>> heading_anchor("3. The singularity locus"), heading_anchor("Component 12")
    ('3-the-singularity-locus', 'component-12')
    """
    return re.sub(r"[^\w\- ]", "", text.strip().lower()).replace(" ", "-")


def md_refs(text: str, figures: dict, headings: dict) -> str:
    """``text`` (Markdown) with its cross-reference placeholders as links.

    ``figures`` maps a figure's label to (its number, its file name),
    ``headings`` a heading's label to its anchor.  A reference to an unknown
    label is left as its plain text.
    """
    def link(m):
        kind, label, words = m[1], m[2], md_escape(m[3])
        if kind == "f":
            if label not in figures:
                return words
            number, file = figures[label]
            return f"[{words} {number}]({file})"
        return f"[{words}](#{headings[label]})" if label in headings else words

    return MD_REF.sub(link, text)


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
        if ch in "\n\t":
            out.append(ch)
        elif ch < " " or ch == "\x7f":
            out.append(" ")
        elif ch in _TEX_SPECIAL:
            out.append(_TEX_SPECIAL[ch])
        elif ch in _TEX_UNICODE:
            out.append(_TEX_UNICODE[ch])
        elif ord(ch) < 128:
            out.append(ch)
        else:
            out.append("?")
    return "".join(out)


_MD_SPECIAL = re.compile(r"([\\`*_<>|#])")
# In text from a model file, [ and ] (links and images) and $ (math) become character
# references: a backslash before [ or ( starts display or inline math in some renderers.
_MD_LITERAL = re.compile(r"([\\`*_<>|#~])|([\[\]$])")
_MD_CODE_SAFE = re.compile(r"[A-Za-z0-9_.,:;/()+= -]*")


def md_escape(text: str) -> str:
    """Plain text safe in Markdown (also inside a table cell).

    Examples
    --------
    >>> md_escape("a_2 * b | c")
    'a\\\\_2 \\\\* b \\\\| c'
    """
    return _MD_SPECIAL.sub(r"\\\1", text)


def _literal_md(kind: str, text: str) -> str:
    """A :func:`literal` segment as Markdown (a :func:`ref` as its placeholder)."""
    if kind in "fs":
        return _REF_OPEN + kind + text + _REF_CLOSE
    if kind == "c" and text and _MD_CODE_SAFE.fullmatch(text):
        return f"`{text}`"
    return _MD_LITERAL.sub(lambda m: "\\" + m[1] if m[1] else f"&#{ord(m[2])};", text)


def _literal_tex(kind: str, text: str) -> str:
    """A :func:`literal` segment (or a :func:`ref`) as LaTeX."""
    if kind in "fs":
        label, words = text.split(_SEP, 1)
        if kind == "f":
            return f"{tex_escape(words)}~\\ref{{{label}}}"
        return f"\\hyperref[{label}]{{{tex_escape(words)}}}"
    return r"\texttt{" + tex_escape(text) + "}" if kind == "c" else tex_escape(text)


def _with_literals(text: str, rich, plain) -> str:
    """``text`` with its :func:`literal` segments spelled by ``plain``, the rest by ``rich``."""
    parts = _LITERAL.split(text)
    out = [rich(parts[0])]
    for k in range(1, len(parts), 3):
        out.append(plain(parts[k], parts[k + 1]))
        out.append(rich(parts[k + 2]))
    return "".join(out)


_SEGMENTS = re.compile(r"(\$[^$]+\$|`[^`]+`)")


def rich_tex(text: str) -> str:
    """Text with ``$math$`` and ```code``` segments as LaTeX: text escaped, math kept.

    Examples
    --------
    >>> rich_tex("50% of $x_1$ in `a_b`")
    '50\\\\% of $x_1$ in \\\\texttt{a\\\\_b}'
    """
    if _OPEN in text:
        return _with_literals(text, rich_tex, _literal_tex)
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
    if _OPEN in text:
        return _with_literals(text, rich_md, _literal_md)
    out = []
    for p in _SEGMENTS.split(text):
        if len(p) > 1 and ((p[0] == p[-1] == "$") or (p[0] == p[-1] == "`")):
            out.append(p)
        else:
            out.append(md_escape(p))
    return "".join(out)


def _html_text(text: str) -> str:
    """Plain text as HTML text."""
    import html

    return html.escape(text, quote=True)


def _literal_html(kind: str, text: str) -> str:
    """A :func:`literal` segment (or a :func:`ref`) as HTML: a reference links to its heading."""
    if kind in "fs":
        label, words = text.split(_SEP, 1)
        if kind == "f":
            return _REF_OPEN + kind + label + _SEP + words + _REF_CLOSE
        return f'<a href="#{_html_text(html_id(label))}">{_html_text(words)}</a>'
    return f"<code>{_html_text(text)}</code>" if kind == "c" else _html_text(text)


def html_id(label: str) -> str:
    """A block label (``rankloci:MODEL:part``) as an HTML id: letters, digits, ``-`` and ``_``.

    Examples
    --------
    >>> html_id("rankloci:puma560:component:2")
    'rankloci-puma560-component-2'
    """
    return re.sub(r"[^A-Za-z0-9_-]", "-", label)


def rich_html(text: str) -> str:
    """Text with ``$math$`` and ```code``` segments as HTML: text escaped, math in a span.

    The math keeps its LaTeX source in the span, which the page's math renderer
    replaces by MathML.  A figure reference stays a placeholder (``\\x10f label \\x1f words
    \\x11``) until the figures are numbered.

    Examples
    --------
    >>> print(rich_html("a < b and $x_1 < 2$ in `a_b`"))
    a &lt; b and <span class="math">x_1 &lt; 2</span> in <code>a_b</code>
    """
    if _OPEN in text:
        return _with_literals(text, rich_html, _literal_html)
    out = []
    for p in _SEGMENTS.split(text):
        if len(p) > 1 and p[0] == p[-1] == "$":
            out.append(f'<span class="math">{_html_text(p[1:-1])}</span>')
        elif len(p) > 1 and p[0] == p[-1] == "`":
            out.append(f"<code>{_html_text(p[1:-1])}</code>")
        else:
            out.append(_html_text(p))
    return "".join(out)
