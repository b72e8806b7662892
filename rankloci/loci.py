"""Rank-deficiency loci: the result type shared by every method.

A :class:`Locus` is a union of :class:`Component` objects.  Each component
lists equations that vanish on it (sympy expressions in the joint variables
and the parameters), its solved form where there is one, the variables that
stay free, its dimension, the rank drop, and the task directions that are
lost there.  :meth:`Locus.to_dict` writes a locus as a JSON document and
:func:`parse_locus_dict` (:meth:`Locus.from_dict`) reads one back.
"""

from __future__ import annotations

import enum
import functools
import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import sympy as sp

from .errors import ExpressionError, ModelError
from .expr import as_expression, exact_number, natural_key, parse_expression
from .tolerances import LOCUS_CONTAINS_RTOL

if TYPE_CHECKING:
    import networkx as nx

__all__ = ["Component", "Locus", "Outcome", "SCHEMA", "READABLE_SCHEMAS", "dimension_bound",
           "parse_locus_dict", "MAX_LOCUS_COMPONENTS", "MAX_RANK_DROP"]

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
    #: The branch's dimension is below the determinantal bound at its sample points.
    BELOW_BOUND = "below the dimension bound"
    #: Every real point found on the branch lies where one of its substitutions
    #: (C, S) ~ (b, -a) is undefined (a = b = 0): those points are the branches of a = b = 0.
    EXCEPTIONAL = "real points only where a substitution is undefined (their own branches)"
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
    real_points_of : tuple of sympy.Expr
        Empty for a component of the real locus in its own right.  Otherwise the
        equations of a component of the *complex* locus whose real points are fewer, or of
        lower dimension, than its complex ones (``x**2 + y**2 = 0``): this component holds
        those real points, and the certificate counts the complex component as covering
        its witness points (see :mod:`rankloci.exact.real_points`).
    for_model : bool
        Whether the component has real points for the model's own parameter
        values (a component with parameter conditions the model does not
        satisfy, or whose equations have no real solution for them, has not).
        The others are kept apart, in :attr:`Locus.special`.
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
    real_points_of: tuple = ()

    @property
    def exists_for_model(self) -> bool:
        """The old name of :attr:`for_model`, which it returns (with a DeprecationWarning)."""
        import warnings

        warnings.warn("Component.exists_for_model is for_model", DeprecationWarning,
                      stacklevel=2)
        return self.for_model

    def __repr__(self) -> str:
        kind = f", {self.kind}" if self.kind else ""
        return (f"<Component {_equations_text(self)}: dimension {self.dimension}, rank drop "
                f"{self.rank_drop}{kind}>")

    def _repr_latex_(self) -> str:
        return f"$\\displaystyle {_equations_latex(self)}$"

    def _repr_html_(self) -> str:
        return _table_html([self], None)

    def lambdify(self, variables=None, parameters=None):
        """The equations as one numpy function of the variables.

        Parameters
        ----------
        variables : sequence of sympy.Symbol, optional
            The arguments, in order; default: the symbols of the equations
            that are not parameters, in natural name order (``q2`` before ``q10``).
        parameters : mapping, optional
            Parameter symbol -> value, substituted first (``Locus.parameters``).

        Returns
        -------
        callable
            ``f(*values)`` returns the list of the equations' values; it
            broadcasts over numpy arrays.

        See Also
        --------
        Locus.equations_function : the same function for every component of a
            locus: one argument, the joint vector (or N of them), the model's
            parameter values substituted, an array returned.

        Examples
        --------
        >>> q1, q2 = sp.symbols("q1 q2", real=True)
        >>> f = Component(equations=(sp.sin(q2),)).lambdify([q1, q2])
        >>> [round(float(v), 6) for v in f(0.0, 1.5707963267948966)]
        [1.0]
        """
        subs = {k: as_expression(v) for k, v in dict(parameters or {}).items()}
        eqs = [as_expression(e).subs(subs) for e in self.equations]
        if variables is None:
            symbols = set().union(*(e.free_symbols for e in eqs)) if eqs else set()
            variables = sorted(symbols, key=natural_key)
        from .numeric.functions import numpy_function

        return numpy_function(tuple(variables), eqs)

    def to_dict(self) -> dict:
        """The component as JSON-ready data (an entry of ``components`` in ``rankloci.locus/2``)."""
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
        } | ({"real_points_of": [sp.sstr(e) for e in self.real_points_of]}
             if self.real_points_of else {})


