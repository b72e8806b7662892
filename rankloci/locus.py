"""Rank-deficiency loci: the result type shared by every method.

A :class:`Locus` is a union of :class:`Component` objects.  Each component
lists equations that vanish on it (sympy expressions in the joint variables
and the parameters), its solved form where there is one, the variables that
stay free, its dimension, the rank drop, and the task directions that are
lost there.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

__all__ = ["Component", "Locus", "SCHEMA"]

SCHEMA = "rankloci.locus/1"


@dataclass(frozen=True)
class Component:
    """One piece of a rank-deficiency locus.

    Attributes
    ----------
    equations : tuple of sympy.Expr
        Each vanishes on the component; together they cut it out.
    solved : dict
        Joint variable -> tuple of exact values, where the component fixes it.
    free : tuple of sympy.Symbol
        Joint variables the equations leave free.
    dimension : int
        Dimension of the component in joint space (at a generic point).
    rank_drop : int
        min(rows, cols) minus the rank at a generic point of the component.
    direction : tuple of tuple of sympy.Expr
        Lost directions: left null vectors of J (right null vectors when J
        has more rows than columns), as expressions valid on the component.
    direction_at_sample : tuple of tuple of float
        The same directions evaluated at ``sample`` and normalised.
    sample : dict
        A point of the component: variable name -> value.
    parameter_conditions : tuple of sympy.Expr
        Equations in the parameters alone: the component exists only for
        those special parameter values.
    excluding : tuple of sympy.Expr
        Expressions that do not vanish at the generic points of the
        component: it is the closure of the set where the equations vanish
        and these do not.  Empty when the equations alone cut it out.
    kind : str or None
        For the locus of an augmented matrix: "kinematic" (inside the locus
        of J), "algorithmic" (J has full rank there) or "mixed" (J has full
        rank at its generic points but the component meets J's locus).
    meets : tuple of dict
        For a mixed component: the components of J's locus it meets
        (1-based ``base_component``, their ``equations``, and a ``point``).
    for_model : bool
        Whether the component has real points for the model's own parameter
        values (a component with parameter conditions the model does not
        satisfy, or whose equations have no real solution for them, has not).
    """

    equations: tuple
    solved: dict = field(default_factory=dict)
    free: tuple = ()
    dimension: int = 0
    rank_drop: int = 1
    direction: tuple = ()
    direction_at_sample: tuple = ()
    sample: dict = field(default_factory=dict)
    parameter_conditions: tuple = ()
    for_model: bool = True
    excluding: tuple = ()
    kind: str | None = None
    meets: tuple = ()
    _branch: object = field(default=None, repr=False, compare=False)

    def to_dict(self) -> dict:
        return {
            "equations": [sp.sstr(e) for e in self.equations],
            "solved": {str(k): [sp.sstr(v) for v in vals] for k, vals in self.solved.items()},
            "free": [str(v) for v in self.free],
            "dimension": self.dimension,
            "rank_drop": self.rank_drop,
            "direction": [[sp.sstr(x) for x in vec] for vec in self.direction],
            "direction_at_sample": [[float(x) for x in vec] for vec in self.direction_at_sample],
            "sample": {k: float(v) for k, v in self.sample.items()},
            "parameter_conditions": [sp.sstr(e) for e in self.parameter_conditions],
            "for_model": self.for_model,
            "excluding": [sp.sstr(e) for e in self.excluding],
        }


@dataclass(frozen=True)
class Locus:
    """The rank-deficiency locus of a matrix: a union of components."""

    model: str
    variables: tuple
    parameters: dict
    shape: tuple
    method: str
    components: tuple
    degenerate: bool = False
    tree: object = None        # networkx.DiGraph of the branch tree, or None
    seconds: float = 0.0
    notes: tuple = ()
    base: "Locus | None" = None   # for an augmented matrix: the locus of J itself

    def to_dict(self) -> dict:
        return {
            "schema": SCHEMA,
            "model": self.model,
            "variables": [str(v) for v in self.variables],
            "parameters": {str(k): float(v) for k, v in self.parameters.items()},
            "matrix": {"rows": self.shape[0], "cols": self.shape[1]},
            "method": self.method,
            "components": [c.to_dict() | ({"kind": c.kind, "meets": list(c.meets)}
                                          if self.base is not None else {})
                           for c in self.components],
            "degenerate": self.degenerate,
            "seconds": round(self.seconds, 4),
            "notes": list(self.notes),
        } | ({"base_locus": self.base.to_dict()} if self.base is not None else {})
