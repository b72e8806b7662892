"""Certified points of branches: an exact point near a numeric one, with every exclusion nonzero.

A branch that excludes the zero set of a polynomial ``p`` can lie on a
component where ``p`` is nonzero but tiny against the size of its terms
(romeo_laas_small's elbow: 3e-7 to 1.2e-6, coefficients of 300 digits that
nearly cancel), next to another component of the same equations on which
``p`` vanishes identically.  A sample point near the first is a point of the
branch, one near the second is not; the double precision value of ``p`` at a
point that is accurate to ``ROOT_XTOL`` does not tell them apart.

Interval arithmetic does.  The generators that no substitution solves are
split, at the numeric point, into one pivot per implicit equation (the
columns of the equations' Jacobian best conditioned together; of an angle
pair the component of smaller magnitude, the other one staying fixed, which
is a chart of the pair since every polynomial is homogeneous in it) and the
rest, fixed at their double values (exact binary rationals).  The square
system in the pivots is refined by Newton's method in ``PRECISION_BITS``-bit
ball arithmetic (python-flint's ``arb``), and Krawczyk's test on a small box
around the result proves that the box holds exactly one exact zero.  When no
excluded polynomial's enclosure over that box contains 0, that exact zero is
a real point of the branch: ``p`` is nonzero there by proof, not by a
threshold.  A box where an enclosure contains 0 (a component on which ``p``
vanishes), a singular Jacobian (a point where components meet, a squared
equation) or a failed Krawczyk test leave the point undecided, and the
caller rejects it as before.
"""

from __future__ import annotations

import itertools

import flint
import numpy as np

from ..algebra import PolyRing
from ..tolerances import (BOX_RTOL, EXCLUSION_CERTIFY_RTOL, EXCLUSION_RTOL, FLOAT_NEWTON_SETTLED,
                          FLOAT_NEWTON_STEPS, FLOAT_SINGULAR_COND, NEWTON_SETTLED, NEWTON_STEPS,
                          PIVOT_CHOICES, PIVOT_RTOL, PRECISION_BITS, ROOT_XTOL)
from .branch import Branch

__all__ = ["certified_point", "admitted_near", "at_dyadic"]


def certified_point(ring: PolyRing, branch: Branch, g: np.ndarray, movable,
                    pivots=None, cache: dict | None = None, *,
                    numeric_above: float | None = None, accept=None) -> np.ndarray | None:
    """``g`` moved onto a proved point of ``branch`` at which every exclusion is nonzero.

    Parameters
    ----------
    ring : PolyRing
    branch : Branch
    g : numpy.ndarray
        Generator values of a numeric point of ``branch`` (its equations small).
    movable : iterable of int
        Generators that may move (those the sampler solved for); the others
        stay at their values in ``g``.
    pivots : sequence of int, optional
        The generators to solve for, one per implicit equation (default: the
        best conditioned ones at ``g``).
    cache : dict, optional
        Numeric evaluators compiled for ``branch``, kept between calls on the
        same branch.
    numeric_above : float, optional
        Where every exclusion at the point solved in doubles is above this
        times the size of its terms, that point is returned without a proof
        (the standard a branch's samples are held to, EXCLUSION_RTOL).
    accept : callable, optional
        A test of the point solved in doubles (generator values -> bool); where it
        fails, nothing is proved and None is returned.  The proved zero lies within
        ``BOX_RTOL`` of that point, so a test of where it lies is decided before the
        proof, which costs far more.

    Returns
    -------
    numpy.ndarray or None
        The generator vector with the pivots at the double values of the
        proved zero (the substituted generators are left as in ``g``: the
        caller recomputes them), or None when nothing was proved.
    """
    solved = _substituted(ring, branch)
    cache = {} if cache is None else cache
    eqs, excl = _system(ring, branch, cache)
    if any(p.is_zero() for p in excl):
        return None
    if any(ring.variable_indices(q) & solved for q in eqs + excl):
        return None
    cand = _coordinates(ring, g, set(movable) - solved)
    if len(eqs) > len(cand):
        return None
    if pivots is not None:
        cols = list(pivots) if len(pivots) == len(eqs) and set(pivots) <= set(cand) else None
    else:
        cols = _pivots(ring, eqs, cand, g, cache) if eqs else []
    if cols is None:
        return None
    g = _float_newton(ring, eqs, cols, g, cache) if eqs else np.asarray(g, dtype=float)
    if g is None or (accept is not None and not accept(g)) or \
            not _worth_proving(ring, excl, g, cache):
        return None
    if numeric_above is not None and _worth_proving(ring, excl, g, cache, numeric_above):
        return np.asarray(g, dtype=float)
    if eqs and _float_condition(ring, eqs, cols, g, cache) > FLOAT_SINGULAR_COND:
        return None
    with flint.ctx.workprec(PRECISION_BITS):
        vals = [flint.arb(float(x)) for x in g]
        for j, prime in enumerate(ring.surds):
            vals[ring.surd_start + j] = flint.arb(prime).sqrt()
        if eqs:
            jac = _jacobian(ring, eqs, cols, cache)
            box = _krawczyk(eqs, cols, vals, cache.setdefault("balls", {}), jac)
            if box is None:
                return None
        else:
            box = vals
        if any(_value(p, box, cache.setdefault("balls", {})).contains(0) for p in excl):
            return None
        out = np.array(g, dtype=float)
        for j in cols:
            out[j] = float(box[j].mid())
        return out


