"""Robot model files and raw-matrix files in TOML.

:func:`parse_model` turns the text of a file into a :class:`RobotModel` (a
file with ``[[joint]]`` tables) or a :class:`MatrixModel` (a file with a
``matrix`` array); :func:`read_model` reads a file and calls it.  Every
problem is reported as a :class:`~rankloci.errors.ModelError` naming the
file, the 1-based joint and the field.
"""

from __future__ import annotations

import re
import tomllib
import warnings
from pathlib import Path

import sympy as sp

from ..errors import ExpressionError, ModelError
from ..expr import CONSTANTS, FUNCTIONS, AngleSnapWarning, angle_value, exact_number, parse_expression
from ..model import MatrixModel, RobotModel, DHParams, Joint, homogeneous, rot_x, rot_z, task_rows, trans

__all__ = ["parse_model", "read_model", "MAX_FILE_BYTES", "MAX_JOINTS"]

MAX_FILE_BYTES = 1_000_000
MAX_JOINTS = 64
MAX_MATRIX_ENTRIES = 4096

_NAME_RE = re.compile(r"^[a-z0-9][a-z0-9_-]{0,63}\Z")
_IDENT_RE = re.compile(r"^[A-Za-z_][A-Za-z0-9_]{0,31}\Z")
_ROBOT_KEYS = {"name", "title", "source", "notes", "convention", "task", "rows", "frame",
               "parameters", "base", "tool", "joint", "augment", "points"}
_MATRIX_KEYS = {"name", "title", "source", "notes", "variables", "parameters", "matrix", "augment"}
_JOINT_KEYS = {"kind", "a", "alpha", "d", "theta", "name", "limits"}
_CONVENTIONS = ("dh", "mdh")
_FRAMES = ("base", "tool")


def _err(msg, joint=None, field=None):
    return ModelError(msg, joint=joint, field=field)


def _reserved(name: str) -> bool:
    return name in FUNCTIONS or name in CONSTANTS or re.fullmatch(r"q\d+", name) is not None


def _parameters(data) -> dict[str, sp.Symbol]:
    table = data.get("parameters", {})
    if not isinstance(table, dict):
        raise _err("must be a table of name = number", field="parameters")
    values = {}
    for key, value in table.items():
        if not _IDENT_RE.match(key) or _reserved(key):
            raise _err(f"{key!r} is not a usable parameter name", field=f"parameters.{key}")
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise _err(f"value {value!r} is not a number", field=f"parameters.{key}")
        try:
            values[sp.Symbol(key, real=True)] = exact_number(value)
        except ExpressionError as e:
            raise _err(e.reason, field=f"parameters.{key}") from None
    return values


def _expr(value, names, *, field, joint=None, angle=False):
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise _err(f"expected a number or an expression string, got {value!r}", joint, field)
    try:
        if angle and isinstance(value, float):
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always", AngleSnapWarning)
                out = angle_value(value)
            for w in caught:
                where = f"joint {joint}: " if joint else ""
                warnings.warn(f"{where}field {field!r}: {w.message}", AngleSnapWarning, stacklevel=4)
            return out
        return parse_expression(value, names)
    except ExpressionError as e:
        raise _err(str(e), joint, field) from None


def _transform_table(data, key, names):
    table = data.get(key)
    if table is None:
        return sp.ImmutableMatrix(sp.eye(4))
    if not isinstance(table, dict) or set(table) - {"xyz", "rpy"}:
        raise _err("must be a table with keys xyz and rpy", field=key)
    vals = {}
    for sub in ("xyz", "rpy"):
        v = table.get(sub, [0, 0, 0])
        if not isinstance(v, list) or len(v) != 3:
            raise _err("must be a list of three numbers or expressions", field=f"{key}.{sub}")
        vals[sub] = [_expr(x, names, field=f"{key}.{sub}", angle=sub == "rpy") for x in v]
    return homogeneous(vals["xyz"], vals["rpy"])


