"""The sweep specification: a TOML file read as data, validated once.

A spec names the models of a sweep, a grid over parameter values and
constraint rows, and how each case is computed::

    task = "position"          # optional: as --task (default: each model's own)
    method = "svm"             # optional: svm, subdeterminant or determinant
    numeric = true             # default true: each case's values substituted (as --numeric)
    seed = 0
    timeout = 60               # seconds per case (0 = none)
    memory = 4096              # MiB per case (0 = none)
    verify = true              # the self-check of `rankloci locus`; its verdict is `check`
    models = ["planar2r", "arms/"]   # built-in names, .toml/.urdf files, directories

    [[model]]                  # the long form, one table per entry
    path = "robots/arm.urdf"
    chains = "all"             # every serial chain of the file ...
    min_joints = 2             # ... with this many movable joints or more
    max_joints = 9             # ... and this many or fewer

    [grid]
    augment = ["", "lock(q3)", ["sum(q1, q2)", "q3"]]   # "" = no constraint row
    [grid.parameters]
    l2 = [0.5, 1.0, "3/2"]
    l3 = { start = 0.5, stop = 1.5, num = 3 }            # or step = 0.5

``examples/sweeps/`` of the source tree has specs that run as written (a robot
collection with the files named above, a design grid, an augment grid).

Nothing in the file is executed: TOML is parsed with :mod:`tomllib` and every
expression string with :func:`rankloci.expr.parse_expression`.  Relative
paths are taken from the spec's directory.  Every problem is a
:class:`SpecError` naming the spec file and the key.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path

import sympy as sp

from ..errors import ExpressionError, ModelError

__all__ = ["SpecError", "Grid", "ModelEntry", "SweepSpec", "parse_spec", "read_spec",
           "METHODS", "MAX_CASES"]

#: The methods a spec may name (those of ``rankloci locus --method``).
METHODS = ("svm", "subdeterminant", "determinant")

#: Largest spec file read, in bytes.
MAX_SPEC_BYTES = 1_000_000

#: Most cases one sweep may expand to: a grid written by mistake (ten axes of ten values)
#: is refused before anything runs.
MAX_CASES = 100_000

#: Most values one grid axis may have.
MAX_AXIS_VALUES = 10_000

#: Default seconds per case and MiB per case (those of ``rankloci locus``).
DEFAULT_TIMEOUT = 600.0
DEFAULT_MEMORY_MB = 8192

_TOP_KEYS = {"models", "model", "task", "method", "numeric", "numeric_parameters", "seed",
             "timeout", "memory", "verify", "grid"}
_ENTRY_KEYS = {"name", "path", "base_link", "tip", "chains", "min_joints", "max_joints",
               "pattern", "task", "grid"}


class SpecError(ModelError):
    """A sweep specification is malformed; ``str`` names the file and the key."""


@dataclass(frozen=True)
class Grid:
    """The values a model entry is swept over.

    Attributes
    ----------
    parameters : tuple of (str, tuple of (str, sympy.Expr))
        Per parameter name, its values as written (for labels) and as exact numbers.
    augment : tuple of tuple of str
        The constraint-row options; ``()`` is J without extra rows.
    """

    parameters: tuple = ()
    augment: tuple = ((),)

    @property
    def size(self) -> int:
        """The number of grid points."""
        n = len(self.augment)
        for _, values in self.parameters:
            n *= len(values)
        return n


@dataclass(frozen=True)
class ModelEntry:
    """One entry of the spec's model list: a built-in name, a file or a directory."""

    name: str | None = None          # a built-in model
    path: Path | None = None         # a .toml or .urdf file, or a directory
    base_link: str | None = None
    tip: str | None = None
    chains: bool = False             # every chain of a URDF file
    min_joints: int = 1
    max_joints: int | None = None
    pattern: str = "*"               # files of a directory (those ending .toml or .urdf)
    task: object = None              # a task name or a row list; None: the spec's
    grid: Grid = field(default_factory=Grid)
    where: str = ""                  # the key that defined it, for error messages


@dataclass(frozen=True)
class SweepSpec:
    """A validated sweep specification (see the module docstring)."""

    entries: tuple
    task: object = None
    method: str | None = None
    numeric: bool = True
    seed: int = 0
    timeout: float = DEFAULT_TIMEOUT
    memory: int = DEFAULT_MEMORY_MB
    verify: bool = True
    file: str = ""


def _err(file, key, message) -> SpecError:
    return SpecError(message, file=file or None, field=key or None)


