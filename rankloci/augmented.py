"""Augmented Jacobians: kinematic and algorithmic singularities told apart.

Redundancy is often resolved by stacking the gradients of constraint
functions g(q) under J.  The augmented matrix J_aug loses rank wherever J
does (when J_aug is square or wide; a tall J_aug can only lose rank where J
does), and also where a constraint gradient falls into the row space of J:
an *algorithmic* singularity.  :func:`classify` labels each component of
the locus of J_aug by comparing it with the locus of J:

- ``kinematic``: J loses rank at the generic points of the component (the
  component lies inside J's locus);
- ``algorithmic``: J has full rank on the whole component;
- ``mixed``: J has full rank at its generic points, but the component meets
  J's locus; ``meets`` says on which components of J's locus, with a point.

Constraints are plain expressions in the joint variables, or presets that
expand to plain expressions (see :func:`expand_preset`).
"""

from __future__ import annotations

import dataclasses
import re

import numpy as np
import sympy as sp

from .errors import ModelError

__all__ = ["PRESETS", "expand_preset", "parse_augment", "classify", "KINDS", "augmented_locus",
           "augmented_locus_and_tree"]

KINDS = ("kinematic", "algorithmic", "mixed")

#: Preset constraint functions, as written on the command line.
PRESETS = {
    "lock(qi)": "lock joint i: g = qi",
    "sum(qi, qj, ...)": "a joint sum, e.g. the orientation of a planar arm: g = qi + qj + ...",
    "position(k, x|y|z)": "a coordinate of the origin of link frame k in the base frame",
    "NAME(x|y|z)": "a coordinate of a point the model names in [points] (elbow, wrist, ...)",
}

_CALL = re.compile(r"^\s*([A-Za-z_][A-Za-z0-9_]*)\s*\((.*)\)\s*$")
_AXES = {"x": 0, "y": 1, "z": 2}


def expand_preset(model, text: str, *, flag: str = "--augment"):
    """``(name, expression)`` of a preset constraint, or None if ``text`` is no preset.

    Errors name ``flag``: the command line's option, or the Python argument ``augment``.

    Examples
    --------
    >>> from rankloci.io import load_model
    >>> m = load_model("planar3r")
    >>> expand_preset(m, "sum(q1, q2, q3)")
    ('sum(q1, q2, q3)', q1 + q2 + q3)
    >>> expand_preset(m, "lock(q2)")
    ('lock(q2)', q2)
    >>> expand_preset(m, "position(2, y)")[1]
    l1*sin(q1) + l2*sin(q1)*cos(q2) + l2*sin(q2)*cos(q1)
    """
    from .model import RobotModel

    m = _CALL.match(text)
    if not m:
        return None
    head, args = m.group(1), [a.strip() for a in m.group(2).split(",")] if m.group(2).strip() else []
    by_name = {v.name: v for v in model.variables}
    points = dict(getattr(model, "points", ()))
    if head in ("lock", "sum"):
        if not args or (head == "lock" and len(args) != 1):
            raise ModelError(f"{flag} {text!r}: {head}() takes "
                             f"{'one joint variable' if head == 'lock' else 'joint variables'}")
        unknown = [a for a in args if a not in by_name]
        if unknown:
            raise ModelError(f"{flag} {text!r}: {', '.join(unknown)} is not a joint variable "
                             f"of {model.name} ({', '.join(by_name)})")
        return text.strip(), sp.Add(*[by_name[a] for a in args])
    if head == "position" or head in points:
        if not isinstance(model, RobotModel):
            raise ModelError(f"{flag} {text!r}: positions need a robot model, not a raw matrix")
        if head == "position":
            if len(args) != 2 or not args[0].isdigit():
                raise ModelError(f"{flag} {text!r}: write position(k, x|y|z) with a link "
                                 f"frame number k")
            frame, axis = int(args[0]), args[1]
            if not 0 <= frame <= model.dof:
                raise ModelError(f"{flag} {text!r}: link frame {frame} is not in 0..{model.dof}")
        else:
            if len(args) != 1:
                raise ModelError(f"{flag} {text!r}: write {head}(x|y|z)")
            frame, axis = points[head], args[0]
        if axis not in _AXES:
            raise ModelError(f"{flag} {text!r}: {axis!r} is not x, y or z")
        from .kinematics import frame_position, relative_transforms, trig_normal

        T = relative_transforms(model, "base")[frame_position(model, frame)]
        return text.strip(), trig_normal(sp.expand_trig(T[_AXES[axis], 3]))
    return None


