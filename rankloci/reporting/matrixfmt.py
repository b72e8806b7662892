"""A symbolic Jacobian prepared for display: compact entries, abbreviations, named subexpressions.

:func:`jacobian_display` writes each entry in its narrowest form (see
:func:`~rankloci.reporting.mathfmt.compact`) in the ``s_i``/``c_i``
abbreviations of the sines and cosines, names common subexpressions
``xi_k`` when that shortens the matrix enough, and decides whether the
whole matrix fits on a line or is shown column by column.  Pure.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .mathfmt import LINE_WIDTH, abbreviations, angle_sums, compact, latex, math_width

__all__ = ["JacobianDisplay", "jacobian_display", "CSE_MIN_GAIN", "CSE_MIN_WIDTH"]

#: Common subexpressions are named only when that shortens the matrix by this fraction.
CSE_MIN_GAIN = 0.2

#: A common subexpression narrower than this is put back: naming it does not help a reader.
CSE_MIN_WIDTH = 10.0


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
