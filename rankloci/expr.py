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
import re
import warnings
from fractions import Fraction
from typing import Mapping

import sympy as sp

from .errors import ExpressionError
from .tolerances import ANGLE_SNAP_ATOL

__all__ = ["parse_expression", "as_expression", "exact_number", "snap_angle", "natural_key",
           "FUNCTIONS", "AngleSnapWarning"]

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
MAX_MAGNITUDE = 1e12       # largest |value| of a number (a length in metres, an angle, a factor)

#: Bits of the largest integer with MAX_DIGITS decimal digits.
_MAX_BITS = math.ceil(MAX_DIGITS * math.log2(10))

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
        # bit_length, not str(): str() of a 5000-digit integer raises ValueError
        if value.bit_length() > _MAX_BITS:
            raise ExpressionError(f"<integer of about {int(value.bit_length() * 0.30103) + 1} "
                                  "digits>", f"integer longer than {MAX_DIGITS} digits")
        return sp.Integer(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ExpressionError(repr(value), "number is not finite")
        if abs(value) > MAX_MAGNITUDE:
            raise ExpressionError(repr(value), f"number larger than {MAX_MAGNITUDE:g} in magnitude")
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


def parse_expression(text, names: Mapping[str, sp.Expr] | None = None, *,
                     bounded: bool = True) -> sp.Expr:
    """Parse an expression string into a sympy expression, safely.

    Parameters
    ----------
    text : str, int or float
        The expression.  Numbers are accepted as they are.
    names : mapping, optional
        The names the expression may use (joint variables, parameters), mapped
        to their symbols.  ``pi`` and the functions in :data:`FUNCTIONS` are
        always allowed.
    bounded : bool, default True
        Apply the size limits (:data:`MAX_LENGTH`, :data:`MAX_DEPTH`,
        :data:`MAX_EXPONENT`, :data:`MAX_DIGITS`, :data:`MAX_NUMBER_DIGITS`).
        Only text that rankloci itself wrote from an expression (a branch
        condition of its own tree) is read with ``bounded=False``; the syntax
        whitelist holds either way.

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
    if bounded and len(text) > MAX_LENGTH:
        raise ExpressionError(text[:40] + "...", f"longer than {MAX_LENGTH} characters")
    if not text.strip():
        raise ExpressionError(text, "empty expression")
    if not text.isascii():
        # Python folds identifiers to NFKC: a fullwidth letter would silently name another symbol
        bad = next(ch for ch in text if not ch.isascii())
        raise ExpressionError(text, f"non-ASCII character {bad!r}; expressions are plain ASCII")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", SyntaxWarning)
            tree = ast.parse(text.strip(), mode="eval")
    except (SyntaxError, ValueError):
        raise ExpressionError(text, "invalid syntax") from None
    except RecursionError:
        raise ExpressionError(text, "nested too deeply") from None
    try:
        if not bounded:
            return _build(tree.body, text, names, 0, bounded=False)
        return _checked(_build(tree.body, text, names, 0), text)
    except RecursionError:
        raise ExpressionError(text, "nested too deeply") from None


MAX_NUMBER_DIGITS = 200    # digits of any exact number inside an expression


def _checked(value, text):
    """Refuse results with huge numbers or huge powers (they would stall the algebra)."""
    if value.has(sp.I):
        raise ExpressionError(text, "not a real number (it involves sqrt(-1))")
    for atom in value.atoms(sp.Rational):
        if len(str(abs(atom.p))) > MAX_NUMBER_DIGITS or len(str(atom.q)) > MAX_NUMBER_DIGITS:
            raise ExpressionError(text, f"a number with more than {MAX_NUMBER_DIGITS} digits")
    for power in value.atoms(sp.Pow):
        e = power.exp
        if e.is_Rational and (abs(e.p) > MAX_EXPONENT or e.q > MAX_EXPONENT):
            raise ExpressionError(text, f"exponent larger than {MAX_EXPONENT}")
    return value


def _finite(value, text):
    """Refuse a constant that is not a real number of moderate size (exp(exp(100)), asin(2))."""
    if value.free_symbols or not value.is_number:
        return _checked(value, text)
    try:
        v = complex(sp.N(value, 15))
    except (OverflowError, TypeError, ValueError):
        raise ExpressionError(text, f"{sp.sstr(value)[:40]} is not a finite real number") from None
    if not (math.isfinite(v.real) and math.isfinite(v.imag)) or abs(v) > MAX_MAGNITUDE:
        raise ExpressionError(text, f"{sp.sstr(value)[:40]} is larger than {MAX_MAGNITUDE:g} "
                                    "in magnitude")
    if abs(v.imag) > 1e-12 * max(1.0, abs(v.real)):
        raise ExpressionError(text, f"{sp.sstr(value)[:40]} is not a real number")
    return _checked(value, text)


def _as_is(value, text):
    return value


def _build(node, text, names, depth, bounded=True):
    if bounded and depth > MAX_DEPTH:
        raise ExpressionError(text, "nested too deeply")
    depth += 1
    check, finite = (_checked, _finite) if bounded else (_as_is, _as_is)
    if isinstance(node, ast.Constant):
        v = node.value
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise ExpressionError(text, f"literal {v!r} is not a number")
        if not bounded:
            return sp.Integer(v) if isinstance(v, int) else exact_number(v)
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
        arg = _build(node.operand, text, names, depth, bounded)
        return -arg if isinstance(node.op, ast.USub) else arg
    if isinstance(node, ast.BinOp) and type(node.op) in _BINOPS:
        # a + b + c ... is parsed as ((a + b) + c) ...: a flat chain, not nesting
        chain = []
        while isinstance(node, ast.BinOp) and type(node.op) in _BINOPS:
            chain.append(node)
            node = node.left
        value = _build(node, text, names, depth, bounded)
        for link in reversed(chain):
            right = _build(link.right, text, names, depth, bounded)
            if isinstance(link.op, ast.Div) and right.is_zero:
                raise ExpressionError(text, "division by zero")
            value = check(_BINOPS[type(link.op)](value, right), text)
        return value
    if isinstance(node, ast.BinOp):
        if isinstance(node.op, ast.Pow):
            base = _build(node.left, text, names, depth, bounded)
            exp = _build(node.right, text, names, depth, bounded)
            if not exp.is_number:
                raise ExpressionError(text, "exponent must be a number")
            if not exp.is_Rational:
                raise ExpressionError(text, "exponent must be rational")
            if not bounded:
                if base.is_zero and exp.is_negative:
                    raise ExpressionError(text, "division by zero")
                return base ** exp
            if exp.is_Integer and abs(int(exp)) > MAX_EXPONENT:
                raise ExpressionError(text, f"exponent larger than {MAX_EXPONENT}")
            if abs(exp.p) > MAX_EXPONENT or exp.q > MAX_EXPONENT:
                raise ExpressionError(text, f"exponent larger than {MAX_EXPONENT}")
            if base.is_zero and exp.is_negative:
                raise ExpressionError(text, "division by zero")
            bits = max([max(abs(r.p), r.q).bit_length() for r in base.atoms(sp.Rational)], default=0)
            if abs(exp.p) * bits > 4 * MAX_DIGITS * MAX_EXPONENT:
                raise ExpressionError(text, "number too large")  # (9**64)**64)**64... would take minutes
            return check(base ** exp, text)
        op = _BINOPS.get(type(node.op))
        if op is None:
            raise ExpressionError(text, f"operator {type(node.op).__name__} is not allowed")
        left = _build(node.left, text, names, depth, bounded)
        right = _build(node.right, text, names, depth, bounded)
        if isinstance(node.op, ast.Div) and right.is_zero:
            raise ExpressionError(text, "division by zero")
        return check(op(left, right), text)
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
        if any(isinstance(a, ast.Starred) for a in node.args):
            raise ExpressionError(text, "starred arguments are not allowed")
        args = [_build(a, text, names, depth, bounded) for a in node.args]
        return finite(FUNCTIONS[fname](*args), text)
    raise ExpressionError(text, f"{type(node).__name__} is not allowed in an expression")


def as_expression(value, names: Mapping[str, sp.Expr] | None = None) -> sp.Expr:
    """A sympy expression from a value handed to the Python API.

    A string is parsed by :func:`parse_expression` over ``names``, as a model
    file's would be, never by ``sympy.sympify`` (which evaluates strings as
    Python).  A sympy object is returned as it is; a number becomes a sympy
    number; anything else is refused.

    Raises
    ------
    ExpressionError
        A string the parser refuses, a boolean, or an object that is neither
        a number nor a sympy object.

    Examples
    --------
    >>> k = sp.Symbol("k")
    >>> as_expression("2*k + 1", {"k": k}), as_expression(0.5)
    (2*k + 1, 0.500000000000000)
    >>> as_expression("__import__('os').getcwd()")
    Traceback (most recent call last):
    ...
    rankloci.errors.ExpressionError: cannot parse "__import__('os').getcwd()": call of 'Attribute' is not allowed
    """
    if isinstance(value, str):
        return parse_expression(value, names)
    if isinstance(value, sp.Basic):
        return value
    if isinstance(value, bool):
        raise ExpressionError(repr(value), "a boolean is not a number")
    try:
        # strict: numbers and objects that convert themselves; never a string, never str(value)
        return sp.sympify(value, strict=True)
    except sp.SympifyError:
        raise ExpressionError(repr(value)[:40], f"a {type(value).__name__} is not a number or "
                                                "an expression") from None


def natural_key(symbol) -> list:
    """A sort key that puts ``q2`` before ``q10``: the digits of a name compare as numbers.

    Examples
    --------
    >>> sorted(sp.symbols("q10 q2 d1"), key=natural_key)
    [d1, q2, q10]
    """
    return [int(t) if t.isdigit() else t for t in re.split(r"(\d+)", str(symbol))]