@dataclass(frozen=True)
class Locus:
    """The rank-deficiency locus of a matrix: a union of components.

    ``components`` is the locus of the model as given: every component has
    real points for the model's own parameter values.  ``special`` holds the
    components that exist only for other parameter values (a link length of
    zero, two equal offsets the model does not have): the analysis found
    them with symbolic parameters, and they say where the locus would change.
    A component given in ``components`` that does not exist for the model
    is moved to ``special`` when the locus is made; :attr:`all_components`
    gives both.

    ``joint_names`` gives, for a URDF chain, the URDF joint of each variable
    (``q1`` is ``joint_names[0]``), and ``()`` for other models; ``contains``
    accepts those names as keys.  It is not part of :meth:`to_dict` (the JSON
    of ``rankloci locus`` adds it as ``"joint_names"``, which
    :meth:`from_dict` reads back).
    """

    model: str
    variables: tuple
    parameters: dict
    shape: tuple
    method: str
    components: tuple
    degenerate: bool = False
    tree: nx.DiGraph | None = None    # the branch tree, or None
    seconds: float = 0.0
    notes: tuple = ()
    base: "Locus | None" = None   # for an augmented matrix: the locus of J itself
    special: tuple = ()           # components for other parameter values only
    complete: bool | None = None  # the certificate passed (None: not certified either way)
    certificate: object = None    # rankloci.exact.certificate.Certificate, when one was computed
    joint_names: tuple = ()       # the model's joint (URDF) name of each variable, or ()

    def __post_init__(self):
        # the one place where components are split: those without real points for the model's
        # own parameter values go to ``special``, whoever built the locus
        apart = tuple(c for c in self.components if not c.for_model)
        if apart:
            object.__setattr__(self, "components",
                               tuple(c for c in self.components if c.for_model))
            object.__setattr__(self, "special", tuple(self.special) + apart)

    @property
    def all_components(self) -> tuple:
        """:attr:`components`, then :attr:`special`: every component the computation found."""
        return tuple(self.components) + tuple(self.special)

    def __repr__(self) -> str:
        special = f" (+{len(self.special)} special)" if self.special else ""
        done = {True: "", False: ", INCOMPLETE", None: ""}[self.complete]
        return (f"<Locus {self.model!r}: {self.shape[0]}x{self.shape[1]}, {self.method}, "
                f"{_count(len(self.components), 'component')}{special}, "
                f"{self.seconds:.2f} s{done}>")

    def _repr_latex_(self) -> str:
        rows = " \\\\ ".join(f"{k}.\\; & {_equations_latex(c)}"
                             for k, c in enumerate(self.components, 1))
        return (f"$\\displaystyle \\begin{{array}}{{rl}} {rows} \\end{{array}}$" if rows
                else "$\\emptyset$")

    def _repr_html_(self) -> str:
        return _table_html(self.components, self)

    def contains(self, q, *, rtol: float = LOCUS_CONTAINS_RTOL):
        """Is the configuration ``q`` on the locus (of the model's own components)?

        ``q`` is on a component when every equation, divided by the sum of the
        absolute values of its coefficients (parameters substituted), is at
        most ``rtol`` there, and it is not in the component's ``excluding``
        sets, or lies in their closure (points of the component with every
        exclusion nonzero come arbitrarily close).

        Parameters
        ----------
        q : array_like or mapping
            One configuration: the values of :attr:`variables` in order, or a
            mapping from a variable (name or symbol), or from a URDF joint name
            (:attr:`joint_names`), to its value; N
            configurations: an array of shape (N, n).
        rtol : float
            See :data:`rankloci.tolerances.LOCUS_CONTAINS_RTOL`.

        Returns
        -------
        bool or numpy.ndarray
            One bool for one configuration; a boolean array of shape (N,) for
            an (N, n) array.

        Raises
        ------
        rankloci.errors.ArgumentError
            A value that is not a finite number (NaN), the wrong number of
            values, a missing or unknown name.

        Examples
        --------
        >>> q1, q2 = sp.symbols("q1 q2", real=True)
        >>> L = Locus("m", (q1, q2), {}, (2, 2), "determinant", (Component((sp.sin(q2),)),))
        >>> L.contains([0.4, 0.0]), L.contains({"q1": 0.4, "q2": 3.0})
        (True, False)
        >>> L.contains([[0.4, 0.0], [0.4, 1.0], [2.0, 3.141592653589793]])
        array([ True, False,  True])
        """
        import numpy as np

        from .numeric.points import configurations

        X, single = configurations(q, self.variables, self.joint_names)
        inside = np.zeros(len(X), dtype=bool)
        for k in range(len(self.components)):
            todo = np.flatnonzero(~inside)
            if not todo.size:
                break
            eqs = self._equations(k)
            values = eqs.batch(X[todo])                    # (equations, points)
            residual = np.max(np.abs(values), axis=0) if len(values) else np.zeros(todo.size)
            for i in todo[residual <= rtol]:
                if eqs.admits(X[i]) or _near_admitted(eqs, X[i], np.random.default_rng(k)):
                    inside[i] = True
        return bool(inside[0]) if single else inside

    def _equations(self, k):
        """The scaled numeric equations of component ``k`` (lambdified once per content)."""
        comp = self.components[k]
        key = (tuple(comp.equations), tuple(self.variables),
               tuple(dict(self.parameters).items()), tuple(comp.excluding))
        try:
            return _numeric_equations(*key)
        except TypeError:          # a value that cannot be hashed: not kept
            return _numeric_equations.__wrapped__(*key)

    def equations_function(self, k: int):
        """The equations of component ``k`` as a numpy function of the joint vector.

        Every component's function takes the same argument: the values of
        :attr:`variables`, in order (one configuration, or an (N, n) array);
        the model's parameter values are substituted.  For a function of
        other arguments, see :meth:`Component.lambdify`.

        Parameters
        ----------
        k : int
            Index into :attr:`components` (0-based).

        Returns
        -------
        callable
            ``f(q)`` returns the values of the equations (not scaled): an
            array of shape (m,) for one configuration, (N, m) for N of them.
            It raises :class:`~rankloci.errors.ArgumentError` for a value that
            is not a finite number.

        Examples
        --------
        >>> q1, q2, l = sp.symbols("q1 q2 l", real=True)
        >>> L = Locus("m", (q1, q2), {l: 2}, (2, 2), "determinant",
        ...           (Component((l * sp.sin(q2),)),))
        >>> f = L.equations_function(0)
        >>> f([0.3, 0.0]), f([[0.3, 0.0], [0.3, 1.5707963267948966]])
        (array([0.]), array([[0.],
               [2.]]))
        """
        import numpy as np

        from .numeric.functions import numpy_function
        from .numeric.points import configurations

        comp = self.components[k]
        subs = {p: as_expression(v) for p, v in dict(self.parameters).items()}
        eqs = [as_expression(e).subs(subs) for e in comp.equations]
        f = numpy_function(tuple(self.variables), eqs) if eqs else None
        names = self.joint_names

        def equations(q):
            X, single = configurations(q, self.variables, names)
            if f is None:
                values = np.zeros((len(X), 0))
            else:
                values = np.stack([np.broadcast_to(np.asarray(v, dtype=float), (len(X),))
                                   for v in f(*X.T)], axis=-1)
            return values[0] if single else values

        return equations

    @classmethod
    def from_dict(cls, data, model=None) -> "Locus":
        """The locus of a ``rankloci.locus/2`` (or ``/1``) document, as :meth:`to_dict` wrote it.

        Parameters
        ----------
        data : dict
            The parsed JSON.
        model : RobotModel or MatrixModel, optional
            The model the locus belongs to: its symbols are used, and the
            document's variables must be the model's.  Without it the symbols
            are made from the document's names (real symbols, as in model files).

        Raises
        ------
        rankloci.errors.ModelError
            Naming the field of the first problem.

        Examples
        --------
        >>> q1, q2 = sp.symbols("q1 q2", real=True)
        >>> L = Locus("m", (q1, q2), {}, (2, 2), "determinant", (Component((sp.sin(q2),)),))
        >>> Locus.from_dict(L.to_dict()).to_dict() == L.to_dict()
        True
        """
        return parse_locus_dict(data, model)

    def to_dict(self) -> dict:
        """The locus as JSON-ready data, schema ``rankloci.locus/2`` (read by :meth:`from_dict`).

        Parameter values are written as floats and ``seconds`` to 4 decimals;
        the branch tree is not included.
        """
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
            "certificate": self.certificate.to_dict() if self.certificate is not None else None,
            "seconds": round(self.seconds, 4),
            "notes": list(self.notes),
        } | ({"base_locus": self.base.to_dict()} if self.base is not None else {})

    def _component_dict(self, c) -> dict:
        extra = {"kind": c.kind, "meets": list(c.meets)} if self.base is not None else {}
        return c.to_dict() | extra


