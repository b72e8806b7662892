"""Every numeric tolerance rankloci uses, and every count and budget that decides a result.

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

Which a user may tune
---------------------
Only RANK_RTOL, and only where it decides a numeric check: ``rank_rtol=`` of
``rankloci.locus``, ``rankloci.check`` and ``rankloci.report`` (``--rank-rtol``
of ``rankloci locus``, ``check`` and ``report``) sets the threshold of the
self-check, of the cross-check (on the components: ON_LOCUS_RTOL; off the
locus; at the completeness probe's minima: PROBE_SINGULAR_RTOL) and is
recorded in their JSON.  The components themselves come from exact algebra and
the certificate uses no tolerance, so no option changes them.  And
LOCUS_CONTAINS_RTOL, the default of ``rtol=`` of ``Locus.contains`` and
``rankloci.is_singular``: how close a measured configuration must be to a
component to count as on it.  The other
values here are not options: each is tied to the precision of a computation
(double rounding, Newton's convergence, a prime's size) or to a budget whose
change would change which branches are found, not to a property of a user's
model.
"""

#: sigma_min / sigma_max at or below which a matrix counts as rank deficient.  The default of
#: the numeric checks' ``rank_rtol`` option (see above): a model whose data are rounded to a
#: few digits may need it raised, one nearly singular by design lowered.
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

#: A chain taken from another library (a Pinocchio model between two frames) has the Jacobian
#: that library computes for it, to this relative to its largest singular value: the chain's
#: transforms are the library's own floats composed once more (each product rounds at ~1e-16)
#: and its lengths are written to 15 significant digits (``adapters.transforms.length_text``),
#: so the two agree to ~1e-14; a wrong axis, sign or placement moves entries by the size of
#: the arm.
FOREIGN_JACOBIAN_RTOL = 1e-12

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

#: A matrix whose largest singular value at a point is at most this times its typical largest
#: singular value (the median over random configurations) vanishes there up to rounding, and
#: has rank 0: sigma_min/sigma_max of the rounding residue (sin(pi) = 1.2e-16 on a diagonal)
#: says nothing.  Rounding leaves entries ~1e-16 of their size; 1e-12 is four orders above
#: that, and at a regular point sigma_max is of the order of its typical value (a matrix that
#: nearly vanishes away from its locus would need coefficients 1e12 apart).
ZERO_MATRIX_RTOL = 1e-12

#: On-locus points must have sigma_min/sigma_max at most this: the package's RANK_RTOL, >= 3
#: orders above the ~1e-12 that points accurate to ON_COMPONENT_RESIDUAL give (sigma_min is
#: Lipschitz in q with a constant ~sigma_max).  ``rank_rtol`` of the checks replaces it.
ON_LOCUS_RTOL = RANK_RTOL

#: Off-locus configurations keep every component's largest scaled equation above this: 1e-2 is
#: ~0.01 rad from the component, where sigma_min/sigma_max is ~1e-2 * (a constant of order 1),
#: six orders above RANK_RTOL, so a full-rank J is expected there.
OFF_LOCUS_MIN_RESIDUAL = 1e-2

#: A completeness-probe minimum counts as singular when sigma_min/sigma_max <= this (RANK_RTOL;
#: ``rank_rtol`` of the checks replaces it).
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

#: The arm view of the HTML report moves the joints that follow its sliders on a component:
#: as many as the rank of the gradient of the component's equations, a column counting when
#: its pivot in a QR factorization with column pivoting is above this times the largest.
#: Gradients of the built-in components at their sample points have pivots within a factor
#: 1e3 of each other, or exactly zero (a variable that does not enter); 1e-8 (RANK_RTOL's
#: value) separates the two and leaves rounding in the gradient (~1e-16) far below.
FOLLOWER_RTOL = 1e-8

#: The arm view of the HTML report says a pose is on the locus, and its browser test requires,
#: that sigma_min/sigma_max of the Jacobian the page computes (double precision, from the
#: chain's numbers) is at most this.  The page's Gauss-Newton steps stop at an equation
#: residual of 1e-14 times the equations' scale, where sigma_min/sigma_max is ~1e-14 on a simple
#: component; the page's own Jacobi SVD and kinematics add ~1e-15 (measured on the built-in
#: models: 1e-19 to 1e-16).  It is RANK_RTOL, the tool's own rank decision, so that the page
#: calls on the locus exactly what the locus computation would; regular poses of the built-in
#: models have 1e-3 or more.
VIEW_ON_LOCUS_RTOL = RANK_RTOL

