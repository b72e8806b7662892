"""LaTeX math shared by the Markdown and the LaTeX report: compact forms, widths, line breaks.

Both renderings carry their equations as LaTeX math, so the work of making an
expression short enough to read is done once here: trigonometric functions of
the joint variables are abbreviated (``s_2 = sin q2``, ``c_2 = cos q2``, the
usual robotics notation), each expression is written in the shortest of its
expanded, factored and parameter-collected forms, and lines that are too wide
for a page are broken between terms.  :mod:`~rankloci.reporting.matrixfmt` builds
the display of a whole Jacobian on these; :mod:`~rankloci.reporting.escape`
escapes the plain text around the math.

Everything here is pure: expressions in, strings and expressions out.
"""

from __future__ import annotations

import re

import sympy as sp

from ..expr import as_expression

__all__ = ["LINE_WIDTH", "FACTOR_MAX_TERMS", "math_width", "latex", "abbreviations",
           "angle_sums", "compact", "factor_rational", "terms_latex", "broken_lines",
           "trig_latex", "value_latex"]

#: Width, in :func:`math_width` units (about one letter of 11 pt math), of a displayed line
#: that fits between the margins of the report's page (15.9 cm of text at 11 pt) and of a
#: typical one-column paper page.  Calibrated on the built-in models: no overfull box.
LINE_WIDTH = 62.0


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

#: Integers with more digits than this are displayed rounded (a URDF's exact rationals give
#: coefficients of 19 digits and more); the plain-text equations and the JSON keep them exact.
LONG_INTEGER_DIGITS = 8

#: Significant digits of a long integer as displayed, ``1.23457 \cdot 10^{18}``.
SHOWN_DIGITS = 6

_LONG_INTEGER = re.compile(r"(?<![\d.])(\d{%d,})(?![\d.])" % (LONG_INTEGER_DIGITS + 1))


def scaled_integers(text: str) -> str:
    r"""LaTeX ``text`` with each integer of more than LONG_INTEGER_DIGITS digits rounded.

    Examples
    --------
    >>> scaled_integers(r"1234567890123456789 a_{2} + 12 c_{3}")
    '1.23457 \\cdot 10^{18} a_{2} + 12 c_{3}'
    """
    def rounded(m):
        mant, exp = f"{int(m.group(1)):.{SHOWN_DIGITS - 1}e}".split("e")
        return rf"{mant} \cdot 10^{{{int(exp)}}}"

    return _LONG_INTEGER.sub(rounded, text)


def has_long_integers(expr) -> bool:
    """Does ``expr`` hold an integer (or a rational's part) that :func:`latex` rounds?"""
    top = 10 ** LONG_INTEGER_DIGITS
    for r in sp.sympify(expr, strict=True).atoms(sp.Rational):
        if abs(r.p) >= top or abs(r.q) >= top:
            return True
    return False


def latex(expr) -> str:
    """LaTeX of an expression, with ``q1`` printed as ``q_{1}`` and products by juxtaposition.

    Integers of more than :data:`LONG_INTEGER_DIGITS` digits are shown to
    :data:`SHOWN_DIGITS` significant digits (:func:`scaled_integers`).
    """
    return scaled_integers(sp.latex(expr))


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
    v = as_expression(v)
    text = latex(v)
    if not (v / sp.pi).is_rational:
        text += rf" \approx {float(v):.6g}"
    return text