@functools.lru_cache(maxsize=256)
def _numeric_equations(equations, variables, parameters, excluding):
    """:class:`~rankloci.numeric.equations.Equations` of a component, kept by content: a locus
    stays immutable, and asking the same locus (or an equal one) again costs no lambdify."""
    from .numeric.equations import Equations

    return Equations(equations, variables, dict(parameters), excluding)


def _count(n: int, word: str) -> str:
    return f"{n} {word}{'' if n == 1 else 's'}"


def _equations_text(c) -> str:
    text = ", ".join(f"{sp.sstr(e)} = 0" for e in c.equations) or "everywhere"
    if c.excluding:
        text += " where " + ", ".join(f"{sp.sstr(e)} != 0" for e in c.excluding)
    return text


def _equations_latex(c) -> str:
    parts = [f"{sp.latex(e)} = 0" for e in c.equations] or [r"\text{everywhere}"]
    parts += [f"{sp.latex(e)} \\neq 0" for e in c.excluding]
    return r",\quad ".join(parts)


def _table_html(components, locus) -> str:
    """An HTML table of components, headed by what the locus is of."""
    from html import escape

    head = ""
    if locus is not None:
        head = (f"<p><b>{escape(locus.model)}</b>: {locus.shape[0]}x{locus.shape[1]} matrix, "
                f"method {escape(locus.method)}, {_count(len(locus.components), 'component')}"
                + (f" (+{len(locus.special)} for special parameter values)" if locus.special
                   else "") + f", {locus.seconds:.2f} s"
                + {True: ", self-check passed", False: ", <b>INCOMPLETE</b>",
                   None: ""}[locus.complete] + "</p>")
    kinds = any(c.kind for c in components)   # only an augmented matrix's components have one
    rows = []
    for k, c in enumerate(components, 1):
        solved = "; ".join(f"{v} &isin; {{{', '.join(escape(sp.sstr(x)) for x in vals)}}}"
                           for v, vals in c.solved.items())
        cells = [str(k), escape(_equations_text(c)), solved, str(c.dimension), str(c.rank_drop),
                 escape(" ".join(str(v) for v in c.free))] + [escape(c.kind or "")] * kinds
        rows.append("<tr>" + "".join(f"<td>{x}</td>" for x in cells) + "</tr>")
    header = "".join(f"<th>{h}</th>" for h in ("#", "equations", "solved", "dimension",
                                                 "rank drop", "free") + ("kind",) * kinds)
    return f"{head}<table><tr>{header}</tr>{''.join(rows)}</table>"