#: A factored determinant ``det J = kappa * f1**m1 * ...`` shown in a report is checked at
#: random configurations: the ratio det J / (f1**m1 ...) must be the same constant kappa at
#: each, to this relative difference.  numpy's LU determinant is accurate to about
#: cond(J) * n * eps relative to |det J|; random configurations of the built-in models keep
#: sigma_min/sigma_max above 1e-3 (cond below 1e3), so honest ratios agree to ~1e-12, while a
#: wrong exponent or a missing factor changes the ratio by order one between points.
DET_FACTOR_RTOL = 1e-8

#: Random configurations at which such a factorisation is fitted and checked: twelve ratios
#: that agree to DET_FACTOR_RTOL leave no room for a wrong exponent by chance.
DET_POINTS = 12

#: A wide or tall J with more maximal minors than this gets no gcd of its maximal minors in a
#: report (the report says so): a 6 x 8 J has 28, a 6 x 9 J 84.  It decides only whether the
#: gcd is shown, never a locus.
MAX_MINORS = 50

#: A maximal minor of more terms than this stops that gcd (the report says so): a term budget
#: bounds the time as a clock would, but gives the same output on every machine.
MINOR_MAX_TERMS = 20000

# --- proved points next to numeric ones (tree/certify.py) ----------------------------------------

#: Working precision of the ball arithmetic: coefficients of several hundred digits are exact
#: balls, and 256 bits leave ~70 digits after cancellations of one part in 1e6 and more.
PRECISION_BITS = 256

#: Newton steps in doubles from a start 1e-3 off the equations (admitted_near), to within
#: rounding of the zero.
FLOAT_NEWTON_STEPS = 8

#: ... and stops earlier once every equation is below this relative to the size of its terms:
#: rounding in doubles (a few terms' worth of 1.1e-16), far within ROOT_XTOL, and the
#: refinement in PRECISION_BITS takes over from there.
FLOAT_NEWTON_SETTLED = 1e-15

#: Then at most this many refinement steps in ``PRECISION_BITS``-bit arithmetic: the residual F
#: exact at the point, its Jacobian in doubles (mixed-precision refinement).  Each step gains
#: about 53 - log2(cond) bits, so from the double zero two or three steps reach NEWTON_SETTLED;
#: the rest is margin for ill-conditioned pivots.
NEWTON_STEPS = 6

#: The refinement stops once a step is below this relative to max(1, |pivot|): the Krawczyk
#: box (BOX_RTOL) is then 2**20 times the distance left to the zero.
NEWTON_SETTLED = 2.0 ** -120

#: Radius of the Krawczyk box, relative to max(1, |pivot|): far above the Newton residual
#: (NEWTON_SETTLED), far below any distance at which two zeros of a regular system could be told
#: apart in double precision.
BOX_RTOL = 2.0 ** -100

#: Krawczyk's test is not attempted when the double Jacobian at the zero found in doubles, or at
#: the refined zero, has a condition number (max-row-sum norms) above this: a zero on a piece of
#: the system of excess dimension, whose Jacobian is singular there.  The double condition number
#: saturates near 1e16 on a singular Jacobian; the test needs the double inverse to be a good
#: one, and J to vary little over the box.  Measured with the test run in ball arithmetic up to
#: 1e30: every passed test had a condition number below 1e12 (49 on panda's finger chain, 1295 on
#: tiago's arm), while 370 of panda's 442 failed ones were above 1e27 (most 1e72 to 1e84).
#: Skipping the test decides nothing: the point stays unproved, as a failed test leaves it.
FLOAT_SINGULAR_COND = 1e14

#: Pivot columns whose smallest singular value is below this times the largest are no chart
#: of the branch at the point (a point where components meet); the point stays undecided.
PIVOT_RTOL = 1e-12