def _system(ring: PolyRing, branch: Branch, cache: dict):
    """The branch's implicit equations and exclusions, reduced by its substitutions.

    Kept in ``cache`` for the calls that share it: the ball arithmetic's memo holds
    conversions of these very polynomials (by identity), and reducing a leaf's equations
    of thousands of terms costs milliseconds a call.
    """
    if "system" not in cache:
        cache["system"] = (
            [q for q in (branch.reduce(e, ring) for e in branch.implicit) if not q.is_zero()],
            [branch.reduce(p, ring) for p in branch.nonzero])
    return cache["system"]


def _compiled(ring: PolyRing, cache: dict, key, polys, *, sized: bool = False):
    """``ring.compile(polys(), sized=sized)`` under ``key`` in ``cache``."""
    if key not in cache:
        cache[key] = ring.compile(polys(), sized=sized)
    return cache[key]


def _jacobian(ring: PolyRing, eqs, cols, cache: dict):
    """Evaluator of the derivatives of ``eqs`` (the branch's, of ``cache``) in ``cols``: generator
    values -> the k x len(cols) matrix, row by row.

    The derivatives in every generator the equations use are compiled once per branch, as
    one evaluator, and every choice of columns reads its own from it: the candidates (of an
    angle pair, the component of smaller magnitude at the point) change from point to
    point, and one evaluation of all of them costs less than one per column (on tiago's
    9-joint thumb chain the closure proofs evaluate it some 10^5 times).
    """
    if "dJ" not in cache:
        used = sorted(set().union(*(ring.variable_indices(q) for q in eqs)))
        f = ring.compile([q.derivative(j) for j in used for q in eqs])
        cache["dJ"] = (f, {j: i for i, j in enumerate(used)}, len(used))
    f, where, width = cache["dJ"]
    k = len(eqs)
    # a generator no equation uses has a column of zeros: the row ``width`` appended below
    pick = [where.get(j, width) for j in cols]

    def evaluate(x):
        rows = np.concatenate([np.asarray(f(x), dtype=float), np.zeros(k)]).reshape(width + 1, k)
        return rows[pick].T.ravel()

    return evaluate


def _float_newton(ring: PolyRing, eqs, cols, g, cache: dict) -> np.ndarray | None:
    """``g`` with the pivots ``cols`` moved onto the equations by Newton's method in doubles.

    The ball arithmetic then starts within rounding of the zero; None when
    Newton does not settle (no zero next to ``g`` along these pivots).
    """
    k = len(eqs)
    J = _jacobian(ring, eqs, cols, cache)
    sized = _compiled(ring, cache, "F sized", lambda: eqs, sized=True)
    x = np.array(g, dtype=float)
    # a Newton iteration that runs away overflows on its way to inf: that is its failure,
    # caught below, not a warning for the user
    with np.errstate(over="ignore", invalid="ignore"):
        for _ in range(FLOAT_NEWTON_STEPS):
            values, size = sized(x)
            if np.all(np.abs(values) <= FLOAT_NEWTON_SETTLED * size):
                return x
            try:
                step = np.linalg.solve(J(x).reshape(k, k), values)
            except np.linalg.LinAlgError:
                return None
            x[cols] -= step
            if not np.all(np.isfinite(x)):
                return None
        values, size = sized(x)
    resid = np.abs(values) / np.maximum(size, 1e-300)
    return x if np.all(resid <= ROOT_XTOL) else None


