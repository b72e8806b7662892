"""Exact transforms from the decimal floats of a URDF file.

URDF numbers are decimal floats, but the symbolic algebra downstream must
stay exact.  Lengths become the rational of their shortest decimal form
(``0.089159`` is ``89159/1000000``).  An rpy angle within
:data:`~rankloci.tolerances.URDF_ANGLE_SNAP_ATOL` of a multiple of ``pi/12``
(``1.5708``, ``1.57079632679``) is taken as that exact multiple, so its sine
and cosine are exact radicals.  Any other angle ``t`` gives the rational
rotation with ``cos = (1 - u**2)/(1 + u**2)``, ``sin = 2u/(1 + u**2)`` where
``u`` is the rational of smallest denominator that moves the angle by at most
:data:`~rankloci.tolerances.URDF_ROTATION_ATOL` from ``tan(t/2)``: the matrix
is exactly orthogonal (converting float cosines entry by entry would not be)
and its entries are short.  Axis components are snapped the same way
(``0.9999999`` is ``1``); an axis that does not snap becomes an exactly unit
rational vector (inverse stereographic projection of short rationals) within
URDF_ROTATION_ATOL of the normalised float axis.

Lengths within :data:`~rankloci.tolerances.URDF_LENGTH_SNAP_ATOL` of 0 (an
exporter's ``4.33681e-19``) are taken as 0.  Every such change is counted in a
:class:`Snaps`, whose :meth:`Snaps.note` tells the user what the reading changed.

The constant offset of a mimic joint is a motion about or along its exact
axis (:func:`exact_motion`): a rotation by an angle read like an rpy angle,
or a translation by a rational length.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np
import sympy as sp

from ..expr import exact_number
from ..model import trans
from ..tolerances import (MAX_TRANSFORM_DIGITS, URDF_ANGLE_SNAP_ATOL,
                          URDF_DENOMINATOR_BLOCK as _DENOMINATOR_BLOCK,
                          URDF_DENOMINATOR_MAX as _DENOMINATOR_MAX, URDF_LENGTH_SNAP_ATOL,
                          URDF_ROTATION_ATOL)

__all__ = ["exact_origin", "exact_axis", "exact_motion", "expanded_product", "bounded", "Snaps",
           "simplest_rational", "read_angle", "read_axis", "cos_sin"]


# Exact values a unit-axis component may snap to (besides their negatives).
_NICE_COMPONENTS = (sp.Integer(0), sp.Rational(1, 2), sp.sqrt(2) / 2, sp.sqrt(3) / 2,
                    sp.Integer(1))


@dataclass
class Snaps:
    """The changes snapping made while a URDF was read: one list of sizes per kind.

    A value whose float already equals its exact twin's (``0``,
    ``1.5707963267948966``) is no change and is not counted.

    Examples
    --------
    >>> snaps = Snaps()
    >>> T = exact_origin((0.1, 4.33681e-19, 0.0), (1.5708, 0.0, 0.0), snaps)
    >>> print(snaps.note())  # doctest: +NORMALIZE_WHITESPACE
    reading the URDF snapped 1 rpy angle to an exact multiple of pi/12 (largest change 3.7e-06 rad)
    and 1 length to 0 (largest 4.3e-19 m); results are for the snapped model
    """

    angles: list = field(default_factory=list)
    axes: list = field(default_factory=list)
    lengths: list = field(default_factory=list)
    rotations: list = field(default_factory=list)

    def note(self) -> str | None:
        """One line for the output, or None when reading changed nothing."""
        parts = []
        for values, one, many, largest in (
                (self.angles, "rpy angle to an exact multiple of pi/12",
                 "rpy angles to exact multiples of pi/12", "largest change {:.2g} rad"),
                (self.axes, "axis component to an exact value", "axis components to exact values",
                 "largest change {:.2g}"),
                (self.lengths, "length to 0", "lengths to 0", "largest {:.2g} m"),
                (self.rotations, "other rotation or axis to a short exact rational one",
                 "other rotations and axes to short exact rational ones",
                 "largest change {:.2g} rad")):
            if values:
                what = one if len(values) == 1 else many
                parts.append(f"{len(values)} {what} ({largest.format(max(values))})")
        if not parts:
            return None
        listed = parts[0] if len(parts) == 1 else ", ".join(parts[:-1]) + " and " + parts[-1]
        return f"reading the URDF snapped {listed}; results are for the snapped model"


def _length(x: float, snaps: Snaps | None) -> sp.Expr:
    """Exact length of a float in metres; 0 within URDF_LENGTH_SNAP_ATOL of it."""
    if x != 0.0 and abs(x) <= URDF_LENGTH_SNAP_ATOL:
        if snaps is not None:
            snaps.lengths.append(abs(x))
        return sp.Integer(0)
    return exact_number(x)


def simplest_rational(lo: Fraction, hi: Fraction) -> Fraction:
    """The rational with the smallest denominator in ``[lo, hi]`` (``lo <= hi``).

    By continued fractions: an integer in the interval if there is one,
    otherwise the common integer part plus the reciprocal of the simplest
    rational in the reciprocal interval of the fractional parts.

    Examples
    --------
    >>> simplest_rational(Fraction(314, 100), Fraction(315, 100))
    Fraction(22, 7)
    >>> simplest_rational(Fraction(-1, 3), Fraction(1, 2))
    Fraction(0, 1)
    """
    n = math.floor(lo)
    if n == lo:
        return Fraction(n)
    if n + 1 <= hi:
        return Fraction(n + 1)
    return n + 1 / simplest_rational(1 / (hi - n), 1 / (lo - n))


def _short(x: float, tol: float) -> sp.Rational:
    """The rational of smallest denominator within ``tol`` of ``x``."""
    f = simplest_rational(Fraction(x) - Fraction(tol), Fraction(x) + Fraction(tol))
    return sp.Rational(f.numerator, f.denominator)


def _common_denominator(xs, tol: float) -> list[sp.Rational]:
    """Rationals ``A_i / q`` within ``tol`` of each ``xs[i]``, with the smallest such ``q``.

    The two stereographic coordinates of an axis share their denominator, so the
    axis's entries ``(2Aq, 2Bq, q**2 - A**2 - B**2) / (q**2 + A**2 + B**2)`` have
    about twice its digits; two separate short rationals would give four times
    theirs.  For two numbers and ``tol`` 2.5e-10, ``q`` stays below about 1e7
    (the chance that a given ``q`` serves both is about ``(2 q tol)**2``).  Past
    ``_DENOMINATOR_MAX`` each number gets its own short rational instead.

    Examples
    --------
    >>> _common_denominator([0.5, 0.25], 1e-12)
    [1/2, 1/4]
    >>> _common_denominator([0.333333, 0.0], 1e-5)
    [1/3, 0]
    """
    xs = [float(x) for x in xs]
    start = 1
    while start < _DENOMINATOR_MAX:
        q = np.arange(start, start + _DENOMINATOR_BLOCK, dtype=float)
        ok = np.ones(len(q), dtype=bool)
        for x in xs:
            # |x - round(x q) / q| <= tol, checked in floats with a margin, then exactly
            ok &= np.abs(x * q - np.round(x * q)) <= tol * q * (1 - 1e-6)
        for qq in q[ok]:
            qq = int(qq)
            got = [sp.Rational(round(Fraction(x) * qq), qq) for x in xs]
            if all(abs(Fraction(int(g.p), int(g.q)) - Fraction(x)) <= Fraction(tol)
                   for g, x in zip(got, xs)):
                return got
        start += _DENOMINATOR_BLOCK
    return [_short(x, tol) for x in xs]


def _snap_angle(t: float) -> sp.Expr | None:
    """The exact multiple of pi/12 within URDF_ANGLE_SNAP_ATOL of ``t``, or None."""
    k = round(t / (math.pi / 12))
    if abs(t - k * math.pi / 12) <= URDF_ANGLE_SNAP_ATOL:
        return sp.pi * sp.Rational(k, 12)
    return None


def cos_sin(t: float, snaps: Snaps | None = None) -> tuple[sp.Expr, sp.Expr]:
    """Exact (cos, sin) of an angle read as a float; see the module docstring."""
    t = math.remainder(t, 2 * math.pi)  # in [-pi, pi]
    snapped = _snap_angle(t)
    if snapped is not None:
        if snaps is not None and float(snapped) != t:
            snaps.angles.append(abs(float(snapped) - t))
        return sp.cos(snapped), sp.sin(snapped)
    v = math.tan(t / 2)  # finite: angles near +-pi snap
    # d(angle) = 2 du / (1 + u**2)
    u = _short(v, URDF_ROTATION_ATOL * (1 + v * v) / 2)
    if snaps is not None:
        snaps.rotations.append(abs(2 * math.atan(float(u)) - t))
    return (1 - u**2) / (1 + u**2), 2 * u / (1 + u**2)


def read_angle(t: float) -> float:
    """The float value of the exact angle an rpy angle ``t`` of a URDF is read as.

    Examples
    --------
    >>> read_angle(1.5708) == math.pi / 2, abs(read_angle(0.7) - 0.7) <= 1e-9
    (True, True)
    """
    t = math.remainder(t, 2 * math.pi)
    snapped = _snap_angle(t)
    if snapped is not None:
        return float(snapped)
    c, s = cos_sin(t)
    return math.atan2(float(s), float(c))


def _rotation(axis: str, t: float, snaps: Snaps | None = None) -> sp.Matrix:
    """Exact 4x4 rotation by the float angle ``t`` about the x, y or z axis."""
    c, s = cos_sin(t, snaps)
    m = sp.eye(4)
    i, j = {"x": (1, 2), "y": (2, 0), "z": (0, 1)}[axis]
    m[i, i], m[i, j], m[j, i], m[j, j] = c, -s, s, c
    return m


def expanded_product(a: sp.Matrix, b: sp.Matrix) -> sp.Matrix:
    """``a * b`` with every entry expanded."""
    return (a * b).applyfunc(sp.expand)


def _digits(x) -> int:
    return max(x.p.bit_length(), x.q.bit_length()) * 30103 // 100000 + 1


def bounded(T: sp.Matrix) -> sp.Matrix:
    """``T``, or, when its rational entries grow past MAX_TRANSFORM_DIGITS, a short exact twin.

    Composing fixed joints with float rpy angles multiplies the denominators
    of their exact rational rotations.  The rotation of such a product is
    replaced by the exact rotation of the rational quaternion nearest to it
    (each component the shortest decimal of its float value, so the entries
    have about 34 digits and the matrix is exactly orthogonal), within
    rounding error of the product; the translation by the shortest decimals
    of its floats.  Transforms with radicals (snapped angles) are exact and
    short, and are returned as they are.

    Examples
    --------
    >>> T = sp.eye(4)
    >>> for _ in range(50):
    ...     T = bounded(expanded_product(T, exact_origin((0, 0, 0.1), (0.3, 0.2, 0.1))))
    >>> (T[:3, :3] * T[:3, :3].T == sp.eye(3), max(_digits(x) for x in T) <= 80)
    (True, True)
    """
    if not all(x.is_Rational for x in T) or max(_digits(x) for x in T) <= MAX_TRANSFORM_DIGITS:
        return T

    R = np.array(T[:3, :3].evalf(20), dtype=float)
    # the quaternion of R (Shepperd's method: divide by the largest of the four candidates)
    tr = np.trace(R)
    cand = [tr, R[0, 0], R[1, 1], R[2, 2]]
    k = int(np.argmax(cand))
    if k == 0:
        w = np.sqrt(1 + tr) / 2
        q = [w, (R[2, 1] - R[1, 2]) / (4 * w), (R[0, 2] - R[2, 0]) / (4 * w),
             (R[1, 0] - R[0, 1]) / (4 * w)]
    else:
        i, j, m = k - 1, k % 3, (k + 1) % 3
        v = np.sqrt(1 + R[i, i] - R[j, j] - R[m, m]) / 2
        q = [0.0] * 4
        q[0] = (R[m, j] - R[j, m]) / (4 * v)
        q[1 + i] = v
        q[1 + j] = (R[j, i] + R[i, j]) / (4 * v)
        q[1 + m] = (R[m, i] + R[i, m]) / (4 * v)
    a, b, c, d = (exact_number(float(x)) if abs(x) > 1e-15 else sp.Integer(0) for x in q)
    n = a * a + b * b + c * c + d * d
    rot = sp.Matrix([
        [a * a + b * b - c * c - d * d, 2 * (b * c - a * d), 2 * (b * d + a * c)],
        [2 * (b * c + a * d), a * a - b * b + c * c - d * d, 2 * (c * d - a * b)],
        [2 * (b * d - a * c), 2 * (c * d + a * b), a * a - b * b - c * c + d * d]]) / n
    out = sp.eye(4)
    out[:3, :3] = rot
    out[:3, 3] = sp.Matrix([exact_number(float(x)) for x in T[:3, 3]])
    return out


def exact_origin(xyz, rpy, snaps: Snaps | None = None) -> sp.Matrix:
    """Exact 4x4 transform of an ``<origin>``: ``trans(xyz) * Rz(yaw) * Ry(pitch) * Rx(roll)``.

    Snapped angles and lengths are counted in ``snaps`` when it is given.

    Examples
    --------
    >>> exact_origin((0.5, 0.0, 0.0), (0.0, 0.0, 1.5708))
    Matrix([
    [0, -1, 0, 1/2],
    [1,  0, 0,   0],
    [0,  0, 1,   0],
    [0,  0, 0,   1]])
    """
    roll, pitch, yaw = rpy
    T = trans(*(_length(x, snaps) for x in xyz))
    for axis, t in (("z", yaw), ("y", pitch), ("x", roll)):
        if t != 0.0:
            T = expanded_product(T, _rotation(axis, t, snaps))
    return T


def exact_axis(v: tuple[float, ...], snaps: Snaps | None = None) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """Exact unit vector for a float axis; see the module docstring.

    Components snapped to an exact value they were not already are counted in ``snaps``.
    """
    big = max(abs(x) for x in v)  # > 0, checked by urdf_xml.axis_floats
    v = [x / big for x in v]        # no overflow or underflow in the norm
    norm = math.sqrt(sum(x * x for x in v))
    u = [x / norm for x in v]
    snapped = []
    for x in u:
        nice = next((n for n in _NICE_COMPONENTS if abs(abs(x) - float(n)) <= URDF_ANGLE_SNAP_ATOL),
                    None)
        snapped.append(None if nice is None else (nice if x > 0 else -nice))
    if None not in snapped and sp.expand(sum(x**2 for x in snapped)) == 1:
        if snaps is not None:
            snaps.axes.extend(abs(float(n) - x) for n, x in zip(snapped, u) if float(n) != x)
        return tuple(snapped)
    # An exactly unit rational vector: inverse stereographic projection, from the
    # pole opposite the largest component, of the rationalised projected point.
    k = max(range(3), key=lambda m: abs(u[m]))
    others = [m for m in range(3) if m != k]
    if snaps is not None:
        snaps.axes.extend(abs(u[m]) for m in others if 0 < abs(u[m]) <= URDF_ANGLE_SNAP_ATOL)
    # the unit vector moves by at most 2 (|da| + |db|)
    a, b = _common_denominator([0.0 if abs(u[m]) <= URDF_ANGLE_SNAP_ATOL else u[m] / (1 + abs(u[k]))
                                for m in others], URDF_ROTATION_ATOL / 4)
    d = 1 + a**2 + b**2
    out = [sp.Integer(0)] * 3
    out[others[0]], out[others[1]] = 2 * a / d, 2 * b / d
    out[k] = (1 if u[k] > 0 else -1) * (1 - a**2 - b**2) / d
    if snaps is not None and (a != 0 or b != 0):
        snaps.rotations.append(float(np.linalg.norm([float(x) - y for x, y in zip(out, u)])))
    return tuple(out)


def read_axis(v: tuple[float, ...]) -> tuple[float, float, float]:
    """The float values of the exact unit axis a URDF axis ``v`` is read as."""
    return tuple(float(x) for x in exact_axis(v))


def exact_motion(kind: str, axis, value, snaps: Snaps | None = None) -> sp.Matrix:
    """Exact 4x4 motion by a constant ``value`` about (revolute) or along (prismatic) ``axis``.

    ``axis`` is an exact unit vector (:func:`exact_axis`); ``value`` an exact
    rational.  A translation is exact as it stands; a rotation takes its cosine
    and sine from the float angle as an rpy angle does, so it is an exact
    rotation (Rodrigues' formula on an exact unit axis with ``c**2 + s**2 == 1``).

    Examples
    --------
    >>> exact_motion("revolute", (0, 0, 1), sp.Rational(15708, 10000))[:3, :3]
    Matrix([
    [0, -1, 0],
    [1,  0, 0],
    [0,  0, 1]])
    >>> exact_motion("prismatic", (0, 1, 0), sp.Rational(1, 4))[:3, 3].T
    Matrix([[0, 1/4, 0]])
    """
    k = sp.Matrix(axis)
    m = sp.eye(4)
    if kind == "prismatic":
        m[:3, 3] = k * value
        return m
    c, s = cos_sin(float(value), snaps)
    K = sp.Matrix([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    m[:3, :3] = (c * sp.eye(3) + s * K + (1 - c) * k * k.T).applyfunc(sp.expand)
    return m