#: Choices of pivots tried from one start by :func:`rankloci.tree.certify.admitted_near`.
PIVOT_CHOICES = 6

# --- batched SVD screens (numeric/svd.py) --------------------------------------------------------

#: Screening threshold on (sigma_min/sigma_max)**2 from the Gram matrix.  Its
#: eigenvalues carry an absolute error of a few eps * sigma_max**2, i.e. the
#: squared ratio is known to ~1e-15; above 1e-10 (ratio above 1e-5, three
#: orders over RANK_RTOL) the matrix is certainly of full rank.
GRAM_SCREEN = 1e-10

# --- the exact cross-check with Singular (exact/singular.py) -------------------------------------

#: The cross-check is attempted on at most this many terms of the minors sent to Singular, and
#: on at most SINGULAR_MAX_ANGLES angles (two ring variables each): primary decomposition grows
#: fast with more, and beyond them the check reports itself skipped.
SINGULAR_MAX_TERMS = 200
SINGULAR_MAX_ANGLES = 4
#: Seconds Singular gets before the check reports itself skipped (it decides nothing then).
SINGULAR_TIMEOUT_S = 30.0
#: Residual (relative to the coefficient size) below which an equation holds at a point.
SINGULAR_ON_SET_RTOL = 1e-7

# --- Gauss-Newton (numeric/gauss_newton.py) ------------------------------------------------------

#: Step lengths of the line search tried per residual call: 1, 1/2, 1/4, 1/8 of the step.
LINE_LEVELS = 4
#: A start stops once its residual norm is below this: rounding of well-scaled equations
#: (a few 1e-16 per term), far below ON_COMPONENT_RESIDUAL.
GN_RESIDUAL_FLOOR = 1e-14
#: ... or once its residual has not halved in this many steps: no convergence in sight (a
#: start that converges gains digits every step).
GN_STALL_STEPS = 8
#: ... or once its step is shortened below this fraction: the start is stuck.
GN_MIN_STEP = 1e-4
#: ... and after this many steps at most (Gauss-Newton converges in a handful near a zero).
GN_MAX_ITER = 60
#: Forward-difference step of the Jacobian: about sqrt(eps), which balances truncation and
#: rounding for well-scaled equations.
GN_DIFFERENCE_STEP = 1e-7
#: scipy's least_squares (trust region reflective) is run to rounding: its xtol, ftol and gtol
#: far below ON_COMPONENT_RESIDUAL, so that only max_nfev stops it short of a zero.
LEAST_SQUARES_TOL = 1e-15

# --- points on a component's equations (numeric/equations.py) ------------------------------------

#: Random starts per requested point (root finding, off-locus draws).
EQUATIONS_MAX_TRIES = 40

#: Iterations without halving its cost after which a root-finding start above the
#: acceptance threshold is given up (see :func:`points_on`).  Starts that reach the
#: component halved their cost at least every 48 iterations (160 starts: xarm7, panda,
#: centauro's arm, puma560, pa10, mobile10); the others sat at a positive minimum of the
#: cost (residual ~7e-4) until max_nfev, 1400 evaluations.
STALL_ITERATIONS = 200

#: The refinement stops once a step moves the double-precision point by at most this many units
#: in the last place of each coordinate, or of 1 for a coordinate below 1 in size (a joint value
#: is no finer than that).  A converged point keeps moving by the rounding of the working
#: precision, which changes the double value of a coordinate at 0: on romeo_laas_small's gripper
#: chain one point (q6 = 0) took all 200 steps (35 s), moving by 1e-48 after the third, while
#: the others stopped after 3 to 5.
SETTLED_ULPS = 4

#: Step of the complex-step derivative Im f(x + i h) / h.  Its error is h^2 |f'''| / 6 relative
#: to f' and nothing cancels, so any h far below sqrt(machine epsilon) gives f' to rounding;
#: 1e-30 keeps h^2 below every double's precision while h * f' stays far above the smallest
#: positive double.
COMPLEX_STEP = 1e-30

# --- the self-check of a locus (verify.py) -------------------------------------------------------

