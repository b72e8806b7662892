"""Exact polynomial algebra for rank-deficiency loci.

:mod:`~rankloci.algebra.ring` holds the ring of half-angle coordinates and
the conversions between sympy expressions and its polynomials;
:mod:`~rankloci.algebra.polys` the determinants and factorisations done in it.
"""

from .polys import (PolyMemo, TermLimit, abs_poly, circle_free_det, common_factor,
                    irreducible_factors, laplace_det, primitive_vector, transpose)
from .ring import PolyRing

__all__ = ["PolyRing", "PolyMemo", "laplace_det", "circle_free_det", "irreducible_factors", "abs_poly",
           "common_factor", "primitive_vector", "transpose", "TermLimit"]
