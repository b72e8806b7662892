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
    ctx = Context(tm, method=method, rng=rng if rng is not None else np.random.default_rng(0),
                  progress=progress, should_stop=should_stop)
    grow = {"svm": singular_vector_tree, "subdeterminant": subdeterminant_tree,
            "determinant": determinant_tree}[method]
    degenerate = grow(ctx)
    components = finalize(ctx)
    return Locus(model=tm.name, variables=tm.variables, parameters=dict(tm.parameters),
                 shape=tm.matrix.shape, method=method, components=tuple(components),
                 degenerate=degenerate, tree=ctx.tree,
                 seconds=(clock() - t0) if clock else 0.0, notes=tuple(ctx.notes))
