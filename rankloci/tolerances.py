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

#: ``Locus.contains(q)``: q is on a component when each of its equations, divided by the sum
#: of the absolute values of its coefficients, is at most this at q.  Scaled trigonometric
#: equations change by at most their degree per radian, so this admits points within ~1e-9
#: rad of a component, where sigma_min/sigma_max is ~1e-9, below RANK_RTOL: points the SVD
#: also calls singular.  Exact points give ~1e-16, computed ones ON_COMPONENT_RESIDUAL.
LOCUS_CONTAINS_RTOL = 1e-9

#: Residual (relative to the scale of the equations) accepted from the root
#: finder when sampling points on an implicit locus component.  Gauss-Newton
#: reaches 1e-14 on well-scaled equations, but stalls at 1.4e-12 to 1e-11 on
#: near-degenerate ones, whose terms cancel to one part in 1e6 (a 7R arm with
#: 0.5 mm joint offsets: coefficients 512000000 and -511999200), while an
#: equation whose real zeros are all critical (x**2 + y**2) stalls at 1e-8 to
#: 1e-6 (NEAR_MISS_RTOL); 1e-10 accepts the first and not the second.  Rank and
#: zero decisions on branches are exact where the branch has points modulo a
#: prime (rankloci.tree.modular), so these points decide only the rest.
ROOT_XTOL = 1e-10

#: Distance in sigma_min/sigma_max a configuration must keep from RANK_RTOL to
#: count as clearly regular in off-locus sampling.
REGULAR_MIN_RATIO = 1e-6

#: A float angle within this distance of a multiple of pi/12 is taken to be
#: that exact multiple when a model file is read.
ANGLE_SNAP_ATOL = 1e-12

#: A configuration handed back to the tree (a check's hint, where a component was
#: found regular) has each angle within this of a multiple of pi taken as that
#: multiple, so that its half-angle cosine or sine is exactly zero.  A single-term
#: condition such as cos(q3/2) is tested relative to the size of its terms, which
#: is its own value: at the float q3 = -pi, 6e-17, it would never vanish.  The
#: check refines its points onto the equations to ROOT_XTOL; a move of 1e-10 rad
#: leaves every rank decision (LEAF_REGULAR_RTOL) and zero test (ZERO_RTOL) as it
#: was.
HINT_ANGLE_SNAP_ATOL = ROOT_XTOL

#: URDF files write angles with 4-10 significant digits (pi/2 as 1.5708, off by
#: 3.7e-6), so an rpy angle within this of a multiple of pi/12, or a unit-axis
#: component within this of 0, +-1/2, +-sqrt(2)/2, +-sqrt(3)/2 or +-1, is taken
#: as that exact value when a URDF is read.
URDF_ANGLE_SNAP_ATOL = 1e-5

#: URDF exporters write float noise where a length is zero (icub's 4.33681e-19 m,
#: romeo_laas_small's float32 residue 7.45058e-09 m), and every such length adds
#: terms and 50-digit coefficients to every polynomial downstream.  A length
#: (origin xyz component) within this of 0, in metres, is taken as exactly 0 when a
#: URDF is read.  It is of the order of what URDF_ANGLE_SNAP_ATOL already moves a
#: point 0.1 m from its joint, and 500 times below the smallest offsets that real
#: descriptions carry on purpose (KUKA's 0.5 mm).
URDF_LENGTH_SNAP_ATOL = 1e-6

#: A URDF angle that is no multiple of pi/12 (a 40-degree rotation, a romeo arm's
#: axis 0.417025 0.895055 -0.15801) is read as an exact rational rotation: its
#: half-angle tangent, or the stereographic coordinates of its axis, become the
#: rational with the smallest denominator that moves the rotation by at most
#: this many radians.  Those rationals have about 5-digit denominators instead of
#: the 17 digits of a float's shortest decimal, and every coefficient downstream
#: is a product of them.  1e-9 rad is far below the precision of the files (4 to
#: 10 significant digits) and of URDF_ANGLE_SNAP_ATOL.
URDF_ROTATION_ATOL = 1e-9

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

# FSP solution space (rankloci.numeric.fsp_solution).  The listing's absolute
# thresholds (SV_SMALL, SMALL/10) carry the units of A; these are the same
# values for A, b and x of unit size, made relative so that a small motion b
# (one step of a trajectory) or a Jacobian in other units is treated alike.

