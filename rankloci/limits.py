"""The part of a locus a robot can reach: which components meet the joint-limit box.

A joint's ``limits`` (``limits = [lo, hi]`` in a model file, ``<limit lower upper>``
in a URDF) bound its variable; together they make a box in joint space.
:func:`within_limits` says, for each component of a locus, whether it meets
that box, with a point of the component inside the box where one was found.
Each answer states how it was decided:

- ``"no joint limits"``: no variable is bounded, so every component (all have
  real points) meets the box; its own sample point is the witness.
- ``"sample point"``: the component's sample point (a revolute angle moved by
  whole turns where that helps) lies in the box.
- ``"exact"``: the component fixes a bounded variable at exact values
  (:attr:`~rankloci.loci.Component.solved`, or the real roots of an equation in a
  prismatic variable alone, such as a boom's ``q3 = 0``), and none of them (nor, for a
  revolute joint, any value a whole number of turns away) lies within its
  limits: the component does not meet the box.  The values are compared in
  :data:`EXACT_DIGITS` digits.
- ``"numeric search"``: :data:`LIMIT_SEARCH_STARTS` points drawn uniformly in
  the box (a prismatic joint without limits over :data:`DEFAULT_STROKE`) are
  projected onto the component's equations by least squares bounded to the
  box; a point counts when its equations are within the tolerance of
  :meth:`Locus.contains <rankloci.loci.Locus.contains>` and it is off the
  component's excluded sets.  When no start gives one, ``meets`` is None: not
  found, which is no proof that the component misses the box.

:func:`joint_strokes` gives the interval over which each variable is sampled
and plotted: its limits, else a full turn for an angle and
:data:`DEFAULT_STROKE` (metres) for a length.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from .tolerances import EXACT_DIGITS, LIMIT_SEARCH_STARTS, LOCUS_CONTAINS_RTOL

__all__ = ["LimitCheck", "within_limits", "joint_limits", "joint_kinds", "joint_strokes",
           "DEFAULT_STROKE", "LIMIT_SEARCH_STARTS", "EXACT_DIGITS"]

#: Stroke (m) over which a prismatic joint without limits is sampled and plotted.
DEFAULT_STROKE = (-1.0, 1.0)


_TURN = 2 * np.pi


@dataclass(frozen=True)
class LimitCheck:
    """Whether one component of a locus meets the joint-limit box.

    Attributes
    ----------
    component : int
        1-based number of the component in :attr:`Locus.components`.
    meets : bool or None
        True: ``sample`` is a point of the component inside the limits; False:
        proved to miss the box (``how`` says why); None: no point was found.
    sample : dict or None
        Variable name -> value, inside the limits, on the component.
    how : str
        How it was decided (see the module's description).
    reason : str
        One sentence on the decision.
    """

    component: int
    meets: bool | None
    sample: dict | None = None
    how: str = ""
    reason: str = ""
    starts: int = field(default=0, compare=False)

    def to_dict(self) -> dict:
        """JSON-ready data: ``meets``, ``sample``, ``how`` and ``reason``."""
        return {"meets": self.meets,
                "sample": None if self.sample is None else {k: float(v)
                                                            for k, v in self.sample.items()},
                "how": self.how, "reason": self.reason}

    @property
    def word(self) -> str:
        """``"yes"``, ``"no"`` or ``"not decided"``."""
        return {True: "yes", False: "no", None: "not decided"}[self.meets]


def _own_joints(model):
    return [j for j in getattr(model, "joints", ()) if j.mimic is None]


def joint_kinds(model) -> tuple[str, ...]:
    """``"revolute"`` or ``"prismatic"`` per variable of ``model``.

    A :class:`~rankloci.model.MatrixModel` variable is revolute when it enters
    only through sines and cosines (:attr:`~rankloci.model.MatrixModel.angle_variables`).

    Examples
    --------
    >>> from rankloci.io import load_model
    >>> joint_kinds(load_model("planar2r"))
    ('revolute', 'revolute')
    """
    joints = _own_joints(model)
    if joints:
        return tuple(j.kind for j in joints)
    angles = set(model.angle_variables)
    return tuple("revolute" if v in angles else "prismatic" for v in model.variables)


def joint_limits(model) -> tuple[tuple[float, float] | None, ...]:
    """The limits of each variable of ``model`` (None where it has none)."""
    joints = _own_joints(model)
    if joints:
        return tuple(j.limits for j in joints)
    return (None,) * len(model.variables)


def joint_strokes(model) -> tuple[tuple[float, float], ...]:
    """The interval each variable is sampled and plotted over.

    Its limits where it has them; else ``(-pi, pi)`` for an angle and
    :data:`DEFAULT_STROKE` (metres) for a length.

    Examples
    --------
    >>> from rankloci.model import Joint
    >>> import dataclasses
    >>> from rankloci.io import load_model
    >>> arm = load_model("planar2r")
    >>> slide = dataclasses.replace(arm.joints[1], kind="prismatic", limits=(0.0, 0.5))
    >>> joint_strokes(dataclasses.replace(arm, joints=(arm.joints[0], slide)))[1]
    (0.0, 0.5)
    """
    out = []
    for kind, lim in zip(joint_kinds(model), joint_limits(model)):
        if lim is not None:
            out.append((float(lim[0]), float(lim[1])))
        else:
            out.append((-float(np.pi), float(np.pi)) if kind == "revolute" else DEFAULT_STROKE)
    return tuple(out)


def _into_box(q, kinds, limits):
    """``q`` with each revolute angle moved by whole turns into its limits, or None."""
    x = np.array(q, dtype=float)
    for k, (kind, lim) in enumerate(zip(kinds, limits)):
        if lim is None:
            continue
        lo, hi = lim
        if kind == "revolute":
            turns = np.ceil((lo - x[k]) / _TURN)
            x[k] += turns * _TURN
        if not lo <= x[k] <= hi:
            return None
    return x


def _exact_outside(comp, names, kinds, limits):
    """A sentence when a solved variable has no exact value within its limits, else ""."""
    import mpmath

    fixed = dict(comp.solved)
    for e in comp.equations:
        e = sp.sympify(e, strict=True)
        if len(e.free_symbols) != 1:
            continue
        (var,) = e.free_symbols
        name = str(var)
        if var in fixed or name not in names or kinds[names.index(name)] != "prismatic":
            continue
        try:
            fixed[var] = tuple(sp.Poly(e, var).real_roots())
        except (sp.PolynomialError, NotImplementedError):
            continue
    for var, values in fixed.items():
        name = str(var)
        if name not in names:
            continue
        k = names.index(name)
        lim = limits[k]
        if lim is None or not values:
            continue
        lo, hi = (mpmath.mpf(repr(float(b))) for b in lim)
        inside = False
        with mpmath.workdps(EXACT_DIGITS):
            for v in values:
                try:
                    x = mpmath.mpf(str(sp.N(v, EXACT_DIGITS)))
                except (TypeError, ValueError):
                    return ""    # not a real number we can compare: leave it to the search
                if kinds[k] == "revolute":
                    turn = 2 * mpmath.pi
                    x = x + mpmath.ceil((lo - x) / turn) * turn
                margin = mpmath.mpf(10) ** -(EXACT_DIGITS - 5)
                if lo - margin <= x <= hi + margin:
                    inside = True
                    break
        if not inside:
            shown = ", ".join(sp.sstr(v) for v in values)
            turns = " (or any whole number of turns away)" if kinds[k] == "revolute" else ""
            return (f"{name} is fixed at {shown} on the component{turns}, outside its limits "
                    f"[{lim[0]:.6g}, {lim[1]:.6g}]")
    return ""


def within_limits(locus, model, *, rng=None, starts: int = LIMIT_SEARCH_STARTS,
                  rtol: float = LOCUS_CONTAINS_RTOL, box=None) -> tuple[LimitCheck, ...]:
    """Which components of ``locus`` meet the joint-limit box of ``model``.

    Parameters
    ----------
    locus : Locus
        A locus of ``model`` (its variables are the model's).
    model : RobotModel or MatrixModel
        Supplies the limits (:attr:`Joint.limits <rankloci.model.Joint>`) and
        which variables are angles; a matrix model has no limits.
    rng : numpy.random.Generator, optional
        Draws the starts of the numeric search (default: seed 0).
    starts : int
        Random starts per component (:data:`LIMIT_SEARCH_STARTS`).
    rtol : float
        Accepted residual of the scaled equations, as in :meth:`Locus.contains`.
    box : sequence of (float, float) or None, optional
        Bounds per variable instead of the model's limits (None: unbounded);
        ``joint_strokes(model)`` asks for points where a report samples and plots.

    Returns
    -------
    tuple of LimitCheck
        One per component of ``locus.components``, in order.

    Examples
    --------
    >>> import dataclasses
    >>> import rankloci
    >>> arm = rankloci.load_model("planar2r")
    >>> L = rankloci.locus(arm)
    >>> [c.meets for c in within_limits(L, arm)]
    [True]
    >>> elbow = dataclasses.replace(arm.joints[1], limits=(0.5, 2.5))
    >>> bent = dataclasses.replace(arm, joints=(arm.joints[0], elbow))
    >>> check = within_limits(L, bent)[0]
    >>> check.meets, check.how
    (False, 'exact')
    """
    from .numeric.equations import Equations

    rng = rng if rng is not None else np.random.default_rng(0)
    names = [str(v) for v in locus.variables]
    kinds = list(joint_kinds(model))
    limits = list(joint_limits(model) if box is None else box)
    if len(kinds) != len(names) or len(limits) != len(names):
        raise ValueError(f"the locus has {len(names)} variables and the model "
                         f"{model.name!r} {len(kinds)}: not a locus of this model")
    strokes = joint_strokes(model)
    out = []
    for idx, comp in enumerate(locus.components, start=1):
        sample = np.array([float(comp.sample[n]) for n in names], dtype=float) \
            if all(n in comp.sample for n in names) else None
        if all(lim is None for lim in limits):
            out.append(LimitCheck(idx, True, dict(comp.sample) if sample is not None else None,
                                  "no joint limits", "no joint has limits"))
            continue
        eqs = Equations(comp.equations, locus.variables, locus.parameters, comp.excluding)
        moved = _into_box(sample, kinds, limits) if sample is not None else None
        if moved is not None and eqs.residual(moved) <= rtol and eqs.admits(moved):
            out.append(LimitCheck(idx, True, dict(zip(names, map(float, moved))),
                                  "sample point", "the component's sample point lies within "
                                  "the limits"))
            continue
        outside = _exact_outside(comp, names, kinds, limits)
        if outside:
            out.append(LimitCheck(idx, False, None, "exact", outside))
            continue
        found = _search(eqs, kinds, limits, strokes, rng, starts, rtol)
        if found is not None:
            out.append(LimitCheck(idx, True, dict(zip(names, map(float, found))),
                                  "numeric search", "a point of the component within the limits "
                                  "was found by bounded least squares", starts))
        else:
            out.append(LimitCheck(idx, None, None, "numeric search",
                                  f"no point of the component within the limits was found from "
                                  f"{starts} starts (no proof that there is none)", starts))
    return tuple(out)


def _search(eqs, kinds, limits, strokes, rng, starts, rtol):
    """A point of the component in the box by bounded least squares, or None."""
    from scipy.optimize import least_squares

    lo = np.array([lim[0] if lim is not None else -np.inf for lim in limits])
    hi = np.array([lim[1] if lim is not None else np.inf for lim in limits])
    s_lo = np.array([s[0] for s in strokes])
    s_hi = np.array([s[1] for s in strokes])
    # a tiny inset keeps every start strictly inside the bounds, as the method needs
    width = s_hi - s_lo
    s_lo, s_hi = s_lo + 1e-9 * width, s_hi - 1e-9 * width
    for _ in range(starts):
        q0 = rng.uniform(s_lo, s_hi)
        if eqs.empty:
            q = q0
        else:
            try:
                q = least_squares(eqs, q0, bounds=(lo, hi), method="trf", xtol=1e-15,
                                  ftol=1e-15, gtol=1e-15, max_nfev=100 * len(q0)).x
            except ValueError:   # a non-finite value of the equations: try another start
                continue
        if np.all(q >= lo) and np.all(q <= hi) and eqs.residual(q) <= rtol and eqs.admits(q):
            return q
    return None