def _float_condition(ring: PolyRing, eqs, cols, g, cache: dict) -> float:
    """Condition number (max-row-sum norms) of the equations' Jacobian in ``cols`` at ``g``."""
    k = len(eqs)
    J = _jacobian(ring, eqs, cols, cache)
    A = J(np.asarray(g, dtype=float)).reshape(k, k)
    with np.errstate(all="ignore"):
        try:
            c = np.linalg.cond(A, np.inf)
        except np.linalg.LinAlgError:
            return np.inf
    return float(c) if np.isfinite(c) else np.inf


def _worth_proving(ring: PolyRing, excl, g, cache: dict, rtol: float = EXCLUSION_CERTIFY_RTOL) -> bool:
    """Are the exclusions above rounding (``rtol`` of their terms) at ``g``?

    Where one is not, no later numeric test could tell it from 0, and on a
    component on which it vanishes identically it is always there: the
    proof is not attempted.
    """
    if not excl:
        return True
    vals, sizes = _compiled(ring, cache, "excl sized", lambda: excl, sized=True)(g)
    return bool(np.all(np.abs(vals) > rtol * sizes))


def _substituted(ring: PolyRing, branch: Branch) -> set[int]:
    """Generators that a substitution of ``branch`` expresses in the others."""
    out = set()
    for s in branch.substitutions:
        out |= {s.index} if s.kind == "linear" else {2 * s.index, 2 * s.index + 1}
    return out


def _coordinates(ring: PolyRing, g, movable: set[int]) -> list[int]:
    """Generators that can serve as local coordinates: one of each movable angle pair."""
    out = []
    for i in range(ring.n_angles):
        c, s = 2 * i, 2 * i + 1
        if c in movable and s in movable:
            out.append(c if abs(g[c]) <= abs(g[s]) else s)
    out += sorted(j for j in movable if 2 * ring.n_angles <= j < ring.surd_start)
    return out


def _pivots(ring: PolyRing, eqs, cand, g, cache: dict) -> list[int] | None:
    """One generator per equation, where the equations' Jacobian is best conditioned."""
    choices = _regular_choices(ring, eqs, cand, g, cache)
    return choices[0] if choices else None


def _regular_choices(ring: PolyRing, eqs, cand, g, cache: dict) -> list:
    """Pivot sets (one generator per equation) with a regular Jacobian at ``g``, best first."""
    J = _jacobian(ring, eqs, cand, cache)
    J = J(np.asarray(g, dtype=float)).reshape(len(eqs), len(cand))
    norms = np.linalg.norm(J, axis=1)
    if not np.all(np.isfinite(J)) or not np.all(norms > 0):
        return []
    J = J / norms[:, None]
    scored = []
    for combo in itertools.combinations(range(len(cand)), len(eqs)):
        s = np.linalg.svd(J[:, list(combo)], compute_uv=False)
        if s[-1] > PIVOT_RTOL * s[0]:
            scored.append((-s[-1] / s[0], [cand[k] for k in combo]))
    return [cols for _, cols in sorted(scored, key=lambda t: t[0])]


def _exact(x) -> "flint.fmpq":
    """The exact rational value of an arb's midpoint, or of an arf/mag given as an arb."""
    man, exp = x.mid().man_exp()
    return flint.fmpq(man) * 2 ** exp if exp >= 0 else flint.fmpq(man, 2 ** (-exp))


def _value(p, vals, memo: dict | None = None):
    """Ball enclosure of the polynomial ``p`` at the balls ``vals``.

    ``p`` is evaluated exactly (in C) at the rational midpoints; where a ball
    has a radius r_j the mean value theorem bounds the rest:
    ``|p(x) - p(m)| <= sum_j r_j * |d_j p|(|m| + r)``, ``|d_j p|`` the
    derivative with every coefficient made positive, an upper bound of the
    derivative's size over the box.  The bound is exact rational arithmetic
    too, so the enclosure is rigorous.  ``memo`` keeps those derivatives.
    """
    mids = [_exact(v) for v in vals]
    center = flint.arb(at_dyadic(p, mids, memo))
    moved = [j for j, v in enumerate(vals) if not v.rad().is_zero()]
    if not moved:
        return center
    degs = p.degrees()
    upper = None
    err = flint.fmpq(0)
    for j in moved:
        if degs[j] == 0:
            continue
        key = (id(p), j)
        d = memo.get(key) if memo is not None else None
        if d is None:
            dp = p.derivative(j)
            d = p.context().from_dict({m: abs(c) for m, c in zip(dp.monoms(), dp.coeffs())})
            if memo is not None:
                memo[key] = (d, p)      # p kept alive, so that id(p) stays its own
        else:
            d = d[0]
        if upper is None:
            upper = [abs(m) + _exact(v.rad()) for m, v in zip(mids, vals)]
        err += _exact(vals[j].rad()) * at_dyadic(d, upper, memo)
    return center + flint.arb(0, flint.arb(err)) if err else center