def parse_augment(model, texts, *, flag: str = "--augment"):
    """Constraints from ``--augment`` texts: presets first, else plain expressions.

    Errors name ``flag`` (``"augment"`` for the Python API).
    """
    from .jacobians import parse_constraints

    out = []
    for t in texts:
        got = expand_preset(model, t, flag=flag)
        out.extend([got] if got is not None else parse_constraints(model, [t], flag=flag))
    return tuple(out)


# --- classification ---------------------------------------------------------------------------

def _numeric(tm):
    from .numeric.equations import NumericMatrix

    return NumericMatrix(sp.Matrix(tm.matrix).subs(tm.parameters), tm.variables, tm.angles)


def _equations(comp, tm):
    from .numeric.equations import Equations

    return Equations(comp.equations, tm.variables, tm.parameters, comp.excluding)


def _singular(J) -> bool:
    from .numeric.svd import numeric_rank_drop

    return numeric_rank_drop(J) > 0


def _meeting_point(comp, base_comp, tm, nm, rng, tries):
    """A real point on both components where J is singular, or None."""
    from scipy.optimize import least_squares

    from .numeric.equations import Equations
    from .tolerances import LEAST_SQUARES_TOL, ON_COMPONENT_RESIDUAL

    both = Equations(tuple(comp.equations) + tuple(base_comp.equations), tm.variables,
                      tm.parameters)
    if both.empty:
        return None
    for q0 in nm.random_q(rng, tries):
        q = least_squares(both, q0, method="trf", xtol=LEAST_SQUARES_TOL, ftol=LEAST_SQUARES_TOL,
                          gtol=LEAST_SQUARES_TOL,
                          max_nfev=200 * len(q0)).x
        if both.residual(q) <= ON_COMPONENT_RESIDUAL and _singular(nm(q)):
            return q
    return None


def classify(aug, base, tm_aug, tm_base, *, rng=None, samples: int = 4, tries: int = 24):
    """The locus ``aug`` of J_aug with a kind for each component and ``base`` attached.

    Parameters
    ----------
    aug, base : Locus
        Loci of the augmented matrix and of J.
    tm_aug, tm_base : TaskMatrix
        The two matrices (their variables must agree).
    samples : int
        Points solved onto each component, besides its own sample, at which
        the rank of J decides between kinematic and not.
    tries : int
        Random starts when looking for a point a component shares with a
        component of J's locus.
    """
    from .numeric.equations import points_on

    rng = np.random.default_rng(0) if rng is None else rng
    nm = _numeric(tm_base)
    out = []
    for comp in aug.components:
        eqs = _equations(comp, tm_base)
        pts = [np.array([comp.sample[str(v)] for v in tm_base.variables], dtype=float)]
        pts += points_on(eqs, nm, rng, samples)
        singular = [_singular(nm(q)) for q in pts]
        if all(singular):
            out.append(dataclasses.replace(comp, kind="kinematic"))
            continue
        meets = []
        for i, b in enumerate(base.components, start=1):
            q = _meeting_point(comp, b, tm_base, nm, rng, tries)
            if q is not None:
                meets.append({"base_component": i,
                              "equations": [sp.sstr(e) for e in b.equations],
                              "point": {str(v): float(x) for v, x in zip(tm_base.variables, q)}})
        kind = "mixed" if meets else "algorithmic"
        out.append(dataclasses.replace(comp, kind=kind, meets=tuple(meets)))
    return dataclasses.replace(aug, components=tuple(out), base=base)


