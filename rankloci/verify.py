"""The certificate of a locus before it is shown, and the recomputation it triggers.

Three checks:

1. **The certificate** (:mod:`rankloci.exact.witness`): witness points of
   every codimension the locus can have, computed exactly modulo a large
   prime, prove that the reported components are the whole locus and that
   each is rank deficient as stated.  It alone makes ``Locus.complete`` true.
2. **The numeric check** of :func:`rankloci.numeric.crosscheck.cross_check`
   at the model's own parameter values: points on each component must be
   singular, random points away from the locus regular, and singular points
   found by minimising sigma_min/sigma_max must lie on a component.  Its
   regular points are hints that repair the branch tree, and it decides
   ``complete = False`` where the certificate cannot be computed.
3. **The determinantal dimension bound** (Eagon-Northcott), reported in the
   notes of a locus that is not certified.

When the certificate fails, the locus is computed again: with the numeric
check's hints (:func:`rankloci.tree.reducible.repair_leaves`), with the
model's parameter values substituted (the symbolic analysis assumes generic
values, and real robots often have special ones), with another seed, and
then with the subdeterminant method.  The first certified locus is
returned; when none is, the best one is, marked ``complete = False``
(disproved) or ``None`` (undecided), with what the checks found: it is
never shown as if it had passed.
"""

from __future__ import annotations

import dataclasses
import re
from dataclasses import dataclass

import numpy as np
import sympy as sp

from .errors import LocusTimeout
from .loci import dimension_bound
from .tolerances import (CHECK_AHEAD_CODIMENSION, HINT_ROUNDS, RANK_RTOL, SELF_CHECK_SAMPLES,
                         SLICE_ROUNDS)

