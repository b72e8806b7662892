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
    shortest decimal form and the symbols come back as real symbols of the
    same names.  A sympy entry longer than a file's expression
    (:data:`rankloci.expr.MAX_LENGTH` characters) is taken as it is, by the
    same rules.  Symbols of any name are accepted (``θ``,
    ``q'``): a name a model file cannot hold is carried under a stand-in
    (``_s0``, ``_s1``, ... in the returned model), and :func:`rankloci.locus`
    and :func:`rankloci.jacobian` give the caller's own symbol back.
    Each entry must be a polynomial in the variables and in sines and cosines
    of them, with parameters and numbers as coefficients; one that is not
    (``Abs(x)``, ``exp(x)``, ``1/x``, ``tan(x)``) is refused here, before any
    computation, naming the entry.

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
    if isinstance(matrix, sp.MatrixBase):
        _check_functions(matrix)
        stand_ins = stand_in_names(matrix, variables, params)
        if stand_ins:
            return _with_stand_ins(matrix, variables, params, name, stand_ins)
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
    from ..expr import MAX_LENGTH

    texts = [[sp.sstr(e) for e in M.row(i)] for i in range(M.rows)]
    # an entry longer than a model file's expression is the caller's sympy object already:
    # it is not read back from text, but taken with the parser's rules (below)
    long = {(i, j) for i, row in enumerate(texts) for j, t in enumerate(row)
            if len(t) > MAX_LENGTH} if isinstance(matrix, sp.MatrixBase) else set()
    rows = ",\n  ".join("[" + ", ".join(json.dumps("0" if (i, j) in long else t)
                                        for j, t in enumerate(row)) + "]"
                        for i, row in enumerate(texts))
    text = (f"name = {json.dumps(name)}\nvariables = {json.dumps(names)}\n"
            f"matrix = [\n  {rows}\n]\n")
    if params:
        text += "[parameters]\n" + "".join(f"{k} = {_toml_value(v)}\n" for k, v in params.items())
    model = parse_model(text)
    if long:
        model = _with_entries(model, {ij: M[ij] for ij in long})
    _check_polynomial(model)
    return model


def _with_entries(model, entries):
    """``model`` with the given sympy entries, as the parser would read them: each symbol the
    real symbol of its name, each float the exact rational of its shortest decimal form."""
    import dataclasses

    import sympy as sp

    from ..errors import ExpressionError
    from ..expr import exact_number

    A = sp.Matrix(model.matrix)
    for (i, j), e in sorted(entries.items()):
        try:
            exact = {f: exact_number(float(f)) for f in e.atoms(sp.Float)}
        except ExpressionError as err:
            raise ModelError(f"matrix entry [{i}][{j}]: {err}") from None
        real = {s: sp.Symbol(s.name, real=True) for s in e.free_symbols}
        A[i, j] = e.xreplace(exact).xreplace(real)
    return dataclasses.replace(model, matrix=sp.ImmutableMatrix(A))


def stand_in_names(matrix, variables, params) -> dict:
    """Name -> a stand-in name a model file can hold, for each symbol name it cannot."""
    names = {s.name for e in matrix for s in e.free_symbols}
    names |= {str(v) for v in variables or ()} | set(params)
    bad = sorted(n for n in names if not _IDENT.match(n))
    out, k = {}, 0
    for n in bad:
        while f"_s{k}" in names:
            k += 1
        out[n] = f"_s{k}"
        k += 1
    return out


def _with_stand_ins(matrix, variables, params, name, stand_ins):
    """:func:`matrix_model` of the matrix with its unusable symbol names replaced."""
    import sympy as sp

    from ..expr import natural_key

    def renamed(x):
        text = str(x)
        return stand_ins.get(text, text)

    to_stand_in = {s: sp.Symbol(stand_ins[s.name], **s.assumptions0)
                   for e in matrix for s in e.free_symbols if s.name in stand_ins}
    if variables is None:       # the default order is that of the caller's names
        symbols = {s for e in matrix for s in e.free_symbols if s.name not in params}
        variables = sorted(symbols, key=natural_key)
    return matrix_model(sp.Matrix(matrix).xreplace(to_stand_in),
                        variables=None if variables is None else [renamed(v) for v in variables],
                        parameters={renamed(k): v for k, v in params.items()}, name=name)


_NOT_POLYNOMIAL = ("not a polynomial in the variables and in sines and cosines of them (with "
                   "parameters and numbers as coefficients)")


def _check_functions(matrix) -> None:
    """Refuse at once an entry of a sympy matrix with a function other than sin and cos."""
    import sympy as sp

    for (i, j), entry in sorted(sp.Matrix(matrix).todok().items()):
        if not isinstance(entry, sp.Basic):
            continue
        bad = sorted({type(f).__name__ for f in entry.atoms(sp.Function)
                      if not isinstance(f, (sp.sin, sp.cos))})
        if bad:
            raise ModelError(f"matrix entry [{i}][{j}] {sp.sstr(entry)[:80]}: "
                             f"{_NOT_POLYNOMIAL}; it uses {', '.join(bad)}")


def _check_polynomial(model) -> None:
    """Refuse, before any computation, an entry the algebra could not take: one that is no
    polynomial in the variables and in sines and cosines (the parameters at their values),
    a sine or cosine of anything but a whole-number combination of variables plus a
    constant, or a variable both inside a sine or cosine and outside."""
    import sympy as sp

    M = sp.Matrix(model.matrix).subs(dict(model.parameters))
    variables = set(model.variables)
    entries = sorted(M.todok().items())
    inside, outside = set(), set()

    def refuse(i, j, why=""):
        raise ModelError(f"matrix entry [{i}][{j}] {sp.sstr(model.matrix[i, j])[:80]}: "
                         f"{_NOT_POLYNOMIAL}" + (f": {why}" if why else ""))

    for (i, j), entry in entries:
        trig = {a: sp.Dummy() for a in entry.atoms(sp.sin, sp.cos)}
        if not entry.xreplace(trig).is_polynomial(*variables, *trig.values()):
            refuse(i, j)
        outside |= entry.xreplace(trig).free_symbols & variables
        for f in trig:
            arg = sp.expand(f.args[0])
            used = arg.free_symbols & variables
            inside |= used
            rest = arg - sum(arg.coeff(v) * v for v in used)
            if any(not arg.coeff(v).is_Integer for v in used) or rest.free_symbols & variables:
                refuse(i, j, f"{sp.sstr(f)}: sines and cosines are of whole-number combinations "
                             "of the variables (plus a constant)")
    for (i, j), entry in entries:
        mixed = sorted(v.name for v in inside & outside & entry.free_symbols)
        if mixed:
            refuse(i, j, f"{mixed[0]} appears both inside sin/cos and outside them")


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
    model : str, os.PathLike, RobotModel, MatrixModel, sympy.Matrix, DHRobot, pinocchio.Model or RobotWrapper
        A built-in model name or a ``.toml`` / ``.urdf`` path; a model; a
        symbolic matrix (see :func:`matrix_model`); a Robotics Toolbox DH
        robot (:func:`~rankloci.adapters.from_rtb`); a Pinocchio model
        or RobotWrapper (:func:`~rankloci.adapters.from_pinocchio`, ``tip`` and
        ``base_link`` name its frames).
    variables, parameters
        For a sympy matrix only.
    tip : str, optional
        For a URDF file or a Pinocchio model: the chain's last link or frame.
    base_link : str, optional
        For a URDF file or a Pinocchio model: the chain's first link or frame.

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
            return load(spec, base_link=base_link, tip=tip)
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

        return from_pinocchio(model, tip=tip, base_link=base_link)
    raise ArgumentError(f"cannot use a {type(model).__module__}.{type(model).__name__} as a model; "
                    "give a built-in model name, a .toml or .urdf path, a sympy Matrix, a "
                    "Robotics Toolbox DHRobot or a Pinocchio Model")
