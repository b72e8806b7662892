"""Two methods' loci of one matrix compared, with the SVD's verdict where they differ.

:func:`compare_loci` solves points onto each component of one locus and
checks them against the other: a point on no component of the other locus is
a disagreement, and sigma_min/sigma_max of J there says which method is right
(:class:`Disagreement`, :class:`Comparison`).  The report shows the
singular vector and subdeterminant loci compared this way.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import sympy as sp

from .expr import as_expression
from .numeric.equations import NumericMatrix
from .numeric.landscape import (component_equations, component_points, model_components,
                                sigma_ratios)
from .tolerances import COVER_RESIDUAL, RANK_RTOL

__all__ = ["Comparison", "Disagreement", "compare_loci", "equation_sets"]


@dataclass(frozen=True)
class Disagreement:
    """Points of one method's component that lie on no component of the other method.

    The SVD decides which method is right at each of them: where J is singular
    (``sigma_min/sigma_max <= RANK_RTOL``) the point belongs to the locus and
    the other method misses it; where J is regular the component is too large
    there and the other method is right.

    Attributes
    ----------
    method, other : str
        The method whose component it is, and the method that misses the points.
    index : int
        The component's 1-based number among ``method``'s components.
    equations : tuple of str
        Its equations (and ``... != 0`` for its side conditions), as plain text.
    tested : int
        How many of its points were tested.
    points : tuple of tuple of float
        The points on no component of ``other``.
    ratios : tuple of float
        sigma_min/sigma_max of J at each of ``points``.
    """

    method: str
    other: str
    index: int
    equations: tuple
    tested: int
    points: tuple
    ratios: tuple

    @property
    def regular(self) -> tuple:
        """Indices into ``points`` where J has full rank: the component is wrong there."""
        return tuple(k for k, r in enumerate(self.ratios) if r > RANK_RTOL)

    @property
    def singular(self) -> tuple:
        """Indices into ``points`` where J is rank deficient: ``other`` misses them."""
        return tuple(k for k, r in enumerate(self.ratios) if r <= RANK_RTOL)

    @property
    def right(self) -> tuple:
        """The methods the SVD sides with at these points (one, or none when both err).

        ``(other,)`` when every point is regular (the component holds regular
        points), ``(method,)`` when every point is singular (``other`` misses
        them), ``()`` when some are each.
        """
        if not self.singular:
            return (self.other,)
        if not self.regular:
            return (self.method,)
        return ()


@dataclass(frozen=True)
class Comparison:
    """Whether two loci of the same matrix describe the same set.

    ``identical``: the same equations component by component.  Otherwise
    ``agree`` is decided point by point: every point of a component of one
    (its sample and points solved onto it, away from its excluded sets) must
    lie on a component of the other.  ``disagreements`` holds, per component,
    the points where that fails with the SVD's verdict on them, and
    ``differences`` says the same in words.  Components for special parameter
    values are compared by equations only (``special_same``).
    """

    methods: tuple
    identical: bool
    agree: bool
    differences: tuple = ()
    special_same: bool = True
    points_tested: int = 0
    disagreements: tuple = ()

    @property
    def right(self) -> tuple:
        """The methods the SVD sides with wherever the loci differ (see :class:`Disagreement`).

        One method when every disagreement is decided for it, ``()`` when the
        loci agree or when each method errs somewhere.
        """
        wrong = set()
        for d in self.disagreements:
            if d.regular:
                wrong.add(d.method)
            if d.singular:
                wrong.add(d.other)
        if not self.disagreements or len(wrong) != 1:
            return ()
        return tuple(m for m in self.methods if m not in wrong)


def _normal(e):
    e = as_expression(e)
    return sp.sstr(-e if e.could_extract_minus_sign() else e)


def equation_sets(locus, special: bool = False):
    """The equations of each component, normalised and sorted: of the model's own components,
    or (``special=True``) of the others."""
    comps = locus.special if special else locus.components
    return sorted(tuple(sorted(_normal(e) for e in c.equations)) for c in comps)


def compare_loci(a, b, nm: NumericMatrix, parameters, rng, *, points: int = 4) -> Comparison:
    """Compare the loci ``a`` and ``b`` of one matrix (see :class:`Comparison`)."""
    methods = (a.method, b.method)
    special_same = equation_sets(a, True) == equation_sets(b, True)
    if equation_sets(a) == equation_sets(b) and a.degenerate == b.degenerate:
        return Comparison(methods, True, True, (), special_same, 0)
    diffs, found, tested = [], [], 0
    if a.degenerate != b.degenerate:
        diffs.append(f"{a.method} says degenerate={a.degenerate}, {b.method} {b.degenerate}")
    for x, y in ((a, b), (b, a)):
        ys = [component_equations(c, nm, parameters) for _, c in model_components(y)]
        for i, comp in model_components(x):
            pts = component_points(comp, nm, parameters, rng, points)
            tested += len(pts)
            off = [q for q in pts if not any(e.residual(q) <= COVER_RESIDUAL for e in ys)]
            if off:
                ratios = sigma_ratios(nm.batch(np.array(off)))
                eqs = tuple(f"{sp.sstr(e)} = 0" for e in comp.equations)
                eqs += tuple(f"{sp.sstr(e)} != 0" for e in comp.excluding)
                found.append(Disagreement(x.method, y.method, i, eqs, len(pts),
                                          tuple(tuple(float(v) for v in q) for q in off),
                                          tuple(float(r) for r in ratios)))
                diffs.append(f"{x.method} component {i} has {len(off)} of {len(pts)} tested "
                             f"points on no {y.method} component")
    return Comparison(methods, False, not diffs, tuple(diffs), special_same, tested, tuple(found))
