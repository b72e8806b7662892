"""Rank-deficiency loci: the result type shared by every method.

A :class:`Locus` is a union of :class:`Component` objects.  Each component
lists equations that vanish on it (sympy expressions in the joint variables
and the parameters), its solved form where there is one, the variables that
stay free, its dimension, the rank drop, and the task directions that are
lost there.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, field

import sympy as sp

__all__ = ["Component", "Locus", "Outcome", "SCHEMA"]

SCHEMA = "rankloci.locus/2"

#: Schemas of locus files that can be read back (``rankloci check --locus``).
READABLE_SCHEMAS = ("rankloci.locus/1", SCHEMA)


class Outcome(enum.StrEnum):
    """Why a node of the branch tree stopped (or that it was refined).

    The branch tree (``Locus.tree``, a networkx DiGraph) stores one of these
    in each node's ``"outcome"`` attribute.  Being a ``str``, an outcome
    prints, compares and exports (JSON, Graphviz) as its text.
    """

    #: The branch was split further: its children carry the outcomes.
    REFINED = "refined"
    #: The branch has no real point.
    EMPTY = "empty"
    #: Every point of the branch lies on a component found before.
    KNOWN = "inside a component already found"
    #: The chosen null vectors vanish on the branch: the whole matrix has full rank at its
    #: generic points, which are covered by the sub-branch where the null vectors degenerate.
    COVERED = "null vectors vanish (covered by its own branch)"
    #: A component leaf whose branch turned out to have no real point when the
    #: components were formed.
    NO_REAL_POINT = "component leaf without a real point"
    #: The whole matrix is rank deficient everywhere.
    DEGENERATE = "degenerate"
    #: Singular vector method: more null vectors than redundant columns, a component.
    BEYOND_REDUNDANCY = "k > redundant columns"
    #: A factor of the determinant of a square (level) matrix: a component.
    NO_REDUNDANT_COLUMN = "no redundant column"
    #: Subdeterminant method: every maximal minor vanishes on the branch, a component.
    ALL_MINORS_VANISH = "all minors vanish"

    @property
    def is_component(self) -> bool:
        """Is a leaf with this outcome a component of the locus?"""
        return self in _COMPONENT_OUTCOMES


_COMPONENT_OUTCOMES = frozenset({Outcome.DEGENERATE, Outcome.BEYOND_REDUNDANCY,
                                 Outcome.NO_REDUNDANT_COLUMN, Outcome.ALL_MINORS_VANISH})


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
        satisfy, or whose equations have no real solution for them, has not);
        see :attr:`exists_for_model`.
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

    @property
    def exists_for_model(self) -> bool:
        """Is this a component of the model's own locus?

        It is when it has real points for the model's own parameter values:
        its parameter conditions, if any, hold for them.  The others are kept
        apart, in :attr:`Locus.special`.
        """
        return self.for_model

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
    """The rank-deficiency locus of a matrix: a union of components.

    ``components`` is the locus of the model as given: every component has
    real points for the model's own parameter values.  ``special`` holds the
    components that exist only for other parameter values (a link length of
    zero, two equal offsets the model does not have): the analysis found
    them with symbolic parameters, and they say where the locus would change.
    """

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
    special: tuple = ()           # components for other parameter values only
    complete: bool | None = None  # the self-check passed (None: not checked)

    def to_dict(self) -> dict:
        return {
            "schema": SCHEMA,
            "model": self.model,
            "variables": [str(v) for v in self.variables],
            "parameters": {str(k): float(v) for k, v in self.parameters.items()},
            "matrix": {"rows": self.shape[0], "cols": self.shape[1]},
            "method": self.method,
            "components": [self._component_dict(c) for c in self.components],
            "special_components": [self._component_dict(c) for c in self.special],
            "degenerate": self.degenerate,
            "complete": self.complete,
            "seconds": round(self.seconds, 4),
            "notes": list(self.notes),
        } | ({"base_locus": self.base.to_dict()} if self.base is not None else {})

    def _component_dict(self, c) -> dict:
        extra = {"kind": c.kind, "meets": list(c.meets)} if self.base is not None else {}
        return c.to_dict() | extra