def _near_admitted(eqs, x, rng) -> bool:
    """Do points of the component with every exclusion nonzero lie near ``x``?"""
    import numpy as np

    from .numeric.closure import near_admitted

    return near_admitted(lambda Y: eqs.batch(Y).T,
                         lambda Y: np.array([eqs.residual(y) <= LOCUS_CONTAINS_RTOL for y in Y]),
                         eqs.admits, x, rng)

# --- a locus read back from its JSON document (``rankloci.locus/2`` or ``/1``) --------------
#
# parse_locus_dict is what Locus.from_dict and ``rankloci check --locus FILE`` use.  Every
# string is parsed with the safe expression parser over the document's (or the model's)
# variable and parameter names, and every field is checked for its type and size: the
# document may come from anywhere.


#: The most components a locus file may hold (the built-in models have at most 12).
MAX_LOCUS_COMPONENTS = 1000

#: The largest rank drop a locus file may state (a 100 x 100 matrix losing all its rank).
MAX_RANK_DROP = 100

#: The most entries of any list or mapping of one component (samples, solved values, ...).
MAX_ITEMS = 10_000

#: The most entries of one lost direction (a row or column count of the matrix).
MAX_VECTOR = 1000


def _names(data, key, where=None) -> list:
    value = data.get(key, [])
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value) \
            or len(value) > MAX_ITEMS:
        raise ModelError("must be a list of names", field=where or key)
    return value