__all__ = ["Verification", "dimension_bound", "dimension_findings", "verified_locus",
           "SELF_CHECK_SAMPLES"]


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
    notes : tuple of str
        What the locus's notes say of the checks: the dimension bound, the verdict of a
        locus that is not certified, and the computations tried when there were several.
    """

    complete: bool
    attempts: tuple = ()
    problems: tuple = ()
    notes: tuple = ()

    def to_dict(self) -> dict:
        return {"complete": self.complete, "attempts": list(self.attempts),
                "problems": list(self.problems)}


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


def _slice_recovery(locus, cert, reference, seed, should_stop, progress, slice_compute,
                    computed=None):
    """Components missing from ``locus`` that fix a variable at a known value: the locus of
    the matrix with that variable at each value (the same engine, one variable fewer), lifted,
    keeping the components the certificate needs."""
    from .certify import certify_locus
    from .loci import Component

    added, lifted_complex = [], []
    # every slice's locus is started at once (in worker processes when there are any), and
    # they are taken in the certificate's order
    wanted = [(var, value) for var, values in cert.slices for value in values
              if computed is None or (var, value) not in computed]
    parts = {key: slice_compute(*key) for key in wanted}
    for var, values in cert.slices:
        for value in values:
            if should_stop():
                break
            if (var, value) not in parts:
                continue        # its pieces were offered in an earlier round
            progress(f"certificate: computing the locus on the slice {var} = {sp.sstr(value)}, "
                     "where witness points lie on no component")
            try:
                part = parts[(var, value)].result(should_stop)
            except LocusTimeout:
                break
            if computed is not None:
                computed[(var, value)] = part
            for c in part.components:
                solved = {var: (value,), **{k: v for k, v in c.solved.items()}}
                added.append(dataclasses.replace(
                    c, equations=(_value_equation(var, value, var in set(reference.angles)),)
                    + tuple(c.equations),
                    solved=solved, sample={**c.sample, var.name: float(value)}))
            # the slice's components without real points, which its certificate proved so
            cc = part.certificate.complex_components if part.certificate is not None else ()
            for eqs in cc:
                lifted_complex.append(Component(
                    (_value_equation(var, value, var in set(reference.angles)), *eqs),
                    dimension=len(part.variables) - len(eqs)))
    # a lifted piece below the determinantal bound lies inside a larger component
    n, m = sorted(reference.shape)
    N = len(reference.variables)
    added = [c for c in added if N - c.dimension <= c.rank_drop * (m - n + c.rank_drop)]
    if not added and not lifted_complex:
        return locus, cert
    # the complex components the certificate counted before, and the lifted ones
    complex_only = tuple(Component(tuple(eqs), dimension=N - len(eqs))
                         for eqs in cert.complex_components) + tuple(lifted_complex)
    trial = dataclasses.replace(locus, components=locus.components + tuple(added))
    again = certify_locus(trial, reference, seed=seed, should_stop=should_stop,
                          complex_only=complex_only)
    if again.verdict == "failed" and again.uncovered >= cert.uncovered:
        return locus, cert
    # the lifted components the certificate does not need (inside others) are left out
    kept = list(added)
    for c in list(added):
        fewer = [k for k in kept if k is not c]
        test = certify_locus(dataclasses.replace(
            locus, components=locus.components + tuple(fewer)), reference, seed=seed,
            should_stop=should_stop, complex_only=complex_only)
        if test.verdict == again.verdict and test.uncovered <= again.uncovered \
                and len(test.findings) <= len(again.findings):
            kept = fewer
    notes = []
    if kept:
        notes.append(f"{len(kept)} component{'s' * (len(kept) != 1)} found on slices where a "
                     "variable is fixed at a value the certificate's witness points gave")
    if lifted_complex:
        notes.append(f"{len(lifted_complex)} component{'s' * (len(lifted_complex) != 1)} of "
                     "the complex locus without real points found on slices, not part of the "
                     "robot's locus: " + "; ".join(", ".join(f"{sp.sstr(e)} = 0"
                                                             for e in c.equations)
                                                   for c in lifted_complex))
    trial = dataclasses.replace(locus, components=locus.components + tuple(kept),
                                notes=locus.notes + tuple(notes))
    final = certify_locus(trial, reference, seed=seed, should_stop=should_stop,
                          complex_only=complex_only)
    return trial, dataclasses.replace(final, complex_components=tuple(
        tuple(c.equations) for c in complex_only))


def _real_part_recovery(locus, cert, reference, seed, should_stop, progress):
    """Complex components that are sums of squares, whose witness points lie on no component:
    their real points added as components (the certificate counts the complex component as
    covering its witness points), and those without real points as complex only."""
    from .certify import certify_locus, completed_component, real_part_components

    progress("certificate: looking for complex components with fewer real points")
    found, without = real_part_components(locus, reference, seed=seed)
    if not found and not without:
        return locus, cert
    # the rank drop was computed exactly; the sample and the lost directions numerically
    added = tuple(completed_component(c, reference, seed=seed, rank_drop=c.rank_drop)
                  for _, comps in found for c in comps)
    complex_only = tuple(cert.discovered_complex) + tuple(c for _, c in without)
    trial = dataclasses.replace(locus, components=locus.components + added)
    again = certify_locus(trial, reference, seed=seed, should_stop=should_stop,
                          progress=progress, complex_only=complex_only)
    if again.verdict == "failed" and again.uncovered >= cert.uncovered:
        return locus, cert
    notes = []
    index = len(locus.components)
    for part, comps in found:
        numbers = ", ".join(str(index + k) for k in range(1, len(comps) + 1))
        index += len(comps)
        notes.append(f"component{'s' * (len(comps) != 1)} {numbers}: the real points of the "
                     f"complex component {sp.sstr(part.equation)} = 0, which has no real "
                     f"point of its own dimension ({sp.sstr(part.equation)} is a weighted sum "
                     f"of the squares of {', '.join(sp.sstr(e) for e in part.squares)}, so its "
                     "real points are where these all vanish)")
    for part, _ in without:
        notes.append(f"the complex component {sp.sstr(part.equation)} = 0 has no real point "
                     f"(a weighted sum of the squares of "
                     f"{', '.join(sp.sstr(e) for e in part.squares)}, which have no common "
                     "real zero): not part of the robot's locus")
    locus = dataclasses.replace(trial, notes=trial.notes + tuple(notes))
    return locus, dataclasses.replace(again, complex_components=tuple(
        cert.complex_components) + tuple((part.equation,) for part, _ in without))


def _value_equation(var, value, is_angle=True):
    """An equation in ``var`` that vanishes at ``value`` (of an angle: in its half angle)."""
    if not is_angle:
        return var - value
    if value == sp.pi:
        return sp.cos(var / 2)
    t = sp.tan(value / 2)
    return sp.sin(var / 2) - t * sp.cos(var / 2)


def _sliced(tm, var, value):
    """``tm`` (parameters substituted) with the variable ``var`` fixed at the exact ``value``."""
    t = tm.numeric_parameters()
    if var in set(t.angles):
        half = sp.tan(value / 2) if value != sp.pi else None
        c = sp.Integer(-1) if half is None else (1 - half ** 2) / (1 + half ** 2)
        s_ = sp.Integer(0) if half is None else 2 * half / (1 + half ** 2)
        M = t.matrix.applyfunc(lambda e: sp.expand(sp.expand_trig(e).xreplace(
            {sp.cos(var): sp.radsimp(c), sp.sin(var): sp.radsimp(s_)})))
    else:
        M = t.matrix.subs(var, value)
    return dataclasses.replace(t, matrix=sp.ImmutableMatrix(M),
                               variables=tuple(v for v in t.variables if v != var),
                               angles=tuple(v for v in t.angles if v != var))


def _slice_locus(tm, var, value, method, seed, should_stop=None):
    """The certified locus of ``tm`` (parameters substituted) with ``var`` fixed at ``value``:
    one part of the certificate's recovery, run in a worker process when there are any."""
    from .methods import compute_locus, method_for

    part = _sliced(tm, var, value)
    found = compute_locus(part, method_for(part.shape, method, strict=False),
                          rng=np.random.default_rng(seed), should_stop=should_stop)
    # the slice's own certificate completes its locus where witness points fix a value
    return _certified(found, part, seed, should_stop or (lambda: False), lambda msg: None)[0]