#: Default ``tol`` of ``fsp_solution.solve``: a singular value at most this times
#: sigma_max of A counts as zero when the reducer looks for dependent rows (the
#: listing's SV_SMALL = 1e-4 and condition bound 1/SV_SMALL, relative to sigma_max).
FSP_SOLVE_RTOL = FSP_SV_SMALL

#: Blocking search: a component of a solution vector g counts as zero (that column
#: may not be blocked next) when |g_c| <= this * max|g|: the listing's SMALL/10 =
#: 1e-4 * max|A_ij| for a unit-size solution.
FSP_G_ZERO_RTOL = 1e-4

#: The reduced b is all zero (the completely restricted case, section 5.1) when
#: max|b_red| <= this * max(max|b|, max|A| * max|x_fixed|): back-substitution leaves
#: rounding of a few eps times those terms; 1e-12 leaves four orders of margin.
FSP_B_ZERO_RTOL = 1e-12

#: A dependent row's constraint sum (A_j g^i) t_i = b_j, minus its part along
#: sum t_i = 1, is redundant when its entries are at most this times the size of
#: the terms of A_j g^i (sum_l |A_jl g^i_l|).  For an exactly dependent row they
#: cancel to ~cond * eps (1e-13 for a condition number of 1e3); 1e-9 leaves margin.
#: Also the rank threshold (relative to sigma_max) of the directions of S: the
#: search keeps vectors at least FSP_G_ZERO_RTOL apart, far above it.
FSP_CONSTRAINT_RTOL = 1e-9

#: x solves A x = b when max_i |A_i x - b_i| is at most this times the size of the
#: terms, max_i sum_l |A_il x_l| + max_i |b_i| (normwise): rounding of a solve with
#: condition number up to 1e4 (the reducer's bound) stays near 1e-12; 1e-9 leaves margin.
FSP_RESIDUAL_RTOL = 1e-9

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

#: Below EXCLUSION_RTOL and above EXCLUSION_CERTIFY_RTOL times the size of its terms, an
#: excluded polynomial decides nothing by its value: a point near a component on which it
#: vanishes identically gives up to ~1e-8 (ROOT_XTOL times the gradient of near-degenerate
#: terms), while near-degenerate geometry can keep it at 1e-6 of its term size on a whole
#: component (romeo_laas_small's elbow, coefficients of 300 digits that nearly cancel).  Such
#: a point is accepted only when ball arithmetic proves an exact point of the branch next to
#: it with the polynomial nonzero (rankloci.tree.certify); the bound is only the rounding
#: of evaluating a polynomial of a few thousand terms in double precision (~1e-15 of the
#: term size each), below which no later numeric test could tell the value from 0.
EXCLUSION_CERTIFY_RTOL = 1e-12

#: A branch without sample points whose best Gauss-Newton residual (relative
#: to the size of the terms) is at most NEAR_MISS_RTOL probably has real
#: points where its last equation and that equation's gradient vanish
#: together: there Gauss-Newton converges only linearly (the residual of a
#: squared distance d**2 stalls near 1e-8 to 1e-6 while d is 1e-4 to 1e-3).
#: Such a branch is searched again with the gradient's equations added,
#: where convergence is quadratic.  A branch with no real point keeps a
#: residual of order 1e-2 and up.
NEAR_MISS_RTOL = 1e-4

#: Step (radians, or units of a polynomial variable) across a sample point of an equation
#: whose gradient looks critical, to see whether the equation changes sign there.  Sample
#: points are within ~1e-6 of a critical zero set (the linear convergence above) and within
#: ~1e-12 of a regular one, so 1e-4 steps beyond both while staying local: a regular zero
#: with a relative gradient of 1e-6 changes the value by ~1e-10 of the term size, far above
#: ZERO_RTOL, and a sum of squares stays positive on both sides.
SIGN_STEP = 1e-4

# ---------------------------------------------------------------------------
# Forming components from the leaves (rankloci.methods.finalize)
# ---------------------------------------------------------------------------

#: Central-difference step (in radians, or units of a polynomial variable) for
#: the gradient of a component's equations at its sample point.  The truncation
#: error is O(h**2) = 1e-12 and the rounding error O(eps / h) = 1e-10, both
#: small against the gradients' O(1) entries.
DIMENSION_STEP = 1e-6

#: The dimension of a component is the number of joint variables minus the
#: numeric rank of its equations' gradient (rows scaled to unit norm): singular
#: values at most DIMENSION_RTOL times the largest count as zero.  With the
#: difference error of DIMENSION_STEP (~1e-10), 1e-7 leaves three orders of
#: margin; independent equations of the built-in models give ratios of 1e-3 and up.
DIMENSION_RTOL = 1e-7

