"""Safe parsing of expression strings from model files.

Model files are data.  An expression string is parsed with :mod:`ast` and the
tree is walked by hand: only numbers, whitelisted names, the arithmetic
operators and calls of whitelisted functions are accepted, and the sympy
expression is built node by node.  Nothing is ever passed to ``eval``,
``exec`` or ``sympy.sympify`` (which evaluates strings), so a hostile file
cannot run code.

Floats become exact rationals of their shortest decimal form (``0.4318`` is
``2159/5000``), so later polynomial algebra stays exact.
"""

from __future__ import annotations

import ast
import math
import warnings
from fractions import Fraction
from typing import Mapping

import sympy as sp

from .errors import ExpressionError
from .tolerances import ANGLE_SNAP_ATOL

__all__ = ["parse_expression", "exact_number", "snap_angle", "FUNCTIONS", "AngleSnapWarning"]

#: Functions an expression may call, by name.
FUNCTIONS = {
    "sin": sp.sin,
    "cos": sp.cos,
    "tan": sp.tan,
    "sqrt": sp.sqrt,
    "atan2": sp.atan2,
    "asin": sp.asin,
    "acos": sp.acos,
    "atan": sp.atan,
    "exp": sp.exp,
    "abs": sp.Abs,
}

#: Constants an expression may name.
CONSTANTS = {"pi": sp.pi, "E": sp.E}

MAX_LENGTH = 2000          # characters in one expression
MAX_DEPTH = 50             # nesting depth of the syntax tree
MAX_EXPONENT = 64          # largest |integer exponent| accepted in a power
MAX_DIGITS = 40            # longest integer literal accepted

_BINOPS = {
    ast.Add: lambda a, b: a + b,
    ast.Sub: lambda a, b: a - b,
    ast.Mult: lambda a, b: a * b,
    ast.Div: lambda a, b: a / b,
}


class AngleSnapWarning(UserWarning):
    """A float angle was replaced by the exact multiple of pi/12 it approximates."""