def at_dyadic(p, xs, memo: dict | None = None) -> "flint.fmpq":
    """``p(*xs)`` exactly, for rationals ``xs`` whose denominators are powers of two.

    With ``xs = a / 2**e`` (integers ``a``) and ``p = P / den`` (``P`` with integer
    coefficients, total degree ``D``), ``p(xs) = P_h(a, 2**e) / (den * 2**(e D))``, where
    ``P_h`` is ``P`` homogenised by one more variable: an evaluation in integers, about four
    times faster than one in rationals (which reduces a fraction at every step).  ``memo``
    keeps ``P_h`` for the polynomial (converting costs about one evaluation).
    """
    if p.is_constant():
        return p(*xs) if xs else flint.fmpq(p.leading_coefficient())
    key = ("homogenised", id(p))
    got = memo.get(key) if memo is not None else None
    if got is None:
        ctx = p.context()
        D = p.total_degree()
        coeffs = p.coeffs()
        den = flint.fmpz(1)
        for c in coeffs:
            if c.q != 1:
                den = den * c.q // den.gcd(c.q)
        hctx = flint.fmpz_mpoly_ctx.get(ctx.names() + ("homogenising",), "degrevlex")
        P = hctx.from_dict({m + (D - sum(m),): (c * den).p for m, c in zip(p.monoms(), coeffs)})
        got = (P, den, D, p)        # p kept alive, so that id(p) stays its own
        if memo is not None:
            memo[key] = got
    P, den, D, _ = got
    scale = flint.fmpz(2) ** max(int(x.q.bit_length()) - 1 for x in xs)
    scaled = [x * scale for x in xs]
    if any(y.q != 1 for y in scaled):       # a denominator that is no power of two
        return p(*xs)
    return flint.fmpq(P(*(y.p for y in scaled), scale), den * scale ** D)


def _krawczyk(eqs, cols, vals, memo: dict, jac) -> list | None:
    """``vals`` with the pivots ``cols`` on a box holding a unique zero of ``eqs``; else None.

    The point is refined by Newton steps whose residual is exact and whose
    Jacobian is the double one (``jac``: generator values -> the k x k
    derivatives in ``cols``, row by row).  Krawczyk's operator
    ``K = (I - Y J(box)) delta - Y F(x)`` encloses the zeros in the box for
    any matrix ``Y``; an approximate inverse of J, here the double one, only
    makes it contract.  So only F at the point and J over the box are
    enclosed rigorously.  ``memo`` keeps derived polynomials between calls on
    the same ``eqs`` (see :func:`_value`).
    """
    k = len(eqs)
    key = ("gradients", tuple(id(q) for q in eqs), tuple(cols))
    if key not in memo:
        memo[key] = ([[q.derivative(j) for j in cols] for q in eqs], eqs)
    grads = memo[key][0]
    vals = list(vals)

    with np.errstate(all="ignore"):
        for _ in range(NEWTON_STEPS):
            F = flint.arb_mat(k, 1, [_value(q, vals, memo) for q in eqs])
            A = np.asarray(jac(np.array([float(v.mid()) for v in vals])), dtype=float)
            A = A.reshape(k, k)
            residual = np.array([float(F[i, 0].mid()) for i in range(k)])
            try:
                step = np.linalg.solve(A, residual)
            except np.linalg.LinAlgError:
                return None
            if not np.all(np.isfinite(step)):
                return None
            scale = [max(1.0, abs(float(vals[j].mid()))) for j in cols]
            if all(abs(step[i]) <= NEWTON_SETTLED * scale[i] for i in range(k)):
                break
            for i, j in enumerate(cols):
                vals[j] = (vals[j] - flint.arb(float(step[i]))).mid()
        else:
            return None
        try:
            inverse = np.linalg.inv(A)
        except np.linalg.LinAlgError:
            return None
        if not np.all(np.isfinite(inverse)) or \
                np.linalg.norm(inverse, np.inf) * np.linalg.norm(A, np.inf) > FLOAT_SINGULAR_COND:
            return None     # the box's derivative bounds, the costliest part, are not computed
    Y = flint.arb_mat(k, k, [float(x) for x in inverse.ravel()])
    radii = [BOX_RTOL * max(1.0, abs(float(vals[j]))) for j in cols]
    box = list(vals)
    for i, j in enumerate(cols):
        box[j] = flint.arb(vals[j].mid(), radii[i])
    Jbox = flint.arb_mat(k, k, [_value(d, box, memo) for row in grads for d in row])
    delta = flint.arb_mat(k, 1, [box[j] - vals[j] for j in cols])
    eye = flint.arb_mat(k, k, [1 if a == b else 0 for a in range(k) for b in range(k)])
    K = (eye - Y * Jbox) * delta - Y * F
    if not all((K[i, 0]).abs_upper() < radii[i] for i in range(k)):
        return None
    return box