#: A probe point of one component lies on another when every equation of the
#: other, divided by the sum of the absolute values of its coefficients (parameters
#: substituted; a trigonometric monomial is at most 1), is at most CONTAINED_RTOL
#: there.  The points are sample points accurate to ROOT_XTOL relative to the
#: terms' size, rotated in free variables that the other's equations do not see, so
#: an on-component value stays below ~1e-12 of that scale (UR5 position task:
#: 1.2e-7 against coefficients summing to 3e8); points off it give 1e-3 and up.
CONTAINED_RTOL = 1e-9

#: At such a point an excluded expression counts as vanishing when it is at most
#: CONTAINED_EXCLUSION_RTOL times the sum of its coefficients' absolute values.
CONTAINED_EXCLUSION_RTOL = 1e-7

#: A point where an exclusion vanishes is in the closure of a component when
#: points of the component with the exclusion nonzero lie near it: starts
#: perturbed by NEAR_ADMITTED_STEP are projected back onto the equations, and
#: must land within NEAR_ADMITTED_RADIUS (both in radians) with every
#: exclusion above NEAR_ADMITTED_EXCLUSION_RTOL times its coefficient size (a
#: perturbation of 1e-3 moves a simple zero of an exclusion by about as much).
NEAR_ADMITTED_STEP = 1e-3
NEAR_ADMITTED_RADIUS = 0.05
NEAR_ADMITTED_EXCLUSION_RTOL = 1e-6
#: ... from this many random starts (a point in the closure has admitted points all round
#: it: any start of the few lands on one).
NEAR_ADMITTED_TRIES = 6

# ---------------------------------------------------------------------------
# Numeric cross-check of a locus (rankloci.numeric.crosscheck)
# ---------------------------------------------------------------------------

#: A point counts as on a component when every equation, divided by the sum of the absolute
#: values of its coefficients (a trig polynomial is then at most 1), is at most this.  Root
#: finding reaches ~1e-15 on a component's equations; 1e-11 leaves four orders of margin.
ON_COMPONENT_RESIDUAL = 1e-11

#: On-locus points must have sigma_min/sigma_max at most this: the package's RANK_RTOL, >= 3
#: orders above the ~1e-12 that points accurate to ON_COMPONENT_RESIDUAL give (sigma_min is
#: Lipschitz in q with a constant ~sigma_max).
ON_LOCUS_RTOL = RANK_RTOL

#: Off-locus configurations keep every component's largest scaled equation above this: 1e-2 is
#: ~0.01 rad from the component, where sigma_min/sigma_max is ~1e-2 * (a constant of order 1),
#: six orders above RANK_RTOL, so a full-rank J is expected there.
OFF_LOCUS_MIN_RESIDUAL = 1e-2

#: A completeness-probe minimum counts as singular when sigma_min/sigma_max <= this (RANK_RTOL).
PROBE_SINGULAR_RTOL = RANK_RTOL

#: Such a minimum is then followed by Newton steps on sigma_min/sigma_max
#: (rankloci.numeric.equations.descend_to_singular) and counts as a singular point only if
#: they drive the ratio to at most this.  At rank-deficient configurations of the built-in
#: arms (puma560, ur5, pa10, ssrms, mobile10, planar4r) the minimum is 4e-19 to 6e-17, the
#: rounding floor; a minimum that stalls far above it is a positive local minimum, a
#: configuration that is nearly but not exactly singular: a 7R arm with 0.5 mm joint offsets
#: has them at 9e-13 to 8e-10 (the one at 1.7e-10 is regular when evaluated with 40 digits).
PROBE_DESCENT_RTOL = 1e-13

#: A probe minimum where a variable that is not an angle is larger than this in magnitude ran
#: off to infinity: sigma_min/sigma_max can tend to 0 there without J ever losing rank (J =
#: [[1, x], [0, 1]], whose determinant is 1, has a ratio of about 1/x**2), so it is no singular
#: point.  The probe starts at normal(0, 1) values; lengths of the models in millimetres stay
#: below 1e4, so a real singular point near a start is far inside this bound.
PROBE_ESCAPE_ABS = 1e6

#: dJ/dq by the complex step (rankloci.numeric.equations.NumericMatrix) and by the symbolic
#: derivative agree to this, relative to the largest |dJ/dq_k| entry at the same q.  Both are
#: exact up to rounding (the complex step subtracts nothing); on the built-in arms they differ
#: by <= 6e-16, and 1e-12 leaves room for the cancellation among the ~100 terms of an entry.
DERIVATIVE_RTOL = 1e-12

