"""Optional exact cross-check with Singular: minimal associated primes.

When the computer-algebra system Singular is on PATH (Debian package
``singular``), the ideal of all maximal minors of J, written in c_i = cos q_i
and s_i = sin q_i with the relations c_i**2 + s_i**2 - 1 and the numeric
parameters as rationals, is decomposed by ``minAssGTZ`` (primdec.lib).  The
primes are then compared with the locus components:

- every component's sample point must lie on some prime's variety;
- every prime with a real point (found numerically) must have that point on
  some component.

Singular is driven by subprocess with a time limit; ideals larger than
``MAX_TERMS`` terms are not sent (raw Jacobian determinants of 6-DOF arms
are hopeless for it).  When Singular is absent the result says so.
"""

from __future__ import annotations

import itertools
import re
import shutil
import subprocess
from dataclasses import dataclass

import numpy as np
import sympy as sp

from ..algebra.ring import square_root_primes
from ..tolerances import (SINGULAR_MAX_ANGLES as MAX_ANGLES, SINGULAR_MAX_TERMS as MAX_TERMS,
                          SINGULAR_ON_SET_RTOL as ON_SET_RTOL, SINGULAR_TIMEOUT_S as TIMEOUT_S)

__all__ = ["SingularResult", "singular_cross_check", "singular_available"]


@dataclass(frozen=True)
class SingularResult:
    status: str              # "agree", "disagree", "skipped"
    reason: str
    primes: tuple = ()       # each a tuple of generator strings in c_i, s_i
    findings: tuple = ()

    def to_dict(self) -> dict:
        return {"status": self.status, "reason": self.reason,
                "primes": [list(p) for p in self.primes], "findings": list(self.findings)}


def singular_available() -> bool:
    return shutil.which("Singular") is not None


def _cs_symbols(variables):
    return {q: (sp.Symbol(f"c{i + 1}"), sp.Symbol(f"s{i + 1}")) for i, q in enumerate(variables)}


def _to_cs(expr, cs):
    rep = {}
    for q, (c, s) in cs.items():
        rep[sp.cos(q)] = c
        rep[sp.sin(q)] = s
    return sp.expand(sp.expand_trig(expr).xreplace(rep))


def singular_cross_check(tm, locus, *, rng, parameters=None) -> SingularResult:
    """Compare the minimal primes of the maximal-minor ideal with ``locus``.

    ``tm`` must have numeric parameters and only angle variables.  The
    locus's equations may still name parameters (a locus read from a file):
    ``parameters`` (default ``locus.parameters``) gives their values, by name.
    """
    if not singular_available():
        return SingularResult("skipped", "Singular is not installed (Debian package 'singular')")
    if tm.parameters:
        return SingularResult("skipped", "needs numeric parameters (--numeric)")
    if set(tm.variables) != set(tm.angles):
        return SingularResult("skipped", "only matrices in angles are supported")
    if square_root_primes(tm.matrix):
        return SingularResult("skipped", "the matrix has irrational entries (square roots); this "
                                         "check works over the rationals only")
    if len(tm.variables) > MAX_ANGLES:
        return SingularResult("skipped", f"more than {MAX_ANGLES} joint variables: the decomposition "
                                         "would not finish; the numeric checks stand alone")
    cs = _cs_symbols(tm.variables)
    J = sp.Matrix(tm.matrix)
    if J.rows > J.cols:
        J = J.T
    n, m = J.shape
    Jcs = J.applyfunc(lambda e: _to_cs(e, cs))
    minors = []
    for cols in itertools.combinations(range(m), n):
        d = sp.expand(Jcs[:, list(cols)].det(method="berkowitz"))
        if d != 0:
            minors.append(d)
    if not minors:
        return SingularResult("skipped", "all maximal minors vanish identically (degenerate matrix)")
    terms = sum(len(sp.Add.make_args(d)) for d in minors)
    if terms > MAX_TERMS:
        return SingularResult("skipped", f"ideal too large for Singular ({terms} terms > {MAX_TERMS})")
    gens = [s for pair in cs.values() for s in pair]
    ideal = [sp.sstr(d).replace("**", "^") for d in minors]
    ideal += [f"{c}^2+{s}^2-1" for c, s in cs.values()]
    script = (f"ring r = 0, ({','.join(map(str, gens))}), dp;\n"
              f"ideal I = {', '.join(ideal)};\n"
              'LIB "primdec.lib";\nlist L = minAssGTZ(I);\n'
              'int i; for (i = 1; i <= size(L); i++) { print("PRIME"); print(L[i]); }\nquit;\n')
    try:
        proc = subprocess.run(["Singular", "-q", "--no-warn"], input=script, capture_output=True,
                              text=True, timeout=TIMEOUT_S)
    except subprocess.TimeoutExpired:
        return SingularResult("skipped", f"Singular did not finish within {TIMEOUT_S:g} s")
    primes = _parse_primes(proc.stdout)
    if proc.returncode != 0 or not primes:
        return SingularResult("skipped", f"Singular failed: {proc.stderr.strip()[:200]}")
    values = {str(k): v for k, v in (locus.parameters if parameters is None
                                     else parameters).items()}
    findings = _compare(primes, gens, cs, tm, _with_values(locus, values), rng)
    return SingularResult("agree" if not findings else "disagree",
                          f"{len(primes)} minimal associated "
                          f"prime{'' if len(primes) == 1 else 's'}",
                          tuple(tuple(p) for p in primes), tuple(findings))


