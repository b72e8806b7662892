"""LaTeX math shared by the Markdown and the LaTeX report: compact forms, widths, line breaks.

Both renderings carry their equations as LaTeX math, so the work of making an
expression short enough to read is done once here: trigonometric functions of
the joint variables are abbreviated (``s_2 = sin q2``, ``c_2 = cos q2``, the
usual robotics notation), each entry is written in the shortest of its
expanded, factored and parameter-collected forms, common subexpressions are
named when that saves space, and lines that are too wide for a page are
broken between terms.

Everything here is pure: expressions in, strings and expressions out.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import sympy as sp

__all__ = ["JacobianDisplay", "jacobian_display", "math_width", "broken_lines", "latex",
           "compact", "factor_rational", "abbreviations", "value_latex", "vector_latex", "LINE_WIDTH",
           "tex_escape", "md_escape", "rich_tex", "rich_md"]

#: Width, in :func:`math_width` units (about one letter of 11 pt math), of a displayed line
#: that fits between the margins of the report's page (15.9 cm of text at 11 pt) and of a
#: typical one-column paper page.  Calibrated on the built-in models: no overfull box.
LINE_WIDTH = 62.0

#: Common subexpressions are named only when that shortens the matrix by this fraction.
CSE_MIN_GAIN = 0.2

#: A common subexpression narrower than this is put back: naming it does not help a reader.
CSE_MIN_WIDTH = 10.0


# --- text escaping ----------------------------------------------------------------------------

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


# --- width of a LaTeX math string -------------------------------------------------------------

_NAMED = {"sin": 3, "cos": 3, "tan": 3, "atan": 4, "operatorname": 0, "sqrt": 1, "pi": 1,
          "cdot": 1.5, "quad": 1.5, "qquad": 3, "ldots": 2.5, "dots": 2.5, "approx": 2, "in": 2,
          "mathsf": 0, "mathrm": 0, "boldsymbol": 0, "mathbf": 0, "text": 0, "xi": 1}
_ZERO = {"left", "right", "begin", "end", "displaystyle", "limits", "big", "Big"}
_SPACES = {",": 0.3, ";": 0.5, "!": -0.2, " ": 0.4}


def math_width(s: str) -> float:
    """Approximate printed width of LaTeX math ``s``, in letter widths.

    Subscripts and superscripts count 0.7, a fraction the wider of its parts,
    binary operators and relations 1.8 (their spacing included).

    Examples
    --------
    >>> math_width("a_{2} \\\\cos{\\\\left(q_{2} \\\\right)}")
    8.4
    """
    width, _ = _width(s, 0, 1.0)
    return round(width, 6)


def _group(s, i, scale):
    """Width of the brace group starting at s[i] == '{' (or of one token); return (w, next)."""
    if i >= len(s):
        return 0.0, i
    if s[i] == "{":
        return _width(s, i + 1, scale, stop="}")
    if s[i] == "\\":
        j = i + 1
        while j < len(s) and s[j].isalpha():
            j += 1
        return scale, max(j, i + 2)
    return scale, i + 1


def _width(s, i, scale, stop=None):
    w = 0.0
    n = len(s)
    while i < n:
        ch = s[i]
        if stop and ch == stop:
            return w, i + 1
        if ch == "{":
            gw, i = _width(s, i + 1, scale, stop="}")
            w += gw
            continue
        if ch in "^_":
            gw, i = _group(s, i + 1, scale * 0.7)
            w += gw
            continue
        if ch == "\\":
            j = i + 1
            while j < n and s[j].isalpha():
                j += 1
            name = s[i + 1:j]
            if not name:  # \, \; \! \\ \{ ...
                sym = s[i + 1:i + 2]
                w += scale * _SPACES.get(sym, 1.0 if sym not in "\\" else 0.0)
                i += 2
                continue
            i = j
            if name == "frac":
                a, i = _group(s, i, scale)
                b, i = _group(s, i, scale)
                w += max(a, b) + 0.4 * scale
            elif name in ("begin", "end"):
                _, i = _group(s, i, 0.0)
            elif name in _ZERO:
                pass
            elif name in ("operatorname", "mathrm", "text", "mathsf", "mathbf", "boldsymbol"):
                gw, i = _group(s, i, scale)
                w += gw
            else:
                w += scale * _NAMED.get(name, 1.0)
            continue
        if ch in "+-=<>":
            w += 1.8 * scale
        elif ch in " &":
            pass
        else:
            w += scale
        i += 1
    return w, i


# --- compact forms -----------------------------------------------------------------------------

def latex(expr) -> str:
    """LaTeX of an expression, with ``q1`` printed as ``q_{1}`` and products by juxtaposition."""
    return sp.latex(expr)


def _angle_suffix(arg, variables):
    """``"2"`` for q2, ``"23"`` for q2 + q3 (``"2,13"`` when an index has two digits), else None."""
    index = {v: i for i, v in enumerate(variables, start=1)}
    plain = all(str(v) == f"q{i}" for v, i in index.items())
    if arg in index:
        return str(index[arg]) if plain else str(arg)
    if not (plain and arg.is_Add) or any(t not in index for t in arg.args):
        return None
    ks = sorted(index[t] for t in arg.args)
    return ("," if max(ks) > 9 else "").join(map(str, ks))


def abbreviations(variables, taken=(), atoms=()) -> dict:
    """``sin(q) -> s_i``, ``cos(q) -> c_i`` for each variable, unless a name would clash.

    ``atoms`` may add sines and cosines of sums of variables: ``sin(q2 + q3) -> s_23``.

    Examples
    --------
    >>> q1, q2 = sp.symbols("q1 q2")
    >>> ab = abbreviations([q1, q2], atoms=[sp.cos(q1 + q2)])
    >>> ab[sp.sin(q2)], ab[sp.cos(q1)], ab[sp.cos(q1 + q2)]
    (s_2, c_1, c_12)
    """
    taken = {str(t) for t in taken}
    args = list(variables) + [a.args[0] for a in atoms if isinstance(a, (sp.sin, sp.cos))]
    out = {}
    for arg in args:
        suffix = _angle_suffix(arg, variables)
        if suffix is None:
            continue
        s_name, c_name = f"s_{suffix}", f"c_{suffix}"
        if s_name in taken or c_name in taken:
            continue
        out[sp.sin(arg)] = sp.Symbol(s_name, real=True)
        out[sp.cos(arg)] = sp.Symbol(c_name, real=True)
    return out


def angle_sums(expr, max_terms: int = 64):
    """``expr`` with products of sines and cosines folded into functions of sums (TR10i).

    Examples
    --------
    >>> q2, q3 = sp.symbols("q2 q3")
    >>> angle_sums(sp.sin(q2)*sp.cos(q3) + sp.sin(q3)*sp.cos(q2))
    sin(q2 + q3)
    """
    from sympy.simplify.fu import TR10i

    if not expr.has(sp.sin, sp.cos) or len(sp.Add.make_args(expr)) > max_terms:
        return expr
    try:
        return TR10i(expr)
    except (RecursionError, ValueError, TypeError):  # pragma: no cover - sympy internals
        return expr


def compact(expr, parameters=()):
    """The narrowest of the expanded, factored and parameter-collected forms of ``expr``.

    Examples
    --------
    >>> a, b, x = sp.symbols("a b x")
    >>> y, z = sp.symbols("y z")
    >>> compact(a*b*x + a*b*y + a*b*z, [a, b])
    a*b*(x + y + z)
    """
    e = sp.expand(expr)
    candidates = [e]
    if e.is_Add and len(e.args) <= 64:
        candidates.append(_factor_safe(e))
        params = [p for p in parameters if e.has(p)]
        if params:
            collected = sp.collect(e, params, evaluate=False)
            if len(collected) > 1:
                candidates.append(sp.Add(*[_factor_safe(coeff) * key if key != 1 else coeff
                                           for key, coeff in collected.items()]))
    return min(candidates, key=lambda c: (math_width(latex(c)), len(sp.srepr(c))))


#: Factorisation is tried only on sums up to this size: larger ones seldom give a narrower
#: form than collecting by parameters.
FACTOR_MAX_TERMS = 64


def factor_rational(e):
    """``e`` (a polynomial with rational coefficients) factored with python-flint, or None.

    sympy's own multivariate factorisation takes a tenth of a second to seconds
    per Jacobian entry; flint's takes microseconds.

    Examples
    --------
    >>> a, x, y = sp.symbols("a x y")
    >>> factor_rational(a*x**2 - a*y**2)
    a*(x - y)*(x + y)
    """
    import flint

    syms = sorted(e.free_symbols, key=str)
    if not syms:
        return e
    try:
        P = sp.Poly(e, *syms)
    except sp.PolynomialError:
        return None
    if not (P.domain.is_ZZ or P.domain.is_QQ):
        return None
    ctx = flint.fmpq_mpoly_ctx.get(tuple(f"v{k}" for k in range(len(syms))), "degrevlex")
    terms = {m: flint.fmpq(int(sp.Rational(c).p), int(sp.Rational(c).q)) for m, c in P.terms()}
    const, factors = ctx.from_dict(terms).factor()

    def back(q):
        return sp.Add(*[sp.Rational(int(c.p), int(c.q)) * sp.Mul(*[s ** k for s, k in zip(syms, m)])
                        for m, c in q.to_dict().items()])

    const = sp.Rational(int(const.p), int(const.q))
    return const * sp.Mul(*[back(f) ** int(k) for f, k in factors])


def _factor_safe(e):
    """The factored form of ``e`` when it is narrower, else ``e``."""
    if len(sp.Add.make_args(e)) > FACTOR_MAX_TERMS:
        return e
    f = factor_rational(e)
    if f is None:
        return e
    return f if math_width(latex(f)) < math_width(latex(e)) else e


def terms_latex(expr) -> list[str]:
    """The printed terms of a sum, each with its sign: ``['a', '- b', '+ c']``."""
    e = expr
    if not e.is_Add:
        return [latex(e)]
    out = []
    for k, t in enumerate(e.as_ordered_terms()):
        tl = latex(t)
        if k == 0:
            out.append(tl)
        elif tl.startswith("-"):
            out.append("- " + tl[1:].lstrip())
        else:
            out.append("+ " + tl)
    return out


def broken_lines(expr, *, lead: str = "", tail: str = "", width: float = LINE_WIDTH) -> list[str]:
    """``lead + expr + tail`` as lines of at most ``width``, broken between terms.

    A product, or a sum with a term, whose printed form is too wide is expanded
    first, so that it can be broken; a single term of the expanded form wider
    than a line stays on its own line.

    Examples
    --------
    >>> x = sp.Symbol("x")
    >>> broken_lines(sum(x**k for k in range(1, 4)), width=4)
    ['x^{3}', '+ x^{2}', '+ x']
    """
    whole = lead + latex(expr) + tail
    if math_width(whole) <= width:
        return [whole]
    e = expr
    if not e.is_Add:
        ex = sp.expand(e)
        if ex.is_Add:
            e = ex
    terms = terms_latex(e)
    if any(math_width(t) > width for t in terms):
        # a term too wide for a line (a long factor in parentheses): break the expanded form
        ex = sp.expand(expr)
        if ex.is_Add and len(ex.args) > len(terms):
            terms = terms_latex(ex)
    lines, cur = [], lead
    for t in terms:
        cand = (cur + " " + t) if cur.strip() and not cur.endswith(" ") else (cur + t)
        if cur.strip() and cur != lead and math_width(cand) > width:
            lines.append(cur)
            cur = t
        else:
            cur = cand
    cur += tail
    lines.append(cur)
    return lines


# --- numbers -----------------------------------------------------------------------------------

def trig_latex(f) -> str:
    r"""``\cos q_{2}`` for cos(q2), ``\sin(q_{2} + q_{3})`` for sin(q2 + q3).

    Examples
    --------
    >>> q2, q3 = sp.symbols("q2 q3")
    >>> trig_latex(sp.cos(q2)), trig_latex(sp.sin(q2 + q3))
    ('\\cos q_{2}', '\\sin(q_{2} + q_{3})')
    """
    name = type(f).__name__
    arg = f.args[0]
    if arg.is_Symbol:
        return rf"\{name} {latex(arg)}"
    return rf"\{name}({latex(arg)})"


def value_latex(v) -> str:
    """An exact value, with its decimal value when it is not a rational multiple of pi.

    Examples
    --------
    >>> value_latex(sp.pi / 2)
    '\\\\frac{\\\\pi}{2}'
    >>> value_latex(2 * sp.atan(sp.Rational(1, 3)))
    '2 \\\\operatorname{atan}{\\\\left(\\\\frac{1}{3} \\\\right)} \\\\approx 0.643501'
    """
    v = sp.sympify(v)
    text = latex(v)
    if not (v / sp.pi).is_rational:
        text += rf" \approx {float(v):.6g}"
    return text


def vector_latex(vec, digits: int = 3) -> str:
    """A numeric vector as a LaTeX row ``(+0.123, -0.456)``."""
    return r"\left(" + ", ".join(f"{x:+.{digits}f}" for x in vec) + r"\right)"


# --- the Jacobian -------------------------------------------------------------------------------

@dataclass(frozen=True)
class JacobianDisplay:
    """A symbolic matrix prepared for display.

    Attributes
    ----------
    entries : tuple of tuple of sympy.Expr
        Compact entries, in the abbreviations and the common subexpressions.
    abbreviations : tuple of (Symbol, Expr)
        ``s_i = sin q_i``, ``c_i = cos q_i`` for the variables that occur.
    definitions : tuple of (Symbol, Expr)
        Common subexpressions ``xi_k``, in the order they must be read.
    layout : str
        ``"matrix"`` (the whole matrix fits on a line) or ``"columns"``.
    row_labels, column_labels : tuple of str
    """

    entries: tuple
    abbreviations: tuple
    definitions: tuple
    layout: str
    row_labels: tuple
    column_labels: tuple

    @property
    def shape(self):
        return (len(self.entries), len(self.entries[0]) if self.entries else 0)


def jacobian_display(matrix, variables, parameters=(), row_labels=(), *,
                     width: float = LINE_WIDTH) -> JacobianDisplay:
    """Prepare ``matrix`` (a sympy matrix in ``variables``) for display.

    Examples
    --------
    >>> q1, q2, l1, l2 = sp.symbols("q1 q2 l1 l2")
    >>> J = sp.Matrix([[-l1*sp.sin(q1) - l2*sp.sin(q1 + q2)]])
    >>> jacobian_display(J, [q1, q2], [l1, l2]).entries[0][0]
    -l1*s_1 - l2*s_12
    """
    M = sp.Matrix(matrix)
    names = {str(s) for e in M for s in e.free_symbols}
    summed = [angle_sums(e) for e in M]
    atoms = set().union(*(e.atoms(sp.sin, sp.cos) for e in summed)) if summed else set()
    ab = abbreviations(variables, names, sorted(atoms, key=sp.default_sort_key))
    params = sorted(parameters, key=str)
    entries = [[None] * M.cols for _ in range(M.rows)]
    for k, (plain, folded) in enumerate(zip(M, summed)):
        a = compact(plain.xreplace(ab), params)
        b = compact(folded.xreplace(ab), params) if folded is not plain else a
        entries[k // M.cols][k % M.cols] = min(a, b, key=lambda e: math_width(latex(e)))
    used = set().union(*(e.free_symbols for row in entries for e in row)) if entries else set()
    abbrevs = tuple((s, f) for f, s in ab.items() if s in used)
    abbrevs = tuple(sorted(abbrevs, key=lambda p: (_arg_key(p[1], variables), str(p[0])[0] == "s")))
    entries, definitions = _named_subexpressions(entries, params)
    cols = [str(v) for v in variables]
    layout = "matrix" if _matrix_width(entries) <= width else "columns"
    return JacobianDisplay(tuple(tuple(r) for r in entries), abbrevs, tuple(definitions), layout,
                           tuple(row_labels), tuple(cols))


def _arg_key(f, variables):
    arg = f.args[0]
    vs = list(variables)
    terms = sp.Add.make_args(arg)
    return (len(terms), [vs.index(t) if t in vs else len(vs) for t in terms])


def _matrix_width(entries) -> float:
    if not entries:
        return 0.0
    cols = len(entries[0])
    widths = [max(math_width(latex(entries[i][j])) for i in range(len(entries))) for j in range(cols)]
    return sum(widths) + 2.0 * (cols - 1) + 4.0


def _total_width(entries, definitions=()) -> float:
    return (sum(math_width(latex(e)) for row in entries for e in row)
            + sum(math_width(latex(d)) + 3 for _, d in definitions))


def _named_subexpressions(entries, params):
    """Name common subexpressions when that shortens the matrix by CSE_MIN_GAIN."""
    flat = [e for row in entries for e in row]
    if not flat or all(e.is_Atom or e.is_number for e in flat):
        return entries, []
    taken = {str(s) for e in flat for s in e.free_symbols}
    xi = (sp.Symbol(f"xi_{k}") for k in range(1, 10_000) if f"xi_{k}" not in taken)
    try:
        replacements, reduced = sp.cse(flat, symbols=xi, order="canonical")
    except (RecursionError, ValueError):  # pragma: no cover - sympy internals
        return entries, []
    # put back the narrow ones
    keep, back = [], {}
    for sym, expr in replacements:
        expr = expr.xreplace(back)
        if math_width(latex(expr)) < CSE_MIN_WIDTH:
            back[sym] = expr
        else:
            keep.append((sym, expr))
    reduced = [r.xreplace(back) for r in reduced]
    # renumber the kept ones 1, 2, ... in order of definition
    renumber = {}
    for k, (sym, _) in enumerate(keep, start=1):
        renumber[sym] = sp.Symbol(f"xi_{k}")
    keep = [(renumber[s], e.xreplace(renumber)) for s, e in keep]
    reduced = [compact(r.xreplace(renumber), params) for r in reduced]
    cols = len(entries[0])
    new = [reduced[i * cols:(i + 1) * cols] for i in range(len(entries))]
    if not keep or _total_width(new, keep) > (1 - CSE_MIN_GAIN) * _total_width(entries):
        return entries, []
    return new, keep