def _augment(data, names):
    entries = data.get("augment", [])
    if not isinstance(entries, list):
        raise _err("must be an array of tables [[augment]]", field="augment")
    out = []
    for i, entry in enumerate(entries, 1):
        if not isinstance(entry, dict) or "expr" not in entry:
            raise _err(f"entry {i} needs an 'expr'", field="augment")
        if set(entry) - {"name", "expr"}:
            raise _err(f"entry {i} has unknown keys {sorted(set(entry) - {'name', 'expr'})}", field="augment")
        name = entry.get("name", f"g{i}")
        if not isinstance(name, str):
            raise _err(f"entry {i}: name must be a string", field="augment")
        out.append((name, _expr(entry["expr"], names, field=f"augment[{i}].expr")))
    return tuple(out)


def _limits(limits, index):
    """``(lower, upper)`` in rad or m from ``[lower, upper]``: numbers or constant expressions
    (``"-8*pi/9"``); None when absent."""
    if limits is None:
        return None
    if not isinstance(limits, list) or len(limits) != 2:
        raise _err("must be [lower, upper] with lower < upper", index, "limits")
    bounds = []
    for x in limits:
        if isinstance(x, bool) or not isinstance(x, (int, float, str)):
            raise _err("must be [lower, upper] with lower < upper", index, "limits")
        try:
            value = parse_expression(x, {})
        except ExpressionError as e:
            raise _err(f"{e} (a limit is a number or a constant such as '-8*pi/9')",
                       index, "limits") from None
        if value.free_symbols or not value.is_real or not value.is_finite:
            raise _err(f"{x!r} is not a finite real constant", index, "limits")
        bounds.append(float(value))
    if not bounds[0] < bounds[1]:
        raise _err("must be [lower, upper] with lower < upper", index, "limits")
    return (bounds[0], bounds[1])


def _joint(entry, index, convention, names):
    if not isinstance(entry, dict):
        raise _err("must be a table", index)
    unknown = set(entry) - _JOINT_KEYS
    if unknown:
        raise _err(f"unknown key(s) {sorted(unknown)}; allowed: {sorted(_JOINT_KEYS)}", index)
    kind = entry.get("kind", "revolute")
    if kind not in ("revolute", "prismatic"):
        raise _err(f"{kind!r} is not 'revolute' or 'prismatic'", index, "kind")
    a = _expr(entry.get("a", 0), names, field="a", joint=index)
    alpha = _expr(entry.get("alpha", 0), names, field="alpha", joint=index, angle=True)
    d = _expr(entry.get("d", 0), names, field="d", joint=index)
    theta = _expr(entry.get("theta", 0), names, field="theta", joint=index, angle=True)
    limits = _limits(entry.get("limits"), index)
    name = entry.get("name", f"joint{index}")
    if not isinstance(name, str):
        raise _err("must be a string", index, "name")
    fixed_dh = rot_z(theta) * trans(0, 0, d) * trans(a, 0, 0) * rot_x(alpha)
    fixed_mdh = rot_x(alpha) * trans(a, 0, 0) * rot_z(theta) * trans(0, 0, d)
    eye = sp.ImmutableMatrix(sp.eye(4))
    if convention == "dh":
        pre, post = eye, sp.ImmutableMatrix(fixed_dh)
    else:
        pre, post = sp.ImmutableMatrix(fixed_mdh), eye
    return Joint(kind=kind, axis=(sp.Integer(0), sp.Integer(0), sp.Integer(1)), pre=pre, post=post,
                 name=name, dh=DHParams(convention, a, alpha, d, theta), limits=limits)


def _check_keys(data, allowed):
    unknown = set(data) - allowed
    if unknown:
        raise _err(f"unknown top-level key(s) {sorted(unknown)}; allowed: {sorted(allowed)}")


def _belongs(table: str, key: str, value) -> bool:
    """Whether ``key = value`` is an entry a ``[table]`` (or ``[[table]]``) may hold."""
    if table == "parameters":
        return isinstance(value, (int, float)) and not isinstance(value, bool)
    if table == "points":
        return isinstance(value, int) and not isinstance(value, bool)
    if table == "joint":
        return key in _JOINT_KEYS
    if table == "augment":
        return key in ("name", "expr")
    return False