def base_matrix(model, tm):
    """J without any constraint row, in the frame and about the point ``tm`` uses."""
    from .jacobians import task_matrix
    from .model import RobotModel

    task = tm.rows if isinstance(model, RobotModel) and tm.rows else None
    return task_matrix(model, task=list(task) if task else None, frame=tm.frame,
                       point=tm.point if tm.point is not None else "tool", augment=(),
                       use_model_augment=False, numeric=not tm.parameters and bool(model.parameters))


def augmented_locus(model, tm, method: str | None = None, *, seed: int = 0, progress=None,
                    should_stop=None, clock=None, hints=(), grown=None, workers=None):
    """Loci of J_aug (``tm``) and of J, and J_aug's components classified.

    ``method`` applies to J_aug and to J, as
    :func:`~rankloci.methods.method_for` decides (by default the
    determinant method for a square matrix, svm otherwise); a request for
    the determinant method falls back to svm for J when only J_aug is
    square.  Both loci use the generator seeded with ``seed``.  ``hints`` and ``grown`` go to
    :func:`~rankloci.methods.compute_locus` for J_aug.  With ``workers``
    (:class:`~rankloci.parallel.Workers`), J's locus is computed in a worker process while
    J_aug's is computed here; the result is the same.

    Examples
    --------
    >>> from rankloci.io import load_model
    >>> from rankloci.jacobians import task_matrix
    >>> m = load_model("planar3r_orient")
    >>> locus = augmented_locus(m, task_matrix(m, numeric=True))
    >>> [(str(c.equations[0]), c.kind) for c in locus.components]
    [('sin(q2)', 'mixed')]
    >>> [str(e) for e in locus.base.components[0].equations]
    ['sin(q2)', 'sin(q3)']
    """
    return augmented_locus_and_tree(model, tm, method, seed=seed, progress=progress,
                                    should_stop=should_stop, clock=clock, hints=hints,
                                    grown=grown, workers=workers)[0]


def augmented_locus_and_tree(model, tm, method: str | None = None, *, seed: int = 0,
                             progress=None, should_stop=None, clock=None, hints=(), grown=None,
                             workers=None):
    """:func:`augmented_locus`, and the tree grown for J_aug
    (:class:`~rankloci.methods.GrownTree`, or None), to resume from with hints."""
    from .directions import directions_in_model_frame
    from .methods import compute_locus, locus_and_tree, method_for
    progress = progress or (lambda msg: None)
    base_task = None
    workers = workers.sized(len(tm.variables)) if workers is not None else None
    if tm.n_constraint_rows and workers is not None and workers.jobs > 1:
        # J's locus needs nothing from J_aug's: a worker computes it meanwhile
        base_tm = base_matrix(model, tm)
        base_method = method_for(base_tm.shape, method, strict=False)
        progress(f"locus of J without the constraint rows ({base_tm.shape[0]}x"
                 f"{base_tm.shape[1]}), method {base_method}, in a worker process")
        base_task = workers.submit(compute_locus, base_tm, base_method,
                                   rng=np.random.default_rng(seed), should_stop=None,
                                   clock=clock)
    aug, tree = locus_and_tree(tm, method_for(tm.shape, method), rng=np.random.default_rng(seed),
                               progress=progress, should_stop=should_stop, clock=clock,
                               hints=hints, grown=grown)
    aug = directions_in_model_frame(aug, model, tm)
    if not tm.n_constraint_rows:
        return aug, tree
    if base_task is not None:
        base = base_task.result(should_stop)
    else:
        base_tm = base_matrix(model, tm)
        base_method = method_for(base_tm.shape, method, strict=False)
        progress(f"locus of J without the constraint rows ({base_tm.shape[0]}x"
                 f"{base_tm.shape[1]}), method {base_method}")
        base = compute_locus(base_tm, base_method, rng=np.random.default_rng(seed),
                             progress=progress, should_stop=should_stop, clock=clock)
    base = directions_in_model_frame(base, model, base_tm)
    progress("classifying the components: kinematic, algorithmic or mixed")
    return classify(aug, base, tm, base_tm, rng=np.random.default_rng(seed)), tree