#: Sample points per component, off-locus points and probe starts of the self-check.  The
#: probe finds the components that are hit from random starts with high probability; a
#: component missed by the self-check but found by ``rankloci check --samples 50`` is
#: possible for small components (reported by that command).
SELF_CHECK_SAMPLES = 6

#: Rounds of slices computed from the witness points that lie on no component (each round's
#: certificate may fix other variables at the points still uncovered).
SLICE_ROUNDS = 3

#: Codimension from which the numeric check of a first computation starts in a worker beside
#: its certificate (``jobs`` above 1): where components of codimension 3 or more can occur
#: (n x m matrices with m - n >= 2), the certificate's eliminations of those codimensions are
#: beyond its budget but for small matrices, and it leaves the long chains undecided (snake9,
#: tiago's 9-joint chains), so the check is needed.  Below, the certificate decides, and a
#: worker started for a check that is not needed costs a second of CPU on a busy machine.
CHECK_AHEAD_CODIMENSION = 3

#: Rounds of recomputation with the configurations where the check found a component regular
#: (each adds the new ones): a split leaf's pieces are checked in the next round.
HINT_ROUNDS = 2

# --- the certificate's budgets (exact/witness.py) ------------------------------------------------

#: Codimensions whose witness points are computed (affine subspaces of that dimension): one
#: variable is eliminated per codimension above 1, and each elimination squares the degrees.
MAX_CODIMENSION = 4

#: The largest codimension decided on coordinate slices where a random subspace is beyond the
#: elimination budgets (exact/witness.py, ``_CoordinatePlane``).  On a chain's J the minors
#: have degree at most 4 per angle there: two eliminations from three variables reach degree
#: 2 * 32 * 32 = 2048, within the budgets; from four variables the last reaches about 8
#: million, beyond them, so codimension 4 is not tried.  Nor are slices used where a higher
#: codimension can occur (6 x 9 and wider): the verdict could not pass, and the 84 slices of
#: a 9R snake take about a minute.
MAX_SLICE_CODIMENSION = 3

#: The largest degree an elimination may reach (the square of the degree of the polynomials it
#: eliminates from); beyond it the codimension is left undecided.  A resultant of two
#: polynomials of degree 60 in few variables takes flint about a second.
MAX_ELIMINATION_DEGREE = 3600

#: ... and the most terms it may have (a resultant in two or more remaining variables): beyond,
#: one resultant takes minutes.
MAX_ELIMINATION_TERMS = 20000

#: Primes are drawn from [2**PRIME_BITS, 2**(PRIME_BITS + 1)): word-sized for flint's nmod
#: arithmetic, and large enough that the Schwartz-Zippel bound of a wrong verdict (degrees of a
#: few thousand) is below 1e-12.
PRIME_BITS = 61

#: Fresh random choices tried when one is degenerate (a projection that does not separate the
#: witness points, a denominator divisible by the prime): such a choice has a probability
#: below 1e-12, so two retries are plenty.
WITNESS_RETRIES = 3

#: A variable is taken as fixed on the missing components when the values it takes at their
#: witness points are the roots of one polynomial of at most this degree whose coefficients
#: are rationals of small height (MAX_HEIGHT): random values (a free variable) give such a
#: polynomial with probability below 1e-12.
MAX_FIXED_DEGREE = 6
MAX_HEIGHT = 2 ** 24

#: The height of an integer relation of degree 2 found by lattice reduction for a value in
#: GF(P) alone (its conjugate not among the witness points): random values have shortest
#: relations near P**(1/3), about 2**20.
MAX_RELATION_HEIGHT = 2 ** 14

# --- leaves that also hold on a regular piece: samples and budgets (tree/reducible.py) -----------

#: Points sampled on a leaf before it is recorded.  The sampler's first three points decide
#: the rank of a branch; a regular piece of a reducible leaf attracted 1 to 3 of 5 random solves
#: on PR2's arm chains, so twelve miss it with probability below 0.8**12 = 7e-2 each, and the
#: leaves found on those chains are all caught (PR2's finger chain in tests/io/test_corpus.py;
#: tests/tree/test_reducible.py has a matrix of its own).
LEAF_POINTS = 12

