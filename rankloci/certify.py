"""The certificate of a locus, for the model's own parameter values.

:func:`certify_locus` substitutes the parameter values (exact rationals, as
the model gives them) into the matrix and into every component of the model's
locus, and runs :func:`rankloci.exact.witness.certify_components`: witness
points of every codimension that can occur, computed exactly modulo a large
prime, prove that the components are the whole locus and that each is
rank deficient as stated.  The same function checks a locus that was
computed here and one that a user brought (``rankloci check --locus``).
"""

from __future__ import annotations

import dataclasses

import sympy as sp

from .exact.witness import Certificate, certify_components
from .expr import as_expression

__all__ = ["certify_locus", "completed_component", "Certificate"]


def _values(parameters) -> dict:
    out = {}
    for k, v in dict(parameters or {}).items():
        v = as_expression(v)
        if isinstance(v, sp.Float):
            # a float read back from JSON: its shortest decimal is the value the model wrote
            v = sp.Rational(repr(float(v)))
        out[k if isinstance(k, sp.Symbol) else sp.Symbol(str(k), real=True)] = v
    return out


def _substituted(expr, values):
    expr = as_expression(expr)
    by_name = {s.name: s for s in expr.free_symbols}
    subs = {by_name[k.name]: v for k, v in values.items()
            if k.name in by_name and by_name[k.name] is not v}
    return expr.xreplace(subs) if subs else expr


def certify_locus(locus, reference, *, seed: int = 0, should_stop=None,
                  progress=None, complex_only=()) -> Certificate:
    """The certificate of ``locus`` (its model's own components) for the matrix ``reference``.

    Parameters
    ----------
    locus : Locus
    reference : TaskMatrix
        The matrix the locus is of, in any frame (the rank is the same), with its
        parameters symbolic and their values in ``reference.parameters``, or substituted.
    seed : int
        Seed of the certificate's random choices.
    should_stop : callable, optional
        Polled; when it returns True the certificate stops, ``"undecided"``.
    progress : callable, optional
    complex_only : sequence of Component
        Components without real points that the certificate may count as covering complex
        witness points (see :func:`~rankloci.exact.witness.certify_components`).

    Returns
    -------
    Certificate

    Examples
    --------
    >>> import rankloci
    >>> from rankloci.jacobians import task_matrix
    >>> L = rankloci.locus("planar2r", verify=False)
    >>> certify_locus(L, task_matrix(rankloci.load_model("planar2r"))).verdict
    'passed'
    """
    values = _values(reference.parameters)
    values.update({k: v for k, v in _values(locus.parameters).items()
                   if k.name not in {s.name for s in values}})
    # the locus's variables are the reference's, matched by name (a caller's own symbols and
    # the real symbols of a document read back are the same variables)
    values.update({sp.Symbol(v.name): v for v in reference.variables})
    matrix = sp.Matrix(reference.matrix).applyfunc(lambda e: _substituted(e, values))
    components = [dataclasses.replace(
        c, equations=tuple(_substituted(e, values) for e in c.equations),
        excluding=tuple(_substituted(e, values) for e in c.excluding),
        real_points_of=tuple(_substituted(e, values) for e in c.real_points_of))
        for c in locus.components]
    return certify_components(matrix, reference.variables, reference.angles, components,
                              seed=seed, deadline=should_stop, progress=progress,
                              complex_only=complex_only)


def completed_component(component, reference, *, seed: int = 0, rank_drop=None):
    """A component found by the certificate, with a real sample point, the rank drop there and
    the lost directions at it (numerically, from ``reference`` at its parameter values; the
    directions of ``rank_drop`` when it is given, a rank drop computed exactly)."""
    import numpy as np

    from .numeric.equations import NumericMatrix
    from .tolerances import RANK_RTOL

    rng = np.random.default_rng(seed)
    values = _values(reference.parameters)
    matrix = sp.Matrix(reference.matrix).applyfunc(lambda e: _substituted(e, values))
    nm = NumericMatrix(matrix, reference.variables, reference.angles)
    solved = {str(k): v for k, v in component.solved.items()}
    sample = {}
    for v in reference.variables:
        if v.name in solved and solved[v.name]:
            sample[v.name] = float(solved[v.name][0])
        else:
            sample[v.name] = float(rng.uniform(-np.pi, np.pi))
    A = np.asarray(nm([sample[v.name] for v in reference.variables]), dtype=float)
    if A.shape[0] > A.shape[1]:
        A = A.T
    U, sv, _ = np.linalg.svd(A)
    rank = int(np.sum(sv > RANK_RTOL * (sv[0] if sv.size and sv[0] > 0 else 1.0)))
    drop = rank_drop if rank_drop is not None else max(1, min(A.shape) - rank)
    dirs = tuple(tuple(float(x) for x in U[:, min(A.shape) - drop + i]) for i in range(drop))
    return dataclasses.replace(component, sample=sample, rank_drop=drop,
                               direction_at_sample=dirs)


def real_part_components(locus, reference, *, seed: int = 0):
    """Components for the complex components of the locus of ``reference`` (at its parameter
    values) that are sums of squares: the real points of each, in solved form, with
    ``real_points_of`` naming it; and those without real points, as complex-only
    components.  Those the locus already holds are left out.

    See :mod:`rankloci.exact.real_points`.

    Examples
    --------
    >>> import rankloci
    >>> from rankloci.jacobians import TaskMatrix
    >>> x, y = sp.symbols("x y", real=True)
    >>> tm = TaskMatrix("rot", sp.ImmutableMatrix([[x, -y], [y, x]]), (x, y), ())
    >>> L = rankloci.locus(tm.matrix, variables=(x, y), verify=False)
    >>> found, without = real_part_components(L, tm)
    >>> [(part.equation, comps) for part, comps in found]
    [(x**2 + y**2, [<Component x = 0, y = 0: dimension 0, rank drop 2>])]
    """
    import numpy as np

    from .exact.real_points import definite_parts, real_point_components
    from .loci import Component

    values = _values(reference.parameters)
    values.update({sp.Symbol(v.name): v for v in reference.variables})
    matrix = sp.Matrix(reference.matrix).applyfunc(lambda e: _substituted(e, values))
    known = {sp.sstr(e) for c in locus.components for e in c.real_points_of}
    rng = np.random.default_rng(seed)
    found, without = [], []
    N = len(reference.variables)
    for part in definite_parts(matrix, reference.variables, reference.angles):
        if sp.sstr(part.equation) in known:
            continue
        if not part.points:
            without.append((part, Component((part.equation,), dimension=N - 1)))
            continue
        found.append((part, real_point_components(part, matrix, reference.variables,
                                                  reference.angles, rng)))
    return found, without
