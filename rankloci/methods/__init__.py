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

from dataclasses import dataclass

import networkx as nx
import numpy as np

from ..errors import LocusError
from ..jacobians import lift_directions, pivot_constant_columns
from ..loci import Locus

__all__ = ["compute_locus", "locus_and_tree", "GrownTree", "method_for", "METHODS"]

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


@dataclass(frozen=True, eq=False)
class GrownTree:
    """A branch tree grown by :func:`locus_and_tree`, to be taken up again with hints.

    Hints (configurations where a check found a component regular) change only the leaves of
    a grown tree (:func:`~rankloci.tree.reducible.repair_leaves`), so a computation with hints
    resumes from this value instead of growing the tree again (on a 9R snake the tree takes
    most of a computation).  The value is never changed: a computation that resumes from it
    works in a copy of its context and returns that copy as a new value.

    Attributes
    ----------
    tm : TaskMatrix
        The matrix the tree was grown for.
    method : str
        The method that grew it.
    context : rankloci.tree.context.Context
        The grown computation, after its leaves were finalised.
    degenerate : bool
        What the method returned: the matrix is rank deficient everywhere.
    notes_kept : int
        The context's notes that the growth wrote (those of a finalisation are written again).
    seconds : float
        How long the growth took (``Locus.seconds`` of a resumed computation counts it).
    """

    tm: object
    method: str
    context: object
    degenerate: bool
    notes_kept: int
    seconds: float


def compute_locus(tm, method: str = "svm", *, rng=None, progress=None,
                  should_stop=None, clock=None, hints=(), grown=None) -> Locus:
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
    grown : GrownTree, optional
        A tree :func:`locus_and_tree` grew for ``tm`` with ``method``: the computation
        resumes from it (``rng`` is then unused: the tree's context has its own random
        stream).  It is not changed.

    Examples
    --------
    >>> from rankloci.io import load_model
    >>> from rankloci.jacobians import task_matrix
    >>> locus = compute_locus(task_matrix(load_model("planar2r"), numeric=True))
    >>> [str(c.equations[0]) for c in locus.components]
    ['sin(q2)']
    """
    return locus_and_tree(tm, method, rng=rng, progress=progress, should_stop=should_stop,
                          clock=clock, hints=hints, grown=grown)[0]


def locus_and_tree(tm, method: str = "svm", *, rng=None, progress=None, should_stop=None,
                   clock=None, hints=(), grown=None) -> tuple[Locus, GrownTree | None]:
    """:func:`compute_locus`, and the grown tree as a value to resume from with hints.

    Parameters and the locus are those of :func:`compute_locus`.  The tree is None when the
    matrix has no row left once its constant columns are pivoted out (there is no tree then).
    Calling it twice with the same arguments gives the same locus and an equal tree: a
    computation that resumes from ``grown`` edits a copy of its context (measured on
    ``snake9``, the copy takes a small fraction of a second against tens of seconds of growth).

    Examples
    --------
    >>> import numpy as np
    >>> from rankloci.io import load_model
    >>> from rankloci.jacobians import task_matrix
    >>> tm = task_matrix(load_model("planar2r"), numeric=True)
    >>> locus, tree = locus_and_tree(tm, rng=np.random.default_rng(0))
    >>> again = compute_locus(tm, hints=({"q1": 0.1, "q2": 0.5},), grown=tree)
    >>> [str(c.equations[0]) for c in again.components]
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
    if grown is not None and (grown.method != method or grown.tm is not tm and grown.tm != tm):
        raise ValueError(f"grown: a tree grown with method {grown.method!r} for "
                         f"{grown.tm.name!r}, not with {method!r} for {tm.name!r}")
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
                     seconds=(clock() - t0) if clock else 0.0, notes=tuple(notes)), None
    if grown is not None:
        t0 -= grown.seconds
        degenerate = grown.degenerate
        # the leaves repaired by earlier hints stay repaired (the hints come again, and a
        # split leaf's pieces or a kept exclusion no longer admit them); the notes of the
        # earlier finalisation are written again
        ctx = grown.context.copy()
        ctx.resume(progress=progress, should_stop=should_stop, notes_kept=grown.notes_kept)
        ctx.progress("taking up the branch tree grown before, with the hints")
        grown = GrownTree(tm, method, ctx, degenerate, grown.notes_kept, grown.seconds)
    else:
        rng = rng if rng is not None else np.random.default_rng(0)
        ctx = Context(reduced, method=method, rng=rng, progress=progress, should_stop=should_stop)
        grow = {"svm": singular_vector_tree, "subdeterminant": subdeterminant_tree,
                "determinant": determinant_tree}[method]
        degenerate = grow(ctx)
        refine_leaves(ctx)
        grown = GrownTree(tm, method, ctx, degenerate, len(ctx.notes),
                          (clock() - t0) if clock else 0.0)
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
                 seconds=(clock() - t0) if clock else 0.0, notes=tuple(notes) + ctx.notes), grown