def _certified(locus, reference, seed, should_stop, progress, slice_compute=None):
    """``locus`` with its certificate (and that of its base locus, for an augmented matrix)."""
    from .certify import certify_locus

    progress("certificate: witness points of the locus, modulo a prime")
    cert = certify_locus(locus, reference, seed=seed, should_stop=should_stop,
                         progress=progress)
    if cert.redundant:
        # components below the determinantal bound of their rank drop lie inside larger ones
        # (or are not singular at all): the locus without them is the same set, or a better one
        gone = set(cert.redundant)
        kept = tuple(c for i, c in enumerate(locus.components, 1) if i not in gone)
        locus = dataclasses.replace(locus, components=kept, notes=locus.notes + (
            f"{len(gone)} component{'s' * (len(gone) > 1)} below the dimension bound of "
            f"{'their' if len(gone) > 1 else 'its'} rank drop left out (inside larger ones)",))
        cert = certify_locus(locus, reference, seed=seed, should_stop=should_stop,
                             progress=progress)
    if cert.verdict == "failed" and (cert.discovered or cert.discovered_complex):
        # witness points on no component that fix a few variables at values of small height:
        # the components through them, added and certified again
        from .certify import completed_component

        again = None
        offers = ([cert.discovered_merged] if cert.discovered_merged else []) + \
            ([cert.discovered] if cert.discovered else []) + \
            ([()] if cert.discovered_complex else [])
        for offered in offers:
            # the variables' values all at once first (sin q2 = sin q3 = 0), then one
            # component per combination of values, then none: the components without real
            # points alone (a combination of values the points do not share is no component)
            added = tuple(completed_component(c, reference, seed=seed) for c in offered)
            trial = dataclasses.replace(locus, components=locus.components + added)
            again = certify_locus(trial, reference, seed=seed, should_stop=should_stop,
                                  progress=progress, complex_only=cert.discovered_complex)
            if again.verdict == "passed":
                break
        # a trial is kept when it passed or left fewer points uncovered, and never when the
        # certificate found one of the components it added unsound
        first_added = len(locus.components) + 1
        unsound = any(f.startswith((f"component {i}:", f"component {i} "))
                      for f in again.findings
                      for i in range(first_added, first_added + len(added)))
        if again.verdict == "passed" or (not unsound and (
                again.verdict != "failed" or again.uncovered < cert.uncovered)):
            notes = []
            if added:
                notes.append(f"{len(added)} component{'s' * (len(added) != 1)} found from the "
                             "witness points of the certificate that lay on no component of "
                             "the branch tree")
            if cert.discovered_complex:
                notes.append(f"{len(cert.discovered_complex)} component"
                             f"{'s' * (len(cert.discovered_complex) != 1)} of the complex locus "
                             "without real points (each fixes a variable at values none of "
                             "which is real), not part of the robot's locus: "
                             + "; ".join(", ".join(f"{sp.sstr(e)} = 0" for e in c.equations)
                                         for c in cert.discovered_complex))
            locus = dataclasses.replace(trial, notes=trial.notes + tuple(notes))
            cert = dataclasses.replace(again, complex_components=tuple(
                tuple(c.equations) for c in cert.discovered_complex))
    if cert.verdict == "failed" and cert.uncovered:
        locus, cert = _real_part_recovery(locus, cert, reference, seed, should_stop, progress)
    computed = {}
    for _ in range(SLICE_ROUNDS):
        if cert.verdict != "failed" or not cert.slices or slice_compute is None:
            break
        if _complex_only_failure(cert):
            # points of codimension 3 on coordinate slices, values not recognised: the locus of
            # J on each slice is a whole computation of the engine per value, which searches
            # real components (on tiago_dual's arm two of them ran past its 120 s limit), and
            # the robot's locus stays undecided without them
            break
        before = cert.uncovered
        locus, cert = _slice_recovery(locus, cert, reference, seed, should_stop, progress,
                                      slice_compute, computed)
        if cert.uncovered >= before:
            break
    if locus.base is not None and reference.n_constraint_rows:
        base_ref = dataclasses.replace(
            reference, matrix=reference.matrix[:reference.shape[0] - reference.n_constraint_rows, :],
            n_constraint_rows=0)
        base_cert = certify_locus(locus.base, base_ref, seed=seed, should_stop=should_stop)
        base_notes = ()
        if base_cert.verdict == "failed" and base_cert.discovered_complex \
                and not base_cert.discovered:
            # witness points on components without real points only (as for J_aug above)
            again = certify_locus(locus.base, base_ref, seed=seed, should_stop=should_stop,
                                  complex_only=base_cert.discovered_complex)
            if again.verdict != "failed":
                found = base_cert.discovered_complex
                base_cert = dataclasses.replace(again, complex_components=tuple(
                    tuple(c.equations) for c in found))
                base_notes = (f"{len(found)} component{'s' * (len(found) != 1)} of the complex "
                              "locus without real points (each fixes a variable at values none "
                              "of which is real), not part of the robot's locus: "
                              + "; ".join(", ".join(f"{sp.sstr(e)} = 0" for e in c.equations)
                                          for c in found),)
        base = dataclasses.replace(locus.base, certificate=base_cert,
                                   complete=_complete(base_cert, True),
                                   notes=locus.base.notes + base_notes)
        locus = dataclasses.replace(locus, base=base)
        if base_cert.verdict != "passed" and cert.verdict == "passed":
            cert = dataclasses.replace(cert, verdict=base_cert.verdict, findings=tuple(
                f"the locus of J without the constraint rows: {f}" for f in base_cert.findings))
    return dataclasses.replace(locus, certificate=cert), cert


