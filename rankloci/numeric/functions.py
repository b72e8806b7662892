"""Numeric functions of sympy expressions of any size.

``sympy.lambdify`` writes an expression as one line of Python source.  A
sum of many thousand terms becomes a chain of additions nested as deep as
the sum is long, and Python's compiler stops with ``RecursionError:
maximum recursion depth exceeded during compilation`` (an iCub arm's
component equations, 30000 terms).  :func:`numpy_function` compiles such an
expression in pieces instead: a long sum or product is split into chunks of
at most :data:`CHUNK_TERMS` terms, each compiled on its own (recursively),
and the pieces are added or multiplied when the function is called.  The
values are the same; the function is called as the one lambdify returns.
"""

from __future__ import annotations

import functools
import operator

import sympy as sp

__all__ = ["numpy_function", "CHUNK_TERMS"]

#: Terms of a sum (factors of a product) compiled together: far below the nesting at which
#: Python's compiler runs out of recursion (a few thousand), and large enough that the calls
#: between pieces cost nothing next to the arithmetic.
CHUNK_TERMS = 400


def numpy_function(variables, exprs, *, modules="numpy", cse=False):
    """``sympy.lambdify(variables, exprs, modules, cse=cse)``, for expressions of any size.

    Parameters
    ----------
    variables : sequence of sympy.Symbol
    exprs : sympy.Expr or sequence of sympy.Expr
        A sequence gives a function returning a list, as with lambdify.
    modules, cse
        As for :func:`sympy.lambdify`.

    Examples
    --------
    >>> x, y = sp.symbols("x y")
    >>> f = numpy_function([x, y], sp.Add(*[x ** k * y for k in range(3000)]))
    >>> f(1.0, 2.0)
    6000.0
    """
    variables = tuple(variables)
    single = not isinstance(exprs, (list, tuple))
    items = [exprs] if single else list(exprs)
    try:
        if all(_size(e) <= CHUNK_TERMS for e in items):
            return sp.lambdify(variables, exprs if single else items, modules=modules, cse=cse)
    except RecursionError:
        pass
    parts = [_pieces(variables, sp.sympify(e, strict=True), modules, cse) for e in items]
    if single:
        return parts[0]

    def evaluate(*args):
        return [p(*args) for p in parts]

    return evaluate


def _size(e) -> int:
    e = sp.sympify(e, strict=True)
    return max([len(e.args)] + [len(a.args) for a in e.args]) if e.args else 0


def _pieces(variables, e, modules, cse):
    if isinstance(e, (sp.Add, sp.Mul)) and len(e.args) > CHUNK_TERMS:
        args = e.args
        chunks = [e.func(*args[i:i + CHUNK_TERMS]) for i in range(0, len(args), CHUNK_TERMS)]
        fs = [_pieces(variables, c, modules, cse) for c in chunks]
        combine = operator.add if isinstance(e, sp.Add) else operator.mul

        def evaluate(*a):
            return functools.reduce(combine, (f(*a) for f in fs))

        return evaluate
    try:
        return sp.lambdify(variables, e, modules=modules, cse=cse)
    except RecursionError:
        if not e.args:
            raise
        # a deep expression that is no long sum: its arguments in pieces, then its head
        fs = [_pieces(variables, a, modules, cse) for a in e.args]
        dummies = sp.symbols(f"a0:{len(fs)}", cls=sp.Dummy)
        head = sp.lambdify(dummies, e.func(*dummies), modules=modules)

        def evaluate(*a):
            return head(*(f(*a) for f in fs))

        return evaluate