#: Starts with angles at multiples of pi/2 screened for exact points of a leaf (one batch
#: evaluation): a piece that fixes k angles at one of two values each is hit by about
#: SPECIAL_STARTS / 4**k of them, 8 for k = 4.
SPECIAL_STARTS = 2048

#: Of those exact points, at most this many have their rank tested.
SPECIAL_POINTS = 64

#: Regular blocks whose determinants are compared; the one with fewest terms splits the branch.
MINOR_CANDIDATES = 3

#: Groups of special starts at which some of a leaf's equations vanish exactly, and not all,
#: solved for the rest with their angles at multiples of pi/2 held (see special_solved_points),
#: and starts solved per group.
SPECIAL_SOLVES = 8
SPECIAL_SOLVE_ROWS = 2

#: Of the special starts at which some equations vanish, those whose held angles are sought.
SPECIAL_PARTIAL_ROWS = 64

#: Values of one unknown at which an equation is evaluated in search of sign changes.
SCAN_GRID = 256

#: Bisection steps of a line solve decided by one evaluation (of 2**BISECT_LEVELS - 1 points).
BISECT_LEVELS = 3

# --- exact rank decisions modulo a prime (tree/modular.py) ---------------------------------------

#: Random points per branch; the rank is the largest over them (a rank mod P can only drop,
#: and a branch cut by several equations can consist of pieces of different rank).
MODULAR_POINTS = 3

#: Branches with more implicit equations are left to the numeric probes.
MODULAR_MAX_IMPLICIT = 3

#: Failed attempts at one prime before the next, and primes tried before a branch is left to
#: the numeric probes: a random univariate polynomial mod P has a root with probability ~0.63,
#: a quadratic with a non-square discriminant has roots for half of the primes.
MODULAR_MISSES = 4
MODULAR_PRIMES = 8

# --- block choice (tree/blocks.py) ---------------------------------------------------------------

#: At most this many column sets are ranked by size when choosing a block.
MAX_COLUMN_SETS = 5000

#: Once a regular block's determinant has more terms than this, no further candidate is
#: formed: on 8-joint URDF chains (icub's arm with its torso) the root's candidates have 1.2 to
#: 4.3 million terms and take 29 to 84 s each, and the smallest is usually among the first
#: (the blocks are tried smallest entries first).
CANDIDATE_MAX_TERMS = 200_000

#: Blocks of the null-vector level are searched only when there are at most this many.
MAX_BLOCKS = 400

# --- lost directions (methods/finalize.py) -------------------------------------------------------

#: A lost direction is given as expressions only when its entries hold at most this many terms
#: together (after their common factor divides out): longer ones are too long to read.
MAX_DIRECTION_TERMS = 400

#: The cofactors a symbolic direction is built from are abandoned beyond this many terms.  Their
#: common factor divides out (:func:`~rankloci.algebra.primitive_vector`; PUMA 560's shoulder:
#: 4312 terms -> 169), so this is far above MAX_DIRECTION_TERMS: on the built-in models the
#: largest is 58208 (SSRMS, 1366 after the division); URDF chains with rotations that do not
#: snap reach 200000-280000 terms (centauro's arm, 2-4 s each) and never come under
#: MAX_DIRECTION_TERMS.
MAX_DIRECTION_COFACTOR_TERMS = 60_000

#: A direction is abandoned, before any cofactor, where the whole matrix with the branch's
#: substitutions applied holds more terms than this.  The matrices whose directions came out
#: small enough to show held at most 7740 terms (9R snake; 1192 on talos' arm, 990 on
#: centauro's, 344 on the built-in models); on the snake, substituting one leaf's matrix
#: (1173201 terms) and then its cofactors took 35 s of the locus's 100 s, for a direction
#: abandoned anyway.
MAX_DIRECTION_MATRIX_TERMS = 50_000

# --- branches (tree/branch.py) -------------------------------------------------------------------

#: A condition a*C + b*S whose a and b have more terms than this together stays an implicit
#: equation instead of becoming the substitution (C, S) ~ (b, -a).  Substituting multiplies an
#: entry of degree d in the pair by about (terms of a and b)**d: on panda's finger chain a
#: 39 + 51 term pair gave entries of about 1100 terms and one 5 x 5 minor of 443072 terms (23 s
#: of the chain's 94 s); with that condition implicit the chain takes 49 s.  alex's arms (pairs
#: of 110 and 201 terms) went from over 300 s to 45-53 s.  The pairs on tiago's, PR2's and
#: human's 8-9 joint chains have at most 30 terms.
PAIR_MAX_TERMS = 60