#: A singular probe point is covered when some component's scaled equations are all at most this.
#: A minimiser stops within ~ratio/|grad ratio| (~1e-8 rad) of a smooth locus, ~1e-6 rad near
#: tangential intersections; scaled trig equations change by at most their degree (<= 8) per
#: radian, so 1e-6 accepts those while a missing component leaves residuals of 1e-2 or more.
COVER_RESIDUAL = 1e-6

#: A singular point farther than COVER_RESIDUAL from every component is still covered when
#: solving a component's equations from it (least squares) lands within this distance (in
#: radians or metres) at a singular point.  Where the singular set meets a surface through the
#: point tangentially, sigma_min/sigma_max grows only as c * d**2 with the distance d, so a
#: minimiser, whose ratio bottoms out at ~1e-15 (double-precision SVD), stalls at
#: d ~ sqrt(1e-15/c): 1e-6 for c ~ 1e-3 (seen on romeo_laas_small's head), 1e-4 for c down to
#: 1e-7.  A component missing from the locus would have to pass within 1e-4 of a found one at
#: a random singular minimum.  Used by the grading of benchmarks/corpus.py and the tests.
COVER_DISTANCE = 1e-4

#: The largest maximal minor relative to the product of row norms "vanishes" at or below this:
#: it is about (sigma_min/sigma_max) * sigma_max^n / prod(row norms); row norms within a factor
#: ~100 of sigma_max over the rows leave it within 1e2 of RANK_RTOL.
MINOR_RTOL = 1e2 * RANK_RTOL

# ---------------------------------------------------------------------------
# Minimum infinity-norm solutions and manipulability (rankloci.near)
# ---------------------------------------------------------------------------

#: Ha and Lee's (and Cadzow's) optimality test ||x_1||_inf <= y'u accepts x when
#: ||x_1||_inf <= (1 + INF_NORM_RTOL) y'u.  Both sides carry a relative rounding error
#: of about cond(A) * eps (the null-space solve of step 8); for the Jacobians of a
#: path, kept at sigma_min/sigma_max >= 1e-6 by the path's own stop, that is <= 1e-10,
#: and 1e-9 leaves an order of margin.  An x that passes is optimal to that accuracy:
#: y'u is a lower bound of every solution's norm (weak duality).
INF_NORM_RTOL = 1e-9

#: An entry of A_2'u (u normalised so that ||A_2'u||_1 = 1) counts as zero when its
#: absolute value is at most INF_NORM_ZERO_RTOL.  u comes from an SVD of A_1 and is
#: accurate to cond(A_1) * eps; exactly degenerate entries (a column of A_2 in the
#: span of A_1, as when the Haar condition fails) come out near 1e-16, genuine ones
#: are of order 1/n and up for the systems solved here.
INF_NORM_ZERO_RTOL = 1e-10

#: A x = y with A rank deficient (rank r < m, decided at RANK_RTOL) has a solution
#: when y lies in the range of A.  y counts as in the range when its part along the m - r
#: left singular vectors of the dropped singular values is at most INF_NORM_RANGE_RTOL
#: ||y||.  A y that is A x for some x carries there only rounding and the dropped
#: singular values themselves, at most RANK_RTOL relative to sigma_max; a task velocity
#: that the robot cannot produce (a generic y at a singular configuration) has a part of
#: order ||y|| there.  The same 1e-8 as RANK_RTOL: the rank decision and this one are made
#: at the same relative scale.
INF_NORM_RANGE_RTOL = RANK_RTOL

#: A manipulability polytope counts as flat when its half-width along the left
#: singular vector of sigma_min, over its half-width along that of sigma_max, is at
#: most FLAT_RTOL.  The half-width of the zonotope along a unit vector d is
#: ||J'd||_1, between ||J'd||_2 and sqrt(n) ||J'd||_2, so the ratio is at most
#: sqrt(n) sigma_min / sigma_max: on the locus (sigma_min/sigma_max <= RANK_RTOL)
#: at most 10 RANK_RTOL for up to 100 joints.
FLAT_RTOL = 10 * RANK_RTOL

#: ``rankloci ik``: the tool point of the start configuration must lie within
#: IK_START_RTOL * (1 + |x0|) of the path's first point.  Coordinates typed on a
#: command line carry 6 or more significant digits; a start solved by least squares
#: reaches ~1e-12.
IK_START_RTOL = 1e-6