def _number(value, where) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) \
            or not math.isfinite(value):
        raise ModelError(f"{str(value)[:20]!r} is not a finite number", field=where)
    return float(value)


def _symbols(data, model):
    """Variables and parameters (symbol -> value) of the document, in the model's symbols."""
    if not isinstance(data, dict):
        raise ModelError("a locus file must hold a JSON object", field="schema")
    if data.get("schema") not in READABLE_SCHEMAS:
        raise ModelError(f"schema is {str(data.get('schema'))[:40]!r}, expected one of "
                         f"{', '.join(READABLE_SCHEMAS)}", field="schema")
    raw = data.get("parameters", {})
    if not isinstance(raw, dict) or len(raw) > MAX_ITEMS:
        raise ModelError("must be an object of numbers", field="parameters")
    if model is not None:
        names = [v.name for v in model.variables]
        if data.get("variables") != names:
            raise ModelError(f"variables {data.get('variables')!r} are not the model's {names}",
                             field="variables")
        params = {p: model.parameters[p] for p in model.parameters if p.name in raw}
        return tuple(model.variables), params, {p.name: p for p in model.parameters}
    names = _names(data, "variables")
    try:
        params = {sp.Symbol(k, real=True): exact_number(_number(v, f"parameters.{k}"))
                  for k, v in raw.items()}
    except ExpressionError as e:
        raise ModelError(str(e), field="parameters") from None
    bad = [n for n in names + list(raw) if not n.isidentifier()]
    if bad:
        raise ModelError(f"{bad[0][:40]!r} is not a symbol name", field="variables")
    return (tuple(sp.Symbol(n, real=True) for n in names), params,
            {p.name: p for p in params})


def _undefined_somewhere(e):
    """The part of ``e`` that is not finite at some configuration, or None.

    Equations of a locus are polynomials in the variables and in sines and
    cosines of them; ``sqrt(sin(q2))``, ``acos(q2)`` or ``1/q2`` have no real
    value at some points, where a numeric check could not evaluate them.
    Functions of constants only (``sqrt(2)``) are numbers.
    """
    for node in sp.preorder_traversal(e):
        if not node.free_symbols:
            continue
        if isinstance(node, sp.Function) and not isinstance(node, (sp.sin, sp.cos)):
            return node
        if isinstance(node, sp.Pow) and not (node.exp.is_Integer and node.exp >= 0):
            return node
    return None