# --- rank decisions in 40 digits (tree/precise.py) -----------------------------------------------

#: Terms of a branch's conditions above which its points are not refined: each Gauss-Newton
#: step evaluates the conditions and their gradients exactly, and leaves of 8- and 9-joint
#: chains have conditions of thousands of terms.
PRECISE_MAX_TERMS = 2000

#: Gauss-Newton steps before a refinement that has not converged is given up.
PRECISE_STEPS = 30

# --- points of a branch (tree/sampler.py) --------------------------------------------------------

#: Rows of one batch whose tiny exclusion is put to the proof of .certify: a branch needs a
#: few points, and a row in an excluded set costs a failed proof.
CERTIFY_ROWS = 4

# --- determinants (algebra/polys.py) -------------------------------------------------------------

#: With a term budget (``max_terms``), :func:`laplace_det` stops before a product of an entry
#: and a minor whose term counts multiply to more than this many times the budget.  Such a
#: product is formed in full before any reduction (one of a 4 x 4 minor on a 9R snake: 25258
#: terms times 174532, a 6.4 GB allocation that aborted the process), and a determinant built
#: from it is, unless nearly all of it cancels, far over the budget.
PRODUCT_BUDGET_FACTOR = 100

# --- joint limits (limits.py) --------------------------------------------------------------------

#: Random starts of the bounded least-squares search per component.  The search stops at
#: the first point it accepts; a component that meets the box in a set of positive measure
#: on its own dimension is reached from a uniform start with a probability that grows with
#: that set, and 64 starts reach every component of the built-in models that meets their box.
LIMIT_SEARCH_STARTS = 64

#: Digits in which exact solved values are compared with the limits.
EXACT_DIGITS = 30

# --- exact values of a URDF file's floats (io/urdf_exact.py) -------------------------------------

#: Digits a rational entry of a composed transform may have before its rotation is replaced by
#: the nearest short exact rotation (:func:`rankloci.io.urdf_exact.bounded`).  One rpy rotation of a float angle has
#: entries of about 34 digits; a chain of them would multiply the digits without bound.
MAX_TRANSFORM_DIGITS = 40

#: Denominators searched at once by the common-denominator search of
#: :mod:`rankloci.io.urdf_exact` (one numpy block), and the largest searched (about a second)
#: before each number gets its own short rational.
URDF_DENOMINATOR_BLOCK = 1 << 20
URDF_DENOMINATOR_MAX = 1 << 26

# --- minimum infinity-norm solutions (near/min_inf_norm.py) --------------------------------------

#: Where A_2'u has k zero entries (a degenerate dual solution), Ha and Lee choose
#: sgn(0) at random; here the 2**k choices are tried in a fixed order, for k up to
#: this (beyond it only the first, the signs of x2).
MAX_SIGN_CHOICES = 4

# --- the nearest component (near/nearest.py) -----------------------------------------------------

#: Longest step (joint-space norm, radians) of the projection onto a component.  A full
#: Gauss-Newton step from far away can jump past the nearest zero of a trigonometric
#: equation to another; short steps follow the descent of the residual to the nearest.
MAX_PROJECTION_STEP = 0.1

# --- real points of complex components (exact/real_points.py) ----------------------------------

#: The largest matrix (its smaller side) whose maximal minors are expanded symbolically to
#: find hypersurface components whose real points are of lower dimension, and the most
#: minors: beyond, the expansion costs more than the rest of the certificate, and such
#: components are left to the certificate's verdict.
REAL_POINTS_MAX_SIDE = 3
REAL_POINTS_MAX_MINORS = 20
#: The most terms the matrix's entries may have in total, and the most monomials in half the
#: Newton polytope of a factor (the size of its Gram matrix).
REAL_POINTS_MAX_ENTRY_TERMS = 120
REAL_POINTS_MAX_GRAM = 40