#: Report branch trees: a leaf's branch condition counts as vanishing at a point of a
#: component when it is at most LEAF_MATCH_RTOL relative to the sum of the absolute
#: values of its terms there.  Points on a component are accurate to 1e-10 (ROOT_XTOL) or better;
#: conditions that do not hold stay of order 1e-3 and above at generic points.
LEAF_MATCH_RTOL = 1e-7

#: Report heat maps: a joint along which log10(sigma_min/sigma_max), floored at
#: REGULAR_MIN_RATIO, spreads by less than SENSITIVITY_MIN is one the ratio does not
#: depend on (a base rotation); joints it depends on spread by order 1 and more.
SENSITIVITY_MIN = 1e-3

#: A leaf is split as reducible (rankloci.tree.reducible) only at points where the whole
#: matrix has sigma_min/sigma_max above this, besides points where it is rank deficient.
#: Points of a branch whose equations are squared or critical (the gradient branches of
#: rankloci.tree.cover) are accurate only to ~sqrt(ROOT_XTOL) = 1e-5 in the joint variables,
#: so a singular piece shows ratios up to ~1e-6 there (7e-8 to 9e-7 on tiago's arm), while the
#: regular pieces of PR2's reducible leaves have ratios of 1e-2 to 1e-1 and coordinate pieces
#: are sampled exactly.
LEAF_REGULAR_RTOL = 1e-4

#: Digits of the extended-precision rank decisions at real points of a leaf
#: (rankloci.tree.precise).  Forty digits hold a point of a branch to PRECISE_RESIDUAL with
#: eight digits of headroom for cancellation in equations whose terms cancel to one part in
#: 1e6 (the offset arm's coefficients 512000000 and -511999200).
PRECISE_DPS = 40
#: Residual of a branch's conditions, relative to the size of their terms, at which the
#: extended-precision refinement of a point stops.
PRECISE_RESIDUAL = 1e-32
#: sigma_min / sigma_max at a point refined to PRECISE_RESIDUAL at or below which the matrix
#: is singular there.  Singular points show ratios near the residual (1e-32 and below);
#: regular points of nearly degenerate geometry show 1e-17 and more (the 7R arm with 0.5 mm
#: offsets, at its closest to singular, evaluated at 60 digits): seven orders of margin on
#: either side.
PRECISE_SINGULAR_RTOL = 1e-24
#: A leaf's sample point whose double-precision sigma_min/sigma_max (rows scaled) is at or
#: below this is singular without the extended-precision decision, which costs 20 to 80 ms a
#: point.  Measured: of talos' 7-joint arm's 206 leaf points sent to it, 189 had ratios below
#: 1e-15 and all 206 were singular in 40 digits; on the 0.5 mm offset arm, of 749, 386 lay
#: below 1e-15 and 384 of them were singular (the locus is the same without deciding them).
LEAF_PRECISE_FLOOR = 1e-15

#: A point solved onto a component whose double-precision sigma_min/sigma_max is above this
#: is decided again in extended precision by the numeric check (rankloci.numeric.crosscheck):
#: points of exactly singular components evaluate to 1e-15 and below in double precision
#: where the component's equations have a simple root, and nearly degenerate geometry makes
#: regular points look singular down to 1e-13 (the 7R arm with 0.5 mm offsets: on
#: 800 sin q4 + cos q4 = 0 alone the ratio is 1e-10 to 1e-13 at 60 digits, where a double
#: precision check with RANK_RTOL calls it singular).
PRECISE_CHECK_FLOOR = 1e-14
#: The two precisions (decimal digits) of that decision: the point is moved onto the
#: component's equations and J evaluated in each.  At a singular point the ratio falls with
#: the digits (to ~1e-40 and ~1e-90 at a simple root; by a factor (1e-50)**(1/k) at a
#: root of multiplicity k, 1e-6 for k = 8); at a regular point it stays, to the precision
#: of the point (~1e-40, far below PRECISE_STABLE_RTOL).
PRECISE_CHECK_DIGITS = (50, 100)
#: Singular: the ratio at the higher precision is at most this times the lower one's.
PRECISE_FALL = 1e-4
#: Regular: the two ratios agree to this, relative, and lie above PRECISE_CHECK_FLOOR (below
#: it a stable ratio can come from data rounded to double precision).  Anything else is left
#: undecided, and the double-precision verdict stands.
PRECISE_STABLE_RTOL = 1e-6