def _component(c, where, symbols, schema_1, special, n_variables=0):
    if not isinstance(c, dict) or "equations" not in c:
        raise ModelError("each component must be an object with 'equations'", field=where)

    def exprs(items, field, *, everywhere=False):
        if not isinstance(items, list) or len(items) > MAX_ITEMS:
            raise ModelError(f"{where}.{field} must be a list of strings", field=f"{where}.{field}")
        try:
            got = tuple(parse_expression(t, symbols) for t in items)
        except ExpressionError as e:
            raise ModelError(str(e), field=f"{where}.{field}") from None
        for e in got if everywhere else ():
            bad = _undefined_somewhere(e)
            if bad is not None:
                raise ModelError(f"{sp.sstr(bad)[:60]} is not defined at every configuration; "
                                 "equations are polynomials in the variables and in sines and "
                                 "cosines", field=f"{where}.{field}")
        return got

    def integer(field, default, low, high):
        v = c.get(field, default)
        if isinstance(v, bool) or not isinstance(v, int) or not low <= v <= high:
            raise ModelError(f"{field} must be an integer from {low} to {high}, not "
                             f"{str(v)[:20]}", field=f"{where}.{field}")
        return v

    def mapping(field):
        v = c.get(field, {})
        if not isinstance(v, dict) or len(v) > MAX_ITEMS:
            raise ModelError("must be an object", field=f"{where}.{field}")
        return v

    solved = {}
    for name, vals in mapping("solved").items():
        if name not in symbols:
            raise ModelError(f"unknown variable {name[:40]!r}", field=f"{where}.solved")
        solved[symbols[name]] = exprs(vals, f"solved.{name}")
    free = _names(c, "free", f"{where}.free")
    if any(n not in symbols for n in free):
        raise ModelError("names a symbol that is not a variable", field=f"{where}.free")
    direction = c.get("direction", [])
    at_sample = c.get("direction_at_sample", [])
    for key, vecs in (("direction", direction), ("direction_at_sample", at_sample)):
        if not isinstance(vecs, list) or len(vecs) > MAX_RANK_DROP or not all(
                isinstance(v, list) and len(v) <= MAX_VECTOR for v in vecs):
            raise ModelError(f"must be at most {MAX_RANK_DROP} lists of at most {MAX_VECTOR} "
                             "entries", field=f"{where}.{key}")
    kind = c.get("kind")
    if kind not in (None, "kinematic", "algorithmic", "mixed"):
        raise ModelError(f"kind {str(kind)[:20]!r} is not kinematic, algorithmic or mixed",
                         field=f"{where}.kind")
    meets = c.get("meets", [])
    if not isinstance(meets, list) or len(meets) > MAX_ITEMS or not all(
            isinstance(m, dict) for m in meets):
        raise ModelError("must be a list of objects", field=f"{where}.meets")
    conditions = exprs(c.get("parameter_conditions", []), "parameter_conditions")
    equations = exprs(c["equations"], "equations", everywhere=True)
    # a component without a stated dimension is taken as cut out by its equations, one
    # codimension each (the certificate checks it like a stated one)
    default_dimension = max(0, n_variables - len([e for e in equations if e != 0]))
    return Component(
        equations=equations,
        solved=solved,
        free=tuple(symbols[n] for n in free),
        dimension=integer("dimension", default_dimension, 0, MAX_ITEMS),
        rank_drop=integer("rank_drop", 1, 1, MAX_RANK_DROP),
        direction=tuple(exprs(v, "direction") for v in direction),
        direction_at_sample=tuple(tuple(_number(x, f"{where}.direction_at_sample") for x in v)
                                  for v in at_sample),
        sample={str(k): _number(v, f"{where}.sample") for k, v in mapping("sample").items()},
        parameter_conditions=conditions,
        # schema /1 listed special-parameter components among the others
        for_model=not special and bool(c.get("for_model", True))
        and not (schema_1 and c.get("parameter_conditions")),
        excluding=exprs(c.get("excluding", []), "excluding", everywhere=True),
        kind=kind, meets=tuple(meets),
        real_points_of=exprs(c.get("real_points_of", []), "real_points_of", everywhere=True))


