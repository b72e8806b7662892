"""Locus methods: one interface, one result type.

``compute_locus(tm, method=...)`` runs the singular vector method
(``"svm"``), the subdeterminant method (``"subdeterminant"``) or the
determinant method (``"determinant"``, square matrices only; ``svm`` on a
square matrix is the same computation).  :func:`method_for` says which
method a matrix gets when none is asked for.

The methods only decide which polynomial conditions to branch on; the tree
they grow lives in :mod:`rankloci.tree`, and :mod:`.finalize` turns its
leaves into components.
"""

from __future__ import annotations

import networkx as nx
import numpy as np

from ..errors import LocusError
from ..jacobians import lift_directions, pivot_constant_columns
from ..loci import Locus

__all__ = ["compute_locus", "method_for", "METHODS"]

METHODS = ("svm", "subdeterminant", "determinant")


def method_for(shape, requested: str | None = None, *, strict: bool = True) -> str:
    """The method a matrix of ``shape`` is computed with.

    Without a request: the determinant method for a square matrix, the
    singular vector method otherwise.  A request for the determinant method
    on a matrix that is not square is an error, or, with ``strict=False``,
    falls back to the singular vector method (for the matrix J under an
    augmented J_aug that is square).

    Examples
    --------
    >>> method_for((6, 6)), method_for((6, 7)), method_for((6, 7), "subdeterminant")
    ('determinant', 'svm', 'subdeterminant')
    >>> method_for((6, 7), "determinant", strict=False)
    'svm'
    """
    if requested is not None and requested not in METHODS:
        raise ValueError(f"method {requested!r} is not one of {METHODS}")
    square = shape[0] == shape[1]
    if requested in (None, "determinant"):
        if square:
            return "determinant"
        if requested is not None and strict:
            raise LocusError(f"the determinant method needs a square matrix; this one is "
                             f"{shape[0]}x{shape[1]}")
        return "svm"
    return requested


def compute_locus(tm, method: str = "svm", *, rng=None, progress=None,
                  should_stop=None, clock=None, hints=(), trees=None) -> Locus:
    """Rank-deficiency locus of a :class:`~rankloci.jacobians.TaskMatrix`.

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
        raises :class:`~rankloci.errors.LocusTimeout`.
    clock : callable, optional
        Returns seconds; used only to fill ``Locus.seconds``.
    hints : sequence of dict, optional
        Configurations (variable name -> value) at which a check of an earlier
        computation found a component regular: the leaves whose equations hold
        there are split or keep their exclusions (see
        :func:`~rankloci.tree.reducible.repair_leaves`).
    trees : dict, optional
        Where the grown tree of a computation is kept, for a computation again of the same
        ``tm`` and ``method`` from the same random state with ``hints``: hints change only
        the leaves of a grown tree, so that one resumes from it instead of growing it again
        (the self-check's rounds, :func:`~rankloci.verify.verified_locus`; on a 9R snake the
        tree takes about 70 of the 80 s of a computation).  The trees stay alive as long as
        the dict does.  ``Locus.seconds`` of a resumed computation counts the tree's growth.

    Examples
    --------
    >>> from rankloci.io import load_model
    >>> from rankloci.jacobians import task_matrix
    >>> locus = compute_locus(task_matrix(load_model("planar2r"), numeric=True))
    >>> [str(c.equations[0]) for c in locus.components]
    ['sin(q2)']
    """
    from ..tree.context import Context
    from ..tree.reducible import refine_leaves, repair_leaves
    from .determinant import determinant_tree
    from .finalize import finalize
    from .singular_vector import singular_vector_tree
    from .subdeterminant import subdeterminant_tree

    if method not in METHODS:
        raise ValueError(f"method {method!r} is not one of {METHODS}")
    t0 = clock() if clock else 0.0
    shape = tm.matrix.shape
    reduced, pivots = pivot_constant_columns(tm)
    notes = []
    if pivots:
        notes.append(f"{len(pivots)} constant column{'' if len(pivots) == 1 else 's'} pivoted "
                     f"out first (rows "
                     f"{', '.join(str(r + 1) for r, _ in pivots)} with columns "
                     f"{', '.join(str(c + 1) for _, c in pivots)}): rank J = {len(pivots)} + the "
                     f"rank of the remaining {reduced.shape[0]}x{reduced.shape[1]} matrix")
    if reduced.shape[0] == 0:
        return Locus(model=tm.name, variables=tm.variables, parameters=dict(tm.parameters),
                     shape=shape, method=method, components=(), tree=nx.DiGraph(),
                     seconds=(clock() - t0) if clock else 0.0, notes=tuple(notes))
    rng = rng if rng is not None else np.random.default_rng(0)
    key = (id(tm), method, repr(rng.bit_generator.state))
    kept = trees.get(key) if trees is not None else None
    if kept is not None and hints:
        # the dict holds tm, so that its id is not reused while the tree is kept
        _, ctx, degenerate, n_notes, grown = kept
        t0 -= grown
        # the leaves repaired by earlier hints stay repaired (the hints come again, and a
        # split leaf's pieces or a kept exclusion no longer admit them); the notes of the
        # earlier finalisation are written again
        ctx.resume(progress=progress, should_stop=should_stop, notes_kept=n_notes)
        ctx.progress("taking up the branch tree grown before, with the hints")
    else:
        ctx = Context(reduced, method=method, rng=rng, progress=progress, should_stop=should_stop)
        grow = {"svm": singular_vector_tree, "subdeterminant": subdeterminant_tree,
                "determinant": determinant_tree}[method]
        degenerate = grow(ctx)
        refine_leaves(ctx)
        if trees is not None:
            trees[key] = (tm, ctx, degenerate, len(ctx.notes), (clock() - t0) if clock else 0.0)
    if hints:
        repaired = ctx.count_repaired(repair_leaves(ctx, hints))
        ctx.note(f"{repaired} of the leaves were split or kept an exclusion at "
                         f"{len(hints)} configuration{'' if len(hints) == 1 else 's'} where a "
                         f"check of the first computation found a component regular")
    components = [lift_directions(c, [r for r, _ in pivots], shape[0]) for c in finalize(ctx)]
    return Locus(model=tm.name, variables=tm.variables, parameters=dict(tm.parameters),
                 shape=shape, method=method,
                 components=tuple(components),
                 degenerate=degenerate, tree=ctx.tree,
                 seconds=(clock() - t0) if clock else 0.0, notes=tuple(notes) + ctx.notes)
