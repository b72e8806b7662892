"""Locus methods: one interface, one result type.

``compute_locus(tm, method=...)`` runs the singular vector method
(``"svm"``, the default), the subdeterminant method (``"subdeterminant"``)
or the determinant method (``"determinant"``, square matrices only; ``svm``
on a square matrix is the same computation).
"""

from __future__ import annotations


import numpy as np

from ..locus import Locus

__all__ = ["compute_locus", "METHODS"]

METHODS = ("svm", "subdeterminant", "determinant")


def compute_locus(tm, method: str = "svm", *, frame_choice=None, rng=None, progress=None,
                  should_stop=None, clock=None) -> Locus:
    """Rank-deficiency locus of a :class:`~rankloci.matrix.TaskMatrix`.

    Parameters
    ----------
    tm : TaskMatrix
    method : {"svm", "subdeterminant", "determinant"}
    rng : numpy.random.Generator, optional
        Random source of the numeric probes (default: seed 0).
    progress : callable, optional
        Called with one-line progress messages.
    should_stop : callable, optional
        Polled during the computation; when it returns True the computation
        raises :class:`~rankloci.methods._common.LocusTimeout`.
    clock : callable, optional
        Returns seconds; used only to fill ``Locus.seconds``.

    Examples
    --------
    >>> from rankloci.io import load_model
    >>> from rankloci.matrix import task_matrix
    >>> locus = compute_locus(task_matrix(load_model("planar2r"), numeric=True))
    >>> [str(c.equations[0]) for c in locus.components]
    ['sin(q2)']
    """
    from ._common import Context, finalize
    from .determinant import determinant_tree
    from .singular_vector import singular_vector_tree
    from .subdeterminant import subdeterminant_tree

    if method not in METHODS:
        raise ValueError(f"method {method!r} is not one of {METHODS}")
    t0 = clock() if clock else 0.0
    shape = tm.matrix.shape
    reduced, pivots = pivot_constant_columns(tm)
    notes = []
    if pivots:
        notes.append(f"{len(pivots)} constant column(s) pivoted out first (rows "
                     f"{', '.join(str(r + 1) for r, _ in pivots)} with columns "
                     f"{', '.join(str(c + 1) for _, c in pivots)}): rank J = {len(pivots)} + the "
                     f"rank of the remaining {reduced.shape[0]}x{reduced.shape[1]} matrix")
    if reduced.shape[0] == 0:
        import networkx as nx

        return Locus(model=tm.name, variables=tm.variables, parameters=dict(tm.parameters),
                     shape=shape, method=method, components=(), tree=nx.DiGraph(),
                     seconds=(clock() - t0) if clock else 0.0, notes=tuple(notes))
    ctx = Context(reduced, method=method, rng=rng if rng is not None else np.random.default_rng(0),
                  progress=progress, should_stop=should_stop)
    grow = {"svm": singular_vector_tree, "subdeterminant": subdeterminant_tree,
            "determinant": determinant_tree}[method]
    degenerate = grow(ctx)
    components = [_lift(c, [r for r, _ in pivots], shape[0]) for c in finalize(ctx)]
    return Locus(model=tm.name, variables=tm.variables, parameters=dict(tm.parameters),
                 shape=shape, method=method, components=tuple(components),
                 degenerate=degenerate, tree=ctx.tree,
                 seconds=(clock() - t0) if clock else 0.0, notes=tuple(notes + ctx.notes))


def pivot_constant_columns(tm):
    """``tm`` without the rows and columns of constant pivot columns, and the pivots.

    A column whose entries in the remaining rows are numbers, exactly one of
    them nonzero (a prismatic base joint in the base frame, say), is a pivot:
    column operations clear its row elsewhere, so rank J = 1 + rank of J
    without that row and column.  Only for matrices with at least as many
    columns as rows (then the left null vectors of the rest, with zeros in
    the pivot rows, are those of J).

    Returns
    -------
    TaskMatrix, list of (row, column)
    """
    import dataclasses

    import sympy as sp

    J = tm.matrix
    if J.rows > J.cols:
        return tm, []
    rows, cols = list(range(J.rows)), list(range(J.cols))
    pivots = []
    found = True
    while found and rows:
        found = False
        for j in cols:
            entries = [J[i, j] for i in rows]
            if all(e.is_number for e in entries):
                nonzero = [i for i, e in zip(rows, entries) if e != 0]
                if len(nonzero) == 1:
                    pivots.append((nonzero[0], j))
                    rows.remove(nonzero[0])
                    cols.remove(j)
                    found = True
                    break
    if not pivots:
        return tm, []
    labels = tuple(tm.row_labels[i] for i in rows) if tm.row_labels else ()
    return dataclasses.replace(tm, matrix=sp.ImmutableMatrix(J.extract(rows, cols)),
                               row_labels=labels), pivots


def _lift(comp, pivot_rows, n_rows):
    """Lost directions of the reduced matrix as directions of J: zeros in the pivot rows."""
    import dataclasses

    import sympy as sp

    if not pivot_rows:
        return comp
    keep = [i for i in range(n_rows) if i not in pivot_rows]

    def lift(vec, zero):
        out = [zero] * n_rows
        for i, x in zip(keep, vec):
            out[i] = x
        return tuple(out)

    return dataclasses.replace(
        comp, direction=tuple(lift(v, sp.Integer(0)) for v in comp.direction),
        direction_at_sample=tuple(lift(v, 0.0) for v in comp.direction_at_sample))