def parse_locus_dict(data, model=None):
    """A :class:`~rankloci.loci.Locus` from its JSON document.

    Parameters
    ----------
    data : dict
    model : RobotModel or MatrixModel, optional
        Whose symbols to use; the document's variables must be the model's.

    Raises
    ------
    ModelError
        If the schema key is wrong, the variables are not the model's, a field
        has the wrong type or size, or an expression does not parse over the
        variable and parameter names.
    """
    variables, params, names = _symbols(data, model)
    symbols = {v.name: v for v in variables} | names
    schema_1 = data["schema"] == READABLE_SCHEMAS[0]
    comps = data.get("components")
    if not isinstance(comps, list):
        raise ModelError("'components' must be a list", field="components")
    special = data.get("special_components", [])
    if not isinstance(special, list):
        raise ModelError("'special_components' must be a list", field="special_components")
    if len(comps) + len(special) > MAX_LOCUS_COMPONENTS:
        raise ModelError(f"more than {MAX_LOCUS_COMPONENTS} components", field="components")
    out = [_component(c, f"components[{k}]", symbols, schema_1, False, len(variables))
           for k, c in enumerate(comps, 1)]
    out += [_component(c, f"special_components[{k}]", symbols, schema_1, True, len(variables))
            for k, c in enumerate(special, 1)]
    shape = data.get("matrix", {})
    if not isinstance(shape, dict):
        raise ModelError("must be an object with rows and cols", field="matrix")
    dims = tuple(shape.get(k, 0) for k in ("rows", "cols"))
    if not all(isinstance(n, int) and not isinstance(n, bool) and 0 <= n <= MAX_ITEMS
               for n in dims):
        raise ModelError("rows and cols must be integers", field="matrix")
    notes = _names(data, "notes")
    complete = data.get("complete")
    if complete not in (None, True, False):
        raise ModelError("must be true, false or null", field="complete")
    certificate = data.get("certificate")
    if certificate is not None:
        from .exact.certificate import Certificate

        try:
            certificate = Certificate.from_dict(certificate, symbols)
        except ValueError as exc:
            raise ModelError(str(exc), field="certificate") from None
    base = data.get("base_locus")
    if base is not None:
        if isinstance(base, dict) and "base_locus" in base:
            raise ModelError("a base locus cannot have a base locus", field="base_locus")
        base = parse_locus_dict(base, model)
    return Locus(
        model=str(data.get("model", model.name if model is not None else "locus"))[:200],
        variables=variables, parameters=params, shape=dims,
        method=str(data.get("method", "file"))[:40],
        components=tuple(out),
        degenerate=bool(data.get("degenerate", False)),
        seconds=_number(data.get("seconds", 0.0), "seconds"),
        notes=tuple(notes), base=base, complete=complete, certificate=certificate,
        joint_names=_joint_names(data, variables))


def _joint_names(data, variables) -> tuple:
    """The ``joint_names`` entry ``rankloci locus --format json`` adds for a URDF chain, if any."""
    given = data.get("joint_names")
    if given is None:
        return ()
    if not isinstance(given, dict) or set(given) != {v.name for v in variables} \
            or not all(isinstance(j, str) and 0 < len(j) <= 200 for j in given.values()):
        raise ModelError("'joint_names' must map every variable to a joint name",
                         field="joint_names")
    return tuple(given[v.name] for v in variables)
