"""Every numeric tolerance rankloci uses, in one place.

All rank decisions are relative to the largest singular value sigma_max, as in
``numpy.linalg.matrix_rank``: a matrix is numerically rank deficient when
sigma_min <= RANK_RTOL * sigma_max.

Why these values
----------------
The Jacobians handled here are evaluated in double precision from closed-form
trigonometric expressions with O(10) terms per entry, so the entries carry a
relative rounding error of a few 1e-16.  The smallest singular value of a
matrix that is exactly singular is then about max(n, m) * eps * sigma_max,
i.e. ~1e-15 for 6x10.  Points on a locus found by a numerical root finder are
accurate to ~1e-12 in the joint variables (ROOT_XTOL), and sigma_min is
Lipschitz in q with a constant of order sigma_max, so on-locus points have
sigma_min/sigma_max ~ 1e-12.  RANK_RTOL = 1e-8 leaves four orders of
magnitude above that, and random regular configurations of the built-in
models have sigma_min/sigma_max of 1e-3 or more (see the off-locus checks),
far above it.
"""

#: sigma_min / sigma_max at or below which a matrix counts as rank deficient.
RANK_RTOL = 1e-8

#: Residual (relative to the scale of the equations) accepted from the root
#: finder when sampling points on an implicit locus component.
ROOT_XTOL = 1e-12

#: Distance in sigma_min/sigma_max a configuration must keep from RANK_RTOL to
#: count as clearly regular in off-locus sampling.
REGULAR_MIN_RATIO = 1e-6

#: A float angle within this distance of a multiple of pi/12 is taken to be
#: that exact multiple when a model file is read.
ANGLE_SNAP_ATOL = 1e-12

#: URDF files write angles with 4-10 significant digits (pi/2 as 1.5708, off by
#: 3.7e-6), so an rpy angle within this of a multiple of pi/12, or a unit-axis
#: component within this of 0, +-1/2, +-sqrt(2)/2, +-sqrt(3)/2 or +-1, is taken
#: as that exact value when a URDF is read.
URDF_ANGLE_SNAP_ATOL = 1e-5
