"""Everything the library accepts as a model, turned into a rankloci model.

:func:`as_model` is what every public function calls first: a built-in
model name, a path to a ``.toml`` or ``.urdf`` file, a
:class:`~rankloci.model.RobotModel` or :class:`~rankloci.model.MatrixModel`,
a sympy matrix, a Robotics Toolbox ``DHRobot`` or a Pinocchio ``Model``.
"""

from __future__ import annotations

import json
import os
import re
from typing import TYPE_CHECKING, Any

__all__ = ["as_model", "matrix_model"]

if TYPE_CHECKING:
    from collections.abc import Mapping, Sequence
    from typing import TypeAlias

    import sympy as sp

    from ..model import MatrixModel, RobotModel

    #: What the public functions take as a model: a built-in model name or a
    #: ``.toml`` / ``.urdf`` path, a model, a sympy matrix, or a Robotics Toolbox
    #: ``DHRobot`` or Pinocchio ``Model`` (optional packages, hence ``Any``).
    ModelLike: TypeAlias = str | os.PathLike[str] | RobotModel | MatrixModel | sp.MatrixBase | Any
    #: The column variables of a sympy matrix, as symbols or names.
    Variables: TypeAlias = Sequence[sp.Symbol | str]
    #: Parameter symbol or name -> value (a number or an exact sympy value).
    ParameterValues: TypeAlias = Mapping[sp.Symbol | str, int | float | sp.Expr | str]

from ..errors import ArgumentError, ModelError

_IDENT = re.compile(r"^[A-Za-z_][A-Za-z0-9_]{0,31}\Z")


def _toml_value(value) -> str:
    """A parameter value written into TOML: a number, or an exact expression string."""
    import sympy as sp

    if isinstance(value, bool):
        raise ArgumentError(f"parameters=: value {value!r} is not a number")
    if isinstance(value, (int, float)):
        return repr(value)
    from ..errors import ExpressionError, ModelError
    from ..expr import as_expression

    try:
        expr = as_expression(value, {})   # a string is parsed as a model file's would be
    except ExpressionError as e:
        raise ModelError(f"parameters=: {e}") from None
    if expr.free_symbols or not expr.is_real:
        raise ArgumentError(f"parameters=: value {value!r} is not a real number")
    if isinstance(expr, sp.Integer):
        return str(int(expr))
    if isinstance(expr, sp.Float) or (expr.is_Rational and _decimal_exact(expr)):
        return repr(float(expr))
    return json.dumps(sp.sstr(expr))


def _decimal_exact(r) -> bool:
    """Is the rational ``r`` what a model file reads from ``repr(float(r))``?"""
    from ..errors import ExpressionError
    from ..expr import exact_number

    try:
        return exact_number(float(r)) == r
    except ExpressionError:      # too large for a model file's number
        return False


def matrix_model(matrix, *, variables=None, parameters=None, name: str = "matrix"):
    """A :class:`~rankloci.model.MatrixModel` from a sympy matrix.

    The matrix goes through the parser of raw-matrix model files, so it is
    validated as a file would be: floats become the exact rationals of their
    shortest decimal form, only ``sin cos tan sqrt ...`` are accepted, an entry
    may have up to 2000 characters (:data:`rankloci.expr.MAX_LENGTH`), and the
    symbols come back as real symbols of the same names.

    Parameters
    ----------
    matrix : sympy.Matrix
        Any shape.
    variables : sequence of sympy.Symbol or str, optional
        The column variables: the matrix loses rank at values of these.
        Default: every symbol that is not a parameter, in natural name order.
    parameters : mapping, optional
        Parameter symbol (or name) -> numeric value.  Parameters stay symbolic
        in the analysis; their values decide which components belong to this
        matrix and are used by the numeric checks.
    name : str, default "matrix"
        The model name (lowercase letters, digits, ``_`` and ``-``).

    Returns
    -------
    MatrixModel

    Raises
    ------
    rankloci.errors.ModelError
        A symbol that is neither a variable nor a parameter with a value, or
        an entry the parser refuses.

    Examples
    --------
    >>> import sympy as sp
    >>> x, k = sp.symbols("x k")
    >>> m = matrix_model(sp.Matrix([[sp.cos(x), k], [sp.sin(x), 1]]), parameters={k: 2})
    >>> m.variables, m.parameters
    ((x,), {k: 2})
    """
    import sympy as sp

    from ..errors import ModelError
    from ..expr import natural_key
    from ..io.toml_model import parse_model

    params = {str(k): v for k, v in (parameters or {}).items()}
    M = _sympy_matrix(matrix, [str(v) for v in variables or ()] + list(params))
    symbols = set().union(*(e.free_symbols for e in M)) if M else set()
    if variables is None:
        variables = sorted((s for s in symbols if s.name not in params), key=natural_key)
    names = [str(v) for v in variables]
    missing = sorted({s.name for s in symbols} - set(names) - set(params))
    if missing:
        raise ModelError(f"symbol {missing[0]!r} is neither a variable nor a parameter with a "
                         f"value; pass parameters={{{missing[0]!r}: value}} or list it in "
                         f"variables")
    for n in names + list(params):
        if not _IDENT.match(n):
            raise ModelError(f"{n!r} is not a usable symbol name (letters, digits and _)")
    rows = ",\n  ".join("[" + ", ".join(json.dumps(sp.sstr(e)) for e in M.row(i)) + "]"
                        for i in range(M.rows))
    text = (f"name = {json.dumps(name)}\nvariables = {json.dumps(names)}\n"
            f"matrix = [\n  {rows}\n]\n")
    if params:
        text += "[parameters]\n" + "".join(f"{k} = {_toml_value(v)}\n" for k, v in params.items())
    return parse_model(text)