def admitted_near(ring: PolyRing, branch: Branch, g: np.ndarray, movable, rng, *,
                  step: float, radius: float, tries: int = 4, cache: dict | None = None) -> bool:
    """Is there a proved point of ``branch``, every exclusion nonzero, within ``radius`` of ``g``?

    ``g`` is a point of the branch's equations at which an exclusion
    vanishes.  It lies in the closure of the branch when it lies on a
    component of the equations on which no exclusion vanishes identically:
    then points next to it on that component keep every exclusion nonzero,
    and :func:`certified_point`, started from ``g`` moved by ``step`` in the
    movable angles and variables, proves one, or finds one in doubles whose
    exclusions are all above EXCLUSION_RTOL of their terms (the standard a
    branch's samples are held to; no proof is needed there).  On a component
    where an exclusion vanishes identically no start is ever proved.
    """
    movable = list(movable)
    angles = [i for i in range(ring.n_angles) if 2 * i in movable and 2 * i + 1 in movable]
    rest = [j for j in movable if j >= 2 * ring.n_angles]
    theta = 2 * np.arctan2(g[[2 * i + 1 for i in angles]], g[[2 * i for i in angles]])
    # evaluators and ball-arithmetic conversions of the branch's polynomials, kept by the
    # caller between calls on the same branch (they do not depend on g)
    cache = {} if cache is None else cache

    def near(x):
        back = 2 * np.arctan2(x[[2 * i + 1 for i in angles]], x[[2 * i for i in angles]])
        moved = np.abs((back - theta + np.pi) % (2 * np.pi) - np.pi)
        return bool(np.all(moved <= radius) and np.all(np.abs(x[rest] - g[rest]) <= radius))

    for _ in range(tries):
        start = np.array(g, dtype=float)
        t = theta + step * rng.standard_normal(len(angles))
        start[[2 * i for i in angles]] = np.cos(t / 2)
        start[[2 * i + 1 for i in angles]] = np.sin(t / 2)
        start[rest] = start[rest] + step * rng.standard_normal(len(rest))
        for cols in _pivot_choices(ring, branch, start, movable, cache):
            # a zero farther than ``radius`` is no proof of this closure: its distance is
            # tested on the zero in doubles, before the proof (on centauro's arm, 2.5 s of
            # failed tests went to proving points that were then found too far)
            if certified_point(ring, branch, start, movable, pivots=cols, cache=cache,
                               numeric_above=EXCLUSION_RTOL, accept=near) is not None:
                return True
    return False


def _pivot_choices(ring: PolyRing, branch: Branch, g, movable, cache: dict) -> list:
    """Every regular choice of pivots at ``g``, the best conditioned first (at most PIVOT_CHOICES).

    Near a point where two components of the equations cross, solving for
    one generator leads to one component and solving for another to the
    other: each is tried.
    """
    solved = _substituted(ring, branch)
    eqs = _system(ring, branch, cache)[0]
    cand = _coordinates(ring, g, set(movable) - solved)
    if not eqs:
        return [[]]
    if len(eqs) > len(cand):
        return []
    return _regular_choices(ring, eqs, cand, g, cache)[:PIVOT_CHOICES]