def _number(value, file, key, *, integer=False, minimum=None, maximum=None):
    if isinstance(value, bool) or not isinstance(value, (int, float)) or (
            integer and not isinstance(value, int)):
        raise _err(file, key, f"{str(value)[:40]!r} is not {'an integer' if integer else 'a number'}")
    if isinstance(value, float) and not math.isfinite(value):
        raise _err(file, key, f"{value!r} is not finite")
    if minimum is not None and value < minimum:
        raise _err(file, key, f"{value!r} is below {minimum}")
    if maximum is not None and value > maximum:
        raise _err(file, key, f"{str(value)[:40]} is above {maximum}")
    return value


def _task(value, file, key):
    from ..model import TASKS, task_rows

    if value is None or value in TASKS:
        return value
    if isinstance(value, list) and all(isinstance(x, int) and not isinstance(x, bool)
                                       for x in value):
        try:
            return list(task_rows(value))
        except ValueError as e:
            raise _err(file, key, str(e)) from None
    raise _err(file, key, f"{str(value)[:40]!r} is not one of {', '.join(TASKS)} or a list of "
                          f"rows like [0, 1, 5]")


def _label(value: sp.Expr) -> str:
    """A short label of an exact number: a decimal when it has one, else its sympy form."""
    if isinstance(value, sp.Rational):
        f = Fraction(int(value.p), int(value.q))
        d = f.denominator
        while d % 2 == 0:
            d //= 2
        while d % 5 == 0:
            d //= 5
        if d == 1 and f.denominator <= 10 ** 12:
            digits = 0
            while (f * 10 ** digits).denominator != 1:
                digits += 1
            text = f"{float(f):.{digits}f}" if digits else str(f.numerator)
            if Fraction(text) == f:
                return text
    return sp.sstr(value)


def _value(raw, file, key) -> tuple[str, sp.Expr]:
    from ..expr import exact_number, parse_expression

    try:
        if isinstance(raw, str):
            value = parse_expression(raw, {})
            if not value.is_number or value.is_real is False:
                raise ExpressionError(raw, "not a real number")
            return raw.strip(), value
        value = exact_number(raw)
    except ExpressionError as e:
        raise _err(file, key, str(e)) from None
    return _label(value), value


def _range(table, file, key) -> list:
    unknown = set(table) - {"start", "stop", "num", "step"}
    if unknown or "start" not in table or "stop" not in table or (
            ("num" in table) == ("step" in table)):
        raise _err(file, key, "a range is { start = A, stop = B, num = N } or "
                              "{ start = A, stop = B, step = S } (both ends included)")
    start = Fraction(repr(_number(table["start"], file, f"{key}.start")))
    stop = Fraction(repr(_number(table["stop"], file, f"{key}.stop")))
    if "num" in table:
        num = _number(table["num"], file, f"{key}.num", integer=True, minimum=1)
        if num > MAX_AXIS_VALUES:
            raise _err(file, f"{key}.num", f"more than {MAX_AXIS_VALUES} values")
        if num == 1 and start != stop:
            raise _err(file, f"{key}.num", "num = 1 needs start = stop")
        return [start + (stop - start) * k / max(num - 1, 1) for k in range(num)]
    step = Fraction(repr(_number(table["step"], file, f"{key}.step")))
    if step == 0 or (stop - start) / step < 0:
        raise _err(file, f"{key}.step", "the step must be nonzero and lead from start to stop")
    count = int((stop - start) / step) + 1
    if count > MAX_AXIS_VALUES:
        raise _err(file, f"{key}.step", f"more than {MAX_AXIS_VALUES} values")
    return [start + step * k for k in range(count)]