def _sympy_matrix(matrix, names):
    """``matrix`` as a sympy Matrix; string entries are parsed over ``names``, never evaluated.

    ``sympy.Matrix`` would pass strings to ``sympify``, which evaluates them as Python.
    """
    import sympy as sp

    from ..errors import ExpressionError, ModelError
    from ..expr import as_expression

    if isinstance(matrix, sp.MatrixBase):
        return sp.Matrix(matrix)
    if isinstance(matrix, (str, bytes)):
        raise ArgumentError("matrix must be a sympy Matrix or a sequence of rows, not a string")
    symbols = {n: sp.Symbol(n, real=True) for n in names if _IDENT.match(n)}
    try:
        rows = [list(row) for row in matrix]
    except TypeError:
        raise ArgumentError(f"matrix must be a sympy Matrix or a sequence of rows, not a "
                        f"{type(matrix).__name__}") from None
    if any(isinstance(row, (str, bytes)) for row in matrix) or len({len(r) for r in rows}) > 1:
        raise ArgumentError("matrix must be a sequence of rows of equal length")
    try:
        return sp.Matrix([[as_expression(e, symbols) for e in row] for row in rows])
    except ExpressionError as e:
        raise ModelError(f"matrix entry: {e}") from None


def _is_from(obj, package: str) -> bool:
    module = type(obj).__module__ or ""
    return module == package or module.startswith(package + ".")


def _in_api_words(error):
    """A URDF reader's error as the Python API says it: ``tip=``, not ``--tip``.

    A tip or base link that is not in the file, or a file whose chain needs a
    tip, is an :class:`~rankloci.errors.ArgumentError` naming the argument.
    """
    message = error.message.replace("--base-link", "base_link=").replace("--tip", "tip=")
    if error.field in ("tip_link", "base_link") and error.joint is None:
        argument = "tip" if error.field == "tip_link" else "base_link"
        where = f" ({error.file})" if error.file else ""
        return ArgumentError(f"{argument}=: {message}{where}", argument=argument)
    return ModelError(message, file=error.file, joint=error.joint, field=error.field)


def as_model(model, *, variables=None, parameters=None, tip=None, base_link=None):
    """The rankloci model of anything the library accepts as one.

    Parameters
    ----------
    model : str, os.PathLike, RobotModel, MatrixModel, sympy.Matrix, DHRobot or pinocchio.Model
        A built-in model name or a ``.toml`` / ``.urdf`` path; a model; a
        symbolic matrix (see :func:`matrix_model`); a Robotics Toolbox DH
        robot (:func:`~rankloci.adapters.from_rtb`); a Pinocchio model
        (:func:`~rankloci.adapters.from_pinocchio`, ``tip`` names the frame).
    variables, parameters
        For a sympy matrix only.
    tip : str, optional
        For a URDF file or a Pinocchio model: the chain's last link or frame.
    base_link : str, optional
        For a URDF file: the chain's first link.

    Returns
    -------
    RobotModel or MatrixModel

    Examples
    --------
    >>> as_model("planar2r").variables
    (q1, q2)
    """
    import sympy as sp

    from ..io import load_model as load
    from ..jacobians import TaskMatrix
    from ..model import MatrixModel, RobotModel

    if (variables is not None or parameters is not None) and not isinstance(model, sp.MatrixBase):
        raise ArgumentError("variables= and parameters= apply to a sympy matrix only, not to "
                         f"{type(model).__name__}")
    if isinstance(model, (RobotModel, MatrixModel)):
        if tip is not None or base_link is not None:
            raise ArgumentError("tip= and base_link= apply to URDF files and Pinocchio models, "
                             f"not to a loaded {type(model).__name__}")
        bad = [k for k, v in dict(model.parameters).items() if not isinstance(v, sp.Basic)]
        if bad:
            # later substitutions would hand a string to sympify, which evaluates it
            raise ArgumentError(f"parameter {str(bad[0])!r} of {type(model).__name__} "
                             f"{model.name!r} has a {type(model.parameters[bad[0]]).__name__} "
                             "value; model parameters are sympy numbers (load_model parses "
                             "strings)")
        return model
    if isinstance(model, (str, os.PathLike)):
        spec = os.fspath(model)
        if (tip is not None or base_link is not None) and not spec.lower().endswith(".urdf"):
            raise ArgumentError(f"tip= and base_link= apply to URDF files and Pinocchio models; "
                             f"{spec!r} is neither")
        try:
            return load(spec, base_link=base_link, tip_link=tip)
        except ModelError as e:
            raise _in_api_words(e) from None
    if isinstance(model, sp.MatrixBase):
        return matrix_model(model, variables=variables, parameters=parameters)
    if isinstance(model, TaskMatrix):
        return matrix_model(model.matrix, variables=model.variables,
                            parameters=model.parameters, name=model.name)
    if _is_from(model, "roboticstoolbox"):
        from ..adapters import from_rtb

        return from_rtb(model)
    if _is_from(model, "pinocchio"):
        from ..adapters import from_pinocchio

        if base_link is not None:
            raise ArgumentError("base_link= applies to URDF files; a Pinocchio chain starts at "
                             "the model's root")
        return from_pinocchio(model, tip=tip)
    raise ArgumentError(f"cannot use a {type(model).__module__}.{type(model).__name__} as a model; "
                    "give a built-in model name, a .toml or .urdf path, a sympy Matrix, a "
                    "Robotics Toolbox DHRobot or a Pinocchio Model")
