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

# ---------------------------------------------------------------------------
# FSP reducer (rankloci.numeric.fsp)
#
# The thresholds of ReduceA and mat_null in K. A. Morgansen, F. G. Pin,
# "Enhanced Code for the Full Space Parameterization Approach to Solving
# Underspecified Systems of Algebraic Equations", ORNL/TM-12816 (1995),
# section 4 and the listings FSP.h / FSP.c / matrix.c of appendix B.  They are
# the report's values, not derived from RANK_RTOL: the reducer is a faithful
# port, and with these values it reproduces the report's examples 6.1-6.4.
# ---------------------------------------------------------------------------

#: ReduceA's zero threshold is SMALL = FSP_SMALL_FRACTION * max|A_ij|: an entry
#: with |A_ij| <= SMALL counts as zero ("This value is then divided by 1000").
FSP_SMALL_FRACTION = 1e-3

#: matrix.c SV_SMALL: mat_null counts a singular value below it as zero.  An
#: absolute threshold, as in the listing; section 4 quotes 1.0e-5 for the
#: examples, but the listing that produced them has 1.0e-4.
FSP_SV_SMALL = 1e-4

#: Condition number s_max/s_min above which mat_null also counts the smallest
#: singular value as zero.  The listing tests s_min/s_max < SV_SMALL, i.e. this
#: bound is 1/SV_SMALL.
FSP_NULL_K2_BND = 1.0 / FSP_SV_SMALL

#: FSP.h K2_BND: the largest condition number of an acceptable square
#: submatrix in the FSP solution search (section 4: "set to a value of 10").
#: Not the reducer's bound: the Jacobian of example 6.1 has condition number
#: 12.5, and with 10 the reducer would call one of its rows dependent, which
#: the report says it is not.
FSP_K2_BND = 10.0

#: ReduceA's N_BND = FSP_N_BND_NUMERATOR / (N + 1), N the number of rows of A:
#: a null vector's first component at least this large names a dependent row.
FSP_N_BND_NUMERATOR = 0.9

#: A polynomial counts as vanishing at a point when its value is at most
#: ZERO_RTOL times the value of the same polynomial with every coefficient and
#: every variable replaced by its absolute value (the size of its terms).
#: Points of a branch are accurate to ROOT_XTOL, and the polynomials that are
#: tested have at most a few thousand terms, so a vanishing polynomial stays
#: below ~1e-11 of its term size; 1e-9 leaves a margin of two orders.
ZERO_RTOL = 1e-9

#: A sample point of a branch that excludes the zero set of a polynomial e
#: (where the null vectors of a level degenerate) is accepted only when |e| is
#: above EXCLUSION_RTOL times the size of its terms.  Generic points of the
#: branch are far from that set (|e| of order 1e-2 of its term size and up);
#: points within 1e-4 of it carry a rank decision that rounding could flip,
#: so they are left to the excluded set's own branch.
EXCLUSION_RTOL = 1e-4

#: A branch without sample points whose best Gauss-Newton residual (relative
#: to the size of the terms) is at most NEAR_MISS_RTOL probably has real
#: points where its last equation and that equation's gradient vanish
#: together: there Gauss-Newton converges only linearly (the residual of a
#: squared distance d**2 stalls near 1e-8 to 1e-6 while d is 1e-4 to 1e-3).
#: Such a branch is searched again with the gradient's equations added,
#: where convergence is quadratic.  A branch with no real point keeps a
#: residual of order 1e-2 and up.
NEAR_MISS_RTOL = 1e-4