#: A finding of witness points on no component, and its codimension.
_UNCOVERED = re.compile(r"^\d+ of the \d+ witness points of codimension (\d+) lie on no "
                        r"reported component")


def _complete(cert, numeric_ok: bool):
    """``Locus.complete``: True only for a passing certificate; False when the certificate or
    the numeric check disproves the locus; None when neither decides.

    Witness points of codimension 3 or more (coordinate slices) that lie on no component and
    that the recovery could not attribute disprove the complex locus, not the real one: on
    the long chains where they occur (tiago's arm, panda's finger) no variable of theirs is
    at a value of small height, and the numeric check, which searches real singular
    configurations, finds none off the components.  When they are the certificate's only
    failure and the numeric check passed, the real locus is undecided (None), not refused."""
    if cert.verdict == "passed":
        return True
    if not numeric_ok:
        return False
    if cert.verdict == "failed":
        return None if _complex_only_failure(cert) else False
    return None


def _complex_only_failure(cert) -> bool:
    """Whether the certificate's only failure is witness points of codimension 3 or more on
    no component (see :func:`_complete`)."""
    failing = [f for f in cert.findings
               if "are not certified" not in f and "is not certified" not in f]
    found = [_UNCOVERED.match(f) for f in failing]
    return bool(failing) and all(m is not None and int(m.group(1)) >= 3 for m in found)


