"""Numeric cross-check of a rank-deficiency locus against the SVD of J(q).

:func:`cross_check` tests a :class:`~rankloci.loci.Locus` three ways, with
J evaluated in double precision (the model's own frame, parameters
substituted):

1. *on-locus*: points solved onto each component must make J rank deficient
   (sigma_min/sigma_max <= RANK_RTOL);
2. *off-locus*: random configurations away from every component must make
   J full rank;
3. *completeness*: minima of sigma_min/sigma_max from random starts that
   reach rank deficiency must lie on some component.

The SVD decides.  At each on-locus point the FSP reducer
(:func:`rankloci.numeric.fsp.dependent_rows`) and the scale-free largest
maximal minor (:func:`rankloci.numeric.minors.relative_max_minor`) are
evaluated too; where they disagree with the SVD this is recorded as a
finding, not a failure.  Failed checks are data in the frozen
:class:`CheckReport`, never exceptions.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
import sympy as sp

from ..expr import as_expression
from ..tolerances import (COVER_RESIDUAL, MINOR_RTOL, OFF_LOCUS_MIN_RESIDUAL, ON_COMPONENT_RESIDUAL,
                          ON_LOCUS_RTOL, PRECISE_CHECK_DIGITS, PRECISE_CHECK_FLOOR, PRECISE_FALL,
                          PRECISE_STABLE_RTOL, PROBE_DESCENT_RTOL, PROBE_ESCAPE_ABS,
                          RANK_RTOL, ZERO_MATRIX_RTOL)
from .equations import (MAX_TRIES, Equations, NumericMatrix, descend_to_singular, minimise_ratio,
                        points_on)
from .fsp import dependent_rows
from .minors import relative_max_minor
from .svd import numeric_rank_drop, sigma_ratio

__all__ = ["cross_check", "parse_locus", "render_check_text", "CheckReport", "ComponentCheck",
           "PointCheck", "NumericMatrix", "SCHEMA"]

SCHEMA = "rankloci.check/1"



# --- results --------------------------------------------------------------------------------

@dataclass(frozen=True)
class PointCheck:
    """One configuration and what each numeric test says there."""

    q: tuple
    sigma_ratio: float
    rank_drop: int
    fsp_dependent: tuple
    minor: float
    #: the extended-precision verdict ("singular", "regular") where double precision could
    #: not tell, with the ratio at the higher precision; None where it was not asked
    precise: str | None = None
    precise_ratio: float | None = None
    #: the rank threshold on sigma_min/sigma_max the check used (its ``rank_rtol``)
    rtol: float = ON_LOCUS_RTOL

    @property
    def regular(self) -> bool:
        """Is J regular here: the extended-precision verdict, else the double ratio."""
        if self.precise is not None:
            return self.precise == "regular"
        return self.sigma_ratio > self.rtol

    def to_dict(self) -> dict:
        out = {"q": list(self.q), "sigma_ratio": self.sigma_ratio, "rank_drop": self.rank_drop,
               "fsp_dependent_rows": list(self.fsp_dependent), "relative_max_minor": self.minor}
        if self.precise is not None:
            out["precise"] = {"verdict": self.precise, "sigma_ratio": self.precise_ratio,
                              "digits": PRECISE_CHECK_DIGITS[1]}
        return out


@dataclass(frozen=True)
class ComponentCheck:
    """On-locus check of one component."""

    index: int
    equations: tuple
    points: tuple = ()
    failures: tuple = ()          # PointCheck where J is regular
    ok: bool = True
    message: str = ""
    #: what else the check of the points depended on: the component's exclusions (as text)
    #: and rank drop (see ``earlier`` of :func:`cross_check`)
    excluding: tuple = ()
    rank_drop: int | None = None

    @property
    def max_ratio(self) -> float:
        return max((p.sigma_ratio for p in self.points), default=float("nan"))

    def to_dict(self) -> dict:
        return {"index": self.index, "equations": list(self.equations), "ok": self.ok,
                "message": self.message, "n_points": len(self.points),
                "max_sigma_ratio": None if not self.points else self.max_ratio,
                "points": [p.to_dict() for p in self.points]}


@dataclass(frozen=True)
class CheckReport:
    """Everything :func:`cross_check` found; ``ok`` when every SVD-decided check passed."""

    model: str
    seed: object
    samples: int
    components: tuple
    skipped: tuple                # equations of components not checked (parameter conditions)
    off_locus: tuple              # PointCheck
    off_locus_failures: tuple
    probe_singular: int
    probe_starts: int
    uncovered: tuple              # PointCheck of singular probe points on no component
    findings: tuple = ()          # FSP / minor disagreements with the SVD (data only)
    thresholds: dict = field(default_factory=dict)
    probe_escaped: int = 0        # probe minima that ran off to infinity (not singular points)

    @property
    def ok(self) -> bool:
        return (all(c.ok for c in self.components) and not self.off_locus_failures
                and not self.uncovered)

    def to_dict(self) -> dict:
        return {
            "schema": SCHEMA, "model": self.model, "seed": self.seed, "samples": self.samples,
            "ok": self.ok,
            "on_locus": [c.to_dict() for c in self.components],
            "skipped_components": [list(e) for e in self.skipped],
            "off_locus": {"ok": not self.off_locus_failures, "n_points": len(self.off_locus),
                          "min_sigma_ratio": min((p.sigma_ratio for p in self.off_locus),
                                                 default=None),
                          "failures": [p.to_dict() for p in self.off_locus_failures]},
            "completeness": {"ok": not self.uncovered, "starts": self.probe_starts,
                             "singular_minima": self.probe_singular,
                             "ran_off_to_infinity": self.probe_escaped,
                             "uncovered": [p.to_dict() for p in self.uncovered]},
            "findings": list(self.findings),
            "thresholds": dict(self.thresholds),
        }


# --- the checks -----------------------------------------------------------------------------

def _settled(nm: NumericMatrix, eqs: Equations, p: PointCheck) -> PointCheck:
    """``p``, or where a point regular in J lands when refined onto the equations.

    A point solved near a multiple root of the equations can lie off the component by far
    more than its residual says (:meth:`Equations.refined`); its sigma ratio is that of the
    refined point, when that one is a point of the component (:meth:`Equations.settled`).
    """
    if p.sigma_ratio <= p.rtol:
        return p
    q = eqs.settled(np.array(p.q))
    return p if q is None else _point(nm, q, p.rtol)


def _decided(nm: NumericMatrix, eqs: Equations, p: PointCheck) -> PointCheck:
    """``p`` with the extended-precision verdict where its double ratio cannot tell.

    Above PRECISE_CHECK_FLOOR a ratio in double precision is no evidence either way: nearly
    degenerate geometry shows 1e-13 at regular points, a point near a multiple root of the
    equations 1e-5 at singular ones.  The point is moved onto the component in each of
    PRECISE_CHECK_DIGITS and J's ratio evaluated there: it falls with the digits where J is
    singular on the component and stays where it is regular.
    """
    if p.sigma_ratio <= PRECISE_CHECK_FLOOR:
        return p
    lo, hi = PRECISE_CHECK_DIGITS
    q = np.array(p.q)
    x_lo, x_hi = eqs.precise(q, lo), eqs.precise(q, hi)
    if x_lo is None or x_hi is None:
        return p
    r_lo, r_hi = nm.precise_ratio(x_lo, lo), nm.precise_ratio(x_hi, hi)
    if r_hi <= PRECISE_FALL * r_lo:
        verdict = "singular"
    elif abs(r_hi - r_lo) <= PRECISE_STABLE_RTOL * r_lo and r_hi > PRECISE_CHECK_FLOOR:
        # a stable ratio below the floor is what data rounded to double precision give
        # (a float parameter against its exact reading): not evidence of a regular point
        verdict = "regular"
    else:
        return p
    return replace(p, precise=verdict, precise_ratio=float(r_hi))


def _point(nm: NumericMatrix, q, rtol: float = ON_LOCUS_RTOL) -> PointCheck:
    J = nm(q)
    A = J.T if J.shape[0] > J.shape[1] else J
    top = np.linalg.svd(np.asarray(J, dtype=float), compute_uv=False)[:1]
    if top.size and top[0] <= ZERO_MATRIX_RTOL * nm.typical_scale():
        # J vanishes here up to rounding: rank 0, whatever the ratio of the residue
        return PointCheck(q=tuple(float(x) for x in q), sigma_ratio=0.0,
                          rank_drop=int(min(J.shape)), fsp_dependent=tuple(range(A.shape[0])),
                          minor=0.0, rtol=rtol)
    return PointCheck(q=tuple(float(x) for x in q), sigma_ratio=float(sigma_ratio(J)),
                      rank_drop=int(numeric_rank_drop(J, rtol)),
                      fsp_dependent=tuple(int(i) for i in dependent_rows(A)),
                      minor=relative_max_minor(J), rtol=rtol)


def _findings_at(label: str, p: PointCheck, singular: bool) -> list:
    out = []
    if singular and not p.fsp_dependent:
        out.append(f"{label}: SVD rank deficient (ratio {p.sigma_ratio:.1e}) but FSP finds no "
                   "dependent row")
    if not singular and p.fsp_dependent:
        out.append(f"{label}: SVD full rank (ratio {p.sigma_ratio:.1e}) but FSP finds dependent "
                   f"rows {list(p.fsp_dependent)}")
    if singular and p.minor > MINOR_RTOL:
        out.append(f"{label}: SVD rank deficient but the relative maximal minor is {p.minor:.1e}")
    if not singular and p.minor <= MINOR_RTOL:
        out.append(f"{label}: SVD full rank but the relative maximal minor is {p.minor:.1e}")
    return out


def cross_check(locus, matrix, variables, *, angles=(), parameters=None, samples: int = 10,
                rng=None, seed=None, progress=None, earlier: CheckReport | None = None,
                rank_rtol: float = RANK_RTOL) -> CheckReport:
    """Check `locus` numerically against the SVD of `matrix` (see the module docstring).

    Parameters
    ----------
    locus : Locus
    matrix : sympy.Matrix
        J in the joint `variables` (any frame: the rank is the same); parameters
        still in it are replaced by `parameters`.
    variables : sequence of Symbol
        Column variables, matched by name to ``locus.variables``.
    angles : sequence of Symbol
        Variables drawn uniformly in [-pi, pi); the others are drawn normal.
    parameters : dict, optional
        Symbol -> value, substituted into J and into the component equations.
    samples : int
        Points per component, off-locus configurations and completeness starts.
    rng : numpy.random.Generator
    seed : optional
        Only recorded in the report.
    progress : callable, optional
        Called with a one-line message before each component and each later part (refining
        points in extended precision can take seconds each on long chains).
    earlier : CheckReport, optional
        A check of another locus of the same matrix, with the same parameters: a component
        that passed there, with the same equations, exclusions and rank drop, keeps its
        points and verdict instead of being sampled again.  A locus recomputed after a
        failed check (:func:`rankloci.verify.verified_locus`) differs in a few leaves.
    rank_rtol : float
        J is rank deficient at a point when sigma_min <= ``rank_rtol`` * sigma_max: on the
        components (:data:`~rankloci.tolerances.ON_LOCUS_RTOL`), at the configurations off
        the locus, and at the minima of the completeness probe
        (:data:`~rankloci.tolerances.PROBE_SINGULAR_RTOL`).  Default
        :data:`~rankloci.tolerances.RANK_RTOL`; recorded in ``thresholds``.

    Examples
    --------
    >>> from rankloci.io import load_model
    >>> from rankloci.jacobians import task_matrix
    >>> from rankloci.methods import compute_locus
    >>> tm = task_matrix(load_model("planar2r"), numeric=True)
    >>> report = cross_check(compute_locus(tm), tm.matrix, tm.variables, angles=tm.angles,
    ...                      samples=3, rng=np.random.default_rng(0))
    >>> report.ok
    True
    """
    rng = np.random.default_rng(0) if rng is None else rng
    parameters = dict(parameters or {})
    by_name = {v.name: v for v in variables}
    missing = [str(v) for v in locus.variables if str(v) not in by_name]
    if missing:
        raise ValueError(f"locus variables {missing} are not among the matrix variables "
                         f"{sorted(by_name)}")
    nm = NumericMatrix(sp.Matrix(matrix).subs(parameters), variables, angles)
    # the locus' own symbols may differ in assumptions: rename them to the matrix symbols
    rename = {v: by_name[str(v)] for v in locus.variables}
    params_by_name = {str(k): v for k, v in parameters.items()}

    def prepared(e):
        e = as_expression(e).xreplace(rename)
        return e.subs({s: params_by_name[s.name] for s in e.free_symbols if s.name in params_by_name})

    checked, findings = [], []
    all_eqs = []                  # every checked component's equations (residuals only)
    skipped = [tuple(sp.sstr(e) for e in comp.equations) for comp in locus.special]
    tell = progress or (lambda msg: None)
    passed = {(c.equations, c.excluding, c.rank_drop): c
              for c in (earlier.components if earlier is not None else ()) if c.ok}
    for i, comp in enumerate(locus.components, start=1):
        tell(f"check: component {i} of {len(locus.components)}")
        eq_text = tuple(sp.sstr(e) for e in comp.equations)
        ex_text = tuple(sp.sstr(e) for e in comp.excluding)
        eqs = Equations([prepared(e) for e in comp.equations], nm.variables, {},
                         [prepared(e) for e in comp.excluding])
        all_eqs.append(eqs)
        same = passed.get((eq_text, ex_text, comp.rank_drop))
        if same is not None:
            pts = list(same.points)
        else:
            pts = [_decided(nm, eqs, _settled(nm, eqs, _point(nm, q, rank_rtol)))
                   for q in points_on(eqs, nm, rng, samples)]
        fails = tuple(p for p in pts if p.regular)
        for p in pts:
            if p.sigma_ratio <= rank_rtol and not p.regular:
                findings += _findings_at(f"component {i}", p, True)
            if p.sigma_ratio <= rank_rtol and not p.regular and p.rank_drop != comp.rank_drop:
                findings.append(f"component {i}: numeric rank drop {p.rank_drop}, component says "
                                f"{comp.rank_drop}")
        if not pts:
            msg, ok = "no point found on the component (no real solution?)", False
        elif fails:
            msg, ok = (f"J is regular at {len(fails)}/{len(pts)} points "
                       f"(largest sigma ratio {max(p.sigma_ratio for p in fails):.1e}"
                       + (f"; {sum(p.precise == 'regular' for p in fails)} decided in "
                          f"{PRECISE_CHECK_DIGITS[1]} digits"
                          if any(p.precise for p in fails) else "") + ")"), False
        else:
            msg, ok = "", True
        checked.append(ComponentCheck(i, eq_text, tuple(pts), fails, ok, msg, ex_text,
                                      comp.rank_drop))

    # off-locus
    tell("check: random configurations off the locus")
    off = []
    for q in nm.random_q(rng, MAX_TRIES * samples):
        if all(e.residual(q) > OFF_LOCUS_MIN_RESIDUAL for e in all_eqs):
            off.append(_point(nm, q, rank_rtol))
            if len(off) == samples:
                break
    off_fails = tuple(p for p in off if p.sigma_ratio <= rank_rtol)
    for p in off:
        if p.sigma_ratio > rank_rtol:
            findings += _findings_at("off-locus", p, False)

    # completeness
    tell("check: singular points found by minimising sigma_min/sigma_max")
    singular, uncovered, escaped = 0, [], 0
    unbounded = np.array([v not in nm.angles for v in nm.variables], dtype=bool)

    def ran_off(q):
        return bool(np.any(np.abs(np.asarray(q)[unbounded]) > PROBE_ESCAPE_ABS))

    for q0 in nm.random_q(rng, samples):
        q = minimise_ratio(nm, q0)
        if ran_off(q):
            escaped += 1        # the ratio tends to 0 at infinity: no singular point
            continue
        if sigma_ratio(nm(q)) > rank_rtol:
            continue
        q, r = descend_to_singular(nm, q)
        if ran_off(q):
            escaped += 1
            continue
        if r > PROBE_DESCENT_RTOL:
            continue            # a positive local minimum: nearly, not exactly, singular
        p = _point(nm, q, rank_rtol)
        singular += 1
        findings += _findings_at("probe", p, True)
        if not any(e.residual(np.array(p.q)) <= COVER_RESIDUAL for e in all_eqs):
            uncovered.append(p)

    thresholds = {"RANK_RTOL": rank_rtol, "ON_COMPONENT_RESIDUAL": ON_COMPONENT_RESIDUAL,
                  "OFF_LOCUS_MIN_RESIDUAL": OFF_LOCUS_MIN_RESIDUAL,
                  "COVER_RESIDUAL": COVER_RESIDUAL, "MINOR_RTOL": MINOR_RTOL,
                  "PROBE_ESCAPE_ABS": PROBE_ESCAPE_ABS}
    return CheckReport(model=locus.model, seed=seed, samples=samples, components=tuple(checked),
                       skipped=tuple(skipped), off_locus=tuple(off), off_locus_failures=off_fails,
                       probe_singular=singular, probe_starts=samples, uncovered=tuple(uncovered),
                       findings=tuple(findings), thresholds=thresholds, probe_escaped=escaped)


def render_check_text(report: CheckReport) -> str:
    """A summary table of a :class:`CheckReport`."""
    lines = [f"check of {report.model}: seed {report.seed}, {report.samples} samples"]
    lines.append(f"{'check':<34} {'points':>6}  {'result':<6} detail")
    for c in report.components:
        eqs = ", ".join(c.equations) or "(no equation)"
        if len(eqs) > 30:
            eqs = eqs[:27] + "..."
        detail = c.message or f"max sigma ratio {c.max_ratio:.1e}"
        precise = sum(p.precise == "singular" for p in c.points)
        if c.ok and precise:
            detail += f" ({precise} decided singular in {PRECISE_CHECK_DIGITS[1]} digits)"
        lines.append(f"{'on ' + eqs:<34} {len(c.points):>6}  {'ok' if c.ok else 'FAIL':<6} {detail}")
    for eqs in report.skipped:
        lines.append(f"{'on ' + ', '.join(eqs)[:31]:<34} {'-':>6}  {'skip':<6} parameter conditions")
    mn = min((p.sigma_ratio for p in report.off_locus), default=None)
    lines.append(f"{'off-locus (full rank)':<34} {len(report.off_locus):>6}  "
                 f"{'ok' if not report.off_locus_failures else 'FAIL':<6} "
                 + (f"{len(report.off_locus_failures)} rank deficient, min sigma ratio {mn:.1e}"
                    if mn is not None else "no configuration is off the locus"))
    lines.append(f"{'completeness probe':<34} {report.probe_starts:>6}  "
                 f"{'ok' if not report.uncovered else 'FAIL':<6} "
                 f"{report.probe_singular} singular minima, {len(report.uncovered)} on no component"
                 + (f", {report.probe_escaped} ran off to infinity" if report.probe_escaped
                    else ""))
    for p in report.uncovered:
        lines.append("  uncovered: (" + ", ".join(f"{x:+.6f}" for x in p.q)
                     + f"), sigma ratio {p.sigma_ratio:.1e}")
    if report.findings:
        n = len(report.findings)
        lines.append(f"{n} finding{'' if n == 1 else 's'} (FSP / minors vs SVD; the SVD decides):")
        lines += [f"  {f}" for f in report.findings[:20]]
        if len(report.findings) > 20:
            lines.append(f"  ... {len(report.findings) - 20} more")
    lines.append("result: " + ("PASS" if report.ok else "FAIL"))
    return "\n".join(lines)


def parse_locus(data, model):
    """A :class:`~rankloci.loci.Locus` from its ``rankloci.locus/1`` or ``/2`` dict, in `model`'s symbols.

    The same as :meth:`Locus.from_dict(data, model) <rankloci.loci.Locus.from_dict>`.

    Raises
    ------
    ModelError
        If the schema key is wrong, the variables are not the model's, or an
        equation does not parse over the model's variable and parameter names.
    """
    from ..loci import Locus

    return Locus.from_dict(data, model)
