"""Reading a locus back from its JSON document (``rankloci.locus/2`` or ``/1``).

:func:`parse_locus_dict` is what :meth:`rankloci.locus.Locus.from_dict` and
``rankloci check --locus FILE`` use.  Every string is parsed with the safe
expression parser over the document's (or the model's) variable and
parameter names, and every field is checked for its type and size: the
document may come from anywhere.
"""

from __future__ import annotations

import math

import sympy as sp

from .errors import ExpressionError, ModelError
from .expr import exact_number, parse_expression

__all__ = ["parse_locus_dict", "MAX_LOCUS_COMPONENTS", "MAX_RANK_DROP"]

#: The most components a locus file may hold (the built-in models have at most 12).
MAX_LOCUS_COMPONENTS = 1000

#: The largest rank drop a locus file may state (a 100 x 100 matrix losing all its rank).
MAX_RANK_DROP = 100

#: The most entries of any list or mapping of one component (samples, solved values, ...).
MAX_ITEMS = 10_000

#: The most entries of one lost direction (a row or column count of the matrix).
MAX_VECTOR = 1000


def _names(data, key, where=None) -> list:
    value = data.get(key, [])
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value) \
            or len(value) > MAX_ITEMS:
        raise ModelError("must be a list of names", field=where or key)
    return value


def _number(value, where) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) \
            or not math.isfinite(value):
        raise ModelError(f"{str(value)[:20]!r} is not a finite number", field=where)
    return float(value)


def _symbols(data, model):
    """Variables and parameters (symbol -> value) of the document, in the model's symbols."""
    from .locus import READABLE_SCHEMAS

    if not isinstance(data, dict):
        raise ModelError("a locus file must hold a JSON object", field="schema")
    if data.get("schema") not in READABLE_SCHEMAS:
        raise ModelError(f"schema is {str(data.get('schema'))[:40]!r}, expected one of "
                         f"{', '.join(READABLE_SCHEMAS)}", field="schema")
    raw = data.get("parameters", {})
    if not isinstance(raw, dict) or len(raw) > MAX_ITEMS:
        raise ModelError("must be an object of numbers", field="parameters")
    if model is not None:
        names = [v.name for v in model.variables]
        if data.get("variables") != names:
            raise ModelError(f"variables {data.get('variables')!r} are not the model's {names}",
                             field="variables")
        params = {p: model.parameters[p] for p in model.parameters if p.name in raw}
        return tuple(model.variables), params, {p.name: p for p in model.parameters}
    names = _names(data, "variables")
    try:
        params = {sp.Symbol(k, real=True): exact_number(_number(v, f"parameters.{k}"))
                  for k, v in raw.items()}
    except ExpressionError as e:
        raise ModelError(str(e), field="parameters") from None
    bad = [n for n in names + list(raw) if not n.isidentifier()]
    if bad:
        raise ModelError(f"{bad[0][:40]!r} is not a symbol name", field="variables")
    return (tuple(sp.Symbol(n, real=True) for n in names), params,
            {p.name: p for p in params})


def _undefined_somewhere(e):
    """The part of ``e`` that is not finite at some configuration, or None.

    Equations of a locus are polynomials in the variables and in sines and
    cosines of them; ``sqrt(sin(q2))``, ``acos(q2)`` or ``1/q2`` have no real
    value at some points, where a numeric check could not evaluate them.
    Functions of constants only (``sqrt(2)``) are numbers.
    """
    for node in sp.preorder_traversal(e):
        if not node.free_symbols:
            continue
        if isinstance(node, sp.Function) and not isinstance(node, (sp.sin, sp.cos)):
            return node
        if isinstance(node, sp.Pow) and not (node.exp.is_Integer and node.exp >= 0):
            return node
    return None