def verified_locus(compute, tm, reference, *, seed: int = 0, samples: int = SELF_CHECK_SAMPLES,
                   progress=None, should_stop=None, method=None, workers=None,
                   rank_rtol: float = RANK_RTOL, with_notes: bool = True):
    """The locus of ``tm``, certified, and recomputed when its certificate fails.

    Each computation is checked twice: numerically (:func:`~rankloci.numeric.crosscheck.
    cross_check`, whose regular points are hints that repair the branch tree) and by the
    certificate (:func:`~rankloci.certify.certify_locus`), which alone decides
    ``Locus.complete``.  The attempts: the computation as asked, with the hints of its numeric
    check, with the model's parameter values substituted, with other seeds, and then with the
    subdeterminant method (the same engine, another way through the tree), until one passes its
    certificate or the time runs out.

    Parameters
    ----------
    compute : callable
        ``compute(tm, seed, hints=(), method=None, grown=None)`` returns the
        :class:`~rankloci.loci.Locus` of a task matrix (``method`` None: the one asked for),
        or a pair of the locus and the tree it grew (:class:`~rankloci.methods.GrownTree`):
        that tree comes back as ``grown`` with the hints of the locus's numeric check, so that
        the recomputation resumes from it.  ``grown`` is passed only to a ``compute`` that
        returned a tree.
    tm : TaskMatrix
        The matrix to compute the locus of.
    reference : TaskMatrix
        The same matrix with the parameters symbolic (their values are the
        model's): what the checks evaluate.
    seed : int
        Seed of the first computation and of every check.
    samples : int
        Points per part of the numeric check.
    progress : callable, optional
        Called with one-line progress messages.
    should_stop : callable, optional
        True once the time is up: the certificate stops undecided, and no further attempt
        starts.
    method : str, optional
        The method of the first computation; the subdeterminant method is tried last when it
        is another one.
    workers : rankloci.parallel.Workers, optional
        Where the numeric check runs beside the certificate, and the loci of the slices of
        the certificate's recovery side by side (default: one after another, here).  The
        result is the same.
    rank_rtol : float
        The numeric check's rank threshold on sigma_min/sigma_max
        (:func:`~rankloci.numeric.crosscheck.cross_check`).
    with_notes : bool
        Add ``Verification.notes`` to the locus's notes (the pipeline's result stage adds
        them itself, with the other notes).

    Returns
    -------
    (Locus, Verification)
        The locus carries its certificate; its notes say what the checks found when it is not
        certified.

    Raises
    ------
    LocusTimeout
        The time ran out before any attempt passed or left its certificate undecided
        (an attempt that failed it is not returned then: the time limit stopped the work).
    """
    from .numeric.crosscheck import cross_check

    from .parallel import Workers

    progress = progress or (lambda msg: None)
    stop = should_stop or (lambda: False)
    workers = (workers if workers is not None else Workers(1)).sized(len(reference.variables))
    one = Workers(1)
    # the first numeric check starts beside the certificate only where the certificate is not
    # expected to decide (CHECK_AHEAD_CODIMENSION)
    n, m = sorted(reference.shape)
    ahead = min(m - n + 1, len(reference.variables)) >= CHECK_AHEAD_CODIMENSION

    def slice_compute(var, value):
        return workers.submit(_slice_locus, tm, var, value, method, seed, should_stop=None)

    # each attempt: (matrix, seed, what, method, the tree to resume from)
    plan = [(tm, seed, "as computed", None, None)]
    if tm.parameters:
        numeric = tm.numeric_parameters()
        plan += [(numeric, seed, "with the model's parameter values substituted", None, None),
                 (numeric, seed + 1, f"with the model's values, seed {seed + 1}", None, None)]
    else:
        plan += [(tm, seed + 1, f"seed {seed + 1}", None, None)]
    if method is not None and method != "subdeterminant":
        plan += [(tm.numeric_parameters(), seed, "by the subdeterminant method",
                  "subdeterminant", None)]
    attempts, locus, hints, what, report = [], None, [], "", None
    best = None        # (rank, locus, problems, complete): passed < undecided < failed
    rounds = 0
    timed_out = False
    queue = list(plan)
    while queue:
        t, s, base, how, grown = queue.pop(0)
        what = base if not hints else (
            f"{base}, with the {len(hints)} configuration{'' if len(hints) == 1 else 's'} "
            f"where the self-check found a component regular")
        if attempts:
            progress(f"certificate not passed; computing the locus again {what}")
        try:
            options = {"hints": tuple(hints)} if hints else {}
            if how is not None:
                options["method"] = how
            if grown is not None:
                options["grown"] = grown
            locus = compute(t, s, **options)
            if isinstance(locus, tuple):
                locus, grown = locus
        except LocusTimeout:
            if best is None:
                raise
            attempts.append(f"{what}: did not finish within the time limit")
            timed_out = True
            break
        # the numeric check of the engine's locus, beside its certificate; a first
        # computation that the certificate proves needs no numeric check
        # after a first attempt that did not pass, the next ones are not expected to either
        checker = workers if ahead or attempts else one
        here = checker.jobs == 1
        checking = checker.submit(
            cross_check, locus, reference.matrix, reference.variables, angles=reference.angles,
            parameters=reference.parameters, samples=samples, rng=np.random.default_rng(seed),
            seed=seed, progress=(lambda msg: progress(f"self-{msg}")) if here else None,
            earlier=report if how is None else None, rank_rtol=rank_rtol)
        if not here:
            progress("self-check: in a worker process, beside the certificate")
        locus, cert = _certified(locus, reference, seed, stop, progress, slice_compute)
        if cert.verdict == "passed" and not attempts:
            checking.cancel()
            attempts.append(f"{what}: certificate passed")
            best = (0, locus, [], True)
            break
        report = checking.result(stop)
        numeric_problems = _check_problems(report)
        complete = _complete(cert, not numeric_problems)
        # a passing certificate is of the locus as completed; the numeric check was of the
        # engine's
        problems = ([f"certificate: {f}" for f in cert.findings] + numeric_problems
                    if cert.verdict != "passed" else [])
        attempts.append(f"{what}: certificate {cert.verdict}"
                        + (f", numeric check {'passed' if not numeric_problems else 'failed'}"))
        rank = {True: 0, None: 1, False: 2}[complete]
        if best is None or rank < best[0]:
            best = (rank, locus, problems, complete)
        if complete is True:
            break
        if stop():
            timed_out = True
            break
        if complete is None and cert.verdict == "undecided" and not cert.prime:
            break      # the certificate does not apply to this matrix: recomputing cannot help
        new = [q for q in _regular_points(report, reference.variables) if q not in hints]
        if new and rounds < HINT_ROUNDS:
            # the configurations where a component is regular go back to the tree, which
            # splits the leaves or keeps the exclusions that hold there
            rounds += 1
            hints += new
            queue.insert(0, (t, s, base, how, grown))
        elif complete is None:
            break      # the numeric check passes and nothing decides more: keep this locus
    _, locus, problems, complete = best
    if timed_out and complete is False:
        # no attempt passed and the time ran out before the next one could: what stopped the
        # computation is the time limit, not the certificate
        raise LocusTimeout("the time ran out while the locus was computed again after it "
                           "failed its certificate (" + "; ".join(attempts) + ")")
    notes = tuple(dimension_findings(locus)) if complete is not True else ()
    cert = locus.certificate
    if complete is False:
        notes += ("INCOMPLETE: the locus is not certified; "
                  + "; ".join(problems[:4]) + (" ..." if len(problems) > 4 else ""),)
    elif complete is None:
        notes += ("NOT CERTIFIED: " + "; ".join(cert.findings[:3])
                  + ("; the numeric self-check passed" if not problems or all(
                      p.startswith("certificate:") for p in problems) else ""),)
    if len(attempts) > 1:
        notes += ("computations: " + "; ".join(attempts),)
    verification = Verification(complete is True, tuple(attempts), tuple(problems), notes)
    return dataclasses.replace(locus, notes=locus.notes + (notes if with_notes else ()),
                               complete=complete), verification
