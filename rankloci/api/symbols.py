"""The caller's own symbols in what the library returns.

A sympy matrix goes through the parser of model files (:func:`~rankloci.api.models.matrix_model`),
which makes every symbol real (``Symbol("x", real=True)``).  sympy tells symbols apart by
their assumptions, so an equation in the real ``x`` ignores ``subs({x: 0.3})`` with the
caller's plain ``x``.  :func:`with_symbols` puts the caller's symbols back, by name, into a
:class:`~rankloci.loci.Locus` or a :class:`~rankloci.jacobians.TaskMatrix`.
"""

from __future__ import annotations

import dataclasses

__all__ = ["caller_symbols", "with_symbols"]


def caller_symbols(model, variables=None, parameters=None) -> dict:
    """Name -> symbol, for every sympy symbol the caller handed in.

    The free symbols of a sympy matrix ``model``, and the symbols among
    ``variables`` and the keys of ``parameters`` (names given as strings
    bring no symbol of their own); a name a model file cannot hold is keyed
    by its stand-in (:func:`~rankloci.api.models.matrix_model`).

    Examples
    --------
    >>> import sympy as sp
    >>> x, k = sp.symbols("x k")
    >>> caller_symbols(sp.Matrix([[x, k]]), variables=["x"], parameters={"k": 1})
    {'k': k, 'x': x}
    """
    import sympy as sp

    from .models import stand_in_names

    found = []
    if isinstance(model, sp.MatrixBase):
        found += sorted(model.free_symbols, key=lambda s: s.name)
    found += [v for v in variables or () if isinstance(v, sp.Symbol)]
    found += [k for k in dict(parameters or {}) if isinstance(k, sp.Symbol)]
    # a name a model file cannot hold is carried under a stand-in (matrix_model)
    ins = (stand_in_names(model, variables, {str(k): v for k, v in dict(parameters or {}).items()})
           if isinstance(model, sp.MatrixBase) else {})
    return {ins.get(s.name, s.name): s for s in sorted(found, key=lambda s: s.name)}


def with_symbols(result, symbols):
    """``result`` with each of its symbols replaced by the symbol of ``symbols`` of the same name.

    Parameters
    ----------
    result : Locus or TaskMatrix
        For a locus: its variables, the keys of its parameters and, in every
        component (special ones and those of ``base`` too), the equations,
        ``solved`` (keys and values), ``free``, ``direction``,
        ``parameter_conditions`` and ``excluding``.  The branch tree and the
        certificate keep the library's symbols.
    symbols : mapping of str to sympy.Symbol

    Returns
    -------
    Locus or TaskMatrix
        ``result`` itself when no symbol changes.

    Examples
    --------
    >>> import sympy as sp
    >>> from rankloci.loci import Component, Locus
    >>> xr = sp.Symbol("x", real=True)
    >>> L = Locus("m", (xr,), {}, (1, 1), "determinant", (Component((sp.sin(xr),)),))
    >>> x = sp.Symbol("x")
    >>> with_symbols(L, {"x": x}).components[0].equations[0].subs({x: 0})
    0
    """
    from ..jacobians import TaskMatrix

    own = {s for s in _symbols_of(result) if s.name in symbols and symbols[s.name] != s}
    if not own:
        return result
    swap = {s: symbols[s.name] for s in own}
    if isinstance(result, TaskMatrix):
        return dataclasses.replace(
            result, matrix=result.matrix.xreplace(swap),
            variables=tuple(_swap(v, swap) for v in result.variables),
            angles=tuple(_swap(v, swap) for v in result.angles),
            parameters={_swap(k, swap): v for k, v in result.parameters.items()})
    return _locus_with(result, swap)


def _swap(e, swap):
    """``e`` with the symbols of ``swap`` replaced; a value that is not a sympy object as is."""
    import sympy as sp

    return e.xreplace(swap) if isinstance(e, sp.Basic) else e


def _symbols_of(result) -> set:
    """Every symbol of the fields :func:`with_symbols` rewrites."""
    import sympy as sp

    from ..jacobians import TaskMatrix

    if isinstance(result, TaskMatrix):
        return set(result.matrix.free_symbols) | set(result.variables) | set(result.parameters)
    found = set(result.variables) | set(result.parameters)
    for c in result.all_components:
        for e in (*c.equations, *c.excluding, *c.parameter_conditions, *c.free, *c.solved,
                  *(x for vals in c.solved.values() for x in vals),
                  *(x for vec in c.direction for x in vec)):
            if isinstance(e, sp.Basic):
                found |= e.free_symbols
    if result.base is not None:
        found |= _symbols_of(result.base)
    return {s for s in found if isinstance(s, sp.Symbol)}


def _component_with(c, swap):
    return dataclasses.replace(
        c,
        equations=tuple(_swap(e, swap) for e in c.equations),
        solved={_swap(k, swap): tuple(_swap(v, swap) for v in vals)
                for k, vals in c.solved.items()},
        free=tuple(_swap(v, swap) for v in c.free),
        direction=tuple(tuple(_swap(x, swap) for x in vec) for vec in c.direction),
        parameter_conditions=tuple(_swap(e, swap) for e in c.parameter_conditions),
        excluding=tuple(_swap(e, swap) for e in c.excluding))


def _locus_with(locus, swap):
    return dataclasses.replace(
        locus,
        variables=tuple(_swap(v, swap) for v in locus.variables),
        parameters={_swap(k, swap): v for k, v in locus.parameters.items()},
        components=tuple(_component_with(c, swap) for c in locus.components),
        special=tuple(_component_with(c, swap) for c in locus.special),
        base=None if locus.base is None else _locus_with(locus.base, swap))