def _component(c, where, symbols, schema_1, special, n_variables=0):
    from .locus import Component

    if not isinstance(c, dict) or "equations" not in c:
        raise ModelError("each component must be an object with 'equations'", field=where)

    def exprs(items, field, *, everywhere=False):
        if not isinstance(items, list) or len(items) > MAX_ITEMS:
            raise ModelError(f"{where}.{field} must be a list of strings", field=f"{where}.{field}")
        try:
            got = tuple(parse_expression(t, symbols) for t in items)
        except ExpressionError as e:
            raise ModelError(str(e), field=f"{where}.{field}") from None
        for e in got if everywhere else ():
            bad = _undefined_somewhere(e)
            if bad is not None:
                raise ModelError(f"{sp.sstr(bad)[:60]} is not defined at every configuration; "
                                 "equations are polynomials in the variables and in sines and "
                                 "cosines", field=f"{where}.{field}")
        return got

    def integer(field, default, low, high):
        v = c.get(field, default)
        if isinstance(v, bool) or not isinstance(v, int) or not low <= v <= high:
            raise ModelError(f"{field} must be an integer from {low} to {high}, not "
                             f"{str(v)[:20]}", field=f"{where}.{field}")
        return v

    def mapping(field):
        v = c.get(field, {})
        if not isinstance(v, dict) or len(v) > MAX_ITEMS:
            raise ModelError("must be an object", field=f"{where}.{field}")
        return v

    solved = {}
    for name, vals in mapping("solved").items():
        if name not in symbols:
            raise ModelError(f"unknown variable {name[:40]!r}", field=f"{where}.solved")
        solved[symbols[name]] = exprs(vals, f"solved.{name}")
    free = _names(c, "free", f"{where}.free")
    if any(n not in symbols for n in free):
        raise ModelError("names a symbol that is not a variable", field=f"{where}.free")
    direction = c.get("direction", [])
    at_sample = c.get("direction_at_sample", [])
    for field, vecs in (("direction", direction), ("direction_at_sample", at_sample)):
        if not isinstance(vecs, list) or len(vecs) > MAX_RANK_DROP or not all(
                isinstance(v, list) and len(v) <= MAX_VECTOR for v in vecs):
            raise ModelError(f"must be at most {MAX_RANK_DROP} lists of at most {MAX_VECTOR} "
                             "entries", field=f"{where}.{field}")
    kind = c.get("kind")
    if kind not in (None, "kinematic", "algorithmic", "mixed"):
        raise ModelError(f"kind {str(kind)[:20]!r} is not kinematic, algorithmic or mixed",
                         field=f"{where}.kind")
    meets = c.get("meets", [])
    if not isinstance(meets, list) or len(meets) > MAX_ITEMS or not all(
            isinstance(m, dict) for m in meets):
        raise ModelError("must be a list of objects", field=f"{where}.meets")
    conditions = exprs(c.get("parameter_conditions", []), "parameter_conditions")
    equations = exprs(c["equations"], "equations", everywhere=True)
    # a component without a stated dimension is taken as cut out by its equations, one
    # codimension each (the certificate checks it like a stated one)
    default_dimension = max(0, n_variables - len([e for e in equations if e != 0]))
    return Component(
        equations=equations,
        solved=solved,
        free=tuple(symbols[n] for n in free),
        dimension=integer("dimension", default_dimension, 0, MAX_ITEMS),
        rank_drop=integer("rank_drop", 1, 1, MAX_RANK_DROP),
        direction=tuple(exprs(v, "direction") for v in direction),
        direction_at_sample=tuple(tuple(_number(x, f"{where}.direction_at_sample") for x in v)
                                  for v in at_sample),
        sample={str(k): _number(v, f"{where}.sample") for k, v in mapping("sample").items()},
        parameter_conditions=conditions,
        # schema /1 listed special-parameter components among the others
        for_model=not special and bool(c.get("for_model", True))
        and not (schema_1 and c.get("parameter_conditions")),
        excluding=exprs(c.get("excluding", []), "excluding", everywhere=True),
        kind=kind, meets=tuple(meets))


def parse_locus_dict(data, model=None):
    """A :class:`~rankloci.locus.Locus` from its JSON document.

    Parameters
    ----------
    data : dict
    model : RobotModel or MatrixModel, optional
        Whose symbols to use; the document's variables must be the model's.

    Raises
    ------
    ModelError
        If the schema key is wrong, the variables are not the model's, a field
        has the wrong type or size, or an expression does not parse over the
        variable and parameter names.
    """
    from .locus import READABLE_SCHEMAS, Locus

    variables, params, names = _symbols(data, model)
    symbols = {v.name: v for v in variables} | names
    schema_1 = data["schema"] == READABLE_SCHEMAS[0]
    comps = data.get("components")
    if not isinstance(comps, list):
        raise ModelError("'components' must be a list", field="components")
    special = data.get("special_components", [])
    if not isinstance(special, list):
        raise ModelError("'special_components' must be a list", field="special_components")
    if len(comps) + len(special) > MAX_LOCUS_COMPONENTS:
        raise ModelError(f"more than {MAX_LOCUS_COMPONENTS} components", field="components")
    out = [_component(c, f"components[{k}]", symbols, schema_1, False, len(variables))
           for k, c in enumerate(comps, 1)]
    out += [_component(c, f"special_components[{k}]", symbols, schema_1, True, len(variables))
            for k, c in enumerate(special, 1)]
    shape = data.get("matrix", {})
    if not isinstance(shape, dict):
        raise ModelError("must be an object with rows and cols", field="matrix")
    dims = tuple(shape.get(k, 0) for k in ("rows", "cols"))
    if not all(isinstance(n, int) and not isinstance(n, bool) and 0 <= n <= MAX_ITEMS
               for n in dims):
        raise ModelError("rows and cols must be integers", field="matrix")
    notes = _names(data, "notes")
    complete = data.get("complete")
    if complete not in (None, True, False):
        raise ModelError("must be true, false or null", field="complete")
    certificate = data.get("certificate")
    if certificate is not None:
        from .exact.certificate import Certificate

        try:
            certificate = Certificate.from_dict(certificate)
        except ValueError as exc:
            raise ModelError(str(exc), field="certificate") from None
    base = data.get("base_locus")
    if base is not None:
        if isinstance(base, dict) and "base_locus" in base:
            raise ModelError("a base locus cannot have a base locus", field="base_locus")
        base = parse_locus_dict(base, model)
    return Locus(
        model=str(data.get("model", model.name if model is not None else "locus"))[:200],
        variables=variables, parameters=params, shape=dims,
        method=str(data.get("method", "file"))[:40],
        components=tuple(c for c in out if c.exists_for_model),
        special=tuple(c for c in out if not c.exists_for_model),
        degenerate=bool(data.get("degenerate", False)),
        seconds=_number(data.get("seconds", 0.0), "seconds"),
        notes=tuple(notes), base=base, complete=complete, certificate=certificate,
        joint_names=_joint_names(data, variables))


def _joint_names(data, variables) -> tuple:
    """The ``joint_names`` entry ``rankloci locus --format json`` adds for a URDF chain, if any."""
    given = data.get("joint_names")
    if given is None:
        return ()
    if not isinstance(given, dict) or set(given) != {v.name for v in variables} \
            or not all(isinstance(j, str) and 0 < len(j) <= 200 for j in given.values()):
        raise ModelError("'joint_names' must map every variable to a joint name",
                         field="joint_names")
    return tuple(given[v.name] for v in variables)