def _grid(table, file, key) -> Grid:
    if not isinstance(table, dict):
        raise _err(file, key, "must be a table with 'parameters' and/or 'augment'")
    unknown = set(table) - {"parameters", "augment"}
    if unknown:
        raise _err(file, f"{key}.{sorted(unknown)[0]}", "unknown key (expected 'parameters' "
                                                         "or 'augment')")
    params = []
    ptable = table.get("parameters", {})
    if not isinstance(ptable, dict):
        raise _err(file, f"{key}.parameters", "must be a table of name = list or range")
    for name, spec in ptable.items():
        k = f"{key}.parameters.{name}"
        if isinstance(spec, dict):
            values = [(_label(sp.Rational(v.numerator, v.denominator)),
                       sp.Rational(v.numerator, v.denominator)) for v in _range(spec, file, k)]
        elif isinstance(spec, list) and spec:
            if len(spec) > MAX_AXIS_VALUES:
                raise _err(file, k, f"more than {MAX_AXIS_VALUES} values")
            values = [_value(v, file, f"{k}[{i}]") for i, v in enumerate(spec)]
        else:
            raise _err(file, k, "must be a non-empty list of values or a range table")
        if len({v for _, v in values}) != len(values):
            raise _err(file, k, "a value is listed twice")
        params.append((name, tuple(values)))
    augment = table.get("augment", [""])
    if not isinstance(augment, list) or not augment:
        raise _err(file, f"{key}.augment", "must be a non-empty list of constraints: a string "
                                           "(\"\" for none) or a list of strings per option")
    options = []
    for i, option in enumerate(augment):
        rows = [option] if isinstance(option, str) else option
        if not isinstance(rows, list) or not all(isinstance(r, str) for r in rows):
            raise _err(file, f"{key}.augment[{i}]", "must be a string or a list of strings")
        options.append(tuple(r.strip() for r in rows if r.strip()))
    if len(set(options)) != len(options):
        raise _err(file, f"{key}.augment", "an option is listed twice")
    return Grid(tuple(params), tuple(options))


def _entry(raw, base: Path, file, key, grid: Grid) -> ModelEntry:
    if isinstance(raw, str):
        raw = {"name": raw} if not _looks_like_path(raw, base) else {"path": raw}
    if not isinstance(raw, dict):
        raise _err(file, key, "must be a model name, a path, or a table")
    unknown = set(raw) - _ENTRY_KEYS
    if unknown:
        raise _err(file, f"{key}.{sorted(unknown)[0]}", f"unknown key (expected one of "
                                                        f"{', '.join(sorted(_ENTRY_KEYS))})")
    if ("name" in raw) == ("path" in raw):
        raise _err(file, key, "give either 'name' (a built-in model) or 'path' (a file or "
                              "directory)")
    for k in ("name", "path", "base_link", "tip", "pattern"):
        if k in raw and (not isinstance(raw[k], str) or not raw[k].strip()):
            raise _err(file, f"{key}.{k}", "must be a non-empty string")
    chains = raw.get("chains")
    if chains not in (None, "all"):
        raise _err(file, f"{key}.chains", f"{str(chains)[:40]!r}: the only value is \"all\" "
                                          "(every chain of a URDF file)")
    if chains and ("base_link" in raw or "tip" in raw):
        raise _err(file, f"{key}.chains", "\"all\" chains and base_link/tip exclude each other")
    lo = _number(raw.get("min_joints", 1), file, f"{key}.min_joints", integer=True, minimum=1)
    hi = raw.get("max_joints")
    if hi is not None:
        hi = _number(hi, file, f"{key}.max_joints", integer=True, minimum=lo)
    if ("min_joints" in raw or "max_joints" in raw) and not chains:
        raise _err(file, f"{key}.min_joints" if "min_joints" in raw else f"{key}.max_joints",
                   "joint-count bounds apply with chains = \"all\"")
    path = None
    if "path" in raw:
        path = Path(raw["path"])
        path = path if path.is_absolute() else base / path
        if not path.exists():
            raise _err(file, f"{key}.path", f"{raw['path']!r}: no such file or directory")
        if path.is_file() and path.suffix.lower() not in (".toml", ".urdf"):
            raise _err(file, f"{key}.path", f"{raw['path']!r}: expected a .toml or .urdf file "
                                            "or a directory")
        if path.is_file() and path.suffix.lower() != ".urdf" and (
                chains or "base_link" in raw or "tip" in raw):
            raise _err(file, key, "chains, base_link and tip apply to URDF files")
    elif chains or "base_link" in raw or "tip" in raw or "pattern" in raw:
        raise _err(file, key, "chains, base_link, tip and pattern apply to paths")
    pattern = raw.get("pattern", "*")
    if pattern.startswith(("/", "\\")) or ".." in pattern.replace("\\", "/").split("/"):
        raise _err(file, f"{key}.pattern", f"{pattern[:60]!r}: a pattern names files inside "
                                           "the entry's directory (no leading / and no ..)")
    own = _grid(raw["grid"], file, f"{key}.grid") if "grid" in raw else grid
    return ModelEntry(name=raw.get("name"), path=path, base_link=raw.get("base_link"),
                      tip=raw.get("tip"), chains=bool(chains), min_joints=lo, max_joints=hi,
                      pattern=pattern,
                      task=_task(raw.get("task"), file, f"{key}.task"), grid=own, where=key)