def _parse_primes(text):
    primes, current = [], None
    for line in text.splitlines():
        line = line.strip()
        if line == "PRIME":
            current = []
            primes.append(current)
        elif current is not None and line:
            m = re.match(r"_\[\d+\]=(.*)", line)
            current.append((m.group(1) if m else line).rstrip(","))
    return [p for p in primes if p]


def _parse_poly(text, names):
    from ..expr import parse_expression

    return parse_expression(text.replace("^", "**"), names)


def _with_values(locus, values):
    """``locus`` with the parameter values substituted into its components' equations."""
    import dataclasses

    def numeric(c):
        def sub(e):
            return e.subs({s: values[s.name] for s in e.free_symbols if s.name in values})
        return dataclasses.replace(c, equations=tuple(sub(e) for e in c.equations),
                                   excluding=tuple(sub(e) for e in c.excluding))

    return dataclasses.replace(locus, components=tuple(numeric(c) for c in locus.components))


def _compare(primes, gens, cs, tm, locus, rng):
    names = {str(g): g for g in gens}
    polys = [[_parse_poly(g, names) for g in p] for p in primes]
    funcs = [sp.lambdify(gens, P) for P in polys]
    scales = [[float(sum(abs(c) for c in sp.Poly(g, *gens).coeffs())) for g in P] for P in polys]

    def cs_point(q):
        return [f(q[v]) for v in tm.variables for f in (np.cos, np.sin)]

    def on_prime(k, x):
        vals = np.abs(np.array(funcs[k](*x), dtype=float))
        return bool(np.all(vals <= ON_SET_RTOL * np.array(scales[k])))

    findings = []
    comps = list(locus.components)
    for c in comps:
        q = _component_point(c, tm, rng)
        if q is None:
            findings.append(f"component {[sp.sstr(e) for e in c.equations]} has no real point "
                            "that could be found")
            continue
        x = cs_point(q)
        if not any(on_prime(k, x) for k in range(len(polys))):
            findings.append(f"component {[sp.sstr(e) for e in c.equations]} is on no prime")
    comp_funcs = [(sp.lambdify(list(tm.variables), list(c.equations)), c) for c in comps]
    for k in range(len(polys)):
        x = _real_point(funcs[k], scales[k], len(tm.variables), rng)
        if x is None:
            continue  # a prime without real points has nothing to compare
        q = np.array([2 * np.arctan2(x[2 * i + 1], 1 + x[2 * i]) for i in range(len(tm.variables))])
        if not any(np.all(np.abs(np.array(f(*q), dtype=float)) < ON_SET_RTOL * 10) for f, _ in comp_funcs):
            findings.append(f"prime {primes[k]} has a real point on no component")
    return findings


def _component_point(comp, tm, rng):
    """A point of ``comp``: its sample, or (for a locus read from a file) one solved for."""
    if all(str(v) in comp.sample for v in tm.variables):
        return {v: comp.sample[str(v)] for v in tm.variables}
    from ..numeric.equations import Equations, NumericMatrix, points_on

    eqs = Equations(comp.equations, tm.variables, {}, excluding=comp.excluding)
    found = points_on(eqs, NumericMatrix(tm.matrix, tm.variables, tm.angles), rng, 1)
    return dict(zip(tm.variables, found[0])) if found else None


def _real_point(func, scales, n_angles, rng, starts=30):
    """A real point of a prime in (c, s) coordinates, on the circles, or None."""
    from ..numeric.gauss_newton import gauss_newton

    scales = np.maximum(np.array(scales), 1e-300)

    def residual(t):
        x = np.ravel([[np.cos(a), np.sin(a)] for a in t])
        return np.array(func(*x), dtype=float) / scales

    def residual_rows(T):
        return np.array([residual(t) for t in T])

    for _ in range(starts):
        t = gauss_newton(residual_rows, rng.uniform(-np.pi, np.pi, n_angles))
        if t is not None and np.max(np.abs(residual(t))) < ON_SET_RTOL:
            return np.ravel([[np.cos(a), np.sin(a)] for a in t])
    return None
