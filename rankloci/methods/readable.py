"""Equations of a component in the form a reader wants: solved where they can be.

A condition like ``S_q`` (q = 0) or ``C_q*a - S_q*b`` becomes, back in
sympy, ``sin(q/2)`` or ``a*cos(q/2) - b*sin(q/2)``; here each equation in one
angle is solved for that angle where its half-angle form allows it, and the
value is substituted into the other equations.
"""

from __future__ import annotations

import functools

import sympy as sp

from ..kinematics import trig_normal

__all__ = ["solved_value", "readable_equations", "solved_at_values"]


def solved_value(e, q):
    """Values of q on {e = 0} when e depends on q alone and is a half-angle line."""
    if e.free_symbols != {q}:
        return None
    return _solved_value(e, q)


@functools.lru_cache(maxsize=1024)
def _solved_value(e, q):
    # the components of one locus share most of their equations in one angle (sin(q5/2),
    # cos(q2/2), ...), and each is solved many times over: the values, computed once each
    C, S = sp.Dummy("C"), sp.Dummy("S")
    h = e.subs({sp.cos(q / 2): C, sp.sin(q / 2): S})
    if h.has(q):
        # full angles: sin(q), cos(q) in the equation
        h2 = sp.expand(e.subs({sp.cos(q): C ** 2 - S ** 2, sp.sin(q): 2 * C * S}))
        if h2.has(q):
            return None
        h = h2
    try:
        poly = sp.Poly(h, C, S)
    except sp.PolynomialError:
        return None
    if not poly.is_homogeneous:
        return None
    vals = []
    d = poly.total_degree()
    ht = sp.Poly(h.subs(C, 1), S)
    if ht.degree() < d:
        vals.append(sp.pi)            # C = 0 is a root: q = pi
    if ht.degree() > 0:
        try:
            found = sp.roots(ht, filter="R")
        except (sp.PolynomialError, NotImplementedError):
            return None
        real_count = sum(1 for r in sp.Poly(ht, S).nroots() if abs(sp.im(r)) < 1e-12)
        if sum(found.values()) < real_count:
            return None
        for t in found:
            v = 2 * sp.atan(t)
            if v.has(sp.atan) and len(sp.sstr(v)) > 40:
                return None
            vals.append(v)
    return tuple(sorted(set(vals), key=lambda x: float(x))) if vals else None


def solved_at_values(eqs, variables, values) -> dict:
    """Values of the joint variables that the equations fix once the parameters have values.

    A component such as the PUMA elbow, ``a3*sin(q3) + d4*cos(q3) = 0``, fixes q3
    only for given a3 and d4.  Each equation in one joint variable (after the
    parameters in ``values`` are substituted as exact rationals) is solved with
    :func:`solved_value`; variables it cannot solve are left out.

    Examples
    --------
    >>> a, d, q = sp.symbols("a d q")
    >>> solved_at_values([a * sp.sin(q) + d * sp.cos(q)], [q], {a: 1, d: 1})
    {q: (-pi/4, 3*pi/4)}
    """
    subs = {k: sp.nsimplify(v, rational=True) for k, v in dict(values).items()}
    out = {}
    for e in eqs:
        e = sp.sympify(e, strict=True).subs(subs)
        free = [q for q in variables if q in e.free_symbols]
        if len(free) != 1 or free[0] in out or e.free_symbols != {free[0]}:
            continue
        vals = solved_value(e, free[0])
        if vals:
            out[free[0]] = vals
    return out


def readable_equations(eqs, variables):
    """Substitute each solved variable into the other equations; return eqs and solved."""
    solved = {}
    eqs = list(eqs)
    changed = True
    while changed:
        changed = False
        for i, e in enumerate(eqs):
            for q in variables:
                if q in solved:
                    continue
                vals = solved_value(e, q)
                if vals is None or len(vals) != 1:
                    continue
                solved[q] = vals
                rest = []
                for j, f in enumerate(eqs):
                    if j == i:
                        continue
                    g = trig_normal(f.subs(q, vals[0]))
                    if g != 0:
                        rest.append(g)
                eqs = [e] + rest
                changed = True
                break
            if changed:
                break
    out = []
    for e in eqs:
        if e.is_number:
            continue
        if e.could_extract_minus_sign():
            e = -e
        if e not in out:
            out.append(e)
    for q in variables:
        if q not in solved:
            for e in out:
                vals = solved_value(e, q)
                if vals:
                    solved[q] = vals
    return out, solved
