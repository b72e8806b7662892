"""Checks of the inputs of the FSP reducer (:mod:`rankloci.numeric.fsp`).

Each returns a float copy of an array, so that the caller's data is never
modified, or raises naming the parameter and the value.
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from ..errors import ShapeError

__all__ = ["finite_matrix", "finite_vector", "check_number"]


def finite_matrix(A, name: str) -> np.ndarray:
    """A float copy of a finite 2-D array.

    Examples
    --------
    >>> finite_matrix([[1, 2]], "A")
    array([[1., 2.]])
    >>> finite_matrix([1, 2], "A")
    Traceback (most recent call last):
        ...
    rankloci.errors.ShapeError: A must be a 2-D matrix, got shape (2,)
    """
    a = np.array(A, dtype=float)
    if a.ndim != 2:
        raise ShapeError(f"{name} must be a 2-D matrix, got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be finite")
    return a


def finite_vector(b, length: int, name: str) -> np.ndarray:
    """A float copy of a finite 1-D array of the given length."""
    v = np.array(b, dtype=float)
    if v.shape != (length,):
        raise ShapeError(f"{name} must have shape ({length},), got {v.shape}")
    if not np.all(np.isfinite(v)):
        raise ValueError(f"{name} must be finite")
    return v


def check_number(name: str, value: float, low: float, high: float = math.inf,
                 low_inclusive: bool = False) -> None:
    """Raise ValueError unless low < value <= high (low <= value if inclusive).

    Examples
    --------
    >>> check_number("n_bnd", 0.5, 0.0, 1.0)
    >>> check_number("n_bnd", 0.0, 0.0, 1.0)
    Traceback (most recent call last):
        ...
    ValueError: n_bnd must be a number in (0.0, 1.0], got 0.0
    """
    ok = isinstance(value, numbers.Real) and value <= high and (
        value >= low if low_inclusive else value > low)
    if not ok:
        bracket = "[" if low_inclusive else "("
        raise ValueError(f"{name} must be a number in {bracket}{low}, {high}], "
                         f"got {value!r}")