def exact_number(value) -> sp.Expr:
    """Exact sympy number for an int, a float or a decimal string.

    Examples
    --------
    >>> exact_number(0.4318)
    2159/5000
    >>> exact_number(3)
    3
    """
    if isinstance(value, bool):
        raise ExpressionError(repr(value), "a boolean is not a number")
    if isinstance(value, int):
        return sp.Integer(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ExpressionError(repr(value), "number is not finite")
        f = Fraction(repr(value))
        return sp.Rational(f.numerator, f.denominator)
    if isinstance(value, str):
        try:
            return exact_number(float(value)) if any(ch in value for ch in ".eE") else sp.Integer(int(value))
        except ValueError:
            raise ExpressionError(value, "not a number") from None
    raise ExpressionError(repr(value), f"expected a number, got {type(value).__name__}")


def snap_angle(value: float) -> sp.Expr | None:
    """The exact multiple of pi/12 within ANGLE_SNAP_ATOL of ``value``, or None.

    Examples
    --------
    >>> snap_angle(1.5707963267948966)
    pi/2
    >>> snap_angle(0.3) is None
    True
    """
    k = round(value / (math.pi / 12))
    if abs(value - k * math.pi / 12) <= ANGLE_SNAP_ATOL:
        return sp.pi * sp.Rational(k, 12)
    return None


def angle_value(value, *, what: str = "angle") -> sp.Expr:
    """Exact angle from a float, snapping multiples of pi/12 with a warning."""
    if isinstance(value, float) and value != 0.0 and math.isfinite(value):  # nan/inf: exact_number refuses
        snapped = snap_angle(value)
        if snapped is not None:
            warnings.warn(f"{what}: float {value!r} taken as exact {snapped}", AngleSnapWarning,
                          stacklevel=2)
            return snapped
    return exact_number(value)


def parse_expression(text, names: Mapping[str, sp.Expr] | None = None) -> sp.Expr:
    """Parse an expression string into a sympy expression, safely.

    Parameters
    ----------
    text : str, int or float
        The expression.  Numbers are accepted as they are.
    names : mapping, optional
        The names the expression may use (joint variables, parameters), mapped
        to their symbols.  ``pi`` and the functions in :data:`FUNCTIONS` are
        always allowed.

    Raises
    ------
    ExpressionError
        On a syntax error, an unknown name, or any construct other than
        numbers, names, ``+ - * / **``, unary minus and calls of the allowed
        functions.

    Examples
    --------
    >>> import sympy as sp
    >>> q1 = sp.Symbol("q1", real=True)
    >>> parse_expression("cos(q1) - pi/2", {"q1": q1})
    cos(q1) - pi/2
    >>> parse_expression("__import__('os')")
    Traceback (most recent call last):
    ...
    rankloci.errors.ExpressionError: cannot parse "__import__('os')": call of '__import__' is not allowed
    """
    if not isinstance(text, str):
        return exact_number(text)
    names = dict(names or {})
    if len(text) > MAX_LENGTH:
        raise ExpressionError(text[:40] + "...", f"longer than {MAX_LENGTH} characters")
    if not text.strip():
        raise ExpressionError(text, "empty expression")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", SyntaxWarning)
            tree = ast.parse(text.strip(), mode="eval")
    except (SyntaxError, ValueError):
        raise ExpressionError(text, "invalid syntax") from None
    except RecursionError:
        raise ExpressionError(text, "nested too deeply") from None
    try:
        return _checked(_build(tree.body, text, names, 0), text)
    except RecursionError:
        raise ExpressionError(text, "nested too deeply") from None


MAX_NUMBER_DIGITS = 200    # digits of any exact number inside an expression


def _checked(value, text):
    """Refuse results with huge numbers or huge powers (they would stall the algebra)."""
    for atom in value.atoms(sp.Rational):
        if len(str(abs(atom.p))) > MAX_NUMBER_DIGITS or len(str(atom.q)) > MAX_NUMBER_DIGITS:
            raise ExpressionError(text, f"a number with more than {MAX_NUMBER_DIGITS} digits")
    for power in value.atoms(sp.Pow):
        e = power.exp
        if e.is_Rational and (abs(e.p) > MAX_EXPONENT or e.q > MAX_EXPONENT):
            raise ExpressionError(text, f"exponent larger than {MAX_EXPONENT}")
    return value


def _build(node, text, names, depth):
    if depth > MAX_DEPTH:
        raise ExpressionError(text, "nested too deeply")
    depth += 1
    if isinstance(node, ast.Constant):
        v = node.value
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise ExpressionError(text, f"literal {v!r} is not a number")
        if isinstance(v, int) and len(str(abs(v))) > MAX_DIGITS:
            raise ExpressionError(text, "integer literal too long")
        return exact_number(v)
    if isinstance(node, ast.Name):
        if node.id in names:
            return names[node.id]
        if node.id in CONSTANTS:
            return CONSTANTS[node.id]
        if node.id in FUNCTIONS:
            raise ExpressionError(text, f"function {node.id!r} used without arguments")
        raise ExpressionError(text, f"unknown name {node.id!r}")
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
        arg = _build(node.operand, text, names, depth)
        return -arg if isinstance(node.op, ast.USub) else arg
    if isinstance(node, ast.BinOp):
        if isinstance(node.op, ast.Pow):
            base = _build(node.left, text, names, depth)
            exp = _build(node.right, text, names, depth)
            if not exp.is_number:
                raise ExpressionError(text, "exponent must be a number")
            if exp.is_Integer and abs(int(exp)) > MAX_EXPONENT:
                raise ExpressionError(text, f"exponent larger than {MAX_EXPONENT}")
            if not exp.is_Rational:
                raise ExpressionError(text, "exponent must be rational")
            if abs(exp.p) > MAX_EXPONENT or exp.q > MAX_EXPONENT:
                raise ExpressionError(text, f"exponent larger than {MAX_EXPONENT}")
            if base.is_zero and exp.is_negative:
                raise ExpressionError(text, "division by zero")
            if abs(exp.p) * max([max(abs(r.p), r.q).bit_length() for r in base.atoms(sp.Rational)], default=0) > 4 * MAX_DIGITS * MAX_EXPONENT:
                raise ExpressionError(text, "number too large")  # (9**64)**64)**64... would take minutes
            return _checked(base ** exp, text)
        op = _BINOPS.get(type(node.op))
        if op is None:
            raise ExpressionError(text, f"operator {type(node.op).__name__} is not allowed")
        left = _build(node.left, text, names, depth)
        right = _build(node.right, text, names, depth)
        if isinstance(node.op, ast.Div) and right.is_zero:
            raise ExpressionError(text, "division by zero")
        return _checked(op(left, right), text)
    if isinstance(node, ast.Call):
        if not isinstance(node.func, ast.Name) or node.func.id not in FUNCTIONS:
            what = node.func.id if isinstance(node.func, ast.Name) else type(node.func).__name__
            raise ExpressionError(text, f"call of {what!r} is not allowed")
        if node.keywords:
            raise ExpressionError(text, "keyword arguments are not allowed")
        fname = node.func.id
        nargs = 2 if fname == "atan2" else 1
        if len(node.args) != nargs:
            raise ExpressionError(text, f"{fname} takes {nargs} argument(s)")
        args = [_build(a, text, names, depth) for a in node.args]
        if any(isinstance(a, ast.Starred) for a in node.args):
            raise ExpressionError(text, "starred arguments are not allowed")
        return FUNCTIONS[fname](*args)
    raise ExpressionError(text, f"{type(node).__name__} is not allowed in an expression")