# --- the geometry of a pose (geometry.py) --------------------------------------------------------

#: Two unit axis directions count as parallel, and distances as zero relative to the size of
#: the arm, below this.  Points on a component are accurate to 1e-10 (ROOT_XTOL); random
#: configurations keep these quantities of order 1e-2 and above, so 1e-7 separates them
#: with five orders of margin on either side.
GEOMETRY_RTOL = 1e-7

#: Random configurations whose geometric facts are facts of the design (they are never the
#: reading of a component): a fact that holds at five random configurations holds at all of
#: them but on a set of probability zero.
RANDOM_POINTS = 5

# --- slices and paths of sigma_min/sigma_max (numeric/landscape.py) ------------------------------

#: Grid points per axis of a slice: 181 puts a node every 2 degrees on [-pi, pi].
SLICE_GRID = 181

#: Points along a path through a component.
PATH_POINTS = 401

#: A local minimum of sigma_min/sigma_max along a path is refined (and kept if it reaches
#: ON_LOCUS_RTOL) only when it is at most this: a grid point next to a crossing lies within
#: one step (1/200 of the path) of it, where the ratio is of order 1e-3, while the minima of
#: near misses of a regular path stay of order 0.1 and above.
ZERO_CANDIDATE_RATIO = 0.05

#: How far (rad or m) a joint the equations use is moved to probe the ratio off the locus.
PROBE_STEP = 0.5

#: Joint-space length of half a path through a component, and the share of it across the
#: component (along its normal space): about 1 rad of travel across, either side.
PATH_LENGTH = 1.2
PATH_NORMAL_SHARE = 0.8

# --- the reading of a lost direction (directions.py) -------------------------------------------

#: ``|u^T J| <= DIRECTION_RTOL * sigma_max(J)`` verifies a lost direction at the sample
#: point: rank decisions use RANK_RTOL = 1e-8 on sigma_min/sigma_max, and the direction is
#: printed to 3 decimals, so 1e-6 is checked on the unrounded vector.
DIRECTION_RTOL = 1e-6

#: A part of a unit lost direction (its linear, angular or constraint rows) shorter than this
#: counts as zero: directions are read to 3 decimals.
DIRECTION_PART_MIN = 1e-3

# --- directions across a component (near/across.py) ----------------------------------------------

#: A singular value of the angular rows of J above this times the largest counts in their
#: rank: those rows are exact trigonometric entries, whose null directions show singular
#: values at rounding level (1e-16), far below 1e-9.
ORIENTATION_NULL_RTOL = 1e-9

#: A direction across a component is bent to keep the orientation only when at least this
#: share of it is left: a shorter remainder points mostly along the component.
ACROSS_KEEP_SHARE = 0.1

# --- a robot near its locus (api/near_study.py) --------------------------------------------------

#: Joint-space distance (rad, or m along a prismatic joint) from a component's sample point to
#: the pose "near" it: close enough that sigma_min/sigma_max is of order 1e-2, far enough
#: that the ellipsoid is still drawn.
NEAR_OFFSET = 0.05
#: Joint-space distance (rad, or m along a prismatic joint) from a component's sample point to
#: the start of the path: the rates there are those of a regular pose.
PATH_OFFSET = 0.4
#: Poses near at most this many components (the first ones).
MAX_NEAR_COMPONENTS = 4
#: Arms with more joints get the polytope of the position rows only (2^n vertices).
FULL_POLYTOPE_JOINTS = 7
#: A rate peak counts as the path's crossing when it lies within this much of the path
#: parameter (0..1) from the point closest to the locus.
PEAK_WINDOW = 0.05
#: A peak counts when the largest rate is at least this many times the rate at the start.
PEAK_RATIO = 3.0
#: Steps of the path through a component.
PATH_STEPS = 120

# --- the reading of a component (geometry.py, api/geometry.py) ---------------------------------

#: Extra points per component on which geometric readings are confirmed, and points sampled
#: on each factor's hypersurface: a fact of the axes that holds at four points of a component
#: (its sample and three solved onto it at random) and at no random configuration holds on
#: all of it but on a set of probability zero.
READING_POINTS = 3
FACTOR_POINTS = 3
