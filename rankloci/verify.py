"""Self-checks that run before a locus is shown, and the refinement they trigger.

Two checks, both cheap next to the locus itself:

1. **The determinantal dimension bound.**  Where an n x m matrix (n <= m)
   has rank n - k, its maximal minors cut out a set each of whose (complex)
   components has codimension at most k (m - n + k) (Eagon-Northcott).  A
   reported component of lower dimension is either inside a larger one or a
   sign that a larger one was missed.  Real loci can legitimately be smaller
   (the real points of a complex component), so a violation is reported,
   and the numeric check below decides.
2. **The numeric check** of :func:`rankloci.numeric.crosscheck.cross_check`
   at the model's own parameter values: points on each component must be
   singular (sound), random points away from the locus regular, and
   singular points found by minimising sigma_min/sigma_max from random
   starts must lie on a component (complete).

When the numeric check finds a component regular at some of its points,
the locus is computed again with those configurations as hints: the
leaves whose equations hold there are split, or keep the exclusion that
vanishes there (:func:`rankloci.tree.reducible.repair_leaves`).  When it
still fails, the locus is computed again with the
model's parameter values substituted (the symbolic analysis assumes generic
values, and real robots often have special ones), then with other seeds.
If no attempt passes, the last locus is returned marked incomplete, with
what the check found: it is never shown as if it had passed.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from .errors import LocusTimeout

__all__ = ["Verification", "dimension_bound", "dimension_findings", "verified_locus",
           "SELF_CHECK_SAMPLES"]

#: Sample points per component, off-locus points and probe starts of the self-check.  The
#: probe finds the components that are hit from random starts with high probability; a
#: component missed by the self-check but found by ``rankloci check --samples 50`` is
#: possible for small components (reported by that command).
SELF_CHECK_SAMPLES = 6

#: Rounds of recomputation with the configurations where the check found a component regular
#: (each adds the new ones): a split leaf's pieces are checked in the next round.
HINT_ROUNDS = 2


@dataclass(frozen=True)
class Verification:
    """The outcome of the self-checks of a locus.

    Attributes
    ----------
    complete : bool
        The numeric check of the returned locus passed.
    attempts : tuple of str
        Each computation tried, in order, and its verdict.
    problems : tuple of str
        What the check of the returned locus found (empty when complete).
    """

    complete: bool
    attempts: tuple = ()
    problems: tuple = ()

    def to_dict(self) -> dict:
        return {"complete": self.complete, "attempts": list(self.attempts),
                "problems": list(self.problems)}


def dimension_bound(shape, n_variables: int, rank_drop: int) -> int:
    """The smallest dimension a component of the given rank drop can have.

    Examples
    --------
    >>> dimension_bound((6, 7), 7, 1)      # a 6x7 Jacobian losing one rank: codimension <= 2
    5
    >>> dimension_bound((6, 6), 6, 2)      # square, rank drop 2: codimension <= 4
    2
    """
    n, m = sorted(shape)
    return max(0, n_variables - rank_drop * (m - n + rank_drop))


def dimension_findings(locus) -> list[str]:
    """Components of ``locus`` below the determinantal dimension bound."""
    out = []
    nvars = len(locus.variables)
    for i, c in enumerate(locus.components, start=1):
        bound = dimension_bound(locus.shape, nvars, c.rank_drop)
        if c.dimension < bound:
            out.append(f"component {i} has dimension {c.dimension}, below the bound {bound} for "
                       f"rank drop {c.rank_drop} of a {locus.shape[0]}x{locus.shape[1]} matrix in "
                       f"{nvars} variables: it lies inside a larger component, has only "
                       "lower-dimensional real points, or a larger component was missed")
    return out


def _check_problems(report) -> list[str]:
    out = []
    for c in report.components:
        if not c.ok:
            out.append(f"component {c.index} ({', '.join(c.equations)[:60]}): {c.message}")
    for p in report.off_locus_failures:
        out.append(f"singular configuration away from every component: q = "
                   f"{[round(x, 4) for x in p.q]}")
    for p in report.uncovered:
        out.append(f"singular point on no component (sigma ratio {p.sigma_ratio:.1e}): q = "
                   f"{[round(x, 4) for x in p.q]}")
    return out


def _regular_points(report, variables) -> list[dict]:
    """The configurations (variable name -> value) at which the check found a component
    regular."""
    names = [str(v) for v in variables]
    return [dict(zip(names, (float(x) for x in p.q)))
            for c in report.components for p in c.failures if p.regular]


def verified_locus(compute, tm, reference, *, seed: int = 0, samples: int = SELF_CHECK_SAMPLES,
                   progress=None):
    """The locus of ``tm``, checked against ``reference`` and recomputed when the check fails.

    Parameters
    ----------
    compute : callable
        ``compute(tm, seed)`` returns the :class:`~rankloci.locus.Locus` of a task matrix;
        ``compute(tm, seed, hints=...)`` the same with the configurations where a check
        found a component regular (see :func:`~rankloci.methods.compute_locus`).
    tm : TaskMatrix
        The matrix to compute the locus of.
    reference : TaskMatrix
        The same matrix with the parameters symbolic (their values are the
        model's): what the numeric check evaluates.
    seed : int
        Seed of the first computation and of every check.
    samples : int
        Points per part of the numeric check.
    progress : callable, optional
        Called with one-line progress messages.

    Returns
    -------
    (Locus, Verification)
        The locus carries the dimension findings and, when it is incomplete,
        the check's findings in its notes.
    """
    from .numeric.crosscheck import cross_check

    progress = progress or (lambda msg: None)
    plan = [(tm, seed, "as computed")]
    if tm.parameters:
        numeric = tm.numeric_parameters()
        plan += [(numeric, seed, "with the model's parameter values substituted"),
                 (numeric, seed + 1, f"with the model's values, seed {seed + 1}")]
    else:
        plan += [(tm, seed + 1, f"seed {seed + 1}"), (tm, seed + 2, f"seed {seed + 2}")]
    attempts, locus, problems, hints, what, report = [], None, [], [], "", None
    rounds = 0
    queue = list(plan)
    while queue:
        t, s, base = queue.pop(0)
        what = base if not hints else (
            f"{base}, with the {len(hints)} configuration{'' if len(hints) == 1 else 's'} "
            f"where the self-check found a component regular")
        if attempts:
            progress(f"self-check failed; computing the locus again {what}")
        try:
            locus = compute(t, s, hints=tuple(hints)) if hints else compute(t, s)
        except LocusTimeout:
            if locus is None:
                raise
            attempts.append(f"{what}: did not finish within the time limit")
            break
        report = cross_check(locus, reference.matrix, reference.variables,
                             angles=reference.angles, parameters=reference.parameters,
                             samples=samples, rng=np.random.default_rng(seed), seed=seed,
                             progress=lambda msg: progress(f"self-{msg}"), earlier=report)
        problems = _check_problems(report)
        attempts.append(f"{what}: {'passed' if not problems else 'failed'}")
        if not problems:
            break
        new = [q for q in _regular_points(report, reference.variables) if q not in hints]
        if new and rounds < HINT_ROUNDS:
            # the configurations where a component is regular go back to the tree, which
            # splits the leaves or keeps the exclusions that hold there
            rounds += 1
            hints += new
            queue.insert(0, (t, s, base))
    notes = tuple(dimension_findings(locus))
    if problems:
        notes += ("INCOMPLETE: the self-check rejects this locus; "
                  + "; ".join(problems[:4]) + (" ..." if len(problems) > 4 else ""),)
    elif len(attempts) > 1:
        notes += (f"the first computation failed its self-check; this locus is the one "
                  f"{what}",)
    verification = Verification(not problems, tuple(attempts), tuple(problems))
    return dataclasses.replace(locus, notes=locus.notes + notes,
                               complete=verification.complete), verification