def _check_misplaced(data):
    """Refuse a top-level key that a ``[table]`` header above it swallowed.

    In TOML every key after ``[parameters]`` belongs to that table up to the
    next header, so ``matrix = ...`` written below it is not a top-level key.
    Only a key the file lacks at the top level, and that the table cannot
    hold, is taken for such a slip.
    """
    top = (_ROBOT_KEYS | _MATRIX_KEYS) - set(data)
    for table, value in data.items():
        if isinstance(value, dict):
            tables = [(f"[{table}]", value)]
        elif isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
            tables = [(f"[[{table}]] number {i}" if len(value) > 1 else f"[[{table}]]", v)
                      for i, v in enumerate(value, 1)]
        else:
            continue
        for where, entries in tables:
            for key, v in entries.items():
                if key in top and not _belongs(table, key, v):
                    raise _err(f"{key!r} is inside {where}; top-level keys must come before "
                               "the first [table]")


def _text_field(data, key, default=""):
    v = data.get(key, default)
    if not isinstance(v, str):
        raise _err("must be a string", field=key)
    return v


def _parse_robot(data, name):
    _check_keys(data, _ROBOT_KEYS)
    params = _parameters(data)
    pnames = {s.name: s for s in params}
    convention = data.get("convention", "dh")
    if convention not in _CONVENTIONS:
        raise _err(f"{convention!r} is not one of {list(_CONVENTIONS)}", field="convention")
    joints_data = data.get("joint")
    if not isinstance(joints_data, list) or not joints_data:
        raise _err("a robot model needs at least one [[joint]] table", field="joint")
    if len(joints_data) > MAX_JOINTS:
        raise _err(f"more than {MAX_JOINTS} joints", field="joint")
    joints = tuple(_joint(e, i, convention, pnames) for i, e in enumerate(joints_data, 1))
    variables = tuple(sp.Symbol(f"q{i}", real=True) for i in range(1, len(joints) + 1))
    if "task" in data and "rows" in data:
        raise _err("give either 'task' or 'rows', not both", field="rows")
    task_spec = data.get("rows", data.get("task", "full"))
    try:
        if not isinstance(task_spec, (str, list)):
            raise ValueError(f"{task_spec!r} is not a task name or a list of rows")
        task = task_rows(task_spec)
    except ValueError as e:
        raise _err(str(e), field="rows" if "rows" in data else "task") from None
    frame = data.get("frame", "base")
    if frame not in _FRAMES:
        raise _err(f"{frame!r} is not one of {list(_FRAMES)}", field="frame")
    allnames = {**pnames, **{v.name: v for v in variables}}
    return RobotModel(
        name=name, joints=joints, variables=variables, parameters=params,
        title=_text_field(data, "title", name), source=_text_field(data, "source"),
        base=_transform_table(data, "base", pnames), tool=_transform_table(data, "tool", pnames),
        task=task, frame=frame, augment=_augment(data, allnames), convention=convention,
        points=_points(data, len(joints)),
    )


def _points(data, dof):
    """Named points ``[points] elbow = 3``: the origin of link frame 3."""
    table = data.get("points", {})
    if not isinstance(table, dict):
        raise _err("must be a table of name = link frame number", field="points")
    out = []
    for key, frame in table.items():
        if not _IDENT_RE.match(key):
            raise _err(f"{key!r} is not a valid point name", field="points")
        if not isinstance(frame, int) or isinstance(frame, bool) or not 0 <= frame <= dof:
            raise _err(f"{key}: {frame!r} is not a link frame number in 0..{dof}", field="points")
        out.append((key, frame))
    return tuple(out)