def _looks_like_path(text: str, base: Path) -> bool:
    p = Path(text)
    return "/" in text or p.suffix.lower() in (".toml", ".urdf") or (base / p).exists()


def parse_spec(text: str, *, base: Path | str = ".", file: str = "") -> SweepSpec:
    """Parse the text of a sweep specification.

    Parameters
    ----------
    text : str
        The TOML text.
    base : path, optional
        Directory relative paths are taken from (the spec's own).
    file : str, optional
        File name for error messages.

    Raises
    ------
    SpecError
        Naming the file and the key of the first problem.

    Examples
    --------
    >>> spec = parse_spec('models = ["planar3r"]\\ntimeout = 30\\n'
    ...                   '[grid.parameters]\\nl2 = { start = 0.5, stop = 1.5, num = 3 }\\n')
    >>> spec.entries[0].name, spec.timeout, spec.entries[0].grid.parameters[0][1]
    ('planar3r', 30.0, (('0.5', 1/2), ('1', 1), ('1.5', 3/2)))
    """
    from ..process_limits import MAX_MEMORY_MB, MAX_TIMEOUT_S

    base = Path(base)
    if len(text) > MAX_SPEC_BYTES:
        raise _err(file, "", f"larger than {MAX_SPEC_BYTES} bytes")
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise _err(file, "", f"invalid TOML: {e}") from None
    except RecursionError:
        raise _err(file, "", "nested too deeply") from None
    unknown = set(data) - _TOP_KEYS
    if unknown:
        raise _err(file, sorted(unknown)[0], f"unknown key (expected one of "
                                             f"{', '.join(sorted(_TOP_KEYS))})")
    grid = _grid(data["grid"], file, "grid") if "grid" in data else Grid()
    raw = []
    short = data.get("models", [])
    if not isinstance(short, list):
        raise _err(file, "models", "must be a list of model names, files or directories")
    raw += [(m, f"models[{i}]") for i, m in enumerate(short)]
    tables = data.get("model", [])
    if not isinstance(tables, list):
        raise _err(file, "model", "must be an array of tables: [[model]]")
    raw += [(m, f"model[{i}]") for i, m in enumerate(tables)]
    if not raw:
        raise _err(file, "models", "no model: give models = [...] or [[model]] tables")
    entries = tuple(_entry(m, base, file, key, grid) for m, key in raw)
    method = data.get("method")
    if method is not None and method not in METHODS:
        raise _err(file, "method", f"{str(method)[:40]!r} is not one of {', '.join(METHODS)}")
    if "numeric_parameters" in data:     # the old name of numeric (as --numeric-parameters)
        if "numeric" in data:
            raise _err(file, "numeric_parameters", "give numeric only (numeric_parameters is "
                       "its old name)")
        import warnings

        warnings.warn(f"{Path(file).name if file else 'the spec'}: numeric_parameters is "
                      "deprecated; use numeric", FutureWarning, stacklevel=2)
        data = {**data, "numeric": data["numeric_parameters"]}
    flags = {}
    for k, default in (("numeric", True), ("verify", True)):
        flags[k] = data.get(k, default)
        if not isinstance(flags[k], bool):
            raise _err(file, k, "must be true or false")
    return SweepSpec(
        entries=entries, task=_task(data.get("task"), file, "task"), method=method,
        numeric=flags["numeric"], verify=flags["verify"],
        seed=_number(data.get("seed", 0), file, "seed", integer=True, minimum=0),
        timeout=float(_number(data.get("timeout", DEFAULT_TIMEOUT), file, "timeout", minimum=0,
                              maximum=MAX_TIMEOUT_S)),
        memory=_number(data.get("memory", DEFAULT_MEMORY_MB), file, "memory", integer=True,
                       minimum=0, maximum=MAX_MEMORY_MB),
        file=file)


def read_spec(path) -> SweepSpec:
    """Read a sweep specification file; see :func:`parse_spec`."""
    p = Path(path)
    from ..io.files import read_bounded

    if p.is_dir():
        raise _err(p.name, "", "is a directory, not a spec file")
    try:
        text = read_bounded(p, MAX_SPEC_BYTES).decode("utf-8")
    except UnicodeDecodeError:
        raise _err(p.name, "", "not UTF-8 text") from None
    except OSError as e:
        raise _err(p.name, "", f"cannot read: {e.strerror}") from None
    return parse_spec(text, base=p.resolve().parent, file=p.name)