def _parse_matrix(data, name):
    _check_keys(data, _MATRIX_KEYS)
    params = _parameters(data)
    var_names = data.get("variables")
    if not isinstance(var_names, list) or not var_names:
        raise _err("must be a non-empty list of names", field="variables")
    variables = []
    for v in var_names:
        if not isinstance(v, str) or not _IDENT_RE.match(v) or v in FUNCTIONS or v in CONSTANTS:
            raise _err(f"{v!r} is not a usable variable name", field="variables")
        variables.append(sp.Symbol(v, real=True))
    if len(set(var_names)) != len(var_names):
        raise _err("variable names repeat", field="variables")
    clash = set(var_names) & {s.name for s in params}
    if clash:
        raise _err(f"{sorted(clash)} are both variables and parameters", field="variables")
    names = {s.name: s for s in params} | {v.name: v for v in variables}
    rows = data.get("matrix")
    if not isinstance(rows, list) or not rows or not all(isinstance(r, list) for r in rows):
        raise _err("must be a non-empty list of rows", field="matrix")
    ncols = len(rows[0])
    if ncols == 0 or any(len(r) != ncols for r in rows):
        raise _err(f"rows have different lengths {[len(r) for r in rows]}", field="matrix")
    if len(rows) * ncols > MAX_MATRIX_ENTRIES:
        raise _err(f"more than {MAX_MATRIX_ENTRIES} entries", field="matrix")
    entries = [[_expr(x, names, field=f"matrix[{i}][{j}]") for j, x in enumerate(r)]
               for i, r in enumerate(rows)]
    return MatrixModel(
        name=name, matrix=sp.ImmutableMatrix(entries), variables=tuple(variables), parameters=params,
        title=_text_field(data, "title", name), source=_text_field(data, "source"),
        augment=_augment(data, names),
    )


def parse_model(text: str, *, file: str = "", name: str | None = None):
    """Parse the text of a TOML model file.

    Parameters
    ----------
    text : str
        File contents.
    file : str, optional
        File name used in error messages; its stem must equal the ``name`` key.
    name : str, optional
        Name to use when the file has no ``name`` key (default: the file stem).

    Returns
    -------
    RobotModel or MatrixModel

    Raises
    ------
    ModelError
        Naming the file, the joint and the field of the first problem.

    Examples
    --------
    >>> m = parse_model('name = "r1"\\n[[joint]]\\nkind = "revolute"\\na = "l1"\\n'
    ...                 '[parameters]\\nl1 = 0.5\\n')
    >>> m.dof, m.parameters
    (1, {l1: 1/2})
    """
    try:
        try:
            if len(text) > MAX_FILE_BYTES:
                raise _err(f"file larger than {MAX_FILE_BYTES} bytes")
            try:
                data = tomllib.loads(text)
            except tomllib.TOMLDecodeError as e:
                raise _err(f"invalid TOML: {e}") from None
            _check_misplaced(data)
            stem = Path(file).stem if file else None
            model_name = data.get("name", name or stem or "model")
            if not isinstance(model_name, str) or not _NAME_RE.match(model_name):
                raise _err(f"{model_name!r} is not a valid model name (lowercase letters, digits, _ and -)",
                           field="name")
            if stem is not None and "name" in data and model_name != stem:
                raise _err(f"name {model_name!r} does not match the file stem {stem!r}", field="name")
            if "matrix" in data:
                return _parse_matrix(data, model_name)
            return _parse_robot(data, model_name)
        except RecursionError:
            raise _err("nested too deeply") from None
    except ModelError as e:
        raise e.located(file=file or None) from None


def read_model(path, *, require_source: bool = False):
    """Read a TOML model file; see :func:`parse_model`."""
    path = Path(path)
    from .files import read_bounded

    try:
        text = read_bounded(path, MAX_FILE_BYTES).decode("utf-8")
    except UnicodeDecodeError:
        raise ModelError("not UTF-8 text", file=path.name) from None
    except OSError as e:
        raise ModelError(f"cannot read: {e.strerror}", file=path.name) from None
    model = parse_model(text, file=path.name)
    if require_source and not model.source.strip():
        raise ModelError("a built-in model needs a 'source' citation", file=path.name, field="source")
    return _with_path(model, str(path))


def _with_path(model, path):
    import dataclasses
    return dataclasses.replace(model, path=path)
